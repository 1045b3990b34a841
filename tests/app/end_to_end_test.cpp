// End-to-end: a short scenario through the whole pipeline (blend, time, IK, the elastic arm's
// simulation, metrics, files), without video or plots so it stays fast. The tests read the typed
// result the runner returns (run_summary.hpp) and check that summary.json is its serialization.
// The bounds below are what the tuned cascade on this arm achieves; a regression in any stage
// moves the numbers past them.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "blendbench/app/runner.hpp"
#include "blendbench/io/scenario.hpp"
#include "support/input_error.hpp"
#include "support/property.hpp"

namespace blendbench {
namespace {

namespace fs = std::filesystem;

// Tracking error bound for 200 mm/s moves on this arm with every feed-forward (m): a tenth of what
// the plain PD leaves.
constexpr double kTrackingBound = 0.3e-3;

const char* const kScenario = R"(name: e2e
units: mm
frame: {origin: [400, -50, 250], rpy_deg: [0, 0, 0]}
defaults: {velocity: 200, acceleration: 2000, jerk: 20000}
simulation: {settle_tolerance: 0.05, settle_time_s: 0.5}
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

  RunResult run(const std::string& text) {
    const Scenario sc = parse_scenario(text, "e2e.yaml", test::source_path("scenarios"));
    RunRequest request;
    request.out_dir = dir_;
    request.video = false;
    request.plots = false;
    return run_scenario(sc, request);
  }

  // The scenario with one text replacement.
  static std::string with(const std::string& from, const std::string& to) {
    std::string text = kScenario;
    text.replace(text.find(from), from.size(), to);
    return text;
  }

