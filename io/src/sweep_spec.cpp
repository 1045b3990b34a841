#include "blendbench/io/sweep_spec.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <set>

#include "blendbench/io/data_root.hpp"
#include "blendbench/io/program_io.hpp"
#include "blendbench/io/scenario.hpp"
#include "blendbench/core/format.hpp"
#include "yaml_document.hpp"

namespace blendbench {
namespace {

namespace fs = std::filesystem;

static_assert(kMaxKeyPathSteps == static_cast<std::size_t>(yaml_detail::kMaxDepth));

// A key path as messages show it: a path of thousands of characters is cut, so that a refusal
// stays one readable line.
std::string shortened(const std::string& path) {
  constexpr std::size_t kShown = 120;
  if (path.size() <= kShown) return path;
  return path.substr(0, kShown) + "... (" + std::to_string(path.size()) + " characters)";
}

SourceRef mark_of(const std::string& file, const YAML::Node& node) {
  const YAML::Mark mark = node.IsDefined() ? node.Mark() : YAML::Mark::null_mark();
  return {file, mark.line >= 0 ? mark.line + 1 : 0, mark.column >= 0 ? mark.column + 1 : 0};
}

// The sweep file's nodes with their file, so every error names file, line, column and key.
class SweepReader {
 public:
  explicit SweepReader(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const YAML::Node& node, const std::string& field, const std::string& message) const {
    fail_at(mark_of(file_, node), field, message);
  }

  SourceRef where(const YAML::Node& node) const { return mark_of(file_, node); }

  std::string text(const YAML::Node& node, const std::string& field) const {
    if (!node.IsScalar()) fail(node, field, "expected a string");
    return node.Scalar();
  }

  double number(const YAML::Node& node, const std::string& field) const {
    if (!node.IsScalar()) fail(node, field, "expected a number");
    try {
      const double value = node.as<double>();
      if (!std::isfinite(value)) fail(node, field, "expected a finite number");
      return value;
    } catch (const YAML::BadConversion&) {
      fail(node, field, "expected a number, got '" + node.Scalar() + "'");
    }
  }

  std::vector<std::string> strings(const YAML::Node& node, const std::string& field, std::vector<SourceRef>* marks) const {
    if (!node.IsSequence()) fail(node, field, "expected a list of strings");
    std::vector<std::string> out;
    for (std::size_t i = 0; i < node.size(); ++i) {
      out.push_back(text(node[i], field + "[" + std::to_string(i) + "]"));
      if (marks != nullptr) marks->push_back(where(node[i]));
    }
    return out;
  }

  // Fails on any key of the mapping `node` that is not in `allowed`.
  void check_keys(const YAML::Node& node, const std::string& field, const std::vector<std::string>& allowed) const {
    if (!node.IsMap()) fail(node, field, "expected a mapping (key: value pairs)");
    for (const auto& item : node) {
      // a key is a name: a list or mapping as a key is refused where it stands
      if (!item.first.IsScalar()) fail(item.first, field, "a key must be a name, not a list or mapping");
      const std::string key = item.first.as<std::string>();
      if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
      std::string list;
      for (const std::string& k : allowed) list += (list.empty() ? "" : ", ") + k;
      fail(item.first, field.empty() ? key : field + "." + key, "unknown key '" + key + "' (allowed: " + list + ")");
    }
  }

  [[nodiscard]] const std::string& file() const { return file_; }

