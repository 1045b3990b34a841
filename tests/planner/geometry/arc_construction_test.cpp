#include "blendbench/geometry/arc_construction.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

#include "support/property.hpp"
#include "support/random_geometry.hpp"

namespace blendbench {
namespace {

constexpr double kTol = 1e-12;
constexpr double kPi = std::numbers::pi;

TEST(ArcConstruction, QuarterCircleFromCentreBothDirections) {
  const ArcBuild ccw = arc_from_center({1, 0, 0}, {0, 1, 0}, {0, 0, 0}, Vec3::UnitZ(), true);
  ASSERT_TRUE(ccw.outcome.ok());
  EXPECT_NEAR(ccw.arc.radius, 1.0, kTol);
  EXPECT_NEAR(ccw.arc.sweep, kPi / 2, kTol);
  const ArcBuild cw = arc_from_center({1, 0, 0}, {0, 1, 0}, {0, 0, 0}, Vec3::UnitZ(), false);
  ASSERT_TRUE(cw.outcome.ok());
  EXPECT_NEAR(cw.arc.sweep, 3 * kPi / 2, kTol);
  // the cw arc passes through (0, -1, 0), the ccw one through (sqrt(.5), sqrt(.5), 0)
  EXPECT_TRUE(point(Segment(cw.arc), kPi / 2).isApprox(Vec3(0, -1, 0), kTol));
  EXPECT_TRUE(point(Segment(ccw.arc), kPi / 4).isApprox(Vec3(std::sqrt(0.5), std::sqrt(0.5), 0), kTol));
}

TEST(ArcConstruction, FullCircleAndHelix) {
  const ArcBuild full = arc_from_center({1, 0, 0}, {1, 0, 0}, {0, 0, 0}, Vec3::UnitZ(), true);
  ASSERT_TRUE(full.outcome.ok());
  EXPECT_NEAR(full.arc.sweep, 2 * kPi, kTol);
  const ArcBuild helix = arc_from_center({1, 0, 0}, {-1, 0, 0.5}, {0, 0, 0}, Vec3::UnitZ(), true, 1);
  ASSERT_TRUE(helix.outcome.ok());
  EXPECT_NEAR(helix.arc.sweep, 3 * kPi, kTol);
  EXPECT_NEAR(helix.arc.rise, 0.5, kTol);
  EXPECT_TRUE(point(Segment(helix.arc), length(helix.arc)).isApprox(Vec3(-1, 0, 0.5), kTol));
}

// A rise of rounding size (here 1e-13 m on a 20 mm arc at z = 0.3 m) is no helix: the arc ends
// in its start's plane, which the corner rules read as planar; 1e-9 m on the same arc stays a
// helix.
TEST(ArcConstruction, RiseOfRoundingSizeIsNoHelix) {
  const Vec3 start(0.02, 0, 0.3), centre(0, 0, 0.3);
  const ArcBuild flat = arc_from_center(start, Vec3(0, 0.02, 0.3 + 1e-13), centre, Vec3::UnitZ(), true);
  ASSERT_TRUE(flat.outcome.ok());
  EXPECT_EQ(flat.arc.rise, 0.0);
  EXPECT_LE((point(flat.arc, length(flat.arc)) - Vec3(0, 0.02, 0.3)).norm(), 1e-15);
  const ArcBuild helix = arc_from_center(start, Vec3(0, 0.02, 0.3 + 1e-9), centre, Vec3::UnitZ(), true);
  ASSERT_TRUE(helix.outcome.ok());
  EXPECT_NEAR(helix.arc.rise, 1e-9, 1e-15);
}

TEST(ArcConstruction, FullCircleWithAnEndPointOffByRoundingKeepsItsCentre) {
  // an end point one rounding away from the start has no chord direction to correct along
  const Vec3 start(0.1, 0.2, 0.3);
  const Vec3 end = start + Vec3(3e-17, -2e-17, 0);
  const ArcBuild full = arc_from_center(start, end, {0.1, 0.25, 0.3}, Vec3::UnitZ(), false, 0, 1e-6);
  ASSERT_TRUE(full.outcome.ok());
  EXPECT_NEAR(full.arc.radius, 0.05, kTol);
  EXPECT_TRUE(full.arc.center.isApprox(Vec3(0.1, 0.25, 0.3), kTol));
  EXPECT_NEAR(full.arc.sweep, 2 * kPi, 1e-9);
}

TEST(ArcConstruction, RadiusMismatchIsRejectedBeyondTheTolerance) {
  EXPECT_FALSE(arc_from_center({1, 0, 0}, {0, 1.01, 0}, {0, 0, 0}, Vec3::UnitZ(), true, 0, 1e-3).outcome.ok());
  const ArcBuild close = arc_from_center({1, 0, 0}, {0, 1.0005, 0}, {0, 0, 0}, Vec3::UnitZ(), true, 0, 1e-3);
  ASSERT_TRUE(close.outcome.ok());
  // the end point is hit exactly even though the radii differed slightly
  EXPECT_TRUE(point(Segment(close.arc), length(close.arc)).isApprox(Vec3(0, 1.0005, 0), kTol));
}

TEST(ArcConstruction, RadiusFormPicksShortOrLongArc) {
  const ArcBuild short_arc = arc_from_radius({0, 0, 0}, {1, 1, 0}, 1.0, Vec3::UnitZ(), false);
  ASSERT_TRUE(short_arc.outcome.ok());
  EXPECT_NEAR(short_arc.arc.sweep, kPi / 2, kTol);
  const ArcBuild long_arc = arc_from_radius({0, 0, 0}, {1, 1, 0}, -1.0, Vec3::UnitZ(), false);
  ASSERT_TRUE(long_arc.outcome.ok());
  EXPECT_NEAR(long_arc.arc.sweep, 3 * kPi / 2, kTol);
  EXPECT_FALSE(arc_from_radius({0, 0, 0}, {3, 0, 0}, 1.0, Vec3::UnitZ(), true).outcome.ok());
}

TEST(ArcConstruction, ThreePointArcPassesThroughTheViaPoint) {
  // every draw from the seeded generator (Eigen's Random() is std::rand's, which no seed replays)
  const std::uint64_t seed = 7;
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(2000); ++i) {
    SCOPED_TRACE(test::seed_text(seed));
    const Vec3 c = test::random_point(rng);
    const Vec3 n = test::random_unit(rng);
    const Vec3 u = any_perpendicular(n);
    const Vec3 v = n.cross(u);
    const double r = test::uniform(rng, 0.001, 2.0);
    const double a0 = test::uniform(rng, 0, 2 * kPi);
    const double a1 = a0 + test::uniform(rng, 0.01, 1.9 * kPi);
    const double am = test::uniform(rng, a0 + 0.001, a1 - 0.001);
    const auto at = [&](double a) -> Vec3 { return c + r * (std::cos(a) * u + std::sin(a) * v); };
    const ArcBuild b = arc_through(at(a0), at(am), at(a1));
    ASSERT_TRUE(b.outcome.ok()) << "case " << i;
    EXPECT_NEAR(b.arc.radius, r, 1e-9 * r) << "case " << i;
    EXPECT_NEAR(b.arc.sweep, a1 - a0, 1e-8) << "case " << i;
    EXPECT_LT((point(Segment(b.arc), length(b.arc)) - at(a1)).norm(), 1e-9 * r) << "case " << i;
    EXPECT_LT((point(Segment(b.arc), r * (am - a0)) - at(am)).norm(), 1e-9 * r) << "case " << i;
  }
  EXPECT_FALSE(arc_through({0, 0, 0}, {1, 0, 0}, {2, 0, 0}).outcome.ok());
}

// The distance from q to the spiral, found independently of the code under test: dense samples
// in the angle, each local minimum among them (a spiral of several turns passes q once per turn)
// refined by golden-section search between its neighbours.
double distance_to_spiral(const Spiral& s, const Vec3& q) {
  constexpr int kDense = 4000;
  std::vector<double> d(kDense + 1);
  for (int k = 0; k <= kDense; ++k) d[static_cast<std::size_t>(k)] = (spiral_point(s, s.sweep * k / kDense) - q).norm();
  const auto at = [&](double phi) { return (spiral_point(s, phi) - q).norm(); };
  double best = *std::min_element(d.begin(), d.end());
  for (int k = 0; k <= kDense; ++k) {
    const double here = d[static_cast<std::size_t>(k)];
    const bool left = k == 0 || here <= d[static_cast<std::size_t>(k - 1)];
    const bool right = k == kDense || here <= d[static_cast<std::size_t>(k + 1)];
    if (!left || !right) continue;
    double lo = s.sweep * std::max(0, k - 1) / kDense;
    double hi = s.sweep * std::min(kDense, k + 1) / kDense;
    const double g = (std::sqrt(5.0) - 1) / 2;
    for (int i = 0; i < 80; ++i) {
      const double a = hi - g * (hi - lo);
      const double b = lo + g * (hi - lo);
      if (at(a) < at(b)) {
        hi = b;
      } else {
        lo = a;
      }
    }
    best = std::min(best, at(0.5 * (lo + hi)));
  }
  return best;
}

// Points of a chain of arcs, `per_arc` on each (ends included).
std::vector<Vec3> chain_points(const std::vector<Arc>& arcs, int per_arc) {
  std::vector<Vec3> out;
  for (const Arc& a : arcs) {
    for (int k = 0; k <= per_arc; ++k) out.push_back(point(Segment(a), length(a) * k / per_arc));
  }
  return out;
}

Spiral random_spiral(std::mt19937_64& rng) {
  Spiral s;
  s.center = test::random_point(rng, 0.5);
  const Vec3 w = test::random_unit(rng);
  s.u = any_perpendicular(w);
  s.v = w.cross(s.u);
  s.r0 = test::log_uniform(rng, 1e-4, 0.1);
  // radius differences from rounding (1e-6 relative) to LinuxCNC's looser limit (a few %)
  const double rel = test::log_uniform(rng, 1e-6, 0.05) * (test::uniform(rng, 0, 1) < 0.5 ? -1 : 1);
  s.r1 = s.r0 * (1 + rel);
  s.sweep = test::uniform(rng, 0.05, 3 * 2 * kPi);
  s.rise = test::uniform(rng, 0, 1) < 0.5 ? 0.0 : test::uniform(rng, -0.02, 0.02);
  return s;
}

// Over random spirals (radius 0.1-100 mm, radius changes up to 5 %, up to three turns, helical
// or not): the chain starts and ends on the spiral's end points, is continuous in position and
// tangent (within the planner's G1 angle), and stays within the tolerance of the spiral both
// ways, measured against an independent reference (distances to the spiral by dense search, and
// from the spiral to dense points of the chain).
TEST(SpiralArcs, ChainsFollowTheSpiralWithinTheToleranceAndAreTangentContinuous) {
  const std::uint64_t seed = 20451;
  auto rng = test::make_rng(seed);
  int chains = 0;
  int refused = 0;
  for (int i = 0; i < test::property_cases(40); ++i) {
    SCOPED_TRACE(test::seed_text(seed) + " case " + std::to_string(i));
    const Spiral s = random_spiral(rng);
    const double tol = s.r0 * test::log_uniform(rng, 1e-5, 1e-3);
    const SpiralArcs chain = arcs_along_spiral(s, tol, 2048);
    if (!chain.outcome.ok()) {
      // only a helix can be out of reach: arcs tangent to each other rise at one slope, the
      // spiral linearly in the angle; halfway round they differ by |rise (r1 - r0)| / (4 (r0 + r1))
      EXPECT_NE(s.rise, 0.0) << chain.outcome.message;
      EXPECT_GT(std::abs(s.rise * (s.r1 - s.r0)) / (4 * (s.r0 + s.r1)), 0.5 * tol) << chain.outcome.message;
      EXPECT_GT(chain.deviation, tol);
      ++refused;
      continue;
    }
    ++chains;
    ASSERT_FALSE(chain.arcs.empty());
    // (coordinates round at the size of the centre's, up to 0.5 m here)
    const double scale = std::max(s.r0, s.r1) + std::abs(s.rise) + s.center.norm();
    EXPECT_LT((point(Segment(chain.arcs.front()), 0) - spiral_point(s, 0)).norm(), 1e-12 * scale);
    EXPECT_LT((point(Segment(chain.arcs.back()), length(chain.arcs.back())) - spiral_point(s, s.sweep)).norm(), 1e-10 * scale);
    for (std::size_t k = 0; k + 1 < chain.arcs.size(); ++k) {
      const Segment a(chain.arcs[k]);
      const Segment b(chain.arcs[k + 1]);
      EXPECT_LT((point(a, length(a)) - point(b, 0)).norm(), 1e-12 * scale) << "joint " << k;
      EXPECT_LT(angle_between(tangent(a, length(a)), tangent(b, 0)), 1e-9) << "joint " << k;
    }
    EXPECT_LE(chain.deviation, tol);
    double from_chain = 0;
    for (const Vec3& q : chain_points(chain.arcs, 40)) from_chain = std::max(from_chain, distance_to_spiral(s, q));
    const std::vector<Vec3> dense = chain_points(chain.arcs, 100);
    double from_spiral = 0;
    for (int k = 0; k <= 200; ++k) {
      const Vec3 p = spiral_point(s, s.sweep * k / 200);
      double d = std::numeric_limits<double>::infinity();
      for (const Vec3& q : dense) d = std::min(d, (q - p).norm());
      from_spiral = std::max(from_spiral, d);
    }
    // (the dense chain points are at most half a spacing from the chain itself)
    double spacing = 0;
    for (const Arc& a : chain.arcs) spacing = std::max(spacing, 0.5 * length(a) / 100);
    EXPECT_LE(from_chain, tol * (1 + 1e-6)) << "radius " << s.r0 << " -> " << s.r1 << ", " << chain.arcs.size() << " arcs";
    EXPECT_LE(from_spiral, tol * (1 + 1e-6) + spacing) << chain.arcs.size() << " arcs";
  }
  EXPECT_GT(chains, 0);
}

// A circle is one arc, exactly; a radius off by rounding too; a spiral proper needs a chain,
// more arcs for a tighter tolerance, the biarcs' error falling about eightfold per halving.
TEST(SpiralArcs, OneArcForACircleMoreArcsForATighterTolerance) {
  Spiral s;
  s.center = Vec3(0.1, 0.2, 0.3);
  s.u = Vec3::UnitX();
  s.v = Vec3::UnitY();
  s.r0 = s.r1 = 0.01;
  s.sweep = 1.5 * kPi;
  const SpiralArcs circle = arcs_along_spiral(s, 1e-9, 64);
  ASSERT_TRUE(circle.outcome.ok());
  ASSERT_EQ(circle.arcs.size(), 1u);
  EXPECT_NEAR(circle.arcs[0].radius, 0.01, 1e-15);
  EXPECT_TRUE(circle.arcs[0].center.isApprox(s.center, 1e-14));
  EXPECT_NEAR(circle.arcs[0].sweep, 1.5 * kPi, 1e-12);
  // 10 mm radius growing by 20 um over three quarters of a turn
  s.r1 = 0.01002;
  std::size_t previous = 0;
  double previous_deviation = std::numeric_limits<double>::infinity();
  for (const double tol : {1e-5, 1e-6, 1e-7, 1e-8}) {
    const SpiralArcs chain = arcs_along_spiral(s, tol, 4096);
    ASSERT_TRUE(chain.outcome.ok()) << tol;
    EXPECT_LE(chain.deviation, tol);
    EXPECT_GE(chain.arcs.size(), previous) << tol;
    EXPECT_LE(chain.deviation, previous_deviation);
    previous = chain.arcs.size();
    previous_deviation = chain.deviation;
  }
  EXPECT_GT(previous, 2u);
  // error against the number of biarcs: third order (O(h^3)), so one halving gains about 8x
  Spiral wide = s;
  wide.r1 = 0.012;
  const SpiralArcs coarse = arcs_along_spiral(wide, 1e-4, 8);   // whatever it takes below 8 arcs
  const SpiralArcs finer = arcs_along_spiral(wide, coarse.deviation * 0.99, 4096);
  ASSERT_TRUE(coarse.outcome.ok());
  ASSERT_TRUE(finer.outcome.ok());
  if (coarse.arcs.size() > 1) {
    EXPECT_EQ(finer.arcs.size(), 2 * coarse.arcs.size());
    EXPECT_GT(coarse.deviation / finer.deviation, 5.0);
  }
  // too few arcs allowed: refused with the closest deviation found
  const SpiralArcs refused = arcs_along_spiral(wide, 1e-9, 4);
  EXPECT_FALSE(refused.outcome.ok());
  EXPECT_GT(refused.deviation, 1e-9);
  EXPECT_NE(refused.outcome.message.find("no chain of at most 4 tangent arcs"), std::string::npos) << refused.outcome.message;
  // degenerate spirals are refused, not turned into NaN
  Spiral zero = s;
  zero.r1 = 0;
  EXPECT_FALSE(arcs_along_spiral(zero, 1e-6, 64).outcome.ok());
  zero = s;
  zero.sweep = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(arcs_along_spiral(zero, 1e-6, 64).outcome.ok());
}

}  // namespace
}  // namespace blendbench
