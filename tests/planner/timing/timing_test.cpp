#include "blendbench/timing/timing.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdio>
#include <string>

#include <gtest/gtest-spi.h>

#include "blendbench/corner/blend.hpp"
#include "blendbench/timing/scurve.hpp"
#include "support/input_error.hpp"
#include "support/profile_check.hpp"
#include "support/property.hpp"
#include "support/timing_paths.hpp"

namespace blendbench {
namespace {

constexpr double kFeedShareTol = 1e-9;
using test::expect_valid;
using test::kRel;
using test::Margins;
using test::random_path;
using test::velocities_around;

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
  EXPECT_EQ(timing.pieces[0].binding, Binding::kFeed);
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
  TimingOptions options;
  options.limits = LimitsMode::kPath;
  const Timing timing = plan_timing(path, options);
  ASSERT_EQ(timing.pieces.size(), 1u);
  EXPECT_EQ(timing.pieces[0].binding, Binding::kCurvature);
  EXPECT_NEAR(timing.pieces[0].v_peak, 0.1, 1e-12);
  EXPECT_EQ(timing.feed_share, 0.0);
  expect_valid(path, timing, "arc", options);
  // cartesian: the arc is planned for 0.8 of its highest constant speed (the acceleration bound
  // 0.1 m/s here, the jerk bound cbrt(j / kappa^2) = 0.46 m/s), where (C1) and (C2) are tight
  const Timing vector = plan_timing(path);
  EXPECT_NEAR(vector.pieces[0].v_peak, 0.08, 1e-12);
  EXPECT_GT(vector.cycle_time, timing.cycle_time);
  expect_valid(path, vector, "arc, cartesian");
  test::expect_cartesian_valid(path, vector, {}, "arc, cartesian");
}

TEST(Timing, NonPositiveServoPeriodIsAnInputError) {
  Program program;
  program.moves = {line_move({0, 0, 0}, {1, 0, 0}, {0.5, 2.0, 2.0, 20.0})};
  const Path path = blend(program);
  TimingOptions options;
  options.dt = 0;
  EXPECT_THROW((void)plan_timing(path, options), InputError);
}

TEST(Timing, ANonPositiveLimitIsAnInputErrorNamingThePieceAndTheValueInMm) {
  Program program;
  program.moves = {line_move({0, 0, 0}, {1, 0, 0}, {0.5, 2.0, 2.0, 20.0})};
  Path blended = blend(program);
  // plan_timing takes paths from elsewhere too: a piece whose jerk limit was lost
  Path path;
  PathPiece piece = blended.pieces().front();
  piece.limits.jerk = -20.0;
  path.append(piece);
  test::expect_input_error([&] { (void)plan_timing(path); },
                           {.field = "jerk", .message = "piece 0: jerk limit must be positive, got -20000 mm/s^3"});
}

// Bounded work: a plan of more samples than max_samples is refused before it is sampled, at
// the move whose limit makes it so long, naming that limit; never a float-to-integer overflow.
TEST(Timing, ATooLongPlanIsRefusedAtTheMoveNamingTheLimit) {
  Program program;
  program.moves = {line_move({0, 0, 0}, {0.1, 0, 0}, {0.5, 2.0, 2.0, 20.0}),
                   line_move({0.1, 0, 0}, {1.1, 0, 0}, {1e-9, 2.0, 2.0, 20.0})};
  program.moves[1].where = {"part.ngc", 4, 7};
  const Path path = blend(program);
  try {
    (void)plan_timing(path);
    FAIL() << "a plan of 1e12 samples was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "part.ngc");
    EXPECT_EQ(e.line(), 4);
    EXPECT_EQ(e.field(), "velocity");
    for (const char* part : {"the plan would take 1e+09 s = 1e+12 samples at 1 ms", "limit 1e+07 samples",
                             "raise `velocity` (1e-06 mm/s at line 4)"}) {
      EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
    }
  }
  // the limit is the option's: a 2.35 s line has 2351 samples
  Program line;
  line.moves = {line_move({0, 0, 0}, {1, 0, 0}, {0.5, 2.0, 2.0, 20.0})};
  const Path one = blend(line);
  TimingOptions options;
  options.max_samples = 2351;
  EXPECT_EQ(plan_timing(one, options).samples.size(), 2351u);
  options.max_samples = 2350;
  EXPECT_THROW((void)plan_timing(one, options), InputError);
  options.max_samples = 0.5;
  EXPECT_THROW((void)plan_timing(one, options), InputError);
}

TEST(Timing, LimitsNearTheSmallestDoublesAreRefusedNotSampled) {
  // velocity 1e-300 m/s: 1e300 s; 1e-306 m/s (the cycle time of 3e306 s once converted without
  // a range check); every limit 1e-300, on a line and on an arc (whose caps underflow)
  for (const double v : {1e-300, 3e-307}) {
    Program program;
    program.moves = {line_move({0, 0, 0}, {1, 0, 0}, {v, 2.0, 2.0, 20.0})};
    EXPECT_THROW((void)plan_timing(blend(program)), InputError) << v;
  }
  for (const LimitsMode mode : {LimitsMode::kPath, LimitsMode::kCartesian}) {
    Path path;
    path.append(PathPiece{Line{{0, 0, 0}, {1, 0, 0}}, 0, -1, {1e-300, 1e-300, 1e-300, 1e-300}});
    path.append(PathPiece{Arc{{1, 0.1, 0}, {0, -1, 0}, {1, 0, 0}, 0.1, 1.0, 0.0}, 1, -1, {1e-300, 1e-300, 1e-300, 1e-300}});
    TimingOptions options;
    options.limits = mode;
    try {
      const Timing timing = plan_timing(path, options);
      ADD_FAILURE() << "planned " << timing.samples.size() << " samples, cycle " << timing.cycle_time << " s";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("the plan would take"), std::string::npos) << e.what();
    }
  }
}

