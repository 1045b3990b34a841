// End-to-end: a short scenario through the whole pipeline (blend, time, IK, MuJoCo, metrics,
// files), without video or plots so it stays fast. The bounds below are what a well-tuned PD
// servo on this arm must achieve; a regression in any stage moves the numbers past them.

#include <gtest/gtest.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "support/property.hpp"
#include "blendbench/core/interrupt.hpp"
#include "blendbench/app/runner.hpp"
#include "blendbench/io/scenario.hpp"

namespace blendbench {
namespace {

namespace fs = std::filesystem;

// Tracking error bound for 200 mm/s moves on this arm with the default gains (mm).
constexpr double kTrackingBoundMm = 2.0;

const char* const kScenario = R"(name: e2e
units: mm
frame: {origin: [400, -50, 250], rpy_deg: [0, 0, 0]}
defaults: {velocity: 200, acceleration: 2000, jerk: 20000}
simulation: {settle_tolerance: 0.2, settle_time_s: 0.5}
program:
  start: [0, 0, 0]
  moves:
    - line: [100, 0, 0]
    - line: [100, 100, 0]
variants:
  - {name: exact, transition: {method: none}}
  - {name: arc, transition: {method: arc, parameter: 10}}
)";

class EndToEnd : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("blendbench_e2e_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  // A run into `dir` without video or plots.
  static RunRequest request_into(const fs::path& dir) {
    RunRequest request;
    request.out_dir = dir;
    request.video = false;
    request.plots = false;
    return request;
  }
  fs::path dir_;
};

TEST_F(EndToEnd, MetricsAreFiniteAndPlausible) {
  const Scenario sc = parse_scenario(kScenario, "e2e.yaml", test::source_path("scenarios"));
  RunRequest request;
  request.out_dir = dir_;
  request.video = false;
  request.plots = false;
  const RunResult result = run_scenario(sc, request);
  ASSERT_TRUE(result.all_ok) << result.summary.dump(2);
  ASSERT_EQ(result.summary["variants"].size(), 2u);
  for (const auto& v : result.summary["variants"]) {
    SCOPED_TRACE(v["name"].get<std::string>());
    const double planned = v["planned_cycle_time_s"];
    ASSERT_TRUE(v["cycle_time_s"].is_number()) << "the run must settle";
    const double cycle = v["cycle_time_s"];
    // the arm cannot arrive before the plan ends, and must settle soon after
    EXPECT_GT(cycle, planned - 0.05);
    EXPECT_LT(cycle, planned + 0.5);
    const double tracking = v["tracking_error_max_mm"];
    EXPECT_GT(tracking, 0.0);
    EXPECT_LT(tracking, kTrackingBoundMm);
    EXPECT_LE(v["tracking_error_rms_mm"].get<double>(), tracking);
    EXPECT_LT(v["contour_error_max_mm"].get<double>(), 10.0);
    EXPECT_FALSE(v["torque_limit_reached"].get<bool>());
    for (const char* file : {"trace.csv", "path.csv", "program.csv", "corners.json"}) {
      EXPECT_TRUE(fs::is_regular_file(dir_ / v["name"].get<std::string>() / file)) << file;
    }
  }
  EXPECT_TRUE(fs::is_regular_file(dir_ / "summary.json"));
  // the two paths share the programmed corners; exact stop takes longer than 2 moves of 100 mm at 200 mm/s
  EXPECT_GT(result.summary["variants"][0]["planned_cycle_time_s"].get<double>(), 1.0);
}

// A move the robot cannot reach fails its variant, not the run: the status says where (file,
// line, move), when (the time on the plan) and what (the pose out of reach).
TEST_F(EndToEnd, UnreachableMoveFailsTheVariantNamingTheMove) {
  std::string text = kScenario;
  text.replace(text.find("line: [100, 100, 0]"), 19, "line: [100, 900, 0]");
  const Scenario sc = parse_scenario(text, "e2e.yaml", test::source_path("scenarios"));
  const RunResult result = run_scenario(sc, request_into(dir_));
  EXPECT_FALSE(result.all_ok);
  ASSERT_EQ(result.summary["variants"].size(), 2u);
  for (const auto& v : result.summary["variants"]) {
    SCOPED_TRACE(v["name"].get<std::string>());
    EXPECT_EQ(v["status"], "failed");
    const std::string what = v["message"];
    EXPECT_EQ(what.rfind("e2e.yaml:10:", 0), 0u) << what;
    EXPECT_NE(what.find("'program.moves[1]'"), std::string::npos) << what;
    EXPECT_NE(what.find("t = "), std::string::npos) << what;
    EXPECT_NE(what.find("out of reach: position ("), std::string::npos) << what;
    EXPECT_FALSE(fs::exists(dir_ / v["name"].get<std::string>())) << "a failed variant leaves no folder";
  }
  EXPECT_TRUE(fs::is_regular_file(dir_ / "summary.json"));
}

// Of two variants of one program (tests/data/reach.yaml), the exact stop reaches a corner
// beyond the arm's reach while the biclothoid, 40 mm inside the corner, stays within it: the
// first fails alone and the second runs to the end.
TEST_F(EndToEnd, OneVariantOutOfReachFailsAloneTheOthersRun) {
  const Scenario sc = load_scenario(test::source_path("tests/data/reach.yaml"));
  const RunResult result = run_scenario(sc, request_into(dir_));
  EXPECT_FALSE(result.all_ok);
  const auto& variants = result.summary["variants"];
  ASSERT_EQ(variants.size(), 2u);
  EXPECT_EQ(variants[0]["status"], "failed");
  EXPECT_NE(variants[0]["message"].get<std::string>().find("reach.yaml:12:7: 'program.moves[0]'"), std::string::npos)
      << variants[0]["message"];
  EXPECT_EQ(variants[1]["status"], "ok") << variants[1].dump(2);
  EXPECT_TRUE(variants[1]["cycle_time_s"].is_number());
  EXPECT_TRUE(fs::is_regular_file(dir_ / "biclothoid_40" / "trace.csv"));
  EXPECT_FALSE(fs::exists(dir_ / "exact"));
}

// The start point is every variant's: out of reach, the scenario is bad input, found before any
// variant runs or any file is written.
TEST_F(EndToEnd, UnreachableStartIsBadInputOfTheScenario) {
  std::string text = kScenario;
  text.replace(text.find("origin: [400, -50, 250]"), 23, "origin: [1400, -50, 250]");
  const Scenario sc = parse_scenario(text, "e2e.yaml", test::source_path("scenarios"));
  try {
    (void)run_scenario(sc, request_into(dir_));
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "e2e.yaml");
    EXPECT_EQ(e.line(), 9) << e.what();
    EXPECT_EQ(e.field(), "program.moves[0]") << e.what();
    EXPECT_NE(std::string(e.what()).find("the start point (1400.0, -50.0, 250.0) mm cannot be reached"), std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(dir_ / "summary.json"));
}

// A stop request (what the SIGINT/SIGTERM handler records) while the second variant starts:
// the first variant's results are kept, the second is marked interrupted and leaves no folder,
// summary.json lists both, and the run says which signal stopped it.
TEST_F(EndToEnd, AStopRequestKeepsFinishedVariantsAndMarksTheRest) {
  const Scenario sc = parse_scenario(kScenario, "e2e.yaml", test::source_path("scenarios"));
  RunRequest request = request_into(dir_);
  request.progress = [](const std::string& line) {
    if (line.rfind("[2/2]", 0) == 0) request_stop(SIGTERM);
  };
  const RunResult result = run_scenario(sc, request);
  clear_stop_request();
  EXPECT_EQ(result.interrupted_by, SIGTERM);
  const auto& variants = result.summary["variants"];
  ASSERT_EQ(variants.size(), 2u);
  EXPECT_EQ(variants[0]["status"], "ok");
  EXPECT_EQ(variants[1]["status"], "interrupted");
  EXPECT_TRUE(fs::is_regular_file(dir_ / "exact" / "trace.csv"));
  EXPECT_FALSE(fs::exists(dir_ / "arc"));
  EXPECT_TRUE(fs::is_regular_file(dir_ / "summary.json"));
}

// A path below the floor is run (the model has no contacts) and reported: the lowest TCP height
// and when it first went below z = 0 of the base frame.
TEST_F(EndToEnd, APathBelowTheFloorIsReported) {
  std::string text = kScenario;
  text.replace(text.find("origin: [400, -50, 250]"), 23, "origin: [400, -50, 20]");
  text.replace(text.find("line: [100, 0, 0]"), 17, "line: [100, 0, -40]");
  const Scenario sc = parse_scenario(text, "e2e.yaml", test::source_path("scenarios"));
  const RunResult result = run_scenario(sc, request_into(dir_));
  ASSERT_TRUE(result.all_ok) << result.summary.dump(2);
  for (const auto& v : result.summary["variants"]) {
    SCOPED_TRACE(v["name"].get<std::string>());
    const auto& w = v["workspace"];
    EXPECT_TRUE(w["below_floor"].get<bool>()) << w.dump();
    // the exact stop's commanded path reaches z = -20 mm at the first corner, the arc blend's
    // stays above it by the cut of its corner; the actual TCP is within the tracking bound
    const double z_min = w["tcp_z_min_mm"].get<double>();
    EXPECT_LT(z_min, -10.0) << w.dump();
    EXPECT_GT(z_min, -20.0 - kTrackingBoundMm) << w.dump();
    if (v["name"] == "exact") {
      EXPECT_NEAR(z_min, -20.0, kTrackingBoundMm) << w.dump();
    }
    EXPECT_GT(w["below_floor_t_s"].get<double>(), 0.0);
    EXPECT_FALSE(w["into_base"].get<bool>());
  }
}

}  // namespace
}  // namespace blendbench
