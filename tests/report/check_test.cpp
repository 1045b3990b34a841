#include "blendbench/report/check.hpp"

#include <gtest/gtest.h>

#include "blendbench/core/input_error.hpp"

namespace blendbench {
namespace {

nlohmann::json summary(double cycle, double tracking, const std::string& status = "ok") {
  return {{"scenario", "s"},
          {"variants",
           {{{"name", "a"},
             {"status", status},
             {"metrics", {{"cycle_time_s", cycle}, {"tracking_error_max_mm", tracking}}}}}}};
}

TEST(Check, SameRunPasses) {
  const nlohmann::json base = make_baseline(summary(2.0, 0.5));
  EXPECT_TRUE(check_run(summary(2.0, 0.5), base, "b.json").passed());
}

TEST(Check, RegressionBeyondToleranceFailsAndNamesTheMetric) {
  const nlohmann::json base = make_baseline(summary(2.0, 0.5));
  // within tolerance: 1 % + 5 ms on the cycle time
  EXPECT_TRUE(check_run(summary(2.0 * 1.01 + 0.004, 0.5), base, "b.json").passed());
  const CheckReport r = check_run(summary(2.1, 0.5), base, "b.json");
  ASSERT_EQ(r.regressions.size(), 1u);
  EXPECT_NE(r.regressions[0].find("a: metrics.cycle_time_s = 2.1"), std::string::npos) << r.regressions[0];
  EXPECT_FALSE(check_run(summary(2.0, 0.6), base, "b.json").passed());
}

TEST(Check, ImprovementIsANoteNotAFailure) {
  const nlohmann::json base = make_baseline(summary(2.0, 0.5));
  const CheckReport r = check_run(summary(1.5, 0.5), base, "b.json");
  EXPECT_TRUE(r.passed());
  ASSERT_EQ(r.notes.size(), 1u);
  EXPECT_NE(r.notes[0].find("improved"), std::string::npos);
}

TEST(Check, FailedOrMissingVariantRegresses) {
  const nlohmann::json base = make_baseline(summary(2.0, 0.5));
  EXPECT_FALSE(check_run(summary(2.0, 0.5, "failed"), base, "b.json").passed());
  nlohmann::json other = summary(2.0, 0.5);
  other["variants"][0]["name"] = "b";
  const CheckReport r = check_run(other, base, "b.json");
  EXPECT_FALSE(r.passed());
  EXPECT_EQ(r.notes.size(), 1u);  // b is new
  nlohmann::json unsettled = summary(2.0, 0.5);
  unsettled["variants"][0]["metrics"]["cycle_time_s"] = nullptr;
  EXPECT_FALSE(check_run(unsettled, base, "b.json").passed());
}

TEST(Check, MalformedBaselineIsBadInput) {
  EXPECT_THROW((void)check_run(summary(2.0, 0.5), nlohmann::json::object(), "b.json"), InputError);
}

}  // namespace
}  // namespace blendbench
