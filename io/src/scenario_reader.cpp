// The scenario loader's reader (scenario_reader.hpp).

#include "scenario_reader.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>

#include "blendbench/core/format.hpp"
#include "blendbench/io/data_root.hpp"

namespace blendbench::scenario_detail {
namespace {

// "nan", ".inf", "-Infinity", ...: the spellings of values that are not finite numbers.
bool names_non_finite(std::string_view s) {
  if (!s.empty() && (s.front() == '+' || s.front() == '-')) s.remove_prefix(1);
  if (!s.empty() && s.front() == '.') s.remove_prefix(1);
  std::string lower(s);
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lower == "inf" || lower == "infinity" || lower == "nan";
}

// A YAML 1.2 core-schema float or integer: [-+]? (digits [. digits?] | . digits) ([eE] [-+]? digits)?
bool is_decimal(std::string_view s) {
  std::size_t i = 0;
  const auto digits = [&] {
    const std::size_t from = i;
    while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) ++i;
    return i > from;
  };
  if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
  const bool whole = digits();
  bool fraction = false;
  if (i < s.size() && s[i] == '.') {
    ++i;
    fraction = digits();
  }
  if (!whole && !fraction) return false;
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
    if (!digits()) return false;
  }
  return i == s.size();
}

}  // namespace

// A word for what a node is, for "expected a number, got a list".
std::string what_is(const Ref& node) {
  if (!node.defined() || node.is_null()) return "nothing (an empty value)";
  if (node.is_sequence()) return "a list";
  if (node.is_map()) return "a map";
  return "'" + node.scalar() + "'";
}

void Reader::fail(const Field& f, const std::string& message) const {
  const Ref& at = f.node.defined() && !f.fallback ? f.node : f.at;
  throw InputError(file_, at.line(), at.column(), f.path(), message);
}

SourceRef Reader::where(const Field& f) const {
  const Ref& at = f.node.defined() && !f.fallback ? f.node : f.at;
  return {file_, at.line(), at.column()};
}

void Reader::check_keys(const Field& f) const {
  if (!f.node.is_map()) fail(f, "expected a map (key: value pairs), got " + what_is(f.node));
  for (std::size_t i = 0; i < f.node.size(); ++i) {
    const Ref key = f.node.key(i);
    const ScenarioKey* spec = find_scenario_key(f.map, key.scalar());
    if (spec == nullptr) fail({key, &f, key.scalar(), 0, f.map, nullptr, key, false}, unknown_key(f.map, key.scalar()));
    check_value({f.node.value(i), &f, spec->name, 0, spec->opens, spec, key, false});
  }
}

void Reader::check_value(const Field& f) const {
  switch (f.key->type) {
    case KeyType::kMap:
      if (!f.node.is_map()) fail(f, "expected a map (key: value pairs), got " + what_is(f.node));
      return;
    case KeyType::kList:
      if (!f.node.is_sequence()) fail(f, "expected a list, got " + what_is(f.node));
      return;
    case KeyType::kText:
    case KeyType::kFile: (void)text(f); return;
    case KeyType::kChoice: (void)choice(f); return;
    case KeyType::kBool: (void)flag(f); return;
    case KeyType::kInteger: (void)integer(f); return;
    case KeyType::kNumber: (void)number(f); return;
    case KeyType::kNumbers: (void)numbers(f); return;
  }
}

Field Reader::child(const Field& f, std::string_view key) const {
  const ScenarioKey* spec = find_scenario_key(f.map, key);
  if (spec == nullptr) throw std::logic_error("scenario loader: key '" + std::string(key) + "' of '" + std::string(f.map) + "' is not in the table");
  Ref node = f.node.is_map() ? f.node.get(key) : Ref();
  return {node, &f, spec->name, 0, spec->opens, spec, f.node.defined() ? f.node : f.at, false};
}

Field Reader::value(const Field& f, std::string_view key) const {
  Field c = child(f, key);
  if (c.node.defined() || c.key->fallback.empty()) return c;
  c.node = fallback_of(*c.key);
  c.fallback = true;
  return c;
}

Field Reader::require(const Field& f, std::string_view key) const {
  Field c = child(f, key);
  if (!c.node.defined() || c.node.is_null()) fail(c, missing());
  return c;
}

Field Reader::item(const Field& f, std::size_t i) const {
  return {f.node[i], &f, "", i, f.map, nullptr, f.node[i], false};
}

std::string Reader::missing() const {
  const auto& q = doc_.long_quote();
  if (q.line == 0) return "missing required field";
  return "missing required field; the quoted string at line " + std::to_string(q.line) + ", column " +
         std::to_string(q.column) + " spans " + std::to_string(q.lines) + " lines: is its closing quote missing?";
}

