// Tests of the clothoid Taylor recurrence (planner/geometry/include/blendbench/geometry/phase_series.hpp):
// two series summed side by side in a 2-array take, lane by lane, the scalar recurrence's values
// to the last bit, and the coefficients are those of exp(i (b t + g t^2 / 2)).

#include "blendbench/geometry/phase_series.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>

#include "support/property.hpp"

namespace blendbench {
namespace {

TEST(PhaseSeries, TwoSeriesSideBySideAreEachOnItsOwnToTheBit) {
  const std::uint64_t seed = 53;
  auto rng = test::make_rng(seed);
  const int cases = test::property_cases(5000);
  for (int c = 0; c < cases; ++c) {
    // the panels' range of the moments and the fillet table: |b| + |g| up to a few radians
    const double b0 = test::uniform(rng, -3, 3);
    const double g0 = test::uniform(rng, -3, 3);
    const double b1 = test::uniform(rng, -3, 3);
    const double g1 = test::uniform(rng, -3, 3);
    series::PhaseTaylor one{.b = b0, .g = g0};
    series::PhaseTaylor two{.b = b1, .g = g1};
    series::BasicPhaseTaylor<Eigen::Array2d> both{.b = Eigen::Array2d(b0, b1), .g = Eigen::Array2d(g0, g1)};
    for (std::size_t n = 0; n + 2 < series::kInverse.size(); n += 2) {
      one.step_two(n);
      two.step_two(n);
      both.step_two(n);
      // EXPECT_EQ on doubles: the same numbers (not merely close ones)
      ASSERT_EQ(both.re[0], one.re) << test::seed_text(seed) << " case " << c << " n " << n;
      ASSERT_EQ(both.im[0], one.im) << test::seed_text(seed) << " case " << c << " n " << n;
      ASSERT_EQ(both.prev_re[0], one.prev_re) << test::seed_text(seed) << " case " << c << " n " << n;
      ASSERT_EQ(both.prev_im[0], one.prev_im) << test::seed_text(seed) << " case " << c << " n " << n;
      ASSERT_EQ(both.re[1], two.re) << test::seed_text(seed) << " case " << c << " n " << n;
      ASSERT_EQ(both.im[1], two.im) << test::seed_text(seed) << " case " << c << " n " << n;
      ASSERT_EQ(both.prev_re[1], two.prev_re) << test::seed_text(seed) << " case " << c << " n " << n;
      ASSERT_EQ(both.prev_im[1], two.prev_im) << test::seed_text(seed) << " case " << c << " n " << n;
      const Eigen::Array2d size = both.size();
      ASSERT_EQ(size[0] < 1e-18, one.below(1e-18)) << test::seed_text(seed) << " case " << c << " n " << n;
      ASSERT_EQ(size[1] < 1e-18, two.below(1e-18)) << test::seed_text(seed) << " case " << c << " n " << n;
    }
  }
}

TEST(PhaseSeries, TheCoefficientsSumToTheExponential) {
  // sum_n e_n t^n = exp(i (b t + g t^2 / 2)) at |t| <= 1, to rounding
  const std::uint64_t seed = 59;
  auto rng = test::make_rng(seed);
  const int cases = test::property_cases(2000);
  for (int c = 0; c < cases; ++c) {
    const double b = test::uniform(rng, -2, 2);
    const double g = test::uniform(rng, -2, 2);
    const double t = test::uniform(rng, -1, 1);
    series::PhaseTaylor e{.b = b, .g = g};
    std::complex<double> sum(1.0, 0.0);  // e_0
    double t_pow = 1;                    // t^n
    for (std::size_t n = 0; n + 2 < series::kInverse.size(); n += 2) {
      e.step_two(n);
      sum += std::complex<double>(e.prev_re, e.prev_im) * (t_pow * t) +
             std::complex<double>(e.re, e.im) * (t_pow * t * t);
      t_pow *= t * t;
    }
    const std::complex<double> exact = std::exp(std::complex<double>(0.0, b * t + 0.5 * g * t * t));
    EXPECT_LE(std::abs(sum - exact), 1e-14) << test::seed_text(seed) << " case " << c << " b " << b << " g " << g;
  }
}

}  // namespace
}  // namespace blendbench
