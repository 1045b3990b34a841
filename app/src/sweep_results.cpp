#include "blendbench/app/sweep_results.hpp"
#include "blendbench/app/version.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "blendbench/report/output.hpp"

namespace blendbench {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

void flatten_into(const nlohmann::json& j, const std::string& name, std::map<std::string, double>& out) {
  if (j.is_object()) {
    for (const auto& [key, value] : j.items()) flatten_into(value, name.empty() ? key : name + "." + key, out);
  } else if (j.is_array()) {
    for (std::size_t i = 0; i < j.size(); ++i) flatten_into(j[i], name + "[" + std::to_string(i) + "]", out);
  } else if (j.is_number()) {
    out[name] = j.get<double>();
  } else if (j.is_boolean()) {
    out[name] = j.get<bool>() ? 1.0 : 0.0;
  } else if (j.is_null()) {
    out[name] = kNaN;
  }
}

double metric_of(const SweepRow& row, const std::string& name) {
  const auto it = row.metrics.find(name);
  return it == row.metrics.end() ? kNaN : it->second;
}

// A CSV cell: quoted when it holds a separator, a quote or a line break.
std::string csv_cell(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

void append_csv_line(std::string& out, const std::vector<std::string>& cells) {
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (i > 0) out += ',';
    out += csv_cell(cells[i]);
  }
  out += '\n';
}

std::string number_cell(double value) { return std::isnan(value) ? std::string() : format_value(value, 10); }

nlohmann::json number_json(double value) { return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(); }

std::string html_escape(const std::string& text) {
  std::string out;
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string base64(const std::string& bytes) {
  static const char* kDigits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t n = std::min<std::size_t>(3, bytes.size() - i);
    std::uint32_t v = 0;
    for (std::size_t k = 0; k < 3; ++k) {
      v = (v << 8) | (k < n ? static_cast<unsigned char>(bytes[i + k]) : 0U);
    }
    for (std::size_t k = 0; k < 4; ++k) out += k <= n ? kDigits[(v >> (18 - 6 * k)) & 0x3fU] : '=';
  }
  return out;
}

// The metric names of the best table: the Pareto axes, then those a constraint names.
std::vector<std::string> best_metrics(const SweepSpec& spec) {
  std::vector<std::string> names = {spec.pareto_x, spec.pareto_y};
  for (const Constraint& c : spec.constraints) {
    if (std::find(names.begin(), names.end(), c.metric) == names.end()) names.push_back(c.metric);
  }
  return names;
}

std::string constraints_text(const SweepSpec& spec) {
  std::string out;
  for (const Constraint& c : spec.constraints) out += (out.empty() ? "" : ", ") + c.text;
  return out.empty() ? "no constraints" : out;
}

// The rows of the best table as text cells: a header, then one line per method.
std::vector<std::vector<std::string>> best_cells(const SweepPlan& plan, const SweepTable& table) {
  const SweepSpec& spec = plan.spec;
  std::vector<std::vector<std::string>> cells;
  std::vector<std::string> header = {"method", "variant", "point"};
  for (const SweepAxis& axis : spec.axes) header.push_back(axis.path);
  const std::vector<std::string> metrics = best_metrics(spec);
  header.insert(header.end(), metrics.begin(), metrics.end());
  cells.push_back(header);
  for (const MethodSummary& m : table.methods) {
    std::vector<std::string> line = {m.method};
    if (m.best) {
      const SweepRow& row = table.rows[*m.best];
      const SweepPoint& point = plan.points[row.point];
      line.push_back(row.variant);
      line.push_back(std::to_string(row.point));
      for (std::size_t a = 0; a < spec.axes.size(); ++a) line.push_back(spec.axes[a].labels[point.choice[a]]);
      for (const std::string& name : metrics) line.push_back(number_cell(metric_of(row, name)));
    }
    cells.push_back(line);
  }
  return cells;
}

}  // namespace

std::map<std::string, double> flatten_metrics(const nlohmann::json& entry) {
  std::map<std::string, double> out;
  if (entry.is_object()) flatten_into(entry, "", out);
  return out;
}

