#include "planner/timing.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdio>
#include <string>

#include "planner/blend.hpp"
#include "planner/scurve.hpp"
#include "../support/profile_check.hpp"
#include "../support/property.hpp"

namespace blendbench {
namespace {

constexpr double kFeedShareTol = 1e-9;
using test::expect_valid;
using test::kRel;
using test::Margins;

Move line_move(const Vec3& a, const Vec3& b, const Limits& limits) {
  Move move;
  move.geometry = Line{a, b};
  move.limits = limits;
  return move;
}

TEST(Timing, SingleLineIsTheAnalyticScurve) {
  // dv = 0.5 >= a^2/j = 0.2: each ramp 0.5/2 + 2/20 = 0.35 s over 0.0875 m; 0.825 m cruised
  Program program;
  program.moves = {line_move({0, 0, 0}, {1, 0, 0}, {0.5, 2.0, 2.0, 20.0})};
  const Path path = blend(program);
  const Timing timing = plan_timing(path);
  ASSERT_TRUE(timing.outcome.ok());
  EXPECT_NEAR(timing.cycle_time, 0.35 + 1.65 + 0.35, 1e-12);
  EXPECT_EQ(timing.samples.size(), 2351u);
  ASSERT_EQ(timing.pieces.size(), 1u);
  EXPECT_EQ(timing.pieces[0].binding, "feed");
  EXPECT_DOUBLE_EQ(timing.pieces[0].v_peak, 0.5);
  // at or above 99.9 % of the feed: the cruise plus the last tau of each ramp, where the
  // jerk phase leaves v = vp - j tau^2 / 2
  const double tau = std::sqrt(2 * 1e-3 * 0.5 / 20.0);
  EXPECT_NEAR(timing.feed_share, (1.65 + 2 * tau) / 2.35, kFeedShareTol);
  // mid-cruise sample
  EXPECT_NEAR(timing.samples[1000].v, 0.5, 1e-12);
  EXPECT_NEAR(timing.samples[1000].s, 0.0875 + 0.5 * (1.0 - 0.35), 1e-12);
  expect_valid(path, timing, "single line");
}

TEST(Timing, ExactStopSquareStopsAtEveryCorner) {
  const Limits lim{0.2, 1.0, 1.0, 10.0};
  Program program;
  program.moves = {line_move({0, 0, 0}, {0.1, 0, 0}, lim), line_move({0.1, 0, 0}, {0.1, 0.1, 0}, lim),
                   line_move({0.1, 0.1, 0}, {0, 0.1, 0}, lim)};
  const Path path = blend(program);
  const Timing timing = plan_timing(path);
  const double one = plan_scurve(0.1, 0, 0, {0.2, 1.0, 1.0, 10.0}).curve.duration();
  EXPECT_NEAR(timing.cycle_time, 3 * one, 1e-12);
  expect_valid(path, timing, "square");
}

TEST(Timing, ArcPieceIsCappedByItsCurvature) {
  // radius 0.01 m, a = 1: sqrt(a/kappa) = 0.1 m/s < feed 0.5; the arc alone, rest to rest
  Path path;
  PathPiece piece{Arc{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0.01, 3.0, 0.0}, 0, -1, {0.5, 1.0, 1.0, 1000.0}};
  path.append(piece);
  const Timing timing = plan_timing(path);
  ASSERT_EQ(timing.pieces.size(), 1u);
  EXPECT_EQ(timing.pieces[0].binding, "curvature");
  EXPECT_NEAR(timing.pieces[0].v_peak, 0.1, 1e-12);
  EXPECT_EQ(timing.feed_share, 0.0);
  expect_valid(path, timing, "arc");
}

TEST(Timing, NonPositiveServoPeriodIsAnInputError) {
  Program program;
  program.moves = {line_move({0, 0, 0}, {1, 0, 0}, {0.5, 2.0, 2.0, 20.0})};
  const Path path = blend(program);
  TimingOptions options;
  options.dt = 0;
  EXPECT_THROW((void)plan_timing(path, options), InputError);
}

TEST(Timing, EmptyPathIsOneSampleAtRest) {
  const Timing timing = plan_timing(Path{});
  ASSERT_EQ(timing.samples.size(), 1u);
  EXPECT_EQ(timing.cycle_time, 0.0);
}

// log-uniform in [lo, hi]
double log_uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::exp(test::uniform(rng, std::log(lo), std::log(hi)));
}

TEST(Timing, PropertyExactStopProgramsHoldEveryLimit) {
  const int cases = test::property_cases(300);
  for (int i = 0; i < cases; ++i) {
    const auto seed = static_cast<std::uint64_t>(i);
    auto rng = test::make_rng(seed);
    Program program;
    Vec3 p = Vec3::Zero();
    const int n = 1 + static_cast<int>(test::uniform(rng, 0, 5));
    for (int k = 0; k < n; ++k) {
      const Vec3 dir = Vec3(test::uniform(rng, -1, 1), test::uniform(rng, -1, 1), test::uniform(rng, -1, 1)).normalized();
      // a feed that keeps each move within about two seconds (and the sample count small)
      const double len = log_uniform(rng, 1e-6, 0.5);
      const Vec3 q = p + dir * len;
      program.moves.push_back(line_move(p, q, {log_uniform(rng, std::max(1e-3, 0.5 * len), 2.0), log_uniform(rng, 0.1, 50.0),
                                               log_uniform(rng, 0.1, 50.0), log_uniform(rng, 1.0, 5000.0)}));
      p = q;
    }
    const Path path = blend(program);
    const Timing timing = plan_timing(path);
    expect_valid(path, timing, test::seed_text(seed));
    if (HasFailure()) return;
  }
}

// Two lines joined at `theta` (rad) in the x-y plane, no stop, the given buffer mode.
Path kinked_lines(double theta, const Limits& a, const Limits& b, BufferMode mode) {
  Path path;
  const Vec3 corner(0.2, 0, 0);
  path.append(PathPiece{Line{{0, 0, 0}, corner}, 0, -1, a, mode});
  PathPiece second{Line{corner, corner + 0.2 * Vec3(std::cos(theta), std::sin(theta), 0)}, 1, -1, b, mode};
  second.kink_angle = theta;
  path.append(second);
  return path;
}

// The velocity at arc length s, from the samples on either side (the smaller of the two, and
// the jerk-limited bound on how far either is from the knot velocity).
std::pair<double, double> velocities_around(const Timing& timing, double s) {
  const auto& x = timing.samples;
  const auto after = std::lower_bound(x.begin(), x.end(), s, [](const TimedSample& a, double v) { return a.s < v; });
  const auto before = after == x.begin() ? after : std::prev(after);
  return {std::min(before->v, after->v), std::max(before->v, after->v)};
}

TEST(Timing, KinkVelocityKeepsTheAccelerationStepWithinJerkTimesPeriod) {
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

TEST(Timing, BufferModesChooseTheKinkVelocityBelowBothFeeds) {
  // a 1e-4 rad kink (controller limit 0.1 m/s > both feeds): the mode picks the feed, the
  // slower piece's own limit still holds on its side
  const Limits slow{0.05, 2.0, 2.0, 20.0};
  const Limits fast{0.08, 2.0, 2.0, 20.0};
  for (BufferMode mode : {BufferMode::kBlendingLow, BufferMode::kBlendingPrevious, BufferMode::kBlendingNext,
                          BufferMode::kBlendingHigh, BufferMode::kAborting}) {
    const Path path = kinked_lines(1e-4, fast, slow, mode);
    const Timing timing = plan_timing(path);
    const std::string where(to_string(mode));
    expect_valid(path, timing, where);
    const auto [lo, hi] = velocities_around(timing, 0.2);
    EXPECT_GE(lo, 0.05 * (1 - kRel)) << where;
    EXPECT_LE(lo, 0.05 + 0.5 * 20.0 * 1e-6) << where;
  }
  // Buffered stops at the kink
  const Path buffered = kinked_lines(1e-4, fast, slow, BufferMode::kBuffered);
  EXPECT_LE(velocities_around(plan_timing(buffered), 0.2).second, 0.5 * 20.0 * 1e-6 * (1 + kRel));
}

TEST(Timing, CurvatureJumpCapsTheJunctionVelocity) {
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

TEST(Timing, CollinearPiecesWithEqualLimitsAccelerateThrough) {
  const Limits lim{0.5, 2.0, 2.0, 20.0};
  Path split;
  split.append(PathPiece{Line{{0, 0, 0}, {0.3, 0, 0}}, 0, -1, lim});
  split.append(PathPiece{Line{{0.3, 0, 0}, {1, 0, 0}}, 1, -1, lim});
  Path whole;
  whole.append(PathPiece{Line{{0, 0, 0}, {1, 0, 0}}, 0, -1, lim});
  EXPECT_NEAR(plan_timing(split).cycle_time, plan_timing(whole).cycle_time, 1e-12);
}

TEST(Timing, BaselinesOnAStopFreePath) {
  // line -> arc -> line, tangent: exact stop = the sum of rest-to-rest S-curves of the pieces;
  // the junction slow-down only caps the junctions and is faster; no baseline = slow-down here
  const Limits lim{0.5, 2.0, 2.0, 20.0};
  Path path;
  path.append(PathPiece{Line{{-0.2, 0, 0}, {0, 0, 0}}, 0, -1, lim});
  const Arc arc{{0, 0.05, 0}, {0, -1, 0}, {1, 0, 0}, 0.05, M_PI / 2, 0.0};
  path.append(PathPiece{arc, 1, -1, lim});
  const Vec3 end = point(arc, length(arc));
  path.append(PathPiece{Line{end, end + Vec3(0, 0.2, 0)}, 2, -1, lim});
  TimingOptions options;
  options.baseline = TimingOptions::Baseline::kExactStop;
  const Timing stop = plan_timing(path, options);
  expect_valid(path, stop, "exact stop", options.baseline);
  const double arc_cap = std::min(std::sqrt(2.0 * 0.05), std::cbrt(20.0 * 0.05 * 0.05));
  const double expected = 2 * plan_scurve(0.2, 0, 0, {0.5, 2.0, 2.0, 20.0}).curve.duration() +
                          plan_scurve(length(arc), 0, 0, {arc_cap, 2.0, 2.0, 20.0}).curve.duration();
  EXPECT_NEAR(stop.cycle_time, expected, 1e-12);
  for (double s : {0.2, 0.2 + length(arc)}) EXPECT_LE(velocities_around(stop, s).second, 0.5 * 20.0 * 1e-6 * (1 + kRel));
  options.baseline = TimingOptions::Baseline::kJunctionSlowdown;
  const Timing slowdown = plan_timing(path, options);
  expect_valid(path, slowdown, "slowdown", options.baseline);
  EXPECT_LT(slowdown.cycle_time, stop.cycle_time);
  EXPECT_NEAR(plan_timing(path).cycle_time, slowdown.cycle_time, 1e-12);
  // from the junction caps sqrt(j dt / kappa) = 0.032 m/s the arc is too short to reach
  // its cap sqrt(a / kappa) = 0.32 m/s
  EXPECT_EQ(slowdown.pieces[0].binding, "feed");
  EXPECT_EQ(slowdown.pieces[1].binding, "length");
}

TEST(Timing, JunctionSlowdownIgnoresExactStopsExceptBuffered) {
  const Limits lim{0.2, 1.0, 1.0, 10.0};
  Program program;
  program.moves = {line_move({0, 0, 0}, {0.1, 0, 0}, lim), line_move({0.1, 0, 0}, {0.2, 0.01, 0}, lim),
                   line_move({0.2, 0.01, 0}, {0.3, 0.01, 0}, lim)};
  const Path path = blend(program);
  TimingOptions options;
  options.baseline = TimingOptions::Baseline::kJunctionSlowdown;
  const Timing slowdown = plan_timing(path, options);
  const Timing stops = plan_timing(path);
  EXPECT_LT(slowdown.cycle_time, stops.cycle_time);
  program.moves[0].buffer = BufferMode::kBuffered;
  program.moves[1].buffer = BufferMode::kBuffered;
  const Path buffered = blend(program);
  EXPECT_NEAR(plan_timing(buffered, options).cycle_time, stops.cycle_time, 1e-12);
}

// A random path built piece by piece: lines, arcs, clothoids and cubic Beziers, each starting
// tangent to the previous end or at a random kink, with random limits, buffer modes and stops.
Path random_path(std::mt19937_64& rng) {
  const auto unit = [&rng] {
    return Vec3(test::uniform(rng, -1, 1), test::uniform(rng, -1, 1), test::uniform(rng, -1, 1) + 1e-3).normalized();
  };
  const auto random_limits = [&rng] {
    return Limits{log_uniform(rng, 0.02, 2.0), log_uniform(rng, 0.2, 50.0), log_uniform(rng, 0.2, 50.0),
                  log_uniform(rng, 2.0, 5000.0)};
  };
  const Limits shared = random_limits();
  const bool per_piece = test::uniform(rng, 0, 1) < 0.5;
  const BufferMode modes[] = {BufferMode::kAborting, BufferMode::kBuffered, BufferMode::kBlendingLow,
                              BufferMode::kBlendingPrevious, BufferMode::kBlendingNext, BufferMode::kBlendingHigh};
  Path path;
  Vec3 p = Vec3::Zero();
  Vec3 dir = unit();
  const int n = 1 + static_cast<int>(test::uniform(rng, 0, 10));
  for (int k = 0; k < n; ++k) {
    if (k > 0 && test::uniform(rng, 0, 1) < 0.35) dir = unit();
    const Vec3 perp = dir.cross(unit()).normalized();
    const double kind = test::uniform(rng, 0, 4);
    Segment seg = Line{p, p + dir * log_uniform(rng, 1e-4, 0.2)};
    if (kind >= 1 && kind < 2) {
      const double r = log_uniform(rng, 1e-3, 0.2);
      seg = Arc{p - r * perp, perp, dir, r, test::uniform(rng, 0.05, 3.0), 0.0};
    } else if (kind >= 2 && kind < 3) {
      const double len = log_uniform(rng, 1e-4, 0.05);
      seg = Clothoid{p, dir, perp, test::uniform(rng, -50, 50), test::uniform(rng, -1, 1) * 4e3, len};
    } else if (kind >= 3) {
      // legs within 70 degrees of dir: the hodograph never vanishes
      const double l = log_uniform(rng, 1e-4, 0.05);
      std::vector<Vec3> ctrl{p};
      for (int i = 0; i < 3; ++i) {
        const double ang = test::uniform(rng, -1.2, 1.2);
        ctrl.push_back(ctrl.back() + l * (std::cos(ang) * dir + std::sin(ang) * perp));
      }
      seg = Bezier(ctrl);
    }
    PathPiece piece{seg, k, -1, per_piece ? random_limits() : shared,
                    modes[static_cast<int>(test::uniform(rng, 0, 6)) % 6]};
    if (!path.pieces().empty()) {
      const Segment& prev = path.pieces().back().segment;
      piece.kink_angle = angle_between(tangent(prev, length(prev)), tangent(seg, 0.0));
      piece.stop_before = test::uniform(rng, 0, 1) < 0.1 ||
                          (piece.kink_angle > 1e-9 && path.pieces().back().buffer == BufferMode::kBuffered);
    }
    p = end_point(seg);
    dir = tangent(seg, length(seg));
    path.append(std::move(piece));
  }
  return path;
}

TEST(Timing, PropertyRandomPathsHoldEveryLimitInEveryMode) {
  const int cases = test::property_cases(1000);
  Margins worst;
  for (int i = 0; i < cases; ++i) {
    const auto seed = static_cast<std::uint64_t>(5000000 + i);
    auto rng = test::make_rng(seed);
    const Path path = random_path(rng);
    TimingOptions options;
    options.baseline = static_cast<TimingOptions::Baseline>(i % 3);
    const Timing timing = plan_timing(path, options);
    const Margins m = expect_valid(path, timing, test::seed_text(seed), options.baseline);
    worst = {std::max(worst.v, m.v), std::max(worst.a, m.a), std::max(worst.j, m.j), std::max(worst.normal, m.normal)};
    ASSERT_EQ(timing.pieces.size(), path.pieces().size()) << test::seed_text(seed);
    ASSERT_GE(timing.feed_share, 0.0);
    ASSERT_LE(timing.feed_share, 1.0);
    if (HasFailure()) return;
  }
  // the profile uses the limits: some case comes within 0.1 % of each
  EXPECT_GT(worst.v, 0.999);
  EXPECT_GT(worst.a, 0.999);
  EXPECT_GT(worst.j, 0.999);
  RecordProperty("max_ratio_v", std::to_string(worst.v));
  RecordProperty("max_ratio_a", std::to_string(worst.a));
  RecordProperty("max_ratio_j", std::to_string(worst.j));
  RecordProperty("max_ratio_normal", std::to_string(worst.normal));
  std::printf("worst ratios: v %.15f a %.15f j %.15f normal %.15f\n", worst.v, worst.a, worst.j, worst.normal);
}

TEST(Timing, PropertyRaisingALimitNeverSlowsTheCycle) {
  // every piece's limit of one kind raised by the same factor (so the intervals keep their
  // structure): the knot velocities can only rise, and so can every interval's speed
  const int cases = test::property_cases(300);
  for (int i = 0; i < cases; ++i) {
    const auto seed = static_cast<std::uint64_t>(7000000 + i);
    auto rng = test::make_rng(seed);
    const Path path = random_path(rng);
    const double before = plan_timing(path).cycle_time;
    const int which = i % 4;
    const double factor = test::uniform(rng, 1.0, 3.0);
    Path raised;
    for (PathPiece piece : path.pieces()) {
      double* field[] = {&piece.limits.velocity, &piece.limits.acceleration, &piece.limits.deceleration,
                         &piece.limits.jerk};
      *field[which] *= factor;
      raised.append(std::move(piece));
    }
    const double after = plan_timing(raised).cycle_time;
    ASSERT_LE(after, before * (1 + 1e-12)) << test::seed_text(seed) << " limit " << which << " x" << factor;
  }
}

TEST(Timing, PropertyExactStopProgramsThroughTheBlender) {
  // programs of lines and arcs with method none (exact stop at every kink), random buffer modes
  const int cases = test::property_cases(300);
  for (int i = 0; i < cases; ++i) {
    const auto seed = static_cast<std::uint64_t>(9000000 + i);
    auto rng = test::make_rng(seed);
    Program program;
    Vec3 p = Vec3::Zero();
    Vec3 dir = Vec3::UnitX();
    const int n = 1 + static_cast<int>(test::uniform(rng, 0, 6));
    for (int k = 0; k < n; ++k) {
      Move move;
      if (test::uniform(rng, 0, 1) < 0.5) {
        const double ang = test::uniform(rng, -3, 3);
        dir = Vec3(std::cos(ang), std::sin(ang), 0);
        move.geometry = Line{p, p + dir * log_uniform(rng, 1e-3, 0.2)};
      } else {
        const double r = log_uniform(rng, 2e-3, 0.1);
        const Vec3 perp = Vec3::UnitZ().cross(dir) * (test::uniform(rng, 0, 1) < 0.5 ? 1.0 : -1.0);
        const Arc arc{p - r * perp, perp, dir, r, test::uniform(rng, 0.1, 3.0), 0.0};
        move.geometry = arc;
        dir = tangent(arc, length(arc));
      }
      move.limits = {log_uniform(rng, 0.02, 1.0), log_uniform(rng, 0.2, 20.0), log_uniform(rng, 0.2, 20.0),
                     log_uniform(rng, 2.0, 2000.0)};
      move.buffer = static_cast<BufferMode>(static_cast<int>(test::uniform(rng, 0, 6)) % 6);
      p = end_point(to_segment(move.geometry));
      program.moves.push_back(move);
    }
    const Path path = blend(program);
    const Timing timing = plan_timing(path);
    expect_valid(path, timing, test::seed_text(seed));
    if (HasFailure()) return;
  }
}

}  // namespace
}  // namespace blendbench
