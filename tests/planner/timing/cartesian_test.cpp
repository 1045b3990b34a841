#include "blendbench/timing/cartesian.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <utility>
#include <numbers>

#include "support/property.hpp"

namespace blendbench {
namespace {


// (C1) and (C2) of cartesian.hpp at speed v with tangential limits t (true: both hold).
bool conditions_hold(double kappa, double g, const Limits& lim, const TangentialLimits& t, double v, double slack = 0) {
  const double n = kappa * v * v;
  const double a_t = std::max(t.acceleration, t.deceleration);
  const bool c1 = std::hypot(t.acceleration, n) <= lim.acceleration * (1 + slack) &&
                  std::hypot(t.deceleration, n) <= lim.deceleration * (1 + slack);
  const double tangential = t.jerk + kappa * kappa * v * v * v;
  const double normal = 3 * kappa * v * a_t + g * v * v * v;
  return c1 && std::hypot(tangential, normal) <= lim.jerk * (1 + slack);
}

TEST(Cartesian, ALineKeepsTheFullLimits) {
  const Limits lim{0.5, 2, 3, 40};
  const TangentialLimits t = cartesian_tangential_limits(0, 0, lim, 0.8);
  EXPECT_EQ(t.acceleration, 2);
  EXPECT_EQ(t.deceleration, 3);
  EXPECT_EQ(t.jerk, 40);
  const CartesianCap cap = cartesian_speed_limit(0, 0, lim, t);
  EXPECT_TRUE(std::isinf(cap.acceleration) && std::isinf(cap.jerk));
}

// Random curves and limits: the tangential limits are positive and within the limits, the
// conditions hold at the design speed, and the caps are the highest speeds at which they hold.
TEST(Cartesian, PropertySharesHoldBothConditionsAndTheCapsAreTight) {
  const int cases = test::property_cases(20000);
  for (int i = 0; i < cases; ++i) {
    const auto seed = static_cast<std::uint64_t>(8100000 + i);
    auto rng = test::make_rng(seed);
    const Limits lim{test::log_uniform(rng, 1e-3, 10), test::log_uniform(rng, 1e-2, 100), test::log_uniform(rng, 1e-2, 100),
                     test::log_uniform(rng, 1e-1, 1e5)};
    const double kappa = test::log_uniform(rng, 1e-2, 1e4);
    const double g = test::uniform(rng, 0, 1) < 0.3 ? 0.0 : test::log_uniform(rng, 1e-2, 1e7);
    const double share = test::uniform(rng, 0.05, 0.99);
    const TangentialLimits t = cartesian_tangential_limits(kappa, g, lim, share);
    const std::string where = test::seed_text(seed);
    ASSERT_GT(t.acceleration, 0) << where;
    ASSERT_GT(t.deceleration, 0) << where;
    ASSERT_GT(t.jerk, 0) << where;
    ASSERT_LE(t.acceleration, lim.acceleration) << where;
    ASSERT_LE(t.deceleration, lim.deceleration) << where;
    ASSERT_LE(t.jerk, lim.jerk) << where;
    const double v0 = std::min(std::sqrt(std::min(lim.acceleration, lim.deceleration) / kappa),
                               std::cbrt(lim.jerk / std::hypot(kappa * kappa, g)));
    const double vc = std::min(lim.velocity, share * v0);
    ASSERT_TRUE(conditions_hold(kappa, g, lim, t, vc, 1e-12)) << where;
    const CartesianCap cap = cartesian_speed_limit(kappa, g, lim, t);
    const double v = std::min(cap.acceleration, cap.jerk);
    // the stored A_t and J_t are rounded: where they are close to A and J, the small normal
    // budgets A^2 - A_t^2 and J - J_t left to the curve move by eps relative to A^2 and J, and
    // the caps with them (relative eps (A/room)^2 and eps J / (J - J_t)): tight to that
    const double eps = std::numeric_limits<double>::epsilon();
    double rounding = lim.jerk / (lim.jerk - t.jerk);
    for (const auto& [a, a_t] : {std::pair{lim.acceleration, t.acceleration}, std::pair{lim.deceleration, t.deceleration}}) {
      rounding = std::max(rounding, a * a / ((a - a_t) * (a + a_t)));
    }
    const double tight = 1e-9 + 16 * eps * rounding;
    ASSERT_GE(v, vc * (1 - tight)) << where;
    ASSERT_TRUE(conditions_hold(kappa, g, lim, t, v, 1e-12)) << where;
    ASSERT_FALSE(conditions_hold(kappa, g, lim, t, v * (1 + tight))) << where << ": the cap is not the highest";
  }
}

// The jerk formula of cartesian.hpp against third finite differences of the position along a
// motion s(t) with varying speed, on an arc, a helix, a clothoid and a 3D Bezier.
TEST(Cartesian, TcpAccelerationAndJerkMatchFiniteDifferences) {
  const std::vector<Segment> segments = {
      Arc{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 0.05, 3.0, 0.0},
      Arc{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 0.05, 3.0, 0.04},
      Clothoid{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 5.0, 400.0, 0.08},
      Bezier({Vec3(0, 0, 0), Vec3(0.05, 0, 0.01), Vec3(0.08, 0.04, -0.02), Vec3(0.1, 0.1, 0.03)}),
  };
  // s(t) = s0 + v0 t + a0 t^2 / 2 + j0 t^3 / 6
  const double s0 = 0.01, v0 = 0.3, a0 = -1.5, j0 = 40;
  const auto s_of = [&](double t) { return s0 + t * (v0 + t * (a0 / 2 + t * j0 / 6)); };
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const Segment& seg = segments[i];
    for (const double t : {0.0, 0.01, 0.02}) {
      const double s = s_of(t);
      const double v = v0 + t * (a0 + t * j0 / 2);
      const double a = a0 + t * j0;
      const Vec3 tt = tangent(seg, s);
      const Vec3 k = curvature_vector(seg, s);
      const Vec3 acc = tcp_acceleration(v, a, tt, k);
      const Vec3 jerk = tcp_jerk(v, a, j0, tt, k, curvature_derivative(seg, s));
      const double h = 1e-4;
      const auto p = [&](double x) { return point(seg, s_of(x)); };
      const Vec3 fd_a = (p(t + h) - 2 * p(t) + p(t - h)) / (h * h);
      const Vec3 fd_j = (p(t + 2 * h) - 2 * p(t + h) + 2 * p(t - h) - p(t - 2 * h)) / (2 * h * h * h);
      EXPECT_LE((acc - fd_a).norm(), 1e-5 * std::max(1.0, acc.norm())) << "segment " << i << " t=" << t;
      EXPECT_LE((jerk - fd_j).norm(), 1e-3 * std::max(1.0, jerk.norm())) << "segment " << i << " t=" << t;
    }
  }
}

// Per-axis limits lower the vector limits by the motion's reach along each axis: a line along x
// gets the x limits exactly, a line at 45 degrees in xy sqrt(2) times the smaller, a curve in the
// xy plane ignores z, and a 3D curve takes the smallest.
TEST(Cartesian, AxisLimitsLowerTheVectorLimitsByTheReachOfEachAxis) {
  const Limits lim{1, 10, 10, 1000};
  const AxisLimits axes{Vec3(2, 3, 0.5), Vec3(200, 300, 50)};
  const Limits x = effective_vector_limits(Line{Vec3::Zero(), Vec3(1, 0, 0)}, lim, axes);
  EXPECT_DOUBLE_EQ(x.acceleration, 2);
  EXPECT_DOUBLE_EQ(x.jerk, 200);
  const Limits diagonal = effective_vector_limits(Line{Vec3::Zero(), Vec3(1, 1, 0)}, lim, axes);
  EXPECT_NEAR(diagonal.acceleration, 2 * std::sqrt(2.0), 1e-12);
  const Limits planar = effective_vector_limits(Arc{Vec3::Zero(), Vec3(1, 0, 0), Vec3(0, 1, 0), 0.1, 1.0, 0.0}, lim, axes);
  EXPECT_DOUBLE_EQ(planar.acceleration, 2);
  EXPECT_DOUBLE_EQ(planar.deceleration, 2);
  EXPECT_DOUBLE_EQ(planar.jerk, 200);
  const Limits helix = effective_vector_limits(Arc{Vec3::Zero(), Vec3(1, 0, 0), Vec3(0, 1, 0), 0.1, 1.0, 0.1}, lim, axes);
  EXPECT_DOUBLE_EQ(helix.acceleration, 0.5);
  EXPECT_DOUBLE_EQ(helix.jerk, 50);
  EXPECT_DOUBLE_EQ(effective_vector_limits(Line{Vec3::Zero(), Vec3(1, 0, 0)}, lim, std::nullopt).acceleration, 10);
  // a vector in the xy plane at the effective limit never exceeds an axis limit
  for (double angle = 0; angle < 2 * std::numbers::pi; angle += 0.1) {
    const Vec3 a = planar.acceleration * Vec3(std::cos(angle), std::sin(angle), 0);
    EXPECT_LE(a.x(), 2 * (1 + 1e-15));
    EXPECT_LE(a.y(), 3 * (1 + 1e-15));
  }
}

TEST(Cartesian, ModeNamesRoundTrip) {
  for (const LimitsMode mode : {LimitsMode::kPath, LimitsMode::kCartesian}) {
    EXPECT_EQ(limits_mode_from_string(to_string(mode)), mode);
  }
  EXPECT_FALSE(limits_mode_from_string("tangential"));
}

}  // namespace
}  // namespace blendbench
