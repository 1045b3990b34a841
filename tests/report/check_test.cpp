#include "blendbench/report/check.hpp"

#include <gtest/gtest.h>

#include "blendbench/core/input_error.hpp"
#include "support/input_error.hpp"

namespace blendbench {
namespace {

nlohmann::json summary(double cycle, double tracking, const std::string& status = "ok", double min_speed = 100) {
  return {{"scenario", "s"},
          {"variants",
           {{{"name", "a"},
             {"status", status},
             {"metrics", {{"cycle_time_s", cycle}, {"tracking_error_max_mm", tracking}, {"min_speed_mm_s", min_speed}}}}}}};
}

// The tolerance file's form, as results/baselines/tolerances.json writes it.
const std::vector<MetricTolerance> kTolerances = parse_tolerances(
    nlohmann::json::parse(R"({"metrics": {
      "metrics.cycle_time_s": {"relative": 0.01, "absolute": 0.005, "better": "lower", "why": "x"},
      "metrics.tracking_error_max_mm": {"relative": 0.05, "absolute": 0.002},
      "metrics.min_speed_mm_s": {"relative": 0.02, "absolute": 1.0, "better": "higher"}}})"),
    "tolerances.json");

TEST(Check, TheToleranceFileIsReadWithItsDirections) {
  ASSERT_EQ(kTolerances.size(), 3u);
  for (const MetricTolerance& t : kTolerances) {
    EXPECT_EQ(t.higher_is_better, t.metric == "metrics.min_speed_mm_s") << t.metric;
  }
}

TEST(Check, SameRunPasses) {
  const nlohmann::json base = make_baseline(summary(2.0, 0.5), kTolerances);
  const CheckReport r = check_run(summary(2.0, 0.5), base, kTolerances, "b.json");
  EXPECT_TRUE(r.passed());
  EXPECT_EQ(r.rows.size(), 3u);
  EXPECT_EQ(moved_table(r), "nothing moved\n");
}

TEST(Check, RegressionBeyondToleranceFailsAndNamesTheMetric) {
  const nlohmann::json base = make_baseline(summary(2.0, 0.5), kTolerances);
  // within tolerance: 1 % + 5 ms on the cycle time
  const CheckReport within = check_run(summary(2.0 * 1.01 + 0.004, 0.5), base, kTolerances, "b.json");
  EXPECT_TRUE(within.passed());
  EXPECT_NE(moved_table(within).find("within tolerance"), std::string::npos) << moved_table(within);
  const CheckReport r = check_run(summary(2.1, 0.5), base, kTolerances, "b.json");
  ASSERT_EQ(r.regressions.size(), 1u);
  EXPECT_NE(r.regressions[0].find("a: metrics.cycle_time_s = 2.1"), std::string::npos) << r.regressions[0];
  const std::string table = moved_table(r);
  EXPECT_NE(table.find("metrics.cycle_time_s"), std::string::npos) << table;
  EXPECT_NE(table.find("REGRESSION"), std::string::npos) << table;
  EXPECT_EQ(table.find("tracking_error"), std::string::npos) << "only what moved: " << table;
  EXPECT_FALSE(check_run(summary(2.0, 0.6), base, kTolerances, "b.json").passed());
}

TEST(Check, AHigherIsBetterMetricRegressesWhenItFalls) {
  const nlohmann::json base = make_baseline(summary(2.0, 0.5, "ok", 100), kTolerances);
  // 2 % + 1 mm/s below 100 is 97
  EXPECT_TRUE(check_run(summary(2.0, 0.5, "ok", 97.5), base, kTolerances, "b.json").passed());
  const CheckReport r = check_run(summary(2.0, 0.5, "ok", 96), base, kTolerances, "b.json");
  ASSERT_EQ(r.regressions.size(), 1u);
  EXPECT_NE(r.regressions[0].find("metrics.min_speed_mm_s = 96"), std::string::npos) << r.regressions[0];
  EXPECT_NE(r.regressions[0].find("allowed down to 97"), std::string::npos) << r.regressions[0];
  // faster is an improvement, not a failure
  const CheckReport up = check_run(summary(2.0, 0.5, "ok", 150), base, kTolerances, "b.json");
  EXPECT_TRUE(up.passed());
  EXPECT_EQ(up.notes.size(), 1u);
}

TEST(Check, ImprovementIsANoteNotAFailure) {
  const nlohmann::json base = make_baseline(summary(2.0, 0.5), kTolerances);
  const CheckReport r = check_run(summary(1.5, 0.5), base, kTolerances, "b.json");
  EXPECT_TRUE(r.passed());
  ASSERT_EQ(r.notes.size(), 1u);
  EXPECT_NE(r.notes[0].find("improved"), std::string::npos);
}

