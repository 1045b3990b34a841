#include "planner/closest.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace blendbench {
namespace {

template <class... Ts>
struct Overloaded : Ts... {
  using Ts::operator()...;
};

Closest make(const Segment& segment, double s, const Vec3& query) {
  const Vec3 p = point(segment, s);
  return {s, p, (query - p).norm()};
}

// Dense scan of the squared distance, then golden-section refinement around the best sample.
Closest closest_numeric(const Segment& segment, const Vec3& query) {
  const double len = length(segment);
  constexpr int kSamples = 128;
  const double h = len / kSamples;
  double best_s = 0;
  double best_d = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= kSamples; ++i) {
    const double s = h * i;
    const double d = (point(segment, s) - query).squaredNorm();
    if (d < best_d) {
      best_d = d;
      best_s = s;
    }
  }
  double lo = std::max(0.0, best_s - h);
  double hi = std::min(len, best_s + h);
  constexpr double kGolden = 0.6180339887498949;
  const auto f = [&](double s) { return (point(segment, s) - query).squaredNorm(); };
  double x1 = hi - kGolden * (hi - lo);
  double x2 = lo + kGolden * (hi - lo);
  double f1 = f(x1);
  double f2 = f(x2);
  for (int it = 0; it < 80 && hi - lo > 1e-12 * std::max(len, 1e-9); ++it) {
    if (f1 > f2) {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + kGolden * (hi - lo);
      f2 = f(x2);
    } else {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - kGolden * (hi - lo);
      f1 = f(x1);
    }
  }
  const double s = f1 < f2 ? x1 : x2;
  Closest c = make(segment, s, query);
  if (best_d < c.distance * c.distance) c = make(segment, best_s, query);
  return c;
}

Closest closest_line(const Line& line, const Vec3& query) {
  const Vec3 d = line.p1 - line.p0;
  const double len2 = d.squaredNorm();
  const double t = len2 > 0 ? std::clamp((query - line.p0).dot(d) / len2, 0.0, 1.0) : 0.0;
  const Vec3 p = line.p0 + t * d;
  return {t * std::sqrt(len2), p, (query - p).norm()};
}

Closest closest_planar_arc(const Arc& arc, const Vec3& query) {
  const Vec3 rel = query - arc.center;
  const double x = rel.dot(arc.u);
  const double y = rel.dot(arc.v);
  double phi = std::atan2(y, x);
  if (phi < 0) phi += 2 * std::numbers::pi;
  if (x == 0 && y == 0) phi = 0;  // on the axis: every point is equally close
  const Segment seg = arc;
  if (phi <= arc.sweep) return make(seg, phi * arc.radius, query);
  // outside the sweep: the nearer end point
  const Closest a = make(seg, 0.0, query);
  const Closest b = make(seg, length(arc), query);
  return a.distance <= b.distance ? a : b;
}

}  // namespace

Closest closest_point(const Segment& segment, const Vec3& query) {
  return std::visit(Overloaded{
                        [&](const Line& line) { return closest_line(line, query); },
                        [&](const Arc& arc) {
                          return arc.rise == 0 && arc.sweep <= 2 * std::numbers::pi ? closest_planar_arc(arc, query)
                                                                                    : closest_numeric(segment, query);
                        },
                        [&](const Bezier&) { return closest_numeric(segment, query); },
                        [&](const Clothoid&) { return closest_numeric(segment, query); },
                    },
                    segment);
}

Closest closest_point(const Primitive& primitive, const Vec3& query) {
  return closest_point(to_segment(primitive), query);
}

namespace {

double directed(const std::vector<Segment>& from, const std::vector<Segment>& to, double step) {
  double worst = 0;
  for (const Segment& seg : from) {
    const double len = length(seg);
    const int n = std::max(64, static_cast<int>(std::ceil(len / std::max(step, 1e-15))));
    for (int i = 0; i <= n; ++i) {
      const Vec3 p = point(seg, len * i / n);
      double best = std::numeric_limits<double>::infinity();
      for (const Segment& target : to) best = std::min(best, closest_point(target, p).distance);
      worst = std::max(worst, best);
    }
  }
  return worst;
}

}  // namespace

double hausdorff(const std::vector<Segment>& a, const std::vector<Segment>& b, double step) {
  if (a.empty() || b.empty()) return 0;
  return std::max(directed(a, b, step), directed(b, a, step));
}

}  // namespace blendbench
