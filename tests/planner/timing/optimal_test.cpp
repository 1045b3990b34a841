// The optimal velocity planner (TimingOptions::Algorithm::kOptimal): closed forms it must meet,
// properties over random paths and every shipped scenario (never slower than seed 004's plan of
// the same path, never faster than the bound, every limit held on the sampled output, at rest at
// every stop), and an independent reference: the same problem on a 4x finer grid.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <numbers>
#include <optional>
#include <random>
#include <string>
#include <vector>

#include "blendbench/corner/blend.hpp"
#include "blendbench/io/scenario.hpp"
#include "blendbench/timing/timing.hpp"
#include "support/cam_program.hpp"
#include "support/input_error.hpp"
#include "support/profile_check.hpp"
#include "support/property.hpp"
#include "support/shipped_scenarios.hpp"
#include "support/source_tree.hpp"
#include "support/timing_paths.hpp"

namespace blendbench {
namespace {

using Algorithm = TimingOptions::Algorithm;

// The share by which the optimum on the planner's grid may exceed a closed form or lose to a
// feasible plan (the issue allows 0.1 % for the grid).
constexpr double kGridShare = 1e-3;

Timing plan_with(const Path& path, TimingOptions options, Algorithm algorithm) {
  options.algorithm = algorithm;
  return plan_timing(path, options);
}

// The least time of a jerk-limited rest-to-rest move of length L under v, a (= deceleration), j:
// the seven-phase S-curve, with the feed or the acceleration not reached where L or v is short
// for them (closed forms of the symmetric profile).
double scurve_time(double L, double v, double a, double j) {
  // the peak speed a length allows: v_p (v_p/a + a/j) = L once v_p >= a^2/j, else 2 v_p sqrt(v_p/j) = L
  const auto ramp_distance = [&](double vp) { return vp >= a * a / j ? vp * (vp / a + a / j) : 2 * vp * std::sqrt(vp / j); };
  const auto ramp_time = [&](double vp) { return vp >= a * a / j ? vp / a + a / j : 2 * std::sqrt(vp / j); };
  if (ramp_distance(v) <= L) return (L - ramp_distance(v)) / v + 2 * ramp_time(v);
  double vp = 0.5 * a * (-a / j + std::sqrt(a * a / (j * j) + 4 * L / a));
  if (vp < a * a / j) vp = std::cbrt(L * L * j / 4);
  return 2 * ramp_time(vp);
}

Path line_path(double length, const Limits& limits) {
  Path path;
  path.append(PathPiece{Line{{0, 0, 0}, {length, 0, 0}}, 0, -1, limits, BufferMode::kBlendingLow});
  return path;
}

// v = 0 (within a jerk-limited arrival, J dt^2 / 2) on the samples around every stop: stop_before,
// every junction in the exact-stop baseline, only Buffered kinks in the junction slow-down.
void expect_rest_at_stops(const Path& path, const Timing& timing, TimingOptions::Baseline baseline,
                          const std::string& where) {
  using Baseline = TimingOptions::Baseline;
  const auto& x = timing.samples;
  const auto& pieces = path.pieces();
  for (std::size_t p = 1; p < pieces.size(); ++p) {
    const bool buffered_kink = pieces[p].kink_angle > 1e-9 && pieces[p - 1].buffer == BufferMode::kBuffered;
    const bool stop = baseline == Baseline::kExactStop || (baseline == Baseline::kNone ? pieces[p].stop_before : buffered_kink);
    if (!stop) continue;
    const double s = path.offset(p);
    const double jerk = std::max(path.pieces()[p - 1].limits.jerk, path.pieces()[p].limits.jerk);
    // plus the time for which the motion from rest (j t^3 / 6) stays below the rounding of s
    const double lag = std::cbrt(6 * 4 * test::kEps * std::max(s, 1e-300) / jerk);
    const double bound = 0.5 * jerk * (timing.dt + lag) * (timing.dt + lag) * (1 + 1e-9);
    const auto past = std::upper_bound(x.begin(), x.end(), s, [](double q, const TimedSample& a) { return q < a.s; });
    if (past != x.begin()) {
      EXPECT_LE(std::prev(past)->v, bound) << where << " stop before piece " << p;
    }
    if (past != x.end()) {
      EXPECT_LE(past->v, bound) << where << " stop before piece " << p;
    }
  }
}

// v <= the feed of the pieces (or hand-over zones) at every sample.
void expect_within_feed(const Path& path, const Timing& timing, const TimingOptions& options, const std::string& where) {
  const std::vector<HandoverZone> zones = handover_zones(path, options);
  for (const TimedSample& q : timing.samples) {
    EXPECT_LE(q.v, limits_at(path, q.s, zones).feed * (1 + 1e-9)) << where << " s=" << q.s;
  }
}

// The path with the curvature steps at every junction allowed (curvature_steps: allow).
Path with_steps_allowed(const Path& path) {
  Path out;
  for (PathPiece piece : path.pieces()) {
    piece.curvature_step_allowed = true;
    out.append(piece);
  }
  return out;
}

// The largest third difference of the sampled x, y, z over the jerk limit on the stencils that
// cross a limited curvature step (a tangent junction where the curvature vector jumps and the
// piece after it does not allow it): the vector jerk at the step, tangential part included.
double jerk_across_limited_steps(const Path& path, const Timing& timing) {
  const auto& x = timing.samples;
  const auto& pieces = path.pieces();
  const double dt = timing.dt;
  double worst = 0;
  for (std::size_t p = 1; p < pieces.size(); ++p) {
    const Segment& a = pieces[p - 1].segment;
    const Segment& b = pieces[p].segment;
    if (pieces[p].curvature_step_allowed || angle_between(tangent(a, length(a)), tangent(b, 0.0)) > 1e-9) continue;
    if (!((curvature_vector(a, length(a)) - curvature_vector(b, 0.0)).norm() > 1e-9)) continue;
    const double s = path.offset(p);
    const double jerk = std::max(pieces[p - 1].limits.jerk, pieces[p].limits.jerk);
    const auto it = std::upper_bound(x.begin(), x.end(), s, [](double q, const TimedSample& t) { return q < t.s; });
    const auto k = static_cast<std::size_t>(it - x.begin());
    for (std::size_t k0 = k >= 3 ? k - 3 : 0; k0 + 3 < x.size() && k0 < k; ++k0) {
      const Vec3 j = (path.point(x[k0 + 3].s) - 3 * path.point(x[k0 + 2].s) + 3 * path.point(x[k0 + 1].s) -
                      path.point(x[k0].s)) / (dt * dt * dt);
      worst = std::max(worst, j.norm() / jerk);
    }
  }
  return worst;
}

TEST(OptimalTiming, ALineFromRestToRestIsTheExactScurve) {
  // feed reached (with and without the acceleration reached) and not reached
  struct Case {
    double length, v, a, j;
  };
  for (const Case c : {Case{1.0, 0.5, 2.0, 20.0}, Case{0.3, 0.25, 2.5, 50.0}, Case{0.02, 0.25, 2.5, 50.0},
                       Case{0.002, 0.25, 2.5, 50.0}, Case{0.5, 0.1, 5.0, 20.0}}) {
    const Path path = line_path(c.length, {c.v, c.a, c.a, c.j});
    for (const LimitsMode mode : {LimitsMode::kCartesian, LimitsMode::kPath}) {
      TimingOptions options;
      options.limits = mode;
      const Timing timing = plan_with(path, options, Algorithm::kOptimal);
      const double exact = scurve_time(c.length, c.v, c.a, c.j);
      const std::string where = "L=" + std::to_string(c.length) + " v=" + std::to_string(c.v);
      EXPECT_TRUE(timing.outcome.ok()) << where << ": " << timing.outcome.message;
      EXPECT_GE(timing.cycle_time, exact * (1 - 1e-9)) << where;
      EXPECT_LE(timing.cycle_time, exact * (1 + kGridShare)) << where;
      (void)test::expect_valid(path, timing, where, options);
    }
  }
}

TEST(OptimalTiming, TheDefaultScenariosExactStopIsNineScurves) {
  // nine lines from rest to rest, each long enough to reach 250 mm/s:
  // sum L / v + 9 (v / a + a / j) = 5.360 s
  const Limits limits{0.25, 2.5, 2.5, 50.0};
  const std::vector<Vec3> points = {{0, 0, 0},        {0.03, 0.06, 0}, {0, 0.12, 0},   {0.03, 0.18, 0}, {0, 0.24, 0},
                                    {0.03, 0.30, 0}, {0, 0.36, 0},    {0.12, 0.36, 0}, {0.12, 0, 0},   {0, 0, 0}};
  Path path;
  double length = 0;
  for (std::size_t k = 0; k + 1 < points.size(); ++k) {
    PathPiece piece{Line{points[k], points[k + 1]}, static_cast<int>(k), -1, limits, BufferMode::kBlendingLow};
    piece.stop_before = k > 0;
    path.append(piece);
    length += (points[k + 1] - points[k]).norm();
  }
  const double exact = length / 0.25 + 9 * (0.25 / 2.5 + 2.5 / 50.0);
  EXPECT_NEAR(exact, 5.360, 5e-4);
  const Timing timing = plan_with(path, {}, Algorithm::kOptimal);
  EXPECT_TRUE(timing.outcome.ok()) << timing.outcome.message;
  EXPECT_GE(timing.cycle_time, exact * (1 - 1e-9));
  EXPECT_LE(timing.cycle_time, exact * (1 + kGridShare));
  expect_rest_at_stops(path, timing, TimingOptions::Baseline::kNone, "exact stop");
  (void)test::expect_cartesian_valid(path, timing, std::nullopt, "exact stop");
}

TEST(OptimalTiming, AnArcWithItsCurvatureStepsAllowedRunsAtTheFeed) {
  // line, quarter circle, line; the steps allowed: the feed is held through the arc (its normal
  // acceleration v^2 / r = 0.2 and jerk v^3 / r^2 = 0.4 far below the limits), so the time is
  // the S-curve of the whole length
  const Limits limits{0.1, 2.5, 2.5, 50.0};
  const double r = 0.05;
  Path path;
  path.append(PathPiece{Line{{-0.1, 0, 0}, {0, 0, 0}}, 0, -1, limits, BufferMode::kBlendingLow});
  PathPiece arc{Arc{{0, r, 0}, {0, -1, 0}, {1, 0, 0}, r, 0.5 * std::numbers::pi, 0.0}, -1, 0, limits, BufferMode::kBlendingLow};
  arc.curvature_step_allowed = true;
  path.append(arc);
  PathPiece out{Line{{r, r, 0}, {r, r + 0.1, 0}}, 1, -1, limits, BufferMode::kBlendingLow};
  out.curvature_step_allowed = true;
  path.append(out);
  const double exact = scurve_time(path.length(), 0.1, 2.5, 50.0);
  const Timing timing = plan_with(path, {}, Algorithm::kOptimal);
  EXPECT_TRUE(timing.outcome.ok()) << timing.outcome.message;
  EXPECT_GE(timing.cycle_time, exact * (1 - 1e-9));
  EXPECT_LE(timing.cycle_time, exact * (1 + kGridShare));
  (void)test::expect_cartesian_valid(path, timing, std::nullopt, "arc, steps allowed");
}

// Case i of the random-path property below: its path (every curvature step allowed: seed 004's
// plan is then feasible under the optimal plan's rules; under `limit` it is not, its third
// differences reading up to 1.13 J across a step, which the optimal plan holds to J; the
// scenarios' test below compares those) and the options the case's index chooses.
struct RandomCase {
  std::string where;
  Path path;
  TimingOptions options;
};
// (`offset`: the seed offset to replay a case found at another BLENDBENCH_PROPERTY_SEED)
RandomCase random_case(int i, std::optional<std::uint64_t> offset = std::nullopt) {
  const auto seed = static_cast<std::uint64_t>(43000000 + i);
  auto rng = offset ? std::mt19937_64(seed + *offset) : test::make_rng(seed);
  RandomCase c{test::seed_text(seed), with_steps_allowed(test::random_path(rng)), TimingOptions{}};
  c.options.baseline = static_cast<TimingOptions::Baseline>(i % 3);
  c.options.limits = i % 4 == 3 ? LimitsMode::kPath : LimitsMode::kCartesian;
  if (c.options.limits == LimitsMode::kCartesian && i % 2 == 1) {
    c.options.axis_limits = AxisLimits{};
    for (int a = 0; a < 3; ++a) {
      c.options.axis_limits->acceleration[a] = test::log_uniform(rng, 0.1, 50.0);
      c.options.axis_limits->jerk[a] = test::log_uniform(rng, 1.0, 5000.0);
    }
  }
  return c;
}

TEST(OptimalTiming, PropertyRandomPathsNeverLoseToSeed004AndHoldEveryLimit) {
  // 40 cases by default (about 30 s: each case plans twice and checks every sample); 300 pass
  // with BLENDBENCH_PROPERTY_CASES=300 (measured at the commit that added this test)
  const int cases = test::property_cases(40);
  double worst_ratio = 0;  // optimal / seed004
  double best_ratio = 2;
  for (int i = 0; i < cases; ++i) {
    const RandomCase c = random_case(i);
    const Path& path = c.path;
    const TimingOptions& options = c.options;
    const std::string& where = c.where;
    const Timing optimal = plan_with(path, options, Algorithm::kOptimal);
    const Timing seed004 = plan_with(path, options, Algorithm::kSeed004);
    EXPECT_TRUE(optimal.outcome.ok()) << where << ": " << optimal.outcome.message;
    EXPECT_EQ(optimal.algorithm, Algorithm::kOptimal);
    EXPECT_LE(optimal.cycle_time, seed004.cycle_time * (1 + kGridShare)) << where;
    // the bound holds the axis limits through effective_vector_limits (cartesian.hpp), a scalar
    // vector limit per piece that is tighter than the components the optimal plan holds on a
    // curve: with axis limits it is no bound for this planner (seed 43000109: 4.124 s < 4.244 s)
    if (!options.axis_limits) {
      EXPECT_GE(optimal.cycle_time, optimal.bound_cycle_time * (1 - 1e-9)) << where;
    }
    ASSERT_EQ(optimal.pieces.size(), path.pieces().size()) << where;
    EXPECT_GE(optimal.feed_share, 0.0) << where;
    EXPECT_LE(optimal.feed_share, 1.0) << where;
    if (options.limits == LimitsMode::kPath) {
      (void)test::expect_valid(path, optimal, where + " path mode", options);
    } else {
      (void)test::expect_cartesian_valid(path, optimal, options.axis_limits, where);
      expect_within_feed(path, optimal, options, where);
      expect_rest_at_stops(path, optimal, options.baseline, where);
    }
    if (seed004.cycle_time > 0) {
      worst_ratio = std::max(worst_ratio, optimal.cycle_time / seed004.cycle_time);
      best_ratio = std::min(best_ratio, optimal.cycle_time / seed004.cycle_time);
    }
  }
  std::printf("optimal / seed004 over %d random paths: %.6f .. %.6f\n", cases, best_ratio, worst_ratio);
  // the optimiser gains somewhere (so the comparison can fail the other way too)
  EXPECT_LT(best_ratio, 0.99);
}

TEST(OptimalTiming, AStretchTheGridCannotRepresentFallsBackToSeed004) {
  // case 390 of the property above (found with BLENDBENCH_PROPERTY_CASES=2000): the optimiser's
  // motion ran the last 0.1 mm, from a junction's near-zero speed bound to the end, as one
  // constant-jerk stop of 9e10 s, and sampling it at the servo period threw std::bad_alloc; such
  // a motion is not used, and the plan is seed 004's
  const RandomCase c = random_case(390);
  const Path& path = c.path;
  const std::string& where = c.where;
  const Timing optimal = plan_with(path, c.options, Algorithm::kOptimal);
  const Timing seed004 = plan_with(path, c.options, Algorithm::kSeed004);
  ASSERT_TRUE(optimal.outcome.ok()) << where << ": " << optimal.outcome.message;
  EXPECT_LE(optimal.cycle_time, seed004.cycle_time * (1 + kGridShare)) << where;
  EXPECT_GE(optimal.cycle_time, optimal.bound_cycle_time * (1 - 1e-9)) << where;
  (void)test::expect_cartesian_valid(path, optimal, std::nullopt, where);
  expect_rest_at_stops(path, optimal, c.options.baseline, where);
}

TEST(OptimalTiming, TheMeanSpeedOverEveryPeriodHoldsTheFeed) {
  // case 1655 of the property above (path mode; found with BLENDBENCH_PROPERTY_CASES=2000): every
  // sample's speed held the feed, but the motion bulged above it between two samples, and their
  // first difference read 0.433437 m/s against the feed's 0.433436; the planner now checks the
  // first differences too (as it did the second and third)
  const RandomCase c = random_case(1655);
  const Path& path = c.path;
  const std::string& where = c.where;
  const Timing optimal = plan_with(path, c.options, Algorithm::kOptimal);
  ASSERT_TRUE(optimal.outcome.ok()) << where << ": " << optimal.outcome.message;
  (void)test::expect_valid(path, optimal, where + " path mode", c.options);
}

TEST(OptimalTiming, EveryShippedScenarioVariantIsAtMostSeed004sAndHoldsItsLimits) {
  int profiles = 0;
  std::size_t variant_index = 0;
  double seed004_step_jerk = 0;  // seed 004's worst, measured: the step check can fail
  for (const std::filesystem::path& file : test::scenarios_to_plan()) {
    const Scenario sc = load_scenario(file.string());
    for (const Variant& v : sc.variants) {
      // a sample under the sanitizers, where one optimal plan costs ~30x Release's (597 s for a
      // quarter of the variants, measured)
      if (!test::property_sample(variant_index++, 4)) continue;
      const Path path = blend(program_for(sc, v));
      const TimingOptions options = timing_options(sc, v);
      const std::string where = file.filename().string() + " / " + v.name;
      const Timing optimal = plan_with(path, options, Algorithm::kOptimal);
      const Timing seed004 = plan_with(path, options, Algorithm::kSeed004);
      EXPECT_TRUE(optimal.outcome.ok()) << where << ": " << optimal.outcome.message;
      // an optimum cannot lose to a feasible plan: seed 004's is one unless it breaks the vector
      // jerk across a limited curvature step (1.19 J at most, measured), which the optimal plan
      // holds; there it may be slower (the default's arc_0.5mm was, 6.037 s against 5.999 s, before
      // the grid's spacing at low speed; now 5.991 s)
      const bool seed004_feasible =
          options.limits == LimitsMode::kPath || jerk_across_limited_steps(path, seed004) <= 1 + 1e-6;
      if (seed004_feasible) {
        EXPECT_LE(optimal.cycle_time, seed004.cycle_time * (1 + kGridShare)) << where;
      }
      EXPECT_GE(optimal.cycle_time, optimal.bound_cycle_time * (1 - 1e-9)) << where;
      if (options.limits == LimitsMode::kPath) {
        (void)test::expect_valid(path, optimal, where, options);
      } else {
        (void)test::expect_cartesian_valid(path, optimal, options.axis_limits, where);
        expect_within_feed(path, optimal, options, where);
        expect_rest_at_stops(path, optimal, options.baseline, where);
        // the vector jerk across a limited curvature step, tangential part included
        EXPECT_LE(jerk_across_limited_steps(path, optimal), 1 + 1e-6) << where;
        seed004_step_jerk = std::max(seed004_step_jerk, jerk_across_limited_steps(path, seed004));
      }
      std::printf("%-40s seed004 %.4f s  optimal %.4f s  bound %.4f s\n", where.c_str(), seed004.cycle_time,
                  optimal.cycle_time, optimal.bound_cycle_time);
      ++profiles;
    }
  }
  EXPECT_GT(profiles, test::property_cases(20));
  std::printf("seed004's largest vector jerk across a limited curvature step: %.4f J\n", seed004_step_jerk);
  // where every variant was checked (a sample may miss those that show it)
  if (static_cast<std::size_t>(profiles) == variant_index) {
    EXPECT_GT(seed004_step_jerk, 1.05);
  }
}

// A stretch of more than TimingOptions::local_refinement_nodes nodes is solved once and what its
// samples exceed is taken by local slow-downs of the motion, where a shorter one is solved again
// with the cells there tightened. Both hold every limit on the sampled output; the slow-downs
// cost no more than the re-solves (they can cost less: a re-solve tightens whole cells).

// `n` lines of 0.01-0.1 mm along a smooth curve (bench_cam's CAM contour, shorter), every corner
// a biclothoid of 0.05 mm: one stretch, some 4.7 grid nodes a line.
Path cam_path(int n) { return blend(test::cam_program(n)); }

// A plan of cam_path(300): planned, every limit held on its samples, no stretch on seed 004's motion.
void expect_cam_plan_valid(const Path& path, const Timing& t) {
  EXPECT_TRUE(t.outcome.ok()) << t.outcome.message;
  (void)test::expect_cartesian_valid(path, t, std::nullopt, "cam_path(300)");
  EXPECT_EQ(t.seed004_stretches, 0);
}

TEST(OptimalTiming, LocalSlowDownsOnALongStretchHoldEveryLimitAndCostNoMoreThanReSolves) {
  const Path path = cam_path(300);
  TimingOptions options;
  options.dt = 2e-3;
  options.local_refinement_nodes = std::numeric_limits<std::size_t>::max();
  const Timing resolved = plan_with(path, options, Algorithm::kOptimal);
  options.local_refinement_nodes = 500;
  const Timing local = plan_with(path, options, Algorithm::kOptimal);
  const Timing seed004 = plan_with(path, options, Algorithm::kSeed004);
  for (const Timing* t : {&resolved, &local}) {
    expect_cam_plan_valid(path, *t);
    expect_within_feed(path, *t, options, "cam_path(300)");
  }
  std::printf("300 CAM lines: re-solved %.5f s, slowed locally %.5f s, seed004 %.5f s\n", resolved.cycle_time,
              local.cycle_time, seed004.cycle_time);
  EXPECT_LE(local.cycle_time, resolved.cycle_time * (1 + kGridShare));
  EXPECT_GE(local.cycle_time, resolved.cycle_time * (1 - kGridShare));
  EXPECT_LT(local.cycle_time, 0.8 * seed004.cycle_time);
}

TEST(OptimalTiming, ALongStretchEvaluatedOnTwoThreadsPlansAsOnOne) {
  // the 300-line CAM path (some 1400 cells) with the two-thread evaluation from 64 cells on,
  // against one thread: the halves change only the order of the sums, so the plans agree to
  // the solver's tolerance, and both hold every limit (the threads write disjoint derivatives:
  // the sanitizer build runs this too)
  const Path path = cam_path(300);
  TimingOptions options;
  options.dt = 2e-3;
  options.parallel_cells = std::numeric_limits<std::size_t>::max();
  const Timing one = plan_with(path, options, Algorithm::kOptimal);
  options.parallel_cells = 64;
  const Timing two = plan_with(path, options, Algorithm::kOptimal);
  for (const Timing* t : {&one, &two}) expect_cam_plan_valid(path, *t);
  std::printf("300 CAM lines: one thread %.9f s, two %.9f s\n", one.cycle_time, two.cycle_time);
  EXPECT_NEAR(two.cycle_time, one.cycle_time, 1e-4 * one.cycle_time);
}

TEST(OptimalTiming, PropertyLocalSlowDownsHoldEveryLimitOnRandomPaths) {
  // every stretch of more than 8 nodes slowed locally: the same checks as on the re-solved plans
  // (20 cases, about 13 s; 40 measured 0.967 .. 1.005 against the re-solves)
  const int cases = test::property_cases(20);
  double worst = 0;  // local / re-solved
  double best = 2;
  std::string worst_where;
  for (int i = 0; i < cases; ++i) {
    const auto seed = static_cast<std::uint64_t>(43200000 + i);
    auto rng = test::make_rng(seed);
    const Path path = with_steps_allowed(test::random_path(rng));
    TimingOptions options;
    options.baseline = static_cast<TimingOptions::Baseline>(i % 3);
    const std::string where = test::seed_text(seed);
    const Timing resolved = plan_with(path, options, Algorithm::kOptimal);
    options.local_refinement_nodes = 8;
    const Timing local = plan_with(path, options, Algorithm::kOptimal);
    const Timing seed004 = plan_with(path, options, Algorithm::kSeed004);
    EXPECT_TRUE(local.outcome.ok()) << where << ": " << local.outcome.message;
    EXPECT_LE(local.cycle_time, seed004.cycle_time * (1 + kGridShare)) << where;
    EXPECT_GE(local.cycle_time, local.bound_cycle_time * (1 - 1e-9)) << where;
    (void)test::expect_cartesian_valid(path, local, std::nullopt, where);
    expect_within_feed(path, local, options, where);
    expect_rest_at_stops(path, local, options.baseline, where);
    if (resolved.cycle_time > 0) {
      const double ratio = local.cycle_time / resolved.cycle_time;
      if (ratio > worst) worst_where = where;
      worst = std::max(worst, ratio);
      best = std::min(best, ratio);
    }
  }
  std::printf("slowed locally / re-solved over %d random paths: %.6f .. %.6f\n", cases, best, worst);
  // the slow-downs cost little where they are used (a long stretch, and small excesses: a first
  // solve far off is re-solved, kLeastLocalScale)
  EXPECT_LE(worst, 1.01) << "the worst: " << worst_where;
}

// Case `index` of the property above at BLENDBENCH_PROPERTY_SEED=`offset` (the seed without the
// environment, so the case replays as found): its path and options, as the property makes them.
struct PropertyCase {
  Path path;
  TimingOptions options;
  std::string name;
};
PropertyCase property_case(int index, std::uint64_t offset) {
  std::mt19937_64 rng(43200000 + static_cast<std::uint64_t>(index) + offset);
  PropertyCase out{with_steps_allowed(test::random_path(rng)), {}, "case " + std::to_string(index)};
  out.options.baseline = static_cast<TimingOptions::Baseline>(index % 3);
  return out;
}
// A plan of the case that succeeded and holds every limit.
void expect_case_plan_valid(const PropertyCase& c, const Timing& t) {
  ASSERT_TRUE(t.outcome.ok()) << c.name << ": " << t.outcome.message;
  (void)test::expect_cartesian_valid(c.path, t, std::nullopt, c.name);
  expect_within_feed(c.path, t, c.options, c.name);
}
// The case's usual plan and its plan with every stretch slowed locally (as the property plans
// them), both valid.
std::pair<Timing, Timing> usual_and_local(const PropertyCase& c) {
  TimingOptions local = c.options;
  local.local_refinement_nodes = 8;
  std::pair<Timing, Timing> out{plan_with(c.path, c.options, Algorithm::kOptimal), plan_with(c.path, local, Algorithm::kOptimal)};
  expect_case_plan_valid(c, out.first);
  expect_case_plan_valid(c, out.second);
  return out;
}
// Case 180 at 91000000 (found with 300 cases): a random path of 10 pieces whose third stretch has
// 3786 nodes and crawls at 0.7 mm/s near a junction's tiny speed bound.

TEST(OptimalTiming, AReSolveThatStallsKeepsTheLastMotion) {
  // every stretch re-solved where its samples exceed a limit: the long stretch's re-solve, on
  // the tightened and split cells, stalls before its equalities hold; it fell back to seed 004's
  // motion (7.886 s in all, seed004_stretches 1), and now keeps its last motion, settled (as the
  // default plan, which slows that stretch locally, does), holding every limit
  PropertyCase c = property_case(180, 91000000);
  const Timing usual = plan_with(c.path, c.options, Algorithm::kOptimal);
  c.options.local_refinement_nodes = std::numeric_limits<std::size_t>::max();
  const Timing resolved = plan_with(c.path, c.options, Algorithm::kOptimal);
  expect_case_plan_valid(c, resolved);
  std::printf("every stretch re-solved %.6f s (%d on seed 004's motion), as usual %.6f s\n", resolved.cycle_time,
              resolved.seed004_stretches, usual.cycle_time);
  EXPECT_EQ(resolved.seed004_stretches, 0);
  EXPECT_LE(resolved.cycle_time, 1.001 * usual.cycle_time);
}

TEST(OptimalTiming, AKeptMotionIsSlowedLocally) {
  // case 177 of PropertyLocalSlowDowns... at BLENDBENCH_PROPERTY_SEED=92000000: a stretch of
  // 2104 nodes (under local_refinement_nodes) re-solved once, then stalled on its second re-solve
  // and kept its last motion, whose samples still exceeded the jerk limit where the re-solves
  // were meant to mend it; slowed uniformly that motion took 2.180 s (seed 004's 2.309 s), with
  // local slow-downs 1.732 s, as when every stretch is slowed locally
  const auto [usual, local] = usual_and_local(property_case(177, 92000000));
  std::printf("as usual %.6f s, every stretch slowed locally %.6f s\n", usual.cycle_time, local.cycle_time);
  EXPECT_LE(usual.cycle_time, 1.01 * local.cycle_time);
}

TEST(OptimalTiming, AReSolvedStretchRunsNoSlowerThanItsFirstMotionSlowedLocally) {
  // cases 289 and 296 of PropertyLocalSlowDowns... at BLENDBENCH_PROPERTY_SEED=92000000: each
  // re-solve on the tightened cells made a stretch slower (case 296: a stretch of 48 nodes,
  // 0.720 s first, 1.010 s after four rounds), and the usual plan took 1.05 and 1.19 times as
  // long as the plan with every stretch slowed locally. The first solve's motion, slowed
  // locally, is a candidate beside the last.
  for (const int index : {289, 296}) {
    const auto [usual, local] = usual_and_local(property_case(index, 92000000));
    std::printf("case %d: as usual %.6f s, every stretch slowed locally %.6f s\n", index, usual.cycle_time,
                local.cycle_time);
    EXPECT_LE(usual.cycle_time, 1.01 * local.cycle_time) << "case " << index;
  }
}

TEST(OptimalTiming, LocalSlowDownsNeverCostMoreThanTheUniformOne) {
  // case 245 of PropertyLocalSlowDowns... at BLENDBENCH_PROPERTY_SEED=94000000: a stretch of 1248
  // nodes whose samples asked for 0.2 % of uniform slow-down; its 11 bumps, each wider than much
  // of the motion, stacked up to 3.4 % (1.462 s, the re-solved plan 1.415 s). The motion settled
  // uniformly is a candidate too.
  const auto [usual, local] = usual_and_local(property_case(245, 94000000));
  std::printf("as usual %.6f s, every stretch slowed locally %.6f s\n", usual.cycle_time, local.cycle_time);
  EXPECT_LE(local.cycle_time, 1.01 * usual.cycle_time);
}

TEST(OptimalTiming, TheSettleEndsWhereTheSamplesRespondSlowly) {
  // case 329 of PropertyRandomPaths... at BLENDBENCH_PROPERTY_SEED=96000000: a sample whose
  // ratio fell by a quarter of what each uniform slow-down predicted; with the extra share only
  // doubled it halved its excess each round and was 4.8e-10 over after the settle's 8 rounds, and
  // the plan failed. The extra now grows each round.
  const RandomCase c = random_case(329, 96000000);
  const Timing t = plan_with(c.path, c.options, Algorithm::kOptimal);
  ASSERT_TRUE(t.outcome.ok()) << c.where << ": " << t.outcome.message;
  (void)test::expect_cartesian_valid(c.path, t, c.options.axis_limits, c.where);
  expect_within_feed(c.path, t, c.options, c.where);
}

TEST(OptimalTiming, ASwitchToSeed004sMotionLeavesNoLaterStretchSlower) {
  // case 68 of PropertyLocalSlowDowns... at BLENDBENCH_PROPERTY_SEED=98000000: the first stretch
  // took seed 004's motion, the third then started 80 us sooner, and the plan's last settle found
  // its samples near a crawl far over a limit (1.663 s settled before, 1.932 s after, seed 004's
  // motion 1.672 s): the plan took 2.652 s against seed 004's 2.628 s. It is never slower.
  const PropertyCase c = property_case(68, 98000000);
  const Timing optimal = plan_with(c.path, c.options, Algorithm::kOptimal);
  const Timing seed004 = plan_with(c.path, c.options, Algorithm::kSeed004);
  expect_case_plan_valid(c, optimal);
  std::printf("optimal %.6f s, seed004 %.6f s\n", optimal.cycle_time, seed004.cycle_time);
  EXPECT_LE(optimal.cycle_time, seed004.cycle_time * (1 + kGridShare));
}

TEST(OptimalTiming, AfterItsFirstRoundTheSettleAddsLittleToWhatTheSamplesAsk) {
  // case 180: the long stretch asked 0.24 % of uniform slow-down, and then, on the slower
  // motion's samples, 1.2 % more at 0.7 mm/s; the settle doubled that share again and the plan
  // with every stretch slowed locally ran 1.0125 times as long as the usual one (whose re-solve
  // of a shorter stretch moved this one's samples to where they asked for less). With at most
  // kSettleExtra more than asked after the first round: 1.0067, every limit held.
  const auto [resolved, local] = usual_and_local(property_case(180, 91000000));
  std::printf("slowed locally %.6f s, re-solved %.6f s\n", local.cycle_time, resolved.cycle_time);
  EXPECT_LE(local.cycle_time, 1.01 * resolved.cycle_time);
  // case 122 of the same run: a sample whose jerk ratio falls by only half of what each slow-down
  // predicts; asked exactly (no extra), the settle was still 1.1e-7 over after its 8 rounds
  PropertyCase slow = property_case(122, 91000000);
  slow.options.local_refinement_nodes = 8;
  expect_case_plan_valid(slow, plan_with(slow.path, slow.options, Algorithm::kOptimal));
}

// The independent reference: the same problem on a grid 4x as dense, whose plan must hold every
// limit on its own samples too (a reference that broke one between its nodes could be faster for
// that reason alone).
void expect_agrees_with_finer_grid(const std::vector<std::pair<std::string, Path>>& paths, double share) {
  std::size_t index = 0;
  for (const auto& [name, path] : paths) {
    // under the sanitizers one path (this is a numerical reference, which the Release build
    // checks on every path; two paths at four times the grid took 205 s there, measured)
    if (!test::property_sample(index++, 8)) continue;
    TimingOptions options;
    options.dt = 2e-3;  // the default scenario's setpoint period
    const Timing coarse = plan_with(path, options, Algorithm::kOptimal);
    options.grid_refinement = 4;
    const Timing fine = plan_with(path, options, Algorithm::kOptimal);
    EXPECT_TRUE(coarse.outcome.ok()) << name << ": " << coarse.outcome.message;
    EXPECT_TRUE(fine.outcome.ok()) << name << ": " << fine.outcome.message;
    (void)test::expect_cartesian_valid(path, fine, std::nullopt, name + ", 4x finer");
    // the optimiser's motion on every stretch, on both grids (where a stretch falls back to seed
    // 004's plan the comparison measures that plan, not the grid: seed 43100002 did, below)
    EXPECT_EQ(coarse.seed004_stretches, 0) << name;
    EXPECT_EQ(fine.seed004_stretches, 0) << name;
    EXPECT_NEAR(coarse.cycle_time / fine.cycle_time, 1.0, share) << name;
    std::printf("%-28s grid %.5f s, 4x finer %.5f s (ratio %.5f)\n", name.c_str(), coarse.cycle_time, fine.cycle_time,
                coarse.cycle_time / fine.cycle_time);
  }
}

// The default scenario's blended variants, those at mixed parameters (its program with one
// variant per method at its own parameter, on which this reference was set up) and a few random
// paths.
std::vector<std::pair<std::string, Path>> reference_paths() {
  std::vector<std::pair<std::string, Path>> paths;
  for (const char* file : {"scenarios/mixed_parameters.yaml", "scenarios/default.yaml"}) {
    const Scenario sc = load_scenario(test::source_path(file));
    for (const Variant& v : sc.variants) {
      if (v.transition && v.transition->method != Method::kNone) paths.emplace_back(v.name, blend(program_for(sc, v)));
    }
  }
  for (int i = 0; i < 4; ++i) {
    const auto seed = static_cast<std::uint64_t>(43100000 + i);
    auto rng = test::make_rng(seed);
    paths.emplace_back(test::seed_text(seed), test::random_path(rng));
  }
  return paths;
}

// Measured at the commit that enabled every path here (ratio grid / 4x finer): 1.0001-1.0023, the
// largest near limited curvature steps (mixed_parameters arc_10mm 1.0023, default arc_0.5mm
// 1.0021, arc_2mm 1.0021, bezier_0.5mm 1.0021) and seed 43100002 1.0023.
//
// Before it (the node spacing a twelfth of A / J at every speed) these were open, grid against 4x
// finer: arc_10mm 6.0838 / 6.0281 s (0.92 %), arc_0.5mm 6.0366 / 5.9907 (0.77 %), arc_2mm 6.1202 /
// 6.0651 (0.91 %), bezier_0.5mm 4.8678 / 4.8338 (0.70 %), seed 43100002 2.8400 / 2.5346 (12 %).
// The cause was the same on all: near a junction's speed bound the profile runs slowly (20-50
// mm/s on the default scenario's arcs, whose limited curvature steps cap the junction speed), where
// its jerk phases last some sqrt(v / J), far less than the A / J the spacing assumed, so the grid
// there was too coarse for the profile (its optimum on its own grid 6.0380 s for arc_0.5mm before
// any refinement, against 5.9901 on the finer one; 9 cells per full jerk phase, 24
// linearisations and two refinement rounds). On seed 43100002 an arc of 3.7 mm under J = 2.7
// m/s^3 (A / J = 0.55 s, a 0.55 s / 12 spacing) between a limited curvature step (10.8 mm/s) and
// a pinned 135-degree kink is crossed at 10-20 mm/s in 0.3 s: it got 4 cells, on which the barrier
// method's first stretch never reached its equalities, so that stretch (1.74 s) fell back to seed
// 004's plan, and the next one's optimum on its grid lost to seed 004's by 0.8 % and fell back
// too. The finer plan was the right one: it holds every limit on its samples (checked above), and
// with the spacing at low speed (optimal_grid.cpp, kSlowPhase) both grids plan 2.48 s, the 4x
// finer one 2.2 % faster than the old 4x finer one.
TEST(OptimalTiming, AFourTimesFinerGridAgreesWithinHalfAPercent) { expect_agrees_with_finer_grid(reference_paths(), 5e-3); }

}  // namespace
}  // namespace blendbench

