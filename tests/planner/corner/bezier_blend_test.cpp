// Tests of the seed 000 Bezier transition (planner/corner/src/bezier_blend.cpp): hand-derived corners for
// each case of the paper, Algorithm 1, and seeded random corners and programs for the
// invariants (continuity, G1, G2 with direction, the TP bound, no NaN).

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <iostream>
#include <numbers>

#include "support/property.hpp"
#include "support/random_geometry.hpp"
#include "blendbench/core/units.hpp"
#include "blendbench/corner/blend.hpp"
#include "blendbench/corner/corner.hpp"

namespace blendbench {
namespace {

constexpr double kPi = std::numbers::pi;
// Exact-arithmetic identities evaluated in double (control points, lengths), relative.
constexpr double kExact = 1e-12;
// Position continuity at a junction, relative to the corner size (transition length).
constexpr double kPosTol = 1e-9;
// G1: angle (rad) between the tangents at a junction.
constexpr double kG1Tol = 1e-9;
// G2: |K_bezier - K_move| / (|K_move| + 1/L), the curvature-vector jump relative to the larger
// of the move's curvature and the transition's own scale 1/L. Control points are absolute
// coordinates (|P| up to ~0.5 m), so rounding alone gives ~1e-16 |P| L / l^2 here.
constexpr double kG2Tol = 1e-8;
// The transition stays within L (the transition length, <= TP) of the corner: |C(u) - B| <= L
// up to rounding of the absolute coordinates, this fraction of |B| + L.
constexpr double kBoundSlack = 1e-13;

// An arc that starts at `start` with unit tangent `t`, turning about the unit axis `w`
// (perpendicular to t), radius r, sweep (rad).
Arc arc_from(const Vec3& start, const Vec3& t, const Vec3& w, double r, double sweep) {
  const Vec3 e = t.cross(w);  // outward radial at the start: t = w x e
  return Arc{start - r * e, e, t, r, sweep, 0.0};
}

// An arc that ends at `end` with unit tangent `t`, turning about `w`, radius r, sweep (rad).
Arc arc_to(const Vec3& end, const Vec3& t, const Vec3& w, double r, double sweep) {
  const Vec3 e_end = t.cross(w);
  const Vec3 e0 = std::cos(sweep) * e_end - std::sin(sweep) * w.cross(e_end);
  return Arc{end - r * e_end, e0, w.cross(e0), r, sweep, 0.0};
}

// The same curve traversed backwards.
Primitive reversed(const Primitive& p) {
  if (const Line* line = std::get_if<Line>(&p)) return Line{line->p1, line->p0};
  const Arc& arc = std::get<Arc>(p);
  const double len = length(arc);
  return arc_from(point(arc, len), -tangent(arc, len), -arc.u.cross(arc.v), arc.radius, arc.sweep);
}

CornerInput make_corner(const Primitive& in, const Primitive& out, double tp, double in_available = -1,
                        double out_available = -1) {
  CornerInput c;
  c.in = in;
  c.out = out;
  c.in_available = in_available >= 0 ? in_available : length(in);
  c.out_available = out_available >= 0 ? out_available : length(out);
  c.spec.method = Method::kBezier;
  c.spec.parameter = tp;
  c.name = "corner 1 (move 1 -> move 2)";
  return c;
}

const Bezier& only_bezier(const CornerFit& fit) {
  EXPECT_EQ(fit.transition.size(), 1u);
  return std::get<Bezier>(fit.transition.at(0));
}

// Curvature vector of a Bezier at parameter u (1/m).
Vec3 bezier_k(const Bezier& b, double u) {
  const Vec3 c1 = b.d1(u);
  const Vec3 c2 = b.d2(u);
  const double g2 = c1.squaredNorm();
  return (c2 - c1 * (c1.dot(c2) / g2)) / g2;
}

// Bending energy of seed 000 eq. 16, integral of |C''(u)|^2 over [0, 1] (5-point Gauss-Legendre,
// exact for the degree <= 4 curves here since |C''|^2 then has degree <= 4).
double bending_energy(const std::vector<Vec3>& p) {
  const Bezier b(p);
  constexpr std::array<double, 5> x = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                                       0.9061798459386640};
  constexpr std::array<double, 5> w = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                                       0.4786286704993665, 0.2369268850561891};
  double sum = 0;
  for (std::size_t i = 0; i < x.size(); ++i) sum += w[i] * b.d2(0.5 * (x[i] + 1)).squaredNorm();
  return 0.5 * sum;
}

// Junction errors of a fitted corner against its moves.
struct Junction {
  double pos = 0;    // |gap| / L
  double g1 = 0;     // rad
  double g2 = 0;     // relative, see kG2Tol
  double bound = 0;  // max (|C(u) - B| - L) / (|B| + L), <= 0 up to rounding
};

Junction measure(const CornerInput& c, const CornerFit& fit) {
  Junction j;
  const Bezier& b = only_bezier(fit);
  const double l = fit.trim_in;
  const double len_in = length(c.in);
  const Vec3 corner = point(c.out, 0.0);
  // start junction
  const double s_in = len_in - fit.trim_in;
  j.pos = std::max(j.pos, (b.eval(0) - point(c.in, s_in)).norm() / l);
  j.g1 = std::max(j.g1, angle_between(b.d1(0), tangent(c.in, s_in)));
  const Vec3 k_in = curvature_vector(c.in, s_in);
  j.g2 = std::max(j.g2, (bezier_k(b, 0) - k_in).norm() / (k_in.norm() + 1 / l));
  // end junction
  j.pos = std::max(j.pos, (b.eval(1) - point(c.out, fit.trim_out)).norm() / l);
  j.g1 = std::max(j.g1, angle_between(b.d1(1), tangent(c.out, fit.trim_out)));
  const Vec3 k_out = curvature_vector(c.out, fit.trim_out);
  j.g2 = std::max(j.g2, (bezier_k(b, 1) - k_out).norm() / (k_out.norm() + 1 / l));
  // the whole curve stays within L of the corner
  j.bound = -1;
  for (int i = 0; i <= 200; ++i) {
    j.bound = std::max(j.bound, ((b.eval(i / 200.0) - corner).norm() - l) / (corner.norm() + l));
  }
  return j;
}

