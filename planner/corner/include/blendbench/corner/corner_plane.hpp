#pragma once
// A corner between two programmed moves seen in its plane: the moves as planar shapes through
// the corner (a line or a circle), the plane's frame in 3D, and the corners that both clothoid
// methods (fit_clothoid_corner, seed 002 (Makino); fit_biclothoid_corner, seed 004) treat alike before fitting.
//
// Plane conventions: 2D coordinates in the corner plane with the corner at the origin, angles
// in rad measured counter-clockwise from the x axis, curvature signed (positive turns left),
// lengths in m.

#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>

#include <Eigen/Core>

#include "blendbench/corner/corner.hpp"
#include "blendbench/geometry/segment.hpp"

namespace blendbench {

using Vec2 = Eigen::Vector2d;

// A programmed move near the corner: a line (kappa = 0) or a circle through the origin (the
// corner) with tangent angle `theta` there; sigma is the signed arc length from the corner
// along the direction of travel (negative before the corner). `t` is the unit tangent there,
// (cos theta, sin theta), computed once by the constructor: the biclothoid fit needs it in
// every solve and every deviation measure (make a new shape rather than change theta).
// planar_corner passes the tangent it has, its move's tangent in the plane's frame.
struct PlanarShape {
  PlanarShape() = default;
  PlanarShape(double angle, double curvature)
      : theta(angle), kappa(curvature), t(std::cos(angle), std::sin(angle)) {}
  PlanarShape(double angle, double curvature, const Vec2& tangent) : theta(angle), kappa(curvature), t(tangent) {}
  double theta = 0;
  double kappa = 0;
  Vec2 t = Vec2::UnitX();
};

Vec2 shape_point(const PlanarShape& shape, double sigma);
double shape_angle(const PlanarShape& shape, double sigma);

// The incoming shape q1 reaches the corner (the origin), the outgoing q2 leaves it. A fillet
// starts at sigma = -a on q1 and ends at sigma = +b on q2.
struct CornerShapes {
  PlanarShape q1;
  PlanarShape q2;
};

// The same corner travelled backwards: q2 turned round comes in, q1 turned round goes out
// (a fillet of it from a to b is the forward fillet from b to a, reversed). Each unit tangent
// is negated, exactly, not recomputed from the turned angle.
inline CornerShapes reversed(const CornerShapes& shapes) {
  return {PlanarShape{shapes.q2.theta + std::numbers::pi, -shapes.q2.kappa, -shapes.q2.t},
          PlanarShape{shapes.q1.theta + std::numbers::pi, -shapes.q1.kappa, -shapes.q1.t}};
}

// The plane of a corner in 3D: the corner point and an orthonormal basis (x, y) of the plane;
// 2D corner coordinates map to origin + px x + py y.
struct CornerPlane {
  Vec3 origin = Vec3::Zero();
  Vec3 x = Vec3::UnitX();
  Vec3 y = Vec3::UnitY();
};
Vec3 to_space(const CornerPlane& plane, const Vec2& p);

// A corner between two programmed moves seen in its plane. For two lines the plane is the one
// they span, oriented so that the turn is positive (towards +y); with an arc it is the arc's
// plane (normal u x v of the arc, of the incoming one when both are arcs). x is the incoming
// tangent at the corner, so shapes.q1.theta = 0.
struct PlanarCorner {
  bool planar = false;        // false: a helix, or a line or arc out of the other arc's plane
  bool lines = false;         // both moves are lines
  bool same_circle = false;   // two arcs on one circle (same centre, radius and plane)
  bool same_curvature = false;  // equal curvature vectors at the corner
  double angle = 0;           // rad, unsigned angle between the tangents at the corner (3D)
  CornerPlane plane;
  CornerShapes shapes;  // valid when planar
};
PlanarCorner planar_corner(const Primitive& in, const Primitive& out);

// The corners both clothoid methods treat alike, or nullopt for a corner to fit:
//  - a reversal (tangent turns by pi, within 1e-9 rad): no fillet exists; a kink ("reversal",
//    or "same_circle_opposite_direction"), a stop when the buffer mode is Buffered;
//  - a G2-continuous corner (equal tangents and curvature vectors): nothing to do
//    ("collinear", or "same_circle_same_direction");
//  - parameter 0 at a tangent discontinuity: throws InputError at corner.where
//    (field transition.parameter), since no curve stays within a zero deviation;
//  - parameter 0 at a curvature jump only ("tangent"): the path is left as programmed;
//  - no length available on one of the moves: outcome kInfeasible (the blender stops there).
std::optional<CornerFit> clothoid_special_case(const CornerInput& corner, const PlanarCorner& geometry);

// The note of a line-line clothoid pair shrunk to the shorter of its moves, as both clothoid
// methods give it: "deviation (start distance, when `by_start_distance`) shrunk from <asked> to
// <used>: the incoming (outgoing) move is short" (asked, used in m; formatted when read).
Note pair_shrunk_note(bool by_start_distance, double asked, double used, const CornerInput& corner);

}  // namespace blendbench
