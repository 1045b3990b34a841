// The YAML scenario loader (scenario.hpp): the file read into a tree with positions
// (yaml_document.hpp), then walked map by map against the format's table (scenario_keys.hpp),
// which says which keys a map holds, their types, units, ranges and defaults.

#include "blendbench/io/scenario.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <numbers>
#include <set>
#include <unordered_map>

#include "blendbench/core/format.hpp"
#include "blendbench/geometry/arc_construction.hpp"
#include "blendbench/io/data_root.hpp"
#include "blendbench/io/program_io.hpp"
#include "blendbench/io/scenario_keys.hpp"
#include "yaml_document.hpp"

namespace blendbench {
namespace {

using yaml_detail::Document;
using yaml_detail::Ref;

constexpr double kDeg = std::numbers::pi / 180.0;

// A value of the file with its key path, so every error can name file, line, column and key.
// The path is kept as a link to the parent and built only for a message (a path string per
// lookup was a tenth of the loading time): a Field lives no longer than its parent.
struct Field {
  Ref node;                            // no node: the key is absent
  const Field* parent = nullptr;       // the map or list it is in; nullptr for the top level
  std::string_view name;               // its key in the parent map ("" for a list item)
  std::size_t index = 0;               // its index in the parent list
  std::string_view map;                // a map's table map (the keys it may hold)
  const ScenarioKey* key = nullptr;    // the table entry of this value; nullptr for a list item
  Ref at;                              // where an absent key is reported: its map
  bool fallback = false;               // the table's default, not the file's (lengths in mm)

  // e.g. "program.moves[3].arc.center"
  [[nodiscard]] std::string path() const {
    if (parent == nullptr) return std::string(name);
    std::string out = parent->path();
    if (name.empty()) return out.append("[").append(std::to_string(index)).append("]");
    if (!out.empty()) out += '.';
    return out.append(name);
  }
};

// A word for what a node is, for "expected a number, got a list".
std::string what_is(const Ref& node) {
  if (!node.defined() || node.is_null()) return "nothing (an empty value)";
  if (node.is_sequence()) return "a list";
  if (node.is_map()) return "a map";
  return "'" + node.scalar() + "'";
}

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

class Reader {
 public:
  Reader(const Document& doc, std::string file, std::string base_dir)
      : doc_(doc), file_(std::move(file)), base_dir_(std::move(base_dir)) {}

  [[nodiscard]] Field root() const { return {doc_.root(), nullptr, "", 0, "", nullptr, doc_.root(), false}; }

  // The file's length unit in metres (1e-3 for mm), once `units` is read.
  void set_scale(double scale) { scale_ = scale; }

  [[noreturn]] void fail(const Field& f, const std::string& message) const {
    const Ref& at = f.node.defined() ? f.node : f.at;
    throw InputError(file_, at.line(), at.column(), f.path(), message);
  }

  [[nodiscard]] SourceRef where(const Field& f) const {
    const Ref& at = f.node.defined() ? f.node : f.at;
    return {file_, at.line(), at.column()};
  }

  // Fails unless `f` is a map whose every key belongs to its table map and every value has the
  // type and range its table entry gives (in the order written). An unknown key names the
  // closest valid ones (a typo) or the map it belongs in.
  void check_keys(const Field& f) const {
    if (!f.node.is_map()) fail(f, "expected a map (key: value pairs), got " + what_is(f.node));
    for (std::size_t i = 0; i < f.node.size(); ++i) {
      const Ref key = f.node.key(i);
      const ScenarioKey* spec = find_scenario_key(f.map, key.scalar());
      if (spec == nullptr) fail({key, &f, key.scalar(), 0, f.map, nullptr, key, false}, unknown_key(f.map, key.scalar()));
      check_value({f.node.value(i), &f, spec->name, 0, spec->opens, spec, key, false});
    }
  }

