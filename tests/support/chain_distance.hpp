#pragma once
// Directed distances between two chains of segments for tests, computed independently of the
// planner's own deviation code: dense sampling refined by golden-section search, using only the
// public segment queries (point, length); distances to a chain of lines and arcs are exact
// (closest_point).

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "blendbench/geometry/closest.hpp"
#include "blendbench/geometry/segment.hpp"

namespace blendbench::test {

// A chain of segments parameterised by its total arc length.
class Chain {
 public:
  explicit Chain(std::vector<Segment> segments, int samples = 128) : segments_(std::move(segments)) {
    exact_ = std::all_of(segments_.begin(), segments_.end(), [](const Segment& seg) {
      return std::holds_alternative<Line>(seg) || (std::holds_alternative<Arc>(seg) && std::get<Arc>(seg).rise == 0);
    });
    offsets_.push_back(0);
    for (const Segment& seg : segments_) offsets_.push_back(offsets_.back() + length(seg));
    const double total = offsets_.back();
    for (int i = 0; i <= samples; ++i) {
      const double t = total * i / samples;
      ts_.push_back(t);
      points_.push_back(at(t));
    }
    // the junctions too, where a chain may have a kink
    for (std::size_t k = 1; k + 1 < offsets_.size(); ++k) {
      ts_.push_back(offsets_[k]);
      points_.push_back(at(offsets_[k]));
    }
    std::vector<std::size_t> order(ts_.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return ts_[a] < ts_[b]; });
    std::vector<double> ts;
    std::vector<Vec3> pts;
    for (const std::size_t i : order) {
      if (!ts.empty() && ts_[i] <= ts.back()) continue;  // a junction on a sample: keep one
      ts.push_back(ts_[i]);
      pts.push_back(points_[i]);
    }
    ts_ = ts;
    points_ = pts;
  }

  [[nodiscard]] double total() const { return offsets_.back(); }

  [[nodiscard]] Vec3 at(double t) const {
    t = std::clamp(t, 0.0, total());
    std::size_t k = 0;
    while (k + 1 < segments_.size() && t > offsets_[k + 1]) ++k;
    return point(segments_[k], t - offsets_[k]);
  }

  // Distance from x to the chain: nearest sample, then golden section between its neighbours.
  [[nodiscard]] double distance(const Vec3& x) const {
    if (exact_) {
      double d = std::numeric_limits<double>::infinity();
      for (const Segment& seg : segments_) d = std::min(d, closest_point(seg, x).distance);
      return d;
    }
    std::size_t best = 0;
    double best_d = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < points_.size(); ++i) {
      const double d = (points_[i] - x).squaredNorm();
      if (d < best_d) {
        best_d = d;
        best = i;
      }
    }
    const double lo = ts_[best > 0 ? best - 1 : 0];
    const double hi = ts_[std::min(best + 1, ts_.size() - 1)];
    const double refined = golden(lo, hi, [&](double t) { return (at(t) - x).squaredNorm(); }, false);
    return std::sqrt(std::min(best_d, refined));
  }

  // max over this chain of the distance to `other`: samples, then golden section around the best.
  [[nodiscard]] double directed_to(const Chain& other) const {
    std::size_t best = 0;
    double best_d = -1;
    for (std::size_t i = 0; i < points_.size(); ++i) {
      const double d = other.distance(points_[i]);
      if (d > best_d) {
        best_d = d;
        best = i;
      }
    }
    const double lo = ts_[best > 0 ? best - 1 : 0];
    const double hi = ts_[std::min(best + 1, ts_.size() - 1)];
    return std::max(best_d, golden(lo, hi, [&](double t) { return other.distance(at(t)); }, true));
  }

 private:
  // golden-section search for the minimum (or maximum) of f on [lo, hi]; returns the value
  template <class F>
  static double golden(double lo, double hi, const F& f, bool maximise) {
    constexpr double kRatio = 0.6180339887498949;
    const auto g = [&](double t) { return maximise ? -f(t) : f(t); };
    double x1 = hi - kRatio * (hi - lo);
    double x2 = lo + kRatio * (hi - lo);
    double f1 = g(x1);
    double f2 = g(x2);
    for (int it = 0; it < 40; ++it) {
      if (f1 < f2) {
        hi = x2;
        x2 = x1;
        f2 = f1;
        x1 = hi - kRatio * (hi - lo);
        f1 = g(x1);
      } else {
        lo = x1;
        x1 = x2;
        f1 = f2;
        x2 = lo + kRatio * (hi - lo);
        f2 = g(x2);
      }
    }
    const double best = std::min(f1, f2);
    return maximise ? -best : best;
  }

  std::vector<Segment> segments_;
  bool exact_ = false;
  std::vector<double> offsets_;
  std::vector<double> ts_;
  std::vector<Vec3> points_;
};

}  // namespace blendbench::test
