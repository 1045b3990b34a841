#include "blendbench/core/format.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

namespace blendbench {
namespace {

std::string with_unit(double value, const char* unit) { return format_value(value) + ' ' + unit; }

}  // namespace

std::string format_value(double value, int digits) {
  if (std::isnan(value)) return "nan";  // never "-nan"
  if (value == 0) value = 0;            // never "-0"
  // %g with `digits` significant digits, as a stream prints it, without building a stream (the
  // corner fits format their notes on the hot path)
  std::array<char, 64> text{};
  const auto [end, error] = std::to_chars(text.data(), text.data() + text.size(), value, std::chars_format::general,
                                          std::clamp(digits, 1, 40));
  return error == std::errc() ? std::string(text.data(), end) : std::string("?");
}

std::string format_mm(double metres) { return with_unit(metres * 1e3, "mm"); }
std::string format_deg(double radians) { return with_unit(radians * 180.0 / std::numbers::pi, "deg"); }
std::string format_per_mm(double per_metre) { return with_unit(per_metre * 1e-3, "1/mm"); }
std::string format_mm_per_s(double metres_per_second) { return with_unit(metres_per_second * 1e3, "mm/s"); }

}  // namespace blendbench
