#include "blendbench/geometry/follow_distance.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "blendbench/geometry/closest.hpp"
#include "support/property.hpp"
#include "support/random_geometry.hpp"

namespace blendbench {
namespace {

// The polyline through `points` as segments.
std::vector<Segment> lines(const std::vector<Vec3>& points) {
  std::vector<Segment> out;
  for (std::size_t k = 0; k + 1 < points.size(); ++k) out.emplace_back(Line{points[k], points[k + 1]});
  return out;
}

std::vector<double> arc_lengths(const std::vector<Vec3>& points) {
  std::vector<double> out{0.0};
  for (std::size_t k = 1; k < points.size(); ++k) out.push_back(out.back() + (points[k] - points[k - 1]).norm());
  return out;
}

TEST(FollowDistance, AParallelLineIsItsOffsetAwayBothWays) {
  // a line 0.01 mm beside a polyline along it: 0.01 mm both ways, plus at most the resolution
  std::vector<Vec3> points;
  for (int k = 0; k <= 20; ++k) points.push_back(Vec3(k * 0.1e-3, 0, 0));
  const std::vector<Segment> curve = {Line{Vec3(0, 0.01e-3, 0), Vec3(2e-3, 0.01e-3, 0)}};
  const double resolution = 1e-7;
  const FollowDistance d = follow_distance(curve, {0.0}, {2e-3}, points, resolution, 0.2e-3);
  EXPECT_GE(d.curve_to_polyline, 0.01e-3);
  EXPECT_LE(d.curve_to_polyline, 0.01e-3 + resolution);
  EXPECT_GE(d.polyline_to_curve, 0.01e-3);
  EXPECT_LE(d.polyline_to_curve, 0.01e-3 + resolution);
}

TEST(FollowDistance, AnArcAgainstItsChordsIsTheSagitta) {
  // an arc of radius R through points every 10 deg: the chords' sagitta R (1 - cos 5 deg) both
  // ways (the farthest points are the chords' middles and the arc's points above them)
  const double radius = 5e-3;
  const double step = 10 * std::numbers::pi / 180;
  std::vector<Vec3> points;
  for (int k = 0; k <= 9; ++k) points.push_back(Vec3(radius * std::cos(k * step), radius * std::sin(k * step), 0));
  const Arc arc{Vec3::Zero(), Vec3::UnitX(), Vec3::UnitY(), radius, 9 * step, 0};
  const double sagitta = radius * (1 - std::cos(0.5 * step));
  const double resolution = 1e-2 * sagitta;
  const std::vector<double> sigma = arc_lengths(points);
  const FollowDistance d = follow_distance({arc}, {0.0}, {sigma.back()}, points, resolution, 1e-3);
  EXPECT_GE(d.hausdorff(), sagitta);
  EXPECT_LE(d.hausdorff(), sagitta + 2 * resolution);
}

TEST(FollowDistance, BoundsTheDenseHausdorffDistanceFromAbove) {
  // random smooth chains (clothoids and Beziers) and polylines through points near them, each
  // piece corresponding to its stretch: the result is within the resolution above the dense
  // sampling of closest.hpp, never below it
  const int cases = test::property_cases(20);
  for (int i = 0; i < cases; ++i) {
    const std::uint64_t seed = 4400 + static_cast<std::uint64_t>(i);
    auto rng = test::make_rng(seed);
    std::vector<Segment> curve;
    Vec3 at = Vec3::Zero();
    const int pieces = static_cast<int>(test::uniform(rng, 1, 6));
    for (int p = 0; p < pieces; ++p) {
      const auto kind = i % 2 == 0 ? test::SegmentKind::kClothoid : test::SegmentKind::kBezier;
      curve.push_back(test::random_segment(rng, kind, at, 1e-3));
      at = end_point(curve.back());
    }
    // the polyline: points on the curve, moved off it by up to 0.02 mm
    std::vector<Vec3> points;
    std::vector<double> begin, end;
    for (const Segment& s : curve) {
      begin.push_back(points.empty() ? 0.0 : arc_lengths(points).back());
      const int n = static_cast<int>(test::uniform(rng, 3, 12));
      for (int j = points.empty() ? 0 : 1; j <= n; ++j) {
        points.push_back(point(s, length(s) * j / n) + test::random_unit(rng) * test::uniform(rng, 0, 0.02e-3));
      }
      end.push_back(arc_lengths(points).back());
    }
    const double resolution = 5e-6;
    const double step = 1e-6;  // the dense sampling's, which it may underestimate by half
    const FollowDistance d = follow_distance(curve, begin, end, points, resolution, 10e-3);
    const double dense = hausdorff(curve, lines(points), step);
    EXPECT_GE(d.hausdorff(), dense) << test::seed_text(seed);
    EXPECT_LE(d.hausdorff(), dense + 1.5 * resolution + 0.5 * step) << test::seed_text(seed);
    EXPECT_GE(d.curve_to_polyline, directed_hausdorff(curve, lines(points), step)) << test::seed_text(seed);
  }
}

}  // namespace
}  // namespace blendbench
