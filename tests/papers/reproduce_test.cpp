#include "blendbench/core/units.hpp"
#include "blendbench/papers/reproduce.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "blendbench/core/input_error.hpp"
#include "blendbench/timing/scurve.hpp"
#include "support/scratch.hpp"

namespace blendbench {
namespace {

// Where the reports claim agreement with the paper, the tolerances they claim.
constexpr double kTable1Feed = 0.002;    // relative: the paper evaluates eq. 26 with rounded c, kappa
constexpr double kTable2Feed = 0.001;    // relative
constexpr double kCycleTime = 0.015;     // relative: planned vs the machine's measured biclothoid runs
constexpr double kExactStop000 = 0.05;   // relative: our comparable program vs the paper's total
constexpr double kRatio000 = 0.10;       // relative: with/without ratio, tangential limits only
constexpr double kPathLevel = 1 + 1e-9;  // the planner's contract: no limit exceeded by more than 1e-9 relative
// relative: the optimal planner against seed 004's on the same path (issue 43's allowance for the
// optimiser's grid)
constexpr double kOptimalSlack = 1e-3;

// The reproductions run once per test program (about a second each).
const Paper004& paper004() {
  static const Paper004 r = reproduce_004();
  return r;
}

const Paper000& paper000() {
  static const Paper000 r = reproduce_000();
  return r;
}

// Both plans of a run, seed 004's and the optimal planner's.
void expect_path_level_limits_hold(const PlannedRun& run) {
  for (const auto& [m, planner] : {std::pair{&run.margins, "seed004"}, std::pair{&run.optimal_margins, "optimal"}}) {
    EXPECT_LE(m->velocity, kPathLevel) << run.name << " " << planner;
    EXPECT_LE(m->tangential_acceleration, kPathLevel) << run.name << " " << planner;
    EXPECT_LE(m->tangential_jerk, kPathLevel) << run.name << " " << planner;
    EXPECT_LE(m->normal_acceleration, kPathLevel) << run.name << " " << planner;
    EXPECT_LE(m->eq24_jerk, kPathLevel) << run.name << " " << planner;
  }
}

// The row `key` of `table` is seed 004's cycle time of `run`; the row key + "_optimal" beside it
// must be the optimal planner's of the same path: finite, at most seed 004's (in the path model
// both hold the same rules, timing.hpp, so seed 004's plan is a feasible one the optimum cannot
// lose to beyond its grid's resolution) and at least the time-optimal bound without jerk.
void expect_optimal_beside(const FigureTable& table, const std::string& key, const PlannedRun& run) {
  SCOPED_TRACE(table.title + ": " + key + " (" + run.name + ")");
  EXPECT_EQ(run.timing.algorithm, TimingOptions::Algorithm::kSeed004);
  EXPECT_EQ(run.optimal.algorithm, TimingOptions::Algorithm::kOptimal);
  const Figure& seed = table.at(key);
  const Figure& optimal = table.at(key + "_optimal");
  EXPECT_EQ(seed.ours, run.timing.cycle_time);
  EXPECT_EQ(optimal.ours, run.optimal.cycle_time);
  ASSERT_TRUE(std::isfinite(optimal.ours));
  EXPECT_GT(optimal.ours, 0);
  EXPECT_LE(optimal.ours, seed.ours * (1 + kOptimalSlack));
  EXPECT_GE(optimal.ours, run.optimal.bound_cycle_time * (1 - 1e-9));
  EXPECT_NEAR(run.optimal.bound_cycle_time, run.timing.bound_cycle_time, 1e-9 * run.timing.bound_cycle_time);
  // the same paper figure, so the relative difference compares the two planners with the paper
  EXPECT_TRUE(optimal.paper == seed.paper || (std::isnan(optimal.paper) && std::isnan(seed.paper)));
  EXPECT_EQ(optimal.label.rfind(seed.label + ", optimal planner", 0), 0u) << optimal.label;
  // where the optimal planner kept seed 004's motion, the row says on how many stretches
  EXPECT_EQ(optimal.label.find("seed 004's motion kept on " + std::to_string(run.optimal.seed004_stretches)) !=
                std::string::npos,
            run.optimal.seed004_stretches > 0)
      << optimal.label;
}

// An independent lower bound: one S-curve from rest to rest over the run's path length under its
// tangential limits alone (plan_scurve's closed form) relaxes every other limit and every stop.
void expect_above_one_scurve(const PlannedRun& run) {
  const Limits& l = run.path.pieces().front().limits;
  const double relaxed = plan_scurve(run.path.length(), 0.0, 0.0, ScurveLimits{l.velocity, l.acceleration, l.deceleration, l.jerk})
                             .curve.duration();
  EXPECT_GE(run.optimal.cycle_time, relaxed * (1 - 1e-9)) << run.name;
  EXPECT_GE(run.timing.cycle_time, relaxed * (1 - 1e-9)) << run.name;
}

const PlannedRun& run_named(const std::vector<PlannedRun>& runs, const std::string& name) {
  for (const PlannedRun& r : runs) {
    if (r.name == name) return r;
  }
  throw std::out_of_range("no run " + name);
}

TEST(Figure, PrintRoundingAndRelativeDifference) {
  const Figure c1{"c1", "c1", 0.012, 0.011516, 0.001};
  EXPECT_TRUE(c1.within_print_rounding());
  EXPECT_NEAR(c1.relative_difference(), -0.0403, 1e-4);
  EXPECT_FALSE((Figure{"f", "f", 12486, 12501, 1}).within_print_rounding());
  EXPECT_TRUE((Figure{"f", "f", 1.2, 1.1686, 0.1}).within_print_rounding());
  // exactly half a step rounds either way; no step or no paper value never agrees
  EXPECT_TRUE((Figure{"h", "h", 0.47, 0.475, 0.01}).within_print_rounding());
  EXPECT_FALSE((Figure{"r", "r", 0.65, 0.65, 0}).within_print_rounding());
  EXPECT_FALSE((Figure{"n", "n", std::nan(""), 1.0, 0.1}).within_print_rounding());
  EXPECT_TRUE(std::isnan((Figure{"n", "n", std::nan(""), 1.0, 0.1}).relative_difference()));
}

TEST(Figure, TableLookupNamesTheMissingKey) {
  FigureTable t;
  t.title = "T";
  t.rows.push_back(Figure{"a", "A", 1, 1, 1});
  EXPECT_EQ(t.at("a").label, "A");
  try {
    (void)t.at("b");
    FAIL() << "no exception";
  } catch (const std::out_of_range& e) {
    EXPECT_NE(std::string(e.what()).find("'b'"), std::string::npos);
  }
}

TEST(ProfileMargins, DiagonalLineSplitsTheTangentialMotionOverTwoAxes) {
  // a 100 mm line along (1, 1, 0)/sqrt(2): every axis sees the tangential motion times
  // 1/sqrt(2); the tangential jerk reaches its limit and nothing is curved
  Program p;
  Move m;
  m.geometry = Line{Vec3::Zero(), Vec3(0.1, 0.1, 0) / std::sqrt(2.0)};
  m.limits = Limits{0.2, 2.0, 2.0, 40.0};
  p.moves = {m};
  const PlannedRun run = plan_run("line", "diagonal line", p);
  const ProfileMargins& g = run.margins;
  EXPECT_NEAR(g.tangential_jerk, 1.0, 1e-9);
  EXPECT_NEAR(g.velocity, 1.0, 1e-9);  // 100 mm is long enough to reach 0.2 m/s
  EXPECT_EQ(g.normal_acceleration, 0.0);
  EXPECT_EQ(g.eq24_jerk, 0.0);
  // finite differences average the exact values, so they stay within them (plus rounding)
  EXPECT_LE(g.axis_acceleration, g.tangential_acceleration / std::sqrt(2.0) + 1e-6);
  EXPECT_LE(g.axis_jerk, 1 / std::sqrt(2.0) + 1e-6);
  EXPECT_GT(g.axis_jerk, 0.5);
  EXPECT_EQ(run.fillets, 0);
}

TEST(Reproduce004, Section5WorkedExampleToTwoDecimals) {
  const FigureTable& t = paper004().section5;
  for (const char* key : {"c1", "s1", "s2", "x_end", "y_end"}) {
    EXPECT_TRUE(t.at(key).within_print_rounding()) << key << ": " << t.at(key).ours;
  }
}

TEST(Reproduce004, Table1SharpnessCurvatureAndFeed) {
  const FigureTable& t = paper004().table1;
  for (const char* fillet : {"S1S2", "S3S4", "S5S6"}) {
    const std::string f = fillet;
    EXPECT_TRUE(t.at(f + ".sharpness").within_print_rounding()) << f << " " << t.at(f + ".sharpness").ours;
    EXPECT_TRUE(t.at(f + ".kappa_max").within_print_rounding()) << f << " " << t.at(f + ".kappa_max").ours;
    EXPECT_LE(std::abs(t.at(f + ".feed_max").relative_difference()), kTable1Feed) << f;
  }
}

TEST(Reproduce004, Table2BiclothoidAndTheBezierAtTheSameDeviation) {
  const Paper004& r = paper004();
  const FigureTable& t = r.table2;
  for (const char* key : {"biclothoid.length", "biclothoid.kappa_max", "biclothoid.sharpness_max"}) {
    EXPECT_TRUE(t.at(key).within_print_rounding()) << key << ": " << t.at(key).ours;
  }
  EXPECT_LE(std::abs(t.at("biclothoid.feed_max").relative_difference()), kTable2Feed);
  // the Bezier's TP gives the biclothoid's deviation (0.1 mm), as the report states
  EXPECT_NEAR(r.table2_deviation, 0.1 * kMm, 1e-4 * 0.1 * kMm);
  EXPECT_NEAR(r.table2_bezier_deviation, r.table2_deviation, 1e-3 * r.table2_deviation);
  // the paper's conclusion, which the report says holds with our cubic: higher feed, less time
  EXPECT_GT(t.at("biclothoid.feed_max").ours, t.at("bezier.feed_max").ours);
  EXPECT_LT(t.at("time_ratio").ours, 1.0);
}

TEST(Reproduce004, Table3CountsAndBiclothoidCycleTimes) {
  const FigureTable& t = paper004().table3;
  EXPECT_EQ(t.at("chords_0.1").ours, 31);
  EXPECT_EQ(t.at("chords_0.01").ours, 96);
  for (const char* key : {"biclothoid_0.1", "biclothoid_0.01", "bezier_0.1", "bezier_0.01"}) {
    const std::string k = key;
    EXPECT_EQ(t.at(k + ".fillets").ours, t.at(k + ".fillets").paper) << k;
  }
  EXPECT_LE(std::abs(t.at("biclothoid_0.1.cycle_time").relative_difference()), kCycleTime);
  EXPECT_LE(std::abs(t.at("biclothoid_0.01.cycle_time").relative_difference()), kCycleTime);
  // the ranking the paper reports (ours does not match its Bezier times: a different curve)
  EXPECT_LT(t.at("biclothoid_0.1.cycle_time").ours, t.at("bezier_0.1.cycle_time").ours);
  EXPECT_LT(t.at("bezier_0.1.cycle_time").ours, t.at("bezier_0.01.cycle_time").ours);
  EXPECT_LE(t.at("biclothoid_0.01.cycle_time").ours - t.at("biclothoid_0.1.cycle_time").ours, 0.01);
}

TEST(Reproduce004, Section3UnsmoothedCycleTimesRoundToThePapers) {
  const FigureTable& t = paper004().section3;
  EXPECT_TRUE(t.at("unlimited").within_print_rounding()) << t.at("unlimited").ours;
  EXPECT_TRUE(t.at("junction_slowdown").within_print_rounding()) << t.at("junction_slowdown").ours;
  EXPECT_GT(t.at("exact_stop").ours, t.at("junction_slowdown").ours);
  EXPECT_GT(t.at("junction_slowdown").ours, t.at("unlimited").ours);
}

TEST(Reproduce004, OptimalPlannerBesideEveryCycleTime) {
  const Paper004& r = paper004();
  for (const auto& [key, run] : {std::pair{"biclothoid_0.1", "biclothoid_0.1mm"}, std::pair{"biclothoid_0.01", "biclothoid_0.01mm"},
                                 std::pair{"bezier_0.1", "bezier_0.1mm"}, std::pair{"bezier_0.01", "bezier_0.01mm"}}) {
    expect_optimal_beside(r.table3, std::string(key) + ".cycle_time", run_named(r.runs, run));
  }
  expect_optimal_beside(r.section3, "junction_slowdown", run_named(r.runs, "junction_slowdown"));
  expect_optimal_beside(r.section3, "exact_stop", run_named(r.runs, "exact_stop"));
  EXPECT_NEAR(r.section3.at("ratio_optimal").ours,
              r.section3.at("junction_slowdown_optimal").ours / r.section3.at("unlimited").ours, 1e-12);
  for (const PlannedRun& run : r.runs) expect_above_one_scurve(run);
}

TEST(Reproduce004, EveryProfileHoldsThePathLevelLimits) {
  const Paper004& r = paper004();
  ASSERT_EQ(r.runs.size(), 6u);
  for (const PlannedRun& run : r.runs) expect_path_level_limits_hold(run);
}

TEST(Reproduce000, ExactStopAndTangentialRatioAreComparable) {
  const FigureTable& t = paper000().section3_2;
  EXPECT_LE(std::abs(t.at("without").relative_difference()), kExactStop000);
  EXPECT_LE(std::abs(t.at("ratio_tangential").relative_difference()), kRatio000);
  // the arc is not slowed by eq. 25-27, so the planner's exact stops are the tangential-only ones
  EXPECT_NEAR(t.at("without").ours, t.at("without_tangential").ours, 1e-9);
  for (const PlannedRun& run : paper000().runs) expect_path_level_limits_hold(run);
}

TEST(Reproduce000, OptimalPlannerBesideEveryCycleTime) {
  const Paper000& r = paper000();
  const FigureTable& t = r.section3_2;
  expect_optimal_beside(t, "with", run_named(r.runs, "bezier_tp5"));
  expect_optimal_beside(t, "without", run_named(r.runs, "exact_stop"));
  expect_optimal_beside(t, "with_tp20", run_named(r.runs, "bezier_tp20"));
  EXPECT_NEAR(t.at("ratio_optimal").ours, t.at("with_optimal").ours / t.at("without_optimal").ours, 1e-12);
  // an independent reference: at the exact stops every stretch is one move from rest to rest on a
  // line or on the arc where eq. 25-27 do not bind, so the least time is the closed-form S-curve
  // per move (the tangential-only figure, plan_scurve)
  EXPECT_NEAR(t.at("without_optimal").ours, t.at("without_tangential").ours, kOptimalSlack * t.at("without_tangential").ours);
  // and tangential limits only are a relaxation of the blended paths' limits: no faster
  EXPECT_GE(t.at("with_optimal").ours, t.at("with_tangential").ours * (1 - 1e-9));
  for (const PlannedRun& run : r.runs) expect_above_one_scurve(run);
}

TEST(Reproduce000, TheProgramUsesACubicAndAQuartic) {
  const PlannedRun& with = paper000().runs.at(0);
  ASSERT_EQ(with.name, "bezier_tp5");
  std::vector<int> degrees;
  for (const PathPiece& p : with.path.pieces()) {
    if (const auto* b = std::get_if<Bezier>(&p.segment)) degrees.push_back(b->degree());
  }
  EXPECT_EQ(degrees, (std::vector<int>{3, 4}));
}

TEST(Reproduce, WritesTheReportAndRejectsAnUnknownName) {
  const test::ScratchDir scratch("reproduce_test");
  const std::filesystem::path dir = scratch / "out";
  std::ostringstream log;
  EXPECT_EQ(reproduce("000", dir, false, log), 0);
  std::ifstream readme(dir / "000" / "README.md");
  ASSERT_TRUE(readme);
  std::string text;
  for (std::string line; std::getline(readme, line);) text += line + "\n";
  EXPECT_NE(text.find("| with / without |"), std::string::npos);
  EXPECT_NE(text.find("no path-level limit is exceeded"), std::string::npos);
  std::ifstream results(dir / "000" / "results.json");
  const nlohmann::json j = nlohmann::json::parse(results);
  EXPECT_EQ(j["paper"], "000");
  EXPECT_EQ(j["runs"].size(), 3u);
  EXPECT_TRUE(std::filesystem::exists(dir / "000" / "profile_exact_stop.csv"));
  // the optimal planner's figures: rows beside seed 004's, a block per run, its profiles
  EXPECT_NE(text.find("| with transitions: cycle time (s), optimal planner"), std::string::npos);
  std::vector<std::string> keys;
  for (const auto& row : j["tables"][0]["rows"]) keys.push_back(row["key"].get<std::string>());
  for (const char* key : {"with_optimal", "without_optimal", "ratio_optimal", "with_tp20_optimal"}) {
    EXPECT_NE(std::find(keys.begin(), keys.end(), key), keys.end()) << key;
  }
  for (const auto& run : j["runs"]) {
    const std::string name = run["name"].get<std::string>();
    EXPECT_GT(run["optimal"]["cycle_time_s"].get<double>(), 0) << name;
    EXPECT_LE(run["optimal"]["cycle_time_s"].get<double>(), run["cycle_time_s"].get<double>() * (1 + kOptimalSlack)) << name;
    EXPECT_GE(run["optimal"]["cycle_time_s"].get<double>(), run["bound_cycle_time_s"].get<double>()) << name;
    EXPECT_TRUE(std::filesystem::exists(dir / "000" / ("profile_" + name + "_optimal.csv"))) << name;
  }
  EXPECT_THROW(reproduce("003", dir, false, log), InputError);
}

TEST(Reproduce004, MarkdownHasEveryTable) {
  const std::string md = markdown_004(paper004());
  for (const FigureTable* t : {&paper004().section5, &paper004().table1, &paper004().table2, &paper004().table3,
                               &paper004().section3}) {
    EXPECT_NE(md.find("## " + t->title), std::string::npos) << t->title;
  }
  EXPECT_NE(md.find("no path-level limit is exceeded"), std::string::npos);
}

}  // namespace
}  // namespace blendbench