std::vector<VariantResult> variant_results(const nlohmann::json& summary, const std::set<std::string>& named,
                                           std::set<std::string>* known) {
  std::vector<VariantResult> out;
  if (!summary.is_object()) return out;
  const auto variants = summary.find("variants");
  if (variants == summary.end() || !variants->is_array()) return out;
  const auto text = [](const nlohmann::json& v, const char* key) {
    const auto it = v.find(key);
    return it != v.end() && it->is_string() ? it->get<std::string>() : std::string();
  };
  for (const nlohmann::json& v : *variants) {
    if (!v.is_object()) continue;
    VariantResult r{text(v, "name"), text(v, "method"), text(v, "status"), text(v, "message"), {}};
    // only the metrics a table can show are kept: a report field per corner costs memory per row
    for (auto& [key, value] : flatten_metrics(v)) {
      if (known != nullptr && r.status == "ok") known->insert(key);
      if (default_metric(key) || named.count(key) != 0) r.metrics.emplace(key, value);
    }
    out.push_back(std::move(r));
  }
  return out;
}

bool machine_metric(const std::string& name) {
  return name.find("wall_time") != std::string::npos || name.find("real_time_factor") != std::string::npos;
}

bool report_field(const std::string& name) { return name.find("].") != std::string::npos; }

bool default_metric(const std::string& name) { return !machine_metric(name) && !report_field(name); }

std::set<std::string> named_metrics(const SweepSpec& spec) {
  std::set<std::string> names;
  for (const MetricName& m : spec.named_metrics) names.insert(m.name);
  return names;
}

void check_metric_names(const SweepSpec& spec, const std::set<std::string>& known) {
  for (const MetricName& m : spec.named_metrics) {
    if (known.count(m.name) != 0) continue;
    std::string list;
    std::size_t reports = 0;
    std::string example;
    for (const std::string& k : known) {
      if (report_field(k)) {
        if (++reports == 1) example = k;
      } else {
        list += (list.empty() ? "" : ", ") + k;
      }
    }
    if (reports > 0) list += "; and " + std::to_string(reports) + " fields of the reports per corner and piece, such as " + example;
    fail_at(m.where, m.field, "no metric '" + m.name + "' in the runs' summaries (metrics: " + list + ")");
  }
}

