#include "blendbench/program/clothoid_points.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "support/property.hpp"
#include "support/random_stream.hpp"

namespace blendbench {
namespace {

using test::StreamKind;

constexpr double kDeg = std::numbers::pi / 180;
// Joints: pairs meet at zero curvature with the direction of the point they meet at; the
// tangent turns by at most kJointAngle there, the curvature is at most kZeroCurvature (1/m:
// rounding of kappa0 + sharpness L on clothoids of curvature up to 1e5 1/m here), and a pair's
// end lies within kPassGap (m) of the point it aims at (the Fresnel integrals' 2e-15 relative).
constexpr double kJointAngle = 1e-9;
constexpr double kZeroCurvature = 1e-7;
constexpr double kPassGap = 1e-15;

// The turn of a clothoid pair (two pieces) or a line (rad).
double turn_of(const Segment& s) {
  if (const auto* c = std::get_if<Clothoid>(&s)) return std::abs(c->kappa0 * c->length + 0.5 * c->sharpness * c->length * c->length);
  return 0;
}

// Every point is the start of a piece (the curve passes through it exactly), the curvature is
// zero at every piece's ends, the curve is G2, every clothoid pair turns by at most max_turn.
void expect_interpolation(const std::vector<Vec3>& points, const CurveEnds& ends, double max_turn, const std::string& what) {
  const CurveFit fit = clothoid_points(points, ends, max_turn);
  ASSERT_TRUE(fit.outcome.ok()) << what << ": " << fit.outcome.message;
  ASSERT_EQ(fit.piece_segment.size(), fit.pieces.size());
  // each line of non-zero length starts with a piece, in order, that names it
  std::size_t piece = 0;
  for (std::size_t k = 0; k + 1 < points.size(); ++k) {
    if ((points[k + 1] - points[k]).norm() == 0) continue;
    while (piece < fit.pieces.size() && start_point(fit.pieces[piece]) != points[k]) ++piece;
    ASSERT_LT(piece, fit.pieces.size()) << what << ": point " << k << " is not on the curve";
    EXPECT_EQ(fit.piece_segment[piece], k) << what;
  }
  EXPECT_LE((end_point(fit.pieces.back()) - (ends.closed ? points.front() : points.back())).norm(), kPassGap) << what;
  const test::JointJumps jumps = test::joint_jumps(fit.pieces, ends.closed);
  EXPECT_LE(jumps.angle, kJointAngle) << what;
  EXPECT_LE(jumps.curvature, kZeroCurvature) << what;
  EXPECT_LE(jumps.gap, kPassGap) << what;
  for (std::size_t i = 0; i < fit.pieces.size(); ++i) {
    const Segment& s = fit.pieces[i];
    if (std::holds_alternative<Clothoid>(s)) {
      // pieces come in pairs: the first from zero curvature, the second back to it
      const auto& c = std::get<Clothoid>(s);
      if (c.kappa0 == 0) {
        ASSERT_LT(i + 1, fit.pieces.size()) << what;
        EXPECT_LE(turn_of(s) + turn_of(fit.pieces[i + 1]), max_turn * (1 + 1e-12)) << what;
        EXPECT_LE(curvature_vector(fit.pieces[i + 1], length(fit.pieces[i + 1])).norm(), kZeroCurvature) << what;
      }
    }
  }
  if (ends.start_tangent) {
    EXPECT_LE(angle_between(tangent(fit.pieces.front(), 0.0), *ends.start_tangent), kJointAngle) << what;
  }
}

TEST(ClothoidPoints, PointsOfACircleGetOneSymmetricPairEach) {
  // equal steps of 5 deg round a circle of 10 mm: the circle's tangent at each point is
  // symmetric about every chord, so no point is added and every pair turns by 5 deg, peaking at
  // twice the circle's curvature (a pair of half-length L turning by phi peaks at phi / L)
  std::vector<Vec3> points;
  for (int k = 0; k <= 36; ++k) points.push_back(Vec3(10e-3 * std::cos(5 * k * kDeg), 10e-3 * std::sin(5 * k * kDeg), 0));
  const CurveFit fit = clothoid_points(points, CurveEnds{}, 45 * kDeg);
  ASSERT_TRUE(fit.outcome.ok()) << fit.outcome.message;
  EXPECT_EQ(fit.points_added, 0);
  ASSERT_EQ(fit.pieces.size(), 72u);
  for (std::size_t i = 0; i < fit.pieces.size(); i += 2) {
    EXPECT_NEAR(turn_of(fit.pieces[i]) + turn_of(fit.pieces[i + 1]), 5 * kDeg, 1e-12);
    const auto& c = std::get<Clothoid>(fit.pieces[i]);
    EXPECT_NEAR(c.sharpness * c.length, 5 * kDeg / c.length, 1e-9 / c.length);
  }
  expect_interpolation(points, CurveEnds{}, 45 * kDeg, "circle");
}

TEST(ClothoidPoints, Figure11AddsPointsWhereAPairWouldTurnMoreThanTheLimit) {
  // five points like seed 002's Fig. 11, turning by up to 120 deg: with 45 deg pairs, points are
  // added; with 180 deg none beyond the biarc points
  const std::vector<Vec3> points = {Vec3(0, 0, 0), Vec3(0.02, 0.01, 0), Vec3(0.04, 0, 0), Vec3(0.05, 0.02, 0),
                                    Vec3(0.03, 0.03, 0)};
  const CurveFit tight = clothoid_points(points, CurveEnds{}, 45 * kDeg);
  const CurveFit loose = clothoid_points(points, CurveEnds{}, 179 * kDeg);
  ASSERT_TRUE(tight.outcome.ok() && loose.outcome.ok());
  EXPECT_GT(tight.points_added, loose.points_added);
  expect_interpolation(points, CurveEnds{}, 45 * kDeg, "figure 11, 45 deg");
  expect_interpolation(points, CurveEnds{}, 179 * kDeg, "figure 11, 179 deg");
}

TEST(ClothoidPoints, RandomStreamsPassThroughEveryPointG2) {
  const int cases = test::property_cases(60);
  for (int i = 0; i < cases; ++i) {
    const std::uint64_t seed = 5500 + static_cast<std::uint64_t>(i);
    auto rng = test::make_rng(seed);
    const StreamKind kind = test::kStreamKinds[static_cast<std::size_t>(i / 2) % (test::kStreamKinds.size() - 1)];
    const double step = test::log_uniform(rng, 0.01e-3, 1e-3);
    const int count = static_cast<int>(test::uniform(rng, 5, 200));
    const std::vector<Vec3> points = test::random_stream(rng, kind, count, step, 0.1 * step);
    const double max_turn = test::uniform(rng, 5, 90) * kDeg;
    CurveEnds ends;
    if (i % 2 == 1) ends.start_tangent = test::random_unit(rng);  // a joining line at any angle
    expect_interpolation(points, ends, max_turn, test::stream_name(kind) + " " + test::seed_text(seed));
  }
}

TEST(ClothoidPoints, ClosedContoursCloseG2) {
  for (int i = 0; i < test::property_cases(10); ++i) {
    const std::uint64_t seed = 5600 + static_cast<std::uint64_t>(i);
    auto rng = test::make_rng(seed);
    const std::vector<Vec3> points = test::random_stream(rng, StreamKind::kCircle, static_cast<int>(test::uniform(rng, 4, 100)),
                                                         test::log_uniform(rng, 0.01e-3, 1e-3), 0, true);
    CurveEnds ends;
    ends.closed = true;
    expect_interpolation(points, ends, 45 * kDeg, "closed circle " + test::seed_text(seed));
  }
}

TEST(ClothoidPoints, RefusesAReversalWithAReason) {
  const std::vector<Vec3> points = {Vec3(0, 0, 0), Vec3(1e-3, 0, 0), Vec3(0, 0, 0), Vec3(-1e-3, 1e-3, 0)};
  const CurveFit fit = clothoid_points(points, CurveEnds{}, 45 * kDeg);
  EXPECT_FALSE(fit.outcome.ok());
  EXPECT_TRUE(fit.pieces.empty());
  EXPECT_NE(fit.outcome.message.find("reverse"), std::string::npos) << fit.outcome.message;
  EXPECT_FALSE(clothoid_points({Vec3::Zero(), Vec3::Zero()}, CurveEnds{}, 45 * kDeg).outcome.ok());
}

}  // namespace
}  // namespace blendbench
