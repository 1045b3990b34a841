#include "blendbench/core/units.hpp"
#include "blendbench/corner/clothoid_blend.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>

#include "support/input_error.hpp"
#include "support/corner_check.hpp"
#include "blendbench/corner/biclothoid.hpp"
#include "blendbench/corner/blend.hpp"
#include "blendbench/geometry/fresnel.hpp"

namespace blendbench {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDeviationSlack = 1e-9;

CornerInput line_corner(double alpha, double tolerance, double kappa_max = 0, double length = 1.0) {
  CornerInput c;
  const Vec3 t2(std::cos(alpha), std::sin(alpha), 0);
  c.in = Line{Vec3(-length, 0, 0), Vec3(0, 0, 0)};
  c.out = Line{Vec3(0, 0, 0), length * t2};
  c.in_available = length;
  c.out_available = length;
  c.spec.method = Method::kClothoid;
  c.spec.parameter = tolerance;
  c.spec.kappa_max = kappa_max;
  c.name = "corner 1 (move 1 -> move 2)";
  c.where = {"cell.yaml", 12, 5};
  return c;
}

TEST(ClothoidPair, MakinoNinetyDegreeCorner) {
  // seed 002 (Makino) eq. 9 and fig. 6: alpha = 90 deg, phi_max = 45 deg, u_max = sqrt(45 / 90) = 1/sqrt(2).
  // Makino's experiment blends a 25 x 25 mm corner: tangent length T = 25 mm, so
  // a = T / (C(u) + S(u) tan 45) and the peak curvature is pi u / a (eq. 7).
  const double alpha = kPi / 2;
  const ClothoidPair pair = clothoid_pair_for_tangent_length(alpha, 25 * kMm);
  const double u = std::sqrt(0.5);
  EXPECT_DOUBLE_EQ(pair.u, u);
  const FresnelCS f = fresnel(u);
  const double a = 25 * kMm / (f.c + f.s);
  EXPECT_NEAR(pair.scale, a, 1e-15);
  EXPECT_NEAR(pair.kappa_peak, kPi * u / a, 1e-12);
  EXPECT_NEAR(pair.half_length, a * u, 1e-15);
  EXPECT_NEAR(pair.deviation, a * f.s / std::cos(alpha / 2), 1e-15);
  // C(1/sqrt 2) = 0.6647169, S(1/sqrt 2) = 0.1771220 (mpmath): a = 29.697 mm, minimum radius
  // of curvature a / (pi u) = 13.368 mm, deviation 7.439 mm for Makino's corner
  EXPECT_NEAR(a / kMm, 29.697, 0.001);
  EXPECT_NEAR(1 / pair.kappa_peak / kMm, 13.368, 0.001);
  EXPECT_NEAR(pair.deviation / kMm, 7.439, 0.001);

  // the built transition: ends 25 mm from the corner on both lines, tangent at 45 deg with
  // the peak curvature at the midpoint, curvature 0 at both ends
  CornerInput c = line_corner(alpha, pair.deviation);
  const CornerFit fit = fit_clothoid_corner(c);
  ASSERT_TRUE(fit.outcome.ok());
  ASSERT_EQ(fit.transition.size(), 2u);
  EXPECT_NEAR(fit.trim_in, 25 * kMm, 1e-15);
  const Segment& first = fit.transition[0];
  const double h = length(first);
  EXPECT_NEAR(h, pair.half_length, 1e-15);
  EXPECT_TRUE(tangent(first, h).isApprox(Vec3(1, 1, 0).normalized(), 1e-14));
  EXPECT_NEAR(curvature_vector(first, h).norm(), pair.kappa_peak, 1e-9);
  EXPECT_NEAR(curvature_vector(first, 0).norm(), 0.0, 1e-15);
  EXPECT_NEAR(curvature_vector(fit.transition[1], h).norm(), 0.0, 1e-9);
  EXPECT_NEAR(point(first, h).norm(), pair.deviation, 1e-15);  // the midpoint on the bisector
  EXPECT_TRUE(test::is_g2(test::check_fit(c, fit))) << "90 deg";
}

TEST(ClothoidPair, DeviationAndTangentLengthScaleLinearly) {
  for (const double deg : {0.001, 0.5, 45.0, 120.0, 179.999}) {
    const double alpha = deg * kPi / 180;
    const ClothoidPair one = clothoid_pair_for_deviation(alpha, 1.0);
    const ClothoidPair two = clothoid_pair_for_deviation(alpha, 2.0);
    EXPECT_NEAR(two.tangent_length, 2 * one.tangent_length, 1e-14 * two.tangent_length) << deg;
    EXPECT_NEAR(two.kappa_peak, 0.5 * one.kappa_peak, 1e-14 * one.kappa_peak) << deg;
    const ClothoidPair back = clothoid_pair_for_tangent_length(alpha, one.tangent_length);
    EXPECT_NEAR(back.deviation, 1.0, 1e-13) << deg;
    // each half turns alpha / 2: kappa_peak * half_length / 2 (a linear ramp)
    EXPECT_NEAR(0.5 * one.kappa_peak * one.half_length, alpha / 2, 1e-14) << deg;
  }
}

TEST(ClothoidPair, LineLineDeviationEqualsTheTolerance) {
  for (const double deg : {0.01, 10.0, 90.0, 170.0}) {
    const CornerInput c = line_corner(deg * kPi / 180, 0.2 * kMm, 0, 1e4);
    const CornerFit fit = fit_clothoid_corner(c);
    ASSERT_TRUE(fit.outcome.ok());
    EXPECT_EQ(fit.corner_case, CornerCase::kRegular);
    EXPECT_DOUBLE_EQ(fit.parameter_used, 0.2 * kMm);
    EXPECT_NEAR(test::check_fit(c, fit).deviation, 0.2 * kMm, 1e-7 * kMm) << deg;
    EXPECT_TRUE(test::is_g2(test::check_fit(c, fit))) << std::to_string(deg);
  }
}

TEST(ClothoidArcClothoid, DeviationAndTangentLengthGrowWithTheClothoidLength) {
  // the monotonicity that clothoid_blend.hpp proves, checked on a grid
  for (const double deg : {5.0, 60.0, 150.0, 179.0}) {
    const double alpha = deg * kPi / 180;
    const double kappa = 100.0;
    double prev_d = -1;
    double prev_t = -1;
    for (int i = 0; i <= 200; ++i) {
      const ClothoidArcClothoid cac = clothoid_arc_clothoid(alpha, kappa, alpha / kappa * i / 200);
      EXPECT_GT(cac.deviation, prev_d) << deg << " " << i;
      EXPECT_GT(cac.tangent_length, prev_t) << deg << " " << i;
      prev_d = cac.deviation;
      prev_t = cac.tangent_length;
    }
    // the ends: the plain arc, and the pair whose peak is kappa
    const ClothoidArcClothoid arc = clothoid_arc_clothoid(alpha, kappa, 0.0);
    EXPECT_NEAR(arc.deviation, (1 / std::cos(alpha / 2) - 1) / kappa, 1e-14);
    EXPECT_NEAR(arc.tangent_length, std::tan(alpha / 2) / kappa, 1e-14);
    const ClothoidArcClothoid pair = clothoid_arc_clothoid(alpha, kappa, alpha / kappa);
    EXPECT_NEAR(pair.arc_length, 0.0, 1e-15);
    const ClothoidPair makino = clothoid_pair_for_deviation(alpha, pair.deviation);
    EXPECT_NEAR(makino.kappa_peak, kappa, 1e-9 * kappa) << deg;
  }
}

TEST(ClothoidArcClothoid, CurvatureCapInsertsAnArc) {
  // 90 deg at 1 mm: the pair peaks at 0.124 1/mm; capped at 0.1 1/mm an arc is inserted whose
  // curvature is the cap, and the deviation stays the tolerance
  CornerInput c = line_corner(kPi / 2, 1 * kMm, 0, 0.1);
  const double pair_peak = clothoid_pair_for_deviation(kPi / 2, 1 * kMm).kappa_peak;
  c.spec.kappa_max = 0.8 * pair_peak;
  const CornerFit fit = fit_clothoid_corner(c);
  ASSERT_TRUE(fit.outcome.ok());
  EXPECT_EQ(fit.corner_case, CornerCase::kClothoidArcClothoid);
  ASSERT_EQ(fit.transition.size(), 3u);
  EXPECT_TRUE(std::holds_alternative<Arc>(fit.transition[1]));
  EXPECT_NEAR(test::peak_curvature(fit), c.spec.kappa_max, 1e-9 * c.spec.kappa_max);
  EXPECT_NEAR(fit.parameter_used, 1 * kMm, 1e-12 * kMm);
  EXPECT_NEAR(test::check_fit(c, fit).deviation, 1 * kMm, 1e-7 * kMm);
  EXPECT_TRUE(fit.note.empty()) << fit.note;
  EXPECT_TRUE(test::is_g2(test::check_fit(c, fit))) << "clothoid-arc-clothoid";
  // a cap above the pair's peak changes nothing
  c.spec.kappa_max = 1.01 * pair_peak;
  EXPECT_EQ(fit_clothoid_corner(c).corner_case, CornerCase::kRegular);
}

TEST(ClothoidArcClothoid, UnreachableCapKeepsThePairAndSaysWhy) {
  // an arc of radius 1 / kappa_max = 100 mm deviates 41 mm at 90 deg: no curve with that cap
  // stays within 1 mm
  CornerInput c = line_corner(kPi / 2, 1 * kMm, 10.0, 0.5);
  const CornerFit fit = fit_clothoid_corner(c);
  ASSERT_TRUE(fit.outcome.ok());
  EXPECT_EQ(fit.corner_case, CornerCase::kCurvatureCapUnmet);
  EXPECT_EQ(fit.transition.size(), 2u);
  EXPECT_NE(fit.note.text().find("exceeds kappa_max"), std::string::npos) << fit.note;
  EXPECT_NE(fit.note.text().find("deviates"), std::string::npos) << fit.note;
  EXPECT_DOUBLE_EQ(fit.parameter_used, 1 * kMm);
  // with short moves the capped curve would not fit either: the note names the move
  c = line_corner(kPi / 2, 1 * kMm, 500.0, 0.01);
  c.out_available = 1 * kMm;
  const CornerFit short_fit = fit_clothoid_corner(c);
  EXPECT_EQ(short_fit.corner_case, CornerCase::kCurvatureCapUnmet);
  EXPECT_NE(short_fit.note.text().find("outgoing"), std::string::npos) << short_fit.note;
  EXPECT_LE(short_fit.trim_out, 1 * kMm);
}

TEST(ClothoidPair, ShortMovesShrinkTheDeviation) {
  CornerInput c = line_corner(kPi / 3, 5 * kMm, 0, 0.1);
  c.in_available = 2 * kMm;
  const CornerFit fit = fit_clothoid_corner(c);
  ASSERT_TRUE(fit.outcome.ok());
  EXPECT_DOUBLE_EQ(fit.trim_in, 2 * kMm);
  EXPECT_LT(fit.parameter_used, 5 * kMm);
  EXPECT_NE(fit.note.text().find("incoming move is short"), std::string::npos) << fit.note;
  EXPECT_NEAR(test::check_fit(c, fit).deviation, fit.parameter_used, 1e-6 * fit.parameter_used);
  EXPECT_TRUE(test::is_g2(test::check_fit(c, fit))) << "short";
}

TEST(ClothoidPair, SpecialCorners) {
  CornerInput collinear = line_corner(0.0, 1 * kMm);
  EXPECT_EQ(fit_clothoid_corner(collinear).corner_case, CornerCase::kCollinear);
  EXPECT_TRUE(fit_clothoid_corner(collinear).transition.empty());
  CornerInput reversal = line_corner(kPi, 1 * kMm);
  reversal.buffer = BufferMode::kBuffered;
  const CornerFit rev = fit_clothoid_corner(reversal);
  EXPECT_EQ(rev.corner_case, CornerCase::kReversal);
  EXPECT_TRUE(rev.stop);
  EXPECT_TRUE(rev.transition.empty());
  // parameter 0 with a tangent discontinuity: an impossible request
  test::expect_input_error([] { (void)fit_clothoid_corner(line_corner(kPi / 4, 0.0)); },
                           {.file = "cell.yaml", .line = 12, .field = "transition.parameter", .message = "corner 1 (move 1 -> move 2)"});
  // parameter 0 on a collinear corner is fine
  EXPECT_EQ(fit_clothoid_corner(line_corner(0.0, 0.0)).corner_case, CornerCase::kCollinear);
}

TEST(ClothoidPair, CornersWithArcsFallBackToBiclothoids) {
  CornerInput c = line_corner(kPi / 6, 0.1 * kMm);
  const Vec3 t2(std::cos(kPi / 6), std::sin(kPi / 6), 0);
  c.out = test::arc_leaving(Vec3(0, 0, 0), t2, Vec3(0, 0, 1), 1.0, 0.01, 1.0);
  c.out_available = 0.5 * length(c.out);
  c.spec.kappa_max = 10.0;  // 0.01 1/mm: below the arc's own curvature
  const CornerFit fit = fit_clothoid_corner(c);
  ASSERT_TRUE(fit.outcome.ok());
  EXPECT_EQ(fit.fallback, Fallback::kBiclothoid);
  EXPECT_NE(fit.note.text().find("does not cap curvature"), std::string::npos) << fit.note;
  EXPECT_EQ(fit.corner_case, CornerCase::kCurvatureCapUnmet);
  EXPECT_TRUE(test::is_g2(test::check_fit(c, fit))) << "line-arc";
  EXPECT_LE(test::check_fit(c, fit).deviation, 0.1 * kMm * (1 + kDeviationSlack));
}

TEST(ClothoidPair, RandomCornersAreG2WithinToleranceAndCap) {
  const int cases = test::property_cases(2000);
  int capped = 0;
  int unmet = 0;
  for (int i = 0; i < cases; ++i) {
    const std::uint64_t seed = 9000 + static_cast<std::uint64_t>(i);
    auto rng = test::make_rng(seed);
    // three line-line corners for every corner with an arc (those fall back to biclothoids)
    const auto kind = i % 4 == 3 ? static_cast<test::CornerKind>(1 + (i / 4) % 3) : test::CornerKind::kLineLine;
    test::CornerCase cc = test::random_corner(rng, kind, Method::kClothoid);
    if (kind == test::CornerKind::kLineLine && test::uniform(rng, 0, 1) < 0.5) {
      cc.input.spec.kappa_max = std::exp(test::uniform(rng, std::log(1.0), std::log(1e4)));
    }
    const CornerFit fit = fit_clothoid_corner(cc.input);
    ASSERT_TRUE(fit.outcome.ok()) << test::seed_text(seed) << ": " << fit.outcome.message;
    ASSERT_FALSE(fit.transition.empty()) << test::seed_text(seed);
    const test::FitCheck check = test::check_fit(cc.input, fit);
    ASSERT_TRUE(test::is_g2(check)) << test::seed_text(seed);
    // the independent measure locates a maximum at a kink to 1e-10 of the transition's length
    double transition_length = 0;
    for (const Segment& seg : fit.transition) transition_length += length(seg);
    EXPECT_LE(check.deviation, cc.input.spec.parameter * (1 + kDeviationSlack) + 1e-10 * transition_length)
        << test::seed_text(seed);
    if (fit.corner_case == CornerCase::kClothoidArcClothoid) {
      ++capped;
      EXPECT_LE(test::peak_curvature(fit), cc.input.spec.kappa_max * (1 + 1e-9)) << test::seed_text(seed);
    } else if (fit.corner_case == CornerCase::kCurvatureCapUnmet) {
      ++unmet;
      // even the plain arc of the cap's radius breaks the tolerance or the available length
      const ClothoidArcClothoid arc = clothoid_arc_clothoid(cc.angle, cc.input.spec.kappa_max, 0.0);
      EXPECT_TRUE(arc.deviation > cc.input.spec.parameter ||
                  arc.tangent_length > std::min(cc.input.in_available, cc.input.out_available))
          << test::seed_text(seed);
    } else if (cc.input.spec.kappa_max > 0 && kind == test::CornerKind::kLineLine) {
      EXPECT_LE(test::peak_curvature(fit), cc.input.spec.kappa_max * (1 + 1e-9)) << test::seed_text(seed);
    }
  }
  EXPECT_GT(capped, 0);
  EXPECT_GT(unmet, 0);
}

// The shape from the turn's cosine and sine (a line corner's fast path) is the shape from the
// angle to rounding: the half-angle formulas against cos and sin of alpha / 2, at turns
// log-uniform from 1e-9 rad and uniform up to the reversal threshold, with the cosine and sine
// rounded as a corner's dot and cross products round them.
TEST(ClothoidPair, ShapeFromTheTurnsCosineAndSineIsTheShapeFromItsAngle) {
  const int cases = test::property_cases(20000);
  double worst = 0;
  for (int i = 0; i < cases; ++i) {
    const std::uint64_t seed = 9500 + static_cast<std::uint64_t>(i);
    auto rng = test::make_rng(seed);
    const double alpha = i % 2 == 0 ? test::log_uniform(rng, 1e-9, 3.1) : test::uniform(rng, 1e-3, 3.14);
    const Vec3 t1(1, 0, 0);
    const Vec3 t2(std::cos(alpha), std::sin(alpha), 0);
    const double sin_alpha = t1.cross(t2).norm();
    const double cos_alpha = t1.dot(t2);
    const double angle = std::atan2(sin_alpha, cos_alpha);
    const ClothoidPairShape from_angle = clothoid_pair_shape(angle);
    const ClothoidPairShape from_turn = clothoid_pair_shape(angle, cos_alpha, sin_alpha);
    EXPECT_EQ(from_turn.u, from_angle.u) << test::seed_text(seed);
    EXPECT_EQ(from_turn.c, from_angle.c) << test::seed_text(seed);
    EXPECT_EQ(from_turn.s, from_angle.s) << test::seed_text(seed);
    // relative to each value, within a few ulp (the cosine near a reversal and the sine at small
    // turns are small, and carry the rounding of the inputs they come from, as cos and sin do)
    const double cos_error = std::abs(from_turn.cos_half - from_angle.cos_half) / from_angle.cos_half;
    const double sin_error = std::abs(from_turn.sin_half - from_angle.sin_half) / from_angle.sin_half;
    const double bound = 1e-15 + 4e-16 / std::min(from_angle.cos_half, from_angle.sin_half);
    EXPECT_LE(cos_error, bound) << test::seed_text(seed) << " alpha=" << alpha;
    EXPECT_LE(sin_error, bound) << test::seed_text(seed) << " alpha=" << alpha;
    worst = std::max({worst, cos_error, sin_error});
  }
  std::printf("half-angle cosine and sine from the turn: largest relative difference %.2e over %d turns\n", worst,
              cases);
}

TEST(ClothoidPair, SquareThroughTheBlender) {
  // a 100 mm square, 2 mm deviation, one corner capped: G2 everywhere, no stop
  Program program;
  const std::array<Vec3, 5> corners = {Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(0.1, 0.1, 0), Vec3(0, 0.1, 0),
                                       Vec3(0, 0, 0)};
  for (std::size_t k = 0; k + 1 < corners.size(); ++k) {
    Move& move = program.moves.emplace_back();
    move.geometry = Line{corners[k], corners[k + 1]};
    move.limits = {0.2, 2.0, 2.0, 50.0};
    move.transition = {Method::kClothoid, 2 * kMm, k == 1 ? 250.0 : 0.0, 0.0};
  }
  const Path path = blend(program);
  ASSERT_EQ(path.corners.size(), 3u);
  EXPECT_EQ(path.corners[1].corner_case, CornerCase::kClothoidArcClothoid);
  EXPECT_NEAR(path.corners[1].kappa_max, 250.0, 1e-6);
  for (const CornerReport& report : path.corners) {
    EXPECT_LE(report.deviation, 2 * kMm * (1 + kDeviationSlack));
    EXPECT_FALSE(report.stop);
  }
  for (std::size_t k = 1; k < path.pieces().size(); ++k) {
    const Segment& a = path.pieces()[k - 1].segment;
    const Segment& b = path.pieces()[k].segment;
    EXPECT_LE((point(a, length(a)) - point(b, 0)).norm(), 1e-12);
    EXPECT_LE(path.pieces()[k].kink_angle, test::kG2Tangent);
    EXPECT_LE((curvature_vector(a, length(a)) - curvature_vector(b, 0)).norm(), 1e-6);
  }
}

}  // namespace
}  // namespace blendbench