SweepTable build_table(const SweepPlan& plan, std::vector<PointOutcome> outcomes, const std::set<std::string>& known) {
  const SweepSpec& spec = plan.spec;
  SweepTable table;

  // a row per point and variant, from the variant's entry in the point's summary
  std::map<std::string, std::string> method_of_variant;
  std::set<std::string> columns;
  for (std::size_t p = 0; p < plan.points.size(); ++p) {
    PointOutcome& outcome = outcomes[p];
    for (const std::string& name : plan.points[p].variants) {
      SweepRow row;
      row.point = p;
      row.variant = name;
      row.status = outcome.status;
      row.message = outcome.message;
      const auto entry = std::find_if(outcome.variants.begin(), outcome.variants.end(),
                                      [&](const VariantResult& v) { return v.name == name; });
      if (entry != outcome.variants.end()) {
        row.metrics = std::move(entry->metrics);
        if (outcome.status == "ok" || outcome.status == "failed") row.status = entry->status.empty() ? "failed" : entry->status;
        if (row.status != "ok") row.message = entry->message.empty() ? outcome.message : entry->message;
        if (!entry->method.empty()) method_of_variant.emplace(name, entry->method);
        for (const auto& [key, value] : row.metrics) columns.insert(key);
      } else if (outcome.status == "ok" || outcome.status == "failed") {
        row.status = "error";
        row.message = "the run's summary has no variant '" + name + "'";
      }
      table.rows.push_back(std::move(row));
    }
  }
  for (SweepRow& row : table.rows) {
    const auto it = method_of_variant.find(row.variant);
    row.method = it == method_of_variant.end() ? row.variant : it->second;
  }
  if (!known.empty()) check_metric_names(spec, known);

  // the metric columns
  if (spec.metrics.empty()) {
    for (const std::string& k : columns) {
      if (default_metric(k)) table.metrics.push_back(k);
    }
  } else {
    table.metrics = spec.metrics;
  }
  for (const std::string& name : best_metrics(spec)) {
    if (std::find(table.metrics.begin(), table.metrics.end(), name) == table.metrics.end()) table.metrics.push_back(name);
  }

  // constraints
  for (SweepRow& row : table.rows) {
    row.meets_constraints = row.status == "ok" && std::all_of(spec.constraints.begin(), spec.constraints.end(),
                                                              [&](const Constraint& c) { return meets(c, metric_of(row, c.metric)); });
  }

  // per method, in order met: the Pareto front (least x and y) and the best row
  std::vector<std::string> order;
  for (const SweepRow& row : table.rows) {
    if (std::find(order.begin(), order.end(), row.method) == order.end()) order.push_back(row.method);
  }
  const auto y_key = [](double y) { return std::isnan(y) ? std::numeric_limits<double>::infinity() : y; };
  for (const std::string& method : order) {
    MethodSummary m;
    m.method = method;
    std::vector<std::size_t> candidates;
    for (std::size_t i = 0; i < table.rows.size(); ++i) {
      const SweepRow& row = table.rows[i];
      if (row.method != method) continue;
      ++m.rows;
      if (row.status != "ok") continue;
      ++m.ok;
      m.meeting += row.meets_constraints ? 1 : 0;
      const double x = metric_of(row, spec.pareto_x);
      const double y = metric_of(row, spec.pareto_y);
      if (std::isfinite(x) && std::isfinite(y)) candidates.push_back(i);
      if (row.meets_constraints && std::isfinite(x)) {
        const auto better = [&](std::size_t a, std::size_t b) {
          const double xa = metric_of(table.rows[a], spec.pareto_x);
          const double xb = metric_of(table.rows[b], spec.pareto_x);
          if (xa != xb) return xa < xb;
          return y_key(metric_of(table.rows[a], spec.pareto_y)) < y_key(metric_of(table.rows[b], spec.pareto_y));
        };
        if (!m.best || better(i, *m.best)) m.best = i;
      }
    }
    // sorted by x then y, a row is on the front when its y is below every earlier one (or it
    // equals the last front row: the same setting twice)
    std::stable_sort(candidates.begin(), candidates.end(), [&](std::size_t a, std::size_t b) {
      const double xa = metric_of(table.rows[a], spec.pareto_x);
      const double xb = metric_of(table.rows[b], spec.pareto_x);
      if (xa != xb) return xa < xb;
      return metric_of(table.rows[a], spec.pareto_y) < metric_of(table.rows[b], spec.pareto_y);
    });
    double y_min = std::numeric_limits<double>::infinity();
    for (const std::size_t i : candidates) {
      const double x = metric_of(table.rows[i], spec.pareto_x);
      const double y = metric_of(table.rows[i], spec.pareto_y);
      const bool repeat = !m.front.empty() && x == metric_of(table.rows[m.front.back()], spec.pareto_x) &&
                          y == metric_of(table.rows[m.front.back()], spec.pareto_y);
      if (y < y_min || repeat) {
        m.front.push_back(i);
        table.rows[i].on_pareto_front = true;
        y_min = std::min(y_min, y);
      }
    }
    table.methods.push_back(std::move(m));
  }
  std::stable_sort(table.methods.begin(), table.methods.end(), [&](const MethodSummary& a, const MethodSummary& b) {
    if (a.best.has_value() != b.best.has_value()) return a.best.has_value();
    if (!a.best) return false;
    return metric_of(table.rows[*a.best], spec.pareto_x) < metric_of(table.rows[*b.best], spec.pareto_x);
  });
  return table;
}

std::string sweep_csv(const SweepPlan& plan, const SweepTable& table) {
  std::vector<std::string> header = {"point", "variant", "method"};
  for (const SweepAxis& axis : plan.spec.axes) header.push_back(axis.path);
  header.insert(header.end(), {"status", "meets_constraints", "on_pareto_front"});
  header.insert(header.end(), table.metrics.begin(), table.metrics.end());
  std::string out;
  append_csv_line(out, header);
  std::vector<std::string> cells;
  for (const SweepRow& row : table.rows) {
    const SweepPoint& point = plan.points[row.point];
    cells = {std::to_string(row.point), row.variant, row.method};
    for (std::size_t a = 0; a < plan.spec.axes.size(); ++a) cells.push_back(plan.spec.axes[a].labels[point.choice[a]]);
    cells.push_back(row.status);
    cells.push_back(row.meets_constraints ? "true" : "false");
    cells.push_back(row.on_pareto_front ? "true" : "false");
    for (const std::string& m : table.metrics) cells.push_back(number_cell(metric_of(row, m)));
    append_csv_line(out, cells);
  }
  return out;
}

