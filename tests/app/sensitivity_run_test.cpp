// `run --sensitivity` and `compare --sensitivity` through the program (docs/sensitivity.md): the
// `sensitivity` block of summary.json, its nominal runs equal to a plain run's figures, its
// holds counts against a recount from the runs it lists, the models actually perturbed, the
// ranking told it was used, the report's table, and bad input refused (exit 2, file:line and
// key). A short program, three variants and two perturbed models keep it fast (the sanitizer
// build runs it at 20-30x the cost).

#include <gtest/gtest.h>
#include <unistd.h>

#include <csignal>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "support/files.hpp"
#include "support/program.hpp"
#include "support/source_tree.hpp"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// The headline metrics (sensitivity.hpp), keys of both `metrics` and the study's runs.
const char* const kHeadlines[] = {"cycle_time_s", "contour_error_programmed_max_mm", "contour_error_planned_max_mm",
                                  "residual_vibration_corner_max_mm", "residual_vibration_final_mm"};

// Two 40 mm lines with one corner, three variants, two perturbed models (line 4: `sensitivity`).
const char* const kScenario = R"(name: sens
units: mm
frame: {origin: [400, -100, 200], rpy_deg: [0, 0, 0]}
sensitivity: {stiffness_scale: [0.5], inertia_scale: [], friction_scale: [], extra_delay_ticks: [1]}
defaults: {velocity: 250, acceleration: 2500, deceleration: 2500, jerk: 50000, buffer: BlendingLow}
simulation: {settle_time_s: 0.3}
program:
  start: [0, 0, 0]
  moves:
    - line: [40, 0, 0]
    - line: [40, 40, 0]
variants:
  - {name: exact_stop, transition: {method: none}}
  - {name: arc, transition: {method: arc, tolerance: 1}}
  - {name: clothoid, transition: {method: clothoid, tolerance: 1}}
)";

struct Result {
  int exit_code = -1;
  std::string output;
};

Result run(const std::vector<std::string>& args) {
  blendbench::test::Child child(blendbench::test::blendbench_binary(), args);
  Result r;
  r.exit_code = child.wait();
  r.output = child.output();
  return r;
}

json read_json(const fs::path& file) {
  std::ifstream in(file);
  return json::parse(in);
}

class SensitivityRun : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("blendbench_sensitivity_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path write(const std::string& name, const std::string& text) const {
    const fs::path file = dir_ / name;
    std::ofstream(file) << text;
    return file;
  }

  fs::path dir_;
};