void expect_g2(const CornerInput& c, const CornerFit& fit) {
  const Junction j = measure(c, fit);
  EXPECT_LE(j.pos, kPosTol);
  EXPECT_LE(j.g1, kG1Tol);
  EXPECT_LE(j.g2, kG2Tol);
  EXPECT_LE(j.bound, kBoundSlack);
}

// ---- line-line (seed 000 eq. 8-9)

TEST(BezierBlend, LineLine90DegreesWithTp5HasTheCornerTwiceAsControlPoint) {
  const Line in{Vec3(0, 0, 0), Vec3(0.1, 0, 0)};
  const Line out{Vec3(0.1, 0, 0), Vec3(0.1, 0.1, 0)};
  const CornerFit fit = fit_bezier_corner(make_corner(in, out, 5 * kMm, 0.05, 0.05));
  ASSERT_TRUE(fit.outcome.ok()) << fit.outcome.message;
  EXPECT_EQ(fit.corner_case, CornerCase::kRegular);
  EXPECT_TRUE((fit.fallback == Fallback::kNone));
  EXPECT_TRUE(fit.note.empty());
  EXPECT_DOUBLE_EQ(fit.trim_in, 5 * kMm);
  EXPECT_DOUBLE_EQ(fit.trim_out, 5 * kMm);
  EXPECT_DOUBLE_EQ(fit.parameter_used, 5 * kMm);
  const Bezier& b = only_bezier(fit);
  ASSERT_EQ(b.degree(), 3);
  const std::array<Vec3, 4> expected = {Vec3(0.095, 0, 0), Vec3(0.1, 0, 0), Vec3(0.1, 0, 0), Vec3(0.1, 0.005, 0)};
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_LT((b.control_points()[i] - expected[i]).norm(), kExact) << "P" << i;
  }
  // zero curvature at both ends; by symmetry u = 1/2 is mid-length, where
  // C' = (3L/4)(1, 1), C'' = 3L(-1, 1), kappa = (9L^2/2) / ((3L/4)^3 2 sqrt 2) = 16 / (3 sqrt(2) L)
  EXPECT_EQ(curvature_vector(Segment(b), 0.0).norm(), 0.0);
  EXPECT_LT(curvature_vector(Segment(b), b.length()).norm(), 1e-9);
  const double l = 5 * kMm;
  EXPECT_NEAR(curvature_vector(Segment(b), 0.5 * b.length()).norm(), 16 / (3 * std::sqrt(2.0) * l), 1e-9 / l);
  expect_g2(make_corner(in, out, 5 * kMm), fit);
}

TEST(BezierBlend, CollinearLinesNeedNoTransition) {
  const Line in{Vec3(0, 0, 0), Vec3(0.1, 0, 0)};
  const Line out{Vec3(0.1, 0, 0), Vec3(0.3, 0, 0)};
  const CornerFit fit = fit_bezier_corner(make_corner(in, out, 5 * kMm));
  ASSERT_TRUE(fit.outcome.ok());
  EXPECT_EQ(fit.corner_case, CornerCase::kCollinear);
  EXPECT_TRUE(fit.transition.empty());
  EXPECT_EQ(fit.trim_in, 0.0);
  EXPECT_EQ(fit.trim_out, 0.0);
  EXPECT_FALSE(fit.stop);
}

TEST(BezierBlend, ReversalLeavesAKinkAndStops) {
  const Line in{Vec3(0, 0, 0), Vec3(0.1, 0, 0)};
  const Line out{Vec3(0.1, 0, 0), Vec3(0.05, 0, 0)};
  const CornerFit fit = fit_bezier_corner(make_corner(in, out, 5 * kMm));
  ASSERT_TRUE(fit.outcome.ok());
  EXPECT_EQ(fit.corner_case, CornerCase::kReversal);
  EXPECT_TRUE(fit.transition.empty());
  EXPECT_EQ(fit.trim_in, 0.0);
  EXPECT_TRUE(fit.stop);
}

TEST(BezierBlend, ZeroTpIsAZeroDistanceKink) {
  const Line in{Vec3(0, 0, 0), Vec3(0.1, 0, 0)};
  const Line out{Vec3(0.1, 0, 0), Vec3(0.1, 0.1, 0)};
  const CornerFit fit = fit_bezier_corner(make_corner(in, out, 0.0));
  ASSERT_TRUE(fit.outcome.ok());
  EXPECT_EQ(fit.corner_case, CornerCase::kZeroDistance);
  EXPECT_TRUE(fit.transition.empty());
  EXPECT_EQ(fit.trim_in, 0.0);
  EXPECT_FALSE(fit.stop);
}

TEST(BezierBlend, NearReversalIsStillAFiniteG2Cubic) {
  const double phi = kPi - 1e-7;
  const Line in{Vec3(0, 0, 0), Vec3(0.1, 0, 0)};
  const Line out{Vec3(0.1, 0, 0), Vec3(0.1 + 0.1 * std::cos(phi), 0.1 * std::sin(phi), 0)};
  const CornerInput c = make_corner(in, out, 5 * kMm);
  const CornerFit fit = fit_bezier_corner(c);
  ASSERT_TRUE(fit.outcome.ok()) << fit.outcome.message;
  EXPECT_EQ(fit.corner_case, CornerCase::kRegular);
  expect_g2(c, fit);
  EXPECT_TRUE(std::isfinite(max_curvature(fit.transition[0], 0, length(fit.transition[0]))));
}

