#pragma once
// Golden-section and Brent searches for the minimum of a unimodal function on a bracket, used
// after a coarse scan has located the neighbourhood of the extremum.

#include <cmath>
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

// Minimises f on [lo, hi] from the point x (f(x) = fx, lo <= x <= hi) by Brent's method:
// parabolic steps through the three best points while they shrink the bracket fast enough,
// golden-section steps otherwise, until the bracket is narrower than `width` (or
// `max_iterations`). Converges superlinearly near a smooth minimum. Returns {x, f(x)} of the
// best point evaluated (never worse than the start).
template <class F>
std::pair<double, double> brent_minimum(const F& f, double lo, double hi, double x, double fx, double width,
                                        int max_iterations = 60) {
  constexpr double kGoldenStep = 0.3819660112501051;  // 1 - 1 / golden ratio
  double w = x, v = x, fw = fx, fv = fx;
  double step = 0, last = 0;  // the last step and the one before it
  for (int it = 0; it < max_iterations && hi - lo > width; ++it) {
    const double mid = 0.5 * (lo + hi);
    const double tol = 0.25 * width;
    double d = 0;
    bool parabolic = false;
    if (std::abs(last) > tol) {
      // the parabola through (x, fx), (w, fw), (v, fv): its vertex x + p / q
      const double r = (x - w) * (fx - fv);
      double q = (x - v) * (fx - fw);
      double p = (x - v) * q - (x - w) * r;
      q = 2 * (q - r);
      if (q > 0) p = -p;
      q = std::abs(q);
      // accepted when it falls inside the bracket and moves less than half the step before last
      if (std::abs(p) < std::abs(0.5 * q * last) && p > q * (lo - x) && p < q * (hi - x)) {
        last = step;
        d = p / q;
        parabolic = true;
        if (x + d - lo < 2 * tol || hi - (x + d) < 2 * tol) d = x < mid ? tol : -tol;
      }
    }
    if (!parabolic) {
      last = (x < mid ? hi : lo) - x;
      d = kGoldenStep * last;
    }
    step = d;
    const double u = std::abs(d) >= tol ? x + d : x + (d > 0 ? tol : -tol);
    const double fu = f(u);
    if (fu <= fx) {
      (u < x ? hi : lo) = x;
      v = w;
      fv = fw;
      w = x;
      fw = fx;
      x = u;
      fx = fu;
    } else {
      (u < x ? lo : hi) = u;
      if (fu <= fw || w == x) {
        v = w;
        fv = fw;
        w = u;
        fw = fu;
      } else if (fu <= fv || v == x || v == w) {
        v = u;
        fv = fu;
      }
    }
  }
  return {x, fx};
}

}  // namespace blendbench