 private:
  std::string file_;
};

// Flow-style YAML text of a node, one line: how a non-scalar axis value reads in sweep.csv.
std::string flow_text(const YAML::Node& node) {
  YAML::Emitter out;
  out.SetMapFormat(YAML::Flow);
  out.SetSeqFormat(YAML::Flow);
  out << node;
  return out.c_str();
}

// The values of a range {from, to, steps, scale}: `steps` values from `from` to `to` inclusive,
// evenly spaced (linear) or with a constant ratio (log).
void read_range(const SweepReader& r, const YAML::Node& node, const std::string& field, SweepAxis& axis) {
  r.check_keys(node, field, {"from", "to", "steps", "scale"});
  for (const char* key : {"from", "to", "steps"}) {
    if (!node[key].IsDefined()) r.fail(node, field + "." + key, "missing required field of a range");
  }
  const double from = r.number(node["from"], field + ".from");
  const double to = r.number(node["to"], field + ".to");
  const YAML::Node steps_node = node["steps"];
  int steps = 0;
  try {
    steps = steps_node.as<int>();
  } catch (const YAML::BadConversion&) {
    r.fail(steps_node, field + ".steps", "expected an integer, got '" + steps_node.Scalar() + "'");
  }
  if (steps < 2) r.fail(steps_node, field + ".steps", "a range needs at least 2 steps (give one value as a list: [x])");
  // refused before its values are made: no sweep takes more points than this, and a range of
  // 44,444,443 steps once asked for 1 GiB of value texts (found by tests/fuzz/fuzz_sweep)
  if (static_cast<std::size_t>(steps) > kMaxSweepPoints) {
    r.fail(steps_node, field + ".steps",
           std::to_string(steps) + " steps exceed the " + std::to_string(kMaxSweepPoints) +
               " points a sweep may have: split the sweep");
  }
  bool log = false;
  if (const YAML::Node scale = node["scale"]; scale.IsDefined()) {
    const std::string s = r.text(scale, field + ".scale");
    if (s != "linear" && s != "log") r.fail(scale, field + ".scale", "scale must be 'linear' or 'log', got '" + s + "'");
    log = s == "log";
    if (log && !(from > 0 && to > 0)) {
      r.fail(node, field, "a log range needs positive ends, got from " + format_value(from) + " to " + format_value(to));
    }
  }
  for (int i = 0; i < steps; ++i) {
    const double t = static_cast<double>(i) / (steps - 1);
    // the ends exactly as written; inner values on the line or on the geometric sequence
    double value = log ? from * std::pow(to / from, t) : from + (to - from) * t;
    if (i == 0) value = from;
    if (i == steps - 1) value = to;
    const std::string text = format_value(value, 10);
    axis.values.push_back(text);
    axis.labels.push_back(text);
  }
}

SweepAxis read_axis(const SweepReader& r, const YAML::Node& key, const YAML::Node& value) {
  SweepAxis axis;
  axis.path = r.text(key, "axes");
  axis.where = r.where(key);
  const std::string field = "axes." + shortened(axis.path);
  axis.steps = parse_key_path(axis.path, axis.where, field);
  if (value.IsMap()) {
    read_range(r, value, field, axis);
  } else if (value.IsSequence()) {
    if (value.size() == 0) r.fail(value, field, "an axis needs at least one value");
    for (std::size_t i = 0; i < value.size(); ++i) {
      const YAML::Node v = value[i];
      if (v.IsNull()) r.fail(v, field + "[" + std::to_string(i) + "]", "a value must not be empty (null)");
      axis.values.push_back(v.IsScalar() ? YAML::Dump(v) : flow_text(v));
      axis.labels.push_back(v.IsScalar() ? v.Scalar() : flow_text(v));
    }
  } else {
    r.fail(value, field, "expected a list of values or a range {from, to, steps, scale}");
  }
  return axis;
}

void add_metric_name(SweepSpec& spec, const std::string& name, const std::string& field, const SourceRef& where) {
  spec.named_metrics.push_back({name, field, where});
}

// A whole input file, bounded and regular (program_io.hpp read_input_file).
std::string read_file_text(const std::string& path, const std::string& what) { return read_input_file(path, what); }

// 64-bit FNV-1a: a stable content hash (the same on every machine and build), enough to tell
// 10^5 points apart (collision chance ~3e-10).
std::string content_hash(const std::vector<std::string>& parts) {
  std::uint64_t h = 14695981039346656037ULL;
  for (const std::string& part : parts) {
    for (const char c : part) {
      h ^= static_cast<unsigned char>(c);
      h *= 1099511628211ULL;
    }
    // a separator no text holds, so ("ab", "c") and ("a", "bc") differ
    h ^= 0xffU;
    h *= 1099511628211ULL;
  }
  char buffer[17];
  std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(h));
  return buffer;
}

// What a path step found where the sweep meant to go on, for errors.
std::string kind_name(const YAML::Node& node) {
  if (node.IsMap()) return "a mapping";
  if (node.IsSequence()) return "a list";
  if (node.IsScalar()) return "a value ('" + node.Scalar() + "')";
  return "empty";
}

// Sets one axis' value in a scenario tree; `targets` receives the concrete paths it set.
class PathSetter {
 public:
  PathSetter(const SweepAxis& axis, const YAML::Node& value, std::vector<std::string>& targets, std::string& problem)
      : axis_(axis), value_(value), targets_(targets), problem_(problem) {}