  // Fails unless the value `f` has the type and range of its table entry (a map's or a list's
  // own keys are checked when it is read).
  void check_value(const Field& f) const {
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

  // The value of `key` in map `f`; no node when absent. `key` must be in the table.
  [[nodiscard]] Field child(const Field& f, std::string_view key) const {
    const ScenarioKey* spec = find_scenario_key(f.map, key);
    if (spec == nullptr) throw std::logic_error("scenario loader: key '" + std::string(key) + "' of '" + std::string(f.map) + "' is not in the table");
    Ref node = f.node.is_map() ? f.node.get(key) : Ref();
    return {node, &f, spec->name, 0, spec->opens, spec, f.node.defined() ? f.node : f.at, false};
  }

  // The value of `key`, or the table's default when absent (no node when it has none).
  [[nodiscard]] Field value(const Field& f, std::string_view key) const {
    Field c = child(f, key);
    if (c.node.defined() || c.key->fallback.empty()) return c;
    c.node = fallback_of(*c.key);
    c.fallback = true;
    return c;
  }

  // The value of a key that must be given (and not empty).
  [[nodiscard]] Field require(const Field& f, std::string_view key) const {
    Field c = child(f, key);
    if (!c.node.defined() || c.node.is_null()) fail(c, missing());
    return c;
  }

  // Item `i` of list `f`, a map of the table map `f` opens.
  [[nodiscard]] Field item(const Field& f, std::size_t i) const {
    return {f.node[i], &f, "", i, f.map, nullptr, f.node[i], false};
  }

  [[nodiscard]] std::string missing() const {
    const auto& q = doc_.long_quote();
    if (q.line == 0) return "missing required field";
    return "missing required field; the quoted string at line " + std::to_string(q.line) + ", column " +
           std::to_string(q.column) + " spans " + std::to_string(q.lines) + " lines: is its closing quote missing?";
  }

  // A number of the field's table entry: finite, in its range, converted to SI.
  [[nodiscard]] double number(const Field& f) const {
    const double value = raw_number(f);
    check_range(f, value);
    return value * unit_factor(f);
  }

  // An integer of the field's table entry, in its range.
  [[nodiscard]] int integer(const Field& f) const {
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

  [[nodiscard]] bool flag(const Field& f) const {
    const std::string& s = f.node.scalar();
    if (f.node.is_scalar()) {
      if (s == "true" || s == "True" || s == "TRUE") return true;
      if (s == "false" || s == "False" || s == "FALSE") return false;
    }
    fail(f, "expected true or false, got " + what_is(f.node));
  }

  [[nodiscard]] const std::string& text(const Field& f) const {
    if (!f.node.is_scalar()) fail(f, "expected a string, got " + what_is(f.node));
    return f.node.scalar();
  }

  // One of the entry's choices, as the table spells it (the file's may differ in case).
  [[nodiscard]] std::string choice(const Field& f) const {
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

  // A list of the entry's count of numbers, each finite, in range and converted to SI.
  [[nodiscard]] std::vector<double> numbers(const Field& f) const {
    const auto n = static_cast<std::size_t>(f.key->count);
    if (!f.node.is_sequence() || f.node.size() != n) {
      fail(f, "expected a list of " + std::to_string(n) + " numbers, got " +
                  (f.node.is_sequence() ? "a list of " + std::to_string(f.node.size()) : what_is(f.node)));
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

  [[nodiscard]] Vec3 vec3(const Field& f) const {
    const std::vector<double> v = numbers(f);
    return {v[0], v[1], v[2]};
  }

  // An existing file named relative to the scenario's directory, then to the data root
  // (data_root.hpp: models/ and scenarios/ in the source tree or the install prefix); a default
  // names a file of the data root.
  [[nodiscard]] std::string existing_file(const Field& f) const {
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

  [[nodiscard]] const std::string& file() const { return file_; }

 private:
  [[nodiscard]] double raw_number(const Field& f) const {
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

  [[nodiscard]] std::string range_of(const Field& f) const {
    const std::string r = range_text(f.key->range);
    std::string unit(f.key->unit.text);
    // the file's own length unit in place of "units"
    if (const std::size_t at = unit.find("units"); at != std::string::npos) {
      unit.replace(at, 5, f.fallback || scale_ != 1.0 ? "mm" : "m");
    }
    return (r.front() == '[' || r.front() == '(' ? "in " : "") + r + (unit.empty() ? "" : " " + unit);
  }

  void check_range(const Field& f, double value) const {
    const KeyRange& r = f.key->range;
    const bool low = r.lo_open ? value > r.lo : value >= r.lo;
    const bool high = r.hi_open ? value < r.hi : value <= r.hi;
    if (!(low && high)) fail(f, "must be " + range_of(f) + ", got " + f.node.scalar());
  }

  // SI per unit of the file: the length unit to the entry's power (a default's lengths are mm).
  [[nodiscard]] double unit_factor(const Field& f) const {
    const double scale = f.fallback ? 1e-3 : scale_;
    switch (f.key->unit.length_power) {
      case 0: return 1.0;
      case 1: return scale;
      case -1: return 1.0 / scale;
      default: return std::pow(scale, f.key->unit.length_power);
    }
  }

  // The table's default of an entry, parsed once.
  [[nodiscard]] Ref fallback_of(const ScenarioKey& key) const {
    auto& doc = fallbacks_[&key];
    if (!doc) doc = std::make_unique<Document>(key.fallback, "<default of " + std::string(key.name) + ">");
    return doc->root();
  }

  static std::string suggestion(const std::string& word, const std::vector<std::string>& options, const std::string& otherwise) {
    const std::vector<std::string> close = closest_names(word, options);
    if (close.empty()) return "(" + otherwise + ")";
    std::string out = "(did you mean ";
    for (std::size_t i = 0; i < close.size(); ++i) {
      out += (i == 0 ? "" : i + 1 == close.size() ? " or " : ", ") + ("'" + close[i] + "'");
    }
    return out + "?)";
  }

  // "unknown key 'velocty' (did you mean 'velocity'?)", or the map it belongs in, or the list.
  static std::string unknown_key(std::string_view map, const std::string& key) {
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

  const Document& doc_;
  std::string file_;
  std::string base_dir_;
  double scale_ = 1e-3;
  mutable std::unordered_map<const ScenarioKey*, std::unique_ptr<Document>> fallbacks_;
};

Eigen::Matrix3d rpy_deg(const std::vector<double>& rpy) {
  // fixed-axis roll (x), pitch (y), yaw (z), as in URDF: R = Rz(yaw) Ry(pitch) Rx(roll); the
  // values are already radians (the unit deg converts like any other: by kDeg below)
  return (Eigen::AngleAxisd(rpy[2], Vec3::UnitZ()) * Eigen::AngleAxisd(rpy[1], Vec3::UnitY()) *
          Eigen::AngleAxisd(rpy[0], Vec3::UnitX()))
      .toRotationMatrix();
}

// Degrees read from the file, in radians.
std::vector<double> radians(std::vector<double> deg) {
  for (double& v : deg) v *= kDeg;
  return deg;
}

Transition read_transition(const Reader& r, const Field& f) {
  r.check_keys(f);
  Transition t;
  const Field method = r.require(f, "method");
  t.method = *method_from_string(r.choice(method));
  const Field parameter = r.child(f, "parameter");
  const Field start = r.child(f, "start_distance");
  if (start.node.defined()) {
    if (t.method != Method::kBiclothoid) {
      r.fail(start, "a start distance sizes only a biclothoid transition, not " + r.choice(method));
    }
    if (parameter.node.defined()) {
      r.fail(start, "give the biclothoid either a maximum deviation (parameter) or a start distance, not both");
    }
    t.start_distance = r.number(start);
  } else if (parameter.node.defined()) {
    t.parameter = r.number(parameter);
  } else if (t.method != Method::kNone) {
    (void)r.require(f, "parameter");
  }
  t.kappa_max = r.number(r.value(f, "kappa_max"));
  t.velocity = r.number(r.value(f, "velocity"));
  return t;
}

BufferMode read_buffer(const Reader& r, const Field& f) { return *buffer_mode_from_string(r.choice(f)); }

// Reads one arc specification; positions are in the program frame, in metres.
Arc read_arc(const Reader& r, const Field& f, const Vec3& start) {
  r.check_keys(f);
  const Vec3 end = r.vec3(r.require(f, "end"));
  const Field via = r.child(f, "via");
  const Field center = r.child(f, "center");
  const Field radius = r.child(f, "radius");
  const int given = static_cast<int>(via.node.defined()) + static_cast<int>(center.node.defined()) +
                    static_cast<int>(radius.node.defined());
  if (given != 1) r.fail(f, "an arc needs exactly one of 'center', 'radius' or 'via'");

  ArcBuild built;
  if (via.node.defined()) {
    for (const char* key : {"direction", "normal", "turns"}) {
      if (const Field k = r.child(f, key); k.node.defined()) r.fail(k, "not used with 'via' (the via point fixes the arc)");
    }
    built = arc_through(start, r.vec3(via), end);
    if (!built.outcome.ok()) r.fail(via, built.outcome.message);
    return built.arc;
  }
  const bool ccw = r.choice(r.require(f, "direction")) == "ccw";
  const Field n = r.value(f, "normal");
  const Vec3 normal = r.vec3(n);
  if (!(normal.norm() > 0)) r.fail(n, "the normal must not be zero");
  const Field turns_field = r.value(f, "turns");
  const int turns = r.integer(turns_field);
  if (center.node.defined()) {
    // a tolerance of a micrometre on the radii, like a CNC control's arc check
    built = arc_from_center(start, end, r.vec3(center), normal, ccw, turns, 1e-6);
    if (!built.outcome.ok()) r.fail(center, built.outcome.message);
  } else {
    if (turns != 0) r.fail(turns_field, "'turns' needs a 'center'");
    built = arc_from_radius(start, end, r.number(radius), normal, ccw, 1e-9);
    if (!built.outcome.ok()) r.fail(radius, built.outcome.message);
  }
  return built.arc;
}

// Transforms an arc by a rigid frame.
Arc transformed(const Arc& arc, const Eigen::Isometry3d& frame) {
  Arc out = arc;
  out.center = frame * arc.center;
  out.u = frame.linear() * arc.u;
  out.v = frame.linear() * arc.v;
  return out;
}

// Limits and buffer mode every move starts from.
struct MoveDefaults {
  Limits limits;
  BufferMode buffer = BufferMode::kBlendingLow;
};

MoveDefaults read_defaults(const Reader& r, const Field& root) {
  const Field defaults = r.require(root, "defaults");
  r.check_keys(defaults);
  MoveDefaults d;
  d.limits.velocity = r.number(r.require(defaults, "velocity"));
  d.limits.acceleration = r.number(r.require(defaults, "acceleration"));
  const Field dec = r.child(defaults, "deceleration");
  d.limits.deceleration = dec.node.defined() ? r.number(dec) : d.limits.acceleration;
  d.limits.jerk = r.number(r.require(defaults, "jerk"));
  d.buffer = read_buffer(r, r.value(defaults, "buffer"));
  return d;
}

// A program given as a G-code file: read in its own units (G20/G21), placed by the frame.
// Variants replace the transitions of all its moves (the file's G61/G64 apply when a variant
// sets no transition).
void read_gcode_program(const Reader& r, const Field& gcode, const Field& start, const MoveDefaults& defaults,
                        Scenario& sc) {
  GcodeOptions options;
  options.limits = defaults.limits;
  options.buffer = defaults.buffer;
  options.start = r.vec3(start);
  const GcodeResult parsed = load_gcode_file(r.existing_file(gcode), options);
  sc.start = sc.frame * parsed.start;
  sc.ignored = parsed.ignored;
  sc.program.moves.reserve(parsed.program.moves.size());
  for (Move move : parsed.program.moves) {
    if (Line* line = std::get_if<Line>(&move.geometry)) {
      line->p0 = sc.frame * line->p0;
      line->p1 = sc.frame * line->p1;
    } else {
      move.geometry = transformed(std::get<Arc>(move.geometry), sc.frame);
    }
    sc.program.moves.push_back(std::move(move));
  }
  sc.explicit_transition.assign(sc.program.moves.size(), false);
  sc.explicit_buffer.assign(sc.program.moves.size(), false);
}

// One move of the list: its geometry from `current` (program frame, m), its limits and modes.
Move read_move(const Reader& r, const Field& m, std::size_t i, const MoveDefaults& defaults, Vec3& current, Scenario& sc) {
  r.check_keys(m);
  const Field line = r.child(m, "line");
  const Field arc = r.child(m, "arc");
  if (line.node.defined() == arc.node.defined()) r.fail(m, "a move needs exactly one of 'line' or 'arc'");
  Move move;
  move.where = r.where(m);
  move.name = "move " + std::to_string(i + 1) + " (line " + std::to_string(move.where.line) + ")";
  if (line.node.defined()) {
    const Vec3 end = r.vec3(line);
    if ((end - current).norm() <= 1e-12) r.fail(line, "zero-length move: the end point equals the start point");
    move.geometry = Line{sc.frame * current, sc.frame * end};
    current = end;
  } else {
    const Arc a = read_arc(r, arc, current);
    move.geometry = transformed(a, sc.frame);
    current = point(Segment(a), length(a));
  }
  move.limits = defaults.limits;
  const std::array<std::pair<const char*, double*>, 4> limits = {{{"velocity", &move.limits.velocity},
                                                                  {"acceleration", &move.limits.acceleration},
                                                                  {"deceleration", &move.limits.deceleration},
                                                                  {"jerk", &move.limits.jerk}}};
  for (const auto& [key, target] : limits) {
    if (const Field v = r.child(m, key); v.node.defined()) *target = r.number(v);
  }
  move.buffer = defaults.buffer;
  if (const Field b = r.child(m, "buffer"); b.node.defined()) move.buffer = read_buffer(r, b);
  if (const Field t = r.child(m, "transition"); t.node.defined()) move.transition = read_transition(r, t);
  return move;
}

void read_program(const Reader& r, const Field& root, Scenario& sc) {
  const Field program = r.require(root, "program");
  r.check_keys(program);
  const Field moves = r.child(program, "moves");
  const Field gcode = r.child(program, "gcode");
  const MoveDefaults defaults = read_defaults(r, root);
  const Field start = r.value(program, "start");
  if (gcode.node.defined()) {
    if (moves.node.defined()) r.fail(moves, "give either 'moves' or 'gcode', not both");
    read_gcode_program(r, gcode, start, defaults, sc);
    return;
  }
  if (!moves.node.defined()) (void)r.require(program, "moves");
  if (!moves.node.is_sequence() || moves.node.size() == 0) {
    r.fail(moves, "expected a non-empty list of moves, got " + what_is(moves.node));
  }
  if (moves.node.size() > kMaxMoves) {
    r.fail(r.item(moves, kMaxMoves), "more than " + std::to_string(kMaxMoves) + " moves (the limit of one program)");
  }

  Vec3 current = r.vec3(start);
  sc.start = sc.frame * current;
  const std::size_t count = moves.node.size();
  sc.program.moves.reserve(count);
  sc.explicit_transition.reserve(count);
  sc.explicit_buffer.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const Field m = r.item(moves, i);
    sc.program.moves.push_back(read_move(r, m, i, defaults, current, sc));
    sc.explicit_transition.push_back(r.child(m, "transition").node.defined());
    sc.explicit_buffer.push_back(r.child(m, "buffer").node.defined());
  }
}

void read_robot(const Reader& r, const Field& root, Scenario& sc) {
  const Field robot = r.child(root, "robot");
  if (robot.node.defined()) r.check_keys(robot);
  // the shipped arm in the data root (data_root.hpp) unless the scenario names its own model
  sc.robot.urdf = r.existing_file(r.value(robot, "urdf"));
  sc.robot.mjcf = r.existing_file(r.value(robot, "mjcf"));
  sc.robot.base_link = r.text(r.value(robot, "base_link"));
  sc.robot.tip_link = r.text(r.value(robot, "tip_link"));
  sc.robot.tool_rotation = rpy_deg(radians(r.numbers(r.value(robot, "tool_rpy_deg"))));
  const std::vector<double> q = radians(r.numbers(r.value(robot, "q_seed_deg")));
  for (int i = 0; i < 6; ++i) sc.robot.q_seed[i] = q[static_cast<std::size_t>(i)];
}

std::array<double, 6> six(const std::vector<double>& v) {
  std::array<double, 6> out{};
  std::copy(v.begin(), v.end(), out.begin());
  return out;
}

void read_settings(const Reader& r, const Field& root, Scenario& sc) {
  const Field servo = r.child(root, "servo");
  if (servo.node.defined()) r.check_keys(servo);
  const Field rate = r.value(servo, "rate_hz");
  sc.servo.rate_hz = r.number(rate);
  // the physics step is 1 ms: a servo tick must fall on a step
  const double ratio = 1000.0 / sc.servo.rate_hz;
  if (std::abs(ratio - std::round(ratio)) > 1e-9) {
    r.fail(rate, "the servo rate must divide the 1000 Hz physics rate (1000, 500, 250, 200, ...), got " + rate.node.scalar());
  }
  if (const Field f = r.child(servo, "kp"); f.node.defined()) sc.servo.kp = six(r.numbers(f));
  if (const Field f = r.child(servo, "kd"); f.node.defined()) sc.servo.kd = six(r.numbers(f));
  sc.servo.gravity_compensation = r.flag(r.value(servo, "gravity_compensation"));
  sc.servo.feedforward = r.flag(r.value(servo, "feedforward"));

  const Field sim = r.child(root, "simulation");
  if (sim.node.defined()) r.check_keys(sim);
  sc.simulation.settle_tolerance = r.number(r.value(sim, "settle_tolerance"));
  sc.simulation.settle_time = r.number(r.value(sim, "settle_time_s"));

  const Field video = r.child(root, "video");
  if (video.node.defined()) r.check_keys(video);
  sc.video.fps = r.number(r.value(video, "fps"));
  for (auto [key, target] : {std::pair{"width", &sc.video.width}, std::pair{"height", &sc.video.height}}) {
    const Field f = r.value(video, key);
    *target = r.integer(f);
    if (*target % 2 != 0) r.fail(f, "must be an even number of pixels, got " + f.node.scalar());
  }
}

void read_variants(const Reader& r, const Field& root, Scenario& sc) {
  const Field variants = r.require(root, "variants");
  if (!variants.node.is_sequence() || variants.node.size() == 0) {
    r.fail(variants, "expected a non-empty list of variants, got " + what_is(variants.node));
  }
  if (variants.node.size() > kMaxVariants) {
    r.fail(r.item(variants, kMaxVariants), "more than " + std::to_string(kMaxVariants) + " variants (the limit of one scenario)");
  }
  std::set<std::string> names;
  for (std::size_t i = 0; i < variants.node.size(); ++i) {
    const Field f = r.item(variants, i);
    r.check_keys(f);
    Variant v;
    v.where = r.where(f);
    const Field name = r.require(f, "name");
    v.name = r.text(name);
    if (const std::string problem = folder_name_problem(v.name); !problem.empty()) r.fail(name, "variant " + problem);
    if (!names.insert(v.name).second) r.fail(name, "duplicate variant name '" + v.name + "'");
    if (const Field t = r.child(f, "transition"); t.node.defined()) v.transition = read_transition(r, t);
    if (const Field b = r.child(f, "buffer"); b.node.defined()) v.buffer = read_buffer(r, b);
    v.baseline = r.choice(r.value(f, "baseline"));
    sc.variants.push_back(std::move(v));
  }
}

}  // namespace

std::string folder_name_problem(const std::string& name) {
  constexpr std::size_t kMaxLength = 100;
  const auto allowed = [](char c, bool first) {
    const bool alnum = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9');
    return alnum || c == '_' || (!first && (c == '-' || c == '.'));
  };
  const std::string rule = "(letters, digits, '_', '-', '.'; starting with a letter, digit or '_'; at most " +
                           std::to_string(kMaxLength) + " characters)";
  if (name.empty()) return "name is empty; it names the output folder " + rule;
  if (name.size() > kMaxLength) return "name is " + std::to_string(name.size()) + " characters long " + rule;
  for (std::size_t i = 0; i < name.size(); ++i) {
    if (!allowed(name[i], i == 0)) {
      return "name cannot name an output folder: character " + std::to_string(i + 1) + " is not allowed " + rule;
    }
  }
  return {};
}

Scenario parse_scenario(const std::string& text, const std::string& file, const std::string& base_dir) {
  const Document doc(text, file);
  Reader r(doc, file, base_dir);
  const Field root = r.root();
  if (!root.node.is_map()) {
    r.fail(root, "a scenario must be a map with 'name', 'defaults', 'program' and 'variants', got " + what_is(root.node));
  }
  r.check_keys(root);
  Scenario sc;
  sc.file = file;
  const Field name = r.require(root, "name");
  sc.name = r.text(name);
  if (const std::string problem = folder_name_problem(sc.name); !problem.empty()) r.fail(name, "scenario " + problem);
  sc.description = r.text(r.value(root, "description"));
  const double scale = r.choice(r.value(root, "units")) == "m" ? 1.0 : 1e-3;
  r.set_scale(scale);
  if (const Field frame = r.child(root, "frame"); frame.node.defined()) {
    r.check_keys(frame);
    sc.frame.translation() = r.vec3(r.require(frame, "origin"));
    sc.frame.linear() = rpy_deg(radians(r.numbers(r.value(frame, "rpy_deg"))));
  }
  read_robot(r, root, sc);
  read_settings(r, root, sc);
  read_program(r, root, sc);
  read_variants(r, root, sc);
  // the planner's own checks (joins, limits) on the first variant's program
  validate(program_for(sc, sc.variants.front()));
  return sc;
}

Scenario load_scenario(const std::string& path) {
  const std::string text = read_input_file(path, "scenario file");
  const std::string dir = std::filesystem::path(path).parent_path().string();
  return parse_scenario(text, path, dir.empty() ? "." : dir);
}

Program program_for(const Scenario& scenario, const Variant& variant) {
  Program program = scenario.program;
  for (std::size_t k = 0; k < program.moves.size(); ++k) {
    if (variant.transition && !scenario.explicit_transition[k]) program.moves[k].transition = *variant.transition;
    if (variant.buffer && !scenario.explicit_buffer[k]) program.moves[k].buffer = *variant.buffer;
  }
  return program;
}

const Variant& find_variant(const Scenario& scenario, const std::string& name) {
  std::string names;
  for (const Variant& v : scenario.variants) {
    if (v.name == name) return v;
    names += (names.empty() ? "" : ", ") + v.name;
  }
  throw InputError("", 0, 0, "--variant", "no variant '" + name + "' in " + scenario.file + " (variants: " + names + ")");
}

}  // namespace blendbench
