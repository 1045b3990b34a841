#pragma once
// Biclothoid fillets (seed 004, Shahzadeh et al. 2018) in the plane of a corner.
//
// A biclothoid is two clothoids back to back whose sharpness values are opposite (seed 004 def. 2,
// eq. 7-8): the curvature rises (or falls) linearly from kappa0 to a peak kappa_m over s1 and
// returns linearly to kappa_e over s2. fit_biclothoid_corner (corner.hpp) uses it to replace a
// corner between two lines, a line and an arc or two arcs by a G2 fillet whose deviation from
// the programmed path is bounded by a tolerance (seed 004 Algorithms 1 and 2).
//
// The sources follow the algorithm: the curve (biclothoid_curve.cpp), Algorithm 1
// (biclothoid_fit.cpp), the deviation (biclothoid_deviation.cpp), Algorithm 2 and the
// start-distance fit (biclothoid_tolerance.cpp), the corner method (biclothoid_corner.cpp).
//
// Plane conventions as in corner_plane.hpp: 2D coordinates in the corner plane, angles in rad
// measured counter-clockwise from the x axis, curvature signed (positive turns left), lengths in m.

#include <optional>
#include <vector>

#include "blendbench/core/status.hpp"
#include "blendbench/corner/corner_plane.hpp"
#include "blendbench/geometry/segment.hpp"

