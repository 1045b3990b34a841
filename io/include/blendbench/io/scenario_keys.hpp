#pragma once
// The scenario format: every key the YAML loader accepts, in one table that the loader checks
// files with (which keys a map may hold, their types, ranges and defaults) and that the
// reference is generated from (docs/scenario_format.md, `blendbench validate --schema`), so the
// two cannot drift. Adding a key is one line in scenario_keys.cpp plus the code in scenario.cpp
// that uses its value.

#include <cstddef>
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace blendbench {

enum class KeyType {
  kMap,      // a mapping; `opens` names the table map of its keys
  kList,     // a list of mappings; `opens` names the table map of each item
  kText,     // a string
  kFile,     // a file name, relative to the scenario's folder, then to the data folder
  kChoice,   // one of `choices` (case-insensitive)
  kBool,     // true or false
  kInteger,  // a whole number written without a decimal point
  kNumber,   // a finite number
  kNumbers,  // a list of `count` finite numbers (count 0: of any length, up to kMaxListNumbers)
};

// A unit as the file writes it. `length_power` is the power of the file's length unit (`units`:
// mm or m) in it: 1 for units/s, -1 for 1/units, 0 for units that do not scale.
struct KeyUnit {
  std::string_view text = "";  // "" for none
  int length_power = 0;
};

// In a namespace of their own: their names (kLength, kCurvature, ...) are also enumerators of
// Binding (timing.hpp), and the table (scenario_keys.cpp) opens this namespace where it uses them.
namespace key_units {
inline constexpr KeyUnit kNoUnit{"", 0};
inline constexpr KeyUnit kLength{"units", 1};
inline constexpr KeyUnit kVelocity{"units/s", 1};
inline constexpr KeyUnit kAcceleration{"units/s^2", 1};
inline constexpr KeyUnit kJerk{"units/s^3", 1};
inline constexpr KeyUnit kCurvature{"1/units", -1};
inline constexpr KeyUnit kDegrees{"deg", 0};
inline constexpr KeyUnit kAngularVelocity{"deg/s", 0};
inline constexpr KeyUnit kAngularAcceleration{"deg/s^2", 0};
inline constexpr KeyUnit kAngularJerk{"deg/s^3", 0};
inline constexpr KeyUnit kSeconds{"s", 0};
inline constexpr KeyUnit kHertz{"Hz", 0};
inline constexpr KeyUnit kPixels{"px", 0};
inline constexpr KeyUnit kKilograms{"kg", 0};
}  // namespace key_units

// The values a number (every element of a list of numbers) may take, as written in the file.
// Bounds of keys whose unit scales with `units` are 0 or infinite, so they hold in mm and m.
struct KeyRange {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false;  // lo itself excluded
  bool hi_open = false;
};

inline constexpr double kInfinity = std::numeric_limits<double>::infinity();
inline constexpr KeyRange kAnyFinite{};
inline constexpr KeyRange kPositive{0, kInfinity, true, false};
inline constexpr KeyRange kNonNegative{0, kInfinity, false, false};

// The longest list of numbers a key of any length (count 0) takes.
inline constexpr std::size_t kMaxListNumbers = 100;

struct ScenarioKey {
  std::string_view map = "";   // the table map the key belongs to ("" is the top level)
  std::string_view name = "";  // the key as written
  KeyType type = KeyType::kText;
  int count = 0;              // kNumbers: how many (0: a list of any length up to kMaxListNumbers)
  std::string_view opens = "";     // kMap, kList: the table map of its keys / of each item's keys
  KeyUnit unit = key_units::kNoUnit;
  bool required = false;      // must be given (keys required only in some cases say so in `meaning`)
  std::string_view fallback = "";  // the default as YAML text, lengths in mm ("" = none or `meaning` says)
  KeyRange range = kAnyFinite;
  std::string_view choices = "";   // kChoice: "a|b|c"
  std::string_view meaning = "";   // one line
};

// Every key, grouped by map in the order of the reference.
std::span<const ScenarioKey> scenario_keys();

// The key `name` of table map `map`, or nullptr.
const ScenarioKey* find_scenario_key(std::string_view map, std::string_view name);

// Where a table map sits in a file, e.g. "program.moves[]", or "program.moves[].transition"
// and "variants[].transition" for a map reached in two ways; {""} for the top level.
std::vector<std::string> scenario_map_path_list(std::string_view map);
// The same joined by " and ".
std::string scenario_map_paths(std::string_view map);

// A range as messages and the reference print it: "> 0", ">= 0", "[24, 120]", "finite".
std::string range_text(const KeyRange& range);

// The reference of the format in Markdown, generated from the table (docs/scenario_format.md).
std::string scenario_format_markdown();

// The closest keys to `word` among `candidates` by edit distance (insertions, deletions,
// substitutions and swaps of adjacent letters), within a distance of a third of the word's
// length (at least 1); several when tied, none when nothing is that close.
std::vector<std::string> closest_names(std::string_view word, std::span<const std::string> candidates);

}  // namespace blendbench