TEST(Timing, EmptyPathIsOneSampleAtRest) {
  const Timing timing = plan_timing(Path{});
  ASSERT_EQ(timing.samples.size(), 1u);
  EXPECT_EQ(timing.cycle_time, 0.0);
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
      const double len = test::log_uniform(rng, 1e-6, 0.5);
      const Vec3 q = p + dir * len;
      program.moves.push_back(line_move(p, q, {test::log_uniform(rng, std::max(1e-3, 0.5 * len), 2.0), test::log_uniform(rng, 0.1, 50.0),
                                               test::log_uniform(rng, 0.1, 50.0), test::log_uniform(rng, 1.0, 5000.0)}));
      p = q;
    }
    const Path path = blend(program);
    const Timing timing = plan_timing(path);
    expect_valid(path, timing, test::seed_text(seed));
    if (HasFailure()) return;
  }
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
  options.limits = LimitsMode::kPath;
  options.baseline = TimingOptions::Baseline::kExactStop;
  const Timing stop = plan_timing(path, options);
  expect_valid(path, stop, "exact stop", options);
  const double arc_cap = std::min(std::sqrt(2.0 * 0.05), std::cbrt(20.0 * 0.05 * 0.05));
  const double expected = 2 * plan_scurve(0.2, 0, 0, {0.5, 2.0, 2.0, 20.0}).curve.duration() +
                          plan_scurve(length(arc), 0, 0, {arc_cap, 2.0, 2.0, 20.0}).curve.duration();
  EXPECT_NEAR(stop.cycle_time, expected, 1e-12);
  for (double s : {0.2, 0.2 + length(arc)}) EXPECT_LE(velocities_around(stop, s).second, 0.5 * 20.0 * 1e-6 * (1 + kRel));
  options.baseline = TimingOptions::Baseline::kJunctionSlowdown;
  const Timing slowdown = plan_timing(path, options);
  expect_valid(path, slowdown, "slowdown", options);
  EXPECT_LT(slowdown.cycle_time, stop.cycle_time);
  options.baseline = TimingOptions::Baseline::kNone;
  EXPECT_NEAR(plan_timing(path, options).cycle_time, slowdown.cycle_time, 1e-12);
  // from the junction caps sqrt(j dt / kappa) = 0.032 m/s the arc is too short to reach
  // its cap sqrt(a / kappa) = 0.32 m/s
  EXPECT_EQ(slowdown.pieces[0].binding, Binding::kFeed);
  EXPECT_EQ(slowdown.pieces[1].binding, Binding::kLength);
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