TEST(BezierBlend, AlmostReversalWithACuspIsReportedNotReturned) {
  // 2e-9 rad short of a reversal the cubic's speed at u = 1/2 is ~5e-10 of its maximum: a cusp
  const double phi = kPi - 2e-9;
  const Line in{Vec3(0, 0, 0), Vec3(0.1, 0, 0)};
  const Line out{Vec3(0.1, 0, 0), Vec3(0.1 + 0.1 * std::cos(phi), 0.1 * std::sin(phi), 0)};
  const CornerFit fit = fit_bezier_corner(make_corner(in, out, 5 * kMm));
  EXPECT_EQ(fit.outcome.status, Status::kInfeasible);
  EXPECT_NE(fit.outcome.message.find("cusp"), std::string::npos) << fit.outcome.message;
  EXPECT_TRUE(fit.transition.empty());
}

// ---- Algorithm 1 and the blender's availability

TEST(BezierBlend, Algorithm1LongMovesUseTp) {
  // |AB| = 100 mm, |BC| = 100 mm > 2 TP, both blended at both ends (50 mm available each)
  const Line in{Vec3(0, 0, 0), Vec3(0.1, 0, 0)};
  const Line out{Vec3(0.1, 0, 0), Vec3(0.1, 0.1, 0)};
  const CornerFit fit = fit_bezier_corner(make_corner(in, out, 5 * kMm, 0.05, 0.05));
  EXPECT_DOUBLE_EQ(fit.trim_in, 5 * kMm);
  EXPECT_TRUE(fit.note.empty());
}

TEST(BezierBlend, Algorithm1OneShortMoveUsesHalfTheShorter) {
  // |BC| = 6 mm < 2 TP: Length(P1 B) = min(100, 6) / 2 = 3 mm
  const Line in{Vec3(0, 0, 0), Vec3(0.1, 0, 0)};
  const Line out{Vec3(0.1, 0, 0), Vec3(0.1, 0.006, 0)};
  const CornerFit fit = fit_bezier_corner(make_corner(in, out, 5 * kMm, 0.05, 0.003));
  ASSERT_TRUE(fit.outcome.ok());
  EXPECT_DOUBLE_EQ(fit.trim_in, 3 * kMm);
  EXPECT_DOUBLE_EQ(fit.trim_out, 3 * kMm);
  EXPECT_DOUBLE_EQ(fit.parameter_used, 3 * kMm);
  EXPECT_NE(fit.note.text().find("TP shrunk from 5 mm to 3 mm: the outgoing move is short"), std::string::npos) << fit.note;
}

TEST(BezierBlend, Algorithm1BothShortMovesUseHalfTheShorter) {
  // |AB| = 8 mm, |BC| = 6 mm: min(8, 6) / 2 = 3 mm
  const Line in{Vec3(0, 0, 0), Vec3(0.008, 0, 0)};
  const Line out{Vec3(0.008, 0, 0), Vec3(0.008, 0.006, 0)};
  const CornerFit fit = fit_bezier_corner(make_corner(in, out, 5 * kMm, 0.004, 0.003));
  EXPECT_DOUBLE_EQ(fit.trim_in, 3 * kMm);
  EXPECT_DOUBLE_EQ(fit.trim_out, 3 * kMm);
  EXPECT_FALSE(fit.note.empty());
}

Move line_move(const Vec3& a, const Vec3& b, double tp) {
  Move move;
  move.geometry = Line{a, b};
  move.limits = {0.05, 0.1, 0.1, 0.2};
  move.transition.method = Method::kBezier;
  move.transition.parameter = tp;
  return move;
}

TEST(BezierBlend, Algorithm1SharesAShortMoveBetweenTwoCorners) {
  // 100 mm, 6 mm, 100 mm with TP = 5 mm: both corners get 3 mm, the middle move is used up
  Program program;
  program.moves = {line_move({0, 0, 0}, {0.1, 0, 0}, 5 * kMm), line_move({0.1, 0, 0}, {0.1, 0.006, 0}, 5 * kMm),
                   line_move({0.1, 0.006, 0}, {0.2, 0.006, 0}, 5 * kMm)};
  const Path path = blend(program);
  ASSERT_EQ(path.corners.size(), 2u);
  for (const CornerReport& r : path.corners) {
    EXPECT_EQ(r.method, Method::kBezier);
    EXPECT_NEAR(r.trim_in, 3 * kMm, kExact);
    EXPECT_NEAR(r.trim_out, 3 * kMm, kExact);
    EXPECT_NEAR(r.parameter, 3 * kMm, kExact);
    EXPECT_FALSE(r.note.empty());
    EXPECT_FALSE(r.stop);
  }
  // no overlap: the two transitions meet exactly, G1 everywhere, no stop
  EXPECT_LE(path.corners[0].trim_out + path.corners[1].trim_in, 6 * kMm + kExact);
  ASSERT_EQ(path.pieces().size(), 4u);  // move 1, Bezier, Bezier, move 3 (move 2 fully used)
  for (const PathPiece& piece : path.pieces()) {
    EXPECT_LE(piece.kink_angle, kG1Tol);
    EXPECT_FALSE(piece.stop_before);
  }
  // the deviation of each transition stays within its transition length
  for (const CornerReport& r : path.corners) EXPECT_LE(r.deviation, r.parameter * (1 + 1e-6));
}

// ---- line-circle (seed 000 eq. 10-17)

