#include "blendbench/geometry/arc_construction.hpp"

#include "blendbench/core/format.hpp"

#include <cmath>
#include <numbers>
#include <sstream>

namespace blendbench {
namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;

ArcBuild failure(const std::string& message) { return {{Status::kInfeasible, message}, Arc{}}; }

}  // namespace

ArcBuild arc_from_center(const Vec3& start, const Vec3& end, const Vec3& center, const Vec3& normal, bool ccw,
                         int turns, double radius_tolerance) {
  const double nn = normal.norm();
  if (!(nn > 0)) return failure("the arc's plane normal is zero");
  // axis w: motion is counter-clockwise about w
  const Vec3 w = (ccw ? 1.0 : -1.0) * normal / nn;
  // centre projected into the start's plane; in-plane offsets of start and end
  Vec3 c = center + w * (start - center).dot(w);
  double rise = (end - start).dot(w);
  const Vec3 end_in_plane = end - w * rise;
  const double r_start = (start - c).norm();
  if (std::abs(rise) <= kRiseRounding * r_start) rise = 0;
  const double r_end = (end_in_plane - c).norm();
  if (!(r_start > radius_tolerance)) return failure("the arc's start point lies on its centre");
  if (std::abs(r_start - r_end) > radius_tolerance) {
    return failure("the radius to the end (" + format_mm(r_end) + ") differs from the radius to the start (" +
                   format_mm(r_start) + ")");
  }
  // move the centre onto the chord's perpendicular bisector so both radii are equal; a chord
  // at rounding level (a full circle) has no usable direction and needs no correction
  const Vec3 chord = end_in_plane - start;
  if (chord.norm() > 1e-9 * r_start) {
    const Vec3 dir = chord.normalized();
    c -= dir * (c - (start + 0.5 * chord)).dot(dir);
  }
  const Vec3 rs = start - c;
  const Vec3 re = end_in_plane - c;
  const double r = rs.norm();
  Arc arc;
  arc.center = c;
  arc.radius = r;
  arc.u = rs / r;
  arc.v = w.cross(arc.u);
  // sweep: angle from start to end about w in (0, 2 pi], a full circle when they coincide
  double sweep = std::atan2(re.dot(arc.v), re.dot(arc.u));
  if (sweep <= 0) sweep += kTwoPi;
  if (sweep < 1e-12 && re.dot(arc.u) > 0) sweep = kTwoPi;
  arc.sweep = sweep + kTwoPi * turns;
  arc.rise = rise;
  return {{}, arc};
}

ArcBuild arc_from_radius(const Vec3& start, const Vec3& end, double radius, const Vec3& normal, bool ccw,
                         double radius_tolerance) {
  const double nn = normal.norm();
  if (!(nn > 0)) return failure("the arc's plane normal is zero");
  if (!(std::abs(radius) > 0)) return failure("the arc radius is zero");
  const Vec3 w = (ccw ? 1.0 : -1.0) * normal / nn;
  const double rise = (end - start).dot(w);
  const Vec3 chord = end - w * rise - start;
  const double d = chord.norm();
  const double r = std::abs(radius);
  if (!(d > 0)) return failure("an arc given by its radius needs an end point distinct from its start");
  if (d > 2 * r + radius_tolerance) {
    return failure("the radius " + format_mm(r) + " is too small for the chord " + format_mm(d));
  }
  // centre on the perpendicular bisector of the chord, on the left of the motion (ccw about w)
  // for the short arc and on the right for the long one
  const double h = std::sqrt(std::max(0.0, r * r - 0.25 * d * d));
  const Vec3 left = w.cross(chord / d);
  const Vec3 mid = start + 0.5 * chord;
  const Vec3 center = mid + (radius > 0 ? h : -h) * left;
  // the radii agree by construction; allow for rounding
  return arc_from_center(start, end, center, w, true, 0, std::max(radius_tolerance, 1e-12 * r));
}

ArcBuild arc_through(const Vec3& start, const Vec3& via, const Vec3& end) {
  const Vec3 a = via - start;
  const Vec3 b = end - start;
  const Vec3 n = a.cross(b);
  const double scale = std::max({a.norm(), b.norm(), 1e-300});
  if (!(n.norm() > 1e-12 * scale * scale)) {
    return failure("the start, via and end points of the arc are collinear or coincide");
  }
  // circumcentre of the triangle (start, via, end)
  const Vec3 center = start + (b.squaredNorm() * n.cross(a) + a.squaredNorm() * b.cross(n)) / (2 * n.squaredNorm());
  // n = a x b orients the travel start -> via -> end counter-clockwise about n
  return arc_from_center(start, end, center, n, true, 0, 1e-9 * scale);
}

}  // namespace blendbench
