// End-to-end: a short scenario through the whole pipeline (blend, time, IK, MuJoCo, metrics,
// files), without video or plots so it stays fast. The bounds below are what a well-tuned PD
// servo on this arm must achieve; a regression in any stage moves the numbers past them.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "support/input_error.hpp"
#include "support/property.hpp"
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

TEST_F(EndToEnd, UnreachableTargetIsBadInputNamingTheMove) {
  std::string text = kScenario;
  text.replace(text.find("line: [100, 100, 0]"), 19, "line: [100, 900, 0]");
  const Scenario sc = parse_scenario(text, "e2e.yaml", test::source_path("scenarios"));
  RunRequest request;
  request.out_dir = dir_;
  request.video = false;
  request.plots = false;
  // when and where: the time on the plan and the pose that is out of reach
  const InputError e = test::expect_input_error([&] { (void)run_scenario(sc, request); },
                                                {.file = "e2e.yaml", .line = 10, .field = "program.moves[1]",
                                                 .message = "out of reach: position ("});
  EXPECT_NE(std::string(e.what()).find("t = "), std::string::npos) << e.what();
}

}  // namespace
}  // namespace blendbench