// Line along +x into B = 0; arc from B with tangent +y turning left (about +z), radius r,
// centre (-r, 0, 0): the corner turns left by 90 degrees and the arc keeps turning left.
TEST(BezierBlend, LineCircleCoplanarIsTheCubicOfEq13) {
  const double r = 0.05;
  const double l = 5 * kMm;
  const Line in{Vec3(-0.1, 0, 0), Vec3(0, 0, 0)};
  const Arc out = arc_from(Vec3::Zero(), Vec3::UnitY(), Vec3::UnitZ(), r, kPi);
  const CornerInput c = make_corner(in, out, l);
  const CornerFit fit = fit_bezier_corner(c);
  ASSERT_TRUE(fit.outcome.ok()) << fit.outcome.message;
  EXPECT_EQ(fit.corner_case, CornerCase::kRegular);
  EXPECT_TRUE((fit.fallback == Fallback::kNone)) << fit.fallback;
  const Bezier& b = only_bezier(fit);
  ASSERT_EQ(b.degree(), 3);
  // by hand: P3 at angle theta = L/r on the circle; its tangent (-sin, cos) meets y = 0 at
  // x2 = r (1/cos(theta) - 1), |P3 - P2| = r tan(theta); eq. 13 with sin(alpha) = cos(theta):
  // |P1 - P2| = 3 r^2 tan^2(theta) / (2 r cos(theta)), P1 behind P2.
  const double th = l / r;
  const double x2 = r * (1 / std::cos(th) - 1);
  const double p1p2 = 1.5 * r * std::tan(th) * std::tan(th) / std::cos(th);
  const std::array<Vec3, 4> expected = {Vec3(-l, 0, 0), Vec3(x2 - p1p2, 0, 0), Vec3(x2, 0, 0),
                                        Vec3(-r + r * std::cos(th), r * std::sin(th), 0)};
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_LT((b.control_points()[i] - expected[i]).norm(), kExact) << "P" << i;
  }
  // curvature 1/r towards the centre at P3
  const Vec3 centre(-r, 0, 0);
  EXPECT_LT((bezier_k(b, 1) - (centre - expected[3]) / (r * r)).norm(), 1e-9 / r);
  expect_g2(c, fit);
}

TEST(BezierBlend, LineCircleCoplanarSCurveFallsBackToTheQuartic) {
  // the arc turns right while the corner turns left: the cubic would need P1 beyond P2
  const double r = 0.05;
  const Line in{Vec3(-0.1, 0, 0), Vec3(0, 0, 0)};
  const Arc out = arc_from(Vec3::Zero(), Vec3::UnitY(), -Vec3::UnitZ(), r, kPi);
  const CornerInput c = make_corner(in, out, 5 * kMm);
  const CornerFit fit = fit_bezier_corner(c);
  ASSERT_TRUE(fit.outcome.ok()) << fit.outcome.message;
  EXPECT_EQ(fit.corner_case, CornerCase::kRegular);
  EXPECT_EQ(fit.fallback, Fallback::kQuartic);
  EXPECT_NE(fit.note.text().find("the coplanar cubic of eq. 10-13 is not usable"), std::string::npos) << fit.note;
  EXPECT_EQ(only_bezier(fit).degree(), 4);
  expect_g2(c, fit);
}

TEST(BezierBlend, LineCircleNonCoplanarIsTheMinimumEnergyQuartic) {
  const double r = 0.05;
  const double l = 5 * kMm;
  const Line in{Vec3(-0.1, 0, -0.02), Vec3(0, 0, 0)};
  const Arc out = arc_from(Vec3::Zero(), Vec3::UnitY(), Vec3::UnitZ(), r, kPi);
  const CornerInput c = make_corner(in, out, l);
  const CornerFit fit = fit_bezier_corner(c);
  ASSERT_TRUE(fit.outcome.ok()) << fit.outcome.message;
  EXPECT_EQ(fit.corner_case, CornerCase::kNonPlanar);
  EXPECT_TRUE((fit.fallback == Fallback::kNone));
  const Bezier& b = only_bezier(fit);
  ASSERT_EQ(b.degree(), 4);
  const std::vector<Vec3>& p = b.control_points();
  // P2 = B; eq. 15: |P4 - P3|^2 = (3/4) r^2 (1 - cos(theta)), theta = L / r
  EXPECT_LT(p[2].norm(), kExact);
  EXPECT_NEAR((p[4] - p[3]).squaredNorm(), 0.75 * r * r * (1 - std::cos(l / r)), 1e-12 * r * r);
  EXPECT_LT((p[4] - point(out, l)).norm(), kExact);
  // P1 on the line, and eq. 17 in the paper's own variables
  const Vec3 d = (in.p1 - in.p0).normalized();
  EXPECT_LT((p[1] - p[0]).cross(d).norm(), kExact);
  const Vec3 e2 = (p[3] - p[4]).normalized();
  const double l2 = (p[3] - p[4]).norm();
  const double eq17 = (4 * l + 4 * l2 * d.dot(e2) + 3 * d.dot(p[4] - p[0])) / 16;
  EXPECT_NEAR((p[1] - p[0]).norm(), eq17, kExact);
  // dε/dl1 = 0 numerically: ε is a quadratic in l1, so its central difference vanishes while
  // the second difference is positive (a minimum)
  const double l1 = (p[1] - p[0]).norm();
  const double h = 0.1 * l1;
  std::vector<Vec3> plus = p;
  std::vector<Vec3> minus = p;
  plus[1] = p[0] + (l1 + h) * d;
  minus[1] = p[0] + (l1 - h) * d;
  const double e0 = bending_energy(p);
  const double ep = bending_energy(plus);
  const double em = bending_energy(minus);
  EXPECT_GT(ep + em - 2 * e0, 0.0);
  EXPECT_LT(std::abs(ep - em), 1e-9 * (ep + em - 2 * e0));
  expect_g2(c, fit);
}

