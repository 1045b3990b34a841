#include "blendbench/geometry/segment.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "support/property.hpp"
#include "support/random_geometry.hpp"

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

// An arc's points are rounded at the scale of where they lie and of its length, not of its
// radius: the blend of a nearly straight corner has a radius of hundreds of metres to 10^7 m and
// its centre as far away, and a sampled path's third differences (the jerk a controller reads
// from its setpoints) must see the arc's own 1 / R^2, not rounding at eps R (with the points
// taken through the centre, the 351 m blend of a random program read 1e-6 of its jerk limit too
// much at 1 ms; at 10^4 m the differences below fail by orders of magnitude).
TEST(Segment, AnArcOfAnyRadiusIsRoundedAtItsOwnScale) {
  const std::uint64_t seed = 31;
  auto rng = test::make_rng(seed);
  const int cases = test::property_cases(2000);
  constexpr double kEps = std::numeric_limits<double>::epsilon();
  for (int c = 0; c < cases; ++c) {
    const double radius = std::pow(10.0, test::uniform(rng, -3, 7));
    const Vec3 u = test::random_unit(rng);
    const Vec3 v = (test::random_unit(rng).cross(u)).normalized();
    const Vec3 start(test::uniform(rng, -1, 1), test::uniform(rng, -1, 1), test::uniform(rng, -1, 1));
    const double len = std::min(test::uniform(rng, 1e-3, 0.1), 3.0 * radius);
    const Arc arc{start - radius * u, u, v, radius, len / radius, 0.0};
    const Segment seg = arc;
    // rounding allowed: a few eps of where the points lie and of the arc's size
    const double scale = start.norm() + len;
    EXPECT_LE((point(seg, 0.0) - start).norm(), 4 * kEps * (scale + radius)) << test::seed_text(seed) << " case " << c;
    // chords: |p(s2) - p(s1)| = 2 R sin((s2 - s1) / (2 R))
    const double s1 = test::uniform(rng, 0, len);
    const double s2 = test::uniform(rng, 0, len);
    const double chord = 2 * radius * std::sin(std::abs(s2 - s1) / (2 * radius));
    EXPECT_NEAR((point(seg, s2) - point(seg, s1)).norm(), chord, 64 * kEps * scale)
        << test::seed_text(seed) << " case " << c << " radius " << radius;
    // third differences at 64 steps: the arc's own h^3 / R^2, and rounding at the points' scale
    const double h = len / 64;
    double worst = 0;
    for (int k = 0; k + 3 <= 64; ++k) {
      const double s = k * h;
      const Vec3 d3 = point(seg, s + 3 * h) - 3 * point(seg, s + 2 * h) + 3 * point(seg, s + h) - point(seg, s);
      worst = std::max(worst, d3.norm() - h * h * h / (radius * radius));
    }
    EXPECT_LE(worst, 64 * kEps * scale) << test::seed_text(seed) << " case " << c << " radius " << radius;
  }
}

