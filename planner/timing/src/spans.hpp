#pragma once
// Internal to the velocity planner (timing.cpp): steps 2-4 of its method, the spans of
// S-curves between knots of zero acceleration and their knot velocities. Not installed.

#include <vector>

#include "intervals.hpp"

namespace blendbench::timing_detail {

// A run of intervals [first, last) between two knots of zero acceleration, planned as one
// S-curve (steps 2-4).
struct Span {
  std::size_t first = 0;
  std::size_t last = 0;
  double s0 = 0;  // m, global arc lengths of its ends
  double s1 = 0;
  ScurveLimits limits;  // acceleration, deceleration, jerk of its intervals; velocity: peak bound
  Scurve curve;
  double t0 = 0;  // s, start time
  [[nodiscard]] double length() const { return s1 - s0; }
  // The velocity where the curve has covered x (m from the span's start).
  [[nodiscard]] double velocity_at(double x) const { return curve.at(curve.time_at_distance(x)).v; }
};

// Walks the intervals of span sp under its profile: f(i, v_max, holds_peak) for each, with the
// largest velocity on interval i (the profile is unimodal in s: the peak where its peak range
// meets the interval, else the larger end) and whether it holds a peak strictly above both
// span ends. Stops when f returns false; returns whether it walked them all.
template <class F>
bool walk_intervals(const Span& sp, const std::vector<Interval>& iv, F f) {
  const Scurve& c = sp.curve;
  const double t_up = c.durations[0] + c.durations[1] + c.durations[2];
  const double x_up = c.at(t_up).s;
  const double x_down = c.at(t_up + c.durations[3]).s;
  const bool bump = c.v_peak > std::max(c.v0, c.v1);
  double x0 = 0;
  double v0 = c.v0;
  for (std::size_t i = sp.first; i < sp.last; ++i) {
    const bool end = i + 1 == sp.last;
    const double x1 = end ? sp.length() : iv[i].s1 - sp.s0;
    const double v1 = end ? c.v1 : sp.velocity_at(x1);
    const bool peak = x0 <= x_down && x1 >= x_up;
    const double v_max = std::max({v0, v1, peak ? c.v_peak : 0.0});
    if (!f(i, v_max, peak && bump)) return false;
    x0 = x1;
    v0 = v1;
  }
  return true;
}

// Steps 2-3: the spans and their knot velocities w (one per span end) and the knot bounds
// `cap` they were found under. Starts from the anchors; a span that cannot go between its knot
// velocities under its caps gets its higher end lowered (a knot bound) and the passes run
// again; after kLowerRounds its knots fall back to zero acceleration, and after
// kFallbackRounds more every knot does (every span is then one interval, which always fits).
void plan_spans(const std::vector<Interval>& iv, const std::vector<double>& knot_cap, bool carry_acceleration,
                std::vector<Span>& spans, std::vector<double>& w, std::vector<double>& cap);

// Step 4: the curve of span sp between feasible knot velocities w0 and w1 with the highest
// peak under the caps. Returns plan_scurve's outcome.
Outcome shape(Span& sp, double w0, double w1, const std::vector<Interval>& iv);

// Step 4: the fine alternative of span sp between the same knot velocities w0 and w1: one span
// per interval, the inner knot velocities (bounded by `cap`) from local passes, each curve as
// in step 4. Empty when such a chain cannot start at w0 and end at w1.
std::vector<Span> fine_alternative(const Span& sp, double w0, double w1, const std::vector<Interval>& iv,
                                   const std::vector<double>& cap);

}  // namespace blendbench::timing_detail
