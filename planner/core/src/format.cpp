#include "blendbench/core/format.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <numbers>
#include <span>
#include <string_view>

namespace blendbench {
namespace {

std::string with_unit(double value, const char* unit) { return format_value(value) + ' ' + unit; }

// format_value's text written into `text`: its length, 0 when it does not fit
std::size_t write_value(std::span<char> text, double value, int digits) {
  if (std::isnan(value)) value = std::numeric_limits<double>::quiet_NaN();  // never "-nan"
  if (value == 0) value = 0;                                                 // never "-0"
  // %g with `digits` significant digits, as a stream prints it, without building a stream (the
  // corner fits format their notes on the hot path)
  const auto [end, error] = std::to_chars(text.data(), text.data() + text.size(), value, std::chars_format::general,
                                          std::clamp(digits, 1, 40));
  return error == std::errc() ? static_cast<std::size_t>(end - text.data()) : 0;
}

}  // namespace

std::string format_value(double value, int digits) {
  std::array<char, 64> text{};
  const std::size_t n = write_value(text, value, digits);
  return n > 0 ? std::string(text.data(), n) : std::string("?");
}

void append_mm(std::string& out, double metres) {
  std::array<char, 64> text{};
  const std::size_t n = write_value(text, metres * 1e3, 6);
  out.append(n > 0 ? std::string_view(text.data(), n) : std::string_view("?"));
  out += " mm";
}

std::string lengths_note(std::string_view head, double first, std::string_view link, double second,
                         std::string_view why) {
  std::string note;
  note.reserve(head.size() + link.size() + why.size() + 40);
  note += head;
  append_mm(note, first);
  note += link;
  append_mm(note, second);
  note += ": ";
  note += why;
  return note;
}

namespace {

// The length of the well-formed UTF-8 sequence of two to four bytes that starts at text[i], or 0:
// the length from the lead byte, continuation bytes 10xxxxxx, no overlong form, no surrogate, at
// most U+10FFFF (RFC 3629).
std::size_t utf8_length(std::string_view text, std::size_t i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char c = byte(i);
  const std::size_t len = c >= 0xC2 && c <= 0xDF ? 2 : c >= 0xE0 && c <= 0xEF ? 3 : c >= 0xF0 && c <= 0xF4 ? 4 : 0;
  bool ok = len > 0 && i + len <= text.size();
  for (std::size_t k = 1; ok && k < len; ++k) ok = (byte(i + k) & 0xC0) == 0x80;
  if (ok && len == 3) {
    const unsigned char c1 = byte(i + 1);
    ok = !(c == 0xE0 && c1 < 0xA0) && !(c == 0xED && c1 >= 0xA0);
  }
  if (ok && len == 4) {
    const unsigned char c1 = byte(i + 1);
    ok = !(c == 0xF0 && c1 < 0x90) && !(c == 0xF4 && c1 >= 0x90);
  }
  return ok ? len : 0;
}

}  // namespace

bool is_utf8(std::string_view text) {
  for (std::size_t i = 0; i < text.size();) {
    if (static_cast<unsigned char>(text[i]) < 0x80) {
      ++i;
      continue;
    }
    const std::size_t len = utf8_length(text, i);
    if (len == 0) return false;
    i += len;
  }
  return true;
}

std::string printable(std::string_view text) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  out.reserve(text.size());
  const auto escape = [&](unsigned char c) {
    out += "\\x";
    out += kHex[c >> 4];
    out += kHex[c & 0xF];
  };
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(text[i]); };
  for (std::size_t i = 0; i < text.size();) {
    const unsigned char c = byte(i);
    if (c < 0x80) {
      // ASCII: the controls escaped, "\n" and "\t" by name
      if (c == '\n') {
        out += "\\n";
      } else if (c == '\t') {
        out += "\\t";
      } else if (c < 0x20 || c == 0x7F) {
        escape(c);
      } else {
        out += static_cast<char>(c);
      }
      ++i;
      continue;
    }
    // a well-formed UTF-8 sequence is kept; the C1 controls U+0080-U+009F escaped
    const std::size_t len = utf8_length(text, i);
    bool ok = len > 0;
    if (ok && len == 2 && c == 0xC2 && byte(i + 1) < 0xA0) ok = false;  // C1 control
    if (!ok) {
      escape(c);
      ++i;
      continue;
    }
    out.append(text.substr(i, len));
    i += len;
  }
  return out;
}

std::string format_mm(double metres) { return with_unit(metres * 1e3, "mm"); }
std::string format_deg(double radians) { return with_unit(radians * 180.0 / std::numbers::pi, "deg"); }
std::string format_per_mm(double per_metre) { return with_unit(per_metre * 1e-3, "1/mm"); }
std::string format_mm_per_s(double metres_per_second) { return with_unit(metres_per_second * 1e3, "mm/s"); }

}  // namespace blendbench
