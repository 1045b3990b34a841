#pragma once
// Regression checks of a run against a committed baseline (`blendbench check`).
//
// A baseline file (results/baselines/<scenario>.json) holds the scenario's name and, per
// variant, its status and the values of the gated metrics of a reference run. Which metrics are
// gated, and by how much each may move, is declared once for every scenario in the tolerance
// file (results/baselines/tolerances.json): per metric, named by its dotted path in the
// variant's summary entry ("metrics.cycle_time_s" is v["metrics"]["cycle_time_s"]), a relative
// and an absolute tolerance and which way is better. A metric where lower is better regresses
// when
//   value > baseline * (1 + relative) + absolute,
// one where higher is better when value < baseline * (1 - relative) - absolute; a variant
// regresses when its status is no longer its baseline's (a clean run that is no longer "ok") or
// it disappeared. Improvements beyond the tolerance are notes, so a baseline is updated on
// purpose (`blendbench check RUN --update`), never silently.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace blendbench {

// One gated metric of the tolerance file.
struct MetricTolerance {
  std::string metric;             // dotted path in a variant's summary entry
  double relative = 0;            // share of the baseline value, >= 0
  double absolute = 0;            // in the metric's unit (its name's suffix), >= 0
  bool higher_is_better = false;  // "better": "higher" (else "lower")
  std::string why;                // the reason for the values, for the reader
};

// The tolerance file's content: {"metrics": {"<metric>": {"relative": r, "absolute": a,
// "better": "lower"|"higher", "why": "..."}}}. Throws InputError naming `file` and the field
// when a metric lacks a value, a tolerance is negative or not a number, or `better` is neither.
std::vector<MetricTolerance> parse_tolerances(const nlohmann::json& content, const std::string& file);

// One gated metric of one variant, compared.
struct CheckRow {
  enum class Verdict { kUnchanged, kWithin, kImproved, kRegressed };
  std::string variant, metric;
  double baseline = 0, value = 0;
  double bound = 0;  // the worst value allowed
  Verdict verdict = Verdict::kUnchanged;
};

struct CheckReport {
  std::vector<std::string> regressions;  // one line each: variant, metric, value, baseline, bound
  std::vector<std::string> notes;        // improvements beyond tolerance, new variants
  std::vector<CheckRow> rows;            // every gated metric compared, in baseline order
  [[nodiscard]] bool passed() const { return regressions.empty(); }
};

// Checks that a run's summary.json content has what a check reads: an object whose `scenario`
// (when present) is a name and whose `variants` is a list of objects, each with a `name` and, when
// present, a `status` that are strings. Throws InputError naming `file` and the field otherwise
// (a summary of another program, an array, a FIFO's garbage: never a library's message).
void validate_run_summary(const nlohmann::json& summary, const std::string& file);

// Compares a run's summary.json content with a baseline under the tolerances. `summary` must have
// passed validate_run_summary. Throws InputError
// naming `baseline_file` when the baseline is malformed or is the baseline of another scenario
// (the message says which baseline to check against and how to create it).
CheckReport check_run(const nlohmann::json& summary, const nlohmann::json& baseline,
                      const std::vector<MetricTolerance>& tolerances, const std::string& baseline_file);

// A baseline from a run's summary (validated by validate_run_summary): the scenario, and per
// variant its status and the value of every gated metric it has.
nlohmann::json make_baseline(const nlohmann::json& summary, const std::vector<MetricTolerance>& tolerances);

// The rows whose value moved at all (differs from the baseline), as a fixed-width text table
// (variant, metric, baseline, value, change, allowed, verdict); "nothing moved" when none did.
std::string moved_table(const CheckReport& report);

}  // namespace blendbench
