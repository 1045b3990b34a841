#pragma once
// Private to io/src (not installed): a YAML document read into a compact tree whose every node
// knows its line and column, for the scenario loader (scenario.cpp). The text is parsed with
// libyaml's event parser; the tree is built here, so the checks a loader needs happen while it
// is built and the work is bounded before it is done:
//   - one document per file, at most kMaxNodes nodes (aliases counted as the nodes they repeat,
//     so a "billion laughs" document is refused early) and at most kMaxDepth levels of nesting;
//   - map keys are scalars (a list or a map used as a key is refused at its position), never
//     empty, and never twice in one map (YAML says a key is unique; libyaml and yaml-cpp would
//     keep the first or the last silently);
//   - a quoted string the file ends in is named as such, at its opening quote;
//   - every refusal is InputError(file, line, column, path, message), `path` being the key path
//     being read ("program.moves[3].arc").
// Plain scalars "", "~", "null", "Null" and "NULL" are null (YAML 1.2 core schema); everything
// else stays text, for the loader to convert.

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace blendbench::yaml_detail {

// The most nodes one document may have (after aliases): about 600,000 moves of a scenario.
inline constexpr std::size_t kMaxNodes = 4'000'000;
// The deepest nesting of lists and maps: a scenario nests six levels; the rest is headroom.
inline constexpr int kMaxDepth = 64;

enum class Kind : std::uint8_t { kNull, kScalar, kSequence, kMap };

struct Node {
  Kind kind = Kind::kNull;
  bool plain = true;         // a scalar written without quotes
  int line = 0;              // 1-based
  int column = 0;            // 1-based, in characters
  std::string text;          // a scalar's text
  std::uint32_t first = 0;   // children in Document::links_: items, or key and value per entry
  std::uint32_t count = 0;   // sequence items, or map entries
};

class Document;

// A node of a document, or no node (an absent key): what the loader walks. Cheap to copy; valid
// while its document lives.
class Ref {
 public:
  Ref() = default;
  Ref(const Document* doc, std::uint32_t index) : doc_(doc), index_(index) {}

  [[nodiscard]] bool defined() const { return doc_ != nullptr; }
  [[nodiscard]] bool is_null() const { return defined() && node().kind == Kind::kNull; }
  [[nodiscard]] bool is_scalar() const { return defined() && node().kind == Kind::kScalar; }
  [[nodiscard]] bool is_sequence() const { return defined() && node().kind == Kind::kSequence; }
  [[nodiscard]] bool is_map() const { return defined() && node().kind == Kind::kMap; }
  // A scalar's text ("" for other nodes).
  [[nodiscard]] const std::string& scalar() const;
  [[nodiscard]] bool plain() const { return defined() && node().plain; }
  // Items of a sequence, entries of a map, 0 otherwise.
  [[nodiscard]] std::size_t size() const;
  // Item i of a sequence (i < size()).
  [[nodiscard]] Ref operator[](std::size_t i) const;
  // Key and value of map entry i (i < size()).
  [[nodiscard]] Ref key(std::size_t i) const;
  [[nodiscard]] Ref value(std::size_t i) const;
  // The value of `key` in a map; no node when absent or when this is not a map.
  [[nodiscard]] Ref get(std::string_view key) const;
  // 1-based position; 0 for no node.
  [[nodiscard]] int line() const { return defined() ? node().line : 0; }
  [[nodiscard]] int column() const { return defined() ? node().column : 0; }

 private:
  [[nodiscard]] const Node& node() const;
  const Document* doc_ = nullptr;
  std::uint32_t index_ = 0;
};

// A quoted scalar written over more than one line: the usual trace of a missing closing quote
// that a later quote closed.
struct LongQuote {
  int line = 0;  // where it opens, 1-based; 0 when there is none
  int column = 0;
  int lines = 0;  // how many lines it spans
};

class Document {
 public:
  // Parses `text` (UTF-8; UTF-16 with a byte order mark); `file` names it in errors. Throws
  // InputError as described at the top of this file; an empty text is a null root.
  Document(std::string_view text, const std::string& file);

  [[nodiscard]] Ref root() const { return {this, 0}; }
  // The first quoted scalar that spans lines, for messages about a field that seems missing.
  [[nodiscard]] const LongQuote& long_quote() const { return long_quote_; }

 private:
  friend class Ref;
  friend class Builder;
  std::vector<Node> nodes_;
  std::vector<std::uint32_t> links_;
  LongQuote long_quote_;
};

}  // namespace blendbench::yaml_detail
