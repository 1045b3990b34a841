// The junction rules and hand-over zones of the velocity planner (intervals.cpp), through
// plan_timing and handover_zones: kinks, curvature jumps (limited, or allowed and reported),
// buffer modes.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "blendbench/corner/blend.hpp"
#include "blendbench/timing/scurve.hpp"
#include "blendbench/timing/timing.hpp"
#include "support/profile_check.hpp"
#include "support/property.hpp"
#include "support/timing_paths.hpp"

namespace blendbench {
namespace {

using test::expect_valid;
using test::kinked_lines;
using test::kRel;
using test::max_velocity_on;
using test::random_path;
using test::velocities_around;

TEST(Junctions, KinkVelocityKeepsTheAccelerationStepWithinJerkTimesPeriod) {
  // 90 degrees, j dt^2 = 2e-5 < a dt: v = j dt^2 / (2 sin 45 deg) at the knot, a = 0 there
  const Limits lim{0.5, 2.0, 2.0, 20.0};
  const Path path = kinked_lines(M_PI / 2, lim, lim, BufferMode::kBlendingLow);
  const Timing timing = plan_timing(path);
  expect_valid(path, timing, "kink");
  const double v_kink = 20.0 * 1e-6 / (2 * std::sin(M_PI / 4));
  const auto [lo, hi] = velocities_around(timing, 0.2);
  EXPECT_GE(lo, v_kink * (1 - kRel));
  EXPECT_LE(lo, v_kink + 0.5 * 20.0 * 1e-6);
  // a gentle kink is no constraint: the controller limit is above the feed
  const Path gentle = kinked_lines(1e-6, lim, lim, BufferMode::kBlendingLow);
  const Timing fast = plan_timing(gentle);
  EXPECT_GT(velocities_around(fast, 0.2).first, 0.49);
}

TEST(Junctions, BufferModesSetTheJunctionVelocityWithAHandoverZone) {
  // two 0.2 m lines at 0.08 and 0.05 m/s (both orders), G1 or with a 1e-4 rad kink (controller
  // bound 0.1 m/s, above both feeds): the junction runs at the mode's velocity (PLCopen), and
  // the slower line reaches its own velocity within the hand-over zone. The change 0.08 <->
  // 0.05 (dv = 0.03 < a^2/j = 0.2, triangular) takes 2 sqrt(dv/j) = 0.0774597 s over
  // 0.065 m/s times that = 5.03488 mm.
  const Limits fast{0.08, 2.0, 2.0, 20.0};
  const Limits slow{0.05, 2.0, 2.0, 20.0};
  const double zone = 0.065 * 2 * std::sqrt(0.03 / 20.0);
  const double step = 0.5 * 20.0 * 1e-6;  // |v - v_knot| within one period of a knot (a = 0)
  struct Case {
    BufferMode mode;
    double v_fast_first, v_slow_first;  // junction velocity for 0.08 -> 0.05 and 0.05 -> 0.08
  };
  const Case cases[] = {{BufferMode::kBlendingLow, 0.05, 0.05},  {BufferMode::kBlendingPrevious, 0.08, 0.05},
                        {BufferMode::kBlendingNext, 0.05, 0.08}, {BufferMode::kBlendingHigh, 0.08, 0.08},
                        {BufferMode::kAborting, 0.05, 0.08},     {BufferMode::kBuffered, 0.05, 0.05}};
  for (const double theta : {0.0, 1e-4}) {
    for (const Case& c : cases) {
      if (theta > 0 && c.mode == BufferMode::kBuffered) continue;  // a Buffered kink stops (below)
      for (const bool fast_first : {true, false}) {
        const Path path = kinked_lines(theta, fast_first ? fast : slow, fast_first ? slow : fast, c.mode);
        const Timing timing = plan_timing(path);
        const std::string where = std::string(to_string(c.mode)) + (fast_first ? " fast->slow" : " slow->fast") +
                                  " theta " + std::to_string(theta);
        expect_valid(path, timing, where);
        const double v_j = fast_first ? c.v_fast_first : c.v_slow_first;
        const auto [lo, hi] = velocities_around(timing, 0.2);
        EXPECT_GE(lo, v_j * (1 - 1e-9) - step) << where;
        EXPECT_LE(hi, v_j + step) << where;
        // the zone: on the slower line, next to the junction, as long as the change needs
        const std::vector<HandoverZone> zones = handover_zones(path);
        if (v_j == 0.05) {
          EXPECT_TRUE(zones.empty()) << where;
          continue;
        }
        ASSERT_EQ(zones.size(), 1u) << where;
        EXPECT_EQ(zones[0].piece, fast_first ? 1u : 0u) << where;
        EXPECT_NEAR(zones[0].s1 - zones[0].s0, zone, 1e-15) << where;
        EXPECT_EQ(fast_first ? zones[0].s0 : zones[0].s1, fast_first ? 0.0 : 0.2) << where;
        EXPECT_EQ(zones[0].velocity, 0.08) << where;
        // outside the zone the slower line keeps its own velocity
        const double outside = fast_first ? max_velocity_on(timing, 0.2 + zone, 0.4) : max_velocity_on(timing, 0, 0.2 - zone);
        EXPECT_LE(outside, 0.05 * (1 + kRel)) << where;
        // and reaches it: the speed is near 0.05 just outside the zone (a jerk-limited change
        // ends with a = 0, so within two periods v has moved by at most 2 j dt^2)
        const double edge = fast_first ? 0.2 + zone : 0.2 - zone;
        EXPECT_GE(velocities_around(timing, edge).first, 0.05 - 4 * step) << where;
      }
    }
  }
  // Buffered stops at the kink
  const Path buffered = kinked_lines(1e-4, fast, slow, BufferMode::kBuffered);
  EXPECT_LE(velocities_around(plan_timing(buffered), 0.2).second, step * (1 + kRel));
}

TEST(Junctions, HandoverVelocityIsLoweredToTheKinkBound) {
  // a 90 degree kink allows j dt^2 / (2 sin 45 deg) = 1.4e-5 m/s: below both feeds, no zone
  const Path path = kinked_lines(M_PI / 2, {0.08, 2.0, 2.0, 20.0}, {0.05, 2.0, 2.0, 20.0}, BufferMode::kBlendingHigh);
  EXPECT_TRUE(handover_zones(path).empty());
  // with j = 2e4 m/s^3 the bound is min(j dt^2, a dt) / (2 sin(theta/2)) = 2e-3 / (2 sin(theta/2)):
  // 2.0 m/s at 1e-3 rad (High takes the faster feed), 0.020 m/s at 0.1 rad (no zone)
  const Path gentle = kinked_lines(1e-3, {0.08, 2.0, 2.0, 2e4}, {0.05, 2.0, 2.0, 2e4}, BufferMode::kBlendingHigh);
  const std::vector<HandoverZone> zones = handover_zones(gentle);
  ASSERT_EQ(zones.size(), 1u);
  EXPECT_EQ(zones[0].velocity, 0.08);
  const Path tight = kinked_lines(0.1, {0.08, 2.0, 2.0, 2e4}, {0.05, 2.0, 2.0, 2e4}, BufferMode::kBlendingHigh);
  EXPECT_TRUE(handover_zones(tight).empty());
}

TEST(Junctions, ShortSlowPieceBetweenFastOnesIsOneHandoverZone) {
  // High: 0.08 -> 0.05 (2 mm, shorter than either 5.03 mm zone) -> 0.08: both zones cover the
  // whole short line, which never has to slow down to its own velocity
  const Limits fast{0.08, 2.0, 2.0, 20.0};
  const Limits slow{0.05, 2.0, 2.0, 20.0};
  Path path;
  path.append(PathPiece{Line{{0, 0, 0}, {0.2, 0, 0}}, 0, -1, fast, BufferMode::kBlendingHigh});
  path.append(PathPiece{Line{{0.2, 0, 0}, {0.202, 0, 0}}, 1, -1, slow, BufferMode::kBlendingHigh});
  path.append(PathPiece{Line{{0.202, 0, 0}, {0.4, 0, 0}}, 2, -1, fast, BufferMode::kBlendingHigh});
  const std::vector<HandoverZone> zones = handover_zones(path);
  ASSERT_EQ(zones.size(), 2u);
  for (const HandoverZone& z : zones) {
    EXPECT_EQ(z.piece, 1u);
    EXPECT_EQ(z.s0, 0.0);
    EXPECT_NEAR(z.s1, 0.002, 1e-15);
  }
  const Timing timing = plan_timing(path);
  expect_valid(path, timing, "short slow piece");
  EXPECT_GE(max_velocity_on(timing, 0.2, 0.202), 0.08 * (1 - 1e-9) - 0.5 * 20.0 * 1e-6);
  // Low: the short line is at most 0.05
  Path low;
  for (PathPiece piece : path.pieces()) {
    piece.buffer = BufferMode::kBlendingLow;
    low.append(std::move(piece));
  }
  EXPECT_TRUE(handover_zones(low).empty());
  EXPECT_LE(max_velocity_on(plan_timing(low), 0.2, 0.202), 0.05 * (1 + kRel));
}

TEST(Junctions, CurvatureJumpCapsTheJunctionVelocity) {
  // line -> tangent arc of radius 0.02 m: v <= sqrt(j dt / kappa) = sqrt(20e-3 * 0.02) = 0.02 m/s
  const Limits lim{0.5, 2.0, 2.0, 20.0};
  Path path;
  path.append(PathPiece{Line{{-0.2, 0, 0}, {0, 0, 0}}, 0, -1, lim});
  path.append(PathPiece{Arc{{0, 0.02, 0}, {0, -1, 0}, {1, 0, 0}, 0.02, 1.0, 0.0}, 1, -1, lim});
  const Timing timing = plan_timing(path);
  expect_valid(path, timing, "curvature jump");
  const double v_jump = std::sqrt(20.0 * 1e-3 * 0.02);
  const auto [lo, hi] = velocities_around(timing, 0.2);
  EXPECT_GE(lo, v_jump * (1 - kRel));
  EXPECT_LE(lo, v_jump + 0.5 * 20.0 * 1e-6);
}

TEST(Junctions, PropertyHandoverZonesFollowTheRule) {
  // every zone of a random path is justified by timing.hpp's rule: next to a junction that is
  // not a stop, on the slower piece, at most the mode's junction velocity, and exactly as long
  // as the change between that velocity and the piece's own needs (or the whole piece), with
  // the piece's own limits in path mode; in cartesian mode the same on lines, and on curves at
  // least as long (their tangential limits are shares of the piece's)
  const int cases = test::property_cases(1000);
  int seen = 0;
  TimingOptions path_mode;
  path_mode.limits = LimitsMode::kPath;
  for (int i = 0; i < cases; ++i) {
    const auto seed = static_cast<std::uint64_t>(5000000 + i);
    auto rng = test::make_rng(seed);
    const Path path = random_path(rng);
    const auto& pieces = path.pieces();
    const std::vector<HandoverZone> zones = handover_zones(path, path_mode);
    const std::vector<HandoverZone> vector_zones = handover_zones(path);
    ASSERT_EQ(zones.size(), vector_zones.size()) << test::seed_text(seed);
    for (std::size_t k = 0; k < zones.size(); ++k) {
      const HandoverZone& a = zones[k];
      const HandoverZone& b = vector_zones[k];
      ASSERT_EQ(a.piece, b.piece) << test::seed_text(seed);
      ASSERT_EQ(a.velocity, b.velocity) << test::seed_text(seed);
      if (std::holds_alternative<Line>(pieces[a.piece].segment)) {
        EXPECT_TRUE(a.s0 == b.s0 && a.s1 == b.s1) << test::seed_text(seed) << " zone on line " << a.piece;
      } else {
        EXPECT_GE(b.s1 - b.s0, (a.s1 - a.s0) * (1 - 1e-12)) << test::seed_text(seed) << " zone on piece " << a.piece;
      }
    }
    for (const HandoverZone& z : zones) {
      ++seen;
      const PathPiece& p = pieces[z.piece];
      const double len = length(p.segment);
      ASSERT_LT(z.s0, z.s1) << test::seed_text(seed);
      ASSERT_GT(z.velocity, p.limits.velocity) << test::seed_text(seed);
      // the zone at the start (after the junction from q) or at the end (before the one to q)
      bool justified = false;
      if (z.s0 == 0 && z.piece > 0 && !p.stop_before) {
        const PathPiece& q = pieces[z.piece - 1];
        const double d = velocity_change(z.velocity, p.limits.velocity, p.limits.deceleration, p.limits.jerk).distance;
        justified = z.velocity <= junction_velocity(q.buffer, q.limits.velocity, p.limits.velocity) &&
                    z.s1 == std::min(len, d);
      }
      if (!justified && z.s1 == len && z.piece + 1 < pieces.size() && !pieces[z.piece + 1].stop_before) {
        const PathPiece& q = pieces[z.piece + 1];
        const double d = velocity_change(p.limits.velocity, z.velocity, p.limits.acceleration, p.limits.jerk).distance;
        justified = z.velocity <= junction_velocity(p.buffer, p.limits.velocity, q.limits.velocity) &&
                    z.s0 == std::max(0.0, len - d);
      }
      EXPECT_TRUE(justified) << test::seed_text(seed) << " zone on piece " << z.piece;
    }
    if (HasFailure()) return;
  }
  EXPECT_GT(seen, cases / 20);
}

// The default scenario's rectangle (120 x 360 mm, 250 mm/s, 2500 mm/s^2, 50000 mm/s^3) with
// every corner blended by `transition`.
Program rectangle(const Transition& transition) {
  const Limits lim{0.25, 2.5, 2.5, 50.0};
  const Vec3 corners[] = {{0, 0, 0}, {0.12, 0, 0}, {0.12, 0.36, 0}, {0, 0.36, 0}, {0, 0, 0}};
  Program program;
  for (int k = 0; k < 4; ++k) {
    Move& move = program.moves.emplace_back();
    move.geometry = Line{corners[k], corners[k + 1]};
    move.limits = lim;
    move.transition = transition;
  }
  return program;
}

// A circular blend whose curvature steps are allowed is faster than stopping at every corner at
// any servo rate (its steps are not bounded per period), while under the j dt rule its time
// depends on the rate; measured in one run.
TEST(Junctions, AnArcBlendThatAllowsCurvatureStepsBeatsTheExactStopAtEveryServoRate) {
  Transition arc{Method::kArc, 0.01};
  const Path stops = blend(rectangle({}));
  for (const LimitsMode mode : {LimitsMode::kCartesian, LimitsMode::kPath}) {
    for (const double rate : {125.0, 250.0, 500.0, 1000.0, 2000.0, 4000.0, 8000.0}) {
      TimingOptions options;
      options.dt = 1.0 / rate;
      options.limits = mode;
      arc.curvature_steps = CurvatureSteps::kAllow;
      const Path allowed = blend(rectangle(arc));
      arc.curvature_steps = CurvatureSteps::kLimit;
      const Path limited = blend(rectangle(arc));
      const Timing stop = plan_timing(stops, options);
      const Timing allow = plan_timing(allowed, options);
      const Timing limit = plan_timing(limited, options);
      const double ratio = allow.cycle_time / stop.cycle_time;
      std::printf("%s %6.0f Hz: arc allow / exact stop %.4f, arc limit / exact stop %.4f\n", std::string(to_string(mode)).c_str(),
                  rate, ratio, limit.cycle_time / stop.cycle_time);
      const std::string where = std::string(to_string(mode)) + " at " + std::to_string(rate) + " Hz";
      EXPECT_LT(ratio, 1.0) << where;
      expect_valid(allowed, allow, where, options);
      if (mode == LimitsMode::kCartesian) (void)test::expect_cartesian_valid(allowed, allow, {}, where);
    }
  }
}

// Where the steps are allowed, the arc runs at its constant-speed bound (path mode: min(feed,
// sqrt(a/kappa), cbrt(j/kappa^2)); cartesian: 0.99 of it) and each corner reports the step of
// the normal acceleration at the servo period, |dK| v^2 / dt; under the rule that step is at
// most j dt, i.e. the reported jerk at most j.
TEST(Junctions, AllowedCurvatureStepsAreReportedPerCorner) {
  Transition arc{Method::kArc, 0.01};
  arc.curvature_steps = CurvatureSteps::kAllow;
  const Path allowed = blend(rectangle(arc));
  arc.curvature_steps = CurvatureSteps::kLimit;
  const Path limited = blend(rectangle(arc));
  const double kappa = 1 / 0.01;  // 90 degrees, corner distance 10 mm: radius 10 mm
  const double v_arc = std::min({0.25, std::sqrt(2.5 / kappa), std::cbrt(50.0 / (kappa * kappa))});
  for (const LimitsMode mode : {LimitsMode::kPath, LimitsMode::kCartesian}) {
    TimingOptions options;
    options.limits = mode;
    const Timing allow = plan_timing(allowed, options);
    ASSERT_EQ(allow.corner_steps.size(), 3u);
    const double expected_v = mode == LimitsMode::kPath ? v_arc : 0.99 * v_arc;
    for (std::size_t k = 0; k < allowed.pieces().size(); ++k) {
      if (allowed.pieces()[k].corner < 0) continue;
      EXPECT_TRUE(allowed.pieces()[k].curvature_step_allowed);
      EXPECT_NEAR(allow.pieces[k].v_peak, expected_v, 1e-6 * v_arc) << to_string(mode);
    }
    for (const Timing::CornerStep& step : allow.corner_steps) {
      EXPECT_NEAR(step.dk, kappa, 1e-9 * kappa);
      EXPECT_NEAR(step.velocity, expected_v, 1e-6 * v_arc) << to_string(mode);
      EXPECT_NEAR(step.jerk, step.dk * step.velocity * step.velocity / options.dt, 1e-9 * step.jerk);
      EXPECT_GT(step.jerk, 10 * 50.0);
    }
    const Timing limit = plan_timing(limited, options);
    for (const Timing::CornerStep& step : limit.corner_steps) {
      EXPECT_GT(step.jerk, 0.0);
      EXPECT_LE(step.jerk, 50.0 * (1 + kRel)) << to_string(mode);
    }
  }
  // a G2 transition leaves no step
  const Timing smooth = plan_timing(blend(rectangle({Method::kBiclothoid, 0.002})));
  for (const Timing::CornerStep& step : smooth.corner_steps) EXPECT_EQ(step.jerk, 0.0);
}

// Nor where it meets an arc with the arc's curvature only to rounding: a Bezier transition from
// a line into an arc of radius 30 mm (60 degree corner) ends at 33.33 1/m with a difference of
// about 1e-13 1/m, which is no step (intervals.cpp, kCurvatureStepShare).
TEST(Junctions, RoundingSizedCurvatureDifferenceIsNoStep) {
  const double r = 0.03;
  const double c = std::cos(std::numbers::pi / 3), s = std::sin(std::numbers::pi / 3);
  const Vec3 u(s, -c, 0), v(c, s, 0);  // from the centre to the start; the start tangent
  Move line;
  line.geometry = Line{{-0.1, 0, 0}, {0, 0, 0}};
  line.limits = {0.25, 2.5, 2.5, 50.0};
  line.transition = {Method::kBezier, 0.005};
  Move arc;
  arc.geometry = Arc{-r * u, u, v, r, 1.5, 0.0};
  arc.limits = line.limits;
  Program program;
  program.moves = {line, arc};
  const Path path = blend(program);
  ASSERT_EQ(path.corners.size(), 1u);
  const Timing timing = plan_timing(path);
  expect_valid(path, timing, "bezier into an arc");
  ASSERT_EQ(timing.corner_steps.size(), 1u);
  EXPECT_EQ(timing.corner_steps[0].jerk, 0.0);
  EXPECT_EQ(timing.corner_steps[0].dk, 0.0);
}

}  // namespace
}  // namespace blendbench