TEST_F(SensitivityRun, TheBlockAgreesWithItsRunsAndThePlainRun) {
  const fs::path file = write("sens.yaml", kScenario);
  const Result plain = run({"run", file.string(), "--no-video", "--no-plots", "--out", (dir_ / "plain").string()});
  ASSERT_EQ(plain.exit_code, 0) << plain.output;
  const Result r = run({"run", file.string(), "--sensitivity", "--jobs", "2", "--no-video", "--out", (dir_ / "sens").string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json base = read_json(dir_ / "plain" / "summary.json");
  const json summary = read_json(dir_ / "sens" / "summary.json");
  // opt-in: a plain run has no block and its ranking no spread
  EXPECT_FALSE(base.contains("sensitivity"));
  EXPECT_FALSE(base.at("ranking").at("resolution").at("model_spread").get<bool>());

  ASSERT_TRUE(summary.contains("sensitivity")) << r.output;
  const json& s = summary.at("sensitivity");
  EXPECT_EQ(s.at("models"), 2);
  ASSERT_EQ(s.at("perturbations").size(), 2u);
  EXPECT_EQ(s.at("perturbations")[0].at("name"), "stiffness x0.5");
  EXPECT_EQ(s.at("perturbations")[0].at("stiffness_scale"), 0.5);
  EXPECT_EQ(s.at("perturbations")[1].at("name"), "delay +1 tick");
  EXPECT_EQ(s.at("perturbations")[1].at("extra_delay_ticks"), 1);
  EXPECT_EQ(s.at("jobs"), 2);
  ASSERT_EQ(s.at("variants").size(), 3u);

  // each variant: its nominal run is the plain run's figures (the study changes nothing of it),
  // and the softer gears change its figures (the model was perturbed)
  for (std::size_t v = 0; v < 3; ++v) {
    const json& sv = s.at("variants")[v];
    const json& plain_metrics = base.at("variants")[v].at("metrics");
    EXPECT_EQ(sv.at("variant"), base.at("variants")[v].at("name"));
    ASSERT_EQ(sv.at("runs").size(), 3u);
    const json& nominal = sv.at("runs")[0];
    EXPECT_EQ(nominal.at("model"), "nominal");
    bool changed = false;
    for (const char* key : kHeadlines) {
      EXPECT_EQ(nominal.at(key), plain_metrics.at(key)) << sv.at("variant") << ' ' << key;
      changed = changed || sv.at("runs")[1].at(key) != nominal.at(key);
      // the range spans the runs that have the figure
      double lo = 1e300, hi = -1e300;
      int models = 0;
      for (const json& run : sv.at("runs")) {
        if (run.at(key).is_null()) continue;
        lo = std::min(lo, run.at(key).get<double>());
        hi = std::max(hi, run.at(key).get<double>());
        ++models;
      }
      const json& range = sv.at("ranges").at(key);
      EXPECT_EQ(range.at("models"), models) << key;
      if (models > 0) {
        EXPECT_EQ(range.at("min").get<double>(), lo) << key;
        EXPECT_EQ(range.at("max").get<double>(), hi) << key;
      }
    }
    EXPECT_TRUE(changed) << sv.at("variant") << ": stiffness x0.5 changed no headline figure";
  }

  // each conclusion's count, recounted from the runs the block lists
  const auto runs_of = [&](const std::string& name) -> const json& {
    for (const json& sv : s.at("variants"))
      if (sv.at("variant") == name) return sv.at("runs");
    throw std::runtime_error("no variant " + name);
  };
  ASSERT_FALSE(s.at("conclusions").empty());
  for (const json& c : s.at("conclusions")) {
    const std::string key = c.at("metric");
    const json& better = runs_of(c.at("better"));
    const json& worse = runs_of(c.at("worse"));
    const double nb = better[0].at(key).get<double>(), nw = worse[0].at(key).get<double>();
    ASSERT_LE(nb, nw) << c;
    int holds = 0;
    for (std::size_t k = 1; k < better.size(); ++k) {
      if (better[k].at(key).is_null() || worse[k].at(key).is_null()) continue;
      const double b = better[k].at(key).get<double>(), w = worse[k].at(key).get<double>();
      holds += nb < nw ? b < w : b == w;
    }
    EXPECT_EQ(c.at("models"), 2) << c;
    EXPECT_EQ(c.at("holds"), holds) << c;
    EXPECT_EQ(c.at("holds_in"), holds == 2 ? "all" : holds == 0 ? "none" : "some") << c;
    EXPECT_EQ(c.at("statement").get<std::string>().rfind(c.at("better").get<std::string>(), 0), 0u) << c;
  }
  // the ranking was told: its ties follow the study
  EXPECT_TRUE(summary.at("ranking").at("resolution").at("model_spread").get<bool>());
  // the report shows the conclusions next to the answer
  const std::string report = blendbench::test::read_file(dir_ / "sens" / "report.html");
  EXPECT_NE(report.find("Sensitivity to the arm model"), std::string::npos);
  EXPECT_NE(report.find(s.at("conclusions")[0].at("statement").get<std::string>()), std::string::npos);
}

// `compare --sensitivity`: the variants compare builds (here the two baselines and the arc at
// the tolerance) get the block, and the ranking its spread.
TEST_F(SensitivityRun, CompareRunsTheStudyOnItsVariants) {
  const fs::path file = write("sens.yaml", kScenario);
  const Result r = run({"compare", file.string(), "--methods", "arc", "--tolerance", "1", "--sensitivity", "--no-video",
                        "--no-plots", "--out", (dir_ / "cmp").string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json summary = read_json(dir_ / "cmp" / "summary.json");
  ASSERT_TRUE(summary.contains("sensitivity")) << r.output;
  const json& s = summary.at("sensitivity");
  std::vector<std::string> names;
  for (const json& v : s.at("variants")) names.push_back(v.at("variant"));
  std::vector<std::string> ran;
  for (const json& v : summary.at("variants"))
    if (v.at("status") == "ok") ran.push_back(v.at("name"));
  EXPECT_EQ(names, ran);
  EXPECT_EQ(names.size(), 3u);
  EXPECT_EQ(s.at("conclusions").size(), 3u * 5u);  // three pairs, five metrics (every run settled)
  EXPECT_TRUE(summary.at("ranking").at("resolution").at("model_spread").get<bool>());
}

// A stop request while the perturbed models run ends the run as any other: exit 130, the
// finished nominal variants kept in --out (docs/output.md) with a summary that has neither a
// sensitivity block nor a ranking, no staging folder or lock left beside it.
TEST_F(SensitivityRun, SigintDuringThePerturbedRunsKeepsOnlyTheNominalVariants) {
  // the default seven models: 21 simulations, time enough for the signal to land among them
  std::string text = kScenario;
  const std::string line = "sensitivity: {stiffness_scale: [0.5], inertia_scale: [], friction_scale: [], extra_delay_ticks: [1]}\n";
  text.erase(text.find(line), line.size());
  const fs::path file = write("sens.yaml", text);
  const fs::path out = dir_ / "out";
  blendbench::test::Child child(blendbench::test::blendbench_binary(),
                                {"run", file.string(), "--sensitivity", "--no-video", "--no-plots", "--out", out.string()});
  ASSERT_TRUE(child.wait_for_line("sensitivity: 3 variants on 7 perturbed models")) << child.output();
  child.signal(SIGINT);
  EXPECT_EQ(child.wait_within(60), 130) << child.output();
  EXPECT_NE(child.output().find("interrupted by SIGINT: kept 3 finished variant(s)"), std::string::npos) << child.output();
  const json summary = read_json(out / "summary.json");
  EXPECT_FALSE(summary.contains("sensitivity"));
  EXPECT_FALSE(summary.contains("ranking"));
  std::vector<std::string> left;
  for (const fs::directory_entry& e : fs::directory_iterator(dir_)) left.push_back(e.path().filename().string());
  std::sort(left.begin(), left.end());
  EXPECT_EQ(left, (std::vector<std::string>{"out", "sens.yaml"}));
}

TEST_F(SensitivityRun, BadInputIsRefusedWithFileLineAndKey) {
  std::string text = kScenario;
  const std::string from = "stiffness_scale: [0.5]";
  text.replace(text.find(from), from.size(), "stiffness_scale: [-0.5]");
  const fs::path bad = write("bad.yaml", text);
  Result r = run({"run", bad.string(), "--sensitivity", "--no-video", "--no-plots", "--out", (dir_ / "bad").string()});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("bad.yaml:4:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("sensitivity.stiffness_scale[0]"), std::string::npos) << r.output;

  text = kScenario;
  text.replace(text.find(from), from.size(), "stiffnes_scale: [0.5]");
  const fs::path typo = write("typo.yaml", text);
  r = run({"validate", typo.string()});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("typo.yaml:4:"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("stiffness_scale"), std::string::npos) << r.output;

  const fs::path good = write("sens.yaml", kScenario);
  r = run({"run", good.string(), "--jobs", "2", "--no-video", "--no-plots", "--out", (dir_ / "x").string()});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--jobs"), std::string::npos) << r.output;
  r = run({"compare", good.string(), "--sensitivity", "--jobs", "0", "--no-video", "--no-plots", "--out", (dir_ / "y").string()});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--jobs"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "x"));
  EXPECT_FALSE(fs::exists(dir_ / "y"));
}

}  // namespace
