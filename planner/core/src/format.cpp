#include "blendbench/core/format.hpp"

#include <cmath>
#include <limits>
#include <numbers>
#include <sstream>

namespace blendbench {
namespace {

std::string with_unit(double value, const char* unit) { return format_value(value) + ' ' + unit; }

}  // namespace

std::string format_value(double value, int digits) {
  std::ostringstream out;
  out.precision(digits);
  if (std::isnan(value)) value = std::numeric_limits<double>::quiet_NaN();  // never "-nan"
  if (value == 0) value = 0;                                                 // never "-0"
  out << value;
  return out.str();
}

std::string format_mm(double metres) { return with_unit(metres * 1e3, "mm"); }
std::string format_deg(double radians) { return with_unit(radians * 180.0 / std::numbers::pi, "deg"); }
std::string format_per_mm(double per_metre) { return with_unit(per_metre * 1e-3, "1/mm"); }
std::string format_mm_per_s(double metres_per_second) { return with_unit(metres_per_second * 1e3, "mm/s"); }

}  // namespace blendbench