  // Returns false with `problem` set when the path cannot be set in this tree.
  bool set(YAML::Node node, std::size_t i, const std::string& walked) {
    const KeyStep& step = axis_.steps[i];
    const bool last = i + 1 == axis_.steps.size();
    if (step.kind == KeyStep::Kind::kKey) {
      const std::string here = walked.empty() ? step.key : walked + "." + step.key;
      if (!node.IsMap() && !node.IsNull()) {
        problem_ = "'" + walked + "' is " + kind_name(node) + ", not a mapping, so it has no key '" + step.key + "'";
        return false;
      }
      const YAML::Node& lookup = node;
      const bool exists = node.IsMap() && lookup[step.key].IsDefined();
      if (last) {
        node[step.key] = YAML::Clone(value_);
        targets_.push_back(here);
        return true;
      }
      if (!exists) {
        // a missing mapping key may be created (the loader then says whether it may be there);
        // a missing list cannot be indexed
        if (axis_.steps[i + 1].kind != KeyStep::Kind::kKey) {
          problem_ = "the scenario has no list '" + here + "' to take an element of";
          return false;
        }
        node[step.key] = YAML::Node(YAML::NodeType::Map);
      }
      return set(node[step.key], i + 1, here);
    }
    if (!node.IsSequence()) {
      problem_ = "'" + walked + "' is " + kind_name(node) + ", not a list";
      return false;
    }
    std::vector<std::size_t> elements;
    if (step.kind == KeyStep::Kind::kIndex) {
      if (step.index >= node.size()) {
        problem_ = "'" + walked + "' has " + std::to_string(node.size()) + " element" + (node.size() == 1 ? "" : "s") +
                   ", so there is no element [" + std::to_string(step.index) + "]";
        return false;
      }
      elements.push_back(step.index);
    } else {
      if (node.size() == 0) {
        problem_ = "'" + walked + "' is an empty list: [*] matches nothing";
        return false;
      }
      for (std::size_t k = 0; k < node.size(); ++k) elements.push_back(k);
    }
    for (const std::size_t k : elements) {
      const std::string here = walked + "[" + std::to_string(k) + "]";
      if (last) {
        node[k] = YAML::Clone(value_);
        targets_.push_back(here);
      } else if (!set(node[k], i + 1, here)) {
        return false;
      }
    }
    return true;
  }

 private:
  const SweepAxis& axis_;
  const YAML::Node& value_;
  std::vector<std::string>& targets_;
  std::string& problem_;
};

// Whether concrete path `a` is `b` or lies inside it (b is a prefix at a step boundary).
bool inside(const std::string& a, const std::string& b) {
  if (a.size() < b.size() || a.compare(0, b.size(), b) != 0) return false;
  return a.size() == b.size() || a[b.size()] == '.' || a[b.size()] == '[';
}

// The variant names a point runs: the selection, else every `name` of the expanded `variants`.
std::vector<std::string> point_variants(const SweepSpec& spec, const YAML::Node& doc) {
  if (!spec.variants.empty()) return spec.variants;
  std::vector<std::string> names;
  const YAML::Node& root = doc;
  const YAML::Node variants = root["variants"];
  // a key the base lacks is an undefined node, whose type yaml-cpp refuses to tell
  // ("invalid node; first invalid key"): the loader says what is missing
  if (!variants.IsDefined() || !variants.IsSequence()) return names;
  for (std::size_t i = 0; i < variants.size(); ++i) {
    const YAML::Node name = variants[i].IsMap() ? variants[i]["name"] : YAML::Node();
    names.push_back(name.IsScalar() ? name.Scalar() : std::string());
  }
  return names;
}

[[noreturn]] void bad_key_path(const std::string& path, const SourceRef& where, const std::string& field,
                               const std::string& why) {
  fail_at(where, field, "bad key path '" + shortened(path) + "': " + why + " (keys separated by '.', [N] or [*] after a key)");
}

[[noreturn]] void bad_constraint(const std::string& text, const SourceRef& where, const std::string& field,
                                 const std::string& why) {
  fail_at(where, field, "bad constraint '" + text + "': " + why + " (expected 'METRIC OP NUMBER' with OP <=, <, >= or >)");
}

}  // namespace

