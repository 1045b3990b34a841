#include "blendbench/app/smoothing_flags.hpp"

#include <cmath>

#include "blendbench/core/input_error.hpp"

namespace blendbench {

void check_smoothing_flags(const SmoothingFlags& flags) {
  if (!flags.method.empty() && !smoothing_method_from_string(flags.method)) {
    throw InputError("", 0, 0, "--smoothing", "unknown method '" + flags.method + "' (none, clothoid_points, g2_fit)");
  }
  if (flags.tolerance_mm && !(*flags.tolerance_mm > 0 && std::isfinite(*flags.tolerance_mm))) {
    throw InputError("", 0, 0, "--smoothing-tolerance", "must be a positive number of mm");
  }
}

Smoothing apply_smoothing_flags(const SmoothingFlags& flags, Smoothing smoothing) {
  check_smoothing_flags(flags);
  if (!flags.method.empty()) smoothing.method = *smoothing_method_from_string(flags.method);
  if (flags.tolerance_mm) {
    if (smoothing.method != SmoothingMethod::kG2Fit) {
      throw InputError("", 0, 0, "--smoothing-tolerance",
                       "sets g2_fit's tolerance, but the smoothing is " + std::string(to_string(smoothing.method)) +
                           " (add --smoothing g2_fit)");
    }
    smoothing.tolerance = *flags.tolerance_mm * 1e-3;
  }
  return smoothing;
}

Smoothing apply_smoothing_flags_to_variant(const SmoothingFlags& flags, Smoothing smoothing) {
  check_smoothing_flags(flags);
  if (!flags.method.empty()) smoothing.method = *smoothing_method_from_string(flags.method);
  if (flags.tolerance_mm && smoothing.method == SmoothingMethod::kG2Fit) smoothing.tolerance = *flags.tolerance_mm * 1e-3;
  return smoothing;
}

}  // namespace blendbench
