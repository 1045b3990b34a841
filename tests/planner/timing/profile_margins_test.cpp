#include "blendbench/timing/profile_margins.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace blendbench {
namespace {

// Two lines meeting at (0.1, 0, 0) with different limits: a sample on the junction sees both.
Path two_lines(const Limits& first, const Limits& second) {
  Path path;
  path.append(PathPiece{Line{{0, 0, 0}, {0.1, 0, 0}}, 0, -1, first});
  path.append(PathPiece{Line{{0.1, 0, 0}, {0.1, 0.1, 0}}, 1, -1, second});
  return path;
}

// A profile at constant speed v along the whole path, sampled every dt (not from rest: the
// checker takes the samples as they come).
Timing constant_speed(const Path& path, double v, double dt) {
  Timing timing;
  timing.dt = dt;
  const auto n = static_cast<std::size_t>(std::floor(path.length() / (v * dt)));
  for (std::size_t k = 0; k <= n; ++k) {
    const double t = static_cast<double>(k) * dt;
    timing.samples.push_back(TimedSample{t, v * t, v, 0.0, 0.0});
  }
  return timing;
}

TEST(ProfileMargins, JunctionTakesTheStrictestSpeedAndTheLargestRates) {
  const Limits first{0.1, 1.0, 1.5, 10.0};
  const Limits second{0.2, 2.0, 0.5, 20.0};
  const Path path = two_lines(first, second);
  const LocalLimits at = limits_at(path, 0.1);
  EXPECT_EQ(at.v_lim, 0.1);
  EXPECT_EQ(at.feed, 0.2);
  EXPECT_EQ(at.acceleration, 2.0);
  EXPECT_EQ(at.deceleration, 1.5);
  EXPECT_EQ(at.jerk, 20.0);
  EXPECT_EQ(at.kappa, 0.0);
  // inside a piece only its own limits count
  const LocalLimits inside = limits_at(path, 0.15);
  EXPECT_EQ(inside.v_lim, 0.2);
  EXPECT_EQ(inside.acceleration, 2.0);
  EXPECT_EQ(inside.deceleration, 0.5);
  EXPECT_EQ(limits_at(path, 0.05).jerk, 10.0);
  // a stencil's limits are the largest of its samples
  const LocalLimits w = widest({limits_at(path, 0.05), inside}, 0, 1);
  EXPECT_EQ(w.feed, 0.2);
  EXPECT_EQ(w.deceleration, 1.5);
  EXPECT_EQ(w.jerk, 20.0);
}

TEST(ProfileMargins, HandoverZoneRaisesTheFeedOnlyInsideIt) {
  const Path path = two_lines({0.1, 1.0, 1.0, 10.0}, {0.2, 1.0, 1.0, 10.0});
  // two overlapping zones on the first piece: the higher velocity applies where both do
  const std::vector<HandoverZone> zones = {{0, 0.08, 0.1, 0.15}, {0, 0.09, 0.1, 0.18}};
  EXPECT_EQ(feed_at(path, zones, 0, 0.05), 0.1);
  EXPECT_EQ(feed_at(path, zones, 0, 0.085), 0.15);
  EXPECT_EQ(feed_at(path, zones, 0, 0.095), 0.18);
  EXPECT_EQ(feed_at(path, zones, 1, 0.0), 0.2);
  EXPECT_EQ(limits_at(path, 0.085, zones).v_lim, 0.15);
}

TEST(ProfileMargins, ConstantSpeedOnAnArcMeetsTheClosedForms) {
  // a quarter circle of radius r at v: kappa v^2 and, by seed 004 eq. 24 (c = 0), kappa^2 v^3; the
  // axes see the centripetal acceleration and its rotation in full where they line up with
  // them, at the ends of the quarter (finite differences are exact to (v dt / r)^2 ~ 1e-6)
  const double r = 0.1;
  const double v = 0.1;
  const double dt = 1e-3;
  const Limits limits{0.5, 0.5, 0.5, 0.2};  // kappa^2 v^3 = 0.1 m/s^3: half the jerk limit
  Path path;
  path.append(PathPiece{Arc{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, r, 0.5 * std::acos(-1.0), 0.0}, 0, -1, limits});
  const Timing timing = constant_speed(path, v, dt);
  const ProfileMargins m = profile_margins(path, timing);
  const double kappa = 1 / r;
  const double v_lim = std::min({limits.velocity, std::sqrt(limits.acceleration / kappa),
                                 std::cbrt(limits.jerk / (kappa * kappa))});
  EXPECT_NEAR(m.velocity, v / v_lim, 1e-12);
  EXPECT_NEAR(m.normal_acceleration, kappa * v * v / limits.acceleration, 1e-12);
  EXPECT_NEAR(m.eq24_jerk, kappa * kappa * v * v * v / limits.jerk, 1e-12);
  EXPECT_EQ(m.tangential_acceleration, 0.0);
  EXPECT_EQ(m.tangential_jerk, 0.0);
  EXPECT_NEAR(m.axis_acceleration, kappa * v * v / limits.acceleration, 1e-5);
  EXPECT_NEAR(m.axis_jerk, kappa * kappa * v * v * v / limits.jerk, 1e-5);
  EXPECT_EQ(m.axis_jerk_over_time, 0.0);  // 0.5 of the limit

  // with a quarter of that jerk limit the axis jerk (at least 1/sqrt(2) of kappa^2 v^3 on some
  // axis, i.e. 1.41 of the limit) is above it on every stencil
  Path tight;
  tight.append(PathPiece{Arc{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, r, 0.5 * std::acos(-1.0), 0.0}, 0, -1,
                         {0.5, 0.5, 0.5, 0.05}});
  const ProfileMargins over = profile_margins(tight, timing);
  EXPECT_NEAR(over.axis_jerk, 2.0, 2e-5);
  EXPECT_NEAR(over.axis_jerk_over_time, static_cast<double>(timing.samples.size() - 3) * dt, 1e-12);
  EXPECT_GT(over.axis_jerk_s, 0.0);
  EXPECT_LT(over.axis_jerk_s, path.length());
}

TEST(ProfileMargins, EmptyProfileGivesZeros) {
  const Path path = two_lines({0.1, 1.0, 1.0, 10.0}, {0.1, 1.0, 1.0, 10.0});
  const ProfileMargins m = profile_margins(path, Timing{});
  EXPECT_EQ(m.velocity, 0.0);
  EXPECT_EQ(m.axis_jerk, 0.0);
  EXPECT_EQ(m.axis_jerk_over_time, 0.0);
}

}  // namespace
}  // namespace blendbench
