// scenarios/three_corners.yaml planned with every method: what results/figures/three_corners.png
// (tools/make_figures.sh) shows, asserted on the blended path itself. The program has a
// line-line corner (C0, 90 deg), a line-arc corner (C1, 53.13 deg) and an arc-arc corner (C2,
// 69.39 deg); every variant is matched to a 2 mm worst-corner deviation (see the scenario file).

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <ostream>
#include <string>
#include <vector>

#include "support/chain_distance.hpp"
#include "support/property.hpp"
#include "blendbench/core/units.hpp"
#include "blendbench/corner/blend.hpp"
#include "blendbench/io/scenario.hpp"

namespace blendbench {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kG1 = 1e-9;               // rad: tangent jump at a smooth junction
constexpr double kKinkAngle = 1e-12;       // rad: a reported kink angle against the hand-derived one
constexpr double kPosition = 1e-9;         // junction gap / path length
constexpr double kG2 = 1e-7;               // curvature-vector jump / curvature scale (as the method tests)
constexpr double kUnitTangent = 1e-9;      // | |t| - 1 |
constexpr double kDeviationSlack = 1e-9;   // m: tolerance overshoot allowed (biclothoid's own test uses the same)
constexpr double kDeviationAgree = 1e-7;   // m: reported deviation against the independent measure
constexpr double kWorstDeviation = 2 * kMm;  // m: the scenario's matched worst-corner deviation
constexpr double kSampleStep = 0.05 * kMm;   // m: the spacing `blendbench path` samples at
constexpr double kPeakSampled = 1e-3;        // relative: a sampled curvature peak against kappa_max
constexpr double kArcStep = 0.5;             // an arc transition's curvature step / its curvature (0.86 at least here)

// The corners' deflections, from the scenario's directions: C0 +x to +y; C1 +y to (0.8, 0.6),
// the clockwise arc's start tangent; C2 (0.6, -0.8), its end tangent, to (0.96, 0.28), the
// counter-clockwise arc's start tangent.
const std::array<double, 3> kDeflection = {kPi / 2, std::acos(0.6), std::acos(0.6 * 0.96 - 0.8 * 0.28)};

// What each variant's corner reports say (case and documented fallback per corner).
struct Expected {
  std::string variant;
  Method method;
  std::array<const char*, 3> cases;
  std::array<const char*, 3> fallbacks;
};

const std::vector<Expected>& expectations() {
  static const std::vector<Expected> all = {
      {"exact_stop", Method::kNone, {"exact_stop", "exact_stop", "exact_stop"}, {"", "", ""}},
      {"arc", Method::kArc, {"regular", "regular", "regular"}, {"", "", ""}},
      {"bezier", Method::kBezier, {"regular", "regular", "regular"}, {"", "", ""}},
      // the clothoid method fits lines only; corners with an arc use the biclothoid fillet (seed 002, seed 004)
      {"clothoid", Method::kClothoid, {"regular", "regular", "regular"}, {"", "biclothoid", "biclothoid"}},
      {"clothoid_capped", Method::kClothoid, {"clothoid_arc_clothoid", "regular", "regular"}, {"", "biclothoid", "biclothoid"}},
      {"biclothoid", Method::kBiclothoid, {"regular", "regular", "regular"}, {"", "", ""}},
  };
  return all;
}

const Scenario& scenario() {
  static const Scenario sc = load_scenario(test::source_path("scenarios/three_corners.yaml"));
  return sc;
}

bool is_g2_method(Method m) { return m == Method::kBezier || m == Method::kClothoid || m == Method::kBiclothoid; }

// The blended path of one variant, with the program it came from.
struct Planned {
  Program program;
  Path path;
};

Planned plan(const std::string& variant) {
  Planned p{program_for(scenario(), find_variant(scenario(), variant)), {}};
  p.path = blend(p.program);
  return p;
}

// Test names and messages show the variant.
void PrintTo(const Expected& e, std::ostream* os) { *os << e.variant; }

class ThreeCorners : public ::testing::TestWithParam<Expected> {};

TEST(ThreeCornersScenario, HasOneVariantPerMethodAndExpectationsForAll) {
  std::vector<std::string> names;
  for (const Variant& v : scenario().variants) names.push_back(v.name);
  std::vector<std::string> expected;
  for (const Expected& e : expectations()) expected.push_back(e.variant);
  EXPECT_EQ(names, expected);
  ASSERT_EQ(scenario().program.moves.size(), 4u);
}

TEST_P(ThreeCorners, ReportsNameTheCaseOfEveryCorner) {
  const Expected& e = GetParam();
  const Planned p = plan(e.variant);
  ASSERT_EQ(p.path.corners.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    const CornerReport& r = p.path.corners[k];
    EXPECT_EQ(r.index, k);
    EXPECT_EQ(r.method, e.method) << "corner " << k;
    EXPECT_EQ(to_string(r.corner_case), e.cases[k]) << "corner " << k;
    EXPECT_EQ(to_string(r.fallback), e.fallbacks[k]) << "corner " << k;
    EXPECT_TRUE(r.note.empty()) << "corner " << k << ": " << r.note;
    EXPECT_EQ(r.stop, e.method == Method::kNone) << "corner " << k;
  }
}

// G1 at every junction but the reported kinks; the exact stop keeps exactly the three corners,
// with the hand-derived deflections, and every blended variant none.
TEST_P(ThreeCorners, TangentContinuousExceptReportedKinks) {
  const Expected& e = GetParam();
  const Planned p = plan(e.variant);
  const auto& pieces = p.path.pieces();
  std::vector<double> kinks;
  for (std::size_t k = 1; k < pieces.size(); ++k) {
    const Segment& a = pieces[k - 1].segment;
    const Segment& b = pieces[k].segment;
    const double gap = (end_point(a) - start_point(b)).norm();
    EXPECT_LE(gap, kPosition * p.path.length()) << "junction " << k;
    const double turn = angle_between(tangent(a, length(a)), tangent(b, 0.0));
    // two moves meeting without a transition: the report must say the corner is left as a kink
    const bool bare = pieces[k - 1].move >= 0 && pieces[k].move == pieces[k - 1].move + 1;
    if (bare) {
      const CornerReport& r = p.path.corners[pieces[k - 1].move];
      EXPECT_TRUE(r.method == Method::kNone || r.fallback == Fallback::kExactStop) << "junction " << k;
      EXPECT_TRUE(r.stop && pieces[k].stop_before) << "junction " << k;
      EXPECT_NEAR(pieces[k].kink_angle, turn, kKinkAngle) << "junction " << k;
      kinks.push_back(turn);
    } else {
      EXPECT_LE(turn, kG1) << "junction " << k;
    }
  }
  if (e.method == Method::kNone) {
    ASSERT_EQ(kinks.size(), 3u);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(kinks[k], kDeflection[k], kKinkAngle) << "corner " << k;
  } else {
    EXPECT_TRUE(kinks.empty());
  }
}

// Curvature-vector continuity at both ends of every piece of a bezier, clothoid or biclothoid
// transition (and between its pieces); the arc method is G1 only and its steps are what the
// curvature plot shows.
TEST_P(ThreeCorners, CurvatureContinuityWhereTheMethodPromisesIt) {
  const Expected& e = GetParam();
  if (e.method == Method::kNone) GTEST_SKIP() << "no transitions";
  const Planned p = plan(e.variant);
  const auto& pieces = p.path.pieces();
  int transition_junctions = 0;
  for (std::size_t k = 1; k < pieces.size(); ++k) {
    const int corner = std::max(pieces[k - 1].corner, pieces[k].corner);
    if (corner < 0) continue;
    ++transition_junctions;
    const Segment& a = pieces[k - 1].segment;
    const Segment& b = pieces[k].segment;
    const Vec3 ka = curvature_vector(a, length(a));
    const Vec3 kb = curvature_vector(b, 0.0);
    const CornerReport& r = p.path.corners[corner];
    const double scale = std::max({ka.norm(), kb.norm(), 1.0 / std::max(r.trim_in, r.trim_out)});
    if (is_g2_method(e.method)) {
      EXPECT_LE((ka - kb).norm() / scale, kG2) << "junction " << k << " (corner " << corner << ")";
    } else {
      // a circular transition steps from the neighbour's curvature to its own 1 / radius
      EXPECT_GE((ka - kb).norm(), kArcStep * r.kappa_max) << "junction " << k << " (corner " << corner << ")";
    }
  }
  EXPECT_GE(transition_junctions, 6);
}

// Deviation of each transition from the programmed path it replaces, measured independently
// (test::Chain) in both directions: within the tolerance for clothoid and biclothoid, within the
// matched 2 mm for every method, and what the report says.
TEST_P(ThreeCorners, DeviationWithinTheToleranceAndAsReported) {
  const Expected& e = GetParam();
  if (e.method == Method::kNone) GTEST_SKIP() << "no transitions";
  const Planned p = plan(e.variant);
  const Variant& variant = find_variant(scenario(), e.variant);
  for (int k = 0; k < 3; ++k) {
    const CornerReport& r = p.path.corners[k];
    std::vector<Segment> transition;
    for (const PathPiece& piece : p.path.pieces()) {
      if (piece.corner == k) transition.push_back(piece.segment);
    }
    ASSERT_FALSE(transition.empty()) << "corner " << k;
    const Primitive& in = p.program.moves[k].geometry;
    const Primitive& out = p.program.moves[k + 1].geometry;
    const std::vector<Segment> replaced = {to_segment(sub_segment(in, length(in) - r.trim_in, length(in))),
                                           to_segment(sub_segment(out, 0.0, r.trim_out))};
    const test::Chain fillet(transition);
    const test::Chain programmed(replaced);
    const double measured = std::max(fillet.directed_to(programmed), programmed.directed_to(fillet));
    EXPECT_NEAR(measured, r.deviation, kDeviationAgree) << "corner " << k;
    EXPECT_LE(measured, kWorstDeviation + kDeviationSlack) << "corner " << k;
    if (e.method == Method::kClothoid || e.method == Method::kBiclothoid) {
      EXPECT_LE(measured, variant.transition->parameter + kDeviationSlack) << "corner " << k;
      EXPECT_LE(r.deviation, variant.transition->parameter + kDeviationSlack) << "corner " << k;
    }
  }
}

// The sampled path (as `blendbench path` writes it) is finite with unit tangents, and the
// reported transition length and peak curvature are those of the pieces.
TEST_P(ThreeCorners, SampledPathFiniteAndReportNumbersMatchIt) {
  const Expected& e = GetParam();
  const Planned p = plan(e.variant);
  std::array<double, 3> corner_length{};
  std::array<double, 3> corner_peak{};
  for (const PathPiece& piece : p.path.pieces()) {
    const double len = length(piece.segment);
    const int n = std::max(1, static_cast<int>(std::ceil(len / kSampleStep)));
    for (int i = 0; i <= n; ++i) {
      const double s = len * i / n;
      const Vec3 x = point(piece.segment, s);
      const Vec3 t = tangent(piece.segment, s);
      const Vec3 kv = curvature_vector(piece.segment, s);
      ASSERT_TRUE(x.allFinite() && t.allFinite() && kv.allFinite()) << "piece of move " << piece.move << ", s = " << s;
      ASSERT_NEAR(t.norm(), 1.0, kUnitTangent);
      if (piece.corner >= 0) corner_peak[piece.corner] = std::max(corner_peak[piece.corner], kv.norm());
    }
    if (piece.corner >= 0) corner_length[piece.corner] += len;
  }
  for (int k = 0; k < 3; ++k) {
    const CornerReport& r = p.path.corners[k];
    EXPECT_NEAR(corner_length[k], r.length, kPosition * p.path.length()) << "corner " << k;
    EXPECT_LE(corner_peak[k], r.kappa_max * (1 + kPeakSampled)) << "corner " << k;
    EXPECT_GE(corner_peak[k], r.kappa_max * (1 - kPeakSampled)) << "corner " << k;
  }
}

INSTANTIATE_TEST_SUITE_P(EveryMethod, ThreeCorners, ::testing::ValuesIn(expectations()),
                         [](const ::testing::TestParamInfo<Expected>& param) { return param.param.variant; });

}  // namespace
}  // namespace blendbench
