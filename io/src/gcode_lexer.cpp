// The G-code lexer (gcode_lexer.hpp): one line of a part program split into words, with the
// parameters and expressions of RS274/NGC as LinuxCNC reads them (its G-code manual, "Overview":
// parameters, expressions, binary operators, functions).

#include "gcode_lexer.hpp"

#include <cctype>
#include <charconv>
#include <cmath>
#include <numbers>
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
bool is_alpha(char c) { return std::isalpha(static_cast<unsigned char>(c)) != 0; }
bool is_digit(char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; }
char upper(char c) { return static_cast<char>(std::toupper(static_cast<unsigned char>(c))); }
char lower(char c) { return static_cast<char>(std::tolower(static_cast<unsigned char>(c))); }

constexpr double kDegree = std::numbers::pi / 180;
// LinuxCNC interp_internal.hh TOLERANCE_EQUAL: EQ and NE compare within this.
constexpr double kToleranceEqual = 1e-6;
// A parameter number this close to an integer is that integer (it may come from an expression).
constexpr double kIntegerTolerance = 1e-6;

// Binary operators with LinuxCNC's precedence (interp_execute.cc, precedence()): a higher
// number binds tighter; equal precedence groups from the left.
enum class Op { kPower, kTimes, kDivide, kMod, kPlus, kMinus, kEq, kNe, kGt, kGe, kLt, kLe, kAnd, kOr, kXor };
int precedence(Op op) {
  switch (op) {
    case Op::kPower: return 6;
    case Op::kTimes: case Op::kDivide: case Op::kMod: return 5;
    case Op::kPlus: case Op::kMinus: return 4;
    case Op::kEq: case Op::kNe: case Op::kGt: case Op::kGe: case Op::kLt: case Op::kLe: return 3;
    case Op::kAnd: case Op::kOr: case Op::kXor: return 2;
  }
  return 0;
}

// Reads the values of one compacted line: numbers, parameters, expressions, functions.
class Reader {
 public:
  Reader(const CompactLine& line, int line_no, const std::string& file, const Params& params)
      : l_(line), line_no_(line_no), file_(file), params_(params) {}

  [[nodiscard]] char at(std::size_t i) const { return i < l_.text.size() ? l_.text[i] : '\0'; }
  [[nodiscard]] int col(std::size_t i) const { return l_.column[std::min(i, l_.text.size())]; }
  [[nodiscard]] std::size_t size() const { return l_.text.size(); }

  [[noreturn]] void fail(std::size_t i, const std::string& word, const std::string& message) const {
    throw InputError(file_, line_no_, col(i), word, message);
  }
  // The text of the value being read, from where it began (for messages).
  [[nodiscard]] std::string so_far(std::size_t begin, std::size_t end) const {
    return l_.text.substr(begin, std::min(end, size()) - begin);
  }

  // A value: number, parameter, [expression], unary function, or a sign and a value. `start`
  // is where the word (or expression) began, for messages.
  double real_value(std::size_t& i, std::size_t start, int depth) {
    if (depth > kMaxExpressionDepth) {
      fail(i, so_far(start, i + 1), "expression nested deeper than " + std::to_string(kMaxExpressionDepth) + " levels");
    }
    const char c = at(i);
    if (c == '[') return expression(i, start, depth + 1);
    if (c == '#') return parameter_value(i, start, depth + 1);
    // (depth counts brackets, parameter references, functions and signs: each a nesting)
    if (c == '+' || c == '-') {
      ++i;
      if (i >= size() || !(is_digit(at(i)) || at(i) == '.' || at(i) == '[' || at(i) == '#' || is_alpha(at(i)))) {
        fail(start, so_far(start, i), "a sign with no value after it");
      }
      const double v = real_value(i, start, depth + 1);
      return c == '-' ? -v : v;
    }
    if (is_alpha(c)) return function(i, start, depth + 1);
    if (is_digit(c) || c == '.') return number(i, start);
    if (i >= size()) fail(start, so_far(start, i), "a value is missing at the end of the line");
    fail(i, so_far(start, i + 1), std::string("expected a value, found '") + c + "'");
  }