namespace blendbench {

// seed 004 definition 1: position, curvature (1/m, signed) and tangent angle (rad) at a point.
struct Posture {
  Vec2 p = Vec2::Zero();
  double kappa = 0;
  double theta = 0;
};

// A biclothoid: clothoid 1 from `start` with sharpness c over s1, clothoid 2 with sharpness -c
// over s2 (seed 004 eq. 7-8). `mid` is the posture where they meet (the curvature extremum); it is
// filled by make_biclothoid so that evaluation is cheap.
struct Biclothoid {
  Posture start;
  double c = 0;   // 1/m^2
  double s1 = 0;  // m
  double s2 = 0;  // m
  Posture mid;
};

// Completes `mid` from start, c, s1, s2 (s1, s2 >= 0).
Biclothoid make_biclothoid(const Posture& start, double c, double s1, double s2);

// seed 004 eq. 9-14: the biclothoid of total length `length` (> 0) that starts at `start` and ends
// with curvature kappa_e and tangent angle start.theta + dtheta. Always exists; derived in
// closed form (biclothoid_curve.cpp) in a form that stays exact when kappa0 = kappa_e, where
// eq. 11 is 0/0. nullopt only for a non-positive or non-finite length.
std::optional<Biclothoid> biclothoid_from_turn(const Posture& start, double kappa_e, double dtheta, double length);

// The curve of biclothoid_from_turn with its end point and the derivatives of that end point
// with respect to the length and the turn (kappa_e and start held), in closed form from the
// first three moments of each clothoid's tangent (derived in biclothoid_curve.cpp);
// Algorithm 1 uses them for Newton's method. nullopt as for biclothoid_from_turn.
struct BiclothoidEnd {
  Biclothoid curve;
  Vec2 p = Vec2::Zero();         // end point
  Vec2 tangent = Vec2::Zero();   // unit tangent at the end
  Vec2 d_length = Vec2::Zero();  // d p / d length (dimensionless)
  Vec2 d_turn = Vec2::Zero();    // d p / d dtheta (m/rad)
  double kappa_e = 0;            // 1/m, as asked
  double turn = 0;               // rad, dtheta as asked
  // for biclothoid_end_moved: the first clothoid's unit tangent at the peak (s1) and its
  // tangent's second moment about the start, int_0^s1 u^2 T(u) du (m^3)
  Vec2 peak_tangent = Vec2::Zero();
  Vec2 peak_moment = Vec2::Zero();
};
std::optional<BiclothoidEnd> biclothoid_end(const Posture& start, double kappa_e, double dtheta, double length);
// The same, given the start's unit tangent (direction(start.theta)).
std::optional<BiclothoidEnd> biclothoid_end(const Posture& start, const Vec2& start_tangent, double kappa_e,
                                            double dtheta, double length);
// biclothoid_end at the length and turn of `from` moved by `length_step` and `turn_step`, without
// new moments, for Algorithm 1's last Newton step (where both are ~1e-7 of the length and the
// turn): the curve exact (c and s1 from the new length and turn, the peak point carried by its
// derivatives to second order, derived in biclothoid_curve.cpp; ~1e-16 of the length off the
// new curve's peak), the end point linear in the steps (off by their squares: the caller knows
// how much that is) and the end's derivatives those of `from`. nullopt where the peak moves by
// more than 1e-5 of the length or the sharpness c by more than 1e-6 / length^2 (s1 is
// ill-conditioned where c -> 0, and the second-order terms would not do), or for a
// non-positive length.
std::optional<BiclothoidEnd> biclothoid_end_moved(const BiclothoidEnd& from, double length_step, double turn_step);

double length(const Biclothoid& curve);
// The posture at arc length s in [0, length] (clamped).
Posture posture_at(const Biclothoid& curve, double s);
Posture end_posture(const Biclothoid& curve);
// The same curve traversed backwards (a biclothoid again: c -> -c, s1 <-> s2).
Biclothoid reversed(const Biclothoid& curve);
// The same, given the curve's end point (as biclothoid_end found it), which then is not
// integrated again.
Biclothoid reversed(const Biclothoid& curve, const Vec2& end);

// seed 004 Algorithm 1 (derived here: the paper gives only its first lines): the biclothoid that
// starts G2 on q1 at distance `a` before the corner and ends G2 on q2. Unknowns: its length L
// and the end distance b on q2; it turns by the programmed turn delta + kappa1 a + kappa2 b
// (delta the tangent jump at the corner). When q2 is a line the turn is fixed and one scalar
// equation in L remains (Newton, safeguarded by a bracket); otherwise a damped Newton method on
// (L, b). Both use the closed-form derivatives of biclothoid_end. (guess_length, guess_b)
// start the iteration (0 = derive a guess). nullopt when it does not converge or the solution
// leaves b > 0, L > 0.
struct BiclothoidSolution {
  Biclothoid curve;
  double a = 0;  // m, start distance before the corner on q1
  double b = 0;  // m, end distance after the corner on q2
};
std::optional<BiclothoidSolution> fit_biclothoid_at(const CornerShapes& shapes, double a, double guess_length = 0,
                                                    double guess_b = 0);

// seed 004 section 7.1: directed Hausdorff distances between the replaced programmed path
// U = q1[-a, 0] + q2[0, b] and the fillet V, by nested one-dimensional solvers (for a point of
// U, Newton for its closest point on V; over U, a sampled search refined by a secant method on
// the derivative of the distance). `fillet_to_original` (V -> U) uses exact distances to lines
// and circles, a sampled search refined by Newton on their derivative (or, at a tangent jump,
// on the difference of the distances to both sides).
struct Deviation {
  double original_to_fillet = 0;  // m, seed 004 eq. 15 with U the original path
  double fillet_to_original = 0;  // m
  [[nodiscard]] double max() const {
    return original_to_fillet > fillet_to_original ? original_to_fillet : fillet_to_original;
  }
};
Deviation biclothoid_deviation(const BiclothoidSolution& fillet, const CornerShapes& shapes);

// seed 004 Algorithm 2 (derived here; the paper gives only its first lines): the largest fillet
// whose deviation (the larger of the two directed distances) stays within `tolerance` (m, > 0),
// with a <= a_max and b <= b_max (m). Follows section 6: if q2 is more curved than q1 the corner
// is reversed (q1 <-> q2) and the fillet reversed back at the end. The start distance comes from
// Newton's method on y = max(log(deviation / tolerance), log(b / b_max)) against x = log(a)
// (y is nearly linear in x: deviation ~ a at a tangent jump, ~ a^2 at a curvature jump), its
// slope from the envelope theorem at the point where the deviation is attained (derived in
// biclothoid_tolerance.cpp), kept inside the bracket once there is one, bisection otherwise;
// the first a blends the two small-fillet models, so two solves usually suffice. Where the end
// bound b <= b_max sets y (a trial's b / b_max above its deviation / tolerance), Algorithm 1 is
// solved once from the other end, on the reversed corner with b = b_max and warm-started from
// that trial, which is the answer when its deviation is within the tolerance. The result satisfies
// tolerance (1 - 1e-4) <= deviation <= tolerance unless the move lengths limit it (`limited` =
// true, deviation < tolerance). A fillet replaces at most an eighth of a turn of an arc (a
// larger one is no longer a corner fillet, and its turn approaches 2 pi) and stays short of a
// point where q1 and q2 cross again (possible near a reversal). outcome: kNotConverged when
// no solve succeeds.
struct BiclothoidToleranceFit {
  Outcome outcome;
  BiclothoidSolution fillet;  // in the original direction (a on q1, b on q2)
  // max() as biclothoid_deviation gives it; where original_to_fillet is the smaller of the
  // two it may fall short of its maximum (it is not refined where it cannot be the larger)
  Deviation deviation;
  bool limited = false;    // the move lengths (a_max / b_max) or the caps bound it
  bool converged = false;  // limited, or the deviation reached the tolerance band
  bool swapped = false;  // solved on the reversed corner (section 6)
  int solves = 0;        // Algorithm 1 calls, for diagnostics
};
BiclothoidToleranceFit fit_biclothoid_with_tolerance(const CornerShapes& shapes, double tolerance, double a_max,
                                                     double b_max);

// Where Algorithm 2 starts at a corner with both a tangent jump delta and a curvature jump: a
// small fillet there starts `start` times the line-line pair's start (the pair of the tolerance
// at the turn |delta|) before the corner and ends `end` times its own start after it, at
// rho = a_angle / a_curvature (a_curvature = sqrt(42 tol / |kappa jump|)); `aligned`:
// delta (kappa2 - kappa1) > 0, the curvature jump turning the path the way the tangent jump
// does, on the corner as Algorithm 2 solves it (from the more curved shape, section 6). Tables
// of Algorithm 2's own small-fillet solutions (their source is in biclothoid_tolerance.cpp):
// start 1 (to 5e-5) and end 1 below rho = 0.01; above 1000 rho start tends as 1 / rho to the
// curvature jump alone's limit, 1.00046 (biclothoid_curvature_jump_start), and end to
// kEndShare's 0.435.
struct BiclothoidMixedShares {
  double start;
  double end;
};
BiclothoidMixedShares biclothoid_mixed_shares(double rho, bool aligned);

// How the arcs' own curvatures move that start at a tangent jump delta: d log a / d (sgn(delta)
// kappa_i a) for the fillet's start a within the tolerance, at kappa_i -> 0, for the arc the
// fit starts on (`in`, q1) and the one it ends on (`out`, q2), on the corner as Algorithm 2
// solves it (section 6). Both vanish as |delta| -> 0 (there a common curvature bends the path
// and the fillet alike, and only the jump counts: biclothoid_mixed_shares) and reach -0.44 at a
// reversal. A table of Algorithm 2's own solutions (biclothoid_tolerance.cpp), in |delta|.
struct BiclothoidArcSensitivity {
  double in;
  double out;
};
BiclothoidArcSensitivity biclothoid_arc_sensitivity(double turn);

// Where Algorithm 2 starts at a curvature jump alone (a tangent corner): log(a / a_curvature)
// for the fillet's start a within the tolerance, a_curvature = sqrt(42 tol / |kappa2 - kappa1|),
// against u_i = kappa_i a_curvature on the corner as Algorithm 2 solves it (|u1| >= |u2|,
// section 6). Even in (u1, u2) (a mirror image flips both), 4.6e-4 at u -> 0 (seed 004's 42
// is 42.04) and -1e-2 at |u| = 0.8; a quadratic fitted to Algorithm 2's own solutions
// (biclothoid_tolerance.cpp), within 2.2e-5 of them for |u2| <= |u1| <= 0.8; farther out, its
// value where the ray to (u1, u2) leaves that range (at most -1.3e-2; not a number: 0).
double biclothoid_curvature_jump_start(double u1, double u2);

// Algorithm 1's fillet at a curvature jump alone (a tangent corner) at start distance a: its
// length L and end distance b as shares of a, against u_i = kappa_i a. Even in (u1, u2) (a
// mirror image flips both), tending to 1 + 0.4354 and 0.4354 as u -> 0 (the small fillet's end
// share, derived in biclothoid_internal.hpp); quadratics in their logarithms fitted to Algorithm
// 1's own solutions (biclothoid_fit.cpp), within 3e-5 (L) and 5e-5 (b) of them for |u1|, |u2| <=
// pi / 4 (a fillet replaces at most an eighth of a turn of an arc); farther out, the value
// where the ray to (u1, u2) leaves that range; not a number: the u -> 0 limit. Algorithm 1's
// cold guess where the curvature jump dominates.
struct BiclothoidJumpFillet {
  double length;  // L / a
  double end;     // b / a
};
BiclothoidJumpFillet biclothoid_curvature_jump_fillet(double u1, double u2);

// The length of the symmetric clothoid pair (curvature 0 at both ends, seed 002 (Makino)) that
// turns by `turn` (rad) between two points `chord` apart: chord u / (C(u) cos(turn / 2) +
// S(u) sin(turn / 2)), u = sqrt(turn / pi), C and S the Fresnel integrals; 0 where no such pair
// exists (turn <= 0, or beyond 1.46 pi, where the pair's ends would cross).
// Algorithm 1's guess for a fillet that turns by more than the corner between nearby points
// (a hairpin, near a reversal: fit_biclothoid_at).
double biclothoid_hairpin_length(double chord, double turn);

// The other way to size a fillet (seed 004 Algorithm 1 alone): it starts `start_distance` (m, > 0)
// before the corner on q1. The start distance is capped as in the tolerance fit (a_max, an
// eighth of a turn of an arc, short of where the moves cross again); when Algorithm 1 finds no
// fillet there or its end distance b exceeds b_max (or an eighth of a turn of q2), the start
// distance is shrunk to the largest that fits (halving, then bisection in log a to 1e-9), and
// `limited` is set. `deviation` is measured (seed 004 section 7.1). outcome: kNotConverged when no
// start distance down to 2^-60 of the request fits.
struct BiclothoidStartFit {
  // Why the start distance used is below the one asked for.
  enum class Limit {
    kNone,
    kIncoming,    // a_max, an eighth of a turn of q1, or where the moves cross again
    kOutgoing,    // the fillet would end beyond b_max (or an eighth of a turn of q2)
    kNoSolution,  // Algorithm 1 found no fillet at the larger start distances
  };
  Outcome outcome;
  BiclothoidSolution fillet;
  Deviation deviation;
  Limit limit = Limit::kNone;
};
BiclothoidStartFit fit_biclothoid_from_start(const CornerShapes& shapes, double start_distance, double a_max,
                                             double b_max);

// The clothoid segments of a biclothoid in 3D (pieces of zero length omitted).
std::vector<Segment> to_segments(const Biclothoid& curve, const CornerPlane& plane);

// fit_biclothoid_corner (corner.hpp) for a corner whose plane is known (planar_corner) and that
// is none of clothoid_special_case's cases: the clothoid method's corners with an arc, which
// have found both already (planar_corner is about 6 % of such a fit).
CornerFit fit_biclothoid_in_plane(const CornerInput& corner, const PlanarCorner& geometry);

}  // namespace blendbench
