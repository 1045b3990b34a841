#pragma once
// Makino's clothoid corner (seed 002): a symmetric clothoid pair between two lines, and the
// clothoid-arc-clothoid that caps the peak curvature. fit_clothoid_corner (corner.hpp) builds
// the transition from these; corners with arcs fall back to biclothoid fillets (seed 004 (Shahzadeh et al.)).
//
// Geometry of a symmetric corner (derived here; seed 002 gives only eq. 9): a curve that starts on
// the incoming line at tangent length T before the corner, turns by the deflection alpha
// (the angle between the two directions of travel, 0 < alpha < pi) and is symmetric about the
// bisector. If its first half ends at (X, Y) in a frame at its start (x along the incoming
// line, y towards the turn) with tangent angle alpha/2, the midpoint lies on the bisector,
// perpendicular to that tangent, so
//   deviation (corner to midpoint) d = Y / cos(alpha/2),   T = X + Y tan(alpha/2).
// For Makino's pair, X = a C(u), Y = a S(u) with u = sqrt(alpha / pi) (eq. 9:
// u_max = sqrt(phi_max / 90 deg), phi_max = alpha / 2), so d and T are linear in the scale a.

#include <string>
#include <vector>

#include "blendbench/corner/corner_plane.hpp"
#include "blendbench/geometry/segment.hpp"

namespace blendbench {

// seed 002 eq. 4-9 for a corner of deflection alpha (rad, 0 < alpha < pi). Makino's unit clothoid
// has kappa = pi s / a^2, so the sharpness is pi / a^2 and the peak curvature pi u / a.
struct ClothoidPair {
  double alpha = 0;           // rad, deflection of the corner
  double scale = 0;           // m, Makino's scale factor a
  double u = 0;               // Makino's u_max = sqrt(alpha / pi)
  double half_length = 0;     // m, a u: length of each clothoid
  double sharpness = 0;       // 1/m^2
  double kappa_peak = 0;      // 1/m, at the midpoint
  double tangent_length = 0;  // m, corner to either end
  double deviation = 0;       // m, corner to the midpoint (the Hausdorff distance to the corner)
};
ClothoidPair clothoid_pair_for_deviation(double alpha, double deviation);
ClothoidPair clothoid_pair_for_tangent_length(double alpha, double tangent_length);

// The scale-free part of the pairs of deflection alpha (rad, 0 < alpha < pi): u, C(u), S(u) and
// the half-angle's cosine and sine, so that a corner sized first by its deviation and then by
// the available tangent length evaluates the Fresnel integrals once. The overloads below give
// the same pairs as those above.
struct ClothoidPairShape {
  double alpha = 0;     // rad
  double u = 0;         // sqrt(alpha / pi)
  double c = 0;         // C(u)
  double s = 0;         // S(u)
  double cos_half = 0;  // cos(alpha / 2)
  double sin_half = 0;  // sin(alpha / 2)
};
ClothoidPairShape clothoid_pair_shape(double alpha);
// The same from the turn's cosine and sine as well (as a corner of two lines has them, from its
// tangents' dot and cross products): the half angle's cosine and sine by the half-angle
// formulas instead of a sine and cosine of alpha / 2.
ClothoidPairShape clothoid_pair_shape(double alpha, double cos_alpha, double sin_alpha);
ClothoidPair clothoid_pair_for_deviation(const ClothoidPairShape& shape, double deviation);
ClothoidPair clothoid_pair_for_tangent_length(const ClothoidPairShape& shape, double tangent_length);

// The pair's two clothoids in 3D, in the plane of a corner whose incoming line runs along +x to
// the origin and whose turn is towards +y (PlanarCorner of two lines): the first starts at
// (-T, 0) heading +x with zero curvature, the second at the midpoint, whose position
// (-T, 0) + a (C(u), S(u)) is a closed form (seed 002 eq. 9), heading alpha / 2.
std::vector<Segment> clothoid_pair_segments(const ClothoidPair& pair, const ClothoidPairShape& shape,
                                            const CornerPlane& plane);

// The line-line pair as both clothoid methods size it (seed 002 eq. 9, seed 004 section 7.1), at a
// corner of two lines (geometry.lines: its outgoing tangent in the plane is the turn's cosine and sine):
// by `start_distance` where it is > 0 (the biclothoid's start_distance; the clothoid method
// passes 0), else by the corner's tolerance (spec.parameter), shrunk to the shorter available
// move with pair_shrunk_note's note (empty where it fits).
struct LinePair {
  ClothoidPairShape shape;
  ClothoidPair pair;
  Note shrink_note;
  bool shrunk = false;  // shrunk to the shorter available move
};
LinePair line_pair(const CornerInput& corner, const PlanarCorner& geometry, double start_distance);
// The pair as the fit's transition (clothoid_pair_segments in the corner's plane), trimming its
// tangent length from both moves; parameter_used is what the method reports as used; limited
// where the pair was shrunk.
void use_line_pair(const LinePair& line, const CornerPlane& plane, double parameter_used, CornerFit& fit);

// seed 002 figs. 12-13: clothoid (0 -> kappa over clothoid_length), arc of curvature kappa,
// clothoid (kappa -> 0), symmetric, for a corner of deflection alpha (0 < alpha < pi);
// 0 <= clothoid_length <= alpha / kappa (at the upper end the arc vanishes and it is the pair
// with peak kappa; at 0 it is the plain arc of radius 1 / kappa).
//
// For a fixed kappa, deviation and tangent length grow strictly with clothoid_length. Proof:
// write the half curve by its radius of curvature as a function of the tangent angle,
// rho(theta) = ds / dtheta. On the clothoid theta = kappa s^2 / (2 Lc), so
// rho = sqrt(Lc / (2 kappa theta)) for theta < kappa Lc / 2 and rho = 1 / kappa on the arc;
// both branches give rho(theta) >= the old value when Lc grows, pointwise. Then
// Y = int_0^{alpha/2} rho sin(theta) dtheta and X = int rho cos(theta) dtheta grow (sin, cos > 0
// below pi/2), and with them d = Y / cos(alpha/2) and T = X + Y tan(alpha/2).
struct ClothoidArcClothoid {
  double alpha = 0;            // rad
  double kappa = 0;            // 1/m, peak curvature (the arc's)
  double clothoid_length = 0;  // m, each clothoid
  double arc_length = 0;       // m
  double tangent_length = 0;   // m
  double deviation = 0;        // m, corner to the arc's midpoint
};
ClothoidArcClothoid clothoid_arc_clothoid(double alpha, double kappa, double clothoid_length);

}  // namespace blendbench
