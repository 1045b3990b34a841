#include "planner/segment.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "../support/property.hpp"

namespace blendbench {
namespace {

constexpr double kTol = 1e-12;

// Central finite difference of a vector function of s.
template <class F>
Vec3 derivative(const F& f, double s, double h) {
  return (f(s + h) - f(s - h)) / (2 * h);
}

TEST(Segment, LineIsArcLengthParameterised) {
  const Segment line = Line{Vec3(0, 0, 0), Vec3(3, 4, 0)};
  EXPECT_NEAR(length(line), 5.0, kTol);
  EXPECT_TRUE(point(line, 2.5).isApprox(Vec3(1.5, 2, 0), kTol));
  EXPECT_TRUE(tangent(line, 1).isApprox(Vec3(0.6, 0.8, 0), kTol));
  EXPECT_EQ(curvature_vector(line, 1).norm(), 0.0);
}

TEST(Segment, ArcAndHelixAgreeWithFiniteDifferences) {
  for (const double rise : {0.0, 0.3}) {
    const Arc arc{Vec3(1, 2, 3), Vec3(1, 0, 0), Vec3(0, 0, 1), 0.5, 1.5 * std::numbers::pi, rise};
    const Segment seg = arc;
    const double len = length(seg);
    for (double s = 0.05; s < len - 0.05; s += len / 17) {
      const Vec3 t = derivative([&](double x) { return point(seg, x); }, s, 1e-5);
      EXPECT_NEAR(t.norm(), 1.0, 1e-8) << "ds must equal |dp|, rise=" << rise;
      EXPECT_TRUE(t.isApprox(tangent(seg, s), 1e-8));
      const Vec3 k = derivative([&](double x) { return tangent(seg, x); }, s, 1e-5);
      EXPECT_TRUE(k.isApprox(curvature_vector(seg, s), 1e-6)) << "rise=" << rise << " s=" << s;
    }
  }
}

TEST(Segment, SubArcKeepsTheSameCurve) {
  const Arc arc{Vec3(0, 0, 0), Vec3(0, 1, 0), Vec3(-1, 0, 0), 2.0, 2.0, 0.4};
  const Arc part = sub_segment(arc, 0.7, 2.9);
  EXPECT_NEAR(length(part), 2.2, 1e-12);
  for (double s = 0; s <= 2.2; s += 0.1) {
    EXPECT_TRUE(point(part, s).isApprox(point(arc, s + 0.7), 1e-12)) << s;
  }
}

TEST(Segment, BezierArcLengthTableIsExactOnAStraightCubic) {
  // a cubic with collinear, unevenly spaced control points: speed varies, length is known
  const Bezier bezier({Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(0.9, 0, 0), Vec3(1, 0, 0)});
  EXPECT_NEAR(bezier.length(), 1.0, 1e-14);
  for (double s = 0; s <= 1.0; s += 0.05) {
    EXPECT_NEAR(point(Segment(bezier), s).x(), s, 1e-12) << "s=" << s;
  }
}

TEST(Segment, BezierCurvatureMatchesTheFormulaOfPaper000) {
  // 000 eq. 6: kappa(0) = (n-1)/n |(P1-P0) x (P2-P1)| / |P1-P0|^3 for a cubic
  const std::vector<Vec3> p = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 1, 0), Vec3(2, 2, 0.5)};
  const Segment seg = Bezier(p);
  const double expected = (2.0 / 3.0) * (p[1] - p[0]).cross(p[2] - p[1]).norm() / std::pow((p[1] - p[0]).norm(), 3);
  EXPECT_NEAR(curvature_vector(seg, 0).norm(), expected, 1e-10);
  // the curvature vector is normal to the tangent everywhere
  for (double s = 0; s < length(seg); s += length(seg) / 13) {
    EXPECT_NEAR(curvature_vector(seg, s).dot(tangent(seg, s)), 0.0, 1e-10);
  }
}

TEST(Segment, ClothoidCurvatureIsLinearInArcLength) {
  const Clothoid c{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 0.5, 2.0, 1.5};
  const Segment seg = c;
  for (double s = 0.1; s < 1.4; s += 0.1) {
    const Vec3 t = derivative([&](double x) { return point(seg, x); }, s, 1e-5);
    EXPECT_TRUE(t.isApprox(tangent(seg, s), 1e-9)) << s;
    EXPECT_NEAR(curvature_vector(seg, s).norm(), std::abs(0.5 + 2.0 * s), 1e-12);
  }
  EXPECT_DOUBLE_EQ(max_curvature(seg, 0, 1.5), 3.5);
  EXPECT_DOUBLE_EQ(max_sharpness(seg, 0, 1.5), 2.0);
}

TEST(Segment, ClothoidQuadratureMatchesFresnelSeries) {
  // unit clothoid: X(s) = C(s / sqrt(pi)) sqrt(pi) with c = 1; compare with the power series
  // of int_0^s cos(t^2/2) dt and int_0^s sin(t^2/2) dt, convergent and exact for s <= 2
  for (double s = 0.1; s <= 2.0; s += 0.1) {
    double x = 0;
    double y = 0;
    for (int k = 0; k < 30; ++k) {
      const double ck = std::pow(-1.0, k) * std::pow(s, 4 * k + 1) / (std::pow(2.0, 2 * k) * std::tgamma(2 * k + 1)) / (4 * k + 1);
      const double sk = std::pow(-1.0, k) * std::pow(s, 4 * k + 3) / (std::pow(2.0, 2 * k + 1) * std::tgamma(2 * k + 2)) / (4 * k + 3);
      x += ck;
      y += sk;
    }
    const Eigen::Vector2d xy = clothoid_xy(0.0, 1.0, s);
    EXPECT_NEAR(xy.x(), x, 1e-14) << s;
    EXPECT_NEAR(xy.y(), y, 1e-14) << s;
  }
}

TEST(Segment, MaxCurvatureOfABezierFindsTheInteriorPeak) {
  // symmetric cubic corner fillet (P1 = P2 = corner): curvature peaks at the middle
  const Segment seg = Bezier({Vec3(-1, 0, 0), Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(0, 1, 0)});
  const double mid = curvature_vector(seg, 0.5 * length(seg)).norm();
  EXPECT_NEAR(max_curvature(seg, 0, length(seg)), mid, 1e-9 * mid);
}

}  // namespace
}  // namespace blendbench
