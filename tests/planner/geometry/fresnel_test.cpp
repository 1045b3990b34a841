#include "blendbench/geometry/fresnel.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <numbers>

#include "support/property.hpp"

namespace blendbench {
namespace {

// fresnel.hpp promises 1e-14 relative; the brief asks for 1e-12.
constexpr double kRelTol = 1e-14;

using Long = long double;

// 20-point Gauss-Legendre nodes and weights on [-1, 1], computed here in long double by Newton's
// method on P_20 (independent of any table in the planner).
struct GaussLegendre {
  std::array<Long, 20> x{};
  std::array<Long, 20> w{};
  GaussLegendre() {
    constexpr int n = 20;
    for (int i = 0; i < n; ++i) {
      Long z = std::cos(std::numbers::pi_v<Long> * (i + 0.75L) / (n + 0.5L));
      Long dp = 0;
      for (int it = 0; it < 100; ++it) {
        Long p0 = 1;
        Long p1 = z;
        for (int k = 2; k <= n; ++k) {
          const Long p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
          p0 = p1;
          p1 = p2;
        }
        dp = n * (z * p1 - p0) / (z * z - 1);
        const Long dz = p1 / dp;
        z -= dz;
        if (std::abs(dz) < 1e-22L) break;
      }
      x[static_cast<std::size_t>(i)] = z;
      w[static_cast<std::size_t>(i)] = 2 / ((1 - z * z) * dp * dp);
    }
  }
};

// C(x), S(x) by composite long-double Gauss-Legendre with the phase pi t^2 / 2 changing by at
// most 0.25 rad per panel.
std::array<Long, 2> reference(Long x) {
  static const GaussLegendre gl;
  const Long ax = std::abs(x);
  const Long phase = std::numbers::pi_v<Long> * ax * ax / 2;
  const int panels = std::max(1, static_cast<int>(std::ceil(phase / 0.25L)) + static_cast<int>(std::ceil(ax * 4)));
  const Long h = ax / panels;
  Long c = 0;
  Long s = 0;
  for (int p = 0; p < panels; ++p) {
    const Long mid = (p + 0.5L) * h;
    for (std::size_t i = 0; i < 20; ++i) {
      const Long t = mid + 0.5L * h * gl.x[i];
      const Long arg = std::numbers::pi_v<Long> * t * t / 2;
      c += gl.w[i] * std::cos(arg);
      s += gl.w[i] * std::sin(arg);
    }
  }
  const Long sign = x < 0 ? -1 : 1;
  return {sign * c * h / 2, sign * s * h / 2};
}

TEST(Fresnel, MatchesLongDoubleQuadratureOverTheRangeUsed) {
  // both branches (series up to 1.6, continued fraction beyond) and the switch between them
  for (double x = -6.0; x <= 6.0; x += 0.0625) {
    const FresnelCS f = fresnel(x);
    const auto ref = reference(static_cast<Long>(x));
    if (x == 0) {
      EXPECT_EQ(f.c, 0.0);
      EXPECT_EQ(f.s, 0.0);
      continue;
    }
    EXPECT_NEAR(f.c, static_cast<double>(ref[0]), kRelTol * std::abs(static_cast<double>(ref[0]))) << "x=" << x;
    EXPECT_NEAR(f.s, static_cast<double>(ref[1]), kRelTol * std::abs(static_cast<double>(ref[1]))) << "x=" << x;
  }
  for (const double x : {1.5999999, 1.6, 1.6000001, 1e-8, 1e-3, 0.3, 9.75, 17.3, 31.0}) {
    const FresnelCS f = fresnel(x);
    const auto ref = reference(static_cast<Long>(x));
    EXPECT_NEAR(f.c, static_cast<double>(ref[0]), kRelTol * static_cast<double>(ref[0])) << "x=" << x;
    EXPECT_NEAR(f.s, static_cast<double>(ref[1]), kRelTol * static_cast<double>(ref[1])) << "x=" << x;
  }
}

TEST(Fresnel, SmallArgumentsMatchTheLeadingTerms) {
  // C = x - pi^2 x^5 / 40 + ..., S = pi x^3 / 6 - ...: relative accuracy must survive x -> 0
  for (const double x : {1e-300, 1e-100, 1e-20, 1e-6}) {
    const FresnelCS f = fresnel(x);
    EXPECT_DOUBLE_EQ(f.c, x);
    EXPECT_NEAR(f.s, std::numbers::pi * x * x * x / 6, 1e-15 * std::numbers::pi * x * x * x / 6) << x;
  }
}

TEST(Fresnel, LargeArgumentsFollowTheAsymptoticForm) {
  // C = 1/2 + sin(pi x^2/2) / (pi x) + O(x^-3), S = 1/2 - cos(pi x^2/2) / (pi x) + O(x^-3)
  for (const double x : {1e3, 12345.678, 1e6}) {
    const FresnelCS f = fresnel(x);
    const double phase = std::fmod(x * x, 4.0) * std::numbers::pi / 2;
    EXPECT_NEAR(f.c, 0.5 + std::sin(phase) / (std::numbers::pi * x), 1.0 / (x * x * x)) << x;
    EXPECT_NEAR(f.s, 0.5 - std::cos(phase) / (std::numbers::pi * x), 1.0 / (x * x * x)) << x;
  }
  const FresnelCS inf = fresnel(std::numeric_limits<double>::infinity());
  EXPECT_EQ(inf.c, 0.5);
  EXPECT_EQ(inf.s, 0.5);
}

TEST(Fresnel, IsOddAndItsDerivativeIsTheIntegrand) {
  const std::uint64_t seed = 7;
  auto rng = test::make_rng(seed);
  const int cases = test::property_cases(500);
  for (int i = 0; i < cases; ++i) {
    const double x = test::uniform(rng, -8.0, 8.0);
    const FresnelCS f = fresnel(x);
    const FresnelCS g = fresnel(-x);
    EXPECT_EQ(f.c, -g.c) << test::seed_text(seed) << " x=" << x;
    EXPECT_EQ(f.s, -g.s) << test::seed_text(seed) << " x=" << x;
    // central difference of order h^2: error ~ (pi x)^2 h^2 / 6
    const double h = 1e-5;
    const FresnelCS up = fresnel(x + h);
    const FresnelCS down = fresnel(x - h);
    const double arg = std::numbers::pi * x * x / 2;
    EXPECT_NEAR((up.c - down.c) / (2 * h), std::cos(arg), 1e-7 * (1 + x * x)) << test::seed_text(seed) << " x=" << x;
    EXPECT_NEAR((up.s - down.s) / (2 * h), std::sin(arg), 1e-7 * (1 + x * x)) << test::seed_text(seed) << " x=" << x;
  }
}

TEST(Fresnel, NanPropagates) {
  const FresnelCS f = fresnel(std::numeric_limits<double>::quiet_NaN());
  EXPECT_TRUE(std::isnan(f.c));
  EXPECT_TRUE(std::isnan(f.s));
}

}  // namespace
}  // namespace blendbench
