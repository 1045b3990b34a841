#pragma once
// Taylor series of exp(i phi(t)) with a quadratic phase phi(t) = b t + g t^2 / 2: the kernel
// of every clothoid integral in the planner (segment positions, biclothoid moments and panels).
// Shared by the geometry (segment.cpp) and the biclothoid sources of the corner methods
// (biclothoid_curve.cpp, biclothoid_deviation.cpp).

#include <array>
#include <cmath>
#include <cstddef>

namespace blendbench::series {

// kInverse[n] = 1 / n (kInverse[0] unused): the recurrence divides by n + 1 and n + 2.
inline constexpr std::array<double, 48> kInverse = [] {
  std::array<double, 48> inv{};
  for (std::size_t n = 1; n < inv.size(); ++n) inv[n] = 1.0 / static_cast<double>(n);
  return inv;
}();

// The coefficients e_n of exp(i phi(t)) = sum e_n t^n obey, from f' = i (b + g t) f,
//   e_{n+1} = i (b e_n + g e_{n-1}) / (n + 1).
// Two steps at once, both from (e_n, e_{n-1}), halve the chain of dependent operations:
//   e_{n+2} = [(-b^2 / (n+1) + i g) e_n - b g / (n+1) e_{n-1}] / (n + 2).
// Kept in scalars: an Eigen 2-vector or std::complex built from two scalars and read back as a
// pair goes through memory and stalls store forwarding once per coefficient.
struct PhaseTaylor {
  double b;
  double g;
  double re = 1;  // e_n, n even (e_0 = 1)
  double im = 0;
  double prev_re = 0;  // e_{n-1}
  double prev_im = 0;

  // From (e_{n-1}, e_n) to (e_{n+1}, e_{n+2}).
  void step_two(std::size_t n) noexcept {
    const double p = kInverse[n + 1];
    const double q = kInverse[n + 2];
    const double c1 = b * p;
    const double c2 = g * p;
    const double c3 = -b * c1 * q;
    const double c4 = g * q;
    const double c5 = -b * c2 * q;
    const double odd_re = -(c1 * im + c2 * prev_im);
    const double odd_im = c1 * re + c2 * prev_re;
    const double even_re = (c3 * re + c5 * prev_re) - c4 * im;
    const double even_im = (c3 * im + c5 * prev_im) + c4 * re;
    prev_re = odd_re;
    prev_im = odd_im;
    re = even_re;
    im = even_im;
  }

  // Both current coefficients below `tolerance` (1-norm of the parts).
  [[nodiscard]] bool below(double tolerance) const noexcept {
    return std::abs(re) + std::abs(im) + std::abs(prev_re) + std::abs(prev_im) < tolerance;
  }
};

}  // namespace blendbench::series
