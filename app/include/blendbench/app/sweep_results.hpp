#pragma once
// The results of a sweep as one table: a row per point and variant with every metric of the
// run's summary, whether it meets the constraints, the Pareto front of two metrics per method and
// the best setting per method; and the files made from it (sweep.csv, sweep.json, best.csv,
// report.html). Everything here is a function of the plan and the points' summaries alone, so a
// local run, a run with other --jobs and a Slurm array merged by --collect give the same bytes.

#include <nlohmann/json.hpp>

#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "blendbench/io/sweep_spec.hpp"

namespace blendbench {

// Every number of one variant entry of a summary.json by flattened name: nested objects as
// dotted names ("residual.amplitude_mm"), list elements by index ("torque_peak_nm[2]", and in a
// list of objects "corners[1].deviation_mm"), booleans as 0 or 1, null (a cycle that never
// settled) as NaN. Strings are not metrics.
std::map<std::string, double> flatten_metrics(const nlohmann::json& entry);

// Whether a metric measures the machine rather than the point (a name with "wall_time" or
// "real_time_factor" in it): left out of the default metrics, so the table does not depend on
// --jobs or the load of the machine.
bool machine_metric(const std::string& name);

// Whether a metric is a field of an element of a list of objects (the reports per corner and per
// piece: "corners[1].deviation_mm"), whose number varies from point to point.
bool report_field(const std::string& name);

// The default metric columns: every metric that is neither a machine metric nor a report field.
// A sweep may name any metric (in `metrics`, a constraint or `pareto`).
bool default_metric(const std::string& name);

// The metric names a sweep file uses.
std::set<std::string> named_metrics(const SweepSpec& spec);

// Throws InputError at the sweep file key that names a metric not in `known`, listing the known
// default metrics (and how many report fields there are besides).
void check_metric_names(const SweepSpec& spec, const std::set<std::string>& known);

// One variant's entry of a run's summary.json: its name, `method` and `status` (as written;
// empty when absent), `message`, and its metrics (flatten_metrics).
struct VariantResult {
  std::string name;
  std::string method;
  std::string status;
  std::string message;
  std::map<std::string, double> metrics;
};

// The variant entries of a summary.json (none when it has no `variants` list), each keeping the
// metrics that are default metrics or in `named`. `known`, when given, receives every metric
// name of the variants that ran ok.
std::vector<VariantResult> variant_results(const nlohmann::json& summary, const std::set<std::string>& named,
                                           std::set<std::string>* known = nullptr);

// What running a point gave (DIR/points/<hash>/status.json and summary.json).
struct PointOutcome {
  std::string status;                   // ok (every variant ok), failed (a variant failed), error, crashed
  std::string message;                  // why not ok (the run's last message, the signal)
  bool has_summary = false;             // the run wrote its summary.json
  std::vector<VariantResult> variants;  // from the summary
  double wall_time_s = 0;               // how long the run took (not part of the table)
};

struct SweepRow {
  std::size_t point = 0;
  std::string variant;
  std::string method;       // the summary's `method` of the variant, else the variant's name
  std::string status;       // ok, failed (planning failed, diverged), error, crashed
  std::string message;
  std::map<std::string, double> metrics;  // flattened (flatten_metrics)
  bool meets_constraints = false;         // ok and every constraint met
  bool on_pareto_front = false;           // not dominated in (x, y) by another ok row of its method
};

struct MethodSummary {
  std::string method;
  std::vector<std::size_t> front;   // rows on its Pareto front, by increasing x
  std::optional<std::size_t> best;  // the row meeting the constraints with the least x (then y, then first)
  std::size_t rows = 0;
  std::size_t ok = 0;
  std::size_t meeting = 0;
};

struct SweepTable {
  std::vector<std::string> metrics;     // the metric columns, in order
  std::vector<SweepRow> rows;           // by point, then by the point's variants
  std::vector<MethodSummary> methods;   // by best x (methods with no best last, in order met)
};

// The table of a plan from its points' outcomes (outcomes[i] for plan.points[i]; consumed: their
// metrics move into the rows). Metric columns: the sweep's `metrics` (plus any a constraint or
// the Pareto axes name), else every default metric of any row, sorted by name. `known` holds
// every metric name of the variants that ran ok; a name the sweep uses that is not in it is an
// InputError (no check when it is empty: nothing ran ok).
SweepTable build_table(const SweepPlan& plan, std::vector<PointOutcome> outcomes, const std::set<std::string>& known);

// sweep.csv: columns point, variant, method, one per axis (named by its key path), status,
// meets_constraints, on_pareto_front, then the metric columns (names with their units, as the
// summary has them); a metric a row lacks is an empty cell.
std::string sweep_csv(const SweepPlan& plan, const SweepTable& table);

// sweep.json: the sweep (file, scenario, axes and values, constraints, Pareto axes, the metric
// names), every row (values by axis, status, message, and its metrics as a list in the order of
// the metric names, null where a row lacks one), and per method its front, best row and counts.
nlohmann::json sweep_json(const SweepPlan& plan, const SweepTable& table);

// best.csv: per method its best row under the constraints: method, variant, point, the axes,
// the Pareto metrics and the constrained metrics; a method with none has only its name.
std::string best_csv(const SweepPlan& plan, const SweepTable& table);

// The best table as aligned text for the terminal, with a line naming the overall best.
std::string best_text(const SweepPlan& plan, const SweepTable& table);

// report.html, self-contained: the sweep, the Pareto plot (PNG bytes, embedded; none when
// empty) and the best table.
std::string report_html(const SweepPlan& plan, const SweepTable& table, const std::string& pareto_png);

}  // namespace blendbench