// A planar G2 corner like a biclothoid fillet of seed 004 at F15000 (lines of 50 mm, two clothoids
// 0 -> 79/m -> 0 of sharpness 6700/m^2, 11.8 mm each; 0.25 m/s, 2.5 m/s^2, 50 m/s^3): the cap
// falls from cbrt(j/c) = 0.195 m/s at the line to 0.176 m/s at the apex (sharpness-bound).
Path clothoid_fillet() {
  const Limits lim{0.25, 2.5, 2.5, 50.0};
  const double c = 6700.0;
  const double len = 79.0 / c;
  Path path;
  path.append(PathPiece{Line{{-0.05, 0, 0}, {0, 0, 0}}, 0, -1, lim});
  const Segment in = Clothoid{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0.0, c, len};
  path.append(PathPiece{in, -1, 0, lim});
  const Vec3 t = tangent(in, len);
  const Segment out = Clothoid{end_point(in), t, Vec3(-t.y(), t.x(), 0), 79.0, -c, len};
  path.append(PathPiece{out, -1, 0, lim});
  const Vec3 p = end_point(out);
  path.append(PathPiece{Line{p, p + 0.05 * tangent(out, len)}, 1, -1, lim});
  return path;
}

TEST(Timing, ClothoidFilletCarriesAccelerationThroughItsSubIntervals) {
  const Path path = clothoid_fillet();
  ASSERT_NEAR((curvature_vector(path.pieces()[2].segment, 0.0) - curvature_vector(path.pieces()[1].segment, 79.0 / 6700.0)).norm(), 0.0, 1e-9);
  // path mode, seed 004's model (in cartesian mode the clothoids' tangential limits are a share of
  // the limits and the carried profile took 0.714 s against 0.710 s when measured)
  TimingOptions options;
  options.limits = LimitsMode::kPath;
  const Timing carried = plan_timing(path, options);
  expect_valid(path, carried, "carried", options);
  TimingOptions fine = options;
  fine.carry_acceleration = false;
  const Timing zero = plan_timing(path, fine);
  expect_valid(path, zero, "zero acceleration at knots", fine);
  // at the knots between the 16 sub-intervals of each clothoid the zero-acceleration method
  // has |a| <= j dt on the samples either side; the carried profile brakes (and speeds up)
  // through some of them
  const double j_dt = 50.0 * 1e-3;
  const auto largest_knot_acceleration = [&](const Timing& timing) {
    double largest = 0;
    for (std::size_t k : {1u, 2u}) {
      for (int i = 1; i < 16; ++i) {
        const double s = path.offset(k) + (path.offset(k + 1) - path.offset(k)) * i / 16;
        const auto after = std::lower_bound(timing.samples.begin(), timing.samples.end(), s,
                                            [](const TimedSample& x, double v) { return x.s < v; });
        largest = std::max(largest, std::min(std::abs(after->a), std::abs(std::prev(after)->a)));
      }
    }
    return largest;
  };
  EXPECT_LE(largest_knot_acceleration(zero), j_dt * (1 + kRel));
  EXPECT_GT(largest_knot_acceleration(carried), 0.2 * 2.5);
  // and the corner takes less time (0.690 s against 0.704 s when measured)
  EXPECT_LT(carried.cycle_time, zero.cycle_time * 0.99);
}

