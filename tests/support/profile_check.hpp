#pragma once
// Checks a timed profile against its path: every limit of issue 4 on the sampled result
// (v <= v_lim(s) with 004 eq. 25-27, kappa v^2 <= a, |a_t|, |j_t|, also by finite differences of
// the samples) and v = 0 at every stop. Shared by the timing tests and the scenario tests; the
// limits at a sample and the path-level margins come from the planner's profile checker
// (timing/profile_margins.hpp), which the paper reproductions report too.
// The one place the check takes the planner's word: in a hand-over zone of a buffer mode
// (handover_zones, timing.hpp) the feed limit is the zone's junction velocity; timing_test
// checks the zones themselves against the rule.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "blendbench/corner/blend.hpp"
#include "blendbench/timing/profile_margins.hpp"
#include "blendbench/timing/timing.hpp"

namespace blendbench::test {

inline constexpr double kRel = 1e-9;  // relative slack on every limit (issue 4)
inline constexpr double kEps = std::numeric_limits<double>::epsilon();

// Margins of a sampled profile: the largest ratio value/limit seen (<= 1 + kRel required).
struct Margins {
  double v = 0, a = 0, j = 0, normal = 0;
};

// Checks a timing against the path: sampling grid, start and end at rest, monotone s, and on
// every sample v <= v_lim(s), kappa v^2 <= a, |a_t|, |j_t| within the limits; finite
// differences of s (stencil averages of v, a, j) within the largest limits of the pieces the
// stencil touches, up to the rounding noise of s; v = 0 at every stop (the samples on either
// side of a stop are within J dt^2 / 2 of rest: a jerk-limited arrival at rest).
inline Margins expect_valid(const Path& path, const Timing& timing, const std::string& where,
                     TimingOptions::Baseline baseline = TimingOptions::Baseline::kNone) {
  Margins m;
  const auto& x = timing.samples;
  EXPECT_TRUE(timing.outcome.ok()) << where << " " << timing.outcome.message;
  if (x.empty()) {
    ADD_FAILURE() << where << ": no samples";
    return m;
  }
  const double dt = timing.dt;
  EXPECT_EQ(x.size(), static_cast<std::size_t>(std::ceil(timing.cycle_time / dt)) + 1) << where;
  EXPECT_EQ(x.front().s, 0.0) << where;
  EXPECT_EQ(x.front().v, 0.0) << where;
  EXPECT_EQ(x.back().s, path.length()) << where;
  EXPECT_EQ(x.back().v, 0.0) << where;
  EXPECT_EQ(x.back().a, 0.0) << where;
  TimingOptions options;
  options.dt = dt;
  options.baseline = baseline;
  const std::vector<HandoverZone> zones = handover_zones(path, options);
  std::vector<LocalLimits> lim(x.size());
  for (std::size_t k = 0; k < x.size(); ++k) {
    lim[k] = limits_at(path, x[k].s, zones);
    EXPECT_EQ(x[k].t, static_cast<double>(k) * dt) << where;
    if (k > 0) {
      EXPECT_GE(x[k].s, x[k - 1].s) << where << " k=" << k;
    }
    EXPECT_GE(x[k].v, 0.0) << where << " k=" << k;
  }
  // the path-level margins with the limits above (profile_margins, as the reproductions report)
  const ProfileMargins pm = profile_margins(path, timing, lim);
  m.v = pm.velocity;
  m.normal = pm.normal_acceleration;
  m.a = pm.tangential_acceleration;
  m.j = pm.tangential_jerk;
  EXPECT_LE(m.v, 1 + kRel) << where;
  EXPECT_LE(m.normal, 1 + kRel) << where;
  EXPECT_LE(m.a, 1 + kRel) << where;
  EXPECT_LE(m.j, 1 + kRel) << where;

  // finite differences over stencils of 2, 3 and 4 samples; the noise of a sampled s is the
  // rounding of s itself and of the sample instant (t - t0 of its interval, ~eps t) times v
  double v_top = 0;
  for (const PathPiece& p : path.pieces()) v_top = std::max(v_top, p.limits.velocity);
  for (const HandoverZone& z : zones) v_top = std::max(v_top, z.velocity);
  const double noise = 4 * kEps * std::max(path.length() + v_top * timing.cycle_time, 1e-300);
  for (std::size_t k = 0; k + 1 < x.size(); ++k) {
    const double v = (x[k + 1].s - x[k].s) / dt;
    EXPECT_LE(v, widest(lim, k, k + 1).feed * (1 + kRel) + 2 * noise / dt) << where << " k=" << k;
  }
  for (std::size_t k = 1; k + 1 < x.size(); ++k) {
    const double a = (x[k + 1].s - 2 * x[k].s + x[k - 1].s) / (dt * dt);
    const LocalLimits w = widest(lim, k - 1, k + 1);
    EXPECT_LE(a, w.acceleration * (1 + kRel) + 4 * noise / (dt * dt)) << where << " k=" << k;
    EXPECT_GE(a, -w.deceleration * (1 + kRel) - 4 * noise / (dt * dt)) << where << " k=" << k;
  }
  for (std::size_t k = 1; k + 2 < x.size(); ++k) {
    const double j = (x[k + 2].s - 3 * x[k + 1].s + 3 * x[k].s - x[k - 1].s) / (dt * dt * dt);
    EXPECT_LE(std::abs(j), widest(lim, k - 1, k + 2).jerk * (1 + kRel) + 8 * noise / (dt * dt * dt))
        << where << " k=" << k;
  }

  // at rest at every stop: stop_before, every junction in the exact-stop baseline, Buffered
  // kinks only in the junction slow-down baseline
  const auto& pieces = path.pieces();
  for (std::size_t p = 1; p < pieces.size(); ++p) {
    using Baseline = TimingOptions::Baseline;
    const bool buffered_kink = pieces[p].kink_angle > 1e-9 && pieces[p - 1].buffer == BufferMode::kBuffered;
    const bool stop = baseline == Baseline::kExactStop ||
                      (baseline == Baseline::kNone ? pieces[p].stop_before : buffered_kink);
    if (!stop) continue;
    const double s_stop = path.offset(p);
    const double jerk = std::max(pieces[p - 1].limits.jerk, pieces[p].limits.jerk);
    // the last sample at or before the stop position and the first one past it, each within
    // one period of the stop instant, plus the time `lag` for which the motion from rest
    // (j t^3 / 6) stays below the rounding of s
    const auto past = std::upper_bound(x.begin(), x.end(), s_stop, [](double s, const TimedSample& a) { return s < a.s; });
    const double lag = std::cbrt(6 * 4 * kEps * std::max(s_stop, 1e-300) / jerk);
    const double bound = 0.5 * jerk * (dt + lag) * (dt + lag) * (1 + kRel);
    if (past != x.begin()) {
      EXPECT_LE(std::prev(past)->v, bound) << where << " stop before piece " << p;
    }
    if (past != x.end()) {
      EXPECT_LE(past->v, bound) << where << " stop before piece " << p;
    }
  }
  return m;
}

}  // namespace blendbench::test
