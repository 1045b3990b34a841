// On one corner program at equal constant path speed, a G1 circular blend excites more residual
// vibration on the elastic arm than a G2 clothoid pair of the same maximum curvature (seed 002, Makino:
// experiment, papers/paper_002.hpp): the circle's curvature steps are acceleration steps of the
// reference, the clothoid ramps its curvature. Also the constant-speed timing law it runs on.

#include <gtest/gtest.h>

#include <cmath>

#include "blendbench/corner/blend.hpp"
#include "blendbench/papers/constant_speed.hpp"
#include "blendbench/papers/paper_002.hpp"

namespace blendbench {
namespace {

// Speed through the corner (m/s), and the ordering's margin: the circle's vibration is several
// times the clothoid's (6.5 measured), so a factor of 2 separates them for the right reason.
constexpr double kSpeed = 0.4;
constexpr double kMargin = 2.0;

TEST(ConstantSpeedTiming, HoldsTheSpeedBetweenTwoSmoothRamps) {
  Program program;
  for (int i = 0; i < 2; ++i) {
    Move& m = program.moves.emplace_back();
    m.geometry = Line{Vec3(0.1 * i, 0, 0), Vec3(0.1 * (i + 1), 0.02 * i, 0)};
    m.limits = {kSpeed, 10, 10, 100};
    m.transition = {Method::kArc, 0.01};
  }
  const Path path = blend(program);
  constexpr double kRamp = 0.05, kDt = 0.002;
  const Timing timing = constant_speed_timing(path, kSpeed, kRamp, kDt);
  const double accel = M_PI * kSpeed * kSpeed / (4 * kRamp);  // pi V / (2 T), T = 2 ramp / V
  ASSERT_GT(timing.samples.size(), 10u);
  EXPECT_EQ(timing.samples.front().v, 0.0);
  EXPECT_EQ(timing.samples.back().v, 0.0);
  EXPECT_DOUBLE_EQ(timing.samples.back().s, path.length());
  for (std::size_t k = 0; k < timing.samples.size(); ++k) {
    const TimedSample& s = timing.samples[k];
    EXPECT_NEAR(s.t, static_cast<double>(k) * kDt, 1e-12);
    if (k > 0) {
      EXPECT_GE(s.s, timing.samples[k - 1].s) << k;
    }
    EXPECT_LE(std::abs(s.a), accel * (1 + 1e-9)) << k;
    if (s.s > kRamp + 1e-9 && s.s < path.length() - kRamp - 1e-9) {
      EXPECT_DOUBLE_EQ(s.v, kSpeed) << k;
    }
  }
  EXPECT_THROW((void)constant_speed_timing(path, kSpeed, path.length(), kDt), std::invalid_argument);
}

TEST(CornerVibration, CircularBlendExcitesMoreThanAClothoidOfTheSameCurvature) {
  Corner002 corner;
  corner.speed = kSpeed;
  const CurveRun002 circle = run_curve_002(Curve002::kSmallCircle, corner);
  const CurveRun002 clothoid = run_curve_002(Curve002::kClothoid, corner);
  // the same maximum curvature, the same speed through it
  const double k_circle = circle.path.corners.at(0).kappa_max, k_clothoid = clothoid.path.corners.at(0).kappa_max;
  EXPECT_NEAR(k_circle, k_clothoid, 1e-6 * k_clothoid);
  for (const CurveRun002* run : {&circle, &clothoid}) {
    ASSERT_TRUE(run->execution.metrics && run->execution.health) << run->name;
    // clean data: nothing saturated, the reference within every joint limit, the arm within its
    // speed limits. (Its acceleration is not checked against the model's stated limits: those are
    // what the peak torque gives with the arm stretched, and since the UR5e-like model took UR's
    // published inertias (issue 46) they are 28.3 rad/s^2 for joint 1, which the small circle's
    // vibration at the paper's 400 mm/s passes by 5 % (29.8 rad/s^2) without saturating.)
    const Health& health = *run->execution.health;
    EXPECT_FALSE(health.saturated) << run->name;
    EXPECT_FALSE(health.reference_velocity.exceeded || health.reference_acceleration.exceeded) << run->name;
    EXPECT_FALSE(health.actual_velocity.exceeded) << run->name;
  }
  const double v_circle = circle.execution.metrics->vibration_corners.at(0).peak_to_peak;
  const double v_clothoid = clothoid.execution.metrics->vibration_corners.at(0).peak_to_peak;
  EXPECT_GT(v_circle, kMargin * v_clothoid) << "circle " << v_circle << " m, clothoid " << v_clothoid << " m";
  EXPECT_GT(circle.following_peak, kMargin * clothoid.following_peak);
}

}  // namespace
}  // namespace blendbench