std::vector<KeyStep> parse_key_path(const std::string& path, const SourceRef& where, const std::string& field) {
  const auto bad = [&](const std::string& why) { bad_key_path(path, where, field, why); };
  if (path.empty()) bad("it is empty");
  std::vector<KeyStep> steps;
  std::size_t i = 0;
  while (i < path.size()) {
    // a scenario nests at most yaml_detail::kMaxDepth levels, so no longer path names a value
    // (a path of 2*10^4 steps overflowed the stack of the recursive setter)
    if (steps.size() >= kMaxKeyPathSteps) {
      bad("it has more than " + std::to_string(kMaxKeyPathSteps) + " steps; a scenario nests at most " +
          std::to_string(yaml_detail::kMaxDepth) + " levels");
    }
    // a key up to '.', '[' or the end
    std::size_t end = i;
    while (end < path.size() && path[end] != '.' && path[end] != '[' && path[end] != ']') ++end;
    if (end == i) bad(steps.empty() ? "it must start with a key" : "an empty key at character " + std::to_string(i + 1));
    if (end < path.size() && path[end] == ']') bad("a ']' without '[' at character " + std::to_string(end + 1));
    steps.push_back({KeyStep::Kind::kKey, path.substr(i, end - i), 0});
    i = end;
    // any number of [N] or [*]
    while (i < path.size() && path[i] == '[') {
      const std::size_t close = path.find(']', i);
      if (close == std::string::npos) bad("an unclosed '[' at character " + std::to_string(i + 1));
      const std::string inner = path.substr(i + 1, close - i - 1);
      if (inner == "*") {
        steps.push_back({KeyStep::Kind::kEach, "", 0});
      } else if (!inner.empty() && inner.size() <= 9 && inner.find_first_not_of("0123456789") == std::string::npos) {
        steps.push_back({KeyStep::Kind::kIndex, "", static_cast<std::size_t>(std::stoul(inner))});
      } else {
        bad("'[" + inner + "]' is neither an index nor [*]");
      }
      i = close + 1;
    }
    if (steps.size() > kMaxKeyPathSteps) {
      bad("it has more than " + std::to_string(kMaxKeyPathSteps) + " steps; a scenario nests at most " +
          std::to_string(yaml_detail::kMaxDepth) + " levels");
    }
    if (i < path.size()) {
      if (path[i] != '.') bad("expected '.' or '[' at character " + std::to_string(i + 1));
      ++i;
      if (i == path.size()) bad("it ends with '.'");
    }
  }
  return steps;
}

Constraint parse_constraint(const std::string& text, const SourceRef& where, const std::string& field) {
  const auto bad = [&](const std::string& why) { bad_constraint(text, where, field, why); };
  const std::size_t op_at = text.find_first_of("<>=!");
  if (op_at == std::string::npos) bad("no comparison");
  Constraint c;
  c.text = text;
  c.where = where;
  const std::string before = text.substr(0, op_at);
  const std::size_t first = before.find_first_not_of(" \t");
  const std::size_t last = before.find_last_not_of(" \t");
  if (first == std::string::npos) bad("no metric before the comparison");
  c.metric = before.substr(first, last - first + 1);
  if (c.metric.find_first_of(" \t") != std::string::npos) bad("a metric name has no spaces");
  std::size_t rest = op_at;
  const std::string two = text.substr(op_at, 2);
  if (two == "<=") {
    c.op = Comparison::kLessEqual;
    rest += 2;
  } else if (two == ">=") {
    c.op = Comparison::kGreaterEqual;
    rest += 2;
  } else if (text[op_at] == '<' && two != "<<" && two != "<>") {
    c.op = Comparison::kLess;
    rest += 1;
  } else if (text[op_at] == '>' && two != ">>") {
    c.op = Comparison::kGreater;
    rest += 1;
  } else {
    bad("unknown comparison '" + two + "'");
  }
  const std::string number = text.substr(rest);
  std::size_t used = 0;
  try {
    c.bound = std::stod(number, &used);
  } catch (const std::exception&) {
    bad("no number after the comparison");
  }
  if (number.find_first_not_of(" \t", used) != std::string::npos) bad("text after the number");
  if (!std::isfinite(c.bound)) bad("the bound must be finite");
  return c;
}

bool meets(const Constraint& c, double value) {
  if (std::isnan(value)) return false;
  switch (c.op) {
    case Comparison::kLess: return value < c.bound;
    case Comparison::kLessEqual: return value <= c.bound;
    case Comparison::kGreater: return value > c.bound;
    case Comparison::kGreaterEqual: return value >= c.bound;
  }
  return false;
}

