#pragma once
// Golden-section search for the minimum of a unimodal function on a bracket, used after a
// coarse scan has located the neighbourhood of the extremum.

#include <utility>

namespace blendbench {

// Minimises f on [lo, hi] until the bracket is narrower than `width` or `max_iterations`
// steps were taken. Returns {x, f(x)} of the best point evaluated.
template <class F>
std::pair<double, double> golden_minimum(const F& f, double lo, double hi, double width, int max_iterations = 80) {
  constexpr double kGolden = 0.6180339887498949;
  double x1 = hi - kGolden * (hi - lo);
  double x2 = lo + kGolden * (hi - lo);
  double f1 = f(x1);
  double f2 = f(x2);
  for (int it = 0; it < max_iterations && hi - lo > width; ++it) {
    if (f1 > f2) {
      lo = x1;
      x1 = x2;
      f1 = f2;
      x2 = lo + kGolden * (hi - lo);
      f2 = f(x2);
    } else {
      hi = x2;
      x2 = x1;
      f2 = f1;
      x1 = hi - kGolden * (hi - lo);
      f1 = f(x1);
    }
  }
  return f1 <= f2 ? std::pair{x1, f1} : std::pair{x2, f2};
}

}  // namespace blendbench