  // A number: [digits][.digits]; the sign is read by real_value.
  double number(std::size_t& i, std::size_t start) {
    const std::size_t begin = i;
    bool digits = false;
    bool dot = false;
    for (; i < size(); ++i) {
      const char ch = at(i);
      if (is_digit(ch)) {
        digits = true;
      } else if (ch == '.') {
        if (dot) fail(i, so_far(start, i + 1), "malformed number (two decimal points)");
        dot = true;
      } else {
        break;
      }
    }
    if (!digits) fail(start, so_far(start, i), "malformed number");
    double value = 0;
    const std::string digits_text = l_.text.substr(begin, i - begin);
    const auto result = std::from_chars(digits_text.data(), digits_text.data() + digits_text.size(), value);
    if (result.ec != std::errc() || result.ptr != digits_text.data() + digits_text.size() || !std::isfinite(value)) {
      fail(start, so_far(start, i), "malformed number");
    }
    return value;
  }

  // #n, ##n, #[expr], #<name>
  double parameter_value(std::size_t& i, std::size_t start, int depth) {
    const std::size_t hash = i;
    ++i;
    if (at(i) == '<') {
      const std::string name = parameter_name(i, start);
      const std::optional<double> v = params_.named(name);
      if (!v) fail(hash, so_far(hash, i), "named parameter #<" + name + "> is not defined");
      return *v;
    }
    return params_.get(parameter_number(i, hash, start, depth));
  }

  // The number of a numbered parameter (after its '#'), checked to be an integer in range.
  int parameter_number(std::size_t& i, std::size_t hash, std::size_t start, int depth) {
    if (i >= size()) fail(hash, so_far(start, i), "'#' with no parameter number or name after it");
    const double n = real_value(i, start, depth);
    const double rounded = std::round(n);
    if (std::abs(n - rounded) > kIntegerTolerance || rounded < 1 || rounded > kMaxParameter) {
      fail(hash, so_far(hash, i),
           "parameter number must be an integer from 1 to " + std::to_string(kMaxParameter) + ", got " + std::to_string(n));
    }
    return static_cast<int>(rounded);
  }

  // <name> at i (after the '#'): lower case, blanks already removed (LinuxCNC ignores them).
  std::string parameter_name(std::size_t& i, std::size_t start) {
    const std::size_t open = i;
    const std::size_t close = l_.text.find('>', open);
    if (close == std::string::npos) fail(open, so_far(start, size()), "named parameter without a closing '>'");
    std::string name;
    for (std::size_t k = open + 1; k < close; ++k) {
      const char ch = at(k);
      if (ch == '<' || ch == '#' || ch == '[' || ch == ']') fail(k, so_far(start, k + 1), "character not allowed in a parameter name");
      name += lower(ch);
    }
    if (name.empty()) fail(open, so_far(start, close + 1), "empty parameter name");
    i = close + 1;
    return name;
  }

  // [ expression ]: binary operators by precedence, from the left at equal precedence.
  double expression(std::size_t& i, std::size_t start, int depth) {
    const std::size_t open = i;
    ++i;
    const double v = binary(i, start, depth, 0);
    if (at(i) != ']') {
      if (i >= size()) fail(open, so_far(open, i), "expression without a closing ']'");
      fail(i, so_far(start, i + 1), "expected an operator or ']' in the expression");
    }
    ++i;
    return v;
  }

  double binary(std::size_t& i, std::size_t start, int depth, int min_precedence) {
    double left = real_value(i, start, depth);
    while (true) {
      std::size_t after = i;
      const std::optional<Op> op = peek_operator(after);
      if (!op || precedence(*op) < min_precedence) return left;
      const std::size_t op_at = i;
      i = after;
      const double right = binary(i, start, depth, precedence(*op) + 1);
      left = apply(*op, left, right, op_at, start);
    }
  }

  // The operator at i, advancing `i` past it; nullopt if none (e.g. ']').
  std::optional<Op> peek_operator(std::size_t& i) const {
    const char c = at(i);
    const auto one = [&](Op op, std::size_t len) {
      i += len;
      return std::optional<Op>(op);
    };
    switch (c) {
      case '*': return at(i + 1) == '*' ? one(Op::kPower, 2) : one(Op::kTimes, 1);
      case '/': return one(Op::kDivide, 1);
      case '+': return one(Op::kPlus, 1);
      case '-': return one(Op::kMinus, 1);
      default: break;
    }
    if (!is_alpha(c)) return std::nullopt;
    const std::string two{upper(at(i)), upper(at(i + 1))};
    const std::string three = two + upper(at(i + 2));
    if (three == "MOD") return one(Op::kMod, 3);
    if (three == "AND") return one(Op::kAnd, 3);
    if (three == "XOR") return one(Op::kXor, 3);
    if (two == "EQ") return one(Op::kEq, 2);
    if (two == "NE") return one(Op::kNe, 2);
    if (two == "GT") return one(Op::kGt, 2);
    if (two == "GE") return one(Op::kGe, 2);
    if (two == "LT") return one(Op::kLt, 2);
    if (two == "LE") return one(Op::kLe, 2);
    if (two == "OR") return one(Op::kOr, 2);
    return std::nullopt;
  }

