// The rotation budgets of the velocity planner (intervals.cpp, (R1)-(R3)) through plan_timing:
// the tool's angular velocity, acceleration and jerk within the moves' angular limits on the
// sampled profile, the planner slowing down where the rotation binds, and programs that set no
// rotation planned as before.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "blendbench/corner/blend.hpp"
#include "blendbench/timing/timing.hpp"
#include "support/oriented_program.hpp"
#include "support/profile_check.hpp"
#include "support/timing_paths.hpp"
#include "support/property.hpp"

namespace blendbench {
namespace {

// The local differences' share of a piece, and the relative slack of the checks on the sampled
// profile: rounding and the differences' truncation, far below the bounds' margin (5 %).
constexpr double kStep = 1e-5;
constexpr double kSlack = 1e-6;

struct Rates {
  Vec3 rho, d1, d2;  // rad/m, rad/m^2, rad/m^3
};

// rho, rho', rho'' at local arc length x of a piece, by differences within the piece.
Rates rates_at(const PathPiece& piece, double x) {
  const PieceOrientation& o = *piece.orientation;
  const double len = length(piece.segment);
  const double h = kStep * len;
  const double c = std::clamp(x, h, len - h);
  const Vec3 lo = angular_rate_at(o, c - h);
  const Vec3 mid = angular_rate_at(o, c);
  const Vec3 hi = angular_rate_at(o, c + h);
  return {angular_rate_at(o, x), (hi - lo) / (2 * h), (hi - 2 * mid + lo) / (h * h)};
}

// The largest ratios of |omega|, |alpha|, |eta| to the limits of the piece under each sample.
struct Ratios {
  double velocity = 0, acceleration = 0, jerk = 0;
};
Ratios ratios_on(const PathPiece& piece, double x_local, const TimedSample& x) {
  const Rates r = rates_at(piece, x_local);
  const AngularLimits& lim = piece.orientation->limits;
  const Vec3 omega = r.rho * x.v;
  const Vec3 alpha = r.rho * x.a + r.d1 * x.v * x.v;
  const Vec3 eta = r.rho * x.j + 3 * r.d1 * x.v * x.a + r.d2 * x.v * x.v * x.v;
  return {omega.norm() / lim.velocity, alpha.norm() / lim.acceleration, eta.norm() / lim.jerk};
}
Ratios angular_ratios(const Path& path, const Timing& timing) {
  Ratios out;
  for (const TimedSample& x : timing.samples) {
    const Path::Location at = path.locate(x.s);
    Ratios here = ratios_on(path.pieces()[at.piece], at.s, x);
    // A sample on a junction (locate gives the later piece) carries the jerk of the phase that
    // arrives there or of the one that leaves, and the two pieces may have different limits:
    // at a stop between moves, the last sample of the deceleration reaches the junction to
    // rounding (v 1e-11 m/s) with the incoming move's jerk. So it is checked against the piece
    // its phase belongs to, either side; the samples before and after check each phase against
    // its own piece.
    if (at.s == 0 && at.piece > 0) {
      const PathPiece& before = path.pieces()[at.piece - 1];
      const Ratios left = ratios_on(before, length(before.segment), x);
      here = {std::min(here.velocity, left.velocity), std::min(here.acceleration, left.acceleration),
              std::min(here.jerk, left.jerk)};
    }
    out.velocity = std::max(out.velocity, here.velocity);
    out.acceleration = std::max(out.acceleration, here.acceleration);
    out.jerk = std::max(out.jerk, here.jerk);
  }
  return out;
}

// Every random oriented program, blended by every method and planned in both limits modes:
// the translational limits hold as before and the angular ones on every sample; the last
// sample has the last target (position and orientation arrive together). Under either
// orientation interpolation (the spline's targets turn less, within its range).
void expect_angular_limits_held(OrientationInterpolation interpolation, std::uint64_t first_seed, double max_turn,
                                double reached_acceleration) {
  const int cases = test::property_cases(60);
  double seen_velocity = 0, seen_acceleration = 0;
  for (int c = 0; c < cases; ++c) {
    const std::uint64_t seed = first_seed + static_cast<std::uint64_t>(c);
    auto rng = test::make_rng(seed);
    Program program = test::random_program(rng, max_turn);
    program.orientation_interpolation = interpolation;
    for (Move& m : program.moves) {
      m.angular = {test::log_uniform(rng, 0.2, 5.0), test::log_uniform(rng, 1.0, 50.0), test::log_uniform(rng, 10.0, 2000.0)};
    }
    const Path path = blend(program);
    for (const LimitsMode mode : {LimitsMode::kCartesian, LimitsMode::kPath}) {
      TimingOptions options;
      options.limits = mode;
      options.dt = 2e-3;
      const Timing timing = plan_timing(path, options);
      ASSERT_TRUE(timing.outcome.ok()) << test::seed_text(seed) << ": " << timing.outcome.message;
      test::expect_valid(path, timing, test::seed_text(seed), options);
      const Ratios r = angular_ratios(path, timing);
      ASSERT_LE(r.velocity, 1 + kSlack) << test::seed_text(seed);
      ASSERT_LE(r.acceleration, 1 + kSlack) << test::seed_text(seed);
      ASSERT_LE(r.jerk, 1 + kSlack) << test::seed_text(seed);
      seen_velocity = std::max(seen_velocity, r.velocity);
      seen_acceleration = std::max(seen_acceleration, r.acceleration);
      if (const auto& last = program.moves.back().orientation) {
        ASSERT_LE(rotation_angle(path.orientation(timing.samples.back().s), *last), 1e-9) << test::seed_text(seed);
      }
    }
  }
  // the limits were reached, not only held from afar
  EXPECT_GT(seen_velocity, 0.95);
  EXPECT_GT(seen_acceleration, reached_acceleration);
}

TEST(RotationBudget, AngularLimitsHoldOnTheSampledProfile) {
  expect_angular_limits_held(OrientationInterpolation::kSlerp, 9100, 2.1, 0.9);
}

// The spline's rate varies on every piece and the planner bounds a piece by the largest
// rho' on all of it (intervals.cpp, rotation_budget), so the angular acceleration limit is
// reached less closely than on the slerp's moves of constant rate: 0.75 of it at most here.
TEST(RotationBudget, AngularLimitsHoldOnTheSampledProfileOfTheSpline) {
  expect_angular_limits_held(OrientationInterpolation::kSpline, 9400, 0.6, 0.7);
}

// A 100 mm line turning the tool by 90 degrees, feed 0.5 m/s, 30 deg/s: the rotation binds,
// the line runs at omega / rho = 33 mm/s with the tool at its angular velocity limit.
TEST(RotationBudget, RotationBindsWhereItIsTheTighterLimit) {
  Program program;
  Move move;
  move.geometry = Line{Vec3::Zero(), Vec3(0.1, 0, 0)};
  move.limits = {0.5, 5.0, 5.0, 100.0};
  move.angular = {30 * std::numbers::pi / 180, 10.0, 200.0};
  program.moves = {move};
  const Timing plain = plan_timing(blend(program));
  program.moves[0].orientation = Quat(Eigen::AngleAxisd(std::numbers::pi / 2, Vec3::UnitZ()));
  const Path path = blend(program);
  const Timing turned = plan_timing(path);
  ASSERT_EQ(turned.pieces.size(), 1u);
  EXPECT_EQ(turned.pieces[0].binding, Binding::kRotation);
  EXPECT_EQ(plain.pieces[0].binding, Binding::kFeed);
  const double rho = std::numbers::pi / 2 / 0.1;
  EXPECT_NEAR(turned.pieces[0].v_peak, move.angular.velocity / rho, 1e-9);
  const Ratios r = angular_ratios(path, turned);
  EXPECT_NEAR(r.velocity, 1, 1e-9);
  EXPECT_LE(r.acceleration, 1 + kSlack);
  // 90 degrees at 30 deg/s take at least 3 s; the plain line takes 0.3 s
  EXPECT_GT(turned.cycle_time, 3.0);
  EXPECT_LT(plain.cycle_time, 0.5);
  // the bound knows the angular velocity limit
  EXPECT_GT(turned.bound_cycle_time, 3.0);
  EXPECT_LE(turned.bound_cycle_time, turned.cycle_time);
}

// Targets that do not turn the tool give the plan of the program without orientation, sample
// for sample.
TEST(RotationBudget, NoRotationPlansAsWithoutOrientation) {
  const int cases = test::property_cases(20);
  for (int c = 0; c < cases; ++c) {
    const std::uint64_t seed = 9500 + static_cast<std::uint64_t>(c);
    auto rng = test::make_rng(seed);
    Program program = test::random_program(rng, 0.0);
    for (Move& m : program.moves) m.orientation = program.start_orientation;
    Program plain = program;
    for (Move& m : plain.moves) m.orientation.reset();
    const Timing a = plan_timing(blend(program));
    const Timing b = plan_timing(blend(plain));
    ASSERT_EQ(a.samples.size(), b.samples.size()) << test::seed_text(seed);
    for (std::size_t k = 0; k < a.samples.size(); ++k) {
      ASSERT_EQ(a.samples[k].s, b.samples[k].s) << test::seed_text(seed) << " sample " << k;
      ASSERT_EQ(a.samples[k].v, b.samples[k].v) << test::seed_text(seed) << " sample " << k;
    }
  }
}

// A kink left without transition where the rotation rate changes: the junction slow-down
// baseline crosses it at v <= min(alpha dt, eta dt^2) / |d rho| (here 0.28 mm/s, far below
// the 10 mm/s of the 0.6 degree kink's own rule).
TEST(RotationBudget, RateJumpAtAKinkIsBoundedLikeAKink) {
  Program program;
  Move a;
  a.geometry = Line{Vec3::Zero(), Vec3(0.1, 0, 0)};
  a.limits = {0.5, 5.0, 5.0, 100.0};
  a.angular = {10.0, 20.0, 2000.0};
  a.orientation = Quat(Eigen::AngleAxisd(0.5, Vec3::UnitZ()));
  Move b = a;
  b.geometry = Line{Vec3(0.1, 0, 0), Vec3(0.2, 0.001, 0)};
  b.orientation = Quat(Eigen::AngleAxisd(0.5, Vec3::UnitX())) * *a.orientation;
  program.moves = {a, b};
  const Path path = blend(program);
  TimingOptions options;
  options.baseline = TimingOptions::Baseline::kJunctionSlowdown;
  const Timing timing = plan_timing(path, options);
  const double jump = (path.pieces()[1].orientation->law.index() == 0
                           ? (angular_rate_at(*path.pieces()[1].orientation, 0) - angular_rate_at(*path.pieces()[0].orientation, 0.1)).norm()
                           : 0.0);
  ASSERT_GT(jump, 1.0);
  const double cap = std::min(20.0 * options.dt, 2000.0 * options.dt * options.dt) / jump;
  const auto [lo, hi] = test::velocities_around(timing, 0.1);
  // the samples either side lie within the jerk-limited distance of the knot velocity
  EXPECT_LE(lo, cap + 0.5 * a.limits.jerk * options.dt * options.dt);
  EXPECT_GT(hi, 0.5 * cap);
}

}  // namespace
}  // namespace blendbench