namespace {

SweepSpec parse_sweep_text(const std::string& text, const std::string& file, const std::string& base_dir) {
  // the YAML rules of a scenario file first (yaml_document.hpp): one document, no key twice in a
  // map, no control character (a NUL), UTF-8, bounded size and depth; yaml-cpp, which reads the
  // sweep, keeps the last of two keys and the first document silently
  (void)yaml_detail::Document(text, file);
  const SweepReader r(file);
  YAML::Node doc;
  try {
    doc = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw InputError(file, e.mark.line + 1, e.mark.column + 1, "", "invalid YAML: " + e.msg);
  }
  if (!doc.IsMap()) r.fail(doc, "", "a sweep file must be a mapping with 'scenario' and 'axes'");
  r.check_keys(doc, "", {"scenario", "description", "variants", "axes", "metrics", "constraints", "pareto"});
  SweepSpec spec;
  spec.file = file;
  spec.where = {file, 1, 1};

  // the base scenario, as the loader resolves a file name: the sweep file's folder, then the
  // data root (data_root.hpp)
  const YAML::Node scenario = doc["scenario"];
  if (!scenario.IsDefined() || scenario.IsNull()) r.fail(doc, "scenario", "missing required field");
  const std::string name = r.text(scenario, "scenario");
  std::vector<fs::path> candidates = {fs::path(name).is_absolute() ? fs::path(name) : fs::path(base_dir) / name};
  if (!fs::path(name).is_absolute()) {
    try {
      candidates.push_back(data_root() / name);
    } catch (const DataRootError&) {
      // no data root: only the sweep file's folder
    }
  }
  for (const fs::path& candidate : candidates) {
    // a name the file system refuses (too long, ...) is a file that is not found, not an exception
    std::error_code ec;
    if (fs::is_regular_file(candidate, ec)) {
      spec.scenario = fs::absolute(candidate).lexically_normal().string();
      break;
    }
  }
  if (spec.scenario.empty()) r.fail(scenario, "scenario", "file not found: " + name);
  // the scenario's folder is recorded in the plan and each point's JSON, which hold only UTF-8
  // (a folder above named "d\xff" failed every point with nlohmann's type_error 316, exit 1)
  if (!is_utf8(spec.scenario)) {
    r.fail(scenario, "scenario",
           "the path '" + printable(spec.scenario) +
               "' is not UTF-8 text: the sweep records it in its JSON files, which hold only UTF-8; rename the folder");
  }
  if (const YAML::Node d = doc["description"]; d.IsDefined()) spec.description = r.text(d, "description");

  if (const YAML::Node v = doc["variants"]; v.IsDefined()) {
    spec.variants = r.strings(v, "variants", &spec.variants_where);
    if (spec.variants.empty()) r.fail(v, "variants", "an empty selection runs nothing (leave 'variants' out to run all)");
    std::set<std::string> seen;
    for (std::size_t i = 0; i < spec.variants.size(); ++i) {
      if (!seen.insert(spec.variants[i]).second) {
        fail_at(spec.variants_where[i], "variants[" + std::to_string(i) + "]", "variant '" + spec.variants[i] + "' is selected twice");
      }
    }
  }

  const YAML::Node axes = doc["axes"];
  if (!axes.IsDefined() || axes.IsNull()) r.fail(doc, "axes", "missing required field");
  if (!axes.IsMap() || axes.size() == 0) r.fail(axes, "axes", "expected a mapping of key paths to values or ranges");
  spec.axes_where = r.where(axes);
  std::size_t product = 1;
  for (const auto& item : axes) {
    SweepAxis axis = read_axis(r, item.first, item.second);
    for (const SweepAxis& other : spec.axes) {
      if (other.path == axis.path) r.fail(item.first, "axes." + axis.path, "the axis is given twice");
    }
    product *= axis.values.size();
    if (product > kMaxSweepPoints) {
      r.fail(item.first, "axes." + axis.path,
             "the product of the axes exceeds " + std::to_string(kMaxSweepPoints) + " points: split the sweep");
    }
    spec.axes.push_back(std::move(axis));
  }

  if (const YAML::Node m = doc["metrics"]; m.IsDefined()) {
    std::vector<SourceRef> marks;
    spec.metrics = r.strings(m, "metrics", &marks);
    if (spec.metrics.empty()) r.fail(m, "metrics", "an empty list collects nothing (leave 'metrics' out for every metric)");
    for (std::size_t i = 0; i < spec.metrics.size(); ++i) {
      add_metric_name(spec, spec.metrics[i], "metrics[" + std::to_string(i) + "]", marks[i]);
    }
  }
  if (const YAML::Node c = doc["constraints"]; c.IsDefined()) {
    std::vector<SourceRef> marks;
    const std::vector<std::string> texts = r.strings(c, "constraints", &marks);
    for (std::size_t i = 0; i < texts.size(); ++i) {
      const std::string field = "constraints[" + std::to_string(i) + "]";
      spec.constraints.push_back(parse_constraint(texts[i], marks[i], field));
      add_metric_name(spec, spec.constraints.back().metric, field, marks[i]);
    }
  }
  SourceRef x_where = spec.where;
  SourceRef y_where = spec.where;
  if (const YAML::Node p = doc["pareto"]; p.IsDefined()) {
    r.check_keys(p, "pareto", {"x", "y"});
    if (const YAML::Node x = p["x"]; x.IsDefined()) {
      spec.pareto_x = r.text(x, "pareto.x");
      x_where = r.where(x);
    }
    if (const YAML::Node y = p["y"]; y.IsDefined()) {
      spec.pareto_y = r.text(y, "pareto.y");
      y_where = r.where(y);
    }
    if (spec.pareto_x == spec.pareto_y) r.fail(p, "pareto", "x and y must be different metrics");
  }
  add_metric_name(spec, spec.pareto_x, "pareto.x", x_where);
  add_metric_name(spec, spec.pareto_y, "pareto.y", y_where);
  return spec;
}

}  // namespace

