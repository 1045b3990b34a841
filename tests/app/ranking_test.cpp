// The ranking and the recommendation (app/ranking.hpp): the tie rule with and without the arm
// model's spread, the groups per tolerance, margins against the candidates' own cycle times, and
// the recommendation against a brute-force reading of the same figures.

#include "blendbench/app/ranking.hpp"
#include "blendbench/app/unit_text.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>

#include "support/property.hpp"

namespace blendbench {
namespace {

constexpr double kPeriod = 0.002;  // s, the default setpoint period (500 Hz)
// A margin is the difference of two cycle times: exact up to rounding.
constexpr double kMarginTolerance = 1e-12;

RankCandidate candidate(const std::string& name, Method method, double tolerance_mm, double cycle, double contour_mm = 0.1,
                        double vibration_um = 5) {
  RankCandidate c;
  c.name = name;
  c.method = method;
  c.tolerance = tolerance_mm * 1e-3;
  c.clean = true;
  c.status = "ok";
  c.cycle_time = cycle;
  c.contour_error = contour_mm * 1e-3;
  c.vibration = vibration_um * 1e-6;
  return c;
}

TEST(TieRule, ThresholdIsTheLargestOfGridGateAbsoluteAndGateRelative) {
  const CycleResolution r = cycle_resolution(kPeriod);
  EXPECT_DOUBLE_EQ(r.grid, 2 * kPeriod);
  // a short cycle: the gate's 5 ms (above the 4 ms grid)
  EXPECT_DOUBLE_EQ(tie_threshold(0.2, 0.3, r), kCycleTimeGateAbsolute);
  // a long one: 1 % of the faster
  EXPECT_DOUBLE_EQ(tie_threshold(5.0, 5.2, r), 0.05);
  EXPECT_DOUBLE_EQ(tie_threshold(5.2, 5.0, r), 0.05);
  // a coarse setpoint grid (125 Hz: 16 ms) dominates both
  EXPECT_DOUBLE_EQ(tie_threshold(1.0, 1.1, cycle_resolution(0.008)), 0.016);
}

TEST(TieRule, WithoutSpreadADifferenceBelowTheThresholdIsATie) {
  const CycleResolution r = cycle_resolution(kPeriod);
  EXPECT_TRUE(cycle_times_tie(5.0, 5.0, r));
  EXPECT_TRUE(cycle_times_tie(5.0, 5.049, r));
  EXPECT_FALSE(cycle_times_tie(5.0, 5.051, r));
  EXPECT_TRUE(cycle_times_tie(0.5, 0.5049, r));
  EXPECT_FALSE(cycle_times_tie(0.5, 0.5051, r));
  // symmetric
  EXPECT_EQ(cycle_times_tie(5.051, 5.0, r), cycle_times_tie(5.0, 5.051, r));
}

TEST(TieRule, WithSpreadTheModelsDecideAboveTheGrid) {
  const CycleResolution r = cycle_resolution(kPeriod);
  // 0.6 % apart: a tie by the gate's 1 %, resolved when every perturbed model keeps the order
  EXPECT_TRUE(cycle_times_tie(5.0, 5.03, r));
  EXPECT_FALSE(cycle_times_tie(5.0, 5.03, r, OrderHolds::kAll));
  // within the grid the metric cannot tell them apart, whatever the models say
  EXPECT_TRUE(cycle_times_tie(5.0, 5.003, r, OrderHolds::kAll));
  // 10 % apart, but the order flips in some models (or in all): a tie
  EXPECT_TRUE(cycle_times_tie(5.0, 5.5, r, OrderHolds::kSome));
  EXPECT_TRUE(cycle_times_tie(5.0, 5.5, r, OrderHolds::kNone));
  EXPECT_FALSE(cycle_times_tie(5.0, 5.5, r));
}

TEST(TieRule, TheGateConstantsAreTheRegressionGatesTolerance) {
  std::ifstream in(test::source_path("results/baselines/tolerances.json"));
  ASSERT_TRUE(in) << "results/baselines/tolerances.json";
  const nlohmann::json tolerances = nlohmann::json::parse(in);
  const nlohmann::json& cycle = tolerances.at("metrics").at("metrics.cycle_time_s");
  EXPECT_DOUBLE_EQ(cycle.at("absolute").get<double>(), kCycleTimeGateAbsolute);
  EXPECT_DOUBLE_EQ(cycle.at("relative").get<double>(), kCycleTimeGateRelative);
}

TEST(Ranking, OneGroupPerToleranceWithTheBaselinesInEach) {
  const std::vector<RankCandidate> candidates = {
      candidate("exact_stop", Method::kNone, 0, 5.39),        candidate("junction_slowdown", Method::kNone, 0, 5.39),
      candidate("arc_2mm", Method::kArc, 2, 5.9),             candidate("clothoid_2mm", Method::kClothoid, 2, 4.6),
      candidate("arc_0.5mm", Method::kArc, 0.5, 6.1),         candidate("clothoid_0.5mm", Method::kClothoid, 0.5, 4.9),
  };
  const Ranking r = rank(candidates, {}, cycle_resolution(kPeriod));
  ASSERT_EQ(r.groups.size(), 2U);
  EXPECT_DOUBLE_EQ(r.groups[0].tolerance, 0.5e-3);
  EXPECT_DOUBLE_EQ(r.groups[1].tolerance, 2e-3);
  for (const RankGroup& g : r.groups) {
    EXPECT_TRUE(g.like_for_like);
    ASSERT_EQ(g.ranked.size(), 4U);
  }
  const std::vector<std::string> order = {"clothoid_0.5mm", "exact_stop", "junction_slowdown", "arc_0.5mm"};
  for (std::size_t k = 0; k < order.size(); ++k) EXPECT_EQ(r.groups[0].ranked[k].name, order[k]);
  // the two baselines tie (equal times) and share their rank; the next takes its place number
  EXPECT_EQ(r.groups[0].ranked[0].rank, 1);
  EXPECT_EQ(r.groups[0].ranked[1].rank, 2);
  EXPECT_TRUE(r.groups[0].ranked[1].tie);
  EXPECT_EQ(r.groups[0].ranked[2].rank, 2);
  EXPECT_EQ(r.groups[0].ranked[3].rank, 4);
  EXPECT_FALSE(r.groups[0].ranked[3].margin.has_value());
  ASSERT_TRUE(r.groups[0].ranked[0].margin_percent.has_value());
  EXPECT_NEAR(*r.groups[0].ranked[0].margin_percent, 100 * (5.39 - 4.9) / 4.9, 1e-9);
  // no constraints: the fastest of all
  ASSERT_TRUE(r.recommendation.variant.has_value());
  EXPECT_EQ(*r.recommendation.variant, "clothoid_2mm");
  EXPECT_NE(r.recommendation.reason.find("no constraints given"), std::string::npos) << r.recommendation.reason;
}

TEST(Ranking, RanksDoNotChainThroughTies) {
  // 4.0 ~ 4.03 ~ 4.06 by the 1 % rule (40 ms), but 4.0 and 4.06 are apart
  const std::vector<RankCandidate> candidates = {candidate("a", Method::kArc, 1, 4.0), candidate("b", Method::kBezier, 1, 4.03),
                                                 candidate("c", Method::kClothoid, 1, 4.06)};
  const Ranking r = rank(candidates, {}, cycle_resolution(kPeriod));
  ASSERT_EQ(r.groups.size(), 1U);
  const std::vector<RankedVariant>& v = r.groups[0].ranked;
  ASSERT_EQ(v.size(), 3U);
  EXPECT_TRUE(v[0].tie);
  EXPECT_TRUE(v[1].tie);
  EXPECT_EQ(v[0].rank, 1);
  EXPECT_EQ(v[1].rank, 1);
  EXPECT_EQ(v[2].rank, 3);
}

TEST(Ranking, ParameterSizedVariantsAreRankedApartAndMarkedNotLikeForLike) {
  const std::vector<RankCandidate> candidates = {
      candidate("exact_stop", Method::kNone, 0, 5.39), candidate("arc_10mm", Method::kArc, 0, 6.19),
      candidate("bezier_25mm", Method::kBezier, 0, 5.46), candidate("clothoid_1mm", Method::kClothoid, 1, 4.9)};
  const Ranking r = rank(candidates, {}, cycle_resolution(kPeriod));
  ASSERT_EQ(r.groups.size(), 2U);
  EXPECT_TRUE(r.groups[0].like_for_like);
  EXPECT_EQ(r.groups[0].ranked.size(), 2U);
  EXPECT_DOUBLE_EQ(r.groups[1].tolerance, 0);
  EXPECT_FALSE(r.groups[1].like_for_like);
  EXPECT_EQ(r.groups[1].ranked.size(), 3U);
}

TEST(Ranking, BaselinesAloneAreOneLikeForLikeGroup) {
  const Ranking r = rank({candidate("exact_stop", Method::kNone, 0, 1.2)}, {}, cycle_resolution(kPeriod));
  ASSERT_EQ(r.groups.size(), 1U);
  EXPECT_TRUE(r.groups[0].like_for_like);
  ASSERT_TRUE(r.recommendation.variant.has_value());
  EXPECT_EQ(*r.recommendation.variant, "exact_stop");
}

TEST(Ranking, VariantsThatAreNotCleanAreListedUnrankedAndNeverRecommended) {
  std::vector<RankCandidate> candidates = {candidate("exact_stop", Method::kNone, 0, 5.0),
                                           candidate("arc_1mm", Method::kArc, 1, 4.0)};
  candidates[1].clean = false;
  candidates[1].status = "saturated";
  const Ranking r = rank(candidates, {}, cycle_resolution(kPeriod));
  ASSERT_EQ(r.groups.size(), 1U);
  ASSERT_EQ(r.groups[0].ranked.size(), 1U);
  ASSERT_EQ(r.groups[0].unranked.size(), 1U);
  EXPECT_EQ(r.groups[0].unranked[0].name, "arc_1mm");
  EXPECT_NE(r.groups[0].unranked[0].reason.find("saturated"), std::string::npos);
  EXPECT_EQ(*r.recommendation.variant, "exact_stop");
  // none clean: no recommendation, and the reason says why
  candidates[0].clean = false;
  candidates[0].status = "diverged";
  const Ranking none = rank(candidates, {}, cycle_resolution(kPeriod));
  EXPECT_FALSE(none.recommendation.variant.has_value());
  EXPECT_NE(none.recommendation.reason.find("no variant ran clean"), std::string::npos) << none.recommendation.reason;
}

TEST(Recommendation, TheFastestThatMeetsTheConstraints) {
  const std::vector<RankCandidate> candidates = {
      candidate("exact_stop", Method::kNone, 0, 5.39, 0.07, 46), candidate("arc_2mm", Method::kArc, 2, 4.4, 2.0, 36),
      candidate("clothoid_2mm", Method::kClothoid, 2, 4.6, 2.0, 15), candidate("clothoid_0.5mm", Method::kClothoid, 0.5, 4.9, 0.5, 15)};
  Constraints k;
  k.max_contour_error = 1e-3;
  Ranking r = rank(candidates, k, cycle_resolution(kPeriod));
  EXPECT_EQ(*r.recommendation.variant, "clothoid_0.5mm");
  EXPECT_NE(r.recommendation.reason.find("contour error against the program <= 1.000 mm"), std::string::npos)
      << r.recommendation.reason;
  EXPECT_FALSE(r.groups.back().ranked.front().meets_constraints);  // arc_2mm in the 2 mm group
  // vibration: arc_2mm's 36 um is above 20 um
  k = {};
  k.max_vibration = 20e-6;
  r = rank(candidates, k, cycle_resolution(kPeriod));
  EXPECT_EQ(*r.recommendation.variant, "clothoid_2mm");
  // nothing meets both: no variant, the closest named
  k.max_contour_error = 0.01e-3;
  r = rank(candidates, k, cycle_resolution(kPeriod));
  EXPECT_FALSE(r.recommendation.variant.has_value());
  EXPECT_NE(r.recommendation.reason.find("none of the 4 clean variants meets the constraints"), std::string::npos)
      << r.recommendation.reason;
  EXPECT_NE(r.recommendation.reason.find("the closest is exact_stop"), std::string::npos) << r.recommendation.reason;
  // micrometres as the unit convention writes them (the reason goes into summary.json, UTF-8);
  // the command line shows "um" where the locale is not UTF-8
  EXPECT_NE(r.recommendation.reason.find("residual vibration <= 20.0 \xC2\xB5m"), std::string::npos) << r.recommendation.reason;
  EXPECT_EQ(r.recommendation.reason.find(" um"), std::string::npos) << r.recommendation.reason;
  const char* saved = std::getenv("LC_ALL");
  const std::string restore = saved != nullptr ? saved : "";
  ::setenv("LC_ALL", "C", 1);
  const std::string ascii = terminal_text(r.recommendation.reason);
  EXPECT_NE(ascii.find("residual vibration <= 20.0 um"), std::string::npos) << ascii;
  EXPECT_EQ(ascii.find("\xC2\xB5"), std::string::npos) << ascii;
  ::setenv("LC_ALL", "C.UTF-8", 1);
  EXPECT_EQ(terminal_text(r.recommendation.reason), r.recommendation.reason);
  if (saved != nullptr) ::setenv("LC_ALL", restore.c_str(), 1);
  else ::unsetenv("LC_ALL");
}

TEST(Recommendation, AmongTiesTheMostAccurate) {
  // 0.4 % apart: a tie at the gate's resolution; the slower one deviates less
  const std::vector<RankCandidate> candidates = {candidate("clothoid_1mm", Method::kClothoid, 1, 4.800, 1.00),
                                                 candidate("biclothoid_1mm", Method::kBiclothoid, 1, 4.819, 0.98),
                                                 candidate("arc_1mm", Method::kArc, 1, 5.5, 0.5)};
  const Ranking r = rank(candidates, {}, cycle_resolution(kPeriod));
  EXPECT_EQ(*r.recommendation.variant, "biclothoid_1mm");
  EXPECT_NE(r.recommendation.reason.find("ties on cycle time with clothoid_1mm"), std::string::npos) << r.recommendation.reason;
  EXPECT_NE(r.recommendation.reason.find("the next, arc_1mm, takes"), std::string::npos) << r.recommendation.reason;
  // a sensitivity run that keeps the order in every model resolves the tie
  const OrderSpread all = [](const std::string&, const std::string&) { return std::optional<OrderHolds>(OrderHolds::kAll); };
  const Ranking resolved = rank(candidates, {}, cycle_resolution(kPeriod), all);
  EXPECT_EQ(*resolved.recommendation.variant, "clothoid_1mm");
  EXPECT_TRUE(resolved.spread_used);
  EXPECT_FALSE(resolved.groups[0].ranked[0].tie);
  EXPECT_FALSE(r.spread_used);
  EXPECT_TRUE(r.groups[0].ranked[0].tie);
}

// Random runs: the order, the margins, the ties and the ranks against the candidates' own
// figures, and the recommendation against a brute-force search over them.
TEST(RankingProperty, OrderMarginsTiesAndRecommendationAgreeWithTheFigures) {
  const int cases = test::property_cases(500);
  const Method methods[] = {Method::kArc, Method::kBezier, Method::kClothoid, Method::kBiclothoid};
  const CycleResolution res = cycle_resolution(kPeriod);
  for (int n = 0; n < cases; ++n) {
    const std::uint64_t seed = 4400000 + static_cast<std::uint64_t>(n);
    std::mt19937_64 rng = test::make_rng(seed);
    std::vector<RankCandidate> candidates;
    candidates.push_back(candidate("exact_stop", Method::kNone, 0, test::uniform(rng, 3, 6)));
    const int tolerances = 1 + static_cast<int>(rng() % 3);
    for (int t = 0; t < tolerances; ++t) {
      const double tol_mm = 0.1 * (t + 1);
      for (const Method m : methods) {
        if (rng() % 4 == 0) continue;
        // times close together, so ties happen
        RankCandidate c = candidate(std::string(to_string(m)) + "_" + std::to_string(t), m, tol_mm, test::uniform(rng, 4, 4.3),
                                    test::uniform(rng, 0.05, 0.6), test::uniform(rng, 2, 40));
        if (rng() % 8 == 0) {
          c.clean = false;
          c.status = "not_settled";
          c.cycle_time.reset();
        }
        candidates.push_back(c);
      }
    }
    Constraints k;
    if (rng() % 2 == 0) k.max_contour_error = test::uniform(rng, 0.05e-3, 0.7e-3);
    if (rng() % 2 == 0) k.max_vibration = test::uniform(rng, 2e-6, 40e-6);
    const Ranking r = rank(candidates, k, res);
    std::map<std::string, const RankCandidate*> by_name;
    for (const RankCandidate& c : candidates) by_name[c.name] = &c;
    for (const RankGroup& g : r.groups) {
      std::set<std::string> seen;
      for (std::size_t i = 0; i < g.ranked.size(); ++i) {
        const RankedVariant& v = g.ranked[i];
        const RankCandidate& c = *by_name.at(v.name);
        seen.insert(v.name);
        ASSERT_TRUE(c.clean) << test::seed_text(seed);
        ASSERT_TRUE(c.method == Method::kNone || std::abs(c.tolerance - g.tolerance) < 1e-12) << test::seed_text(seed);
        ASSERT_EQ(v.cycle_time, *c.cycle_time) << test::seed_text(seed);
        ASSERT_EQ(v.meets_constraints, (!k.max_contour_error || c.contour_error <= *k.max_contour_error) &&
                                           (!k.max_vibration || c.vibration <= *k.max_vibration))
            << test::seed_text(seed);
        if (i + 1 < g.ranked.size()) {
          const double next = g.ranked[i + 1].cycle_time;
          ASSERT_LE(v.cycle_time, next) << test::seed_text(seed);
          ASSERT_NEAR(*v.margin, next - v.cycle_time, kMarginTolerance) << test::seed_text(seed);
          ASSERT_NEAR(*v.margin_percent, 100 * (next - v.cycle_time) / v.cycle_time, 1e-9) << test::seed_text(seed);
          ASSERT_EQ(v.tie, std::abs(next - v.cycle_time) < std::max({res.grid, res.absolute, res.relative * v.cycle_time}))
              << test::seed_text(seed);
          // the next shares the rank of the first variant holding this rank when it ties with it
          const auto leader = std::find_if(g.ranked.begin(), g.ranked.end(), [&](const RankedVariant& u) { return u.rank == v.rank; });
          const bool with_leader = std::abs(next - leader->cycle_time) <
                                   std::max({res.grid, res.absolute, res.relative * leader->cycle_time});
          ASSERT_EQ(g.ranked[i + 1].rank, with_leader ? v.rank : static_cast<int>(i) + 2) << test::seed_text(seed);
        } else {
          ASSERT_FALSE(v.margin.has_value()) << test::seed_text(seed);
          ASSERT_FALSE(v.tie) << test::seed_text(seed);
        }
      }
      // every member is either ranked or listed unranked, once
      for (const UnrankedVariant& u : g.unranked) {
        ASSERT_FALSE(by_name.at(u.name)->clean && by_name.at(u.name)->cycle_time) << test::seed_text(seed);
        ASSERT_TRUE(seen.insert(u.name).second) << test::seed_text(seed);
      }
      for (const RankCandidate& c : candidates) {
        const bool member = c.method == Method::kNone || std::abs(c.tolerance - g.tolerance) < 1e-12;
        ASSERT_EQ(member, seen.count(c.name) == 1) << c.name << ' ' << test::seed_text(seed);
      }
    }
    // brute force: the fastest clean variant within the constraints
    const RankCandidate* fastest = nullptr;
    for (const RankCandidate& c : candidates) {
      const bool ok = c.clean && c.cycle_time && (!k.max_contour_error || c.contour_error <= *k.max_contour_error) &&
                      (!k.max_vibration || c.vibration <= *k.max_vibration);
      if (ok && (fastest == nullptr || *c.cycle_time < *fastest->cycle_time)) fastest = &c;
    }
    if (fastest == nullptr) {
      ASSERT_FALSE(r.recommendation.variant.has_value()) << test::seed_text(seed);
      continue;
    }
    ASSERT_TRUE(r.recommendation.variant.has_value()) << test::seed_text(seed);
    const RankCandidate& chosen = *by_name.at(*r.recommendation.variant);
    ASSERT_TRUE(!k.max_contour_error || chosen.contour_error <= *k.max_contour_error) << test::seed_text(seed);
    ASSERT_TRUE(!k.max_vibration || chosen.vibration <= *k.max_vibration) << test::seed_text(seed);
    // the chosen one is the fastest or ties with it, and is no less accurate than the fastest
    ASSERT_TRUE(&chosen == fastest || cycle_times_tie(*fastest->cycle_time, *chosen.cycle_time, res)) << test::seed_text(seed);
    ASSERT_LE(chosen.contour_error, fastest->contour_error) << test::seed_text(seed);
  }
}

}  // namespace
}  // namespace blendbench