  fs::path dir_;
};

TEST_F(EndToEnd, MetricsAreFiniteAndPlausible) {
  const RunResult result = run(kScenario);
  const RunSummary& summary = result.summary;
  ASSERT_TRUE(result.all_ok);
  ASSERT_EQ(summary.variants.size(), 2u);
  EXPECT_EQ(summary.robot.model, ArmModel::kElastic);
  EXPECT_GT(summary.robot.natural_frequency_arm[0], 8);
  EXPECT_EQ(summary.servo.rate_hz, 2000);
  EXPECT_EQ(summary.servo.setpoint_rate_hz, 500);
  for (const VariantSummary& v : summary.variants) {
    SCOPED_TRACE(v.name);
    ASSERT_EQ(v.status, VariantStatus::kOk) << v.message;
    ASSERT_TRUE(v.metrics && v.health);
    const Metrics& m = *v.metrics;
    ASSERT_TRUE(m.cycle_time) << "the run must settle";
    // the cycle ends after the reference and soon after it
    EXPECT_GE(*m.cycle_time, v.plan.planned_cycle_time - 0.002);
    EXPECT_LT(*m.cycle_time, v.plan.planned_cycle_time + 0.3);
    EXPECT_GT(m.tracking_error_max, 0.0);
    EXPECT_LT(m.tracking_error_max, kTrackingBound);
    EXPECT_LE(m.tracking_error_rms, m.tracking_error_max);
    EXPECT_LT(m.contour_error_planned_max, kTrackingBound);
    EXPECT_LT(m.contour_error_programmed_max, 10e-3);
    EXPECT_FALSE(v.health->saturated);
    EXPECT_FALSE(v.health->limits_exceeded());
    EXPECT_GT(m.vibration_final.peak_to_peak, 0.0);
    EXPECT_EQ(v.plan.corners.size(), 1u);
    EXPECT_EQ(v.plan.corner_times.size(), 1u);
    EXPECT_LE(v.plan.corner_times[0].t_start, v.plan.corner_times[0].t_end);
    EXPECT_EQ(m.vibration_corners.size(), 1u);
    for (const char* file : {"trace.csv", "path.csv", "program.csv", "corners.json"}) {
      EXPECT_TRUE(fs::is_regular_file(dir_ / v.name / file)) << file;
    }
    ASSERT_TRUE(v.comparison);
    EXPECT_EQ(v.comparison->reference, "exact");
  }
  // the comparison block: cycle time saved against the exact stop, which compares to itself as
  // 0 % and ratios of 1
  const double t_exact = *summary.variants[0].metrics->cycle_time, t_arc = *summary.variants[1].metrics->cycle_time;
  EXPECT_NEAR(*summary.variants[1].comparison->cycle_time_saved_percent, 100 * (t_exact - t_arc) / t_exact, 1e-12);
  EXPECT_EQ(*summary.variants[0].comparison->cycle_time_saved_percent, 0.0);
  for (const auto& [key, ratio] : summary.variants[0].comparison->ratios) {
    if (ratio) {
      EXPECT_DOUBLE_EQ(*ratio, 1.0) << key;
    }
  }
  // summary.json is the one serializer's output of the typed result
  std::ifstream in(dir_ / "summary.json");
  EXPECT_EQ(nlohmann::json::parse(in), nlohmann::json(summary));
}

// Faster is less accurate where the servo's lag decides: under the plain PD the tracking error
// grows with the path speed over a small sweep, on every variant; the feed-forward reduces it on
// every variant at every speed. (With the feed-forward what is left is mostly Coulomb friction
// where a joint's speed passes zero or the path stops, which does not grow with speed, so the
// cascade's own error is not swept.)
TEST_F(EndToEnd, TrackingErrorGrowsWithSpeedAndFeedForwardReducesIt) {
  // the scenario with shorter moves and settling, to keep the sweep short
  std::string base = with("simulation: {settle_tolerance: 0.05, settle_time_s: 0.5}",
                          "simulation: {settle_tolerance: 0.05, settle_time_s: 0.25}");
  for (const auto& [from, to] : {std::pair{"line: [100, 0, 0]", "line: [60, 0, 0]"}, std::pair{"line: [100, 100, 0]", "line: [60, 60, 0]"}}) {
    base.replace(base.find(from), std::string(from).size(), to);
  }
  const auto at = [](std::string t, const std::string& from, const std::string& to) {
    t.replace(t.find(from), from.size(), to);
    return t;
  };
  // (a PD without integral action may stop short of the end point by friction: not settled,
  // but clean tracking data)
  const auto clean = [](const RunResult& r, const std::string& what) {
    for (const VariantSummary& v : r.summary.variants) {
      EXPECT_TRUE(v.metrics && v.health && !v.health->saturated && !v.health->limits_exceeded()) << what << " " << v.name << ": " << v.message;
    }
  };
  std::vector<std::vector<double>> pd_errors;  // per speed, per variant
  for (const char* speed : {"100", "200", "300"}) {
    const std::string fast = at(base, "velocity: 200", std::string("velocity: ") + speed);
    const RunResult cascade = run(fast);
    const RunResult pd = run(at(fast, "units: mm", "units: mm\nservo: {controller: pd}"));
    clean(cascade, speed);
    clean(pd, speed);
    pd_errors.emplace_back();
    for (std::size_t v = 0; v < cascade.summary.variants.size(); ++v) {
      pd_errors.back().push_back(pd.summary.variants[v].metrics->tracking_error_max);
      EXPECT_LT(cascade.summary.variants[v].metrics->tracking_error_max, 0.2 * pd_errors.back().back())
          << speed << " mm/s, variant " << v;
    }
  }
  for (std::size_t v = 0; v < pd_errors[0].size(); ++v) {
    EXPECT_LT(pd_errors[0][v], pd_errors[1][v]) << "variant " << v;
    EXPECT_LT(pd_errors[1][v], pd_errors[2][v]) << "variant " << v;
  }
  // the inertial feed-forward alone (and the deflection compensation that comes with it) halves
  // the cascade's error at least
  const RunResult cascade = run(base);
  const RunResult without =
      run(at(base, "units: mm", "units: mm\nservo: {acceleration_feedforward: false, deflection_compensation: false}"));
  clean(without, "without feed-forward");
  for (std::size_t v = 0; v < cascade.summary.variants.size(); ++v) {
    EXPECT_LT(cascade.summary.variants[v].metrics->tracking_error_max,
              0.5 * without.summary.variants[v].metrics->tracking_error_max) << "variant " << v;
  }
}

TEST_F(EndToEnd, RigidModelRunsAndMismatchesAreBadInput) {
  const RunResult rigid = run(with("units: mm", "units: mm\nrobot: {model: rigid}"));
  EXPECT_TRUE(rigid.all_ok);
  EXPECT_EQ(rigid.summary.robot.model, ArmModel::kRigid);
  EXPECT_EQ(rigid.summary.robot.natural_frequency_arm, JointVector::Zero());
  // found when the model is loaded, named at the YAML key (line 3): robot.model rigid on the
  // elastic file, and a servo rate that does not divide the 8 kHz physics
  const struct {
    std::string line, field, fragment;
  } cases[] = {{"robot: {model: rigid, mjcf: ../models/ur5e_like.xml}", "robot.model", "elastic joints"},
               {"servo: {rate_hz: 3000, setpoint_rate_hz: 500}", "servo.rate_hz", "8000 Hz physics"}};
  for (const auto& c : cases) {
    test::expect_input_error([&] { (void)run(with("units: mm", "units: mm\n" + c.line)); },
                             {.line = 3, .field = c.field, .message = c.fragment}, c.line);
  }
}

TEST_F(EndToEnd, UnreachableTargetIsBadInputNamingTheMove) {
  // when and where: the time on the plan and the pose that is out of reach
  const InputError e = test::expect_input_error([&] { (void)run(with("line: [100, 100, 0]", "line: [100, 900, 0]")); },
                                                {.file = "e2e.yaml", .line = 10, .field = "program.moves[1]",
                                                 .message = "out of reach: position ("});
  EXPECT_NE(std::string(e.what()).find("t = "), std::string::npos) << e.what();
}

}  // namespace
}  // namespace blendbench