namespace blendbench {
namespace {

// A tool, not a check (run with --gtest_also_run_disabled_tests): the ratio of the optimal plan to
// the same problem on a 4x finer grid for every shipped scenario's variant (docs/timing.md).
TEST(OptimalTiming, DISABLED_PrintTheFinerGridRatioOfEveryShippedScenario) {
  for (const std::filesystem::path& file : test::shipped_scenarios()) {
    const Scenario sc = load_scenario(file.string());
    for (const Variant& v : sc.variants) {
      const Path path = blend(program_for(sc, v));
      TimingOptions options = timing_options(sc, v);
      const Timing coarse = plan_with(path, options, Algorithm::kOptimal);
      options.grid_refinement = 4;
      const Timing fine = plan_with(path, options, Algorithm::kOptimal);
      std::printf("| %s | %s | %.4f | %.4f | %.4f |\n", file.filename().string().c_str(), v.name.c_str(),
                  coarse.cycle_time, fine.cycle_time, coarse.cycle_time / fine.cycle_time);
    }
  }
}

}  // namespace
}  // namespace blendbench

namespace blendbench {
namespace {

TEST(OptimalTiming, TheScenarioKeyChoosesThePlannerAndAVariantOverridesIt) {
  const std::string head = "name: t\ndefaults: {velocity: 1, acceleration: 1, jerk: 1}\nprogram: {moves: [{line: [1, 0, 0]}]}\n";
  const std::string variants = "variants: [{name: a}, {name: b, timing: seed004}, {name: c, timing: optimal}]\n";
  const Scenario by_default = parse_scenario(head + variants, "t.yaml", ".");
  const Scenario optimal = parse_scenario("timing: optimal\n" + head + variants, "t.yaml", ".");
  const Scenario seed004 = parse_scenario("timing: seed004\n" + head + variants, "t.yaml", ".");
  // the default (optimal; docs/timing.md), and each variant's own over it
  EXPECT_EQ(timing_options(by_default, by_default.variants[0]).algorithm, Algorithm::kOptimal);
  EXPECT_EQ(timing_options(optimal, optimal.variants[0]).algorithm, Algorithm::kOptimal);
  EXPECT_EQ(timing_options(optimal, optimal.variants[1]).algorithm, Algorithm::kSeed004);
  EXPECT_EQ(timing_options(seed004, seed004.variants[0]).algorithm, Algorithm::kSeed004);
  EXPECT_EQ(timing_options(seed004, seed004.variants[2]).algorithm, Algorithm::kOptimal);
  // an unknown planner names the file, line and key
  (void)test::expect_input_error([&] { (void)parse_scenario("timing: fastest\n" + head + variants, "t.yaml", "."); },
                                 {.file = "t.yaml", .line = 1, .field = "timing", .message = "one of: optimal, seed004"});
  // and the names round-trip
  for (const Algorithm a : {Algorithm::kOptimal, Algorithm::kSeed004}) EXPECT_EQ(algorithm_from_string(algorithm_name(a)), a);
  EXPECT_FALSE(algorithm_from_string("fastest"));
}

}  // namespace
}  // namespace blendbench