TEST(Timing, PropertyRandomPathsHoldEveryLimitInEveryMode) {
  // both limits modes; cartesian (the default) also as vectors and, every other case, under
  // random per-axis limits; path mode's vectors measured to show what the check would catch
  const int cases = test::property_cases(1000);
  Margins worst;
  test::CartesianMargins vector_worst;
  double path_mode_jerk = 0;
  for (int i = 0; i < cases; ++i) {
    const auto seed = static_cast<std::uint64_t>(5000000 + i);
    auto rng = test::make_rng(seed);
    const Path path = random_path(rng);
    TimingOptions options;
    options.baseline = static_cast<TimingOptions::Baseline>(i % 3);
    if (i % 2 == 1) {
      options.axis_limits = AxisLimits{};
      for (int a = 0; a < 3; ++a) {
        options.axis_limits->acceleration[a] = test::log_uniform(rng, 0.1, 50.0);
        options.axis_limits->jerk[a] = test::log_uniform(rng, 1.0, 5000.0);
      }
    }
    const Timing timing = plan_timing(path, options);
    const Margins m = expect_valid(path, timing, test::seed_text(seed), options);
    const test::CartesianMargins c = test::expect_cartesian_valid(path, timing, options.axis_limits, test::seed_text(seed));
    vector_worst = {std::max(vector_worst.a, c.a),       std::max(vector_worst.j, c.j),
                    std::max(vector_worst.axis_a, c.axis_a), std::max(vector_worst.axis_j, c.axis_j),
                    std::max(vector_worst.fd_a, c.fd_a), std::max(vector_worst.fd_j, c.fd_j)};
    // no plan beats the time-optimal bound of its mode
    EXPECT_GE(timing.cycle_time, timing.bound_cycle_time) << test::seed_text(seed);
    EXPECT_GT(timing.bound_cycle_time, 0.0) << test::seed_text(seed);
    worst = {std::max(worst.v, m.v), std::max(worst.a, m.a), std::max(worst.j, m.j), std::max(worst.normal, m.normal)};
    ASSERT_EQ(timing.pieces.size(), path.pieces().size()) << test::seed_text(seed);
    ASSERT_GE(timing.feed_share, 0.0);
    ASSERT_LE(timing.feed_share, 1.0);
    if (HasFailure()) return;
    // path mode on every fourth case: its bound, and its vectors measured
    if (i % 4 != 0) continue;
    TimingOptions tangential = options;
    tangential.limits = LimitsMode::kPath;
    tangential.axis_limits.reset();
    const Timing old = plan_timing(path, tangential);
    EXPECT_GE(old.cycle_time, old.bound_cycle_time) << test::seed_text(seed) << " path mode";
    (void)expect_valid(path, old, test::seed_text(seed) + " path mode", tangential);
    if (!HasFailure()) {
      ::testing::ScopedTrace quiet(__FILE__, __LINE__, "path mode, measured only");
      const test::CartesianMargins o = [&] {
        // measured, not asserted: path mode does not bound the vectors
        testing::TestPartResultArray ignored;
        testing::ScopedFakeTestPartResultReporter reporter(testing::ScopedFakeTestPartResultReporter::INTERCEPT_ONLY_CURRENT_THREAD, &ignored);
        return test::expect_cartesian_valid(path, old, {}, "");
      }();
      path_mode_jerk = std::max(path_mode_jerk, o.j);
    }
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
  std::printf("cartesian: |a| %.12f |j| %.12f axis a %.12f axis j %.12f fd |a| %.12f fd |j| %.12f; path mode |j| %.4f\n",
              vector_worst.a, vector_worst.j, vector_worst.axis_a, vector_worst.axis_j, vector_worst.fd_a,
              vector_worst.fd_j, path_mode_jerk);
  // the vector limits are used, and path mode breaks them (so the check can fail)
  EXPECT_GT(vector_worst.a, 0.999);
  EXPECT_GT(vector_worst.j, 0.999);
  EXPECT_GT(path_mode_jerk, 1.05);
}

TEST(Timing, PropertyRaisingALimitNeverSlowsTheCycle) {
  // every piece's limit of one kind raised by the same factor. With zero acceleration at every
  // knot the intervals keep their structure, so the knot velocities can only rise, and so can
  // every interval's speed. Carrying acceleration through knots chooses its spans from the caps,
  // which move with the limits, so its cycle time is only bounded by the zero-acceleration
  // method's before the raise. Path mode: in cartesian mode the shares of each budget that the
  // tangential limits get on a curve move with the limits (cartesian.hpp), so raising one can
  // shift time between changing speed and cruising there (34 of these 300 paths were slower,
  // by up to 3.5 %, when measured).
  const int cases = test::property_cases(300);
  TimingOptions fine;
  fine.carry_acceleration = false;
  fine.limits = LimitsMode::kPath;
  TimingOptions carried;
  carried.limits = LimitsMode::kPath;
  for (int i = 0; i < cases; ++i) {
    const auto seed = static_cast<std::uint64_t>(7000000 + i);
    auto rng = test::make_rng(seed);
    const Path path = random_path(rng);
    // hand-over zones shrink as the acceleration, deceleration or jerk grow (the slower move
    // reaches its velocity sooner, as PLCopen asks), so the property is for the modes without
    // zones: every Blending mode becomes Low
    Path low;
    for (PathPiece piece : path.pieces()) {
      if (piece.buffer != BufferMode::kBuffered) piece.buffer = BufferMode::kBlendingLow;
      low.append(std::move(piece));
    }
    const double before = plan_timing(low, fine).cycle_time;
    const int which = i % 4;
    const double factor = test::uniform(rng, 1.0, 3.0);
    Path raised;
    for (PathPiece piece : low.pieces()) {
      double* field[] = {&piece.limits.velocity, &piece.limits.acceleration, &piece.limits.deceleration,
                         &piece.limits.jerk};
      *field[which] *= factor;
      raised.append(std::move(piece));
    }
    ASSERT_LE(plan_timing(raised, fine).cycle_time, before * (1 + 1e-12))
        << test::seed_text(seed) << " limit " << which << " x" << factor;
    ASSERT_LE(plan_timing(raised, carried).cycle_time, before * (1 + 1e-12))
        << test::seed_text(seed) << " limit " << which << " x" << factor << ", carrying acceleration";
  }
}

TEST(Timing, PropertyCarryingAccelerationIsNeverSlower) {
  // each span is replaced by the zero-acceleration chain between its knot velocities where
  // that is faster, and a span end is lowered only where that chain would not reach higher
  // either; over random paths the profile is never slower than with zero acceleration at every
  // knot, and is faster on most
  const int cases = test::property_cases(1000);
  TimingOptions fine;
  fine.carry_acceleration = false;
  int faster = 0;
  for (int i = 0; i < cases; ++i) {
    const auto seed = static_cast<std::uint64_t>(5000000 + i);
    auto rng = test::make_rng(seed);
    const Path path = random_path(rng);
    const Timing carried = plan_timing(path);
    const Timing zero = plan_timing(path, fine);
    expect_valid(path, zero, test::seed_text(seed) + " zero acceleration at knots");
    ASSERT_LE(carried.cycle_time, zero.cycle_time * (1 + 1e-12)) << test::seed_text(seed);
    if (carried.cycle_time < zero.cycle_time * (1 - 1e-6)) ++faster;
    if (HasFailure()) return;
  }
  EXPECT_GT(faster, cases / 2);
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
        move.geometry = Line{p, p + dir * test::log_uniform(rng, 1e-3, 0.2)};
      } else {
        const double r = test::log_uniform(rng, 2e-3, 0.1);
        const Vec3 perp = Vec3::UnitZ().cross(dir) * (test::uniform(rng, 0, 1) < 0.5 ? 1.0 : -1.0);
        const Arc arc{p - r * perp, perp, dir, r, test::uniform(rng, 0.1, 3.0), 0.0};
        move.geometry = arc;
        dir = tangent(arc, length(arc));
      }
      move.limits = {test::log_uniform(rng, 0.02, 1.0), test::log_uniform(rng, 0.2, 20.0), test::log_uniform(rng, 0.2, 20.0),
                     test::log_uniform(rng, 2.0, 2000.0)};
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

// A glue bead round a rounded rectangle (scenarios/process/glue_bead_rounded_rectangle.yaml in
// SI): lines tangent to quarter arcs, method none. An exact stop stops only where the tangent
// turns, so the path runs through every tangent junction, slowed there only by the curvature
// step's rule (sqrt(j dt / kappa)); one real kink added at the end still stops.
TEST(Timing, AnExactStopDoesNotStopAtTangentJunctions) {
  const Limits lim{0.1, 2.5, 2.5, 50.0};
  const double r = 0.02, w = 0.16, h = 0.1;
  const auto arc_move = [&](const Vec3& center, const Vec3& u) {
    Move m;
    m.geometry = Arc{center, u, Vec3::UnitZ().cross(u), r, M_PI / 2, 0.0};
    m.limits = lim;
    m.transition.method = Method::kNone;
    return m;
  };
  Program program;
  program.moves = {line_move({r, 0, 0}, {w - r, 0, 0}, lim),     arc_move({w - r, r, 0}, -Vec3::UnitY()),
                   line_move({w, r, 0}, {w, h - r, 0}, lim),     arc_move({w - r, h - r, 0}, Vec3::UnitX()),
                   line_move({w - r, h, 0}, {r, h, 0}, lim),     arc_move({r, h - r, 0}, Vec3::UnitY()),
                   line_move({0, h - r, 0}, {0, r, 0}, lim),     arc_move({r, r, 0}, -Vec3::UnitX()),
                   line_move({r, 0, 0}, {r, -0.05, 0}, lim)};  // a 90 degree kink: a real corner
  for (Move& m : program.moves) m.transition.method = Method::kNone;
  const Path path = blend(program);
  ASSERT_EQ(path.pieces().size(), program.moves.size());
  TimingOptions options;
  options.dt = 2e-3;
  const Timing timing = plan_timing(path, options);
  expect_valid(path, timing, "rounded rectangle", options);
  const double cap = std::sqrt(lim.jerk * options.dt * r);  // 0.0447 m/s at kappa = 1 / r
  for (std::size_t k = 1; k + 1 < path.pieces().size(); ++k) {
    EXPECT_FALSE(path.pieces()[k].stop_before) << "junction " << k;
    EXPECT_EQ(path.corners[k - 1].corner_case, CornerCase::kTangent) << "junction " << k;
    const double v = velocities_around(timing, path.offset(k)).first;
    EXPECT_GT(v, 0.9 * cap) << "junction " << k << " at s = " << path.offset(k);
    // the sample nearest the junction is within a setpoint period of it: a dt more speed at most
    EXPECT_LT(v, cap + lim.acceleration * options.dt) << "the curvature step's rule holds at junction " << k;
  }
  const std::size_t kink = path.pieces().size() - 1;
  EXPECT_TRUE(path.pieces()[kink].stop_before);
  EXPECT_EQ(path.corners[kink - 1].corner_case, CornerCase::kExactStop);
  // at rest between two samples: within half a jerk-limited period of it
  EXPECT_LT(velocities_around(timing, path.offset(kink)).first, 0.5 * lim.jerk * options.dt * options.dt);
}

}  // namespace
}  // namespace blendbench
