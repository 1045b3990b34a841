// Where each corner lies: the programmed corner point and arc length, and the transition's span
// on the planned path (reports, plots and the corner timing of the metrics use it).

#include "blendbench/program/corner_placement.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "blendbench/corner/blend.hpp"
#include "support/property.hpp"

namespace blendbench {
namespace {

// Arc lengths summed from piece lengths: rounding only.
constexpr double kTolerance = 1e-12;  // m

Program polyline(const std::vector<Vec3>& points, const Transition& t) {
  Program p;
  for (std::size_t i = 0; i + 1 < points.size(); ++i) {
    Move& m = p.moves.emplace_back();
    m.geometry = Line{points[i], points[i + 1]};
    m.limits = {0.2, 2, 2, 20};
    m.transition = t;
  }
  return p;
}

TEST(CornerPlacement, ExactStopsSitOnTheJunctions) {
  const Program program = polyline({Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(0.1, 0.05, 0), Vec3(0, 0.05, 0)}, {});
  const Path path = blend(program);
  const std::vector<CornerPlacement> where = corner_placements(path, program);
  ASSERT_EQ(where.size(), 2u);
  EXPECT_TRUE(where[0].point.isApprox(Vec3(0.1, 0, 0)));
  EXPECT_NEAR(where[0].s_programmed, 0.1, kTolerance);
  EXPECT_NEAR(where[1].s_programmed, 0.15, kTolerance);
  for (const CornerPlacement& c : where) {
    EXPECT_EQ(c.s_start, c.s_end);
    EXPECT_NEAR(c.s_start, c.s_programmed, kTolerance) << "an exact stop's path is the programmed one";
  }
}

// Property: on random zig-zags blended with arcs, each corner's span is its transition piece:
// it starts where the incoming move was trimmed, lasts the reported length, and its ends lie on
// the path where the transition's ends are.
TEST(CornerPlacement, TransitionSpansMatchTheReports) {
  const int cases = test::property_cases(100);
  for (int c = 0; c < cases; ++c) {
    const auto seed = static_cast<std::uint64_t>(700 + c);
    auto rng = test::make_rng(seed);
    std::vector<Vec3> points = {Vec3::Zero()};
    for (int k = 0; k < 4; ++k) {
      points.push_back(points.back() + Vec3(test::uniform(rng, 0.05, 0.2), test::uniform(rng, -0.2, 0.2), 0));
    }
    const Program program = polyline(points, {Method::kArc, test::uniform(rng, 0.001, 0.02)});
    const Path path = blend(program);
    const std::vector<CornerPlacement> where = corner_placements(path, program);
    ASSERT_EQ(where.size(), path.corners.size()) << test::seed_text(seed);
    double programmed = 0;
    double saved = 0;  // what the transitions before this corner shortened the path by
    for (std::size_t k = 0; k < where.size(); ++k) {
      const CornerReport& r = path.corners[k];
      programmed += (points[k + 1] - points[k]).norm();
      EXPECT_NEAR(where[k].s_programmed, programmed, kTolerance) << test::seed_text(seed);
      EXPECT_TRUE(where[k].point.isApprox(points[k + 1], 1e-12)) << test::seed_text(seed);
      EXPECT_NEAR(where[k].s_end - where[k].s_start, r.length, 1e-9) << test::seed_text(seed);
      EXPECT_NEAR(where[k].s_start, programmed - saved - r.trim_in, 1e-9) << test::seed_text(seed);
      saved += r.trim_in + r.trim_out - r.length;
    }
  }
}

}  // namespace
}  // namespace blendbench