nlohmann::json sweep_json(const SweepPlan& plan, const SweepTable& table) {
  const SweepSpec& spec = plan.spec;
  nlohmann::json axes = nlohmann::json::array();
  for (const SweepAxis& axis : spec.axes) axes.push_back({{"path", axis.path}, {"values", axis.labels}});
  nlohmann::json constraints = nlohmann::json::array();
  for (const Constraint& c : spec.constraints) constraints.push_back(c.text);
  nlohmann::json rows = nlohmann::json::array();
  for (const SweepRow& row : table.rows) {
    const SweepPoint& point = plan.points[row.point];
    nlohmann::json values = nlohmann::json::object();
    for (std::size_t a = 0; a < spec.axes.size(); ++a) values[spec.axes[a].path] = spec.axes[a].labels[point.choice[a]];
    nlohmann::json metrics = nlohmann::json::array();
    for (const std::string& m : table.metrics) metrics.push_back(number_json(metric_of(row, m)));
    nlohmann::json r = {{"point", row.point},     {"hash", point.hash},
                        {"variant", row.variant}, {"method", row.method},
                        {"values", values},       {"status", row.status},
                        {"meets_constraints", row.meets_constraints},
                        {"on_pareto_front", row.on_pareto_front},
                        {"metrics", metrics}};
    if (!row.message.empty()) r["message"] = row.message;
    rows.push_back(std::move(r));
  }
  nlohmann::json methods = nlohmann::json::array();
  for (const MethodSummary& m : table.methods) {
    methods.push_back({{"method", m.method},
                       {"pareto_front", m.front},
                       {"best", m.best ? nlohmann::json(*m.best) : nlohmann::json()},
                       {"rows", m.rows},
                       {"ok", m.ok},
                       {"meeting_constraints", m.meeting}});
  }
  return {{"version", version_string()},
          {"sweep", spec.file},
          {"scenario", spec.scenario},
          {"description", spec.description},
          {"variants", spec.variants},
          {"axes", axes},
          {"metrics", table.metrics},
          {"constraints", constraints},
          {"pareto", {{"x", spec.pareto_x}, {"y", spec.pareto_y}}},
          {"points", plan.points.size()},
          {"rows", rows},
          {"methods", methods}};
}

std::string best_csv(const SweepPlan& plan, const SweepTable& table) {
  std::string out;
  for (const std::vector<std::string>& line : best_cells(plan, table)) append_csv_line(out, line);
  return out;
}

namespace {

// A column of numbers (the page, the terminal): each with the same decimals, enough for three significant
// digits of its smallest non-zero magnitude (0 to 6), so 0.8710605408 over 12.5 reads 0.871 over
// 12.500. Cells that are not numbers stay as they are.
void fix_decimals(std::vector<std::vector<std::string>>& cells, std::size_t column) {
  double smallest = std::numeric_limits<double>::infinity();
  for (std::size_t k = 1; k < cells.size(); ++k) {
    if (column >= cells[k].size() || cells[k][column].empty()) continue;
    char* end = nullptr;
    const double v = std::strtod(cells[k][column].c_str(), &end);
    if (end == cells[k][column].c_str() || *end != '\0' || !std::isfinite(v)) return;  // not a number column
    if (v != 0) smallest = std::min(smallest, std::abs(v));
  }
  int decimals = std::isfinite(smallest) ? std::clamp(2 - static_cast<int>(std::floor(std::log10(smallest))), 0, 6) : 0;
  // times in s to the ms, as everywhere else (a cycle time of 1.854 s is not 1.85)
  if (cells.front()[column].ends_with("_s")) decimals = std::max(decimals, 3);
  for (std::size_t k = 1; k < cells.size(); ++k) {
    if (column >= cells[k].size() || cells[k][column].empty()) continue;
    cells[k][column] = format_fixed(std::strtod(cells[k][column].c_str(), nullptr), decimals);
  }
}

}  // namespace

