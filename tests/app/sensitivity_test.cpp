// The sensitivity study's conclusions (app/sensitivity.hpp): holds_in and its counts against a
// direct count over the models, the difference range, the statement, the JSON block, and the
// ranking's tie decided by the study's cycle-time conclusions.

#include "blendbench/app/sensitivity.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <map>

#include "support/property.hpp"

namespace blendbench {
namespace {

constexpr double kPeriod = 0.002;  // s, the default setpoint period (500 Hz)
// Differences are ratios of figures: exact up to rounding.
constexpr double kPercentTolerance = 1e-9;

// A clean run with the given cycle time (s) and the other figures from `base` (m).
SensitivityRun clean(double cycle, double base = 1e-4) {
  SensitivityRun run;
  run.figures = HeadlineFigures{cycle, base, base, base, base};
  return run;
}

SensitivityVariant variant(const std::string& name, double nominal, const std::vector<double>& perturbed) {
  SensitivityVariant v;
  v.name = name;
  v.nominal = clean(nominal);
  for (const double t : perturbed) v.perturbed.push_back(clean(t));
  return v;
}

std::vector<Perturbation> perturbations(std::size_t n) {
  std::vector<Perturbation> out = default_perturbations();
  out.resize(n);
  return out;
}

const Conclusion& find(const std::vector<Conclusion>& all, const std::string& a, const std::string& b, Headline metric) {
  const auto it = std::find_if(all.begin(), all.end(), [&](const Conclusion& c) {
    return c.metric == metric && ((c.better == a && c.worse == b) || (c.better == b && c.worse == a));
  });
  EXPECT_NE(it, all.end()) << a << " vs " << b;
  return *it;
}

TEST(Sensitivity, AnOrderThatFlipsInOneModelHoldsInSome) {
  // A is faster than B on the nominal model and on two of three perturbed ones; C is slower
  // than both everywhere
  const std::vector<SensitivityVariant> variants = {variant("A", 4.0, {4.1, 4.3, 3.9}), variant("B", 4.2, {4.2, 4.2, 4.3}),
                                                    variant("C", 5.0, {5.0, 5.1, 5.2})};
  const std::vector<Conclusion> all = conclude(perturbations(3), variants);
  EXPECT_EQ(all.size(), 3u * kHeadlines);  // three pairs, five metrics each

  const Conclusion& ab = find(all, "A", "B", Headline::kCycleTime);
  EXPECT_EQ(ab.better, "A");
  EXPECT_EQ(ab.holds_in, OrderHolds::kSome);
  EXPECT_EQ(ab.models, 3);
  EXPECT_EQ(ab.holds, 2);
  EXPECT_EQ(ab.fails_in, (std::vector<std::string>{default_perturbations()[1].name}));
  EXPECT_TRUE(ab.unresolved.empty());
  // (worse - better) / worse: nominal 0.2 / 4.2, reversed by 0.1 / 4.2 in the second model
  EXPECT_NEAR(ab.difference_nominal, 100 * 0.2 / 4.2, kPercentTolerance);
  EXPECT_NEAR(ab.difference_min, -100 * 0.1 / 4.2, kPercentTolerance);
  EXPECT_NEAR(ab.difference_max, 100 * 0.4 / 4.3, kPercentTolerance);
  EXPECT_EQ(ab.statement, "A is faster (settled cycle time) than B by -2.4 to 9.3 %");

  const Conclusion& bc = find(all, "B", "C", Headline::kCycleTime);
  EXPECT_EQ(bc.better, "B");
  EXPECT_EQ(bc.holds_in, OrderHolds::kAll);
  EXPECT_EQ(bc.holds, 3);
  EXPECT_EQ(bc.statement, "B is faster (settled cycle time) than C by 16.0-17.6 %");

  // equal figures stay equal in every model: "the same", holding everywhere
  const Conclusion& same = find(all, "A", "B", Headline::kContourProgrammed);
  EXPECT_EQ(same.holds_in, OrderHolds::kAll);
  EXPECT_NE(same.statement.find("the same contour error against the program"), std::string::npos) << same.statement;
}

TEST(Sensitivity, AReversedOrderInEveryModelHoldsInNoneAndAMissingFigureIsUnresolved) {
  std::vector<SensitivityVariant> variants = {variant("A", 4.0, {4.5, 4.5}), variant("B", 4.1, {4.2, 4.2})};
  EXPECT_EQ(find(conclude(perturbations(2), variants), "A", "B", Headline::kCycleTime).holds_in, OrderHolds::kNone);
  // B saturates on the second model: no figure there, so the order is not known to hold
  variants[0].perturbed[0] = clean(3.9);
  variants[1].perturbed[1] = SensitivityRun{"saturated", "torque saturated", std::nullopt};
  const Conclusion c = find(conclude(perturbations(2), variants), "A", "B", Headline::kCycleTime);
  EXPECT_EQ(c.holds_in, OrderHolds::kSome);
  EXPECT_EQ(c.holds, 1);
  EXPECT_EQ(c.unresolved, (std::vector<std::string>{default_perturbations()[1].name}));
  EXPECT_EQ(c.fails_in, c.unresolved);
  // a variant without a nominal figure (did not settle) has no conclusion on that metric
  variants[1].nominal.figures->at(0).reset();
  for (const Conclusion& k : conclude(perturbations(2), variants)) EXPECT_NE(k.metric, Headline::kCycleTime);
}

// Random studies: each conclusion's counts, holds_in and difference range against a direct
// count over the models, and the spread the ranking reads against the cycle-time conclusions.
TEST(SensitivityProperty, CountsAndRangesAgreeWithTheFigures) {
  const int cases = test::property_cases(300);
  for (int n = 0; n < cases; ++n) {
    const std::uint64_t seed = 4600000 + static_cast<std::uint64_t>(n);
    std::mt19937_64 rng = test::make_rng(seed);
    const std::size_t models = 1 + rng() % 8;
    const std::size_t count = 2 + rng() % 4;
    std::vector<SensitivityVariant> variants;
    for (std::size_t v = 0; v < count; ++v) {
      SensitivityVariant sv;
      sv.name = "v" + std::to_string(v);
      const auto figures = [&] {
        HeadlineFigures f;
        // few distinct values (a setpoint grid of cycle times), so equal figures happen
        for (std::size_t m = 0; m < kHeadlines; ++m) f[m] = 4.0 + 0.002 * static_cast<double>(rng() % 6);
        if (rng() % 10 == 0) f[0].reset();  // not settled
        return f;
      };
      sv.nominal.figures = figures();
      for (std::size_t k = 0; k < models; ++k) {
        SensitivityRun run;
        if (rng() % 12 == 0) {
          run.status = "saturated";
        } else {
          run.figures = figures();
        }
        sv.perturbed.push_back(run);
      }
      variants.push_back(std::move(sv));
    }
    Sensitivity study;
    study.perturbations = perturbations(std::min(models, default_perturbations().size()));
    for (std::size_t k = study.perturbations.size(); k < models; ++k) study.perturbations.push_back({"extra " + std::to_string(k)});
    study.variants = variants;
    study.conclusions = conclude(study.perturbations, study.variants);
    const OrderSpread spread = order_spread(study);
    std::map<std::string, const SensitivityVariant*> by_name;
    for (const SensitivityVariant& v : variants) by_name[v.name] = &v;
    std::size_t expected = 0;
    for (std::size_t i = 0; i < count; ++i) {
      for (std::size_t j = i + 1; j < count; ++j) {
        for (std::size_t m = 0; m < kHeadlines; ++m) expected += variants[i].nominal.figures->at(m) && variants[j].nominal.figures->at(m);
      }
    }
    ASSERT_EQ(study.conclusions.size(), expected) << test::seed_text(seed);
    for (const Conclusion& c : study.conclusions) {
      const auto m = static_cast<std::size_t>(c.metric);
      const SensitivityVariant& b = *by_name.at(c.better);
      const SensitivityVariant& w = *by_name.at(c.worse);
      const double nb = *b.nominal.figures->at(m), nw = *w.nominal.figures->at(m);
      ASSERT_LE(nb, nw) << test::seed_text(seed);
      int holds = 0;
      double lo = 100 * (nw - nb) / nw, hi = lo;
      for (std::size_t k = 0; k < models; ++k) {
        const auto fb = b.perturbed[k].figures ? b.perturbed[k].figures->at(m) : std::nullopt;
        const auto fw = w.perturbed[k].figures ? w.perturbed[k].figures->at(m) : std::nullopt;
        if (!fb || !fw) continue;
        holds += nb < nw ? *fb < *fw : *fb == *fw;
        lo = std::min(lo, 100 * (*fw - *fb) / *fw);
        hi = std::max(hi, 100 * (*fw - *fb) / *fw);
      }
      ASSERT_EQ(c.models, static_cast<int>(models)) << test::seed_text(seed);
      ASSERT_EQ(c.holds, holds) << test::seed_text(seed);
      ASSERT_EQ(c.fails_in.size(), models - static_cast<std::size_t>(holds)) << test::seed_text(seed);
      const OrderHolds expected_holds = holds == static_cast<int>(models) ? OrderHolds::kAll
                                        : holds == 0                      ? OrderHolds::kNone
                                                                          : OrderHolds::kSome;
      ASSERT_EQ(c.holds_in, expected_holds) << test::seed_text(seed);
      ASSERT_NEAR(c.difference_min, lo, kPercentTolerance) << test::seed_text(seed);
      ASSERT_NEAR(c.difference_max, hi, kPercentTolerance) << test::seed_text(seed);
      ASSERT_EQ(c.statement.rfind(c.better, 0), 0u) << c.statement << ' ' << test::seed_text(seed);
      if (c.metric == Headline::kCycleTime) {
        ASSERT_EQ(spread(c.better, c.worse), c.holds_in) << test::seed_text(seed);
        ASSERT_EQ(spread(c.worse, c.better), c.holds_in) << test::seed_text(seed);
      }
    }
    ASSERT_FALSE(spread("v0", "nobody").has_value()) << test::seed_text(seed);
  }
}

// The ranking's tie follows the study: two cycle times 0.4 % apart tie under the gate's slack,
// are ordered when the order holds in every model, and two 4 % apart (no tie by the gate) tie
// when the order fails in one.
TEST(Sensitivity, TheRankingTieFollowsTheStudy) {
  const auto candidate = [](const std::string& name, double cycle) {
    RankCandidate c;
    c.name = name;
    c.method = Method::kArc;
    c.tolerance = 1e-3;
    c.clean = true;
    c.status = "ok";
    c.cycle_time = cycle;
    return c;
  };
  const auto tie_of = [&](double a, double b, const std::vector<double>& pa, const std::vector<double>& pb) {
    Sensitivity study;
    study.perturbations = perturbations(pa.size());
    study.variants = {variant("A", a, pa), variant("B", b, pb)};
    study.conclusions = conclude(study.perturbations, study.variants);
    const Ranking with = rank({candidate("A", a), candidate("B", b)}, {}, cycle_resolution(kPeriod), order_spread(study));
    const Ranking without = rank({candidate("A", a), candidate("B", b)}, {}, cycle_resolution(kPeriod));
    EXPECT_TRUE(with.spread_used);
    EXPECT_FALSE(without.spread_used);
    return std::pair{without.groups.at(0).ranked.at(0).tie, with.groups.at(0).ranked.at(0).tie};
  };
  EXPECT_EQ(tie_of(4.800, 4.819, {4.810, 4.790}, {4.830, 4.812}), std::pair(true, false));  // holds in all
  EXPECT_EQ(tie_of(4.800, 4.819, {4.810, 4.830}, {4.830, 4.812}), std::pair(true, true));   // holds in some
  EXPECT_EQ(tie_of(4.800, 5.000, {4.810, 5.100}, {5.000, 5.000}), std::pair(false, true));  // 4 %, flips in one
  EXPECT_EQ(tie_of(4.800, 5.000, {4.810, 4.900}, {5.000, 5.000}), std::pair(false, false));
}

TEST(Sensitivity, JsonBlockNamesThePerturbationsRangesAndConclusions) {
  Sensitivity study;
  study.perturbations = perturbations(2);
  study.variants = {variant("A", 4.0, {4.3, 4.3}), variant("B", 4.2, {4.2, 4.2})};
  study.variants[1].perturbed[1] = SensitivityRun{"not_settled", "did not settle", std::nullopt};
  study.conclusions = conclude(study.perturbations, study.variants);
  study.jobs = 2;
  const nlohmann::json j = sensitivity_json(study);
  EXPECT_EQ(j.at("models"), 2);
  ASSERT_EQ(j.at("perturbations").size(), 2u);
  EXPECT_EQ(j.at("perturbations")[0].at("name"), "stiffness x0.5");
  EXPECT_EQ(j.at("perturbations")[0].at("stiffness_scale"), 0.5);
  EXPECT_EQ(j.at("perturbations")[1].at("stiffness_scale"), 1.5);
  EXPECT_EQ(j.at("perturbations")[1].at("extra_delay_ticks"), 0);
  ASSERT_EQ(j.at("variants").size(), 2u);
  const nlohmann::json& a = j.at("variants")[0];
  EXPECT_EQ(a.at("variant"), "A");
  ASSERT_EQ(a.at("runs").size(), 3u);  // the nominal and two perturbed
  EXPECT_EQ(a.at("runs")[0].at("model"), "nominal");
  EXPECT_EQ(a.at("ranges").at("cycle_time_s").at("min"), 4.0);
  EXPECT_EQ(a.at("ranges").at("cycle_time_s").at("max"), 4.3);
  EXPECT_EQ(a.at("ranges").at("cycle_time_s").at("models"), 3);
  EXPECT_DOUBLE_EQ(a.at("ranges").at("contour_error_programmed_max_mm").at("nominal").get<double>(), 0.1);  // 1e-4 m
  const nlohmann::json& b = j.at("variants")[1];
  EXPECT_EQ(b.at("runs")[2].at("status"), "not_settled");
  EXPECT_TRUE(b.at("runs")[2].at("cycle_time_s").is_null());
  EXPECT_EQ(b.at("ranges").at("cycle_time_s").at("models"), 2);
  ASSERT_EQ(j.at("conclusions").size(), kHeadlines);
  const nlohmann::json& c = j.at("conclusions")[0];
  EXPECT_EQ(c.at("metric"), "cycle_time_s");
  EXPECT_EQ(c.at("holds_in"), "none");  // reversed in the first model, unresolved in the second
  EXPECT_EQ(c.at("models"), 2);
  EXPECT_EQ(c.at("holds"), 0);
  EXPECT_EQ(c.at("unresolved"), nlohmann::json::array({"stiffness x1.5"}));
}

}  // namespace
}  // namespace blendbench
