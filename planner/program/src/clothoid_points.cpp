#include "blendbench/program/clothoid_points.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <utility>

#include "blendbench/core/format.hpp"

namespace blendbench {
namespace {

// Consecutive points closer than this (m) are one point.
constexpr double kSamePoint = 1e-12;
// A pair turning by less than this (rad) is a line; two directions within it are symmetric
// about the chord (a single arc, no biarc point).
constexpr double kStraight = 1e-12;
// The share of the circle-tangent formula's size below which a point has no direction (the
// stream reverses there).
constexpr double kReversal = 1e-9;

// The tangent at b of the circle through a, b, c: the chords a->b and b->c weighted by the
// other's squared length, |bc|^2 (b - a) + |ab|^2 (c - b) (unit; on a line, the line's direction).
// Empty when the points reverse at b.
std::optional<Vec3> circle_tangent(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 u = b - a;
  const Vec3 v = c - b;
  const Vec3 t = v.squaredNorm() * u + u.squaredNorm() * v;
  const double scale = u.norm() * v.norm() * (u.norm() + v.norm());
  if (!(t.norm() > kReversal * scale)) return std::nullopt;
  return Vec3(t.normalized());
}

// The end tangent at a of the circle through a, b with tangent t_b at b: t_b mirrored about the
// chord (a chord of a circle bisects the tangents at its ends).
Vec3 mirrored(const Vec3& t_b, const Vec3& a, const Vec3& b) {
  const Vec3 chord = (b - a).normalized();
  return (2 * t_b.dot(chord) * chord - t_b).normalized();
}

// A point with its unit direction.
struct Pose {
  Vec3 p;
  Vec3 t;
};

// Seed 002 eq. 9 and Fig. 5-6: the symmetric clothoid pair from a (direction a.t) to b, whose
// direction is a.t mirrored about the chord. Each half turns by omega, the angle between a.t and
// the chord; a clothoid of length L from zero curvature turning by omega has sharpness
// 2 omega / L^2, and its end lies L (X, Y) from its start, (X, Y) the unit clothoid of
// sharpness 2 omega; the two halves together span the chord l = 2 L (X cos omega + Y sin omega).
void symmetric_pair(const Pose& a, const Vec3& b, std::vector<Segment>& out) {
  const Vec3 chord = b - a.p;
  const double l = chord.norm();
  const Vec3 c = chord / l;
  const double omega = angle_between(a.t, c);
  if (!(omega > kStraight)) {
    out.emplace_back(Line{a.p, b});
    return;
  }
  const Vec3 e1 = a.t;
  const Vec3 e2 = (c - c.dot(e1) * e1).normalized();
  const double phi = 2 * omega;  // the pair's turn
  const Eigen::Vector2d unit = clothoid_xy(0.0, phi, 1.0);
  const double cs = std::cos(omega);
  const double sn = std::sin(omega);
  const double len = l / (2 * (unit.x() * cs + unit.y() * sn));
  Clothoid first{a.p, e1, e2, 0.0, phi / (len * len), len};
  const Vec3 middle = a.p + len * (unit.x() * e1 + unit.y() * e2);
  Clothoid second{middle, cs * e1 + sn * e2, -sn * e1 + cs * e2, phi / len, -phi / (len * len), len};
  out.emplace_back(first);
  out.emplace_back(second);
}

// The circular arc from a to b leaving a along a.t (b not on that line), cut into `parts` equal
// arcs: their end points and directions after a, b last.
std::vector<Pose> arc_points(const Pose& a, const Pose& b, int parts) {
  std::vector<Pose> out;
  const Vec3 chord = b.p - a.p;
  const Vec3 normal = (chord - chord.dot(a.t) * a.t).normalized();  // from a towards the centre
  const double turn = 2 * angle_between(a.t, chord);
  const double radius = chord.norm() / (2 * std::sin(0.5 * turn));
  const Vec3 centre = a.p + radius * normal;
  for (int j = 1; j < parts; ++j) {
    const double psi = turn * j / parts;
    out.push_back({centre + radius * (std::sin(psi) * a.t - std::cos(psi) * normal),
                   std::cos(psi) * a.t + std::sin(psi) * normal});
  }
  out.push_back(b);
  return out;
}

// The junction of the biarc from a to b with equal tangent legs d: the legs' ends a.p + d a.t and
// b.p - d b.t are 2 d apart, so (2 a.t.b.t - 2) d^2 - 2 (v.t) d + v.v = 0 with v = b.p - a.p and
// t = a.t + b.t; its positive root, 2 v.v / (2 v.t + sqrt(4 (v.t)^2 + 8 (1 - a.t.b.t) v.v)),
// stays finite where the tangents are parallel. Empty when there is none (equal tangents that
// point away from the chord).
std::optional<Pose> biarc_junction(const Pose& a, const Pose& b) {
  const Vec3 v = b.p - a.p;
  const double vt = v.dot(a.t + b.t);
  const double vv = v.squaredNorm();
  const double disc = 4 * vt * vt + 8 * std::max(0.0, 1 - a.t.dot(b.t)) * vv;
  const double denominator = 2 * vt + std::sqrt(disc);
  if (!(denominator > kReversal * v.norm())) return std::nullopt;
  const double d = 2 * vv / denominator;
  const Vec3 p = a.p + d * a.t;
  const Vec3 q = b.p - d * b.t;
  const Vec3 leg = q - p;
  if (!(leg.norm() > kReversal * v.norm())) return std::nullopt;
  return Pose{0.5 * (p + q), leg.normalized()};
}

}  // namespace

CurveFit clothoid_points(const std::vector<Vec3>& points, const CurveEnds& ends, double max_turn) {
  CurveFit fit;
  const auto infeasible = [](std::string why) {
    CurveFit out;
    out.outcome = {Status::kInfeasible, std::move(why)};
    return out;
  };
  // distinct points, each with the index of the input segment it starts (of a repeated point,
  // the last copy's: the segment of non-zero length)
  std::vector<Vec3> x;
  std::vector<std::size_t> segment;
  for (std::size_t k = 0; k < points.size(); ++k) {
    if (!x.empty() && (points[k] - x.back()).norm() <= kSamePoint) {
      segment.back() = k;
      continue;
    }
    x.push_back(points[k]);
    segment.push_back(k);
  }
  if (ends.closed && x.size() > 1 && (x.back() - x.front()).norm() <= kSamePoint) x.back() = x.front();
  if (x.size() < 2) return infeasible("fewer than two distinct points");
  const std::size_t n = x.size();
  // the arc length of the input polyline at each point
  std::vector<double> sigma(points.size(), 0.0);
  for (std::size_t k = 1; k < points.size(); ++k) sigma[k] = sigma[k - 1] + (points[k] - points[k - 1]).norm();

  // directions: circle tangents inside (and across the closing point), given or mirrored ends
  std::vector<Vec3> t(n);
  const auto no_direction = [&](std::size_t i) {
    return infeasible("no direction at point " + std::to_string(segment[i] + 1) + ": the points reverse there");
  };
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const auto dir = circle_tangent(x[i - 1], x[i], x[i + 1]);
    if (!dir) return no_direction(i);
    t[i] = *dir;
  }
  if (ends.closed && n > 3) {
    const auto dir = circle_tangent(x[n - 2], x[0], x[1]);
    if (!dir) return no_direction(0);
    t[0] = t[n - 1] = *dir;
  } else {
    if (n == 2) t[0] = t[1] = (x[1] - x[0]).normalized();
    t[0] = ends.start_tangent ? ends.start_tangent->normalized() : n > 2 ? mirrored(t[1], x[0], x[1]) : t[0];
    t[n - 1] = ends.end_tangent ? ends.end_tangent->normalized() : n > 2 ? mirrored(t[n - 2], x[n - 1], x[n - 2]) : t[n - 1];
  }

