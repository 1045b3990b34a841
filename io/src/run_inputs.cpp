#include "blendbench/io/run_inputs.hpp"

namespace blendbench {

void apply_tolerance(Program& program, double tolerance) {
  for (Move& move : program.moves) {
    if (move.transition.method == Method::kNone) continue;
    move.transition.parameter = 0;
    move.transition.start_distance = 0;
    move.transition.tolerance = tolerance;
  }
}

VariantInputs resolve_variant(const Scenario& scenario, const Variant& variant, const RunSelection& selection) {
  VariantInputs out;
  out.name = variant.name;
  out.where = variant.where;
  out.program = program_for(scenario, variant);
  if (selection.tolerance) apply_tolerance(out.program, *selection.tolerance);
  out.timing = timing_options(scenario, variant);
  if (selection.limits) {
    out.timing.limits = *selection.limits;
    // the axis limits are held on the TCP's vectors: the path mode has none
    if (*selection.limits == LimitsMode::kPath) out.timing.axis_limits.reset();
  }
  if (selection.timing) out.timing.algorithm = *selection.timing;
  // what it is: its own transition, else the first move's method
  out.method = variant.transition ? variant.transition->method : out.program.moves.front().transition.method;
  out.parameter = variant.transition ? variant.transition->parameter : 0.0;
  out.tolerance = variant.transition ? variant.transition->tolerance : 0.0;
  if (selection.tolerance && out.method != Method::kNone) {
    out.parameter = 0;
    out.tolerance = *selection.tolerance;
  }
  return out;
}

RunInputs resolve_run(const Scenario& scenario, const RunSelection& selection) {
  std::vector<const Variant*> selected;
  for (const std::string& name : selection.variants) selected.push_back(&find_variant(scenario, name));
  if (selection.variants.empty()) {
    for (const Variant& v : scenario.variants) selected.push_back(&v);
  }
  RunInputs out;
  out.file = scenario.file;
  out.name = scenario.name;
  out.description = scenario.description;
  out.frame = scenario.frame;
  out.start = scenario.start;
  out.ignored = scenario.ignored;
  out.warnings = scenario.warnings;
  out.robot = scenario.robot;
  out.servo = scenario.servo;
  out.simulation = scenario.simulation;
  out.video = scenario.video;
  out.sensitivity = scenario.sensitivity;
  out.variants.reserve(selected.size());
  for (const Variant* v : selected) {
    // variant names become folders under the output folder: never a path that leaves it
    if (const std::string problem = folder_name_problem(v->name); !problem.empty()) {
      throw InputError(scenario.file, v->where.line, v->where.column, "variants[].name", "variant " + problem);
    }
    out.variants.push_back(resolve_variant(scenario, *v, selection));
  }
  return out;
}

}  // namespace blendbench