TEST(BezierBlend, CircleLineIsTheMirrorOfLineCircle) {
  const double r = 0.03;
  const Arc in = arc_to(Vec3::Zero(), Vec3::UnitX(), Vec3(0, 0.6, 0.8), r, 2.0);
  const Line out{Vec3::Zero(), Vec3(0.05, 0.06, 0.01)};
  const CornerInput c = make_corner(in, out, 4 * kMm);
  const CornerFit fit = fit_bezier_corner(c);
  ASSERT_TRUE(fit.outcome.ok()) << fit.outcome.message;
  EXPECT_EQ(fit.corner_case, CornerCase::kNonPlanar);
  expect_g2(c, fit);
  // the same corner traversed backwards is a line-circle corner with the reversed curve
  const CornerFit mirror = fit_bezier_corner(make_corner(reversed(out), reversed(in), 4 * kMm));
  ASSERT_TRUE(mirror.outcome.ok());
  const std::vector<Vec3>& p = only_bezier(fit).control_points();
  const std::vector<Vec3>& q = only_bezier(mirror).control_points();
  ASSERT_EQ(p.size(), q.size());
  for (std::size_t i = 0; i < p.size(); ++i) EXPECT_LT((p[i] - q[q.size() - 1 - i]).norm(), 1e-12);
}

// ---- circle-circle (seed 000 eq. 18-24)

TEST(BezierBlend, CircleCircleIsTheQuarticOfEq22And24) {
  const double r1 = 0.04;
  const double r2 = 0.02;
  const double l = 5 * kMm;
  const Arc in = arc_to(Vec3::Zero(), Vec3::UnitX(), Vec3::UnitZ(), r1, 1.5);
  const Arc out = arc_from(Vec3::Zero(), Vec3(0, 1, 1).normalized(), Vec3(1, 0, 0), r2, 2.5);
  const CornerInput c = make_corner(in, out, l);
  const CornerFit fit = fit_bezier_corner(c);
  ASSERT_TRUE(fit.outcome.ok()) << fit.outcome.message;
  EXPECT_EQ(fit.corner_case, CornerCase::kNonPlanar);
  const std::vector<Vec3>& p = only_bezier(fit).control_points();
  ASSERT_EQ(p.size(), 5u);
  EXPECT_LT(p[2].norm(), kExact);                                                             // P2 = B
  EXPECT_NEAR((p[1] - p[0]).squaredNorm(), 0.75 * r1 * r1 * (1 - std::cos(l / r1)), 1e-12 * r1 * r1);  // eq. 24
  EXPECT_NEAR((p[4] - p[3]).squaredNorm(), 0.75 * r2 * r2 * (1 - std::cos(l / r2)), 1e-12 * r2 * r2);  // eq. 22
  // eq. 22's middle member: (3/4) r2 |P2 - P3| sin(alpha2) with alpha2 = angle P2 P3 P4
  const double sin_a2 = (p[2] - p[3]).normalized().cross((p[4] - p[3]).normalized()).norm();
  EXPECT_NEAR((p[4] - p[3]).squaredNorm(), 0.75 * r2 * (p[2] - p[3]).norm() * sin_a2, 1e-12 * r2 * r2);
  expect_g2(c, fit);
}

TEST(BezierBlend, SameCircleSameDirectionNeedsNoTransition) {
  const Arc in = arc_to(Vec3::Zero(), Vec3::UnitX(), Vec3::UnitZ(), 0.03, 1.0);
  const Arc out = arc_from(Vec3::Zero(), Vec3::UnitX(), Vec3::UnitZ(), 0.03, 1.0);
  const CornerFit fit = fit_bezier_corner(make_corner(in, out, 5 * kMm));
  ASSERT_TRUE(fit.outcome.ok());
  EXPECT_EQ(fit.corner_case, CornerCase::kSameCircleSameDirection);
  EXPECT_TRUE(fit.transition.empty());
}

TEST(BezierBlend, TangentArcsOfDifferentRadiiGetACurvatureTransition) {
  const Arc in = arc_to(Vec3::Zero(), Vec3::UnitX(), Vec3::UnitZ(), 0.03, 1.0);
  const Arc out = arc_from(Vec3::Zero(), Vec3::UnitX(), -Vec3::UnitZ(), 0.01, 1.0);
  const CornerInput c = make_corner(in, out, 2 * kMm);
  const CornerFit fit = fit_bezier_corner(c);
  ASSERT_TRUE(fit.outcome.ok()) << fit.outcome.message;
  EXPECT_EQ(fit.corner_case, CornerCase::kTangent);
  expect_g2(c, fit);
}

TEST(BezierBlend, TpBeyondAHalfTurnOfASmallArcIsShrunk) {
  const double r = 1 * kMm;
  const Line in{Vec3(-0.1, 0, 0), Vec3(0, 0, 0)};
  const Arc out = arc_from(Vec3::Zero(), Vec3(0, 1, 0.2).normalized(), Vec3(1, 0, 0), r, 2 * kPi);
  const CornerInput c = make_corner(in, out, 5 * kMm);
  const CornerFit fit = fit_bezier_corner(c);
  ASSERT_TRUE(fit.outcome.ok());
  EXPECT_NEAR(fit.trim_out, kPi * r, kExact);
  EXPECT_NE(fit.note.text().find("half-turn"), std::string::npos) << fit.note;
  expect_g2(c, fit);
}

TEST(BezierBlend, HelixIsReportedInfeasible) {
  const Line in{Vec3(-0.1, 0, 0), Vec3(0, 0, 0)};
  Arc out = arc_from(Vec3::Zero(), Vec3::UnitY(), Vec3::UnitZ(), 0.02, 2.0);
  out.rise = 0.01;
  const CornerFit fit = fit_bezier_corner(make_corner(in, out, 5 * kMm));
  EXPECT_EQ(fit.outcome.status, Status::kInfeasible);
  EXPECT_FALSE(fit.outcome.message.empty());
}

// ---- the geometry of scenarios/cases/bezier_*.yaml (in SI), blended with TP = 5 mm

