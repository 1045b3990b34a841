#pragma once
// Regression checks of a run against a committed baseline (`blendbench check`).
//
// A baseline file (results/baselines/<scenario>.json) holds, per variant, the metric values of
// a reference run and, per metric, a tolerance: a metric regresses when
//   value > baseline * (1 + relative) + absolute
// (every checked metric is "lower is better"; metrics are named by their dotted path in the
// variant's summary entry, e.g. "metrics.cycle_time_s"), and a variant regresses when its
// status is no longer "ok" or it disappeared. Improvements beyond the tolerance are reported as notes, so a
// baseline is updated on purpose (`blendbench check RUN --update`), never silently.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace blendbench {

struct CheckReport {
  std::vector<std::string> regressions;  // one line each: variant, metric, value, baseline, bound
  std::vector<std::string> notes;        // improvements beyond tolerance, new variants
  [[nodiscard]] bool passed() const { return regressions.empty(); }
};

// Compares a run's summary.json content with a baseline. Throws InputError (field named) when
// the baseline is malformed.
CheckReport check_run(const nlohmann::json& summary, const nlohmann::json& baseline, const std::string& baseline_file);

// A baseline from a run's summary with the default tolerances (see check.cpp).
nlohmann::json make_baseline(const nlohmann::json& summary);

}  // namespace blendbench