SweepSpec parse_sweep(const std::string& text, const std::string& file, const std::string& base_dir) {
  try {
    return parse_sweep_text(text, file, base_dir);
  } catch (...) {
    rethrow_as_input_error({file, 0, 0}, "", "cannot read the sweep file: ");
  }
}

SweepSpec load_sweep(const std::string& path) {
  const std::string dir = fs::path(path).parent_path().string();
  return parse_sweep(read_file_text(path, "sweep file"), path, dir.empty() ? "." : dir);
}

std::size_t sweep_point_count(const SweepSpec& spec) {
  std::size_t count = 1;
  for (const SweepAxis& axis : spec.axes) count *= axis.values.size();
  return count;
}

namespace {

SweepPlan expand(const SweepSpec& spec, const SweepPointCheck& check_first) {
  SweepPlan plan;
  plan.spec = spec;
  plan.base_dir = fs::path(spec.scenario).parent_path().string();
  YAML::Node base;
  const std::string base_text = read_file_text(spec.scenario, "scenario file");
  // the scenario loader's YAML rules, as for the sweep file
  (void)yaml_detail::Document(base_text, spec.scenario);
  try {
    base = YAML::Load(base_text);
  } catch (const YAML::ParserException& e) {
    throw InputError(spec.scenario, e.mark.line + 1, e.mark.column + 1, "", "invalid YAML: " + e.msg);
  }
  if (!base.IsMap()) throw InputError(spec.scenario, 1, 1, "", "a scenario must be a mapping");

  // the selection must name variants of the base scenario
  if (!spec.variants.empty()) {
    SweepSpec all = spec;
    all.variants.clear();
    const std::vector<std::string> names = point_variants(all, base);
    std::string list;
    for (const std::string& n : names) list += (list.empty() ? "" : ", ") + n;
    for (std::size_t i = 0; i < spec.variants.size(); ++i) {
      if (std::find(names.begin(), names.end(), spec.variants[i]) == names.end()) {
        fail_at(spec.variants_where[i], "variants[" + std::to_string(i) + "]",
                "no variant '" + spec.variants[i] + "' in " + spec.scenario + " (variants: " + list + ")");
      }
    }
  }

  const std::size_t count = sweep_point_count(spec);
  std::vector<YAML::Node> values;  // every axis value parsed once, axis by axis
  std::vector<std::size_t> offset;
  for (const SweepAxis& axis : spec.axes) {
    offset.push_back(values.size());
    for (const std::string& v : axis.values) values.push_back(YAML::Load(v));
  }

  plan.points.reserve(count);
  for (std::size_t index = 0; index < count; ++index) {
    SweepPoint point;
    point.index = index;
    // mixed radix, the last axis fastest
    point.choice.assign(spec.axes.size(), 0);
    std::size_t rest = index;
    for (std::size_t a = spec.axes.size(); a-- > 0;) {
      point.choice[a] = rest % spec.axes[a].values.size();
      rest /= spec.axes[a].values.size();
    }
    YAML::Node doc = YAML::Clone(base);
    point.targets.resize(spec.axes.size());
    for (std::size_t a = 0; a < spec.axes.size(); ++a) {
      const SweepAxis& axis = spec.axes[a];
      std::string problem;
      PathSetter setter(axis, values[offset[a] + point.choice[a]], point.targets[a], problem);
      if (!setter.set(doc, 0, "")) {
        fail_at(axis.where, "axes." + axis.path,
                "point " + std::to_string(index) + " of " + std::to_string(count) + " (" + point_values_text(spec, point) +
                    "): cannot set '" + axis.path + "' in " + spec.scenario + ": " + problem);
      }
      // two axes must not set the same value (or one a value inside the other's)
      for (std::size_t b = 0; b < a; ++b) {
        for (const std::string& t : point.targets[a]) {
          for (const std::string& u : point.targets[b]) {
            if (inside(t, u) || inside(u, t)) {
              fail_at(axis.where, "axes." + axis.path,
                      "sets '" + t + "', which axis '" + spec.axes[b].path + "' sets too ('" + u + "')");
            }
          }
        }
      }
    }
    if (!spec.timing.empty()) doc["timing"] = spec.timing;
    YAML::Emitter out;
    out << doc;
    point.scenario_text = std::string(out.c_str()) + "\n";
    point.variants = point_variants(spec, doc);
    std::vector<std::string> parts = {"blendbench sweep point 1", plan.base_dir};
    parts.insert(parts.end(), point.variants.begin(), point.variants.end());
    parts.push_back(point.scenario_text);
    point.hash = content_hash(parts);
    plan.points.push_back(std::move(point));
    if (index == 0 && check_first) check_first(plan, plan.points.front());
  }
  return plan;
}

}  // namespace

