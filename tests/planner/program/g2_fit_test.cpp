#include "blendbench/program/g2_fit.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "blendbench/geometry/closest.hpp"
#include "support/property.hpp"
#include "support/random_stream.hpp"

namespace blendbench {
namespace {

using test::StreamKind;

// Joints of the fitted curve: the tangent turns by at most this (rad) and the curvature vector
// jumps by at most kJointCurvature of the largest curvature at the joint plus kJointCurvatureFloor
// (1/m): rounding of quintic Bezier pieces converted from one spline, far below the velocity
// planner's own threshold for a step (1e-9 relative, timing intervals.cpp).
constexpr double kJointAngle = 1e-9;
constexpr double kJointCurvature = 1e-6;
constexpr double kJointCurvatureFloor = 1e-6;
// The independent dense sampling (closest.hpp hausdorff) every this share of the tolerance.
constexpr double kDenseStep = 0.05;

// A stream `kind` of `count` lines `step` long, fitted at `tolerance`, checked: the ends exact,
// G2 at every joint, every piece regular, and within the tolerance of the polyline both ways by
// dense sampling; the fit's own distance bounds the dense one from above.
void expect_fit(const std::vector<Vec3>& points, const CurveEnds& ends, double tolerance, const std::string& what) {
  G2FitStats stats;
  const CurveFit fit = g2_fit(points, ends, tolerance, &stats);
  ASSERT_TRUE(fit.outcome.ok()) << what << ": " << fit.outcome.message;
  ASSERT_FALSE(fit.pieces.empty()) << what;
  EXPECT_EQ(fit.piece_segment.size(), fit.pieces.size()) << what;
  EXPECT_EQ(start_point(fit.pieces.front()), points.front()) << what;
  EXPECT_EQ(end_point(fit.pieces.back()), ends.closed ? points.front() : points.back()) << what;
  const test::JointJumps jumps = test::joint_jumps(fit.pieces, ends.closed);
  double kappa = 0;
  for (const Segment& piece : fit.pieces) kappa = std::max(kappa, max_curvature(piece, 0, length(piece)));
  EXPECT_LE(jumps.angle, kJointAngle) << what;
  EXPECT_LE(jumps.curvature, kJointCurvature * kappa + kJointCurvatureFloor) << what << " (largest curvature " << kappa << ")";
  EXPECT_LE(jumps.gap, 1e-15) << what;
  if (ends.start_tangent) {
    EXPECT_LE(angle_between(tangent(fit.pieces.front(), 0.0), *ends.start_tangent), kJointAngle) << what;
    EXPECT_LE(curvature_vector(fit.pieces.front(), 0.0).norm(), kJointCurvatureFloor) << what;
  }
  if (ends.end_tangent) {
    const Segment& last = fit.pieces.back();
    EXPECT_LE(angle_between(tangent(last, length(last)), *ends.end_tangent), kJointAngle) << what;
    EXPECT_LE(curvature_vector(last, length(last)).norm(), kJointCurvatureFloor) << what;
  }
  for (const Segment& piece : fit.pieces) {
    const auto& b = std::get<Bezier>(piece);
    for (int j = 0; j <= 16; ++j) ASSERT_GT(b.d1(j / 16.0).norm(), 0) << what;
  }
  const double dense = hausdorff(fit.pieces, test::polyline_segments(points), kDenseStep * tolerance);
  EXPECT_LE(dense, tolerance) << what;
  EXPECT_GE(stats.distance, dense - kDenseStep * tolerance) << what;
  EXPECT_LE(stats.distance, tolerance) << what;
}

TEST(G2Fit, RandomStreamsStayWithinTheToleranceAndAreG2) {
  // every kind of stream but the reversal, open with free ends and with tangent ends (as joined
  // to lines), lines 0.01..0.2 mm at tolerances 0.005..0.05 mm
  const int cases = test::property_cases(24);
  for (int i = 0; i < cases; ++i) {
    const std::uint64_t seed = 4500 + static_cast<std::uint64_t>(i);
    auto rng = test::make_rng(seed);
    const StreamKind kind = test::kStreamKinds[static_cast<std::size_t>(i / 2) % (test::kStreamKinds.size() - 1)];
    const double tolerance = test::log_uniform(rng, 0.005e-3, 0.05e-3);
    const double step = test::log_uniform(rng, 0.01e-3, 0.2e-3);
    const int count = static_cast<int>(test::uniform(rng, 30, 300));
    const std::vector<Vec3> points = test::random_stream(rng, kind, count, step, tolerance);
    CurveEnds ends;
    if (i % 2 == 1) {
      // the directions of the first and last lines of non-zero length
      std::size_t a = 1;
      while ((points[a] - points[0]).norm() == 0) ++a;
      std::size_t b = points.size() - 2;
      while ((points.back() - points[b]).norm() == 0) --b;
      ends.start_tangent = (points[a] - points[0]).normalized();
      ends.end_tangent = (points.back() - points[b]).normalized();
    }
    expect_fit(points, ends, tolerance,
               test::stream_name(kind) + (i % 2 == 1 ? " (tangent ends) " : " ") + test::seed_text(seed));
  }
}

TEST(G2Fit, ClosedContoursCloseG2) {
  // circles and a smooth closed curve: the curve starts and ends at the first point, tangent and
  // curvature continuous across it
  const int cases = test::property_cases(6);
  for (int i = 0; i < cases; ++i) {
    const std::uint64_t seed = 4600 + static_cast<std::uint64_t>(i);
    auto rng = test::make_rng(seed);
    const double tolerance = test::log_uniform(rng, 0.005e-3, 0.05e-3);
    const double step = test::log_uniform(rng, 0.01e-3, 0.1e-3);
    std::vector<Vec3> points;
    if (i % 2 == 0) {
      points = test::random_stream(rng, StreamKind::kCircle, static_cast<int>(test::uniform(rng, 50, 400)), step, tolerance, true);
    } else {
      // a limacon, r = a (1.25 + cos t): dimpled like a cardioid
      const double a = 200 * step / (2 * std::numbers::pi);
      for (int k = 0; k <= 200; ++k) {
        const double t = 2 * std::numbers::pi * k / 200;
        const double r = a * (1.25 + std::cos(t));
        points.push_back(Vec3(r * std::cos(t), r * std::sin(t), 0));
      }
      points.back() = points.front();
    }
    CurveEnds ends;
    ends.closed = true;
    expect_fit(points, ends, tolerance, (i % 2 == 0 ? "circle " : "limacon ") + test::seed_text(seed));
  }
}

TEST(G2Fit, ReversalsFitOrAreRefusedCleanly) {
  // a stream that turns straight back: a G2 curve within the tolerance must turn within it, so
  // the fit either finds one or says why not; never a NaN or a cusp
  for (int i = 0; i < test::property_cases(6); ++i) {
    const std::uint64_t seed = 4700 + static_cast<std::uint64_t>(i);
    auto rng = test::make_rng(seed);
    const double tolerance = 0.02e-3;
    const std::vector<Vec3> points = test::random_stream(rng, StreamKind::kReversal, 60, 0.05e-3, tolerance);
    const CurveFit fit = g2_fit(points, CurveEnds{}, tolerance);
    if (!fit.outcome.ok()) {
      EXPECT_TRUE(fit.pieces.empty());
      EXPECT_NE(fit.outcome.message.find("no G2 fit within 0.02 mm"), std::string::npos) << fit.outcome.message;
      continue;
    }
    expect_fit(points, CurveEnds{}, tolerance, "reversal " + test::seed_text(seed));
  }
}

TEST(G2Fit, ACircleIsNoRougherThanTheCircleItself) {
  // optimality against a feasible curve: the circle through noisy samples of it lies within the
  // tolerance, so the fit's integral of |d^3p/ds^3|^2 (what it minimises) is at most the circle's,
  // 2 pi R kappa^4, up to the fit's convergence (10 %)
  auto rng = test::make_rng(4800);
  const double radius = 10e-3;
  const double tolerance = 0.02e-3;
  std::vector<Vec3> points;
  for (int k = 0; k <= 2000; ++k) {
    const double a = 2 * std::numbers::pi * k / 2000;
    points.push_back(Vec3(radius * std::cos(a), radius * std::sin(a), 0) + test::random_unit(rng) * (tolerance / 3));
  }
  points.back() = points.front();
  CurveEnds ends;
  ends.closed = true;
  const CurveFit fit = g2_fit(points, ends, tolerance);
  ASSERT_TRUE(fit.outcome.ok()) << fit.outcome.message;
  double energy = 0;
  for (const Segment& piece : fit.pieces) {
    const double len = length(piece);
    constexpr int kSamples = 64;
    for (int j = 0; j < kSamples; ++j) energy += curvature_derivative(piece, (j + 0.5) * len / kSamples).squaredNorm() * len / kSamples;
  }
  const double circle = 2 * std::numbers::pi * radius * std::pow(1 / radius, 4);
  EXPECT_LE(energy, 1.1 * circle) << "fit " << energy << ", circle " << circle;
}

TEST(G2Fit, CollinearPointsGiveAStraightCurve) {
  std::vector<Vec3> points;
  for (int k = 0; k <= 50; ++k) points.push_back(Vec3(0.02e-3 * k + 1e-6 * (k % 3), 0, 0));
  const CurveFit fit = g2_fit(points, CurveEnds{}, 0.01e-3);
  ASSERT_TRUE(fit.outcome.ok()) << fit.outcome.message;
  for (const Segment& piece : fit.pieces) EXPECT_LE(max_curvature(piece, 0, length(piece)), 1e-6);
}

TEST(G2Fit, RefusesWhatItCannotFit) {
  EXPECT_FALSE(g2_fit({Vec3::Zero()}, CurveEnds{}, 1e-5).outcome.ok());
  EXPECT_FALSE(g2_fit({Vec3::Zero(), Vec3::Zero()}, CurveEnds{}, 1e-5).outcome.ok());
}

}  // namespace
}  // namespace blendbench