TEST(Segment, TangentAndCurvatureTogetherAreEachOnItsOwnToTheBit) {
  // arcs and helices of any size and sweep, lines, at random and clamped arc lengths
  const std::uint64_t seed = 47;
  auto rng = test::make_rng(seed);
  const int cases = test::property_cases(2000);
  for (int c = 0; c < cases; ++c) {
    const double radius = std::pow(10.0, test::uniform(rng, -4, 4));
    const Vec3 u = test::random_unit(rng);
    const Vec3 v = (test::random_unit(rng).cross(u)).normalized();
    const Vec3 centre(test::uniform(rng, -1, 1), test::uniform(rng, -1, 1), test::uniform(rng, -1, 1));
    const double rise = c % 3 == 0 ? test::uniform(rng, -1, 1) * radius : 0.0;
    const Arc arc{centre, u, v, radius, test::uniform(rng, 1e-6, 4 * std::numbers::pi), rise};
    const Line line{centre, centre + radius * u};
    for (const Primitive& prim : {Primitive{arc}, Primitive{line}}) {
      const double len = length(prim);
      for (const double s : {0.0, len, test::uniform(rng, 0, len), -len, 2 * len}) {
        const TangentCurvature both = tangent_and_curvature(prim, s);
        const Vec3 t = tangent(prim, s);
        const Vec3 k = curvature_vector(prim, s);
        for (Eigen::Index i = 0; i < 3; ++i) {
          // bitwise equal (EXPECT_EQ on doubles: 0 and -0 aside, the same numbers)
          EXPECT_EQ(both.tangent[i], t[i]) << test::seed_text(seed) << " case " << c << " s " << s;
          EXPECT_EQ(both.curvature[i], k[i]) << test::seed_text(seed) << " case " << c << " s " << s;
        }
      }
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
  // seed 000 (single-Bezier transition) eq. 6: kappa(0) = (n-1)/n |(P1-P0) x (P2-P1)| / |P1-P0|^3 for a cubic
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

// int_0^s (cos, sin)(theta0 + k t + c t^2 / 2) dt by composite long-double Gauss-Legendre
// (16 points, the phase changing by at most 0.2 rad per panel): an independent reference. Nodes
// and weights (positive half) to 25 digits, computed with mpmath.
Eigen::Vector2d clothoid_reference(double theta0_in, double k_in, double c_in, double s_in) {
  using Long = long double;
  const Long theta0 = static_cast<Long>(theta0_in), k = static_cast<Long>(k_in), c = static_cast<Long>(c_in),
             s = static_cast<Long>(s_in);
  static const std::array<Long, 8> x = {0.0950125098376374401853193L, 0.2816035507792589132304605L,
                                        0.4580167776572273863424194L, 0.6178762444026437484466718L,
                                        0.7554044083550030338951012L, 0.8656312023878317438804679L,
                                        0.9445750230732325760779884L, 0.9894009349916499325961542L};
  static const std::array<Long, 8> w = {0.1894506104550684962853967L, 0.1826034150449235888667637L,
                                        0.1691565193950025381893121L, 0.1495959888165767320815017L,
                                        0.1246289712555338720524763L, 0.0951585116824927848099251L,
                                        0.0622535239386478928628438L, 0.0271524594117540948517806L};
  const Long turn = std::abs(k) * s + 0.5L * std::abs(c) * s * s;
  const int panels = std::max(1, static_cast<int>(std::ceil(turn / 0.2L)));
  const Long h = s / panels;
  Long sx = 0;
  Long sy = 0;
  for (int p = 0; p < panels; ++p) {
    const Long mid = (p + 0.5L) * h;
    for (std::size_t i = 0; i < 8; ++i) {
      for (const Long sign : {-1.0L, 1.0L}) {
        const Long t = mid + sign * 0.5L * h * x[i];
        const Long th = theta0 + k * t + 0.5L * c * t * t;
        sx += w[i] * std::cos(th);
        sy += w[i] * std::sin(th);
      }
    }
  }
  return {static_cast<double>(sx * h / 2), static_cast<double>(sy * h / 2)};
}

TEST(Segment, ClothoidXyMatchesLongDoubleQuadratureInEveryRegime) {
  // kappa0 != 0 with large and tiny sharpness (where completing the square would cancel),
  // straight lines, arcs and long spirals; clothoid_xy promises an absolute error below 2e-15 s
  constexpr double kXyTol = 2e-15;
  const std::uint64_t seed = 11;
  auto rng = test::make_rng(seed);
  const int cases = test::property_cases(3000);
  for (int i = 0; i < cases; ++i) {
    const double s = std::pow(10.0, test::uniform(rng, -4, 1));
    double k = std::pow(10.0, test::uniform(rng, -3, 1.5)) / s * (test::uniform(rng, 0, 1) < 0.5 ? -1 : 1);
    double c = std::pow(10.0, test::uniform(rng, -3, 1.5)) / (s * s) * (test::uniform(rng, 0, 1) < 0.5 ? -1 : 1);
    if (i % 5 == 0) c = 0;
    if (i % 7 == 0) k = 0;
    if (i % 11 == 0) c *= 1e-9;
    const double theta0 = test::uniform(rng, -4, 4);
    const Eigen::Vector2d ref = clothoid_reference(0.0, k, c, s);
    const Eigen::Vector2d xy = clothoid_xy(k, c, s);
    EXPECT_LE((xy - ref).norm(), kXyTol * s) << test::seed_text(seed) << " case " << i << " k=" << k << " c=" << c
                                              << " s=" << s;
    const Eigen::Vector2d rot = clothoid_reference(theta0, k, c, s);
    EXPECT_LE((clothoid_displacement(theta0, k, c, s) - rot).norm(), kXyTol * s)
        << test::seed_text(seed) << " case " << i;
  }
  EXPECT_EQ(clothoid_xy(1.0, 1.0, 0.0), Eigen::Vector2d::Zero());
  EXPECT_EQ(clothoid_xy(1.0, 1.0, -1.0), Eigen::Vector2d::Zero());
}

TEST(Segment, MaxCurvatureOfABezierFindsTheInteriorPeak) {
  // symmetric cubic corner fillet (P1 = P2 = corner): curvature peaks at the middle
  const Segment seg = Bezier({Vec3(-1, 0, 0), Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(0, 1, 0)});
  const double mid = curvature_vector(seg, 0.5 * length(seg)).norm();
  EXPECT_NEAR(max_curvature(seg, 0, length(seg)), mid, 1e-9 * mid);
}

// d^3p/ds^3 of every segment type against a central difference of its curvature vector, its
// tangent part -kappa^2 (Frenet), and the spatial sharpness against its definition.
TEST(Segment, CurvatureDerivativeAgreesWithFiniteDifferences) {
  const std::vector<Segment> segments = {
      Line{Vec3(0, 0, 0), Vec3(1, 2, 3)},
      Arc{Vec3(1, 2, 3), Vec3(1, 0, 0), Vec3(0, 0, 1), 0.5, 4.0, 0.0},
      Arc{Vec3(1, 2, 3), Vec3(1, 0, 0), Vec3(0, 0, 1), 0.5, 4.0, 0.7},
      Clothoid{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), -0.5, 2.0, 1.5},
      Bezier({Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 1, 0), Vec3(2, 2, 0)}),
      Bezier({Vec3(0, 0, 0), Vec3(1, 0, 0.2), Vec3(2, 1, -0.3), Vec3(2, 2, 0.5), Vec3(1, 3, 1)}),
  };
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const Segment& seg = segments[i];
    const double len = length(seg);
    double spatial = 0;
    for (double s = 0.02 * len; s < 0.98 * len; s += len / 29) {
      const Vec3 d = curvature_derivative(seg, s);
      const Vec3 fd = derivative([&](double x) { return curvature_vector(seg, x); }, s, 1e-5 * len);
      EXPECT_LE((d - fd).norm(), 1e-6 * std::max(1.0, d.norm())) << "segment " << i << " s=" << s;
      const double kappa = curvature_vector(seg, s).norm();
      EXPECT_NEAR(d.dot(tangent(seg, s)), -kappa * kappa, 1e-9 * std::max(1.0, kappa * kappa)) << "segment " << i;
      spatial = std::max(spatial, (d + kappa * kappa * tangent(seg, s)).norm());
    }
    const double reported = max_spatial_sharpness(seg, 0, len);
    EXPECT_GE(reported, spatial * (1 - 1e-9) - 1e-12) << "segment " << i;
    EXPECT_LE(reported, spatial * 1.02 + 1e-12) << "segment " << i;
  }
  // planar: the spatial sharpness is the sharpness; a helix: kappa tau = r b / (r^2 + b^2)^2
  EXPECT_NEAR(max_spatial_sharpness(segments[3], 0, 1.5), max_sharpness(segments[3], 0, 1.5), 1e-15);
  EXPECT_NEAR(max_spatial_sharpness(segments[4], 0, length(segments[4])),
              max_sharpness(segments[4], 0, length(segments[4])), 1e-9);
  const double b = 0.7 / 4.0;
  EXPECT_NEAR(max_spatial_sharpness(segments[2], 0, 1), 0.5 * b / std::pow(0.25 + b * b, 2), 1e-12);
  EXPECT_EQ(max_spatial_sharpness(segments[1], 0, 1), 0.0);
}

}  // namespace
}  // namespace blendbench