  // LinuxCNC's binary operations (interp_execute.cc, execute_binary1/2).
  double apply(Op op, double a, double b, std::size_t at_op, std::size_t start) const {
    const auto truth = [](bool t) { return t ? 1.0 : 0.0; };
    double r = 0;
    switch (op) {
      case Op::kPower:
        if (a < 0 && std::floor(b) != b) fail(at_op, so_far(start, at_op + 2), "a negative number raised to a non-integer power");
        r = std::pow(a, b);
        break;
      case Op::kTimes: r = a * b; break;
      case Op::kDivide:
        if (b == 0) fail(at_op, so_far(start, at_op + 1), "division by zero");
        r = a / b;
        break;
      case Op::kMod:
        // LinuxCNC: fmod, then a negative result is made positive by adding |b|
        if (b == 0) fail(at_op, so_far(start, at_op + 3), "MOD by zero");
        r = std::fmod(a, b);
        if (r < 0) r += std::abs(b);
        break;
      case Op::kPlus: r = a + b; break;
      case Op::kMinus: r = a - b; break;
      case Op::kEq: r = truth(std::abs(a - b) < kToleranceEqual); break;
      case Op::kNe: r = truth(!(std::abs(a - b) < kToleranceEqual)); break;
      case Op::kGt: r = truth(a > b); break;
      case Op::kGe: r = truth(a >= b); break;
      case Op::kLt: r = truth(a < b); break;
      case Op::kLe: r = truth(a <= b); break;
      case Op::kAnd: r = truth(a != 0 && b != 0); break;
      case Op::kOr: r = truth(a != 0 || b != 0); break;
      case Op::kXor: r = truth((a != 0) != (b != 0)); break;
    }
    if (!std::isfinite(r)) fail(at_op, so_far(start, at_op + 1), "the expression's value is not finite");
    return r;
  }

  // NAME[expr] (ATAN[y]/[x], EXISTS[#<name>]); angles in degrees, as in LinuxCNC.
  double function(std::size_t& i, std::size_t start, int depth) {
    const std::size_t begin = i;
    std::string name;
    while (is_alpha(at(i))) name += upper(at(i++));
    if (at(i) != '[') fail(begin, so_far(start, i), "'" + name + "' is not a function (ABS ACOS ASIN ATAN COS EXISTS EXP FIX FUP LN ROUND SIN SQRT TAN) followed by [");
    if (name == "EXISTS") {
      ++i;
      if (at(i) != '#' || at(i + 1) != '<') fail(i, so_far(start, i + 1), "EXISTS takes a named parameter, EXISTS[#<name>]");
      ++i;
      const std::string pname = parameter_name(i, start);
      if (at(i) != ']') fail(i, so_far(start, i + 1), "EXISTS takes one named parameter and ']'");
      ++i;
      return params_.named(pname) ? 1.0 : 0.0;
    }
    const double x = expression(i, start, depth);
    const auto domain = [&](bool ok, const char* what) {
      if (!ok) fail(begin, so_far(start, i), name + " of " + std::to_string(x) + ": " + what);
    };
    double r = 0;
    if (name == "ATAN") {
      if (at(i) != '/' || at(i + 1) != '[') fail(i, so_far(start, i + 1), "ATAN takes two values, ATAN[y]/[x]");
      ++i;
      const double xx = expression(i, start, depth);
      r = std::atan2(x, xx) / kDegree;
    } else if (name == "ABS") {
      r = std::abs(x);
    } else if (name == "ACOS") {
      domain(x >= -1 && x <= 1, "outside [-1, 1]");
      r = std::acos(x) / kDegree;
    } else if (name == "ASIN") {
      domain(x >= -1 && x <= 1, "outside [-1, 1]");
      r = std::asin(x) / kDegree;
    } else if (name == "COS") {
      r = std::cos(x * kDegree);
    } else if (name == "SIN") {
      r = std::sin(x * kDegree);
    } else if (name == "TAN") {
      r = std::tan(x * kDegree);
    } else if (name == "EXP") {
      r = std::exp(x);
    } else if (name == "LN") {
      domain(x > 0, "not positive");
      r = std::log(x);
    } else if (name == "SQRT") {
      domain(x >= 0, "negative");
      r = std::sqrt(x);
    } else if (name == "FIX") {
      r = std::floor(x);
    } else if (name == "FUP") {
      r = std::ceil(x);
    } else if (name == "ROUND") {
      r = std::round(x);  // halves away from zero, as LinuxCNC
    } else {
      fail(begin, so_far(start, i), "unknown function '" + name + "'");
    }
    if (!std::isfinite(r)) fail(begin, so_far(start, i), name + " of " + std::to_string(x) + " is not finite");
    return r;
  }

