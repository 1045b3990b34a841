#pragma once
// The sensitivity study of a run (issue 46, docs/sensitivity.md): every variant that ran cleanly
// on the nominal arm model re-run on perturbed models (io/scenario.hpp, Perturbation; one
// parameter at a time), and for each pair of variants and each headline metric the nominal
// run's statement ("A is faster than B by 3.1-3.4 %") with the number of perturbed models in
// which its order holds. Pure functions of the runs' figures: the runner fills the runs
// (runner.cpp), the tests feed them directly.

#include <nlohmann/json.hpp>

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "blendbench/app/ranking.hpp"
#include "blendbench/io/scenario.hpp"
#include "blendbench/sim/metrics.hpp"

namespace blendbench {

// The headline metrics a conclusion is drawn on, each lower-is-better: the settled cycle time
// (metrics.cycle_time_s: the reference's end plus the time the TCP takes to settle, so it moves
// with the model; the planned cycle time does not), the largest contour error against the
// programmed and against the planned path, the largest residual vibration after a corner and
// after the final stop (peak to peak).
enum class Headline { kCycleTime, kContourProgrammed, kContourPlanned, kVibrationCorner, kVibrationFinal };
inline constexpr std::size_t kHeadlines = 5;
inline constexpr std::array<Headline, kHeadlines> kAllHeadlines = {Headline::kCycleTime, Headline::kContourProgrammed,
                                                                   Headline::kContourPlanned, Headline::kVibrationCorner,
                                                                   Headline::kVibrationFinal};

// Its key in summary.json (the key of metrics it is, with the unit the JSON states it in).
std::string_view headline_key(Headline metric);

// One variant's headline figures on one model (SI: s, m); none where it has none (a cycle time
// when the run did not settle).
using HeadlineFigures = std::array<std::optional<double>, kHeadlines>;
HeadlineFigures headline_figures(const Metrics& metrics);

// One run of a variant on one model. Only a clean run (status "ok") carries figures: a saturated
// run, one beyond the joint limits or one that did not settle has no say in a conclusion.
struct SensitivityRun {
  std::string status = "ok";  // the variant status (run_summary.hpp, to_string(VariantStatus))
  std::string message;        // why it is not ok
  std::optional<HeadlineFigures> figures;
};

// A variant's runs: on the nominal model and on each perturbed one (in the perturbations' order).
struct SensitivityVariant {
  std::string name;
  SensitivityRun nominal;
  std::vector<SensitivityRun> perturbed;
};

// The range of one figure over the nominal and the perturbed models where it has one (SI).
struct FigureRange {
  std::optional<double> nominal, min, max;
  int models = 0;  // how many runs gave it
};
FigureRange figure_range(const SensitivityVariant& variant, Headline metric);

// What the nominal run says of two variants on one metric, and where it holds. `better` has the
// lower nominal figure (the pair's first variant on a tie). The difference of a model is
// (worse - better) / worse, in %; its order holds when the difference has the nominal's sign
// (zero where the nominal's is zero). A perturbed model where either variant has no clean
// figure counts as one where it does not hold (`unresolved` names it). `models` counts the
// perturbed models; holds_in is kAll when it holds in every one, kNone in none, else kSome.
struct Conclusion {
  std::string better, worse;
  Headline metric = Headline::kCycleTime;
  std::string statement;
  OrderHolds holds_in = OrderHolds::kAll;
  int models = 0, holds = 0;
  double difference_nominal = 0;  // %
  double difference_min = 0, difference_max = 0;  // %, over the nominal and the perturbed models that resolve it
  std::vector<std::string> fails_in;    // the perturbations where the order is reversed (or lost)
  std::vector<std::string> unresolved;  // the perturbations where a variant has no clean figure
};

// The conclusions for every pair of `variants` (in their order) that both have the metric on
// the nominal model, for every headline metric, `perturbations` naming the perturbed runs.
std::vector<Conclusion> conclude(const std::vector<Perturbation>& perturbations,
                                 const std::vector<SensitivityVariant>& variants);

// The study as summary.json's `sensitivity` holds it.
struct Sensitivity {
  std::vector<Perturbation> perturbations;
  std::vector<SensitivityVariant> variants;  // those that ran cleanly on the nominal model
  std::vector<std::string> skipped;          // variants not re-run, with why ("name: status")
  std::vector<std::string> notes;            // perturbations left out, and why
  std::vector<Conclusion> conclusions;
  int jobs = 1;          // simulations at a time
  double wall_time = 0;  // s: the perturbed runs, models loaded included
};

// The order spread of the cycle times (ranking.hpp) the study measured: holds_in of the pair's
// cycle-time conclusion, nullopt for a pair it has none for. The study must outlive it.
OrderSpread order_spread(const Sensitivity& study);

// "all", "some", "none".
std::string_view to_string(OrderHolds holds);

// summary.json's `sensitivity` block (docs/sensitivity.md).
nlohmann::json sensitivity_json(const Sensitivity& study);

}  // namespace blendbench
