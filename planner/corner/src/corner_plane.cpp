// A corner seen in its plane (corner_plane.hpp): the programmed moves as planar shapes, the
// plane's frame, and the corners both clothoid methods treat alike.

#include "blendbench/corner/corner_plane.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <variant>

#include "biclothoid_internal.hpp"
#include "blendbench/core/format.hpp"
#include "blendbench/core/geometry.hpp"
#include "blendbench/core/input_error.hpp"

namespace blendbench {
using namespace biclothoid_detail;  // the helpers private to the biclothoid sources
namespace {

// Largest out-of-plane angle (rad) of a line or arc normal for a corner to count as planar.
constexpr double kPlanarAngle = 1e-10;

// sin(x) / x, exact to rounding near 0
double sinc(double x) {
  if (std::abs(x) < 1e-4) return 1.0 - x * x / 6.0;
  return std::sin(x) / x;
}

}  // namespace

Vec2 shape_point(const PlanarShape& shape, double sigma) {
  const double half = 0.5 * shape.kappa * sigma;
  return sigma * sinc(half) * direction(shape.theta + half);
}

double shape_angle(const PlanarShape& shape, double sigma) { return shape.theta + shape.kappa * sigma; }

Vec3 to_space(const CornerPlane& plane, const Vec2& p) { return plane.origin + p.x() * plane.x + p.y() * plane.y; }

namespace {

// A unit vector's direction in the plane (its component out of the plane, if any, dropped).
Vec2 in_plane(const Vec3& v, const CornerPlane& plane) {
  const Vec2 p(v.dot(plane.x), v.dot(plane.y));
  const double norm = p.norm();
  return norm > 0 ? Vec2(p / norm) : Vec2::UnitX();
}

// planar_corner for two lines, the commonest corner and the clothoid methods' fast path:
// segment.cpp's point and tangent arithmetic for lines (so every result is what the general
// code gave them, to the bit), without the variant dispatch, the curvature vectors (zero) and
// the arc checks; the general code below handles corners with an arc only.
PlanarCorner line_corner(const Line& in, const Line& out) {
  PlanarCorner pc;
  pc.lines = true;
  pc.planar = true;           // two lines through the corner span their normal's plane
  pc.same_curvature = true;   // both curvature vectors are zero
  const Vec3 d1 = in.p1 - in.p0;
  const double len_in = d1.norm();
  const Vec3 d2 = out.p1 - out.p0;
  const double len_out = d2.norm();
  const Vec3 t1 = len_in > 0 ? Vec3(d1 / len_in) : Vec3::Zero();
  const Vec3 t2 = len_out > 0 ? Vec3(d2 / len_out) : Vec3::Zero();
  // angle_between(t1, t2), its cross product and dot product kept: they are the cosine and sine
  // of the turn, so the outgoing tangent in the plane below
  Vec3 turn = t1.cross(t2);
  const double sin_angle = turn.norm();
  const double cos_angle = t1.dot(t2);
  pc.angle = std::atan2(sin_angle, cos_angle);
  // The plane's x axis is the incoming tangent itself, so a fillet starts on the incoming line
  // to the bit, and its normal t1 x t2 is made perpendicular to it. At a turn theta the cross
  // product's rounding (1e-16 of its unit factors) tilts its direction by 1e-16 / theta out of
  // the perpendicular; x was t1 projected off that normal, which at theta = 1e-8 rad moved a
  // 0.16 mm fillet's start 4e-13 m off the line (1.3e-9 of its size) and, towards the tangent
  // threshold kTangentAngle = 1e-9 rad, by up to 1e-7 of the fillet's tangent length.
  turn -= turn.dot(t1) * t1;
  // turn.normalized(), whose squared norm is also the test
  const double turn_squared = turn.squaredNorm();
  const Vec3 normal = turn_squared > 0 ? Vec3(turn / std::sqrt(turn_squared)) : any_perpendicular(t1);
  // point(in, length(in)): p0 + d1 * (len / len), and len / len is exactly 1
  pc.plane.origin = len_in > 0 ? Vec3(in.p0 + d1) : in.p0;
  pc.plane.x = t1;
  pc.plane.y = normal.cross(pc.plane.x);
  pc.shapes.q1 = PlanarShape{0.0, 0.0, Vec2::UnitX()};
  // the plane's normal is t1 x t2, so t2 turns by +angle from x; its tangent in the plane is
  // (t1 . t2, |t1 x t2|), as unit as t1 and t2 (no sincos in the commonest fit)
  pc.shapes.q2 = PlanarShape{pc.angle, 0.0, Vec2(cos_angle, sin_angle)};
  return pc;
}

}  // namespace

PlanarCorner planar_corner(const Primitive& in, const Primitive& out) {
  const Line* line1 = std::get_if<Line>(&in);
  const Line* line2 = std::get_if<Line>(&out);
  if (line1 && line2) return line_corner(*line1, *line2);
  PlanarCorner pc;
  const double len_in = length(in);
  const Vec3 corner = point(in, len_in);
  const auto [t1, k1] = tangent_and_curvature(in, len_in);
  const auto [t2, k2] = tangent_and_curvature(out, 0.0);
  pc.angle = angle_between(t1, t2);
  pc.same_curvature = (k1 - k2).norm() <= 1e-9 * std::max({k1.norm(), k2.norm(), 1e-300});
  // from here on, at least one move is an arc: the plane normal is the (first) arc's axis. (By
  // reference through std::get: GCC 12 saw a null dereference in the get_if pointers here.)
  const bool arc_in = std::holds_alternative<Arc>(in);
  if (arc_in && std::holds_alternative<Arc>(out)) {
    const Arc& arc1 = std::get<Arc>(in);
    const Arc& arc2 = std::get<Arc>(out);
    pc.same_circle = (arc1.center - arc2.center).norm() <= 1e-9 * arc1.radius &&
                     std::abs(arc1.radius - arc2.radius) <= 1e-9 * arc1.radius && arc1.rise == 0 && arc2.rise == 0 &&
                     arc1.u.cross(arc1.v).cross(arc2.u.cross(arc2.v)).norm() <= kPlanarAngle;
  }
  const Arc& axis_arc = std::get<Arc>(arc_in ? in : out);
  const Vec3 normal = axis_arc.u.cross(axis_arc.v).normalized();

  // planar: no helix, every line in the plane, every arc axis along the normal (the normal's own
  // arc has it by construction, so only the other move is checked)
  pc.planar = axis_arc.rise == 0;
  const Primitive& other = arc_in ? out : in;
  if (const Arc* arc = std::get_if<Arc>(&other)) {
    if (arc->rise != 0 || arc->u.cross(arc->v).normalized().cross(normal).norm() > kPlanarAngle) pc.planar = false;
  } else {
    const Line& line = std::get<Line>(other);
    if (std::abs((line.p1 - line.p0).normalized().dot(normal)) > kPlanarAngle) pc.planar = false;
  }

  pc.plane.origin = corner;
  pc.plane.x = (t1 - t1.dot(normal) * normal).normalized();
  pc.plane.y = normal.cross(pc.plane.x);
  const auto signed_curvature = [&](const Primitive& prim) {
    const Arc* arc = std::get_if<Arc>(&prim);
    if (!arc) return 0.0;
    return (arc->u.cross(arc->v).dot(normal) > 0 ? 1.0 : -1.0) / arc->radius;
  };
  pc.shapes.q1 = PlanarShape{0.0, signed_curvature(in), Vec2::UnitX()};
  const Vec2 t2_in_plane = in_plane(t2, pc.plane);
  pc.shapes.q2 = PlanarShape{std::atan2(t2_in_plane.y(), t2_in_plane.x()), signed_curvature(out), t2_in_plane};
  return pc;
}

std::optional<CornerFit> clothoid_special_case(const CornerInput& corner, const PlanarCorner& geometry) {
  CornerFit fit;
  fit.parameter_used = 0;
  // a reversal has no fillet: a kink that stops the path when Buffered (seed 001, seed 003)
  if (geometry.angle >= kPi - kReversalAngle) {
    fit.corner_case = geometry.same_circle ? CornerCase::kSameCircleOppositeDirection : CornerCase::kReversal;
    fit.stop = corner.buffer == BufferMode::kBuffered;
    fit.note = "the path reverses at the corner: no curvature-continuous transition exists, the corner stays a kink";
    return fit;
  }
  const bool tangent = geometry.angle <= kTangentAngle;
  // already G2: nothing to smooth
  if (tangent && geometry.same_curvature) {
    fit.corner_case = geometry.same_circle ? CornerCase::kSameCircleSameDirection : CornerCase::kCollinear;
    return fit;
  }
  // no length left on a move (consumed by the neighbouring corner): the corner stays as it is
  if (!(corner.in_available > 0) || !(corner.out_available > 0)) {
    fit.outcome = {Status::kInfeasible, corner.name + ": no length of the " +
                                            (corner.in_available > 0 ? "outgoing" : "incoming") +
                                            " move is left for a transition"};
    return fit;
  }
  if (corner.spec.parameter <= 0 && corner.spec.start_distance <= 0) {
    if (!tangent) {
      fail_at(corner.where, "transition.parameter",
              corner.name + ": a " + std::string(to_string(corner.spec.method)) +
                  " transition with maximum deviation 0 is impossible at a tangent discontinuity of " +
                  format_deg(geometry.angle) + "; give a positive deviation or use method none");
    }
    fit.corner_case = CornerCase::kTangent;
    fit.note = "maximum deviation 0: the curvature jump is left as programmed";
    return fit;
  }
  return std::nullopt;
}

Note pair_shrunk_note(bool by_start_distance, double asked, double used, const CornerInput& corner) {
  return Note::lengths(by_start_distance ? Note::Literal("start distance shrunk from ")
                                         : Note::Literal("deviation shrunk from "),
                       asked, " to ", used,
                       corner.in_available <= corner.out_available ? Note::Literal("the incoming move is short")
                                                                   : Note::Literal("the outgoing move is short"));
}

}  // namespace blendbench
