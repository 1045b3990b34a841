#pragma once
// Fresnel integrals (seed 002 (Makino) eq. 1-2, appendix):
//   C(x) = int_0^x cos(pi t^2 / 2) dt,   S(x) = int_0^x sin(pi t^2 / 2) dt.
//
// Method (derived here, see fresnel.cpp): with t = pi x^2 / 2,
//   C(x) + i S(x) = x sum_m (i t)^m / (m! (2m + 1))                        for |x| <= 1.6,
// the power series of the integrand integrated term by term (the series of seed 002's appendix in
// one complex sum). For |x| > 1.6 the relation to the complementary error function,
//   C + i S = (1 + i)/2 erf(z),  z = (1 - i) sqrt(pi) x / 2,  z^2 = -i pi x^2 / 2,
// with the even part of Laplace's continued fraction for erfc gives
//   C(x) + i S(x) = (1 + i)/2 - (x/2) exp(i pi x^2 / 2) / D(w),  w = -i pi x^2 / 2,
//   D(w) = w + 1/2 - (1*1/2) / (w + 5/2 - (2*3/2) / (w + 9/2 - (3*5/2) / (w + 13/2 - ...))),
// evaluated with the modified Lentz algorithm; the phase pi x^2 / 2 is reduced exactly
// (x^2 split into a double and its rounding error, reduced modulo 4).
//
// Accuracy: relative error below 1e-14 for all finite x (checked against long-double
// quadrature in tests/planner/geometry/fresnel_test.cpp); C and S are odd; C(inf) = S(inf) = 1/2.

namespace blendbench {

struct FresnelCS {
  double c = 0;  // C(x)
  double s = 0;  // S(x)
};

FresnelCS fresnel(double x);

}  // namespace blendbench
