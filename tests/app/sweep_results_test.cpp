// The sweep's table: metrics flattened from run summaries, rows and their statuses, constraint
// marks, the Pareto front and the best setting per method (checked against brute force on random
// tables), and the CSV form.

#include "blendbench/app/sweep_results.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>

#include "support/input_error.hpp"
#include "support/property.hpp"

namespace blendbench {
namespace {

using nlohmann::json;

// A plan with one axis `p` of `n` values and the given variants at every point (no scenario: the
// table needs only the axes and the points).
SweepPlan plan_of(std::size_t n, const std::vector<std::string>& variants, const std::vector<std::string>& constraints = {}) {
  SweepPlan plan;
  SweepAxis axis;
  axis.path = "p";
  for (std::size_t i = 0; i < n; ++i) {
    axis.values.push_back(std::to_string(i));
    axis.labels.push_back(std::to_string(i));
  }
  plan.spec.axes.push_back(axis);
  plan.spec.pareto_x = "x_s";
  plan.spec.pareto_y = "y_mm";
  for (const std::string& c : constraints) plan.spec.constraints.push_back(parse_constraint(c, {}, "constraints"));
  for (std::size_t i = 0; i < n; ++i) {
    SweepPoint p;
    p.index = i;
    p.choice = {i};
    p.variants = variants;
    p.hash = std::to_string(i);
    plan.points.push_back(p);
  }
  return plan;
}

json entry(const std::string& name, const std::string& method, double x, double y) {
  return {{"name", name}, {"method", method}, {"status", "ok"}, {"x_s", x}, {"y_mm", y}};
}

// Every metric name of the ok variants of the outcomes.
std::set<std::string> known_of(const std::vector<PointOutcome>& outcomes) {
  std::set<std::string> known;
  for (const PointOutcome& o : outcomes) {
    for (const VariantResult& v : o.variants) {
      if (v.status != "ok") continue;
      for (const auto& [k, value] : v.metrics) known.insert(k);
    }
  }
  return known;
}

SweepTable table_of(const SweepPlan& plan, const std::vector<PointOutcome>& outcomes) {
  return build_table(plan, outcomes, known_of(outcomes));
}

PointOutcome ok_outcome(const std::vector<json>& entries) {
  PointOutcome o;
  o.status = "ok";
  o.has_summary = true;
  o.variants = variant_results({{"variants", entries}}, {});
  return o;
}

TEST(Flatten, NumbersByDottedNameAndIndexBooleansAndNulls) {
  const json e = {{"name", "arc"},
                  {"cycle_time_s", 1.5},
                  {"settled", true},
                  {"diverged", false},
                  {"not_settled_s", nullptr},
                  {"torque_peak_nm", {1.0, 2.0, 3.0}},
                  {"residual", {{"amplitude_mm", 0.01}, {"frequency_hz", {{"first", 7.5}}}}},
                  {"corners", {{{"index", 0}, {"deviation_mm", 0.1}}}},
                  {"method", "arc"}};
  const std::map<std::string, double> m = flatten_metrics(e);
  EXPECT_DOUBLE_EQ(m.at("cycle_time_s"), 1.5);
  EXPECT_DOUBLE_EQ(m.at("settled"), 1.0);
  EXPECT_DOUBLE_EQ(m.at("diverged"), 0.0);
  EXPECT_TRUE(std::isnan(m.at("not_settled_s")));
  EXPECT_DOUBLE_EQ(m.at("torque_peak_nm[2]"), 3.0);
  EXPECT_DOUBLE_EQ(m.at("residual.amplitude_mm"), 0.01);
  EXPECT_DOUBLE_EQ(m.at("residual.frequency_hz.first"), 7.5);
  // a list of objects by index and field; strings are not metrics
  EXPECT_DOUBLE_EQ(m.at("corners[0].deviation_mm"), 0.1);
  EXPECT_DOUBLE_EQ(m.at("corners[0].index"), 0.0);
  EXPECT_EQ(m.count("name"), 0U);
  EXPECT_EQ(m.count("method"), 0U);
  EXPECT_EQ(m.size(), 11U);
}

// The table keeps what it can show: default metrics and the ones the sweep names; a report
// field is known (a sweep may name it) but is no default column.
TEST(Flatten, VariantResultsKeepDefaultAndNamedMetrics) {
  const json summary = {{"variants",
                         {{{"name", "a"},
                           {"status", "ok"},
                           {"x_s", 1.0},
                           {"sim_wall_time_s", 0.2},
                           {"corners", {{{"deviation_mm", 0.1}}, {{"deviation_mm", 0.3}}}}}}}};
  std::set<std::string> known;
  const std::vector<VariantResult> r = variant_results(summary, {"corners[1].deviation_mm"}, &known);
  ASSERT_EQ(r.size(), 1U);
  EXPECT_EQ(r[0].metrics.size(), 2U);
  EXPECT_EQ(r[0].metrics.count("x_s"), 1U);
  EXPECT_EQ(r[0].metrics.count("corners[1].deviation_mm"), 1U);
  EXPECT_EQ(known, (std::set<std::string>{"corners[0].deviation_mm", "corners[1].deviation_mm", "sim_wall_time_s", "x_s"}));
  EXPECT_TRUE(report_field("corners[1].deviation_mm"));
  EXPECT_FALSE(report_field("torque_peak_nm[1]"));
  EXPECT_TRUE(default_metric("torque_peak_nm[1]"));
  EXPECT_FALSE(default_metric("corners[1].deviation_mm"));
  EXPECT_FALSE(default_metric("sim_wall_time_s"));
}

TEST(Flatten, MachineMetricsAreTheClockOnes) {
  EXPECT_TRUE(machine_metric("sim_wall_time_s"));
  EXPECT_TRUE(machine_metric("real_time_factor_with_video"));
  EXPECT_TRUE(machine_metric("timing.planning_wall_time_s"));
  EXPECT_FALSE(machine_metric("cycle_time_s"));
  EXPECT_FALSE(machine_metric("simulated_time_s"));
}

TEST(Table, RowsTakeTheVariantsStatusAndThePointsWhenTheRunStopped) {
  SweepPlan plan = plan_of(3, {"a", "b"});
  std::vector<PointOutcome> outcomes;
  outcomes.push_back(ok_outcome({entry("a", "arc", 1, 1), entry("b", "bezier", 2, 2)}));
  PointOutcome failed = ok_outcome({entry("a", "arc", 1, 1), {{"name", "b"}, {"status", "failed"}, {"message", "diverged"}}});
  failed.status = "failed";
  outcomes.push_back(failed);
  PointOutcome crashed;
  crashed.status = "crashed";
  crashed.message = "killed by signal 11";
  outcomes.push_back(crashed);
  const SweepTable t = table_of(plan, outcomes);
  ASSERT_EQ(t.rows.size(), 6U);
  EXPECT_EQ(t.rows[3].status, "failed");
  EXPECT_EQ(t.rows[3].message, "diverged");
  EXPECT_EQ(t.rows[2].status, "ok");
  EXPECT_EQ(t.rows[4].status, "crashed");
  EXPECT_EQ(t.rows[5].message, "killed by signal 11");
  // the method of a row that has no entry comes from the variant's entry elsewhere
  EXPECT_EQ(t.rows[5].method, "bezier");
  EXPECT_EQ(t.metrics, (std::vector<std::string>{"x_s", "y_mm"}));
}

TEST(Table, UnknownMetricNamesAreRefusedWithTheKnownOnes) {
  SweepPlan plan = plan_of(1, {"a"}, {"z_mm <= 1"});
  plan.spec.named_metrics.push_back({"z_mm", "constraints[0]", {"s.yaml", 6, 3}});
  test::expect_input_error([&] { (void)table_of(plan, {ok_outcome({entry("a", "arc", 1, 1)})}); },
                           {.file = "s.yaml", .line = 6, .field = "constraints[0]", .message = "no metric 'z_mm' in the runs' summaries (metrics: x_s, y_mm)"});
}

// Random tables: a row is on its method's front exactly when no ok row of the method dominates
// it, and the best row is the least x (then y) among the rows meeting the constraints.
TEST(Table, ParetoFrontAndBestAgreeWithBruteForce) {
  const int cases = test::property_cases(100);
  for (int k = 0; k < cases; ++k) {
    const std::uint64_t seed = 14000 + static_cast<std::uint64_t>(k);
    auto rng = test::make_rng(seed);
    const std::size_t n = 1 + static_cast<std::size_t>(test::uniform(rng, 0, 40));
    const SweepPlan plan = plan_of(n, {"a", "b"}, {"y_mm <= 0.6"});
    std::vector<PointOutcome> outcomes;
    for (std::size_t i = 0; i < n; ++i) {
      // coarse values, so ties and repeats happen
      const auto coarse = [&] { return std::round(test::uniform(rng, 0, 10)) / 10; };
      std::vector<json> entries = {entry("a", "arc", coarse(), coarse()), entry("b", "bezier", coarse(), coarse())};
      if (test::uniform(rng, 0, 1) < 0.1) entries[1]["status"] = "failed";
      outcomes.push_back(ok_outcome(entries));
    }
    const SweepTable t = table_of(plan, outcomes);
    const auto x = [&](std::size_t r) { return t.rows[r].metrics.at("x_s"); };
    const auto y = [&](std::size_t r) { return t.rows[r].metrics.at("y_mm"); };
    for (const MethodSummary& m : t.methods) {
      std::optional<std::size_t> best;
      for (std::size_t r = 0; r < t.rows.size(); ++r) {
        if (t.rows[r].method != m.method) continue;
        if (t.rows[r].status != "ok") {
          EXPECT_FALSE(t.rows[r].on_pareto_front) << test::seed_text(seed);
          EXPECT_FALSE(t.rows[r].meets_constraints) << test::seed_text(seed);
          continue;
        }
        bool dominated = false;
        for (std::size_t q = 0; q < t.rows.size(); ++q) {
          if (t.rows[q].method != m.method || t.rows[q].status != "ok") continue;
          dominated = dominated || (x(q) <= x(r) && y(q) <= y(r) && (x(q) < x(r) || y(q) < y(r)));
        }
        EXPECT_EQ(t.rows[r].on_pareto_front, !dominated) << test::seed_text(seed) << " row " << r;
        EXPECT_EQ(t.rows[r].meets_constraints, y(r) <= 0.6) << test::seed_text(seed);
        if (t.rows[r].meets_constraints && (!best || x(r) < x(*best) || (x(r) == x(*best) && y(r) < y(*best)))) best = r;
      }
      EXPECT_EQ(m.best, best) << test::seed_text(seed) << " " << m.method;
      for (std::size_t i = 1; i < m.front.size(); ++i) EXPECT_LE(x(m.front[i - 1]), x(m.front[i])) << test::seed_text(seed);
    }
    // methods by their best x, those without a best last
    for (std::size_t i = 1; i < t.methods.size(); ++i) {
      if (t.methods[i].best) {
        ASSERT_TRUE(t.methods[i - 1].best) << test::seed_text(seed);
        EXPECT_LE(x(*t.methods[i - 1].best), x(*t.methods[i].best)) << test::seed_text(seed);
      }
    }
  }
}

TEST(Table, CsvHasTheNamedColumnsAndEmptyCellsForMissingMetrics) {
  SweepPlan plan = plan_of(2, {"a"});
  plan.spec.axes[0].path = "variants[*].transition.parameter";
  plan.spec.axes[0].labels = {"0.5", "[1, 2]"};
  json with_extra = entry("a", "arc", 1, 0.25);
  with_extra["extra_mm"] = 3;
  with_extra["sim_wall_time_s"] = 0.01;
  const SweepTable t = table_of(plan, {ok_outcome({with_extra}), ok_outcome({entry("a", "arc", 2, 0.5)})});
  EXPECT_EQ(sweep_csv(plan, t),
            "point,variant,method,variants[*].transition.parameter,status,meets_constraints,on_pareto_front,extra_mm,x_s,y_mm\n"
            "0,a,arc,0.5,ok,true,true,3,1,0.25\n"
            "1,a,arc,\"[1, 2]\",ok,true,false,,2,0.5\n");
  EXPECT_EQ(best_csv(plan, t), "method,variant,point,variants[*].transition.parameter,x_s,y_mm\narc,a,0,0.5,1,0.25\n");
  const std::string html = report_html(plan, t, "PNG");
  EXPECT_NE(html.find("data:image/png;base64,UE5H"), std::string::npos);
}

TEST(Table, TheBestSettingsTextReadsEachMetricInOneCountOfDecimals) {
  // two methods whose metrics differ in magnitude: every cell of a column gets the decimals of
  // three significant digits of its smallest value, a time in s at least the ms; best.csv keeps
  // every digit
  const SweepPlan plan = plan_of(1, {"a", "b"});
  const SweepTable t = table_of(plan, {ok_outcome({entry("a", "arc", 1.8541234, 0.8710605408), entry("b", "bezier", 12.5, 0.0622486)})});
  const std::string text = best_text(plan, t);
  EXPECT_NE(text.find(" 1.854 "), std::string::npos) << text;
  EXPECT_NE(text.find(" 12.500 "), std::string::npos) << text;
  EXPECT_NE(text.find(" 0.8711"), std::string::npos) << text;
  EXPECT_NE(text.find(" 0.0622"), std::string::npos) << text;
  EXPECT_EQ(text.find("0.8710605408"), std::string::npos) << text;
  EXPECT_NE(best_csv(plan, t).find("0.8710605408"), std::string::npos);
}

}  // namespace
}  // namespace blendbench
