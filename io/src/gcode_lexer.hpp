#pragma once
// Private to io/src (not installed): the G-code lexer, which splits one line of a part program
// into words (letter + value) for the reader (gcode.cpp). A value is a number or, as LinuxCNC
// reads it, a parameter (#1, ##2, #[expr], #<name>), an expression in [ ] or a unary function
// (ABS[..], ATAN[..]/[..], ...), evaluated when the line is read with the parameters in force.
// Comments and blanks are dropped first; what the lexer cannot read stops with
// InputError(file, line, column, word, message).

#include <cstddef>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gcode_params.hpp"

namespace blendbench::gcode_detail {

// Brackets and parameter references nest at most this deep in one value (bounds the recursion
// on hostile input; real programs nest a few levels).
inline constexpr int kMaxExpressionDepth = 64;

// A line with its blanks (space, tab, CR, FF, VT) and comments removed (RS274/NGC ignores blanks
// outside comments), each character's 1-based column in the original line kept. U+2212 (Unicode
// minus) becomes '-'.
struct CompactLine {
  std::string text;
  std::vector<int> column;  // column[i] of text[i]; column[text.size()] is one past the end
  bool unicode_minus = false;
};

struct Word {
  char letter = 0;   // upper case
  double value = 0;  // evaluated, program units
  std::string text;  // upper-case letter + the value as written, without blanks
  int column = 0;    // 1-based, in characters
};

// "#n = value" or "#<name> = value" on a line; applied after every value of the line is read.
struct Assignment {
  int number = 0;    // 1..kMaxParameter, or 0 for a named parameter
  std::string name;  // lower case, for a named parameter
  double value = 0;
  std::string text;  // the parameter as written, e.g. "#<depth>"
  int column = 0;
};

struct Block {
  int line = 0;
  std::vector<Word> words;
  std::vector<Assignment> assignments;
  bool unicode_minus = false;
};

// An O-word line's label and keyword ("o100 while [...]"): label "100" or "<name>" (lower case),
// keyword lower case ("sub", "call", ...); `rest` indexes the text after the keyword.
struct OWordHead {
  std::string label;
  std::string keyword;
  int column = 0;  // of the O
  std::size_t rest = 0;
  // How a message names it: "o100" or "o<name>".
  [[nodiscard]] std::string name() const { return "o" + label; }
};

// `s` without leading and trailing blanks (space, tab, CR, FF, VT).
std::string_view strip_blanks(std::string_view s);

// Removes blanks and comments from line `line_no` (1-based); `file` names the program in errors
// (an unclosed or nested comment).
CompactLine compact_line(std::string_view s, int line_no, const std::string& file);

// The O-word of a compacted line (after an optional N word), or nullopt if the line has none.
// Throws InputError for an O-word without a label or keyword.
std::optional<OWordHead> oword_head(const CompactLine& line, int line_no, const std::string& file);

// Splits a compacted line (no O-word) into words and parameter assignments, evaluating every
// value with `params` as they are before the line.
Block lex_block(const CompactLine& line, int line_no, const std::string& file, const Params& params);

// The bracketed expressions after an O-word's keyword ("[1] [#2+3]"), evaluated; throws when
// anything else follows, or when their count is outside [min_count, max_count].
std::vector<double> oword_values(const CompactLine& line, const OWordHead& head, int line_no, const std::string& file,
                                 const Params& params, std::size_t min_count, std::size_t max_count);

}  // namespace blendbench::gcode_detail