double Reader::number(const Field& f) const {
  const double value = raw_number(f);
  check_range(f, value);
  return value * unit_factor(f);
}

int Reader::integer(const Field& f) const {
  if (!f.node.is_scalar()) fail(f, "expected an integer, got " + what_is(f.node));
  const std::string& s = f.node.scalar();
  std::string_view digits = s;
  if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
  long long value = 0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (ec == std::errc::result_out_of_range) fail(f, "expected an integer " + range_of(f) + ", got " + s);
  if (ec != std::errc() || end != digits.data() + digits.size() || digits.empty()) {
    fail(f, "expected an integer (digits only), got '" + s + "'");
  }
  check_range(f, static_cast<double>(value));
  if (value < std::numeric_limits<int>::min() || value > std::numeric_limits<int>::max()) {
    fail(f, "expected an integer " + range_of(f) + ", got " + s);
  }
  return static_cast<int>(value);
}

bool Reader::flag(const Field& f) const {
  const std::string& s = f.node.scalar();
  if (f.node.is_scalar()) {
    if (s == "true" || s == "True" || s == "TRUE") return true;
    if (s == "false" || s == "False" || s == "FALSE") return false;
  }
  fail(f, "expected true or false, got " + what_is(f.node));
}

const std::string& Reader::text(const Field& f) const {
  if (!f.node.is_scalar()) fail(f, "expected a string, got " + what_is(f.node));
  return f.node.scalar();
}

std::string Reader::choice(const Field& f) const {
  const std::string& given = text(f);
  const auto same = [&](std::string_view option) {
    return option.size() == given.size() &&
           std::equal(option.begin(), option.end(), given.begin(), [](char a, char b) {
             return std::tolower(static_cast<unsigned char>(a)) == std::tolower(static_cast<unsigned char>(b));
           });
  };
  std::vector<std::string> options;
  std::string_view rest = f.key->choices;
  while (true) {
    const std::size_t bar = rest.find('|');
    const std::string_view option = rest.substr(0, bar);
    if (same(option)) return std::string(option);
    options.emplace_back(option);
    if (bar == std::string_view::npos) break;
    rest.remove_prefix(bar + 1);
  }
  std::string list;
  for (const std::string& o : options) list += (list.empty() ? "" : ", ") + o;
  fail(f, "unknown value '" + given + "' " + suggestion(given, options, "one of: " + list));
}

std::vector<double> Reader::numbers(const Field& f) const {
  // count 0: a list of any length
  const bool any_length = f.key->count == 0;
  const std::size_t n = any_length && f.node.is_sequence() ? f.node.size() : static_cast<std::size_t>(f.key->count);
  if (!f.node.is_sequence() || f.node.size() != n) {
    fail(f, "expected a list of " + (any_length ? std::string() : std::to_string(n) + " ") + "numbers, got " +
                (f.node.is_sequence() ? "a list of " + std::to_string(f.node.size()) : what_is(f.node)));
  }
  if (n > kMaxListNumbers) {
    fail(f, "expected at most " + std::to_string(kMaxListNumbers) + " numbers, got a list of " + std::to_string(n));
  }
  std::vector<double> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    Field element = f;
    element.node = f.node[i];
    element.parent = &f;
    element.name = "";
    element.index = i;
    out[i] = number(element);
  }
  return out;
}

Vec3 Reader::vec3(const Field& f) const {
  const std::vector<double> v = numbers(f);
  return {v[0], v[1], v[2]};
}

std::string Reader::existing_file(const Field& f) const {
  const std::string name = text(f);
  namespace fs = std::filesystem;
  const auto found = [](const fs::path& candidate) {
    std::error_code ec;
    return fs::is_regular_file(candidate, ec);
  };
  const auto result = [](const fs::path& candidate) { return fs::absolute(candidate).lexically_normal().string(); };
  if (f.fallback) return data_file(name);
  if (fs::path(name).is_absolute()) {
    if (found(name)) return result(name);
    fail(f, "file not found: " + name);
  }
  if (found(fs::path(base_dir_) / name)) return result(fs::path(base_dir_) / name);
  fs::path data;
  try {
    data = data_root();
  } catch (const DataRootError& e) {
    fail(f, "file not found: " + name + " (not beside the scenario, and " + e.what() + ")");
  }
  if (found(data / name)) return result(data / name);
  fail(f, "file not found: " + name);
}

