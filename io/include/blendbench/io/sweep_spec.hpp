#pragma once
// Sweep files and their expansion (a sweep sits above a run). A sweep file names a base
// scenario and axes over any of its values by key path; the product of the axes gives the
// points, and each point is the base scenario with the point's values set, validated exactly as
// the scenario loader validates a file:
//
//   scenario: ../three_corners.yaml          # relative to the sweep file
//   variants: [arc, biclothoid]              # optional: a subset of the scenario's variants
//   axes:
//     variants[*].transition.parameter: [0.5, 1, 2]
//     defaults.velocity: {from: 100, to: 400, steps: 4}          # add `scale: log` for log spacing
//   metrics: [metrics.cycle_time_s, metrics.tracking_error_max_mm]   # default: every metric
//   constraints: ["metrics.tracking_error_max_mm <= 0.5"]
//   pareto: {x: metrics.cycle_time_s, y: metrics.contour_error_programmed_max_mm}   # the default
//
// Key paths are dotted mapping keys with `[N]` (element N, from 0) or `[*]` (every element) after
// a key: `program.moves[2].velocity`, `servo.kp[0]`, `variants[*].transition.parameter`. Every
// problem is an InputError naming the sweep file, line, column and key.

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "blendbench/core/input_error.hpp"

namespace blendbench {

// One step of a key path: a mapping key, a list element, or every element of a list.
struct KeyStep {
  enum class Kind { kKey, kIndex, kEach };
  Kind kind = Kind::kKey;
  std::string key;        // kKey
  std::size_t index = 0;  // kIndex
};

// The most steps a key path may have: a scenario file nests at most 64 levels (the scenario
// loader's limit), so no longer path names one of its values.
constexpr std::size_t kMaxKeyPathSteps = 64;

// Parses a key path ("variants[*].transition.parameter"). Throws InputError located at `where`
// naming `field` when the path is empty or malformed (an empty key, an unclosed bracket, an index
// that is neither digits nor '*', a path that starts with an index), or longer than
// kMaxKeyPathSteps.
std::vector<KeyStep> parse_key_path(const std::string& path, const SourceRef& where, const std::string& field);

// One axis: a key path and the values it takes, in order.
struct SweepAxis {
  std::string path;                 // as written; it names the axis' column in sweep.csv
  std::vector<KeyStep> steps;
  std::vector<std::string> values;  // each value as YAML text, set at the path as a YAML node
  std::vector<std::string> labels;  // each value as sweep.csv shows it: a scalar's text, else flow YAML
  SourceRef where;                  // the axis key in the sweep file
};

// A constraint on one metric of a row: "metrics.tracking_error_max_mm <= 0.5".
enum class Comparison { kLess, kLessEqual, kGreater, kGreaterEqual };
struct Constraint {
  std::string text;    // as written
  std::string metric;  // flattened metric name (see sweep_results.hpp)
  Comparison op = Comparison::kLessEqual;
  double bound = 0;
  SourceRef where;     // in the sweep file
};

// Parses "METRIC OP NUMBER" with OP one of <=, <, >=, > (spaces optional around OP). Throws
// InputError at `where` naming `field` for anything else (another operator, a missing or
// non-finite number, trailing text).
Constraint parse_constraint(const std::string& text, const SourceRef& where, const std::string& field);

// Whether `value` meets `c`. A NaN (a metric a row lacks, a run that never settled) never does.
bool meets(const Constraint& c, double value);

// A metric name the sweep file uses, with where, for errors on names no summary knows.
struct MetricName {
  std::string name;
  std::string field;  // "metrics[1]", "constraints[0]", "pareto.x"
  SourceRef where;
};

struct SweepSpec {
  std::string file;                    // the sweep file, as given
  std::string scenario;                // the base scenario, absolute
  std::string description;
  std::vector<std::string> variants;   // empty: every variant of each point's scenario
  std::vector<SourceRef> variants_where;
  std::vector<SweepAxis> axes;         // in file order, at least one; the last varies fastest
  SourceRef axes_where;
  std::vector<std::string> metrics;    // empty: every metric of the summary (see sweep_results.hpp)
  std::vector<Constraint> constraints;
  std::string pareto_x = "metrics.cycle_time_s";                     // minimised; the best setting has the least
  std::string pareto_y = "metrics.contour_error_programmed_max_mm";  // minimised
  std::vector<MetricName> named_metrics;          // every metric name above, with its location
  SourceRef where;                                // the sweep file's first line
  // the velocity planner set as the top-level `timing` of every point's scenario (the command's
  // --timing: part of each point's text, so of its hash); empty: the scenario's own
  std::string timing;
};

// Reads a sweep file from text: `file` names it in errors, `base_dir` resolves `scenario`
// (then the data root, as the scenario loader resolves its files). The text must first pass the
// scenario loader's YAML rules (one document, no key twice, no control character, UTF-8). Throws
// InputError, also for what a library refuses.
SweepSpec parse_sweep(const std::string& text, const std::string& file, const std::string& base_dir);

// The same from a file.
SweepSpec load_sweep(const std::string& path);

// One point of the product of the axes.
struct SweepPoint {
  std::size_t index = 0;                // 0-based, in product order (the last axis fastest)
  std::vector<std::size_t> choice;      // per axis, the index of its value
  std::vector<std::string> variants;    // the variants this point runs, in order
  std::vector<std::vector<std::string>> targets;  // per axis, the concrete paths it set ("variants[1].transition.parameter")
  std::string scenario_text;            // the expanded scenario (YAML)
  std::string hash;                     // 16 hex digits over base_dir, variants and scenario_text
};

struct SweepPlan {
  SweepSpec spec;
  std::string base_dir;             // the base scenario's folder: relative file names resolve there
  std::vector<SweepPoint> points;   // every point, by index
};

// The largest product of axes a sweep may have.
constexpr std::size_t kMaxSweepPoints = 100000;

// The number of points of the sweep: the product of its axes' value counts.
std::size_t sweep_point_count(const SweepSpec& spec);

// Called on the first point as soon as it is expanded (the plan then holds that point only), so
// that an axis that makes no valid scenario is refused before the rest of a product of up to
// kMaxSweepPoints points is expanded. It throws to refuse.
using SweepPointCheck = std::function<void(const SweepPlan& plan, const SweepPoint& point)>;

// Expands the sweep: loads the base scenario's YAML, and for every point of the product sets each
// axis' path to the point's value (creating missing mapping keys; a missing or out-of-range list
// element, or a key below a scalar, is an error). Checks that the selected variants exist and
// that no two axes set the same value. Validates no point itself except through `check_first`
// (validate_point validates one). Throws InputError naming the axis and the point.
SweepPlan expand_sweep(const SweepSpec& spec, const SweepPointCheck& check_first = {});

// Validates one point as the loader does (parse_scenario on its text with `file_name` for
// messages and the plan's base_dir), and that it has the selected variants. Throws InputError
// located at the axis the loader's message points to (else at `axes`), naming the point, its
// values and the loader's message.
void validate_point(const SweepPlan& plan, const SweepPoint& point, const std::string& file_name);

// "defaults.velocity=200, variants[*].transition.parameter=2": the point's values by axis.
std::string point_values_text(const SweepSpec& spec, const SweepPoint& point);

}  // namespace blendbench
