#include "blendbench/report/check.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include "blendbench/core/format.hpp"
#include "blendbench/core/input_error.hpp"
#include "blendbench/report/output.hpp"

namespace blendbench {
namespace {

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

std::string line(const std::string& variant, const MetricTolerance& t, double value, double base, double bound) {
  return variant + ": " + t.metric + " = " + format_value(value, 6) + " (baseline " + format_value(base, 6) +
         (t.higher_is_better ? ", allowed down to " : ", allowed up to ") + format_value(bound, 6) + ")";
}

std::string verdict_name(CheckRow::Verdict v) {
  switch (v) {
    case CheckRow::Verdict::kUnchanged:
      return "unchanged";
    case CheckRow::Verdict::kWithin:
      return "within tolerance";
    case CheckRow::Verdict::kImproved:
      return "improved (update the baseline)";
    case CheckRow::Verdict::kRegressed:
      return "REGRESSION";
  }
  return "?";
}

}  // namespace

std::vector<MetricTolerance> parse_tolerances(const nlohmann::json& content, const std::string& file) {
  const auto bad = [&](const std::string& field, const std::string& message) {
    throw InputError(file, 0, 0, field, message);
  };
  if (!content.is_object() || !content.contains("metrics") || !content["metrics"].is_object() ||
      content["metrics"].empty()) {
    bad("metrics", "a tolerance file needs a non-empty object 'metrics' (metric name -> {relative, absolute, better})");
  }
  std::vector<MetricTolerance> out;
  for (const auto& [name, entry] : content["metrics"].items()) {
    const std::string field = "metrics." + name;
    if (!entry.is_object()) bad(field, "must be an object {relative, absolute, better, why}");
    MetricTolerance t;
    t.metric = name;
    for (const char* key : {"relative", "absolute"}) {
      if (!entry.contains(key) || !entry[key].is_number() || !(entry[key].get<double>() >= 0) ||
          !std::isfinite(entry[key].get<double>())) {
        bad(field + "." + key, "needs a finite number >= 0");
      }
    }
    for (const char* key : {"better", "why"}) {
      if (entry.contains(key) && !entry[key].is_string()) bad(field + "." + key, "must be a string");
    }
    t.relative = entry["relative"].get<double>();
    t.absolute = entry["absolute"].get<double>();
    const std::string better = entry.value("better", "lower");
    if (better != "lower" && better != "higher") bad(field + ".better", "must be 'lower' or 'higher', got '" + better + "'");
    t.higher_is_better = better == "higher";
    t.why = entry.value("why", "");
    for (const auto& [key, value] : entry.items()) {
      if (key != "relative" && key != "absolute" && key != "better" && key != "why") {
        bad(field + "." + key, "unknown key (valid: relative, absolute, better, why)");
      }
    }
    out.push_back(std::move(t));
  }
  return out;
}

void validate_run_summary(const nlohmann::json& summary, const std::string& file) {
  const auto bad = [&](const std::string& field, const std::string& message) { throw InputError(file, 0, 0, field, message); };
  if (!summary.is_object()) bad("", "not a run summary: expected a JSON object with 'scenario' and 'variants'");
  if (const auto it = summary.find("scenario"); it != summary.end() && !it->is_string()) bad("scenario", "must be a name");
  const auto variants = summary.find("variants");
  if (variants == summary.end() || !variants->is_array()) bad("variants", "a run summary needs a list 'variants'");
  for (std::size_t i = 0; i < variants->size(); ++i) {
    const nlohmann::json& v = (*variants)[i];
    const std::string field = "variants[" + std::to_string(i) + "]";
    if (!v.is_object()) bad(field, "must be an object with 'name' and 'status'");
    if (!v.contains("name") || !v["name"].is_string()) bad(field + ".name", "must be a name");
    // every variant of a run has a status (make_baseline copies it; fuzz_check found one without)
    if (!v.contains("status") || !v["status"].is_string()) bad(field + ".status", "must be a string (ok, failed, ...)");
    if (v.contains("message") && !v["message"].is_string()) bad(field + ".message", "must be a string");
  }
}

nlohmann::json make_baseline(const nlohmann::json& summary, const std::vector<MetricTolerance>& tolerances) {
  nlohmann::json variants = nlohmann::json::object();
  for (const auto& v : summary.at("variants")) {
    nlohmann::json entry = {{"status", v.at("status")}};
    for (const MetricTolerance& t : tolerances) {
      if (const nlohmann::json* value = at_path(v, t.metric); value != nullptr && value->is_number()) entry[t.metric] = *value;
    }
    variants[v.at("name").get<std::string>()] = entry;
  }
  return {{"scenario", summary.value("scenario", "")}, {"variants", variants}};
}

CheckReport check_run(const nlohmann::json& summary, const nlohmann::json& baseline,
                      const std::vector<MetricTolerance>& tolerances, const std::string& baseline_file) {
  const auto bad = [&](const std::string& field, const std::string& message) {
    throw InputError(baseline_file, 0, 0, field, message);
  };
  if (!baseline.is_object() || !baseline.contains("variants") || !baseline["variants"].is_object()) {
    bad("variants", "a baseline needs an object 'variants'");
  }
  const std::string scenario = summary.value("scenario", "");
  if (!baseline.contains("scenario") || !baseline["scenario"].is_string()) bad("scenario", "a baseline needs its scenario's name");
  if (const std::string of = baseline["scenario"].get<std::string>(); of != scenario) {
    bad("scenario", "is the baseline of scenario '" + of + "', but the run is of scenario '" + scenario +
                        "': check against results/baselines/" + scenario + ".json (without --baseline), or create that " +
                        "baseline deliberately with `blendbench check RUN_DIR --update`");
  }
  CheckReport report;
  std::map<std::string, const nlohmann::json*> run;
  for (const auto& v : summary.at("variants")) run[v.at("name").get<std::string>()] = &v;

  for (const auto& [name, base] : baseline["variants"].items()) {
    if (!base.is_object()) bad("variants." + name, "must be an object {status, metric: value, ...}");
    if (base.contains("status") && !base["status"].is_string()) bad("variants." + name + ".status", "must be a string");
    const auto it = run.find(name);
    if (it == run.end()) {
      report.regressions.push_back(name + ": variant missing from the run");
      continue;
    }
    const nlohmann::json& v = *it->second;
    const std::string status = v.value("status", "?");
    const std::string base_status = base.value("status", "ok");
    if (status != base_status) {
      report.regressions.push_back(name + ": status " + status + " (baseline " + base_status + ")" +
                                   (v.value("message", "").empty() ? "" : ": " + v.value("message", "")));
      continue;
    }
    for (const MetricTolerance& t : tolerances) {
      if (!base.contains(t.metric)) continue;
      if (!base[t.metric].is_number()) bad("variants." + name + "." + t.metric, "must be a number");
      const double b = base[t.metric].get<double>();
      const double slack = std::abs(b) * t.relative + t.absolute;
      CheckRow row{name, t.metric, b, 0, t.higher_is_better ? b - slack : b + slack, CheckRow::Verdict::kUnchanged};
      const nlohmann::json* found = at_path(v, t.metric);
      if (found == nullptr || !found->is_number()) {
        report.regressions.push_back(name + ": " + t.metric + " is missing or not a number (e.g. the run did not settle)");
        row.value = std::nan("");
        row.verdict = CheckRow::Verdict::kRegressed;
        report.rows.push_back(row);
        continue;
      }
      row.value = found->get<double>();
      const double worse = t.higher_is_better ? b - row.value : row.value - b;  // > 0: worse
      if (!(worse <= slack)) {
        row.verdict = CheckRow::Verdict::kRegressed;
        report.regressions.push_back(line(name, t, row.value, b, row.bound));
      } else if (-worse > slack) {
        row.verdict = CheckRow::Verdict::kImproved;
        report.notes.push_back(name + ": " + t.metric + " improved to " + format_value(row.value, 6) + " from " +
                               format_value(b, 6) + "; update the baseline with --update");
      } else if (row.value != b) {
        row.verdict = CheckRow::Verdict::kWithin;
      }
      report.rows.push_back(row);
    }
  }
  for (const auto& [name, v] : run) {
    if (!baseline["variants"].contains(name)) report.notes.push_back(name + ": not in the baseline");
  }
  return report;
}

std::string moved_table(const CheckReport& report) {
  std::vector<std::vector<std::string>> cells = {{"variant", "metric", "baseline", "value", "change", "allowed", "verdict"}};
  for (const CheckRow& r : report.rows) {
    if (r.verdict == CheckRow::Verdict::kUnchanged) continue;
    const std::string change = r.baseline != 0 && std::isfinite(r.value)
                                   ? format_value(100 * (r.value - r.baseline) / std::abs(r.baseline), 3) + " %"
                                   : std::string("-");
    cells.push_back({r.variant, r.metric, format_value(r.baseline, 6), std::isfinite(r.value) ? format_value(r.value, 6) : "missing",
                     change, format_value(r.bound, 6), verdict_name(r.verdict)});
  }
  if (cells.size() == 1) return "nothing moved\n";
  std::vector<std::size_t> width(cells[0].size(), 0);
  for (const auto& row : cells) {
    for (std::size_t c = 0; c < row.size(); ++c) width[c] = std::max(width[c], row[c].size());
  }
  std::string out;
  for (const auto& row : cells) {
    for (std::size_t c = 0; c < row.size(); ++c) {
      out += row[c];
      if (c + 1 < row.size()) out += std::string(width[c] - row[c].size() + 2, ' ');
    }
    out += '\n';
  }
  return out;
}

}  // namespace blendbench
