#pragma once
// Private to io/src (not installed): the scenario loader's reader, which walks a YAML document
// (yaml_document.hpp) map by map against the format's table (scenario_keys.hpp): which keys a
// map may hold, their types, ranges, units and defaults. Every refusal is an InputError naming
// the file, line, column and key path. scenario.cpp turns what it reads into a Scenario.

#include <memory>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "blendbench/core/geometry.hpp"
#include "blendbench/core/input_error.hpp"
#include "blendbench/io/scenario_keys.hpp"
#include "yaml_document.hpp"

namespace blendbench::scenario_detail {

using yaml_detail::Document;
using yaml_detail::Ref;

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
std::string what_is(const Ref& node);

class Reader {
 public:
  Reader(const Document& doc, std::string file, std::string base_dir)
      : doc_(doc), file_(std::move(file)), base_dir_(std::move(base_dir)) {}

  [[nodiscard]] Field root() const { return {doc_.root(), nullptr, "", 0, "", nullptr, doc_.root(), false}; }

  // The file's length unit in metres (1e-3 for mm), once `units` is read.
  void set_scale(double scale) { scale_ = scale; }

  // Throws InputError at `f` (at its map when the key is absent), naming its key path.
  [[noreturn]] void fail(const Field& f, const std::string& message) const;

  // Where `f` is written (its map's position when absent), for the planner's messages.
  [[nodiscard]] SourceRef where(const Field& f) const;

  // Fails unless `f` is a map whose every key belongs to its table map and every value has the
  // type and range its table entry gives (in the order written). An unknown key names the
  // closest valid ones (a typo) or the map it belongs in.
  void check_keys(const Field& f) const;

  // Fails unless the value `f` has the type and range of its table entry (a map's or a list's
  // own keys are checked when it is read).
  void check_value(const Field& f) const;

  // The value of `key` in map `f`; no node when absent. `key` must be in the table.
  [[nodiscard]] Field child(const Field& f, std::string_view key) const;

  // The value of `key`, or the table's default when absent (no node when it has none).
  [[nodiscard]] Field value(const Field& f, std::string_view key) const;

  // The value of a key that must be given (and not empty).
  [[nodiscard]] Field require(const Field& f, std::string_view key) const;

  // Item `i` of list `f`, a map of the table map `f` opens.
  [[nodiscard]] Field item(const Field& f, std::size_t i) const;

  // "missing required field", with a hint when a quoted string spans lines (an unclosed quote
  // that a later one closed swallows the keys in between).
  [[nodiscard]] std::string missing() const;

  // A number of the field's table entry: finite, in its range, converted to SI.
  [[nodiscard]] double number(const Field& f) const;

  // An integer of the field's table entry, in its range.
  [[nodiscard]] int integer(const Field& f) const;

  // true or false (True, TRUE, False, FALSE), nothing else.
  [[nodiscard]] bool flag(const Field& f) const;

  // A scalar's text.
  [[nodiscard]] const std::string& text(const Field& f) const;

  // One of the entry's choices, as the table spells it (the file's may differ in case).
  [[nodiscard]] std::string choice(const Field& f) const;

  // A list of the entry's count of numbers, each finite, in range and converted to SI.
  [[nodiscard]] std::vector<double> numbers(const Field& f) const;

  // Three numbers as a vector (SI).
  [[nodiscard]] Vec3 vec3(const Field& f) const;

  // An existing file named relative to the scenario's directory, then to the data root
  // (data_root.hpp: models/ and scenarios/ in the source tree or the install prefix); a default
  // names a file of the data root.
  [[nodiscard]] std::string existing_file(const Field& f) const;

  // Existing folders written as LinuxCNC writes SUBROUTINE_PATH, separated by ':', each
  // relative to the scenario's directory unless absolute.
  [[nodiscard]] std::vector<std::string> existing_folders(const Field& f) const;

  [[nodiscard]] const std::string& file() const { return file_; }

 private:
  // The number as written: a YAML decimal, finite (nan and inf spelt any way refused).
  [[nodiscard]] double raw_number(const Field& f) const;

  // The entry's range in words with its unit in the file's length unit ("in [1, 1000] Hz").
  [[nodiscard]] std::string range_of(const Field& f) const;

  // Fails when `value` (as written) is outside the entry's range.
  void check_range(const Field& f, double value) const;

  // SI per unit of the file: the length unit to the entry's power (a default's lengths are mm).
  [[nodiscard]] double unit_factor(const Field& f) const;

  // The table's default of an entry, parsed once.
  [[nodiscard]] Ref fallback_of(const ScenarioKey& key) const;

  // "(did you mean 'a' or 'b'?)" for the closest options, else "(otherwise)".
  static std::string suggestion(const std::string& word, const std::vector<std::string>& options, const std::string& otherwise);

  // "unknown key 'velocty' (did you mean 'velocity'?)", or the map it belongs in, or the list.
  static std::string unknown_key(std::string_view map, const std::string& key);

  const Document& doc_;
  std::string file_;
  std::string base_dir_;
  double scale_ = 1e-3;
  mutable std::unordered_map<const ScenarioKey*, std::unique_ptr<Document>> fallbacks_;
};

}  // namespace blendbench::scenario_detail
