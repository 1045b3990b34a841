// `blendbench compare` and `blendbench run part.ngc` as a user meets them (docs/compare.md): the
// variants at each tolerance, the ranking against the summary's own cycle times, the
// recommendation with and without constraints, a compare variant equal to a `run` of the same
// transition, a file with no corners, a tolerance no corner reaches, one corner numbering in
// corners.json and report.html, and bad flags refused (exit 2 naming the flag). Small programs
// without video, so the suite stays fast.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "support/program.hpp"
#include "support/source_tree.hpp"

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// The figures of one variant that a compare and a run of the same transition must share exactly
// (the pipeline is deterministic on one machine: test regression_deterministic).
const char* const kSameFigures[] = {"cycle_time_s", "tracking_error_max_mm", "contour_error_programmed_max_mm",
                                    "contour_error_planned_max_mm", "residual_vibration_final_mm"};

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

std::string read_text(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

const json& variant(const json& summary, const std::string& name) {
  for (const json& v : summary.at("variants")) {
    if (v.at("name") == name) return v;
  }
  throw std::runtime_error("no variant " + name);
}

class Compare : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("blendbench_compare_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A file in the test folder.
  fs::path write(const std::string& name, const std::string& text) const {
    const fs::path file = dir_ / name;
    std::ofstream(file) << text;
    return file;
  }

  static std::string tiny() { return blendbench::test::source_path("tests/data/tiny.yaml"); }

  fs::path dir_;
};

// A 40 x 30 mm rectangle at 100 mm/s with its own tolerance (G64 P0.2), corners on lines 3-5.
const char* const kSquare =
    "G21 G90 G17\n"
    "G64 P0.2\n"
    "G1 X40 F6000\n"
    "G1 Y30\n"
    "G1 X0\n"
    "G1 Y0\n"
    "M2\n";

// The ranking of a summary against the summary's own variants: ordered by cycle time, margins
// their differences, every ranked variant clean.
void expect_ranking_consistent(const json& summary) {
  ASSERT_TRUE(summary.contains("ranking"));
  for (const json& group : summary.at("ranking").at("tolerances")) {
    const json& ranked = group.at("variants");
    for (std::size_t k = 0; k < ranked.size(); ++k) {
      const json& r = ranked[k];
      const json& v = variant(summary, r.at("variant"));
      EXPECT_EQ(v.at("status"), "ok") << r;
      EXPECT_EQ(r.at("cycle_time_s").get<double>(), v.at("metrics").at("cycle_time_s").get<double>()) << r;
      if (k + 1 < ranked.size()) {
        const double next = ranked[k + 1].at("cycle_time_s").get<double>();
        const double t = r.at("cycle_time_s").get<double>();
        EXPECT_LE(t, next);
        EXPECT_NEAR(r.at("margin_to_next_s").get<double>(), next - t, 1e-12);
        EXPECT_NEAR(r.at("margin_to_next_percent").get<double>(), 100 * (next - t) / t, 1e-9);
      } else {
        EXPECT_TRUE(r.at("margin_to_next_s").is_null());
      }
    }
  }
}

TEST_F(Compare, AScenarioRunsBothBaselinesAndEveryMethodAtEachTolerance) {
  const fs::path out = dir_ / "out";
  const Result r = run({"compare", tiny(), "--tolerance", "0.5", "--tolerance", "2", "--no-video", "--no-plots", "--out",
                        out.string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json summary = read_json(out / "summary.json");
  std::vector<std::string> names;
  for (const json& v : summary.at("variants")) names.push_back(v.at("name"));
  const std::vector<std::string> expected = {"exact_stop",    "junction_slowdown", "arc_0.5mm",      "bezier_0.5mm",
                                             "clothoid_0.5mm", "biclothoid_0.5mm",  "arc_2mm",        "bezier_2mm",
                                             "clothoid_2mm",   "biclothoid_2mm"};
  EXPECT_EQ(names, expected);
  // each method ran at its tolerance: every corner's deviation is it (within 1 %), never above
  for (const json& v : summary.at("variants")) {
    if (v.at("method") == "none") continue;
    const double t = v.at("tolerance_mm").get<double>();
    for (const json& c : v.at("plan").at("corners")) {
      EXPECT_EQ(c.at("tolerance_mm").get<double>(), t);
      EXPECT_LE(c.at("deviation_mm").get<double>(), t * (1 + 1e-9)) << v.at("name");
      if (c.at("tolerance_reached").get<bool>()) {
        EXPECT_GE(c.at("deviation_mm").get<double>(), 0.99 * t) << v.at("name");
      }
    }
  }
  // the scenario's own variants (exact, arc) did not run, and a note says so
  EXPECT_NE(r.output.find("variant(s) are not run"), std::string::npos) << r.output;
  // two rankings, one per tolerance, each with the two baselines and the four methods
  const json& groups = summary.at("ranking").at("tolerances");
  ASSERT_EQ(groups.size(), 2U);
  EXPECT_EQ(groups[0].at("tolerance_mm").get<double>(), 0.5);
  EXPECT_EQ(groups[1].at("tolerance_mm").get<double>(), 2.0);
  for (const json& g : groups) EXPECT_EQ(g.at("variants").size() + g.at("unranked").size(), 6U);
  expect_ranking_consistent(summary);
  // the recommendation is the fastest clean variant (or ties with it)
  ASSERT_TRUE(summary.at("recommendation").at("variant").is_string()) << summary.at("recommendation");
  double fastest = 1e9;
  for (const json& v : summary.at("variants")) {
    if (v.at("status") == "ok") fastest = std::min(fastest, v.at("metrics").at("cycle_time_s").get<double>());
  }
  const json& chosen = variant(summary, summary.at("recommendation").at("variant"));
  const double threshold = std::max(0.005, 0.01 * fastest);
  EXPECT_LT(chosen.at("metrics").at("cycle_time_s").get<double>() - fastest, threshold);
  EXPECT_NE(r.output.find("recommendation: "), std::string::npos);
}

TEST_F(Compare, AVariantEqualsARunOfTheSameTransition) {
  const fs::path compared = dir_ / "compared";
  ASSERT_EQ(run({"compare", tiny(), "--tolerance", "1", "--methods", "arc", "--no-video", "--no-plots", "--out",
                 compared.string()})
                .exit_code,
            0);
  // the same transition written as a scenario variant, run plainly
  std::string text = read_text(tiny());
  const std::string from = "  - {name: arc, transition: {method: arc, parameter: 5}}";
  text.replace(text.find(from), from.size(), "  - {name: arc_1mm, transition: {method: arc, tolerance: 1}}");
  const fs::path scenario = write("tiny_arc_1mm.yaml", text);
  const fs::path ran = dir_ / "ran";
  ASSERT_EQ(run({"run", scenario.string(), "--no-video", "--no-plots", "--out", ran.string()}).exit_code, 0);
  const json a = variant(read_json(compared / "summary.json"), "arc_1mm");
  const json b = variant(read_json(ran / "summary.json"), "arc_1mm");
  for (const char* key : kSameFigures) EXPECT_EQ(a.at("metrics").at(key), b.at("metrics").at(key)) << key;
  EXPECT_EQ(a.at("plan").at("planned_cycle_time_s"), b.at("plan").at("planned_cycle_time_s"));
  EXPECT_EQ(a.at("plan").at("path_deviation_max_mm"), b.at("plan").at("path_deviation_max_mm"));
  // and the exact stops agree
  const json x = variant(read_json(compared / "summary.json"), "exact_stop");
  const json y = variant(read_json(ran / "summary.json"), "exact");
  EXPECT_EQ(x.at("metrics").at("cycle_time_s"), y.at("metrics").at("cycle_time_s"));
}

TEST_F(Compare, AGcodePartTakesItsG64ToleranceAndNamesItsLinesInTheReport) {
  const fs::path part = write("square.ngc", kSquare);
  const fs::path out = dir_ / "out";
  const Result r = run({"compare", part.string(), "--methods", "arc", "--no-video", "--out", out.string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json summary = read_json(out / "summary.json");
  EXPECT_EQ(summary.at("variants").size(), 3U);
  const json& arc = variant(summary, "arc_0.2mm");
  EXPECT_NE(r.output.find("tolerance from the program's G64 P: 0.2 mm"), std::string::npos) << r.output;
  expect_ranking_consistent(summary);
  // corners: numbered and sourced as the program writes them, the same in corners.json, the
  // summary and the report; points in the program's own coordinates
  const json corners = read_json(out / "arc_0.2mm" / "corners.json");
  ASSERT_EQ(corners.size(), 3U);
  const std::string report = read_text(out / "report.html");
  const double expected_points[3][2] = {{40, 0}, {40, 30}, {0, 30}};
  for (std::size_t k = 0; k < corners.size(); ++k) {
    const json& c = corners[k];
    EXPECT_EQ(c.at("source_line").get<int>(), static_cast<int>(k) + 3);
    EXPECT_EQ(fs::path(c.at("source_file").get<std::string>()).filename(), "square.ngc");
    EXPECT_EQ(c, arc.at("plan").at("corners")[k]);
    std::string name = "C";
    name += std::to_string(c.at("index").get<int>());  // not "C" + ...: GCC 12 -Wrestrict false positive
    // the corner table: its name, its line and its point as programmed
    const std::string row = "<td>" + name + "</td><td>square.ngc:" + std::to_string(k + 3) + "</td>";
    EXPECT_NE(report.find(row), std::string::npos) << row;
    char point[64];
    std::snprintf(point, sizeof point, "%.3f, %.3f, 0.000", expected_points[k][0], expected_points[k][1]);
    EXPECT_NE(report.find(point), std::string::npos) << point;
  }
  // the answer comes first: the recommendation before the comparison table
  const auto answer = report.find("Recommended: ");
  ASSERT_NE(answer, std::string::npos);
  EXPECT_LT(answer, report.find("<h2>Comparison</h2>"));
}

TEST_F(Compare, TheRecommendationHonoursTheConstraintsOrSaysNoneMeetsThem) {
  const fs::path out = dir_ / "out";
  // a contour error below the servo's own tens of micrometres: no variant meets it
  Result r = run({"compare", tiny(), "--tolerance", "1", "--methods", "bezier", "--no-video", "--no-plots",
                  "--max-contour-error", "0.001", "--out", out.string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  json summary = read_json(out / "summary.json");
  EXPECT_TRUE(summary.at("recommendation").at("variant").is_null());
  EXPECT_NE(summary.at("recommendation").at("reason").get<std::string>().find("none of the"), std::string::npos);
  EXPECT_EQ(summary.at("ranking").at("constraints").at("max_contour_error_mm").get<double>(), 0.001);
  // a contour error of 0.5 mm: the 1 mm Bezier is out, a baseline is in
  r = run({"compare", tiny(), "--tolerance", "1", "--methods", "bezier", "--no-video", "--no-plots", "--max-contour-error",
           "0.5", "--max-vibration", "1000", "--out", out.string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  summary = read_json(out / "summary.json");
  const std::string chosen = summary.at("recommendation").at("variant");
  EXPECT_LE(variant(summary, chosen).at("metrics").at("contour_error_programmed_max_mm").get<double>(), 0.5);
  EXPECT_GT(variant(summary, "bezier_1mm").at("metrics").at("contour_error_programmed_max_mm").get<double>(), 0.5);
  EXPECT_NE(chosen, "bezier_1mm");
}

TEST_F(Compare, AFileWithNoCornersRunsTheExactStopAloneWithANote) {
  const fs::path part = write("line.ngc", "G21 G90\nG1 X50 F3000\nG1 X80\nM2\n");
  const fs::path out = dir_ / "out";
  const Result r = run({"compare", part.string(), "--no-video", "--no-plots", "--out", out.string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json summary = read_json(out / "summary.json");
  ASSERT_EQ(summary.at("variants").size(), 1U);
  EXPECT_EQ(summary.at("variants")[0].at("name"), "exact_stop");
  ASSERT_EQ(summary.at("notes").size(), 1U);
  EXPECT_NE(summary.at("notes")[0].get<std::string>().find("no corners"), std::string::npos);
  EXPECT_NE(r.output.find("note: no corners"), std::string::npos) << r.output;
}

// (report.html's line at the top for such a tolerance: tests/plot_scripts_test.py)
TEST_F(Compare, AToleranceNoCornerReachesRuns) {
  const fs::path out = dir_ / "out";
  // the tiny scenario's 60 mm moves cannot hold a 90 degree corner cut 100 mm deep
  const Result r = run({"compare", tiny(), "--tolerance", "100", "--methods", "clothoid", "--no-video", "--no-plots", "--out",
                        out.string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json summary = read_json(out / "summary.json");
  const json& v = variant(summary, "clothoid_100mm");
  for (const json& c : v.at("plan").at("corners")) {
    EXPECT_FALSE(c.at("tolerance_reached").get<bool>());
    EXPECT_LT(c.at("deviation_mm").get<double>(), 100);
  }
  expect_ranking_consistent(summary);
}

TEST_F(Compare, RunTakesAGcodeFileItsOwnBlendingAndTheExactStop) {
  const fs::path part = write("square.ngc", kSquare);
  const fs::path out = dir_ / "out";
  const Result r = run({"run", part.string(), "--no-video", "--no-plots", "--out", out.string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json summary = read_json(out / "summary.json");
  ASSERT_EQ(summary.at("variants").size(), 2U);
  EXPECT_EQ(summary.at("scenario"), "square.ngc");
  const json& programmed = variant(summary, "as_programmed");
  EXPECT_EQ(programmed.at("method"), "biclothoid");  // G64 P0.2
  for (const json& c : programmed.at("plan").at("corners")) EXPECT_NEAR(c.at("deviation_mm").get<double>(), 0.2, 1e-6);
  EXPECT_EQ(variant(summary, "exact_stop").at("method"), "none");
  EXPECT_NE(r.output.find("blendbench compare " + part.string()), std::string::npos) << r.output;
  // the part placed in front of the robot, its box centred at (450, 0, 200) mm
  const json& frame = summary.at("frame").at("position_mm");
  EXPECT_NEAR(frame[0].get<double>(), 450 - 20, 1e-9);
  EXPECT_NEAR(frame[1].get<double>(), 0 - 15, 1e-9);
  EXPECT_NEAR(frame[2].get<double>(), 200, 1e-9);
}

TEST_F(Compare, BadFlagsAreRefusedNamingTheFlag) {
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"--tolerance", "0"}, "--tolerance"},
      {{"--tolerance", "-1"}, "--tolerance"},
      {{"--tolerance", "nan"}, "--tolerance"},
      {{"--tolerance", "0.5", "--tolerance", "inf"}, "--tolerance"},
      {{"--methods", "arc,spline"}, "--methods"},
      {{"--methods", "none"}, "--methods"},
      {{"--max-contour-error", "0"}, "--max-contour-error"},
      {{"--max-vibration", "-5"}, "--max-vibration"},
      {{"--robot", "no_such_robot"}, "--robot"},
      {{"--limits", "sideways"}, "--limits"},
  };
  for (const auto& [flags, name] : cases) {
    std::vector<std::string> args = {"compare", tiny(), "--no-video", "--no-plots", "--out", (dir_ / "bad").string()};
    args.insert(args.end(), flags.begin(), flags.end());
    const Result r = run(args);
    EXPECT_EQ(r.exit_code, 2) << flags.front() << ": " << r.output;
    EXPECT_NE(r.output.find("'" + name + "'"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir_ / "bad")) << flags.front();
  }
  // no input
  const Result r = run({"compare"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
}

}  // namespace