TEST(Check, FailedOrMissingVariantRegresses) {
  const nlohmann::json base = make_baseline(summary(2.0, 0.5), kTolerances);
  EXPECT_FALSE(check_run(summary(2.0, 0.5, "failed"), base, kTolerances, "b.json").passed());
  nlohmann::json other = summary(2.0, 0.5);
  other["variants"][0]["name"] = "b";
  const CheckReport r = check_run(other, base, kTolerances, "b.json");
  EXPECT_FALSE(r.passed());
  EXPECT_EQ(r.notes.size(), 1u);  // b is new
  nlohmann::json unsettled = summary(2.0, 0.5);
  unsettled["variants"][0]["metrics"]["cycle_time_s"] = nullptr;
  EXPECT_FALSE(check_run(unsettled, base, kTolerances, "b.json").passed());
}

TEST(Check, AStatusTheBaselineRecordsIsNoRegression) {
  // a variant known to saturate stays gated on its metrics; becoming ok, or another status, is news
  const nlohmann::json base = make_baseline(summary(2.0, 0.5, "saturated"), kTolerances);
  EXPECT_TRUE(check_run(summary(2.0, 0.5, "saturated"), base, kTolerances, "b.json").passed());
  EXPECT_FALSE(check_run(summary(2.0, 0.5, "not_settled"), base, kTolerances, "b.json").passed());
}

TEST(Check, ABaselineOfAnotherScenarioIsBadInputThatSaysWhichToUse) {
  nlohmann::json base = make_baseline(summary(2.0, 0.5), kTolerances);
  base["scenario"] = "default";
  test::expect_input_error([&] { (void)check_run(summary(2.0, 0.5), base, kTolerances, "b.json"); },
                           {.file = "b.json", .field = "scenario", .message = "results/baselines/s.json"});
}

TEST(Check, MalformedBaselineOrToleranceFileIsBadInput) {
  EXPECT_THROW((void)check_run(summary(2.0, 0.5), nlohmann::json::object(), kTolerances, "b.json"), InputError);
  test::expect_input_error([] { (void)parse_tolerances(nlohmann::json::parse(R"({"metrics": {}})"), "t.json"); },
                           {.file = "t.json", .field = "metrics", .message = "non-empty"});
  test::expect_input_error(
      [] { (void)parse_tolerances(nlohmann::json::parse(R"({"metrics": {"m": {"relative": -1, "absolute": 0}}})"), "t.json"); },
      {.file = "t.json", .field = "metrics.m.relative", .message = ">= 0"});
  test::expect_input_error(
      [] {
        (void)parse_tolerances(nlohmann::json::parse(R"({"metrics": {"m": {"relative": 0, "absolute": 0, "better": "up"}}})"),
                               "t.json");
      },
      {.file = "t.json", .field = "metrics.m.better", .message = "'lower' or 'higher'"});
  test::expect_input_error(
      [] { (void)parse_tolerances(nlohmann::json::parse(R"({"metrics": {"m": {"relative": 0, "absolute": 0, "rel": 1}}})"), "t.json"); },
      {.file = "t.json", .field = "metrics.m.rel", .message = "unknown key"});
}

// Issue 42: a summary or baseline of the wrong shape reached nlohmann's "cannot use value() with
// array" (exit 1); every shape a check reads is checked first, naming the field.
TEST(Check, SummariesAndBaselinesOfTheWrongShapeAreBadInputNamingTheField) {
  struct Case {
    const char* json;
    const char* field;
  };
  const Case summaries[] = {{"[]", ""},
                            {R"({"scenario": 3, "variants": []})", "scenario"},
                            {R"({"scenario": "s"})", "variants"},
                            {R"({"scenario": "s", "variants": [3]})", "variants[0]"},
                            {R"({"scenario": "s", "variants": [{"name": 1}]})", "variants[0].name"},
                            {R"({"scenario": "s", "variants": [{"name": "a", "status": []}]})", "variants[0].status"},
                            // fuzz_check: a variant without a status reached make_baseline's at("status")
                            {R"({"scenario": "s", "variants": [{"name": "a", "stadus": "ok"}]})", "variants[0].status"},
                            {R"({"scenario": "s", "variants": [{"name": "a", "status": "ok", "message": 1}]})", "variants[0].message"}};
  for (const Case& c : summaries) {
    test::expect_input_error([&] { validate_run_summary(nlohmann::json::parse(c.json), "run/summary.json"); },
                             {.file = "run/summary.json", .field = c.field}, c.json);
  }
  EXPECT_NO_THROW(validate_run_summary(summary(2.0, 0.5), "run/summary.json"));
  const Case baselines[] = {{R"({"scenario": "s", "variants": {"a": 3}})", "variants.a"},
                            {R"({"scenario": "s", "variants": {"a": {"status": 1}}})", "variants.a.status"}};
  for (const Case& c : baselines) {
    test::expect_input_error([&] { (void)check_run(summary(2.0, 0.5), nlohmann::json::parse(c.json), kTolerances, "b.json"); },
                             {.file = "b.json", .field = c.field}, c.json);
  }
  test::expect_input_error(
      [] { (void)parse_tolerances(nlohmann::json::parse(R"({"metrics": {"m": {"relative": 0, "absolute": 0, "better": 1}}})"), "t.json"); },
      {.file = "t.json", .field = "metrics.m.better", .message = "must be a string"});
}

}  // namespace
}  // namespace blendbench