Move scenario_move(const Primitive& geometry) {
  Move move;
  move.geometry = geometry;
  move.limits = {0.05, 0.1, 0.1, 0.2};  // seed 000 section 3.2
  move.transition.method = Method::kBezier;
  move.transition.parameter = 5 * kMm;
  return move;
}

int degree_of_corner(const Path& path, int corner) {
  for (const PathPiece& piece : path.pieces()) {
    if (piece.corner == corner) return std::get<Bezier>(piece.segment).degree();
  }
  return 0;
}

TEST(BezierBlendScenario, LineCircle2dIsACubicThenATangentCorner) {
  Program program;
  const Arc arc = arc_from(Vec3(0.1, 0, 0), Vec3::UnitY(), Vec3::UnitZ(), 0.05, kPi / 2);
  ASSERT_LT((point(arc, length(arc)) - Vec3(0.05, 0.05, 0)).norm(), 1e-15);
  program.moves = {scenario_move(Line{Vec3::Zero(), Vec3(0.1, 0, 0)}), scenario_move(arc),
                   scenario_move(Line{Vec3(0.05, 0.05, 0), Vec3(-0.05, 0.05, 0)})};
  const Path path = blend(program);
  ASSERT_EQ(path.corners.size(), 2u);
  EXPECT_EQ(path.corners[0].corner_case, CornerCase::kRegular);
  EXPECT_EQ(degree_of_corner(path, 0), 3);
  EXPECT_EQ(path.corners[1].corner_case, CornerCase::kTangent);
  EXPECT_EQ(degree_of_corner(path, 1), 3);
  for (const CornerReport& r : path.corners) EXPECT_NEAR(r.parameter, 5 * kMm, kExact);
}

TEST(BezierBlendScenario, LineCircle3dIsAQuartic) {
  Program program;
  program.moves = {scenario_move(Line{Vec3(0, 0, 0.04), Vec3(0.1, 0, 0)}),
                   scenario_move(arc_from(Vec3(0.1, 0, 0), Vec3::UnitY(), Vec3::UnitZ(), 0.05, kPi / 2))};
  const Path path = blend(program);
  EXPECT_EQ(path.corners[0].corner_case, CornerCase::kNonPlanar);
  EXPECT_EQ(degree_of_corner(path, 0), 4);
}

TEST(BezierBlendScenario, CircleCircleIsAQuartic) {
  Program program;
  const Arc a1 = arc_from(Vec3::Zero(), -Vec3::UnitY(), Vec3::UnitZ(), 0.05, kPi);
  const Arc a2 = arc_from(Vec3(0.1, 0, 0), Vec3(-0.8, 0.6, 0), Vec3(0.6, 0.8, 0), 0.05, kPi);
  ASSERT_LT((point(a1, 0.5 * length(a1)) - Vec3(0.05, -0.05, 0)).norm(), 1e-15);  // via
  ASSERT_LT((point(a2, 0.5 * length(a2)) - Vec3(0.06, 0.03, 0.05)).norm(), 1e-15);
  ASSERT_LT((point(a2, length(a2)) - Vec3(0.1, 0, 0.1)).norm(), 1e-15);
  program.moves = {scenario_move(a1), scenario_move(a2)};
  const Path path = blend(program);
  EXPECT_EQ(path.corners[0].corner_case, CornerCase::kNonPlanar);
  EXPECT_EQ(degree_of_corner(path, 0), 4);
  EXPECT_NEAR(path.pieces()[1].kink_angle, 0.0, kG1Tol);
}

TEST(BezierBlendScenario, ShortMovesShareTheirLength) {
  Program program;
  const std::array<Vec3, 6> at = {Vec3(0, 0, 0), Vec3(0.1, 0, 0), Vec3(0.1, 0.006, 0), Vec3(0.2, 0.006, 0),
                                  Vec3(0.2, 0.014, 0), Vec3(0.1, 0.014, 0)};
  for (std::size_t k = 0; k + 1 < at.size(); ++k) program.moves.push_back(scenario_move(Line{at[k], at[k + 1]}));
  const Path path = blend(program);
  const std::array<double, 4> expected = {3 * kMm, 3 * kMm, 4 * kMm, 4 * kMm};
  ASSERT_EQ(path.corners.size(), 4u);
  for (std::size_t k = 0; k < 4; ++k) EXPECT_NEAR(path.corners[k].parameter, expected[k], kExact) << "corner " << k;
}

// ---- seeded random corners

// Corner angle in degrees from 0.001 to 179.999, with extra weight near both ends; arcs may
// also meet tangentially.
double random_angle(std::mt19937_64& rng, bool arcs) {
  const double pick = test::uniform(rng, 0, 1);
  if (arcs && pick < 0.05) return 0.0;
  if (pick < 0.25) return test::log_uniform(rng, 0.001, 1.0) * kPi / 180;
  if (pick < 0.45) return kPi - test::log_uniform(rng, 0.001, 1.0) * kPi / 180;
  return test::uniform(rng, 0.001, 179.999) * kPi / 180;
}

struct RandomCorner {
  CornerInput input;
  int kind = 0;  // 0 line-line, 1 line-arc, 2 arc-line, 3 arc-arc
  bool coplanar = false;
};

