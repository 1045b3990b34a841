#pragma once
// Taylor series of exp(i phi(t)) with a quadratic phase phi(t) = b t + g t^2 / 2: the kernel
// of every clothoid integral in the planner (segment positions, biclothoid moments and panels).
// Shared by the geometry (segment.cpp) and the biclothoid sources of the corner methods
// (biclothoid_curve.cpp, biclothoid_deviation.cpp).

#include <array>
#include <cmath>
#include <cstddef>
#include <type_traits>

#include <Eigen/Core>

namespace blendbench::series {

// kInverse[n] = 1 / n (kInverse[0] unused): the recurrence divides by n + 1 and n + 2.
inline constexpr std::array<double, 48> kInverse = [] {
  std::array<double, 48> inv{};
  for (std::size_t n = 1; n < inv.size(); ++n) inv[n] = 1.0 / static_cast<double>(n);
  return inv;
}();

// The magnitude of a coefficient part: of a scalar, or lane by lane of an Eigen array (series
// summed side by side, one in each lane).
inline double magnitude(double x) noexcept { return std::abs(x); }
template <class Derived>
auto magnitude(const Eigen::ArrayBase<Derived>& x) {
  return x.abs();
}

// A number of T's kind with every lane v: the scalar v, or an array filled with it.
template <class T>
T filled(double v) {
  if constexpr (std::is_same_v<T, double>) {
    return v;
  } else {
    return T::Constant(v);
  }
}

// The coefficients e_n of exp(i phi(t)) = sum e_n t^n obey, from f' = i (b + g t) f,
//   e_{n+1} = i (b e_n + g e_{n-1}) / (n + 1).
// Two steps at once, both from (e_n, e_{n-1}), halve the chain of dependent operations:
//   e_{n+2} = [(-b^2 / (n+1) + i g) e_n - b g / (n+1) e_{n-1}] / (n + 2).
// Kept in scalars: an Eigen 2-vector or std::complex built from two scalars and read back as a
// pair goes through memory and stalls store forwarding once per coefficient. T is double for
// one series, or an Eigen array for as many series side by side, one in each lane (the chain is
// latency-bound, so two take about as long as one); each lane takes the operations of the scalar
// recurrence in the same order, so its coefficients are the scalar ones to the last bit.
template <class T>
struct BasicPhaseTaylor {
  T b;
  T g;
  T re = filled<T>(1);  // e_n, n even (e_0 = 1)
  T im = filled<T>(0);
  T prev_re = filled<T>(0);  // e_{n-1}
  T prev_im = filled<T>(0);

  // From (e_{n-1}, e_n) to (e_{n+1}, e_{n+2}).
  void step_two(std::size_t n) noexcept {
    const double p = kInverse[n + 1];
    const double q = kInverse[n + 2];
    const T c1 = b * p;
    const T c2 = g * p;
    const T c3 = -b * c1 * q;
    const T c4 = g * q;
    const T c5 = -b * c2 * q;
    const T odd_re = -(c1 * im + c2 * prev_im);
    const T odd_im = c1 * re + c2 * prev_re;
    const T even_re = (c3 * re + c5 * prev_re) - c4 * im;
    const T even_im = (c3 * im + c5 * prev_im) + c4 * re;
    prev_re = odd_re;
    prev_im = odd_im;
    re = even_re;
    im = even_im;
  }

  // The 1-norm of the current coefficients' parts (lane by lane).
  [[nodiscard]] T size() const noexcept {
    return magnitude(re) + magnitude(im) + magnitude(prev_re) + magnitude(prev_im);
  }

  // One series: both current coefficients below `tolerance` (1-norm of the parts).
  [[nodiscard]] bool below(double tolerance) const noexcept
    requires std::is_same_v<T, double>
  {
    return size() < tolerance;
  }
};
using PhaseTaylor = BasicPhaseTaylor<double>;

// Lane i of series summed side by side, as a series of its own (to go on alone where the other
// lane stopped).
template <class T>
PhaseTaylor lane(const BasicPhaseTaylor<T>& both, Eigen::Index i) {
  return {.b = both.b[i], .g = both.g[i], .re = both.re[i], .im = both.im[i], .prev_re = both.prev_re[i],
          .prev_im = both.prev_im[i]};
}

}  // namespace blendbench::series
