#include "blendbench/timing/time_optimal.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "blendbench/corner/blend.hpp"
#include "blendbench/timing/timing.hpp"

namespace blendbench {
namespace {

constexpr double kClose = 1e-11;  // s: the closed forms, to rounding and the bound's margin

// Both limits modes: the closed forms below hold in either (no curve is sped up or slowed down
// on at its limit curve, where they differ).
class Bound : public ::testing::TestWithParam<LimitsMode> {
 protected:
  [[nodiscard]] TimingOptions options() const {
    TimingOptions o;
    o.limits = GetParam();
    return o;
  }
};

Path one_line(double length, const Limits& lim) {
  Path path;
  path.append(PathPiece{Line{Vec3::Zero(), Vec3(length, 0, 0)}, 0, -1, lim});
  return path;
}

// The time of a line from rest to v1 (<= feed) at its end, under feed v and acceleration a.
double line_time(double len, double v, double a, double v1) {
  const double up = v * v / (2 * a);
  const double down = (v * v - v1 * v1) / (2 * a);
  if (up + down <= len) return v / a + (v - v1) / a + (len - up - down) / v;
  // the peak where speeding up from rest meets slowing down to v1
  const double vp = std::sqrt(a * len + 0.5 * v1 * v1);
  return vp / a + (vp - v1) / a;
}

TEST_P(Bound, StraightLineRestToRestIsTheClosedForm) {
  // reaching the feed: L/v + v/a; not reaching it: 2 sqrt(L/a)
  const Limits lim{0.5, 2.0, 2.0, 20.0};
  // (to the bound's rounding margin of 1e-12, which keeps it below)
  EXPECT_NEAR(time_optimal_bound(one_line(1.0, lim), options()), 1.0 / 0.5 + 0.5 / 2.0, kClose);
  EXPECT_LT(time_optimal_bound(one_line(1.0, lim), options()), 1.0 / 0.5 + 0.5 / 2.0);
  EXPECT_NEAR(time_optimal_bound(one_line(0.1, lim), options()), 2 * std::sqrt(0.1 / 2.0), kClose);
  // the plan, jerk-limited, takes longer: by a/j = 0.1 s with the feed reached
  const Timing timing = plan_timing(one_line(1.0, lim), options());
  EXPECT_NEAR(timing.bound_cycle_time, 2.25, kClose);
  EXPECT_NEAR(timing.cycle_time - timing.bound_cycle_time, 0.1, 1e-9);
}

TEST_P(Bound, LineArcLineRunsTheArcAtSqrtAR) {
  // tangent line (0.2 m), quarter arc (r = 0.05 m), line (0.2 m); feed 0.5 > sqrt(a r) = 0.316
  const Limits lim{0.5, 2.0, 2.0, 1e6};
  const double r = 0.05;
  Path path;
  path.append(PathPiece{Line{{-0.2, 0, 0}, {0, 0, 0}}, 0, -1, lim});
  const Arc arc{{0, r, 0}, {0, -1, 0}, {1, 0, 0}, r, std::numbers::pi / 2, 0.0};
  path.append(PathPiece{arc, 1, -1, lim});
  const Vec3 end = point(arc, length(arc));
  path.append(PathPiece{Line{end, end + Vec3(0, 0.2, 0)}, 2, -1, lim});
  const double v_arc = std::sqrt(2.0 * r);
  const double expected = 2 * line_time(0.2, 0.5, 2.0, v_arc) + length(arc) / v_arc;
  const double bound = time_optimal_bound(path, options());
  EXPECT_LE(bound, expected);
  EXPECT_NEAR(bound, expected, 1e-9 * expected);
  EXPECT_GE(plan_timing(path, options()).cycle_time, bound);
}

TEST_P(Bound, StopsAndKinksBoundTheJunctionVelocity) {
  // a 90 degree kink between two 0.1 m lines: v <= a dt / (2 sin 45 deg) there (the acceleration
  // part of the junction rule); as an exact stop, twice a line from rest to rest
  const Limits lim{0.5, 2.0, 2.0, 1e6};
  Path path;
  path.append(PathPiece{Line{{0, 0, 0}, {0.1, 0, 0}}, 0, -1, lim});
  path.append(PathPiece{Line{{0.1, 0, 0}, {0.1, 0.1, 0}}, 1, -1, lim});
  TimingOptions o = options();
  const double v_kink = 2.0 * o.dt / (2 * std::sin(std::numbers::pi / 4));
  EXPECT_NEAR(time_optimal_bound(path, o), 2 * line_time(0.1, 0.5, 2.0, v_kink), kClose);
  o.baseline = TimingOptions::Baseline::kExactStop;
  EXPECT_NEAR(time_optimal_bound(path, o), 2 * 2 * std::sqrt(0.1 / 2.0), kClose);
}

INSTANTIATE_TEST_SUITE_P(BothModes, Bound, ::testing::Values(LimitsMode::kPath, LimitsMode::kCartesian),
                         [](const ::testing::TestParamInfo<LimitsMode>& p) { return std::string(to_string(p.param)); });

// On a curve the cartesian bound is at least the path one: the vector acceleration leaves less
// to the tangential part, so speeding up and slowing down on it take longer.
TEST(Bound, CartesianSpeedChangesOnACurveTakeLonger) {
  Path path;
  path.append(PathPiece{Arc{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0.05, 3.0, 0.0}, 0, -1, {0.5, 2.0, 2.0, 1e6}});
  TimingOptions tangential;
  tangential.limits = LimitsMode::kPath;
  const double path_bound = time_optimal_bound(path, tangential);
  const double vector_bound = time_optimal_bound(path, {});
  EXPECT_GT(vector_bound, path_bound * 1.01);
  EXPECT_GE(plan_timing(path).cycle_time, vector_bound);
  EXPECT_EQ(time_optimal_bound(Path{}), 0.0);
}

}  // namespace
}  // namespace blendbench