SweepPlan expand_sweep(const SweepSpec& spec, const SweepPointCheck& check_first) {
  try {
    return expand(spec, check_first);
  } catch (...) {
    rethrow_as_input_error(spec.axes_where, "axes", "cannot expand the sweep over " + spec.scenario + ": ");
  }
}

std::string point_values_text(const SweepSpec& spec, const SweepPoint& point) {
  std::string out;
  for (std::size_t a = 0; a < spec.axes.size() && a < point.choice.size(); ++a) {
    out += (a == 0 ? "" : ", ") + spec.axes[a].path + "=" + spec.axes[a].labels[point.choice[a]];
  }
  return out;
}

void validate_point(const SweepPlan& plan, const SweepPoint& point, const std::string& file_name) {
  const SweepSpec& spec = plan.spec;
  const std::string which = "point " + std::to_string(point.index) + " of " + std::to_string(sweep_point_count(spec)) + " (" +
                            point_values_text(spec, point) + ")";
  try {
    const Scenario scenario = parse_scenario(point.scenario_text, file_name, plan.base_dir);
    for (std::size_t i = 0; i < spec.variants.size(); ++i) {
      const bool found = std::any_of(scenario.variants.begin(), scenario.variants.end(),
                                     [&](const Variant& v) { return v.name == spec.variants[i]; });
      if (!found) {
        fail_at(spec.variants_where[i], "variants[" + std::to_string(i) + "]",
                which + " has no variant '" + spec.variants[i] + "' (an axis renamed or removed it)");
      }
    }
  } catch (const InputError& e) {
    if (e.file() == spec.file) throw;
    // the axis whose value the loader refused: its concrete path is, holds or lies in the field
    for (std::size_t a = 0; a < spec.axes.size(); ++a) {
      for (const std::string& target : point.targets[a]) {
        if (!e.field().empty() && (inside(e.field(), target) || inside(target, e.field()))) {
          fail_at(spec.axes[a].where, "axes." + spec.axes[a].path, which + " is not a valid scenario: " + e.what());
        }
      }
    }
    fail_at(spec.axes_where, "axes", which + " is not a valid scenario: " + e.what());
  }
}

}  // namespace blendbench
