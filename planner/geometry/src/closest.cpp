#include "blendbench/geometry/closest.hpp"

#include "blendbench/core/golden.hpp"
#include "blendbench/core/overloaded.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>
#include <vector>

namespace blendbench {
namespace {

Closest make(const Segment& segment, double s, const Vec3& query) {
  const Vec3 p = point(segment, s);
  return {s, p, (query - p).norm()};
}

// Golden-section refinement of every local minimum of squared distances `d2[i]` sampled at
// t = h * i on [0, t_max]; `f2(t)` is the squared distance. Returns the best {t, d2}. Every
// local minimum, not only the smallest sample: on a multi-turn helix the nearest turn can
// sample worse than a farther one when the query sits between samples.
template <class F2>
std::pair<double, double> refine_minima(const std::vector<double>& d2, double h, double t_max, const F2& f2,
                                        double width, int max_iterations) {
  // the smallest sample is a local minimum too, so one pass sees it; the search's best point
  // can be worse than the sample it started from, which is kept then
  const std::size_t n = d2.size();
  std::pair<double, double> best{0.0, std::numeric_limits<double>::infinity()};
  for (std::size_t i = 0; i < n; ++i) {
    const bool left_ok = i == 0 || d2[i] <= d2[i - 1];
    const bool right_ok = i + 1 == n || d2[i] <= d2[i + 1];
    if (!left_ok || !right_ok) continue;
    const double t = h * static_cast<double>(i);
    if (d2[i] < best.second) best = {t, d2[i]};
    const auto refined = golden_minimum(f2, std::max(0.0, t - h), std::min(t_max, t + h), width, max_iterations);
    if (refined.second < best.second) best = refined;
  }
  return best;
}

// Dense scan of the squared distance over a parameter t in [0, t_max] with position `at(t)`,
// then refinement of its local minima; returns the best t and distance.
template <class At>
std::pair<double, double> scan_closest(const At& at, double t_max, const Vec3& query) {
  constexpr int kSamples = 128;
  const double h = t_max / kSamples;
  std::vector<double> d2(kSamples + 1);
  for (int i = 0; i <= kSamples; ++i) d2[static_cast<std::size_t>(i)] = (at(h * i) - query).squaredNorm();
  const auto [t, d] = refine_minima(d2, h, t_max, [&](double x) { return (at(x) - query).squaredNorm(); },
                                    1e-12 * std::max(t_max, 1e-9), 80);
  return {t, std::sqrt(d)};
}

Closest closest_numeric(const Segment& segment, const Vec3& query) {
  const auto [s, d] = scan_closest([&](double x) { return point(segment, x); }, length(segment), query);
  return {s, point(segment, s), d};
}

// A Bezier is scanned in its own parameter u (cheap to evaluate) and s is found once at the end.
Closest closest_bezier(const Bezier& bezier, const Vec3& query) {
  const auto [u, d] = scan_closest([&](double x) { return bezier.eval(x); }, 1.0, query);
  return {bezier.length_to(u), bezier.eval(u), d};
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
                        [&](const Bezier& bezier) { return closest_bezier(bezier, query); },
                        [&](const Clothoid&) { return closest_numeric(segment, query); },
                    },
                    segment);
}

Closest closest_point(const Primitive& primitive, const Vec3& query) {
  return closest_point(to_segment(primitive), query);
}

namespace {

// A segment prepared for many closest-point queries: lines and planar arcs are answered
// exactly; other curves keep a dense table of positions (in s, or in u for a Bezier) so each
// query scans the table without evaluating the curve and refines around its local minima.
class Target {
 public:
  explicit Target(const Segment& segment) : segment_(segment) {
    const Arc* arc = std::get_if<Arc>(&segment);
    exact_ = std::holds_alternative<Line>(segment) ||
             (arc != nullptr && arc->rise == 0 && arc->sweep <= 2 * std::numbers::pi);
    if (exact_) return;
    bezier_ = std::get_if<Bezier>(&segment);
    t_max_ = bezier_ != nullptr ? 1.0 : length(segment);
    table_.resize(kTable + 1);
    for (int i = 0; i <= kTable; ++i) table_[static_cast<std::size_t>(i)] = at(t_max_ * i / kTable);
  }

  double distance(const Vec3& query) const {
    if (exact_) return closest_point(segment_, query).distance;
    d2_.resize(table_.size());
    for (std::size_t i = 0; i < table_.size(); ++i) d2_[i] = (table_[i] - query).squaredNorm();
    const auto refined = refine_minima(d2_, t_max_ / kTable, t_max_,
                                       [&](double t) { return (at(t) - query).squaredNorm(); }, 1e-12 * t_max_, 60);
    return std::sqrt(refined.second);
  }

 private:
  static constexpr int kTable = 256;
  Vec3 at(double t) const { return bezier_ != nullptr ? bezier_->eval(t) : point(segment_, t); }

  const Segment& segment_;
  bool exact_ = false;
  const Bezier* bezier_ = nullptr;
  double t_max_ = 0;
  std::vector<Vec3> table_;
  mutable std::vector<double> d2_;  // scratch for one query, reused to avoid an allocation each
};

// Relative margin on the reach of a target (rounding of its length and of its midpoint, a
// Bezier's arc-length table included, is below 1e-12 of the length).
constexpr double kReachMargin = 1e-9;

double directed(const std::vector<Segment>& from, const std::vector<Segment>& to, double step) {
  std::vector<Target> targets;
  targets.reserve(to.size());
  for (const Segment& seg : to) targets.emplace_back(seg);
  // every point of a target lies within half its length L of its midpoint m (along the curve),
  // so |x - m| - L/2 bounds its distance from x below: targets are tried nearest bound first and
  // passed over once the bound exceeds the best distance so far, which leaves the minimum as it is
  std::vector<Vec3> mid(to.size());
  std::vector<double> reach(to.size());
  for (std::size_t k = 0; k < to.size(); ++k) {
    const double half = 0.5 * length(to[k]);
    mid[k] = point(to[k], half);
    reach[k] = half * (1 + kReachMargin);
  }
  std::vector<std::pair<double, std::size_t>> order(to.size());
  double worst = 0;
  for (const Segment& seg : from) {
    const double len = length(seg);
    // at least 64 samples, at most 2^20 (a step <= 0 or NaN, or tiny against the length,
    // would otherwise overflow the count)
    constexpr double kMaxSamples = 1 << 20;
    const double wanted = step > 0 ? std::ceil(len / step) : kMaxSamples;
    const int n = static_cast<int>(std::clamp(std::isnan(wanted) ? kMaxSamples : wanted, 64.0, kMaxSamples));
    // a Bezier is sampled uniformly in u: as dense, and far cheaper than inverting s
    const Bezier* bezier = std::get_if<Bezier>(&seg);
    for (int i = 0; i <= n; ++i) {
      const Vec3 p = bezier != nullptr ? bezier->eval(static_cast<double>(i) / n) : point(seg, len * i / n);
      for (std::size_t k = 0; k < to.size(); ++k) order[k] = {(p - mid[k]).norm() - reach[k], k};
      if (order.size() > 1) std::sort(order.begin(), order.end());
      double best = std::numeric_limits<double>::infinity();
      for (const auto& [bound, k] : order) {
        if (bound > best) break;
        best = std::min(best, targets[k].distance(p));
      }
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

double directed_hausdorff(const std::vector<Segment>& from, const std::vector<Segment>& to, double step) {
  if (from.empty() || to.empty()) return 0;
  return directed(from, to, step);
}

}  // namespace blendbench