 private:
  const CompactLine& l_;
  int line_no_;
  const std::string& file_;
  const Params& params_;
};

}  // namespace

std::string_view strip_blanks(std::string_view s) {
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  return s;
}

CompactLine compact_line(std::string_view s, int line_no, const std::string& file) {
  CompactLine out;
  out.text.reserve(s.size());
  out.column.reserve(s.size() + 1);
  int c = 0;
  // c: the 1-based column of s[i] (UTF-8 continuation bytes share their lead's column)
  for (std::size_t i = 0; i < s.size(); ++i) {
    const unsigned char byte = static_cast<unsigned char>(s[i]);
    if (!is_continuation(byte)) ++c;
    const char ch = s[i];
    if (is_space(ch)) continue;
    if (ch == ';') break;
    if (ch == '(') {
      const std::size_t close = s.find(')', i + 1);
      const std::size_t nested = s.find('(', i + 1);
      if (close == std::string_view::npos) throw InputError(file, line_no, c, "(", "comment is not closed on this line");
      if (nested < close) {
        int nc = c;
        for (std::size_t j = i + 1; j <= nested; ++j) {
          if (!is_continuation(static_cast<unsigned char>(s[j]))) ++nc;
        }
        throw InputError(file, line_no, nc, "(", "nested comments are not allowed");
      }
      for (std::size_t j = i + 1; j <= close; ++j) {
        if (!is_continuation(static_cast<unsigned char>(s[j]))) ++c;
      }
      i = close;
      continue;
    }
    if (is_unicode_minus(s, i)) {
      out.text += '-';
      out.column.push_back(c);
      out.unicode_minus = true;
      i += 2;
      continue;
    }
    out.text += ch;
    out.column.push_back(c);
  }
  out.column.push_back(c + 1);
  return out;
}

std::optional<OWordHead> oword_head(const CompactLine& line, int line_no, const std::string& file) {
  const std::string& t = line.text;
  std::size_t i = 0;
  // an optional line number before the O-word
  if (!t.empty() && upper(t[0]) == 'N') {
    std::size_t k = 1;
    while (k < t.size() && (is_digit(t[k]) || t[k] == '.')) ++k;
    if (k > 1 && k < t.size() && upper(t[k]) == 'O') i = k;
  }
  if (i >= t.size() || upper(t[i]) != 'O') return std::nullopt;
  OWordHead head;
  head.column = line.column[i];
  std::size_t k = i + 1;
  const auto fail = [&](const std::string& message) {
    throw InputError(file, line_no, head.column, t.substr(i, std::min<std::size_t>(k - i + 1, t.size() - i)), message);
  };
  if (k < t.size() && t[k] == '<') {
    const std::size_t close = t.find('>', k);
    if (close == std::string::npos) fail("O-word label without a closing '>'");
    head.label = "<";
    for (std::size_t j = k + 1; j < close; ++j) head.label += lower(t[j]);
    head.label += ">";
    if (head.label == "<>") fail("empty O-word label");
    k = close + 1;
  } else {
    const std::size_t begin = k;
    while (k < t.size() && is_digit(t[k])) ++k;
    if (k == begin) fail("an O-word needs a number or a <name> as its label");
    // o0100 and o100 are one label
    std::size_t first = begin;
    while (first + 1 < k && t[first] == '0') ++first;
    head.label = t.substr(first, k - first);
  }
  const std::size_t kw = k;
  while (k < t.size() && is_alpha(t[k])) head.keyword += lower(t[k++]);
  if (head.keyword.empty()) {
    k = kw;
    fail("an O-word needs a keyword (sub, endsub, call, if, elseif, else, endif, while, endwhile, do, repeat, endrepeat, break, continue, return)");
  }
  head.rest = k;
  return head;
}

