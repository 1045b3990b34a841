#include "blendbench/report/check.hpp"

#include <cmath>
#include <map>
#include <utility>

#include "blendbench/core/input_error.hpp"
#include "blendbench/report/output.hpp"

namespace blendbench {
namespace {

// Default tolerances: timing is deterministic to the servo period, tracking metrics depend on
// floating-point details of the physics (few percent across compilers/CPUs), so they get
// relative plus absolute slack. A metric is named by its path in the variant's summary entry
// ("metrics.cycle_time_s" is v["metrics"]["cycle_time_s"]).
struct Tolerance {
  const char* metric;
  double relative;
  double absolute;
};
constexpr Tolerance kDefaults[] = {
    {"metrics.cycle_time_s", 0.01, 0.005},
    {"plan.planned_cycle_time_s", 0.005, 0.002},
    {"metrics.tracking_error_max_mm", 0.05, 0.002},
    {"metrics.tracking_error_rms_mm", 0.05, 0.001},
    {"metrics.contour_error_programmed_max_mm", 0.05, 0.01},
    {"metrics.contour_error_planned_max_mm", 0.05, 0.002},
    {"plan.path_deviation_max_mm", 0.02, 0.001},
    {"metrics.residual_vibration_final_mm", 0.1, 0.0005},
    {"metrics.residual_vibration_corner_max_mm", 0.1, 0.0005},
};

// The value at a dotted path of `v`, or nullptr when absent.
const nlohmann::json* at_path(const nlohmann::json& v, const std::string& path) {
  const nlohmann::json* node = &v;
  std::size_t begin = 0;
  while (true) {
    const std::size_t dot = path.find('.', begin);
    const std::string key = path.substr(begin, dot == std::string::npos ? std::string::npos : dot - begin);
    if (!node->is_object() || !node->contains(key)) return nullptr;
    node = &(*node)[key];
    if (dot == std::string::npos) return node;
    begin = dot + 1;
  }
}

std::string line(const std::string& variant, const std::string& metric, double value, double base, double bound) {
  return variant + ": " + metric + " = " + format_value(value, 6) + " (baseline " + format_value(base, 6) +
         ", allowed up to " + format_value(bound, 6) + ")";
}

}  // namespace

nlohmann::json make_baseline(const nlohmann::json& summary) {
  nlohmann::json tolerances = nlohmann::json::object();
  for (const Tolerance& t : kDefaults) tolerances[t.metric] = {{"relative", t.relative}, {"absolute", t.absolute}};
  nlohmann::json variants = nlohmann::json::object();
  for (const auto& v : summary.at("variants")) {
    nlohmann::json entry = {{"status", v.at("status")}};
    for (const Tolerance& t : kDefaults) {
      if (const nlohmann::json* value = at_path(v, t.metric); value != nullptr && value->is_number()) entry[t.metric] = *value;
    }
    variants[v.at("name").get<std::string>()] = entry;
  }
  return {{"scenario", summary.value("scenario", "")}, {"tolerances", tolerances}, {"variants", variants}};
}

CheckReport check_run(const nlohmann::json& summary, const nlohmann::json& baseline, const std::string& baseline_file) {
  const auto bad = [&](const std::string& field, const std::string& message) {
    throw InputError(baseline_file, 0, 0, field, message);
  };
  if (!baseline.is_object() || !baseline.contains("variants") || !baseline["variants"].is_object()) {
    bad("variants", "a baseline needs an object 'variants'");
  }
  if (!baseline.contains("tolerances") || !baseline["tolerances"].is_object()) {
    bad("tolerances", "a baseline needs an object 'tolerances'");
  }
  CheckReport report;
  std::map<std::string, const nlohmann::json*> run;
  for (const auto& v : summary.at("variants")) run[v.at("name").get<std::string>()] = &v;

  for (const auto& [name, base] : baseline["variants"].items()) {
    const auto it = run.find(name);
    if (it == run.end()) {
      report.regressions.push_back(name + ": variant missing from the run");
      continue;
    }
    const nlohmann::json& v = *it->second;
    if (v.value("status", "") != "ok") {
      report.regressions.push_back(name + ": status " + v.value("status", "?") + " (" + v.value("message", "") + ")");
      continue;
    }
    for (const auto& [metric, tol] : baseline["tolerances"].items()) {
      if (!base.contains(metric)) continue;
      if (!tol.contains("relative") || !tol.contains("absolute")) {
        bad("tolerances." + metric, "needs 'relative' and 'absolute'");
      }
      const double b = base[metric].get<double>();
      const double bound = b * (1 + tol["relative"].get<double>()) + tol["absolute"].get<double>();
      const nlohmann::json* found = at_path(v, metric);
      if (found == nullptr || !found->is_number()) {
        report.regressions.push_back(name + ": " + metric + " is missing or not a number (e.g. the run did not settle)");
        continue;
      }
      const double value = found->get<double>();
      if (!(value <= bound)) {
        report.regressions.push_back(line(name, metric, value, b, bound));
      } else if (value < b * (1 - tol["relative"].get<double>()) - tol["absolute"].get<double>()) {
        report.notes.push_back(name + ": " + metric + " improved to " + format_value(value, 6) + " from " +
                               format_value(b, 6) + "; update the baseline with --update");
      }
    }
  }
  for (const auto& [name, v] : run) {
    if (!baseline["variants"].contains(name)) report.notes.push_back(name + ": not in the baseline");
  }
  return report;
}

}  // namespace blendbench
