#pragma once
// Checks a timed profile against its path: every limit of the planner on the sampled result
// (v <= v_lim(s) with seed 004 eq. 25-27, kappa v^2 <= a, |a_t|, |j_t|, also by finite differences of
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
#include <optional>
#include <string>
#include <vector>

#include "blendbench/corner/blend.hpp"
#include "blendbench/timing/cartesian.hpp"
#include "blendbench/timing/profile_margins.hpp"
#include "blendbench/timing/timing.hpp"

namespace blendbench::test {

inline constexpr double kRel = 1e-9;  // relative slack on every limit (the planner's contract)
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
// `planned`: the options the timing was planned with (its hand-over zones are the planner's
// under them; dt is taken from the timing).
inline Margins expect_valid(const Path& path, const Timing& timing, const std::string& where,
                            const TimingOptions& planned) {
  const TimingOptions::Baseline baseline = planned.baseline;
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
  TimingOptions options = planned;
  options.dt = dt;
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
    EXPECT_LE(v, widest(path, x, lim, k, k + 1, zones).feed * (1 + kRel) + 2 * noise / dt) << where << " k=" << k;
  }
  for (std::size_t k = 1; k + 1 < x.size(); ++k) {
    const double a = (x[k + 1].s - 2 * x[k].s + x[k - 1].s) / (dt * dt);
    const LocalLimits w = widest(path, x, lim, k - 1, k + 1, zones);
    EXPECT_LE(a, w.acceleration * (1 + kRel) + 4 * noise / (dt * dt)) << where << " k=" << k;
    EXPECT_GE(a, -w.deceleration * (1 + kRel) - 4 * noise / (dt * dt)) << where << " k=" << k;
  }
  for (std::size_t k = 1; k + 2 < x.size(); ++k) {
    const double j = (x[k + 2].s - 3 * x[k + 1].s + 3 * x[k].s - x[k - 1].s) / (dt * dt * dt);
    EXPECT_LE(std::abs(j), widest(path, x, lim, k - 1, k + 2, zones).jerk * (1 + kRel) + 8 * noise / (dt * dt * dt))
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

// The same for a timing planned with the default options and `baseline`.
inline Margins expect_valid(const Path& path, const Timing& timing, const std::string& where,
                            TimingOptions::Baseline baseline = TimingOptions::Baseline::kNone) {
  TimingOptions options;
  options.baseline = baseline;
  return expect_valid(path, timing, where, options);
}

// Margins of a profile as vectors on the TCP (cartesian.hpp): the largest |a| / A and |j| / J
// over the samples, analytic from v, a_t, j_t and the path's tangent, curvature vector and its
// derivative at each sample (a_t > 0: A the acceleration, a_t < 0: the deceleration, a_t = 0:
// the smaller), and the same for the axis components against the axis limits; fd_a, fd_j: the
// same from finite differences of the sampled x, y, z (2nd and 3rd differences, the averages of
// the acceleration and jerk over their stencils), against the largest limits the stencil
// touches, up to the rounding of the positions.
struct CartesianMargins {
  double a = 0, j = 0, axis_a = 0, axis_j = 0, fd_a = 0, fd_j = 0;
};

// Checks the Cartesian limits on every sample (all within kRel): the analytic vectors of every
// piece touching the sample's s; the finite differences on stencils that cross no kink (a
// velocity step) for the acceleration, and no kink or curvature step (an acceleration step,
// bounded by the junction rule or allowed and reported) for the jerk.
inline CartesianMargins expect_cartesian_valid(const Path& path, const Timing& timing,
                                               const std::optional<AxisLimits>& axes, const std::string& where) {
  CartesianMargins m;
  const auto& x = timing.samples;
  const auto& pieces = path.pieces();
  const double inf = std::numeric_limits<double>::infinity();
  const Vec3 no_axis = Vec3::Constant(inf);
  const Vec3 axis_a = axes ? axes->acceleration : no_axis;
  const Vec3 axis_j = axes ? axes->jerk : no_axis;
  struct Widest {
    double a = 0, j = 0;
  };
  std::vector<Widest> widest(x.size());
  std::vector<Vec3> p(x.size());
  for (std::size_t k = 0; k < x.size(); ++k) {
    const TimedSample& q = x[k];
    p[k] = path.point(q.s);
    // at a junction the sample's a_t and j_t are one side's (the span it falls in): the sample
    // must be valid on at least one of the pieces it touches
    CartesianMargins here{inf, inf, inf, inf, 0, 0};
    path.for_pieces_at(q.s, [&](std::size_t i, double local) {
      const PathPiece& piece = pieces[i];
      const SegmentFrame f = frame(piece.segment, local);
      const Vec3 a = tcp_acceleration(q.v, q.a, f.tangent, f.curvature);
      const Vec3 j = tcp_jerk(q.v, q.a, q.j, f.tangent, f.curvature, f.curvature_derivative);
      const Limits& lim = piece.limits;
      const double a_lim = q.a > 0 ? lim.acceleration : q.a < 0 ? lim.deceleration : std::min(lim.acceleration, lim.deceleration);
      here.a = std::min(here.a, a.norm() / a_lim);
      here.j = std::min(here.j, j.norm() / lim.jerk);
      here.axis_a = std::min(here.axis_a, a.cwiseAbs().cwiseQuotient(axis_a).maxCoeff());
      here.axis_j = std::min(here.axis_j, j.cwiseAbs().cwiseQuotient(axis_j).maxCoeff());
      widest[k].a = std::max({widest[k].a, lim.acceleration, lim.deceleration});
      widest[k].j = std::max(widest[k].j, lim.jerk);
    });
    m.a = std::max(m.a, here.a);
    m.j = std::max(m.j, here.j);
    m.axis_a = std::max(m.axis_a, here.axis_a);
    m.axis_j = std::max(m.axis_j, here.axis_j);
  }
  EXPECT_LE(m.a, 1 + kRel) << where << " |a|";
  EXPECT_LE(m.j, 1 + kRel) << where << " |j|";
  EXPECT_LE(m.axis_a, 1 + kRel) << where << " axis a";
  EXPECT_LE(m.axis_j, 1 + kRel) << where << " axis j";
  if (x.size() < 4) return m;

  // junctions whose kink or curvature step a stencil must not cross
  std::vector<std::pair<double, bool>> steps;  // s, and whether it is a kink
  for (std::size_t i = 1; i < pieces.size(); ++i) {
    const Segment& a = pieces[i - 1].segment;
    const Segment& b = pieces[i].segment;
    const bool kink = angle_between(tangent(a, length(a)), tangent(b, 0.0)) > 1e-9;
    const bool jump = (curvature_vector(a, length(a)) - curvature_vector(b, 0.0)).norm() > 1e-9;
    if (kink || jump) steps.emplace_back(path.offset(i), kink);
  }
  const auto crosses = [&](std::size_t k0, std::size_t k1, bool kinks_only) {
    const auto it = std::lower_bound(steps.begin(), steps.end(), std::pair{x[k0].s, false});
    for (auto s = it; s != steps.end() && s->first <= x[k1].s; ++s) {
      if (!kinks_only || s->second) return true;
    }
    return false;
  };
  double size = 0;
  for (const Vec3& q : p) size = std::max(size, q.cwiseAbs().maxCoeff());
  const double noise = 8 * kEps * (size + path.length());
  const double dt = timing.dt;
  for (std::size_t k = 1; k + 1 < x.size(); ++k) {
    if (crosses(k - 1, k + 1, true)) continue;
    const Vec3 a = (p[k + 1] - 2 * p[k] + p[k - 1]) / (dt * dt);
    const LocalLimits between = limits_between(path, x[k - 1].s, x[k + 1].s);
    const double lim = std::max({widest[k - 1].a, widest[k].a, widest[k + 1].a, between.acceleration, between.deceleration});
    const double slack = 4 * noise / (dt * dt);
    m.fd_a = std::max(m.fd_a, (a.norm() - slack) / lim);
    EXPECT_LE(a.norm(), lim * (1 + kRel) + slack) << where << " finite-difference |a|, k=" << k;
    EXPECT_LE((a.cwiseAbs() - Vec3::Constant(slack)).cwiseQuotient(axis_a).maxCoeff(), 1 + kRel) << where << " axis a, k=" << k;
  }
  for (std::size_t k = 1; k + 2 < x.size(); ++k) {
    if (crosses(k - 1, k + 2, false)) continue;
    const Vec3 j = (p[k + 2] - 3 * p[k + 1] + 3 * p[k] - p[k - 1]) / (dt * dt * dt);
    const double lim = std::max({widest[k - 1].j, widest[k].j, widest[k + 1].j, widest[k + 2].j,
                                 limits_between(path, x[k - 1].s, x[k + 2].s).jerk});
    const double slack = 8 * noise / (dt * dt * dt);
    m.fd_j = std::max(m.fd_j, (j.norm() - slack) / lim);
    EXPECT_LE(j.norm(), lim * (1 + kRel) + slack) << where << " finite-difference |j|, k=" << k;
    EXPECT_LE((j.cwiseAbs() - Vec3::Constant(slack)).cwiseQuotient(axis_j).maxCoeff(), 1 + kRel) << where << " axis j, k=" << k;
  }
  return m;
}

}  // namespace blendbench::test