RandomCorner random_corner(std::mt19937_64& rng, int kind) {
  RandomCorner rc;
  rc.kind = kind;
  const bool in_arc = kind >= 2;
  const bool out_arc = kind == 1 || kind == 3;
  const Vec3 b(test::uniform(rng, -0.3, 0.3), test::uniform(rng, -0.3, 0.3), test::uniform(rng, -0.3, 0.3));
  const Vec3 t_in = test::random_unit(rng);
  const double phi = random_angle(rng, in_arc || out_arc);
  const Vec3 axis = test::random_perpendicular(rng, t_in);
  const Vec3 t_out = Eigen::AngleAxisd(phi, axis) * t_in;
  // one plane for both moves in a third of the cases (the cubic of eq. 10-13 applies)
  rc.coplanar = test::uniform(rng, 0, 1) < 1.0 / 3;
  const Vec3 plane_n = axis * (test::uniform(rng, 0, 1) < 0.5 ? 1.0 : -1.0);
  const auto length_ = [&] { return test::log_uniform(rng, 1e-4, 1.0); };
  Primitive in;
  Primitive out;
  if (in_arc) {
    const double r = test::log_uniform(rng, 1e-4, 1.0);
    const Vec3 w = rc.coplanar ? plane_n : test::random_perpendicular(rng, t_in);
    in = arc_to(b, t_in, w, r, test::uniform(rng, 0.02, 2 * kPi));
  } else {
    in = Line{b - length_() * t_in, b};
  }
  if (out_arc) {
    const double r = test::log_uniform(rng, 1e-4, 1.0);
    const Vec3 w = rc.coplanar ? (test::uniform(rng, 0, 1) < 0.5 ? plane_n : Vec3(-plane_n))
                               : test::random_perpendicular(rng, t_out);
    out = arc_from(b, t_out, w, r, test::uniform(rng, 0.02, 2 * kPi));
  } else {
    out = Line{b, b + length_() * t_out};
  }
  const double tp = test::log_uniform(rng, 1e-5, 0.1);
  const double in_av = length(in) * (test::uniform(rng, 0, 1) < 0.5 ? 0.5 : 1.0);
  const double out_av = length(out) * (test::uniform(rng, 0, 1) < 0.5 ? 0.5 : 1.0);
  rc.input = make_corner(in, out, tp, in_av, out_av);
  return rc;
}

TEST(BezierBlendProperty, RandomCornersAreG2AndStayWithinTpOfTheCorner) {
  const int cases = test::property_cases(4000);
  Junction worst;
  worst.bound = -1;
  int cubic_coplanar = 0;
  int quartic_fallback = 0;
  std::array<int, 4> count{};
  for (int i = 0; i < cases; ++i) {
    const std::uint64_t seed = 1000 + static_cast<std::uint64_t>(i);
    auto rng = test::make_rng(seed);
    const RandomCorner rc = random_corner(rng, i % 4);
    const CornerInput& c = rc.input;
    const CornerFit fit = fit_bezier_corner(c);
    SCOPED_TRACE(test::seed_text(seed) + " kind=" + std::to_string(rc.kind) + " case=" + std::string(to_string(fit.corner_case)));
    ASSERT_TRUE(fit.outcome.ok()) << fit.outcome.message;
    // Algorithm 1 with availability: never more than TP or than a move offers
    EXPECT_LE(fit.trim_in, c.spec.parameter);
    EXPECT_LE(fit.trim_in, c.in_available);
    EXPECT_LE(fit.trim_out, c.out_available);
    EXPECT_EQ(fit.trim_in, fit.trim_out);
    if (fit.transition.empty()) {
      const double angle = angle_between(tangent(c.in, length(c.in)), tangent(c.out, 0.0));
      const bool expected_empty = fit.corner_case == CornerCase::kReversal || fit.corner_case == CornerCase::kCollinear ||
                                  fit.corner_case == CornerCase::kSameCircleSameDirection;
      EXPECT_TRUE(expected_empty) << "angle " << angle;
      continue;
    }
    ++count[static_cast<std::size_t>(rc.kind)];
    const Bezier& b = only_bezier(fit);
    for (const Vec3& p : b.control_points()) ASSERT_TRUE(p.allFinite());
    ASSERT_TRUE(std::isfinite(b.length()));
    if (rc.kind == 1 || rc.kind == 2) {
      if (b.degree() == 3) ++cubic_coplanar;
      if (!(fit.fallback == Fallback::kNone)) ++quartic_fallback;
      // the cubic needs the line in the circle's plane (a tangent line always is)
      if (!rc.coplanar && fit.corner_case != CornerCase::kTangent) {
        EXPECT_EQ(b.degree(), 4);
      }
    }
    const Junction j = measure(c, fit);
    EXPECT_LE(j.pos, kPosTol);
    EXPECT_LE(j.g1, kG1Tol);
    EXPECT_LE(j.g2, kG2Tol);
    EXPECT_LE(j.bound, kBoundSlack);
    worst.pos = std::max(worst.pos, j.pos);
    worst.g1 = std::max(worst.g1, j.g1);
    worst.g2 = std::max(worst.g2, j.g2);
    worst.bound = std::max(worst.bound, j.bound);
    const double kmax = max_curvature(fit.transition[0], 0, b.length());
    EXPECT_TRUE(std::isfinite(kmax));
  }
  std::cout << "[bezier property] cases " << cases << " fitted ll/la/al/aa " << count[0] << "/" << count[1] << "/"
            << count[2] << "/" << count[3] << ", coplanar cubics " << cubic_coplanar << ", cubic->quartic fallbacks "
            << quartic_fallback << "; worst: position " << worst.pos << " (of L), G1 " << worst.g1
            << " rad, G2 " << worst.g2 << " (relative), max (|C - B| - L) / (|B| + L) " << worst.bound << "\n";
}