Block lex_block(const CompactLine& line, int line_no, const std::string& file, const Params& params) {
  Reader r(line, line_no, file, params);
  Block block;
  block.line = line_no;
  block.unicode_minus = line.unicode_minus;
  const std::string& t = line.text;
  std::size_t i = 0;
  while (i < t.size()) {
    const char ch = t[i];
    // a parameter assignment: #n = value, #<name> = value
    if (ch == '#') {
      const std::size_t begin = i;
      Assignment a;
      a.column = r.col(i);
      ++i;
      if (r.at(i) == '<') {
        a.name = r.parameter_name(i, begin);
      } else {
        a.number = r.parameter_number(i, begin, begin, 0);
      }
      a.text = r.so_far(begin, i);
      if (r.at(i) != '=') r.fail(begin, a.text, "a parameter at the start of a word must be assigned (#1 = value)");
      ++i;
      a.value = r.real_value(i, begin, 0);
      block.assignments.push_back(std::move(a));
      continue;
    }
    // a word: a letter, or '@' / '^' (LinuxCNC's polar radius and angle)
    if (is_alpha(ch) || ch == '@' || ch == '^') {
      Word word;
      word.letter = upper(ch);
      word.column = r.col(i);
      const std::size_t begin = i;
      ++i;
      if (word.letter == 'O') r.fail(begin, r.so_far(begin, i + 1), "an O-word must be the first word of its line");
      const char next = r.at(i);
      const bool has_value = next == '[' || next == '#' || next == '+' || next == '-' || next == '.' || is_digit(next) ||
                             (is_alpha(next) && r.at(i + 1) != '\0' && is_alpha(r.at(i + 1)));
      if (!has_value) r.fail(begin, std::string(1, word.letter) + (next == '=' ? "=" : ""), std::string("word '") + word.letter + "' has no number");
      word.value = r.real_value(i, begin, 0);
      word.text = t.substr(begin, i - begin);
      word.text.front() = word.letter;
      block.words.push_back(std::move(word));
      continue;
    }
    const std::string what(1, ch);
    if (ch == '%') r.fail(i, what, "'%' must stand alone on its line (tape marker)");
    if (ch == '/') r.fail(i, what, "block delete '/' must be the first character of the line");
    if (ch == '[' || ch == ']') r.fail(i, what, "an expression must be the value of a word (X[1+2]) or of a parameter (#1=[..])");
    if (ch == '-' || ch == '+') r.fail(i, line.unicode_minus && ch == '-' ? "\u2212" : what, "a sign must follow a word letter");
    if (static_cast<unsigned char>(ch) >= 0x80) {
      std::size_t len = 1;
      while (i + len < t.size() && is_continuation(static_cast<unsigned char>(t[i + len]))) ++len;
      r.fail(i, t.substr(i, len), "unexpected character");
    }
    r.fail(i, what, "unexpected character");
  }
  return block;
}

std::vector<double> oword_values(const CompactLine& line, const OWordHead& head, int line_no, const std::string& file,
                                 const Params& params, std::size_t min_count, std::size_t max_count) {
  Reader r(line, line_no, file, params);
  std::vector<double> values;
  std::size_t i = head.rest;
  while (i < line.text.size()) {
    if (r.at(i) != '[') {
      r.fail(i, r.so_far(i, i + 1),
             "after " + head.name() + " " + head.keyword + " only bracketed expressions may follow, e.g. [#1 + 2]");
    }
    if (values.size() == max_count) {
      r.fail(i, r.so_far(i, i + 1),
             head.name() + " " + head.keyword + " takes at most " + std::to_string(max_count) + " value" + (max_count == 1 ? "" : "s"));
    }
    values.push_back(r.real_value(i, i, 0));
  }
  if (values.size() < min_count) {
    throw InputError(file, line_no, head.column, head.name(), head.keyword + " needs a condition or count in [ ], e.g. " + head.name() + " " + head.keyword + " [#1 LT 10]");
  }
  return values;
}

}  // namespace blendbench::gcode_detail
