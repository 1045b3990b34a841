// The G-code lexer (gcode_lexer.hpp): one line of a part program split into words.

#include "gcode_lexer.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <system_error>

#include "blendbench/core/input_error.hpp"

namespace blendbench::gcode_detail {
namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\f' || c == '\v'; }
bool is_continuation(unsigned char c) { return (c & 0xC0) == 0x80; }
bool is_unicode_minus(std::string_view s, std::size_t i) {
  return i + 2 < s.size() && static_cast<unsigned char>(s[i]) == 0xE2 &&
         static_cast<unsigned char>(s[i + 1]) == 0x88 && static_cast<unsigned char>(s[i + 2]) == 0x92;
}

// The lexer of one program: `file` names it in errors.
class Lexer {
 public:
  explicit Lexer(const std::string& file) : file_(file) {}

  // Splits a line into words (lex_block).
  Block lex(std::string_view s, int line_no) const {
    Block block;
    block.line = line_no;
    // 1-based character column of every byte (UTF-8 continuation bytes share their lead's column)
    std::vector<int> col(s.size() + 1, 1);
    int c = 0;
    for (std::size_t i = 0; i < s.size(); ++i) {
      if (!is_continuation(static_cast<unsigned char>(s[i]))) ++c;
      col[i] = c;
    }
    col[s.size()] = c + 1;

    const auto skip_spaces = [&](std::size_t& i) {
      while (i < s.size() && is_space(s[i])) ++i;
    };
    std::size_t i = 0;
    while (true) {
      skip_spaces(i);
      if (i >= s.size()) break;
      const char ch = s[i];
      if (ch == '(') {
        const std::size_t close = s.find(')', i + 1);
        const std::size_t nested = s.find('(', i + 1);
        if (close == std::string_view::npos) fail(line_no, col[i], "(", "comment is not closed on this line");
        if (nested < close) fail(line_no, col[nested], "(", "nested comments are not allowed");
        i = close + 1;
        continue;
      }
      if (ch == ';') break;
      if (std::isalpha(static_cast<unsigned char>(ch))) {
        block.words.push_back(lex_word(s, i, col, line_no, block.unicode_minus));
        continue;
      }
      const std::string what(1, ch);
      if (ch == '#') fail(line_no, col[i], what, "parameters (#) are not supported");
      if (ch == '[' || ch == ']') fail(line_no, col[i], what, "expressions ([ ]) are not supported");
      if (ch == '%') fail(line_no, col[i], what, "'%' must stand alone on its line (tape marker)");
      if (ch == '/') fail(line_no, col[i], what, "block delete '/' must be the first character of the line");
      if (is_unicode_minus(s, i)) fail(line_no, col[i], "\u2212", "a minus sign must follow a word letter");
      if (static_cast<unsigned char>(ch) >= 0x80) {
        std::size_t len = 1;
        while (i + len < s.size() && is_continuation(static_cast<unsigned char>(s[i + len]))) ++len;
        fail(line_no, col[i], std::string(s.substr(i, len)), "unexpected character");
      }
      fail(line_no, col[i], what, "unexpected character");
    }
    return block;
  }

 private:
  [[noreturn]] void fail(int line, int column, const std::string& word, const std::string& message) const {
    throw InputError(file_, line, column, word, message);
  }

  // Reads a letter and its number starting at s[i]; advances i past them.
  Word lex_word(std::string_view s, std::size_t& i, const std::vector<int>& col, int line_no, bool& unicode_minus) const {
    Word word;
    word.letter = static_cast<char>(std::toupper(static_cast<unsigned char>(s[i])));
    word.column = col[i];
    ++i;
    const auto skip_spaces = [&] {
      while (i < s.size() && is_space(s[i])) ++i;
    };
    // O-words name subroutines and control flow; report them whole
    if (word.letter == 'O') {
      std::size_t end = i;
      while (end < s.size() && !is_space(s[end]) && s[end] != '(' && s[end] != ';') ++end;
      fail(line_no, word.column, "O" + std::string(s.substr(i, end - i)),
           "O-words (subroutines, loops, conditionals) are not supported");
    }
    std::string number;
    skip_spaces();
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) {
      number += s[i];
      ++i;
    } else if (is_unicode_minus(s, i)) {
      number += '-';
      unicode_minus = true;
      i += 3;
    }
    bool digits = false;
    bool dot = false;
    while (true) {
      skip_spaces();
      if (i >= s.size()) break;
      const char ch = s[i];
      if (std::isdigit(static_cast<unsigned char>(ch))) {
        digits = true;
      } else if (ch == '.') {
        if (dot) fail(line_no, col[i], std::string(1, word.letter) + number + ".", "malformed number (two decimal points)");
        dot = true;
      } else {
        break;
      }
      number += ch;
      ++i;
    }
    word.text = std::string(1, word.letter) + number;
    if (!digits) {
      if (i < s.size() && s[i] == '#') fail(line_no, col[i], word.text + "#", "parameters (#) are not supported");
      if (i < s.size() && s[i] == '[') fail(line_no, col[i], word.text + "[", "expressions ([ ]) are not supported");
      fail(line_no, word.column, word.text, std::string("word '") + word.letter + "' has no number");
    }
    // std::from_chars takes neither a leading '+' nor a bare trailing '.'
    std::string plain = number;
    if (!plain.empty() && plain.front() == '+') plain.erase(0, 1);
    const auto result = std::from_chars(plain.data(), plain.data() + plain.size(), word.value);
    if (result.ec != std::errc() || result.ptr != plain.data() + plain.size() || !std::isfinite(word.value)) {
      fail(line_no, word.column, word.text, "malformed number");
    }
    return word;
  }

  const std::string& file_;
};

}  // namespace

std::string_view strip_blanks(std::string_view s) {
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  return s;
}

Block lex_block(std::string_view s, int line_no, const std::string& file) { return Lexer(file).lex(s, line_no); }

}  // namespace blendbench::gcode_detail