std::vector<std::string> Reader::existing_folders(const Field& f) const {
  namespace fs = std::filesystem;
  const std::string list = text(f);
  std::vector<std::string> out;
  std::size_t begin = 0;
  while (begin <= list.size()) {
    const std::size_t end = std::min(list.find(':', begin), list.size());
    const std::string name = list.substr(begin, end - begin);
    begin = end + 1;
    if (name.empty()) fail(f, "an empty folder name in '" + list + "' (folders are separated by ':')");
    const fs::path folder = fs::path(name).is_absolute() ? fs::path(name) : fs::path(base_dir_) / name;
    std::error_code ec;
    if (!fs::is_directory(folder, ec)) fail(f, "folder not found: " + name);
    out.push_back(fs::absolute(folder).lexically_normal().string());
  }
  return out;
}

double Reader::raw_number(const Field& f) const {
  if (!f.node.is_scalar()) fail(f, "expected a number, got " + what_is(f.node));
  const std::string& s = f.node.scalar();
  if (!is_decimal(s)) {
    if (names_non_finite(s)) fail(f, "expected a finite number, got '" + s + "'");
    fail(f, "expected a number, got '" + s + "'");
  }
  std::string_view digits = s;
  if (digits.front() == '+') digits.remove_prefix(1);
  double value = 0;
  const auto [end, ec] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (ec == std::errc::result_out_of_range) {
    // beyond the range of a double, or below its smallest value (then it is zero, or nearly)
    value = std::strtod(s.c_str(), nullptr);
    if (!std::isfinite(value)) fail(f, "expected a finite number, got " + s + " (beyond the range of a double)");
  } else if (ec != std::errc() || end != digits.data() + digits.size()) {
    fail(f, "expected a number, got '" + s + "'");
  }
  return value;
}

std::string Reader::range_of(const Field& f) const {
  const std::string r = range_text(f.key->range);
  std::string unit(f.key->unit.text);
  // the file's own length unit in place of "units"
  if (const std::size_t at = unit.find("units"); at != std::string::npos) {
    unit.replace(at, 5, f.fallback || scale_ != 1.0 ? "mm" : "m");
  }
  return (r.front() == '[' || r.front() == '(' ? "in " : "") + r + (unit.empty() ? "" : " " + unit);
}

void Reader::check_range(const Field& f, double value) const {
  const KeyRange& r = f.key->range;
  const bool low = r.lo_open ? value > r.lo : value >= r.lo;
  const bool high = r.hi_open ? value < r.hi : value <= r.hi;
  if (!(low && high)) fail(f, "must be " + range_of(f) + ", got " + f.node.scalar());
}

double Reader::unit_factor(const Field& f) const {
  const double scale = f.fallback ? 1e-3 : scale_;
  switch (f.key->unit.length_power) {
    case 0: return 1.0;
    case 1: return scale;
    case -1: return 1.0 / scale;
    default: return std::pow(scale, f.key->unit.length_power);
  }
}

Ref Reader::fallback_of(const ScenarioKey& key) const {
  auto& doc = fallbacks_[&key];
  if (!doc) doc = std::make_unique<Document>(key.fallback, "<default of " + std::string(key.name) + ">");
  return doc->root();
}

std::string Reader::suggestion(const std::string& word, const std::vector<std::string>& options, const std::string& otherwise) {
  const std::vector<std::string> close = closest_names(word, options);
  if (close.empty()) return "(" + otherwise + ")";
  std::string out = "(did you mean ";
  for (std::size_t i = 0; i < close.size(); ++i) {
    out += (i == 0 ? "" : i + 1 == close.size() ? " or " : ", ") + ("'" + close[i] + "'");
  }
  return out + "?)";
}

std::string Reader::unknown_key(std::string_view map, const std::string& key) {
  std::vector<std::string> keys;
  std::vector<std::string> elsewhere;
  for (const ScenarioKey& k : scenario_keys()) {
    if (k.map == map) keys.emplace_back(k.name);
    if (k.map != map && k.name == key) {
      for (const std::string& p : scenario_map_path_list(k.map)) elsewhere.push_back(p.empty() ? "the top level" : p);
    }
  }
  std::string list;
  for (const std::string& k : keys) list += (list.empty() ? "" : ", ") + k;
  if (closest_names(key, keys).empty() && !elsewhere.empty()) {
    std::string places;
    for (const std::string& p : elsewhere) places += (places.empty() ? "" : " or ") + p;
    return "unknown key '" + key + "' here; it belongs in " + places + " (allowed here: " + list + ")";
  }
  return "unknown key '" + key + "' " + suggestion(key, keys, "allowed: " + list);
}

}  // namespace blendbench::scenario_detail