TEST(BezierBlendProperty, QuarticLineArmMinimisesTheBendingEnergy) {
  const int cases = test::property_cases(4000) / 8;
  int checked = 0;
  for (int i = 0; i < cases * 4 && checked < cases; ++i) {
    const std::uint64_t seed = 50000 + static_cast<std::uint64_t>(i);
    auto rng = test::make_rng(seed);
    const RandomCorner rc = random_corner(rng, 1 + i % 2);
    const CornerFit fit = fit_bezier_corner(rc.input);
    if (fit.transition.empty() || only_bezier(fit).degree() != 4) continue;
    SCOPED_TRACE(test::seed_text(seed));
    ++checked;
    std::vector<Vec3> p = only_bezier(fit).control_points();
    if (rc.kind == 2) std::reverse(p.begin(), p.end());  // the line is at the end: mirror
    const Vec3 d = (p[1] - p[0]).normalized();
    const double l1 = (p[1] - p[0]).norm();
    // the derived range of the minimum-energy arm: P1 strictly between P0 and B
    EXPECT_GE(l1, 0.096 * fit.trim_in);
    EXPECT_LE(l1, 0.78 * fit.trim_in);
    const double h = 0.1 * l1;
    std::vector<Vec3> plus = p;
    std::vector<Vec3> minus = p;
    plus[1] = p[0] + (l1 + h) * d;
    minus[1] = p[0] + (l1 - h) * d;
    const double e0 = bending_energy(p);
    const double ep = bending_energy(plus);
    const double em = bending_energy(minus);
    EXPECT_GT(ep + em - 2 * e0, 0.0);
    EXPECT_LT(std::abs(ep - em), 1e-6 * (ep + em - 2 * e0));
  }
  EXPECT_GT(checked, 0);
}

// ---- whole programs through blend()

Program random_program(std::mt19937_64& rng) {
  Program program;
  const int n = 2 + static_cast<int>(test::uniform(rng, 0, 6));
  Vec3 at(test::uniform(rng, -0.2, 0.2), test::uniform(rng, -0.2, 0.2), test::uniform(rng, -0.2, 0.2));
  Vec3 dir = test::random_unit(rng);
  const bool planar = test::uniform(rng, 0, 1) < 0.3;
  const Vec3 plane_n = any_perpendicular(dir);
  for (int k = 0; k < n; ++k) {
    Move move;
    move.limits = {0.05, 0.1, 0.1, 0.2};
    move.buffer = test::uniform(rng, 0, 1) < 0.2 ? BufferMode::kBuffered : BufferMode::kBlendingLow;
    move.transition.method = Method::kBezier;
    move.transition.parameter = test::log_uniform(rng, 1e-4, 0.05);
    // turn the direction by a random angle (in the plane for planar programs)
    const double phi = random_angle(rng, false);
    const Vec3 axis = planar ? plane_n : test::random_perpendicular(rng, dir);
    const Vec3 next_dir = k == 0 ? dir : Vec3(Eigen::AngleAxisd(phi, axis) * dir);
    if (test::uniform(rng, 0, 1) < 0.5) {
      move.geometry = Line{at, at + test::log_uniform(rng, 1e-3, 0.3) * next_dir};
    } else {
      const Vec3 w = planar ? plane_n * (test::uniform(rng, 0, 1) < 0.5 ? 1.0 : -1.0) : test::random_perpendicular(rng, next_dir);
      move.geometry = arc_from(at, next_dir, w, test::log_uniform(rng, 1e-3, 0.2), test::uniform(rng, 0.1, 2 * kPi));
    }
    const double len = length(move.geometry);
    at = point(move.geometry, len);
    dir = tangent(move.geometry, len);
    program.moves.push_back(move);
  }
  return program;
}

TEST(BezierBlendProperty, RandomProgramsBlendToG2Paths) {
  const int cases = std::max(1, test::property_cases(4000) / 320);
  double worst_gap = 0;
  double worst_g2 = 0;
  for (int i = 0; i < cases; ++i) {
    const std::uint64_t seed = 90000 + static_cast<std::uint64_t>(i);
    auto rng = test::make_rng(seed);
    const Program program = random_program(rng);
    SCOPED_TRACE(test::seed_text(seed));
    const Path path = blend(program);
    ASSERT_EQ(path.corners.size(), program.moves.size() - 1);
    for (const CornerReport& r : path.corners) {
      // only a fillet that would be a cusp is refused (corner.hpp: radius below 1 % of TP)
      EXPECT_TRUE(r.fallback != Fallback::kExactStop || r.note.text().find("would be a cusp") != std::string::npos) << r.note;
      EXPECT_TRUE(std::isfinite(r.deviation) && std::isfinite(r.kappa_max) && std::isfinite(r.sharpness_max));
      EXPECT_LE(r.deviation, r.parameter * (1 + 1e-6) + 1e-12) << r.corner_case;
      EXPECT_LE(r.parameter, program.moves[static_cast<std::size_t>(r.index)].transition.parameter);
    }
    // consecutive pieces: continuous, G1 except at a reversal, G2 wherever a Bezier meets a move
    const auto& pieces = path.pieces();
    for (std::size_t k = 1; k < pieces.size(); ++k) {
      const Segment& a = pieces[k - 1].segment;
      const Segment& b = pieces[k].segment;
      const double la = length(a);
      const double scale = std::max(la, length(b));
      const double gap = (end_point(a) - start_point(b)).norm() / scale;
      worst_gap = std::max(worst_gap, gap);
      EXPECT_LE(gap, kPosTol);
      const bool bezier_junction = std::holds_alternative<Bezier>(a) || std::holds_alternative<Bezier>(b);
      if (!bezier_junction) continue;
      EXPECT_LE(pieces[k].kink_angle, kG1Tol);
      const Bezier& bz = std::holds_alternative<Bezier>(a) ? std::get<Bezier>(a) : std::get<Bezier>(b);
      const Vec3 ka = curvature_vector(a, la);
      const Vec3 kb = curvature_vector(b, 0.0);
      const double g2 = (ka - kb).norm() / (std::min(ka.norm(), kb.norm()) + 1 / bz.length());
      worst_g2 = std::max(worst_g2, g2);
      EXPECT_LE(g2, kG2Tol);
    }
    for (double s = 0; s <= path.length(); s += path.length() / 97) ASSERT_TRUE(path.point(s).allFinite());
  }
  std::cout << "[bezier programs] cases " << cases << "; worst gap " << worst_gap << " (of piece length), G2 "
            << worst_g2 << " (relative)\n";
}

}  // namespace
}  // namespace blendbench
