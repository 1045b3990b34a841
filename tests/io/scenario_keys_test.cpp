// The scenario format's table drives the loader: every key's default is what an absent key
// gives, every key refuses values of the wrong type or range by name, every typo of every key
// gets that key suggested, and the committed reference is what the table generates.

#include "blendbench/io/scenario_keys.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <optional>
#include <set>
#include <sstream>
#include <utility>
#include <vector>

#include "blendbench/core/format.hpp"
#include "blendbench/io/scenario.hpp"
#include "support/input_error.hpp"
#include "support/property.hpp"

namespace blendbench {
namespace {

// A YAML value to build scenario texts from: a scalar as written, a map in order, or a list.
// (A map's entries are a struct of their own: std::pair of an incomplete type does not compile
// with clang's standard library checks, a vector of an incomplete struct does.)
struct YamlEntry;
struct Yaml {
  enum class Kind { kScalar, kMap, kList } kind = Kind::kScalar;
  std::string scalar;
  std::vector<YamlEntry> map;
  std::vector<Yaml> list;
};
struct YamlEntry {
  std::string first;
  Yaml second;
};

Yaml S(std::string text) { return {Yaml::Kind::kScalar, std::move(text), {}, {}}; }
Yaml M(std::vector<YamlEntry> entries) { return {Yaml::Kind::kMap, "", std::move(entries), {}}; }
Yaml L(std::vector<Yaml> items) { return {Yaml::Kind::kList, "", {}, std::move(items)}; }

// Flow style: {a: 1, b: [1, 2]}; the top level as one "key: value" line per entry.
std::string flow(const Yaml& y) {
  std::string out;
  switch (y.kind) {
    case Yaml::Kind::kScalar: return y.scalar;
    case Yaml::Kind::kMap:
      for (const auto& [k, v] : y.map) out += (out.empty() ? "" : ", ") + k + ": " + flow(v);
      return "{" + out + "}";
    case Yaml::Kind::kList:
      for (const Yaml& v : y.list) out += (out.empty() ? "" : ", ") + flow(v);
      return "[" + out + "]";
  }
  return out;
}

std::string text_of(const Yaml& root) {
  std::string out;
  for (const auto& [k, v] : root.map) out += k + ": " + flow(v) + "\n";
  return out;
}

// A valid scenario in which every map of the table is present (an arc with a centre and an
// orientation, both transitions), so any key can be set in it.
Yaml base() {
  return M({{"name", S("all")},
            {"units", S("mm")},
            {"frame", M({{"origin", S("[0, 0, 0]")}})},
            {"robot", M({{"tool", M({})}, {"estimate_inertia", M({{"total_mass_kg", S("20")}})}})},
            {"servo", M({})},
            {"simulation", M({})},
            {"sensitivity", M({})},
            {"video", M({{"camera", M({})}})},
            {"axis_limits", M({{"a", S("[1000, 1000, 1000]")}, {"j", S("[10000, 10000, 10000]")}})},
            {"defaults", M({{"velocity", S("100")}, {"acceleration", S("1000")}, {"jerk", S("10000")}})},
            {"program", M({{"moves", L({M({{"arc", M({{"end", S("[20, 0, 0]")}, {"center", S("[10, 0, 0]")}, {"direction", S("ccw")}})},
                                           {"orientation", M({{"rpy_deg", S("[180, 0, 0]")}})},
                                           {"transition", M({{"method", S("arc")}, {"parameter", S("1")}})}}),
                                        M({{"line", S("[20, 10, 0]")}})})},
                          {"smoothing", M({})}})},
            {"variants", L({M({{"name", S("a")}, {"transition", M({{"method", S("none")}})}, {"smoothing", M({})}})})}});
}

// The base scenario for a key of the map at `path`: base(), but with its program given as a
// G-code file with tool angles for the keys of program.gcode_angles (which only a G-code
// program takes).
Yaml base_for(const std::string& path) {
  Yaml y = base();
  if (!path.starts_with("program.gcode_angles")) return y;
  for (auto& [k, v] : y.map) {
    if (k != "program") continue;
    v = M({{"gcode", S("\"" + test::source_path("scenarios/parts/bracket.ngc") + "\"")},
           {"gcode_angles", M({{"a", S("roll")}, {"b", S("pitch")}, {"c", S("yaw")}})}});
  }
  return y;
}

// The map at `path` (as scenario_map_path_list writes it: "program.moves[].arc"), the first
// item of each list.
Yaml& map_at(Yaml& root, const std::string& path) {
  Yaml* y = &root;
  std::stringstream parts(path);
  for (std::string part; std::getline(parts, part, '.');) {
    const bool item = part.size() > 2 && part.ends_with("[]");
    const std::string key = item ? part.substr(0, part.size() - 2) : part;
    Yaml* next = nullptr;
    for (auto& [k, v] : y->map) {
      if (k == key) next = &v;
    }
    EXPECT_NE(next, nullptr) << "no map '" << key << "' in the base scenario (" << path << ")";
    if (next == nullptr) return root;
    y = item ? &next->list.front() : next;
  }
  return *y;
}

// `root` with `key: value` first in the map at `path` (replacing the key's own entry).
Yaml with_key(Yaml root, const std::string& path, const std::string& key, Yaml value) {
  Yaml& map = path.empty() ? root : map_at(root, path);
  std::erase_if(map.map, [&](const auto& entry) { return entry.first == key; });
  map.map.insert(map.map.begin(), {key, std::move(value)});
  return root;
}

// The key path a message names: list items as [0].
std::string field_of(const std::string& path, const std::string& key) {
  std::string out = path;
  for (std::size_t at; (at = out.find("[]")) != std::string::npos;) out.replace(at, 2, "[0]");
  return out.empty() ? key : out + "." + key;
}

Scenario parse(const Yaml& y) { return parse_scenario(text_of(y), "keys.yaml", "."); }

// Everything the loader fills in, as text, to compare two loads.
std::string signature(const Scenario& sc) {
  std::ostringstream out;
  out.precision(17);
  const auto transition = [&](const Transition& t) {
    out << static_cast<int>(t.method) << ' ' << t.parameter << ' ' << t.kappa_max << ' ' << t.start_distance << ' '
        << t.velocity << ';';
  };
  out << sc.name << '|' << sc.description << '|' << sc.frame.matrix() << '|' << sc.start.transpose() << '|';
  const auto flag = [](const std::optional<bool>& b) { return b ? (*b ? 1 : 0) : -1; };
  out << static_cast<int>(sc.robot.model) << sc.robot.urdf << sc.robot.mjcf << sc.robot.base_link << sc.robot.tip_link
      << sc.robot.tool_rotation << sc.robot.q_seed.transpose() << sc.robot.tool.matrix() << sc.robot.allow_branch_change
      << sc.robot.mjcf_from_urdf << sc.robot.estimate_total_mass << '|';
  const ServoSettings& s = sc.servo;
  out << static_cast<int>(s.controller) << ' ' << s.rate_hz << ' ' << s.setpoint_rate_hz << ' ' << s.measurement_delay_ticks
      << ' ' << s.encoder_counts_per_turn << ' ' << flag(s.velocity_feedforward) << flag(s.acceleration_feedforward)
      << flag(s.gravity_compensation) << flag(s.deflection_compensation) << '|';
  const SimulationSettings& sim = sc.simulation;
  out << sim.settle_tolerance << ' ' << sim.settle_speed_tolerance << ' ' << sim.settle_window << ' ' << sim.settle_time
      << ' ' << sim.vibration_window << ' ' << sim.vibration_highpass << ' ' << sim.jerk_lowpass << '|';
  for (const Perturbation& p : sc.sensitivity.perturbations) {
    out << p.name << ' ' << p.stiffness_scale << ' ' << p.inertia_scale << ' ' << p.friction_scale << ' ' << p.extra_delay_ticks << ';';
  }
  out << '|' << sc.video.fps << ' ' << sc.video.width << ' ' << sc.video.height << '|';
  const VideoCamera& c = sc.video.camera;
  out << static_cast<int>(c.mode) << ' ' << c.fill << ' ' << c.azimuth_deg.value_or(-1e9) << ' ' << c.elevation_deg.value_or(-1e9)
      << ' ' << c.position.transpose() << ' ' << c.look_at.transpose() << ' ' << c.distance << ' ' << c.fovy_deg << '|';
  for (const Move& m : sc.program.moves) {
    out << length(m.geometry) << ' ' << point(m.geometry, length(m.geometry) / 3).transpose() << ' ' << m.limits.velocity
        << ' ' << m.limits.acceleration << ' ' << m.limits.deceleration << ' ' << m.limits.jerk << ' '
        << static_cast<int>(m.buffer) << ' ';
    transition(m.transition);
  }
  for (const Variant& v : sc.variants) {
    out << v.name << ' ' << baseline_name(v.baseline) << ' ' << (v.buffer ? static_cast<int>(*v.buffer) : -1) << ' ';
    if (v.transition) transition(*v.transition);
  }
  return out.str();
}

TEST(ScenarioKeys, TheBaseScenarioLoads) { EXPECT_NO_THROW((void)parse(base())); }

// A default written out gives the same scenario as the key left out: the table's default is
// what the loader uses.
TEST(ScenarioKeys, EveryDefaultWrittenOutLoadsLikeTheKeyLeftOut) {
  const std::string expected = signature(parse(base()));
  int checked = 0;
  for (const ScenarioKey& k : scenario_keys()) {
    if (k.fallback.empty()) continue;
    for (const std::string& path : scenario_map_path_list(k.map)) {
      const std::string field = field_of(path, std::string(k.name));
      try {
        EXPECT_EQ(signature(parse(with_key(base_for(path), path, std::string(k.name), S(std::string(k.fallback))))), expected) << field;
        ++checked;
      } catch (const InputError& e) {
        ADD_FAILURE() << field << " = " << k.fallback << ": " << e.what();
      }
    }
  }
  EXPECT_GT(checked, 20);
}

// Values the table says are wrong for each key, with the words of the refusal.
std::vector<std::pair<Yaml, std::string>> wrong_values(const ScenarioKey& k) {
  std::vector<std::pair<Yaml, std::string>> out;
  const bool integer = k.type == KeyType::kInteger;
  const auto scalar_cases = [&](std::vector<std::pair<std::string, std::string>>& cases) {
    const KeyRange& r = k.range;
    const double step = integer ? 1 : 0.5;
    if (std::isfinite(r.lo)) cases.emplace_back(format_value(r.lo_open ? r.lo : r.lo - step), "must be ");
    if (std::isfinite(r.hi)) cases.emplace_back(format_value(r.hi_open ? r.hi : r.hi + step), "must be ");
    cases.emplace_back(".nan", integer ? "expected an integer" : "expected a finite number");
    cases.emplace_back("[1]", integer ? "expected an integer, got a list" : "expected a number, got a list");
  };
  switch (k.type) {
    case KeyType::kNumber:
    case KeyType::kInteger: {
      std::vector<std::pair<std::string, std::string>> cases;
      scalar_cases(cases);
      for (auto& [v, m] : cases) out.emplace_back(S(v), m);
      break;
    }
    case KeyType::kNumbers: {
      std::vector<std::pair<std::string, std::string>> cases;
      scalar_cases(cases);
      // the first element wrong, the others valid
      const KeyRange& r = k.range;
      const double fine = std::isfinite(r.lo) ? r.lo + 1 : std::isfinite(r.hi) ? r.hi - 1 : 0;
      for (auto& [v, m] : cases) {
        if (v == "[1]") continue;
        std::vector<Yaml> items = {S(v)};
        for (int i = 1; i < k.count; ++i) items.push_back(S(format_value(fine)));
        out.emplace_back(L(items), m);
      }
      if (k.count > 0) {
        out.emplace_back(S("7"), "expected a list of " + std::to_string(k.count) + " numbers, got '7'");
        out.emplace_back(L({S("1")}), "expected a list of " + std::to_string(k.count) + " numbers, got a list of 1");
      } else {
        // a list of any length, up to kMaxListNumbers
        out.emplace_back(S("7"), "expected a list of numbers, got '7'");
        out.emplace_back(L(std::vector<Yaml>(kMaxListNumbers + 1, S(format_value(fine)))),
                         "expected at most " + std::to_string(kMaxListNumbers) + " numbers");
      }
      break;
    }
    case KeyType::kChoice: out.emplace_back(S("no_such_value"), "unknown value 'no_such_value'"); break;
    case KeyType::kBool: out.emplace_back(S("maybe"), "expected true or false, got 'maybe'"); break;
    case KeyType::kText:
    case KeyType::kFile: out.emplace_back(L({S("1")}), "expected a string, got a list"); break;
    case KeyType::kMap: out.emplace_back(S("5"), "expected a map (key: value pairs), got '5'"); break;
    case KeyType::kList: out.emplace_back(S("5"), "expected a list, got '5'"); break;
  }
  return out;
}

TEST(ScenarioKeys, EveryKeyRefusesValuesOfTheWrongTypeOrRangeByName) {
  int checked = 0;
  for (const ScenarioKey& k : scenario_keys()) {
    for (const std::string& path : scenario_map_path_list(k.map)) {
      for (const auto& [value, words] : wrong_values(k)) {
        std::string field = field_of(path, std::string(k.name));
        const std::size_t items = k.count > 0 ? static_cast<std::size_t>(k.count) : 1;  // a wrong first element
        if (k.type == KeyType::kNumbers && value.kind == Yaml::Kind::kList && value.list.size() == items) {
          field += "[0]";
        }
        const Yaml y = with_key(base_for(path), path, std::string(k.name), value);
        test::expect_input_error([&] { (void)parse(y); }, {.file = "keys.yaml", .field = field, .message = words},
                                 field + " = " + flow(value));
        ++checked;
      }
    }
  }
  EXPECT_GT(checked, 2 * static_cast<int>(scenario_keys().size()));
}

// True when a and b differ by one insertion, deletion, substitution or swap of neighbours.
bool one_edit_apart(const std::string& a, const std::string& b) {
  if (a == b) return false;
  const std::string& s = a.size() <= b.size() ? a : b;
  const std::string& l = a.size() <= b.size() ? b : a;
  if (l.size() - s.size() > 1) return false;
  std::size_t i = 0;
  while (i < s.size() && s[i] == l[i]) ++i;
  if (s.size() == l.size()) {
    if (s.substr(i + 1) == l.substr(i + 1)) return true;  // substitution
    return i + 1 < s.size() && s[i] == l[i + 1] && s[i + 1] == l[i] && s.substr(i + 2) == l.substr(i + 2);  // swap
  }
  return s.substr(i) == l.substr(i + 1);  // insertion
}

// Every key of the table misspelt as people do: a letter dropped, two neighbours swapped, a
// letter doubled. The message suggests the key; where another key is as close (one edit from
// the typo as well), both are named.
TEST(ScenarioKeys, EveryTypoOfEveryKeySuggestsThatKey) {
  int unique = 0;
  int tied = 0;
  for (const ScenarioKey& k : scenario_keys()) {
    std::set<std::string> keys_of_map;
    for (const ScenarioKey& other : scenario_keys()) {
      if (other.map == k.map) keys_of_map.emplace(other.name);
    }
    const std::string key(k.name);
    std::set<std::string> typos;
    for (std::size_t i = 0; i < key.size(); ++i) {
      typos.insert(key.substr(0, i) + key.substr(i + 1));                              // dropped
      typos.insert(key.substr(0, i + 1) + key[i] + key.substr(i + 1));                // doubled
      if (i + 1 < key.size()) typos.insert(key.substr(0, i) + key[i + 1] + key[i] + key.substr(i + 2));  // swapped
    }
    const std::string path = scenario_map_path_list(k.map).front();
    for (const std::string& typo : typos) {
      if (typo.empty() || keys_of_map.count(typo) != 0) continue;
      const Yaml y = with_key(base_for(path), path, typo, S("1"));
      const InputError e = test::expect_input_error(
          [&] { (void)parse(y); }, {.field = field_of(path, typo), .message = "unknown key '" + typo + "' (did you mean "},
          key + " as " + typo);
      const std::string what = e.what();
      const std::size_t open = what.find("(did you mean ");
      if (open == std::string::npos) continue;
      const std::string suggested = what.substr(open);
      EXPECT_NE(suggested.find("'" + key + "'"), std::string::npos) << what;
      // any other key suggested is as close to the typo
      std::size_t named = 0;
      for (const std::string& other : keys_of_map) {
        if (suggested.find("'" + other + "'") == std::string::npos) continue;
        ++named;
        EXPECT_TRUE(other == key || one_edit_apart(typo, other)) << what;
      }
      (named == 1 ? unique : tied) += 1;
    }
  }
  EXPECT_GT(unique, 1000);
  EXPECT_LT(tied, unique / 20) << "ties: " << tied;
}

// The choices of the table are the planner's names, all of them.
TEST(ScenarioKeys, ChoicesAreThePlannersNames) {
  const auto choices = [](std::string_view map, std::string_view name) {
    std::set<std::string> out;
    std::stringstream in{std::string(find_scenario_key(map, name)->choices)};
    for (std::string c; std::getline(in, c, '|');) out.insert(c);
    return out;
  };
  std::set<std::string> methods;
  for (const Method m : {Method::kNone, Method::kArc, Method::kBezier, Method::kClothoid, Method::kBiclothoid}) {
    methods.emplace(to_string(m));
  }
  EXPECT_EQ(choices("transition", "method"), methods);
  std::set<std::string> buffers;
  for (const BufferMode b : {BufferMode::kAborting, BufferMode::kBuffered, BufferMode::kBlendingLow, BufferMode::kBlendingPrevious,
                             BufferMode::kBlendingNext, BufferMode::kBlendingHigh}) {
    buffers.emplace(to_string(b));
  }
  for (const std::string_view map : {"defaults", "move", "variant"}) EXPECT_EQ(choices(map, "buffer"), buffers) << map;
}

// Table hygiene: every map is reachable from the top level, every key has a meaning, lengths
// have bounds that hold in mm and m, every default and every range is of the key's kind.
TEST(ScenarioKeys, TheTableIsConsistent) {
  std::set<std::pair<std::string, std::string>> seen;
  for (const ScenarioKey& k : scenario_keys()) {
    const std::string id = std::string(k.map) + "." + std::string(k.name);
    EXPECT_TRUE(seen.emplace(k.map, k.name).second) << "twice: " << id;
    EXPECT_FALSE(k.meaning.empty()) << id;
    EXPECT_FALSE(scenario_map_path_list(k.map).empty()) << "unreachable map of " << id;
    EXPECT_EQ(k.type == KeyType::kMap || k.type == KeyType::kList, !k.opens.empty()) << id;
    EXPECT_EQ(k.type == KeyType::kChoice, !k.choices.empty()) << id;
    EXPECT_TRUE(k.type == KeyType::kNumbers || k.count == 0) << id;  // count 0: a list of any length
    EXPECT_FALSE(k.required && !k.fallback.empty()) << "a required key with a default: " << id;
    if (k.unit.length_power != 0) {
      for (const double bound : {k.range.lo, k.range.hi}) EXPECT_TRUE(bound == 0 || std::isinf(bound)) << id;
    }
    EXPECT_EQ(find_scenario_key(k.map, k.name), &k) << id;
  }
}

// docs/scenario_format.md is what the table generates (`blendbench validate --schema`).
TEST(ScenarioKeys, TheCommittedReferenceIsWhatTheTableGenerates) {
  std::ifstream in(test::source_path("docs/scenario_format.md"));
  ASSERT_TRUE(in) << "docs/scenario_format.md is missing: build/blendbench validate --schema > docs/scenario_format.md";
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), scenario_format_markdown())
      << "docs/scenario_format.md is stale: build/blendbench validate --schema > docs/scenario_format.md";
}

TEST(ScenarioKeys, ClosestNamesFindsTyposAndTiesAndNothingFar) {
  const std::vector<std::string> keys = {"velocity", "acceleration", "deceleration", "jerk", "kp", "kd"};
  EXPECT_EQ(closest_names("velocty", keys), std::vector<std::string>{"velocity"});
  EXPECT_EQ(closest_names("jrek", keys), std::vector<std::string>{"jerk"});
  EXPECT_EQ(closest_names("accelleration", keys), std::vector<std::string>{"acceleration"});
  EXPECT_EQ(closest_names("k", keys), (std::vector<std::string>{"kp", "kd"}));
  EXPECT_TRUE(closest_names("speed", keys).empty());
  EXPECT_TRUE(closest_names("", keys).empty());
}

}  // namespace
}  // namespace blendbench
