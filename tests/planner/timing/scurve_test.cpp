#include "blendbench/timing/scurve.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "support/property.hpp"
#include "blendbench/core/format.hpp"

namespace blendbench {
namespace {

constexpr double kRel = 1e-9;  // relative slack on every limit (the planner's contract)
constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kDistanceTol = 8 * kEps;  // relative, on s(time_at_distance(x)) - x

// Checks every limit on the analytic profile at `n` instants plus the phase boundaries, and on
// finite differences of positions sampled every h = duration/n (averages of v, a, j over the
// stencil, so they can never exceed the limits except by the rounding noise of the positions,
// 2^k * 4 eps * distance / h^k for the k-th difference).
void expect_within_limits(const Scurve& c, const ScurveLimits& lim, const std::string& where, int n = 2000) {
  const double total = c.duration();
  ASSERT_TRUE(std::isfinite(total)) << where;
  std::vector<double> times;
  for (int k = 0; k <= n; ++k) times.push_back(total * k / n);
  double t_phase = 0;
  for (double d : c.durations) {
    t_phase += d;
    times.push_back(std::min(t_phase, total));
  }
  for (double t : times) {
    const ScurveState x = c.at(t);
    ASSERT_GE(x.v, 0.0) << where << " t=" << t;
    ASSERT_LE(x.v, lim.velocity * (1 + kRel)) << where << " t=" << t;
    ASSERT_LE(x.a, lim.acceleration * (1 + kRel)) << where << " t=" << t;
    ASSERT_GE(x.a, -lim.deceleration * (1 + kRel)) << where << " t=" << t;
    ASSERT_LE(std::abs(x.j), lim.jerk * (1 + kRel)) << where << " t=" << t;
    ASSERT_GE(x.s, 0.0) << where;
    ASSERT_LE(x.s, c.distance) << where;
  }
  // finite differences of the sampled positions; s must never decrease
  if (total <= 0) return;
  const double h = total / n;
  std::vector<double> s(static_cast<std::size_t>(n) + 1);
  for (int k = 0; k <= n; ++k) s[static_cast<std::size_t>(k)] = c.at(h * k).s;
  // rounding of s and of the sample instant h k (~eps t, times v)
  const double noise = 4 * kEps * std::max(c.distance + lim.velocity * total, 1e-300);
  for (std::size_t k = 0; k + 1 < s.size(); ++k) {
    ASSERT_GE(s[k + 1], s[k]) << where << " k=" << k;
    ASSERT_LE((s[k + 1] - s[k]) / h, lim.velocity * (1 + kRel) + 2 * noise / h) << where;
  }
  for (std::size_t k = 1; k + 1 < s.size(); ++k) {
    const double a = (s[k + 1] - 2 * s[k] + s[k - 1]) / (h * h);
    ASSERT_LE(a, lim.acceleration * (1 + kRel) + 4 * noise / (h * h)) << where << " k=" << k;
    ASSERT_GE(a, -lim.deceleration * (1 + kRel) - 4 * noise / (h * h)) << where << " k=" << k;
  }
  for (std::size_t k = 1; k + 2 < s.size(); ++k) {
    const double j = (s[k + 2] - 3 * s[k + 1] + 3 * s[k] - s[k - 1]) / (h * h * h);
    ASSERT_LE(std::abs(j), lim.jerk * (1 + kRel) + 8 * noise / (h * h * h)) << where << " k=" << k;
  }
}

TEST(VelocityChange, TrapezoidalAndTriangularByHand) {
  // dv = 1 >= a^2/j = 0.4: duration 1/2 + 2/10 = 0.7 s, distance mean(0, 1) * 0.7
  const VelocityChange trap = velocity_change(0.0, 1.0, 2.0, 10.0);
  EXPECT_DOUBLE_EQ(trap.duration, 0.7);
  EXPECT_DOUBLE_EQ(trap.distance, 0.35);
  EXPECT_DOUBLE_EQ(trap.a_peak, 2.0);
  // dv = 0.1 < 0.4: duration 2 sqrt(0.1/10) = 0.2 s, peak sqrt(0.1 * 10) = 1, distance 0.25*0.2
  const VelocityChange tri = velocity_change(0.5, 0.4, 2.0, 10.0);
  EXPECT_DOUBLE_EQ(tri.duration, 0.2);
  EXPECT_DOUBLE_EQ(tri.distance, 0.09);
  EXPECT_DOUBLE_EQ(tri.a_peak, 1.0);
  EXPECT_EQ(velocity_change(0.3, 0.3, 2.0, 10.0).distance, 0.0);
}

TEST(Scurve, LongRestToRestMoveCruisesAtTheLimit) {
  const ScurveLimits lim{1.0, 2.0, 2.0, 10.0};
  const ScurveResult r = plan_scurve(10.0, 0.0, 0.0, lim);
  ASSERT_TRUE(r.outcome.ok()) << r.outcome.message;
  EXPECT_EQ(r.curve.v_peak, 1.0);
  // ramps 0.7 s each covering 0.35 m; 9.3 m cruised at 1 m/s
  EXPECT_NEAR(r.curve.duration(), 10.7, 1e-12);
  EXPECT_NEAR(r.curve.durations[3], 9.3, 1e-12);
  EXPECT_EQ(r.curve.at(r.curve.duration()).s, 10.0);
  EXPECT_EQ(r.curve.at(r.curve.duration()).v, 0.0);
  EXPECT_NEAR(r.curve.at(0.35).a, 2.0, 1e-12);
  EXPECT_NEAR(r.curve.at(5.0).v, 1.0, 1e-12);
  expect_within_limits(r.curve, lim, "long move");
}

TEST(Scurve, ShortRestToRestMoveIsJerkLimitedWithTheClosedFormPeak) {
  // triangular acceleration on both sides: L = 2 vp sqrt(vp/j) -> vp = (j L^2/4)^(1/3)
  const ScurveLimits lim{5.0, 2.0, 2.0, 10.0};
  const double length = 0.1;
  const ScurveResult r = plan_scurve(length, 0.0, 0.0, lim);
  ASSERT_TRUE(r.outcome.ok());
  const double vp = std::cbrt(10.0 * length * length / 4.0);
  EXPECT_NEAR(r.curve.v_peak, vp, 1e-14);
  EXPECT_NEAR(r.curve.duration(), 4.0 * std::sqrt(vp / 10.0), 1e-13);
  EXPECT_NEAR(r.curve.durations[3], 0.0, 1e-13);
  EXPECT_NEAR(r.curve.peak_acceleration(), std::sqrt(vp * 10.0), 1e-12);
  expect_within_limits(r.curve, lim, "short move");
}

TEST(Scurve, UnequalAccelerationAndDecelerationMatchTheirOwnRamps) {
  const ScurveLimits lim{1.0, 4.0, 1.0, 100.0};
  const ScurveResult r = plan_scurve(2.0, 0.0, 0.0, lim);
  ASSERT_TRUE(r.outcome.ok());
  EXPECT_EQ(r.curve.v_peak, 1.0);
  EXPECT_NEAR(r.curve.peak_acceleration(), 4.0, 1e-12);
  EXPECT_NEAR(r.curve.peak_deceleration(), 1.0, 1e-12);
  // up: 1/4 + 4/100 s; down: 1/1 + 1/100 s; cruise 2 - mean distances
  const double up = 0.25 + 0.04;
  const double down = 1.0 + 0.01;
  EXPECT_NEAR(r.curve.duration(), up + down + (2.0 - 0.5 * up - 0.5 * down), 1e-12);
  expect_within_limits(r.curve, lim, "unequal");
}

TEST(Scurve, VelocityChangeBetweenNonZeroBoundaries) {
  // the change 1.2 -> 0.3 alone needs 0.75 * (0.9/1.5 + 1.5/20) = 0.50625 m
  const ScurveLimits lim{2.0, 3.0, 1.5, 20.0};
  const ScurveResult r = plan_scurve(0.6, 1.2, 0.3, lim);
  ASSERT_TRUE(r.outcome.ok());
  EXPECT_GE(r.curve.v_peak, 1.2);
  EXPECT_EQ(r.curve.at(0).v, 1.2);
  EXPECT_EQ(r.curve.at(r.curve.duration()).v, 0.3);
  EXPECT_EQ(r.curve.at(r.curve.duration()).s, 0.6);
  expect_within_limits(r.curve, lim, "change");
}

TEST(Scurve, TooShortForTheVelocityChangeIsInfeasible) {
  const ScurveLimits lim{2.0, 1.0, 1.0, 10.0};
  const double needed = velocity_change(1.0, 0.0, 1.0, 10.0).distance;
  const ScurveResult r = plan_scurve(0.5 * needed, 1.0, 0.0, lim);
  EXPECT_EQ(r.outcome.status, Status::kInfeasible);
  EXPECT_NE(r.outcome.message.find("too short"), std::string::npos) << r.outcome.message;
  // the change and both distances, in the units users read
  EXPECT_NE(r.outcome.message.find("1000 mm/s -> 0 mm/s"), std::string::npos) << r.outcome.message;
  EXPECT_NE(r.outcome.message.find("(needs " + format_mm(needed) + ")"), std::string::npos) << r.outcome.message;
  EXPECT_DOUBLE_EQ(r.curve.distance, needed);
}

TEST(Scurve, ZeroDistanceAtRestTakesNoTime) {
  const ScurveResult r = plan_scurve(0.0, 0.0, 0.0, {1.0, 1.0, 1.0, 1.0});
  ASSERT_TRUE(r.outcome.ok());
  EXPECT_EQ(r.curve.duration(), 0.0);
  EXPECT_EQ(r.curve.at(0.0).s, 0.0);
}

TEST(ReachableVelocity, ClosedFormsInBothRegimes) {
  // triangular from rest: L = 2 v sqrt(v/j)... from rest one change: L = v sqrt(v/j)
  const double j = 10.0;
  const double v = reachable_velocity(0.0, 0.02, 100.0, j, 10.0);
  EXPECT_NEAR(v * std::sqrt(v / j), 0.02, 1e-15);
  // trapezoidal: from the hand example, 0.35 m reaches exactly 1 m/s with a = 2, j = 10
  EXPECT_NEAR(reachable_velocity(0.0, 0.35, 2.0, 10.0, 5.0), 1.0, 1e-14);
  EXPECT_EQ(reachable_velocity(0.3, 0.0, 2.0, 10.0, 5.0), 0.3);
  EXPECT_EQ(reachable_velocity(0.3, 100.0, 2.0, 10.0, 0.5), 0.5);
}

TEST(ReachableVelocity, PropertyTightAndNeverOverTheDistance) {
  const int cases = test::property_cases(5000);
  for (int i = 0; i < cases; ++i) {
    const auto seed = static_cast<std::uint64_t>(i);
    auto rng = test::make_rng(seed);
    const double v0 = test::uniform(rng, 0, 1) < 0.3 ? 0.0 : test::log_uniform(rng, 1e-6, 10.0);
    const double dist = test::log_uniform(rng, 1e-6, 10.0);
    const double a = test::log_uniform(rng, 1e-3, 1e3);
    const double jerk = test::log_uniform(rng, 1e-2, 1e5);
    const double v = reachable_velocity(v0, dist, a, jerk, std::numeric_limits<double>::infinity());
    ASSERT_GE(v, v0) << test::seed_text(seed);
    ASSERT_LE(velocity_change(v0, v, a, jerk).distance, dist) << test::seed_text(seed);
    // tight: a slightly higher velocity would not fit (where that change is representable)
    if (v - v0 > 1e-6 * v0) {
      ASSERT_GT(velocity_change(v0, v0 + (v - v0) * (1 + 1e-9), a, jerk).distance, dist) << test::seed_text(seed);
    }
  }
}

TEST(Scurve, PropertyLimitsHeldEndReachedPeakOptimal) {
  const int cases = test::property_cases(3000);
  for (int i = 0; i < cases; ++i) {
    const auto seed = static_cast<std::uint64_t>(1000000 + i);
    auto rng = test::make_rng(seed);
    const std::string where = test::seed_text(seed);
    const ScurveLimits lim{test::log_uniform(rng, 1e-3, 10.0), test::log_uniform(rng, 1e-3, 1e3), test::log_uniform(rng, 1e-3, 1e3),
                           test::log_uniform(rng, 1e-2, 1e5)};
    double v0 = 0;
    double v1 = 0;
    if (test::uniform(rng, 0, 1) < 0.5) {
      v0 = test::uniform(rng, 0, lim.velocity);
      v1 = test::uniform(rng, 0, lim.velocity);
    }
    // a distance at least the change v0 -> v1 needs
    const double v_low = std::max(v0, v1);
    const double d_min = velocity_change(v0, v_low, lim.acceleration, lim.jerk).distance +
                         velocity_change(v_low, v1, lim.deceleration, lim.jerk).distance;
    const double dist = std::max(test::log_uniform(rng, 1e-6, 10.0), d_min);
    const ScurveResult r = plan_scurve(dist, v0, v1, lim);
    ASSERT_TRUE(r.outcome.ok()) << where << " " << r.outcome.message;
    const Scurve& c = r.curve;
    ASSERT_EQ(c.at(c.duration()).s, dist) << where;
    ASSERT_EQ(c.at(c.duration()).v, v1) << where;
    ASSERT_EQ(c.at(0).v, v0) << where;
    ASSERT_EQ(c.at(0).s, 0.0) << where;
    // the peak is the limit or a higher one would not fit
    if (c.v_peak < lim.velocity) {
      const double up = c.v_peak * (1 + 1e-9);
      const double ramps = velocity_change(v0, up, lim.acceleration, lim.jerk).distance +
                           velocity_change(up, v1, lim.deceleration, lim.jerk).distance;
      ASSERT_GT(ramps, dist) << where;
    }
    expect_within_limits(c, lim, where, 400);
    // time_at_distance inverts s(t) to within a few ulps of the distance
    for (int k = 0; k <= 8; ++k) {
      const double x = dist * k / 8;
      const double t = c.time_at_distance(x);
      ASSERT_GE(t, 0.0) << where;
      ASSERT_LE(t, c.duration()) << where;
      ASSERT_NEAR(c.at(t).s, x, kDistanceTol * dist) << where << " x=" << x;
    }
  }
}

TEST(Scurve, TimeAtDistanceByHand) {
  // rest to rest over 1 m with v = 0.5, a = 2, j = 20 (timing_test's single line): ramps of
  // 0.35 s over 0.0875 m each, cruise of 1.65 s; the middle of the cruise is 0.5 m at 1.175 s,
  // and s(t) = j t^3 / 6 in the first jerk phase (0.1 s): 1/600 m at 0.05 s
  const Scurve c = plan_scurve(1.0, 0.0, 0.0, {0.5, 2.0, 2.0, 20.0}).curve;
  EXPECT_NEAR(c.time_at_distance(0.5), 1.175, 1e-12);
  EXPECT_NEAR(c.time_at_distance(20.0 * 0.05 * 0.05 * 0.05 / 6), 0.05, 1e-9);
  EXPECT_EQ(c.time_at_distance(0.0), 0.0);
  EXPECT_EQ(c.time_at_distance(-1.0), 0.0);
  EXPECT_EQ(c.time_at_distance(1.0), c.duration());
  EXPECT_EQ(c.time_at_distance(2.0), c.duration());
  // a profile of zero length
  EXPECT_EQ(plan_scurve(0.0, 0.0, 0.0, {1.0, 1.0, 1.0, 1.0}).curve.time_at_distance(0.5), 0.0);
}

}  // namespace
}  // namespace blendbench