  // per pair of points: one arc where the directions are symmetric about the chord, else the
  // biarc's two; each arc cut into parts of at most max_turn, a symmetric clothoid pair each
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const Pose a{x[i], t[i]};
    const Pose b{x[i + 1], t[i + 1]};
    const Vec3 chord = (b.p - a.p).normalized();
    std::vector<Pose> arcs;  // end of each arc
    const Vec3 sum = a.t + b.t;
    if (sum.norm() > kStraight && angle_between(sum, chord) <= kStraight) {
      arcs.push_back(b);
    } else {
      const auto junction = biarc_junction(a, b);
      if (!junction) {
        return infeasible("no biarc between points " + std::to_string(segment[i] + 1) + " and " +
                          std::to_string(segment[i] + 2) + ": their directions point away from each other");
      }
      arcs.push_back(*junction);
      arcs.push_back(b);
      ++fit.points_added;
    }
    const std::size_t first_piece = fit.pieces.size();
    Pose from = a;
    for (const Pose& to : arcs) {
      const double turn = 2 * angle_between(from.t, to.p - from.p);
      if (!(turn < 2 * std::numbers::pi - kStraight)) {
        return infeasible("the arc between points " + std::to_string(segment[i] + 1) + " and " +
                          std::to_string(segment[i] + 2) + " would turn a full circle");
      }
      const int parts = turn > kStraight ? std::max(1, static_cast<int>(std::ceil(turn / max_turn - 1e-12))) : 1;
      std::vector<Pose> ends_of_parts = parts > 1 ? arc_points(from, to, parts) : std::vector<Pose>{to};
      fit.points_added += parts - 1;
      for (const Pose& end : ends_of_parts) {
        symmetric_pair(from, end.p, fit.pieces);
        from = end;
      }
    }
    for (std::size_t j = first_piece; j < fit.pieces.size(); ++j) {
      fit.piece_segment.push_back(segment[i]);
      fit.span_begin.push_back(sigma[segment[i]]);
      fit.span_end.push_back(i + 1 < segment.size() ? sigma[segment[i + 1]] : sigma.back());
    }
  }
  return fit;
}

}  // namespace blendbench
