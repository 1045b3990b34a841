// Tests of the `arc` transition method (planner/corner/src/arc_blend.cpp): the corner distance rules of
// seed 001 (line to line) and seed 003 (arc to arc), each special case by a hand-derived example, then
// seeded random corners for the invariants (continuity, tangency, corner distance, no NaN).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <string>

#include "blendbench/corner/blend.hpp"
#include "blendbench/corner/corner.hpp"
#include "support/property.hpp"

namespace blendbench {
namespace {

constexpr double kPi = std::numbers::pi;
// m: exact values derived by hand, compared after a handful of floating-point operations
constexpr double kExact = 1e-14;
// relative to the corner size: position continuity at the junctions
constexpr double kPosRel = 1e-9;
// rad: tangent continuity (G1) at the junctions
constexpr double kG1 = 1e-9;

// Cases that leave a tangent kink at the corner (a zero-length transition).
const std::set<CornerCase> kKinkCases = {CornerCase::kZeroDistance, CornerCase::kIntersection, CornerCase::kReversal, CornerCase::kNearReversal,
                                         CornerCase::kSameCircleOppositeDirection};

// A circular arc starting at `start` around `center`, counter-clockwise about `axis`.
Arc arc_from(const Vec3& center, const Vec3& start, const Vec3& axis, double sweep) {
  Arc arc;
  arc.center = center;
  arc.radius = (start - center).norm();
  arc.u = (start - center) / arc.radius;
  arc.v = axis.normalized().cross(arc.u);
  arc.sweep = sweep;
  return arc;
}

CornerInput make_corner(const Primitive& in, const Primitive& out, double d,
                        BufferMode buffer = BufferMode::kBlendingLow) {
  CornerInput corner;
  corner.in = in;
  corner.out = out;
  corner.in_available = length(in);
  corner.out_available = length(out);
  corner.spec.method = Method::kArc;
  corner.spec.parameter = d;
  corner.buffer = buffer;
  corner.name = "test corner";
  return corner;
}

const Arc& as_arc(const Segment& seg) { return std::get<Arc>(seg); }

// Largest position gap and tangent angle over the junctions in -> transition -> out.
struct Joins {
  double gap = 0;    // m
  double angle = 0;  // rad
  double size = 0;   // m: the corner size (largest trim or transition length)
};

Joins measure_joins(const CornerInput& corner, const CornerFit& fit) {
  const double len_in = length(corner.in);
  Vec3 p = point(corner.in, len_in - fit.trim_in);
  Vec3 t = tangent(corner.in, len_in - fit.trim_in);
  Joins joins;
  joins.size = std::max(fit.trim_in, fit.trim_out);
  double transition_length = 0;
  for (const Segment& seg : fit.transition) {
    joins.gap = std::max(joins.gap, (start_point(seg) - p).norm());
    joins.angle = std::max(joins.angle, angle_between(t, tangent(seg, 0.0)));
    p = end_point(seg);
    t = tangent(seg, length(seg));
    transition_length += length(seg);
  }
  joins.size = std::max(joins.size, transition_length);
  joins.gap = std::max(joins.gap, (point(corner.out, fit.trim_out) - p).norm());
  joins.angle = std::max(joins.angle, angle_between(t, tangent(corner.out, fit.trim_out)));
  return joins;
}

// ---- line to line (seed 001 (controller manual, line-to-line))

TEST(ArcBlendLineLine, RightAngleFilletHasRadiusEqualToTheCornerDistance) {
  // theta = 90 deg: r = d / tan(45 deg) = d, centre at (0.09, 0.01), sweep pi/2, both trims d
  const CornerFit fit = fit_arc_corner(make_corner(Line{{0, 0, 0}, {0.1, 0, 0}}, Line{{0.1, 0, 0}, {0.1, 0.1, 0}}, 0.01));
  ASSERT_TRUE(fit.outcome.ok());
  EXPECT_EQ(fit.corner_case, CornerCase::kRegular);
  EXPECT_DOUBLE_EQ(fit.trim_in, 0.01);
  EXPECT_DOUBLE_EQ(fit.trim_out, 0.01);
  EXPECT_DOUBLE_EQ(fit.parameter_used, 0.01);
  EXPECT_FALSE(fit.stop);
  ASSERT_EQ(fit.transition.size(), 1u);
  const Arc& arc = as_arc(fit.transition[0]);
  EXPECT_NEAR(arc.radius, 0.01, kExact);
  EXPECT_NEAR(arc.sweep, kPi / 2, 1e-15);
  EXPECT_TRUE(arc.center.isApprox(Vec3(0.09, 0.01, 0), 1e-14));
  EXPECT_TRUE(end_point(arc).isApprox(Vec3(0.1, 0.01, 0), 1e-14));
}

TEST(ArcBlendLineLine, SixtyDegreeTurnGivesRadiusDSqrt3) {
  // theta = 60 deg: r = d / tan(30 deg) = d sqrt(3), arc length r pi / 3
  const double d = 0.005;
  const Vec3 c(0.1, 0, 0);
  const Vec3 dir(std::cos(kPi / 3), std::sin(kPi / 3), 0);
  const CornerFit fit = fit_arc_corner(make_corner(Line{{0, 0, 0}, c}, Line{c, c + 0.1 * dir}, d));
  ASSERT_EQ(fit.transition.size(), 1u);
  EXPECT_NEAR(as_arc(fit.transition[0]).radius, d * std::sqrt(3.0), kExact);
  EXPECT_NEAR(length(fit.transition[0]), d * std::sqrt(3.0) * kPi / 3, kExact);
}

TEST(ArcBlendLineLine, CollinearInsertsALinearTransitionOfTwiceTheCornerDistance) {
  // seed 001 fig. 7-4: path unchanged, a line from 0.09 to 0.11 inserted
  const CornerFit fit = fit_arc_corner(make_corner(Line{{0, 0, 0}, {0.1, 0, 0}}, Line{{0.1, 0, 0}, {0.3, 0, 0}}, 0.01));
  ASSERT_TRUE(fit.outcome.ok());
  EXPECT_EQ(fit.corner_case, CornerCase::kCollinear);
  EXPECT_DOUBLE_EQ(fit.trim_in, 0.01);
  EXPECT_DOUBLE_EQ(fit.trim_out, 0.01);
  EXPECT_FALSE(fit.stop);
  ASSERT_EQ(fit.transition.size(), 1u);
  const Line& line = std::get<Line>(fit.transition[0]);
  EXPECT_TRUE(line.p0.isApprox(Vec3(0.09, 0, 0), 1e-15));
  EXPECT_TRUE(line.p1.isApprox(Vec3(0.11, 0, 0), 1e-15));
}

TEST(ArcBlendLineLine, CollinearWithZeroDistanceInsertsNothing) {
  const CornerFit fit = fit_arc_corner(
      make_corner(Line{{0, 0, 0}, {0.1, 0, 0}}, Line{{0.1, 0, 0}, {0.3, 0, 0}}, 0.0, BufferMode::kBuffered));
  EXPECT_EQ(fit.corner_case, CornerCase::kCollinear);
  EXPECT_TRUE(fit.transition.empty());
  EXPECT_EQ(fit.trim_in, 0.0);
  EXPECT_EQ(fit.trim_out, 0.0);
  EXPECT_FALSE(fit.stop);  // no kink: nothing to stop for
}

TEST(ArcBlendLineLine, ReversalShortensBothMovesToTheSamePointAndStopsWhenBuffered) {
  // seed 001 fig. 7-3: x: 0 -> 0.1 -> 0.05 with d = 0.01; both moves end/start at x = 0.09
  const Line in{{0, 0, 0}, {0.1, 0, 0}};
  const Line out{{0.1, 0, 0}, {0.05, 0, 0}};
  const CornerFit buffered = fit_arc_corner(make_corner(in, out, 0.01, BufferMode::kBuffered));
  ASSERT_TRUE(buffered.outcome.ok());
  EXPECT_EQ(buffered.corner_case, CornerCase::kReversal);
  EXPECT_DOUBLE_EQ(buffered.trim_in, 0.01);
  EXPECT_DOUBLE_EQ(buffered.trim_out, 0.01);
  EXPECT_TRUE(buffered.transition.empty());
  EXPECT_TRUE(buffered.stop);
  EXPECT_TRUE(point(Primitive(in), 0.09).isApprox(point(Primitive(out), 0.01), 1e-15));

  const CornerFit blending = fit_arc_corner(make_corner(in, out, 0.01, BufferMode::kBlendingLow));
  EXPECT_EQ(blending.corner_case, CornerCase::kReversal);
  EXPECT_FALSE(blending.stop);
}

TEST(ArcBlendLineLine, ZeroDistanceInsertsNothingAndStopsOnlyWhenBuffered) {
  // seed 001 fig. 7-5
  const Line in{{0, 0, 0}, {0.1, 0, 0}};
  const Line out{{0.1, 0, 0}, {0.1, 0.1, 0}};
  const CornerFit buffered = fit_arc_corner(make_corner(in, out, 0.0, BufferMode::kBuffered));
  EXPECT_EQ(buffered.corner_case, CornerCase::kZeroDistance);
  EXPECT_TRUE(buffered.transition.empty());
  EXPECT_EQ(buffered.trim_in, 0.0);
  EXPECT_EQ(buffered.trim_out, 0.0);
  EXPECT_TRUE(buffered.stop);
  const CornerFit blending = fit_arc_corner(make_corner(in, out, 0.0, BufferMode::kBlendingNext));
  EXPECT_EQ(blending.corner_case, CornerCase::kZeroDistance);
  EXPECT_FALSE(blending.stop);
}

TEST(ArcBlendLineLine, CornerDistanceIsShrunkToTheAvailableLengthWithANote) {
  CornerInput corner = make_corner(Line{{0, 0, 0}, {0.1, 0, 0}}, Line{{0.1, 0, 0}, {0.1, 0.008, 0}}, 0.01);
  corner.out_available = 0.004;  // half the next move: it is blended at both ends
  const CornerFit fit = fit_arc_corner(corner);
  ASSERT_TRUE(fit.outcome.ok());
  EXPECT_DOUBLE_EQ(fit.parameter_used, 0.004);
  EXPECT_DOUBLE_EQ(fit.trim_in, 0.004);
  EXPECT_DOUBLE_EQ(fit.trim_out, 0.004);
  EXPECT_NE(fit.note.text().find("shrunk from 10 mm to 4 mm"), std::string::npos) << fit.note;
  EXPECT_NEAR(as_arc(fit.transition[0]).radius, 0.004, kExact);
}

// ---- line to arc and arc to line (seed 003 rule, a line counts as infinite radius)

// Line along +x into C = 0, arc out of C heading +y, counter-clockwise, radius R = 0.02 (centre
// (-R, 0)); d = 0.01 shortens the line: T1 = (-d, 0), n1 = +y, w = T1 - centre = (R - d, 0):
// rho = (R^2 - (R - d)^2) / (2 R) = d - d^2 / (2R) = 0.0075, transition centre (-0.01, 0.0075);
// n2 = (O - centre) / (rho - R) = (-0.8, -0.6), T2 = centre - R n2 = (-0.004, 0.012): the arc is
// trimmed by R atan2(3, 4); the transition turns from 0 to 90 + 36.87 deg = pi - atan2(4, 3).
TEST(ArcBlendLineArc, LineIsShortenedByDAndTheTransitionIsTangentToTheArc) {
  const Line in{{-0.05, 0, 0}, {0, 0, 0}};
  const Arc out = arc_from({-0.02, 0, 0}, {0, 0, 0}, Vec3::UnitZ(), kPi / 2);
  const CornerFit fit = fit_arc_corner(make_corner(in, out, 0.01));
  ASSERT_TRUE(fit.outcome.ok()) << fit.outcome.message;
  EXPECT_EQ(fit.corner_case, CornerCase::kRegular);
  EXPECT_TRUE(fit.note.empty()) << fit.note;
  EXPECT_NEAR(fit.trim_in, 0.01, kExact);
  EXPECT_NEAR(fit.trim_out, 0.02 * std::atan2(3.0, 4.0), kExact);
  ASSERT_EQ(fit.transition.size(), 1u);
  const Arc& arc = as_arc(fit.transition[0]);
  EXPECT_NEAR(arc.radius, 0.0075, kExact);
  EXPECT_TRUE(arc.center.isApprox(Vec3(-0.01, 0.0075, 0), 1e-13));
  EXPECT_NEAR(arc.sweep, kPi - std::atan2(4.0, 3.0), 1e-13);
  EXPECT_TRUE(end_point(arc).isApprox(Vec3(-0.004, 0.012, 0), 1e-13));
}

TEST(ArcBlendLineArc, ArcIntoLineMirrorsTheConstruction) {
  // the same corner travelled backwards: the arc (clockwise) comes in, the line goes out
  const Arc in = arc_from({-0.02, 0, 0}, {-0.02, 0.02, 0}, -Vec3::UnitZ(), kPi / 2);
  const Line out{{0, 0, 0}, {-0.05, 0, 0}};
  const CornerFit fit = fit_arc_corner(make_corner(in, out, 0.01));
  ASSERT_TRUE(fit.outcome.ok()) << fit.outcome.message;
  EXPECT_EQ(fit.corner_case, CornerCase::kRegular);
  EXPECT_NEAR(fit.trim_in, 0.02 * std::atan2(3.0, 4.0), kExact);
  EXPECT_NEAR(fit.trim_out, 0.01, kExact);
  const Arc& arc = as_arc(fit.transition[0]);
  EXPECT_NEAR(arc.radius, 0.0075, kExact);
  EXPECT_TRUE(arc.center.isApprox(Vec3(-0.01, 0.0075, 0), 1e-13));
  EXPECT_TRUE(start_point(arc).isApprox(Vec3(-0.004, 0.012, 0), 1e-13));
  EXPECT_TRUE(end_point(arc).isApprox(Vec3(-0.01, 0, 0), 1e-13));
}

TEST(ArcBlendLineArc, ShortArcShrinksTheCornerDistanceToWhereTheTangencyFits) {
  // same corner, only 5 mm of the arc available: the tangency angle psi = s2 / R = 0.25 solves
  // tan(psi) = rho / (R - d) with rho = d - d^2 / (2R):  d^2 / (2R) - d (1 + tan psi) + R tan psi = 0
  const double r = 0.02;
  const double tp = std::tan(0.25);
  const double d_expected = r * ((1 + tp) - std::sqrt((1 + tp) * (1 + tp) - 2 * tp));
  CornerInput corner = make_corner(Line{{-0.05, 0, 0}, {0, 0, 0}}, arc_from({-r, 0, 0}, {0, 0, 0}, Vec3::UnitZ(), kPi / 2), 0.01);
  corner.out_available = 0.005;
  const CornerFit fit = fit_arc_corner(corner);
  ASSERT_TRUE(fit.outcome.ok());
  EXPECT_NEAR(fit.parameter_used, d_expected, 1e-12);
  EXPECT_NEAR(fit.trim_in, d_expected, 1e-12);
  EXPECT_NEAR(fit.trim_out, 0.005, 1e-12);
  EXPECT_NE(fit.note.text().find("shrunk"), std::string::npos);
  const Joins joins = measure_joins(corner, fit);
  EXPECT_LE(joins.gap, kPosRel * joins.size);
  EXPECT_LE(joins.angle, kG1);
}

TEST(ArcBlendLineArc, TangentLineIntoArcIsLeftUnchanged) {
  // G1 corner (curvature jump only): the line's last d becomes the transition, the arc keeps
  // its start
  const Line in{{-0.05, 0, 0}, {0, 0, 0}};
  const Arc out = arc_from({0, 0.02, 0}, {0, 0, 0}, Vec3::UnitZ(), kPi / 2);
  const CornerFit fit = fit_arc_corner(make_corner(in, out, 0.01, BufferMode::kBuffered));
  ASSERT_TRUE(fit.outcome.ok());
  EXPECT_EQ(fit.corner_case, CornerCase::kTangent);
  EXPECT_DOUBLE_EQ(fit.trim_in, 0.01);
  EXPECT_EQ(fit.trim_out, 0.0);
  EXPECT_FALSE(fit.stop);
  const Line& line = std::get<Line>(fit.transition[0]);
  EXPECT_TRUE(line.p0.isApprox(Vec3(-0.01, 0, 0), 1e-15));
  EXPECT_LE(line.p1.norm(), 1e-17);
}

TEST(ArcBlendLineArc, NearTangentCornerWithoutA003CircleShortensTheArcInstead) {
  // the arc leaves 1e-4 rad to the left of the line and curves left (R = 20 mm): a circle
  // tangent to the line 10 mm back and to the arc exists only for d below about R * theta, so
  // the arc is shortened by d and the tangency found on the line
  const double theta = 1e-4;
  const Line in{{-0.05, 0, 0}, {0, 0, 0}};
  const Vec3 m(-std::sin(theta), std::cos(theta), 0);
  const Arc out = arc_from(0.02 * m, {0, 0, 0}, Vec3::UnitZ(), kPi / 2);
  const CornerInput corner = make_corner(in, out, 0.01);
  const CornerFit fit = fit_arc_corner(corner);
  ASSERT_TRUE(fit.outcome.ok()) << fit.outcome.message;
  EXPECT_EQ(fit.fallback, Fallback::kSmallerRadiusShortened);
  EXPECT_DOUBLE_EQ(fit.trim_out, 0.01);
  EXPECT_DOUBLE_EQ(fit.parameter_used, 0.01);
  EXPECT_LT(fit.trim_in, 0.01);
  const Joins joins = measure_joins(corner, fit);
  EXPECT_LE(joins.gap, kPosRel * joins.size);
  EXPECT_LE(joins.angle, kG1);
}

TEST(ArcBlendLineArc, NonPlanarCornerIsJoinedByABiarc) {
  // line along +x, arc in the y-z plane (axis +x) leaving C heading -z: no circle is tangent
  // to both; both moves lose d and two circular arcs join them G1
  const Line in{{-0.05, 0, 0}, {0, 0, 0}};
  const Arc out = arc_from({0, 0.01, 0}, {0, 0, 0}, Vec3::UnitX(), kPi);
  ASSERT_TRUE(tangent(out, 0).isApprox(Vec3(0, 0, -1), 1e-15));
  const CornerInput corner = make_corner(in, out, 0.005, BufferMode::kBuffered);
  const CornerFit fit = fit_arc_corner(corner);
  ASSERT_TRUE(fit.outcome.ok()) << fit.outcome.message;
  EXPECT_EQ(fit.corner_case, CornerCase::kNonPlanar);
  EXPECT_EQ(fit.fallback, Fallback::kBiarc);
  EXPECT_DOUBLE_EQ(fit.trim_in, 0.005);
  EXPECT_DOUBLE_EQ(fit.trim_out, 0.005);
  EXPECT_FALSE(fit.stop);
  ASSERT_EQ(fit.transition.size(), 2u);
  for (const Segment& seg : fit.transition) {
    ASSERT_TRUE(std::holds_alternative<Arc>(seg));
    EXPECT_EQ(as_arc(seg).rise, 0.0);
  }
  // the two arcs have equal tangent lengths, so the second starts where the first ends and the
  // chain is G1 at all three junctions
  const Joins joins = measure_joins(corner, fit);
  EXPECT_LE(joins.gap, kPosRel * joins.size);
  EXPECT_LE(joins.angle, kG1);
}

TEST(ArcBlendLineArc, HelixIsTreatedAsNonPlanar) {
  // a helix is no circle: the biarc fallback joins it G1
  const Line in{{-0.05, 0, 0}, {0, 0, 0}};
  Arc helix = arc_from({-0.02, 0, 0}, {0, 0, 0}, Vec3::UnitZ(), kPi);
  helix.rise = 0.01;
  const CornerInput corner = make_corner(in, helix, 0.005);
  const CornerFit fit = fit_arc_corner(corner);
  ASSERT_TRUE(fit.outcome.ok()) << fit.outcome.message;
  EXPECT_EQ(fit.corner_case, CornerCase::kNonPlanar);
  EXPECT_EQ(fit.fallback, Fallback::kBiarc);
  const Joins joins = measure_joins(corner, fit);
  EXPECT_LE(joins.gap, kPosRel * joins.size);
  EXPECT_LE(joins.angle, kG1);
}

// ---- arc to arc (seed 003 (controller manual, arc-to-arc))

// A: centre 0, radius 0.05, counter-clockwise, ends at C = (0.03, 0.04). B: centre (0.03, 0.01),
// radius 0.03, counter-clockwise, leaves C heading -x. d = arc length of A from T1 = (0.04, 0.03)
// to C = 0.05 (atan2(4, 3) - atan2(3, 4)). n1 at T1 = (-0.8, -0.6), w = T1 - centre_B =
// (0.01, 0.02), |w|^2 = 5e-4, n1.w = -0.02: rho = (9e-4 - 5e-4) / (2 (-0.02 + 0.03)) = 0.02,
// centre O = (0.024, 0.018), |O - centre_B| = 0.01 = |rho - 0.03| (internal tangency),
// T2 = (0.012, 0.034); B is trimmed by 0.03 atan2(3, 4); the transition sweeps pi/2.
TEST(ArcBlendArcArc, LargerArcIsShortenedByDAndTheSmallerTrimmedToTheTangency) {
  const Arc in = arc_from({0, 0, 0}, {0.05, 0, 0}, Vec3::UnitZ(), std::atan2(4.0, 3.0));
  const Arc out = arc_from({0.03, 0.01, 0}, {0.03, 0.04, 0}, Vec3::UnitZ(), kPi / 2);
  const double d = 0.05 * (std::atan2(4.0, 3.0) - std::atan2(3.0, 4.0));
  const CornerFit fit = fit_arc_corner(make_corner(in, out, d));
  ASSERT_TRUE(fit.outcome.ok()) << fit.outcome.message;
  EXPECT_EQ(fit.corner_case, CornerCase::kRegular);
  EXPECT_NEAR(fit.trim_in, d, kExact);
  EXPECT_NEAR(fit.trim_out, 0.03 * std::atan2(3.0, 4.0), kExact);
  const Arc& arc = as_arc(fit.transition[0]);
  EXPECT_NEAR(arc.radius, 0.02, kExact);
  EXPECT_TRUE(arc.center.isApprox(Vec3(0.024, 0.018, 0), 1e-13));
  EXPECT_NEAR(arc.sweep, kPi / 2, 1e-13);
  EXPECT_TRUE(end_point(arc).isApprox(Vec3(0.012, 0.034, 0), 1e-13));
}

TEST(ArcBlendArcArc, ZeroDistanceLeavesTheCornerAndStopsWhenBuffered) {
  const Arc in = arc_from({0, 0, 0}, {0.05, 0, 0}, Vec3::UnitZ(), std::atan2(4.0, 3.0));
  const Arc out = arc_from({0.03, 0.01, 0}, {0.03, 0.04, 0}, Vec3::UnitZ(), kPi / 2);
  const CornerFit fit = fit_arc_corner(make_corner(in, out, 0.0, BufferMode::kBuffered));
  EXPECT_EQ(fit.corner_case, CornerCase::kZeroDistance);
  EXPECT_TRUE(fit.transition.empty());
  EXPECT_EQ(fit.trim_in, 0.0);
  EXPECT_EQ(fit.trim_out, 0.0);
  EXPECT_TRUE(fit.stop);
}

// A: centre 0, radius 0.02, counter-clockwise, ends at C = (0.02, 0). B: centre (0.02, -0.01),
// radius 0.01, counter-clockwise from C. The circles also meet at X = (0.012, -0.016), which A
// passes atan2(4, 3) rad before C, and B reaches after pi - atan2(4, 3) rad.
TEST(ArcBlendArcArc, IntersectionDistanceGivesAZeroLengthTransitionAtTheOtherIntersection) {
  const Arc in = arc_from({0, 0, 0}, {-0.02, 0, 0}, Vec3::UnitZ(), kPi);
  const Arc out = arc_from({0.02, -0.01, 0}, {0.02, 0, 0}, Vec3::UnitZ(), 1.5 * kPi);
  const double d = 0.02 * std::atan2(4.0, 3.0);
  const CornerInput corner = make_corner(in, out, d, BufferMode::kBuffered);
  const CornerFit fit = fit_arc_corner(corner);
  ASSERT_TRUE(fit.outcome.ok()) << fit.outcome.message;
  EXPECT_EQ(fit.corner_case, CornerCase::kIntersection);
  EXPECT_TRUE(fit.transition.empty());
  EXPECT_NEAR(fit.trim_in, d, kExact);
  EXPECT_NEAR(fit.trim_out, 0.01 * (kPi - std::atan2(4.0, 3.0)), 1e-13);
  EXPECT_TRUE(fit.stop);
  EXPECT_TRUE(point(Primitive(in), length(in) - fit.trim_in).isApprox(Vec3(0.012, -0.016, 0), 1e-13));
  EXPECT_TRUE(point(Primitive(out), fit.trim_out).isApprox(Vec3(0.012, -0.016, 0), 1e-12));

  CornerInput blending = corner;
  blending.buffer = BufferMode::kBlendingHigh;
  EXPECT_FALSE(fit_arc_corner(blending).stop);
}

TEST(ArcBlendArcArc, DistancesNearTheIntersectionGiveSmallArcsThatShrinkToIt) {
  // continuity: approaching the intersection distance the transition radius goes to zero
  const Arc in = arc_from({0, 0, 0}, {-0.02, 0, 0}, Vec3::UnitZ(), kPi);
  const Arc out = arc_from({0.02, -0.01, 0}, {0.02, 0, 0}, Vec3::UnitZ(), 1.5 * kPi);
  const double d_int = 0.02 * std::atan2(4.0, 3.0);
  double previous = 1;
  for (const double gap : {1e-3, 1e-5, 1e-7, 1e-9}) {
    const CornerInput corner = make_corner(in, out, d_int - gap);
    const CornerFit fit = fit_arc_corner(corner);
    ASSERT_TRUE(fit.outcome.ok());
    ASSERT_EQ(fit.transition.size(), 1u);
    const double radius = as_arc(fit.transition[0]).radius;
    EXPECT_LT(radius, previous);
    previous = radius;
    const Joins joins = measure_joins(corner, fit);
    EXPECT_LE(joins.gap, kPosRel * joins.size + 1e-16);
    EXPECT_LE(joins.angle, kG1);
  }
  EXPECT_LT(previous, 1e-8);
}

TEST(ArcBlendArcArc, TangentArcsInOppositeDirectionsReplaceDOfTheLargerArc) {
  // S-bend, G1 at C = 0 heading +x: A counter-clockwise radius 0.02, B clockwise radius 0.01.
  // seed 003: a portion d of the larger arc is replaced by an arc; the path is unchanged
  const Arc in = arc_from({0, 0.02, 0}, {-0.02, 0.02, 0}, Vec3::UnitZ(), kPi / 2);
  const Arc out = arc_from({0, -0.01, 0}, {0, 0, 0}, -Vec3::UnitZ(), kPi / 2);
  const CornerFit fit = fit_arc_corner(make_corner(in, out, 0.005, BufferMode::kBuffered));
  ASSERT_TRUE(fit.outcome.ok());
  EXPECT_EQ(fit.corner_case, CornerCase::kTangentOpposite);
  EXPECT_DOUBLE_EQ(fit.trim_in, 0.005);
  EXPECT_EQ(fit.trim_out, 0.0);
  EXPECT_FALSE(fit.stop);
  ASSERT_EQ(fit.transition.size(), 1u);
  const Arc& arc = as_arc(fit.transition[0]);
  EXPECT_NEAR(arc.radius, 0.02, kExact);
  EXPECT_NEAR(length(arc), 0.005, kExact);
  EXPECT_LE(end_point(arc).norm(), 1e-17);

  // the larger arc outgoing: it loses d at its start
  const Arc small_in = arc_from({0, 0.01, 0}, {-0.01, 0.01, 0}, Vec3::UnitZ(), kPi / 2);
  const Arc large_out = arc_from({0, -0.02, 0}, {0, 0, 0}, -Vec3::UnitZ(), kPi / 2);
  const CornerFit swapped = fit_arc_corner(make_corner(small_in, large_out, 0.005));
  EXPECT_EQ(swapped.corner_case, CornerCase::kTangentOpposite);
  EXPECT_EQ(swapped.trim_in, 0.0);
  EXPECT_DOUBLE_EQ(swapped.trim_out, 0.005);

  // equal radii: seed 003 says the incoming arc counts as the larger one
  const Arc equal_out = arc_from({0, -0.02, 0}, {0, 0, 0}, -Vec3::UnitZ(), kPi / 2);
  const CornerFit equal = fit_arc_corner(make_corner(in, equal_out, 0.005));
  EXPECT_EQ(equal.corner_case, CornerCase::kTangentOpposite);
  EXPECT_DOUBLE_EQ(equal.trim_in, 0.005);
  EXPECT_EQ(equal.trim_out, 0.0);
}

// A: centre 0, radius 0.02, counter-clockwise through T1 = (0, -0.02) (heading +x) to
// C = (0.012, -0.016). B: centre (0.02, -0.01), radius 0.01, counter-clockwise from C; its
// lowest point (0.02, -0.02) also heads +x. With d = 0.02 (pi/2 - atan2(4, 3)) the transition
// is the common tangent y = -0.02: infinite radius, a line of length 0.02.
TEST(ArcBlendArcArc, LineSegmentWhenTheTransitionRadiusIsInfinite) {
  const Arc in = arc_from({0, 0, 0}, {-0.02, 0, 0}, Vec3::UnitZ(), kPi - std::atan2(4.0, 3.0));
  const Arc out = arc_from({0.02, -0.01, 0}, {0.012, -0.016, 0}, Vec3::UnitZ(), kPi / 2);
  ASSERT_TRUE(end_point(in).isApprox(Vec3(0.012, -0.016, 0), 1e-15));
  const double d = 0.02 * (kPi / 2 - std::atan2(4.0, 3.0));
  const CornerInput corner = make_corner(in, out, d, BufferMode::kBuffered);
  const CornerFit fit = fit_arc_corner(corner);
  ASSERT_TRUE(fit.outcome.ok()) << fit.outcome.message;
  EXPECT_EQ(fit.corner_case, CornerCase::kLineSegment);
  EXPECT_FALSE(fit.stop);  // G1 at both ends: nothing to stop for
  EXPECT_NEAR(fit.trim_in, d, kExact);
  EXPECT_NEAR(fit.trim_out, 0.01 * std::atan2(4.0, 3.0), 1e-13);
  ASSERT_EQ(fit.transition.size(), 1u);
  const Line& line = std::get<Line>(fit.transition[0]);
  EXPECT_TRUE(line.p0.isApprox(Vec3(0, -0.02, 0), 1e-13));
  EXPECT_TRUE(line.p1.isApprox(Vec3(0.02, -0.02, 0), 1e-13));
  const Joins joins = measure_joins(corner, fit);
  EXPECT_LE(joins.angle, kG1);
}

TEST(ArcBlendArcArc, SameCircleSameDirectionInsertsAnArcOfTwiceD) {
  const Arc in = arc_from({0, 0, 0}, {0, -0.02, 0}, Vec3::UnitZ(), kPi / 2);
  const Arc out = arc_from({0, 0, 0}, {0.02, 0, 0}, Vec3::UnitZ(), kPi / 2);
  const CornerFit fit = fit_arc_corner(make_corner(in, out, 0.004, BufferMode::kBuffered));
  ASSERT_TRUE(fit.outcome.ok());
  EXPECT_EQ(fit.corner_case, CornerCase::kSameCircleSameDirection);
  EXPECT_DOUBLE_EQ(fit.trim_in, 0.004);
  EXPECT_DOUBLE_EQ(fit.trim_out, 0.004);
  EXPECT_FALSE(fit.stop);
  const Arc& arc = as_arc(fit.transition[0]);
  EXPECT_NEAR(arc.radius, 0.02, kExact);
  EXPECT_NEAR(length(arc), 0.008, kExact);
  EXPECT_LE(arc.center.norm(), 1e-17);
}

TEST(ArcBlendArcArc, SameCircleOppositeDirectionShortensBothAndStopsWhenBuffered) {
  // A counter-clockwise up to (0.02, 0), B clockwise back down the same circle
  const Arc in = arc_from({0, 0, 0}, {0, -0.02, 0}, Vec3::UnitZ(), kPi / 2);
  const Arc out = arc_from({0, 0, 0}, {0.02, 0, 0}, -Vec3::UnitZ(), kPi / 4);
  const CornerFit fit = fit_arc_corner(make_corner(in, out, 0.004, BufferMode::kBuffered));
  ASSERT_TRUE(fit.outcome.ok());
  EXPECT_EQ(fit.corner_case, CornerCase::kSameCircleOppositeDirection);
  EXPECT_DOUBLE_EQ(fit.trim_in, 0.004);
  EXPECT_DOUBLE_EQ(fit.trim_out, 0.004);
  EXPECT_TRUE(fit.transition.empty());
  EXPECT_TRUE(fit.stop);
  EXPECT_TRUE(point(Primitive(in), length(in) - 0.004).isApprox(point(Primitive(out), 0.004), 1e-14));
  EXPECT_FALSE(fit_arc_corner(make_corner(in, out, 0.004, BufferMode::kAborting)).stop);
}

TEST(ArcBlendArcArc, CuspBetweenArcsThatPartIsJoinedByAUTurn) {
  // 180 deg between internally tangent circles travelled in opposite senses: A counter-clockwise
  // (radius 0.02) arrives at C = 0 heading +x, B clockwise (radius 0.01, inside A) leaves heading
  // -x. The moves part at once, so unlike seed 001's line reversal nothing overlaps: the seed 003
  // construction gives a small U-turn arc tangent to both (the limit of near-180 deg corners)
  const Arc in = arc_from({0, 0.02, 0}, {-0.02, 0.02, 0}, Vec3::UnitZ(), kPi / 2);
  const Arc out = arc_from({0, 0.01, 0}, {0, 0, 0}, -Vec3::UnitZ(), kPi / 2);
  const CornerInput corner = make_corner(in, out, 0.005, BufferMode::kBuffered);
  const CornerFit fit = fit_arc_corner(corner);
  ASSERT_TRUE(fit.outcome.ok()) << fit.outcome.message;
  EXPECT_EQ(fit.corner_case, CornerCase::kReversal);
  EXPECT_FALSE(fit.stop);
  EXPECT_DOUBLE_EQ(fit.trim_in, 0.005);
  ASSERT_EQ(fit.transition.size(), 1u);
  EXPECT_GT(as_arc(fit.transition[0]).sweep, kPi / 2);
  const Joins joins = measure_joins(corner, fit);
  EXPECT_LE(joins.gap, kPosRel * joins.size);
  EXPECT_LE(joins.angle, kG1);
}

TEST(ArcBlendLineArc, LineReversalIntoAnArcIsAUTurnOfRadiusDSquaredOver4R) {
  // line along +x into C = 0, clockwise arc (radius r, centre (0, r)) leaving heading -x.
  // T1 = (-d, 0), n1 = +y, w = (-d, -r), rho_B = -r: rho = (r^2 - d^2 - r^2) / (2 (-r - r)) = d^2 / (4r)
  const double r = 0.01;
  const double d = 0.005;
  const CornerFit fit = fit_arc_corner(
      make_corner(Line{{-0.05, 0, 0}, {0, 0, 0}}, arc_from({0, r, 0}, {0, 0, 0}, -Vec3::UnitZ(), kPi / 2), d));
  ASSERT_TRUE(fit.outcome.ok());
  EXPECT_EQ(fit.corner_case, CornerCase::kReversal);
  EXPECT_NEAR(as_arc(fit.transition[0]).radius, d * d / (4 * r), kExact);
  EXPECT_TRUE(as_arc(fit.transition[0]).center.isApprox(Vec3(-d, d * d / (4 * r), 0), 1e-13));
}

TEST(ArcBlendLineArc, NoUsablePartOfTheArcIsInfeasibleNotNaN) {
  // the blender may take nothing of the arc: every tangency lies beyond the available part,
  // down to the 1 um shrink floor; the result is an error status (the blender stops there)
  const Line in{{-0.05, 0, 0}, {0, 0, 0}};
  CornerInput corner = make_corner(in, arc_from({-0.02, 0, 0}, {0, 0, 0}, Vec3::UnitZ(), kPi / 2), 0.01);
  corner.out_available = 0;
  const CornerFit fit = fit_arc_corner(corner);
  EXPECT_EQ(fit.outcome.status, Status::kInfeasible);
  EXPECT_NE(fit.outcome.message.find("no circular transition"), std::string::npos) << fit.outcome.message;
}

TEST(ArcBlendLineArc, ArcShorterThanTheCornerDistanceIsReplacedWhole) {
  // a 0.5 um arc (radius 0.1 mm) after a right-angle corner with d = 1 mm: the line rule finds
  // the tangency behind the corner, so the arc is shortened instead, by all of its length
  const Line in{{-0.05, 0, 0}, {0, 0, 0}};
  const Arc out = arc_from({-1e-4, 0, 0}, {0, 0, 0}, Vec3::UnitZ(), 0.005);
  const CornerInput corner = make_corner(in, out, 0.001);
  const CornerFit fit = fit_arc_corner(corner);
  ASSERT_TRUE(fit.outcome.ok());
  EXPECT_EQ(fit.fallback, Fallback::kSmallerRadiusShortened);
  EXPECT_DOUBLE_EQ(fit.trim_out, length(out));
  EXPECT_NE(fit.note.text().find("shrunk from 1 mm to 0.0005 mm"), std::string::npos) << fit.note;
  const Joins joins = measure_joins(corner, fit);
  EXPECT_LE(joins.gap, kPosRel * joins.size + 1e-16);
  EXPECT_LE(joins.angle, kG1);
}

// ---- seeded random corners

// Relative size below which a corner's gap is compared with an absolute floor instead (m): the
// coordinates reach ~1 m, where one rounding is ~1e-16 m.
constexpr double kGapFloor = 1e-15;

// Tangent turn at the corner: 0.001 deg .. 179.999 deg, with extra weight near both ends.
double random_turn(std::mt19937_64& rng) {
  constexpr double kLo = 0.001 * kPi / 180;
  const double pick = test::uniform(rng, 0, 1);
  if (pick < 0.25) return test::log_uniform(rng, kLo, 0.1);
  if (pick < 0.5) return kPi - test::log_uniform(rng, kLo, 0.1);
  return test::uniform(rng, kLo, kPi - kLo);
}

Mat3 random_rotation(std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  Eigen::Quaterniond q(normal(rng), normal(rng), normal(rng), normal(rng));
  return q.normalized().toRotationMatrix();
}

// An arc of radius r and sweep phi that ends at c with unit tangent t, its centre towards the
// unit normal m (perpendicular to t).
Arc arc_ending_at(const Vec3& c, const Vec3& t, const Vec3& m, double r, double phi) {
  const Vec3 u = -m;
  const Vec3& v = t;
  Arc arc;
  arc.center = c + r * m;
  arc.radius = r;
  arc.u = std::cos(phi) * u - std::sin(phi) * v;
  arc.v = std::sin(phi) * u + std::cos(phi) * v;
  arc.sweep = phi;
  return arc;
}

// An arc of radius r and sweep phi that starts at c with unit tangent t, centre towards m.
Arc arc_starting_at(const Vec3& c, const Vec3& t, const Vec3& m, double r, double phi) {
  return Arc{c + r * m, -m, t, r, phi, 0.0};
}

Primitive transformed(const Primitive& prim, const Mat3& rot, const Vec3& shift) {
  if (const Line* line = std::get_if<Line>(&prim)) return Line{rot * line->p0 + shift, rot * line->p1 + shift};
  Arc arc = std::get<Arc>(prim);
  arc.center = rot * arc.center + shift;
  arc.u = rot * arc.u;
  arc.v = rot * arc.v;
  return arc;
}

enum class Kinds { kAny, kPlanar, kNonPlanar };

// A random corner at the origin (incoming along +x, outgoing turned by theta in the x-y plane,
// arcs in that plane or tilted about their tangent), then rotated and moved at random.
CornerInput random_corner(std::mt19937_64& rng, Kinds kinds, double theta) {
  const bool in_arc = test::uniform(rng, 0, 1) < 0.6;
  const bool out_arc = test::uniform(rng, 0, 1) < 0.6;
  const double delta = test::uniform(rng, 0, 1) < 0.5 ? theta : -theta;
  const Vec3 t_in = Vec3::UnitX();
  const Vec3 t_out(std::cos(delta), std::sin(delta), 0);
  const bool tilt = kinds == Kinds::kNonPlanar || (kinds == Kinds::kAny && test::uniform(rng, 0, 1) < 0.2);
  // side of the centre: in the plane (beta = 0 or pi) or rotated about the tangent
  const auto side = [&](const Vec3& t) {
    const double beta = tilt ? test::uniform(rng, 0.05, kPi - 0.05) * (test::uniform(rng, 0, 1) < 0.5 ? 1 : -1)
                             : (test::uniform(rng, 0, 1) < 0.5 ? 0.0 : kPi);
    return Vec3(std::cos(beta) * Vec3::UnitZ().cross(t) + std::sin(beta) * Vec3::UnitZ());
  };
  const auto length_or_sweep = [&](double r) { return std::min(test::uniform(rng, 0.01, 6.0), test::log_uniform(rng, 1e-3, 0.6) / r); };
  Primitive in = Line{-test::log_uniform(rng, 1e-3, 0.5) * t_in, Vec3::Zero()};
  Primitive out = Line{Vec3::Zero(), test::log_uniform(rng, 1e-3, 0.5) * t_out};
  if (in_arc) {
    const double r = test::log_uniform(rng, 1e-4, 1.0);
    in = arc_ending_at(Vec3::Zero(), t_in, side(t_in), r, length_or_sweep(r));
  }
  if (out_arc) {
    const double r = test::log_uniform(rng, 1e-4, 1.0);
    out = arc_starting_at(Vec3::Zero(), t_out, side(t_out), r, length_or_sweep(r));
  }
  // a planar tilt of a line-line corner or a single arc in the line's plane is still planar
  const Mat3 rot = random_rotation(rng);
  const Vec3 shift(test::uniform(rng, -0.5, 0.5), test::uniform(rng, -0.5, 0.5), test::uniform(rng, -0.5, 0.5));
  CornerInput corner = make_corner(transformed(in, rot, shift), transformed(out, rot, shift), test::log_uniform(rng, 1e-5, 0.1),
                                   test::uniform(rng, 0, 1) < 0.5 ? BufferMode::kBuffered : BufferMode::kBlendingLow);
  if (test::uniform(rng, 0, 1) < 0.5) corner.in_available *= 0.5;
  if (test::uniform(rng, 0, 1) < 0.5) corner.out_available *= 0.5;
  return corner;
}

// Worst figures over a property run, printed for the report.
struct Worst {
  int cases = 0;
  int infeasible = 0;
  double gap_rel = 0;  // position gap / corner size
  double angle = 0;    // rad, at G1 junctions
  std::map<std::string, int> by_case;
  void print(const std::string& what) const {
    std::ostringstream out;
    out << what << ": " << cases << " corners, " << infeasible << " infeasible, worst gap/size " << gap_rel
        << ", worst tangent angle " << angle << " rad;";
    for (const auto& [name, count] : by_case) out << " " << name << "=" << count;
    std::cout << out.str() << "\n";
  }
};

bool is_circle(const Segment& seg) {
  if (std::holds_alternative<Line>(seg)) return true;
  if (const Arc* arc = std::get_if<Arc>(&seg)) return arc->rise == 0;
  if (const Clothoid* c = std::get_if<Clothoid>(&seg)) return c->sharpness == 0;
  return false;
}

// The invariants every fit must satisfy.
// "case" or "case/fallback", for the tally of what the random corners hit.
std::string case_key(CornerCase corner_case, Fallback fallback) {
  std::string key(to_string(corner_case));
  if (fallback != Fallback::kNone) key += "/" + std::string(to_string(fallback));
  return key;
}

void check_fit(const CornerInput& corner, const CornerFit& fit, const std::string& seed, Worst& worst) {
  ++worst.cases;
  if (!fit.outcome.ok()) {
    ++worst.infeasible;
    EXPECT_EQ(fit.outcome.status, Status::kInfeasible) << seed;
    EXPECT_FALSE(fit.outcome.message.empty()) << seed;
    return;
  }
  ++worst.by_case[case_key(fit.corner_case, fit.fallback)];
  const double d = corner.spec.parameter;
  ASSERT_TRUE(std::isfinite(fit.trim_in) && std::isfinite(fit.trim_out) && std::isfinite(fit.parameter_used)) << seed;
  EXPECT_GE(fit.trim_in, 0.0) << seed;
  EXPECT_GE(fit.trim_out, 0.0) << seed;
  EXPECT_LE(fit.trim_in, corner.in_available * (1 + 1e-12)) << seed;
  EXPECT_LE(fit.trim_out, corner.out_available * (1 + 1e-12)) << seed;
  EXPECT_LE(fit.parameter_used, d * (1 + 1e-12)) << seed;
  for (const Segment& seg : fit.transition) {
    ASSERT_TRUE(std::isfinite(length(seg)) && start_point(seg).allFinite() && end_point(seg).allFinite()) << seed;
    EXPECT_TRUE(is_circle(seg)) << seed << " " << fit.corner_case;
  }

  // continuity: positions always, tangents unless the case leaves a kink
  const Joins joins = measure_joins(corner, fit);
  ASSERT_TRUE(std::isfinite(joins.gap) && std::isfinite(joins.angle)) << seed;
  EXPECT_LE(joins.gap, kPosRel * joins.size + kGapFloor) << seed << " " << fit.corner_case << " size " << joins.size;
  if (joins.size > 0) worst.gap_rel = std::max(worst.gap_rel, joins.gap / joins.size);
  const bool kink = fit.transition.empty() && kKinkCases.count(fit.corner_case) > 0;
  if (kink) {
    EXPECT_EQ(fit.stop, corner.buffer == BufferMode::kBuffered) << seed << " " << fit.corner_case;
  } else {
    EXPECT_FALSE(fit.stop) << seed;
    EXPECT_LE(joins.angle, kG1) << seed << " " << fit.corner_case << " " << fit.fallback;
    worst.angle = std::max(worst.angle, joins.angle);
  }

  // the corner distance: the larger-radius move (a line, the incoming on a tie) loses exactly d
  if (fit.note.empty() && (fit.fallback == Fallback::kNone) && fit.corner_case != CornerCase::kZeroDistance) {
    const Arc* a_in = std::get_if<Arc>(&corner.in);
    const Arc* a_out = std::get_if<Arc>(&corner.out);
    const bool larger_in = a_in == nullptr || (a_out != nullptr && a_in->radius >= a_out->radius * (1 - 1e-12));
    EXPECT_NEAR(larger_in ? fit.trim_in : fit.trim_out, d, 1e-12 * d) << seed << " " << fit.corner_case;
    if (a_in == nullptr && a_out == nullptr) {
      EXPECT_NEAR(fit.trim_out, d, 1e-12 * d) << seed;
    }
    EXPECT_DOUBLE_EQ(fit.parameter_used, d) << seed;
  }
}

// Two circles turning the same way that cross at a small angle theta meet again a distance of
// about 2 theta / (kappa_in - kappa_out) on; halfway, the larger circle runs parallel to the
// smaller at a distance of theta^2 / (2 (kappa_in - kappa_out)). With the corner distance there,
// the circle tangent to the larger move at T1 and to the smaller is the smaller circle itself to
// within that distance, touching it anywhere round its circumference (found by the property test
// below: 0.5 nm from it, 4.4 rad back, an arc that missed T1 by 3e-9 of its length). As d nears
// that point the seed 003 circle's tangency moves back round the smaller circle (continuously:
// 0.1 mm at 0.9 d, 1.3 mm at 0.99 d, ever closer to the smaller circle); where it comes within
// 1e-6 of its radius it is refused and the rule swapped, which keeps the transition local. Every
// fit stays continuous and G1.
TEST(ArcBlendArcArc, NearTangentCirclesAtTheirParallelPointStayLocal) {
  const double r_in = 0.053285325576692;  // the smaller circle
  const double r_out = 0.08141912261056658;
  const double theta = 8.2830522556456078e-05;
  const double d_parallel = theta / (1 / r_in - 1 / r_out);
  for (const double sign : {1.0, -1.0}) {
    const Vec3 t_in = Vec3::UnitX();
    const Vec3 t_out(std::cos(sign * theta), std::sin(sign * theta), 0);
    const Arc in = arc_ending_at(Vec3::Zero(), t_in, sign * Vec3::UnitZ().cross(t_in), r_in, 5.25);
    const Arc out = arc_starting_at(Vec3::Zero(), t_out, sign * Vec3::UnitZ().cross(t_out), r_out, 3.9);
    for (const double f : {0.5, 0.9, 0.99, 0.999, 0.99999, 0.9999999, 1.0, 1.0000001, 1.00001, 1.001, 1.01, 1.1, 1.5}) {
      const CornerInput corner = make_corner(in, out, f * d_parallel);
      const CornerFit fit = fit_arc_corner(corner);
      ASSERT_TRUE(fit.outcome.ok()) << fit.outcome.message;
      const Joins joins = measure_joins(corner, fit);
      EXPECT_LE(joins.gap, kPosRel * joins.size) << "sign " << sign << " d/d_parallel " << f;
      EXPECT_LE(joins.angle, kG1) << "sign " << sign << " d/d_parallel " << f;
      if (std::abs(f - 1) <= 1e-5) {
        EXPECT_EQ(fit.fallback, Fallback::kSmallerRadiusShortened) << "sign " << sign << " d/d_parallel " << f;
        EXPECT_LE(std::max(fit.trim_in, fit.trim_out), 4 * d_parallel) << "sign " << sign << " d/d_parallel " << f;
      }
    }
  }
}

TEST(ArcBlendProperty, RandomPlanarCornersAreContinuousAndTangent) {
  const int n = test::property_cases(20000);
  Worst worst;
  for (int i = 0; i < n; ++i) {
    const auto seed = static_cast<std::uint64_t>(1000 + i);
    auto rng = test::make_rng(seed);
    const CornerInput corner = random_corner(rng, Kinds::kPlanar, random_turn(rng));
    check_fit(corner, fit_arc_corner(corner), test::seed_text(seed), worst);
    if (HasFatalFailure()) return;
  }
  worst.print("planar corners");
}

TEST(ArcBlendProperty, RandomNonPlanarCornersAreJoinedByG1Biarcs) {
  const int n = test::property_cases(10000);
  Worst worst;
  for (int i = 0; i < n; ++i) {
    const auto seed = static_cast<std::uint64_t>(50000 + i);
    auto rng = test::make_rng(seed);
    const CornerInput corner = random_corner(rng, Kinds::kNonPlanar, random_turn(rng));
    const CornerFit fit = fit_arc_corner(corner);
    check_fit(corner, fit, test::seed_text(seed), worst);
    if (HasFatalFailure()) return;
  }
  worst.print("non-planar corners");
}

TEST(ArcBlendProperty, NearStraightAndNearReversalCornersBehaveContinuously) {
  // turns straddling the 1e-12 rad thresholds at 0 and 180 degrees
  const int n = test::property_cases(10000);
  Worst worst;
  for (int i = 0; i < n; ++i) {
    const auto seed = static_cast<std::uint64_t>(90000 + i);
    auto rng = test::make_rng(seed);
    const double small = test::log_uniform(rng, 1e-14, 1e-4);
    const double theta = test::uniform(rng, 0, 1) < 0.5 ? small : kPi - small;
    const CornerInput corner = random_corner(rng, Kinds::kAny, theta);
    check_fit(corner, fit_arc_corner(corner), test::seed_text(seed), worst);
    if (HasFatalFailure()) return;
  }
  worst.print("near 0 / 180 degree corners");
}

TEST(ArcBlendProperty, LineLineFilletRadiusFollowsTheCornerDistance) {
  // seed 001: r = d / tan(theta / 2) whenever d is not shrunk
  const int n = test::property_cases(5000);
  for (int i = 0; i < n; ++i) {
    const auto seed = static_cast<std::uint64_t>(130000 + i);
    auto rng = test::make_rng(seed);
    const double theta = random_turn(rng);
    const Mat3 rot = random_rotation(rng);
    const Vec3 c = rot * Vec3(test::uniform(rng, -0.5, 0.5), 0, 0);
    const Vec3 t_in = rot * Vec3::UnitX();
    const Vec3 t_out = rot * Vec3(std::cos(theta), std::sin(theta), 0);
    const double d = test::log_uniform(rng, 1e-5, 0.1);
    const CornerFit fit = fit_arc_corner(make_corner(Line{c - 0.2 * t_in, c}, Line{c, c + 0.2 * t_out}, d));
    ASSERT_EQ(fit.transition.size(), 1u) << test::seed_text(seed);
    const Segment& seg = fit.transition[0];
    const double r_expected = d / std::tan(theta / 2);
    const double kappa = curvature_vector(seg, 0.5 * length(seg)).norm();
    EXPECT_NEAR(kappa * r_expected, 1.0, 1e-9) << test::seed_text(seed) << " theta " << theta;
  }
}

// The seed 003 figures perturbed around their exact values: the intersection distance, the
// line-segment distance, and a second arc on (almost) the same circle.
TEST(ArcBlendProperty, NearIntersectionLineSegmentAndSameCircleStayContinuous) {
  const int n = test::property_cases(10000);
  Worst worst;
  for (int i = 0; i < n; ++i) {
    const auto seed = static_cast<std::uint64_t>(170000 + i);
    auto rng = test::make_rng(seed);
    const double scale = test::log_uniform(rng, 1e-2, 10.0);  // radii 0.2 mm .. 200 mm
    const double eps = test::log_uniform(rng, 1e-15, 1e-3) * (test::uniform(rng, 0, 1) < 0.5 ? 1 : -1);
    const Mat3 rot = random_rotation(rng);
    const Vec3 shift(test::uniform(rng, -0.5, 0.5), test::uniform(rng, -0.5, 0.5), test::uniform(rng, -0.5, 0.5));
    const double r = 0.02 * scale;
    const int which = static_cast<int>(test::uniform(rng, 0, 3));
    Primitive in;
    Primitive out;
    double d = 0;
    if (which == 0) {
      in = arc_from({0, 0, 0}, {-r, 0, 0}, Vec3::UnitZ(), kPi);
      out = arc_from({r, -0.5 * r, 0}, {r, 0, 0}, Vec3::UnitZ(), 1.5 * kPi);
      d = r * std::atan2(4.0, 3.0) * (1 + eps);
    } else if (which == 1) {
      in = arc_from({0, 0, 0}, {-r, 0, 0}, Vec3::UnitZ(), kPi - std::atan2(4.0, 3.0));
      out = arc_from({r, -0.5 * r, 0}, {0.6 * r, -0.8 * r, 0}, Vec3::UnitZ(), kPi / 2);
      d = r * (kPi / 2 - std::atan2(4.0, 3.0)) * (1 + eps);
    } else {
      // B through C = (r, 0) with its centre moved by |eps| r along a random direction
      const double ang = test::uniform(rng, 0, 2 * kPi);
      const Vec3 centre = std::abs(eps) * r * Vec3(std::cos(ang), std::sin(ang), 0);
      in = arc_from({0, 0, 0}, {0, -r, 0}, Vec3::UnitZ(), kPi / 2);
      out = arc_from(centre, {r, 0, 0}, (eps > 0 ? 1.0 : -1.0) * Vec3::UnitZ(), kPi / 2);
      d = r * test::uniform(rng, 0.01, 0.5);
    }
    const CornerInput corner = make_corner(transformed(in, rot, shift), transformed(out, rot, shift), d,
                                           test::uniform(rng, 0, 1) < 0.5 ? BufferMode::kBuffered : BufferMode::kBlendingLow);
    check_fit(corner, fit_arc_corner(corner), test::seed_text(seed) + " figure " + std::to_string(which), worst);
    if (HasFatalFailure()) return;
  }
  worst.print("near 003 special figures");
}

Move move_of(const Primitive& geometry, double d, BufferMode buffer) {
  Move move;
  move.geometry = geometry;
  move.limits = {0.2, 2.0, 2.0, 20.0};
  move.buffer = buffer;
  move.transition.method = Method::kArc;
  move.transition.parameter = d;
  return move;
}

TEST(ArcBlendProperty, BlendedPathsAreContinuousWithKinksOnlyWhereACaseLeavesOne) {
  const int n = test::property_cases(1000);
  Worst worst;
  for (int i = 0; i < n; ++i) {
    const auto seed = static_cast<std::uint64_t>(210000 + i);
    auto rng = test::make_rng(seed);
    const std::string where = test::seed_text(seed);
    const CornerInput corner = random_corner(rng, Kinds::kAny, random_turn(rng));
    // a third move leaves the end of `out` along its tangent turned by a random angle
    const double len_out = length(corner.out);
    const Vec3 end = point(corner.out, len_out);
    const Vec3 t_end = tangent(corner.out, len_out);
    const Vec3 side = any_perpendicular(t_end);
    const double turn = random_turn(rng);
    const Vec3 dir = std::cos(turn) * t_end + std::sin(turn) * side;
    Program program;
    program.moves = {move_of(corner.in, corner.spec.parameter, corner.buffer),
                     move_of(corner.out, test::log_uniform(rng, 1e-5, 0.1), corner.buffer),
                     move_of(Line{end, end + test::log_uniform(rng, 1e-3, 0.3) * dir}, 0.0, corner.buffer)};
    const Path path = blend(program);
    ASSERT_EQ(path.corners.size(), 2u) << where;
    ASSERT_TRUE(std::isfinite(path.length())) << where;
    // the ends may be those of a transition when a move is trimmed away entirely
    const double skip = kPosRel * (length(corner.in) + length(corner.out) + length(program.moves[2].geometry)) + kGapFloor;
    EXPECT_LE((path.point(0) - start_point(to_segment(corner.in))).norm(), skip) << where;
    EXPECT_LE((path.point(path.length()) - end_point(to_segment(program.moves[2].geometry))).norm(), skip) << where;
    const auto& pieces = path.pieces();
    for (std::size_t k = 1; k < pieces.size(); ++k) {
      const PathPiece& prev = pieces[k - 1];
      const PathPiece& next = pieces[k];
      const int c = next.corner >= 0 ? next.corner : (prev.corner >= 0 ? prev.corner : prev.move);
      ASSERT_TRUE(c >= 0 && c < 2) << where;
      const CornerReport& report = path.corners[static_cast<std::size_t>(c)];
      const double size = std::max({report.trim_in, report.trim_out, report.length});
      const double gap = (end_point(prev.segment) - start_point(next.segment)).norm();
      EXPECT_LE(gap, kPosRel * size + kGapFloor) << where << " corner " << c << " " << report.corner_case;
      if (size > 0) worst.gap_rel = std::max(worst.gap_rel, gap / size);
      if (next.kink_angle > kG1) {
        EXPECT_TRUE(kKinkCases.count(report.corner_case) > 0 || report.fallback == Fallback::kExactStop)
            << where << " corner " << c << " " << report.corner_case << " kink " << next.kink_angle;
      } else {
        worst.angle = std::max(worst.angle, next.kink_angle);
      }
    }
    ++worst.cases;
    for (const CornerReport& report : path.corners) {
      ++worst.by_case[case_key(report.corner_case, report.fallback)];
      EXPECT_TRUE(std::isfinite(report.deviation) && std::isfinite(report.kappa_max)) << where;
    }
    if (HasFatalFailure()) return;
  }
  worst.print("blended 3-move programs");
}

}  // namespace
}  // namespace blendbench
