#pragma once
// Private to io/src (not installed): the G-code lexer, which splits one line of a part program
// into words (letter + number) for the reader (gcode.cpp). Comments are dropped; what the lexer
// cannot read stops with InputError(file, line, column, word, message).

#include <string>
#include <string_view>
#include <vector>

namespace blendbench::gcode_detail {

struct Word {
  char letter = 0;   // upper case
  double value = 0;  // as written, program units
  std::string text;  // upper-case letter + number as written (U+2212 shown as '-')
  int column = 0;    // 1-based, in characters
};

struct Block {
  int line = 0;
  std::vector<Word> words;
  bool unicode_minus = false;
};

// `s` without leading and trailing blanks (space, tab, CR, FF, VT).
std::string_view strip_blanks(std::string_view s);

// Splits line `line_no` (1-based) into words. Spaces and tabs are skipped anywhere outside
// comments (RS274/NGC); `file` names the program in errors.
Block lex_block(std::string_view s, int line_no, const std::string& file);

}  // namespace blendbench::gcode_detail