std::string best_text(const SweepPlan& plan, const SweepTable& table) {
  std::vector<std::vector<std::string>> cells = best_cells(plan, table);
  // the metrics' columns in one count of decimals each (best.csv keeps every digit)
  for (std::size_t c = 3 + plan.spec.axes.size(); c < cells.front().size(); ++c) fix_decimals(cells, c);
  std::vector<std::size_t> width(cells.front().size(), 0);
  for (const auto& line : cells) {
    for (std::size_t i = 0; i < line.size(); ++i) width[i] = std::max(width[i], line[i].size());
  }
  std::string out = "best setting per method (least " + plan.spec.pareto_x + ") under " + constraints_text(plan.spec) + ":\n";
  for (std::size_t k = 0; k < cells.size(); ++k) {
    const auto& line = cells[k];
    std::string text;
    for (std::size_t i = 0; i < line.size(); ++i) {
      text += line[i] + std::string(i + 1 < line.size() ? width[i] - line[i].size() + 2 : 0, ' ');
    }
    if (k > 0 && line.size() == 1) {
      const MethodSummary& m = table.methods[k - 1];
      text += std::string(width[0] - line[0].size() + 2, ' ') + "no setting meets the constraints (" +
              std::to_string(m.ok) + " of " + std::to_string(m.rows) + " rows ran ok)";
    }
    while (!text.empty() && text.back() == ' ') text.pop_back();
    out += "  " + text + "\n";
  }
  if (!table.methods.empty() && table.methods.front().best) {
    const SweepRow& row = table.rows[*table.methods.front().best];
    out += "best: " + row.method + " (variant " + row.variant + ", point " + std::to_string(row.point) + ": " +
           point_values_text(plan.spec, plan.points[row.point]) + "), " + plan.spec.pareto_x + " " +
           number_cell(metric_of(row, plan.spec.pareto_x)) + "\n";
  } else {
    out += "best: no setting of any method meets the constraints\n";
  }
  return out;
}

namespace {

// A header that may break after each '_' (a long key does not widen the table past the page).
std::string breakable(const std::string& key) {
  std::string out;
  for (const char c : html_escape(key)) {
    out += c;
    if (c == '_') out += "<wbr>";
  }
  return out;
}

}  // namespace

std::string report_html(const SweepPlan& plan, const SweepTable& table, const std::string& pareto_png) {
  const SweepSpec& spec = plan.spec;
  std::string out =
      "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>sweep " + html_escape(spec.file) +
      "</title>\n<style>body{font-family:sans-serif;max-width:1100px;margin:2em auto;padding:0 1em}"
      "table{border-collapse:collapse}td,th{border:1px solid #bbb;padding:3px 8px;text-align:right}"
      "th{background:#eee;font-size:12px}td:first-child,td:nth-child(2){text-align:left}img{max-width:100%}"
      ".wide{overflow-x:auto}</style>\n</head><body>\n";
  out += "<h1>Sweep: " + html_escape(spec.file) + "</h1>\n";
  if (!spec.description.empty()) out += "<p>" + html_escape(spec.description) + "</p>\n";
  out += "<p>Scenario " + html_escape(spec.scenario) + "; " + std::to_string(plan.points.size()) + " points, " +
         std::to_string(table.rows.size()) + " rows (point &times; variant).</p>\n<ul>\n";
  for (const SweepAxis& axis : spec.axes) {
    std::string values;
    for (const std::string& v : axis.labels) values += (values.empty() ? "" : ", ") + v;
    out += "<li><code>" + html_escape(axis.path) + "</code>: " + html_escape(values) + "</li>\n";
  }
  out += "</ul>\n<p>Constraints: " + html_escape(constraints_text(spec)) + ".</p>\n";
  out += "<h2>Pareto front: " + html_escape(spec.pareto_x) + " against " + html_escape(spec.pareto_y) + "</h2>\n";
  if (pareto_png.empty()) {
    out += "<p>(no plot: the plot script did not run)</p>\n";
  } else {
    out += "<img alt=\"Pareto front per method\" src=\"data:image/png;base64," + base64(pareto_png) + "\">\n";
  }
  out += "<h2>Best setting per method under the constraints</h2>\n<div class=\"wide\"><table>\n";
  std::vector<std::vector<std::string>> cells = best_cells(plan, table);
  // the metric columns (after method, variant, point and the axes) with one count of decimals each
  for (std::size_t c = 3 + spec.axes.size(); c < cells.front().size(); ++c) fix_decimals(cells, c);
  for (std::size_t k = 0; k < cells.size(); ++k) {
    const char* tag = k == 0 ? "th" : "td";
    out += "<tr>";
    for (const std::string& cell : cells[k]) {
      out += std::string("<") + tag + ">" + (k == 0 ? breakable(cell) : html_escape(cell)) + "</" + tag + ">";
    }
    if (k > 0 && cells[k].size() == 1) {
      out += "<td colspan=\"" + std::to_string(cells[0].size() - 1) + "\">no setting meets the constraints</td>";
    }
    out += "</tr>\n";
  }
  out += "</table></div>\n<p>Every row: <code>sweep.csv</code>, <code>sweep.json</code>.</p>\n</body></html>\n";
  return out;
}

}  // namespace blendbench
