#include "blendbench/app/compare.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "blendbench/core/format.hpp"
#include "blendbench/corner/blend.hpp"
#include "blendbench/io/program_io.hpp"

namespace blendbench {
namespace {

constexpr Method kMethods[] = {Method::kArc, Method::kBezier, Method::kClothoid, Method::kBiclothoid};

// Two tolerances closer than this (m) are one: a value given twice, or in two spellings.
constexpr double kSameTolerance = 1e-12;

std::string mm_text(double metres) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%g", metres * 1e3);
  return buffer;
}

Variant baseline(const std::string& name, TimingOptions::Baseline kind) {
  Variant v;
  v.name = name;
  v.transition = Transition{};
  v.baseline = kind;
  return v;
}

// Whether blending `program` cuts any corner (a transition of some length).
bool cuts_a_corner(const Path& path) {
  return std::any_of(path.corners.begin(), path.corners.end(), [](const CornerReport& c) { return c.length > 0; });
}

}  // namespace

std::vector<double> program_tolerances(const Program& program) {
  std::vector<double> out;
  for (const Move& m : program.moves) {
    // G64 P<tol> reads as the biclothoid's maximum deviation (gcode.hpp)
    if (!is_gcode_file(m.where.file) || m.transition.method != Method::kBiclothoid || !(m.transition.parameter > 0)) continue;
    const double t = m.transition.parameter;
    if (std::none_of(out.begin(), out.end(), [&](double u) { return std::abs(u - t) <= kSameTolerance; })) out.push_back(t);
  }
  return out;
}

std::string compare_variant_name(Method method, double tolerance) {
  return std::string(to_string(method)) + "_" + mm_text(tolerance) + "mm";
}

std::vector<Method> methods_from_list(const std::string& list, const std::string& flag) {
  std::vector<Method> out;
  std::stringstream in(list);
  std::string name;
  while (std::getline(in, name, ',')) {
    const std::optional<Method> m = method_from_string(name);
    if (!m || *m == Method::kNone) {
      throw InputError("", 0, 0, flag,
                       "unknown method '" + printable(name) + "' (arc, bezier, clothoid, biclothoid; the baselines always run)");
    }
    if (std::find(out.begin(), out.end(), *m) == out.end()) out.push_back(*m);
  }
  if (out.empty()) throw InputError("", 0, 0, flag, "names no method (arc, bezier, clothoid, biclothoid, separated by commas)");
  return out;
}

ComparePlan plan_compare(const Scenario& scenario, const CompareRequest& request) {
  ComparePlan plan;
  // the tolerances: as asked, else the program's G64 P, else the default
  std::vector<double> tolerances = request.tolerances;
  for (const double t : tolerances) {
    if (!(std::isfinite(t) && t > 0)) {
      throw InputError("", 0, 0, "--tolerance", "must be > 0 and finite (mm), got " + format_value(t * 1e3));
    }
  }
  if (tolerances.empty()) {
    tolerances = program_tolerances(scenario.program);
    if (!tolerances.empty()) {
      plan.notes.push_back("tolerance from the program's G64 P: " + mm_text(tolerances.front()) + " mm" +
                           (tolerances.size() > 1 ? " and " + std::to_string(tolerances.size() - 1) + " more" : ""));
    }
  }
  if (tolerances.empty()) tolerances.push_back(kDefaultCompareTolerance);
  std::sort(tolerances.begin(), tolerances.end());
  // two tolerances that name the same variant (%g keeps six digits: 0.1 and 0.1000001 mm are both
  // "0.1mm") are one, the smaller kept: two variants of one name would share a folder
  tolerances.erase(std::unique(tolerances.begin(), tolerances.end(),
                               [](double a, double b) { return std::abs(a - b) <= kSameTolerance || mm_text(a) == mm_text(b); }),
                   tolerances.end());
  if (tolerances.size() > kMaxCompareTolerances) {
    throw InputError("", 0, 0, "--tolerance",
                     "at most " + std::to_string(kMaxCompareTolerances) + " tolerances in one comparison, got " +
                         std::to_string(tolerances.size()));
  }
  plan.tolerances = tolerances;
  const std::vector<Method> requested =
      request.methods.empty() ? std::vector<Method>(std::begin(kMethods), std::end(kMethods)) : request.methods;

  // the program as written, every move open to the variants' transitions
  Scenario compared = scenario;
  if (std::find(compared.explicit_transition.begin(), compared.explicit_transition.end(), true) !=
      compared.explicit_transition.end()) {
    plan.notes.push_back("the moves that set their own transition in " + scenario.file +
                         " take each compared method's instead (like for like)");
  }
  std::fill(compared.explicit_transition.begin(), compared.explicit_transition.end(), false);
  if (!scenario.variants.empty() && !is_gcode_file(scenario.file)) {
    plan.notes.push_back("the scenario's own " + std::to_string(scenario.variants.size()) +
                         " variant(s) are not run: compare runs both baselines and every method at each tolerance");
  }
  compared.variants = {baseline("exact_stop", TimingOptions::Baseline::kNone),
                       baseline("junction_slowdown", TimingOptions::Baseline::kJunctionSlowdown)};

  // each method that applies: its blend of the program succeeds (checked here, before anything
  // runs, so a refusal is a note and not a failed variant)
  bool any_cut = false;
  for (const Method m : requested) {
    std::vector<Variant> variants;
    std::string refused;
    bool cut = false;
    for (const double t : tolerances) {
      Variant v;
      v.name = compare_variant_name(m, t);
      v.transition = Transition{};
      v.transition->method = m;
      v.transition->tolerance = t;
      try {
        cut = cuts_a_corner(blend(program_for(compared, v))) || cut;
      } catch (const InputError& e) {
        refused = e.what();
        break;
      }
      variants.push_back(std::move(v));
    }
    if (!refused.empty()) {
      plan.notes.push_back(std::string(to_string(m)) + " left out: it cannot blend this program (" + refused + ")");
      continue;
    }
    any_cut = any_cut || cut;
    plan.methods.push_back(m);
    compared.variants.insert(compared.variants.end(), variants.begin(), variants.end());
  }
  if (!any_cut) {
    // nothing to compare: no corner any method would cut (or no method that can blend it)
    compared.variants.resize(1);
    plan.notes.push_back(plan.methods.empty() ? "no method can blend this program: the exact stop runs alone"
                                              : "no corners: no method cuts any corner of this program, so the exact stop "
                                                "runs alone");
    plan.methods.clear();
  }
  if (compared.variants.size() > kMaxVariants) {
    throw InputError("", 0, 0, "--tolerance",
                     std::to_string(compared.variants.size()) + " variants; at most " + std::to_string(kMaxVariants) +
                         " in one run");
  }
  // the variants, ordered: baselines, then by tolerance, then by method
  std::stable_sort(compared.variants.begin() + (compared.variants.size() > 2 ? 2 : compared.variants.size()),
                   compared.variants.end(), [](const Variant& a, const Variant& b) {
                     return a.transition->tolerance < b.transition->tolerance - kSameTolerance;
                   });
  plan.inputs = resolve_run(compared);
  // the run is not the scenario's: its own name, so `check` never holds it against the
  // scenario's baseline and its folder is not the scenario's run's
  plan.inputs.name = scenario.name + "_compare";
  plan.inputs.notes = plan.notes;
  return plan;
}

}  // namespace blendbench
