// Equal tolerance (fit_corner_at_tolerance, docs/methods.md): every method's parameter solved so
// that the corner's deviation equals the tolerance, checked against an independent dense measure
// of the deviation (test::Chain, not the planner's hausdorff_within nor the closed forms).

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <tuple>
#include <vector>

#include "blendbench/corner/blend.hpp"
#include "blendbench/corner/corner.hpp"
#include "support/chain_distance.hpp"
#include "support/corner_check.hpp"
#include "support/property.hpp"
#include "support/random_corner.hpp"

namespace blendbench {
namespace {

constexpr std::array kMethods = {Method::kArc, Method::kBezier, Method::kClothoid, Method::kBiclothoid};
constexpr double kPi = std::numbers::pi;
// The independent measure (test::Chain: 128 samples and a golden-section refinement) agrees with
// the planner's deviation to this share of the corner's size (its trims and transition length),
// where it is exact on lines and arcs and refines the rest.
constexpr double kIndependentAgreement = 1e-7;

// The deviation of `fit` at `corner` by the independent measure: both directed distances between
// the transition and the replaced stretch; for a fit without a transition, from the skipped
// stretch to the kept path.
double independent_deviation(const CornerInput& corner, const CornerFit& fit) {
  if (!fit.transition.empty()) return test::check_fit(corner, fit).deviation;
  const double len_in = length(corner.in);
  const double len_out = length(corner.out);
  std::vector<Segment> skipped;
  std::vector<Segment> kept;
  if (fit.trim_in > 0) {
    skipped.push_back(to_segment(sub_segment(corner.in, len_in - fit.trim_in, len_in)));
    if (fit.trim_in < len_in) kept.push_back(to_segment(sub_segment(corner.in, 0, len_in - fit.trim_in)));
  }
  if (fit.trim_out > 0) {
    skipped.push_back(to_segment(sub_segment(corner.out, 0, fit.trim_out)));
    if (fit.trim_out < len_out) kept.push_back(to_segment(sub_segment(corner.out, fit.trim_out, len_out)));
  }
  if (skipped.empty() || kept.empty()) return 0;
  return test::Chain(skipped).directed_to(test::Chain(kept));
}

// The size the independent measure's accuracy is relative to.
double corner_size(const CornerFit& fit) {
  double len = fit.trim_in + fit.trim_out;
  for (const Segment& seg : fit.transition) len += length(seg);
  return len;
}

CornerInput line_line(double theta, double len_in, double len_out, Method method, double tolerance) {
  CornerInput c;
  const Vec3 t2(std::cos(theta), std::sin(theta), 0);
  c.in = Line{Vec3(-len_in, 0, 0), Vec3::Zero()};
  c.out = Line{Vec3::Zero(), len_out * t2};
  c.in_available = len_in;
  c.out_available = len_out;
  c.spec.method = method;
  c.spec.tolerance = tolerance;
  c.name = "corner";
  return c;
}

// A non-planar corner: a line arriving at an arc from out of the arc's plane, or two arcs in
// planes tilted by 5-85 degrees against each other (random_corner's are all planar).
CornerInput random_non_planar(std::mt19937_64& rng, bool two_arcs, Method method) {
  const auto log_uniform = [&](double lo, double hi) { return test::log_uniform(rng, lo, hi); };
  const Vec3 n1 = Vec3(test::uniform(rng, -1, 1), test::uniform(rng, -1, 1), test::uniform(rng, -1, 1)).normalized();
  const Vec3 x = any_perpendicular(n1);
  const Vec3 t_out = x;  // the arc leaves the corner along x, in the plane of normal n1
  const double tilt = test::uniform(rng, 5, 85) * kPi / 180;
  const double turn = test::uniform(rng, 5, 150) * kPi / 180;
  // the incoming tangent: turned by `turn` from t_out, out of the plane by `tilt`
  const Vec3 in_plane = std::cos(turn) * t_out + std::sin(turn) * n1.cross(t_out);
  const Vec3 t_in = (std::cos(tilt) * in_plane + std::sin(tilt) * n1).normalized();
  const Vec3 corner(test::uniform(rng, -0.1, 0.1), test::uniform(rng, -0.1, 0.1), test::uniform(rng, -0.1, 0.1));
  CornerInput c;
  const double r2 = log_uniform(1e-3, 1);
  c.out = test::arc_leaving(corner, t_out, n1, test::uniform(rng, 0, 1) < 0.5 ? 1.0 : -1.0, r2,
                            test::uniform(rng, 0.3, 1.5 * kPi));
  if (two_arcs) {
    const Vec3 n2 = t_in.cross(n1).cross(t_in).normalized();  // a plane through t_in
    const Vec3 n_in = (std::cos(tilt) * n2 + std::sin(tilt) * t_in.cross(n2)).normalized();
    const Vec3 n_arc = (n_in - n_in.dot(t_in) * t_in).normalized();
    c.in = test::arc_arriving(corner, t_in, n_arc, test::uniform(rng, 0, 1) < 0.5 ? 1.0 : -1.0, log_uniform(1e-3, 1),
                              test::uniform(rng, 0.3, 1.5 * kPi));
  } else {
    c.in = Line{corner - log_uniform(1e-3, 1) * t_in, corner};
  }
  c.in_available = length(c.in);
  c.out_available = 0.5 * length(c.out);
  c.spec.method = method;
  c.name = "non-planar corner";
  return c;
}

// The tolerance fit as the blender makes it: near reversals first (corner.hpp), the same rule
// for every method, then the solve.
CornerFit fit_as_blended(const CornerInput& corner) {
  const double theta = angle_between(tangent(corner.in, length(corner.in)), tangent(corner.out, 0.0));
  if (auto kink = near_reversal_fit(corner, theta)) return *kink;
  return fit_corner_at_tolerance(corner);
}

// Outcome counts of a random run, for the property tests' messages.
struct Tally {
  int cases = 0;
  int reached = 0;
  int limited = 0;
  int no_cut = 0;
  int failed = 0;
  int jumps = 0;     // below the band where the deviation jumps past it (a change of construction, a cusp)
  int short_of = 0;  // below the band for no reason the fit gives
  std::string text() const {
    return std::to_string(cases) + " corners: " + std::to_string(reached) + " reached, " + std::to_string(limited) +
           " limited by the moves, " + std::to_string(no_cut) + " nothing to cut, " + std::to_string(jumps) +
           " at a jump, " + std::to_string(failed) + " no fit, " + std::to_string(short_of) + " short of it otherwise";
  }
};

// Checks one tolerance fit: never above the tolerance by the independent measure, the reported
// deviation agrees with it, and it reaches the tolerance unless the fit says why not.
void check_tolerance_fit(const CornerInput& corner, const std::string& what, Tally& tally) {
  ++tally.cases;
  const double tol = corner.spec.tolerance;
  const CornerFit fit = fit_as_blended(corner);
  if (!fit.outcome.ok()) {
    ++tally.failed;
    return;
  }
  const double reported = corner_deviation(fit, corner.in, corner.out);
  const double independent = independent_deviation(corner, fit);
  const double slack = kIndependentAgreement * corner_size(fit);
  ASSERT_LE(reported, tol) << what;
  ASSERT_LE(independent, tol + slack) << what << ": reported " << reported;
  ASSERT_NEAR(reported, independent, slack + 1e-9 * tol) << what;
  ASSERT_TRUE(std::isfinite(fit.parameter_used)) << what;
  const bool reached = reported >= tol * (1 - kToleranceBand);
  if (reached) {
    ++tally.reached;
    // within 1 % by the independent measure (the acceptance)
    ASSERT_GE(independent, 0.99 * tol) << what;
  } else if (fit.limited) {
    ++tally.limited;
  } else if (reported <= 1e-9 * tol) {
    ++tally.no_cut;
  } else if (fit.note.text().find("jumps past the tolerance") != std::string::npos) {
    ++tally.jumps;
  } else {
    ++tally.short_of;
    std::printf("short: %s: reported %.9g of %.9g, note: %s\n", what.c_str(), reported, tol, fit.note.text().c_str());
  }
}

TEST(ToleranceFit, LineLineClosedFormsAreTheDeviation) {
  // hand-derived: arc dev = d tan(theta / 4), bezier dev = TP sin(theta / 2) / 4, the
  // clothoid pair's the tolerance itself; each against the dense measure, long moves
  const double tol = 0.2e-3;
  for (const double deg : {1.0, 30.0, 90.0, 120.0, 150.0}) {
    const double theta = deg * kPi / 180;
    for (const Method method : kMethods) {
      const CornerInput c = line_line(theta, 1.0, 1.0, method, tol);
      const CornerFit fit = fit_corner_at_tolerance(c);
      ASSERT_TRUE(fit.outcome.ok()) << deg;
      const double dense = independent_deviation(c, fit);
      EXPECT_NEAR(dense, tol, 1e-9 * tol + kIndependentAgreement * corner_size(fit)) << to_string(method) << " " << deg;
      EXPECT_LE(corner_deviation(fit, c.in, c.out), tol);
      if (method == Method::kArc) {
        EXPECT_NEAR(fit.parameter_used, tol / std::tan(theta / 4), 1e-9 * fit.parameter_used);
      }
      if (method == Method::kBezier) {
        EXPECT_NEAR(fit.parameter_used, 4 * tol / std::sin(theta / 2), 1e-9 * fit.parameter_used);
      }
    }
  }
}

TEST(ToleranceFit, RandomPlanarCornersReachTheToleranceAndNeverExceedIt) {
  const int n = test::property_cases(150);
  for (const Method method : kMethods) {
    for (int kind = 0; kind < 4; ++kind) {
      Tally tally;
      for (int i = 0; i < n; ++i) {
        const std::uint64_t seed = 71000 + 10000 * static_cast<std::uint64_t>(method) + 1000 * kind + i;
        auto rng = test::make_rng(seed);
        CornerInput c = test::random_corner(rng, static_cast<test::CornerKind>(kind), method).input;
        c.spec.tolerance = test::log_uniform(rng, 1e-6, 1e-3);
        c.spec.parameter = 0;
        check_tolerance_fit(c, std::string(to_string(method)) + " kind " + std::to_string(kind) + " " + test::seed_text(seed),
                            tally);
        if (::testing::Test::HasFatalFailure()) return;
      }
      std::printf("%s kind %d: %s\n", std::string(to_string(method)).c_str(), kind, tally.text().c_str());
      EXPECT_EQ(tally.short_of, 0) << tally.text();
      EXPECT_LE(tally.jumps, 1 + tally.cases / 50) << tally.text();  // (1 in 150 seen)
    }
  }
}

TEST(ToleranceFit, RandomNonPlanarCornersReachTheToleranceAndNeverExceedIt) {
  const int n = test::property_cases(100);
  for (const Method method : kMethods) {
    for (const bool two_arcs : {false, true}) {
      Tally tally;
      for (int i = 0; i < n; ++i) {
        const std::uint64_t seed = 91000 + 10000 * static_cast<std::uint64_t>(method) + 1000 * two_arcs + i;
        auto rng = test::make_rng(seed);
        CornerInput c = random_non_planar(rng, two_arcs, method);
        c.spec.tolerance = test::log_uniform(rng, 1e-6, 1e-3);
        check_tolerance_fit(c, std::string(to_string(method)) + (two_arcs ? " arc-arc " : " line-arc ") + test::seed_text(seed),
                            tally);
        if (::testing::Test::HasFatalFailure()) return;
      }
      std::printf("%s non-planar %s: %s\n", std::string(to_string(method)).c_str(), two_arcs ? "arc-arc" : "line-arc",
                  tally.text().c_str());
      EXPECT_EQ(tally.short_of, 0) << tally.text();
      EXPECT_LE(tally.jumps, 1 + tally.cases / 50) << tally.text();  // (1 in 150 seen)
    }
  }
}

// rad: the share of an arc a Bezier may replace with its deviation still growing with TP.
constexpr double kBezierMonotoneTurn = 1.0;
// The turn (rad) of `length` of a move, 0 on a line.
double arc_turn(const Primitive& move, double length) {
  const Arc* arc = std::get_if<Arc>(&move);
  return arc != nullptr ? length / arc->radius : 0.0;
}

// dev(p) against the method's parameter p on a log grid, as the solve measures it: it never
// falls while the fit keeps its construction (case and fallback), so the solve's bracket holds;
// where the construction changes it may jump either way, which the solve treats as a jump (the
// count is printed: the arc's rule with the roles swapped drops it, docs/methods.md).
TEST(ToleranceFit, DeviationGrowsWithTheParameterOnEachConstruction) {
  const int n = test::property_cases(40);
  for (const Method method : kMethods) {
    int drops_at_a_switch = 0;
    for (int kind = 0; kind < 4; ++kind) {
      for (int i = 0; i < n; ++i) {
        const std::uint64_t seed = 131000 + 10000 * static_cast<std::uint64_t>(method) + 1000 * kind + i;
        auto rng = test::make_rng(seed);
        CornerInput c = test::random_corner(rng, static_cast<test::CornerKind>(kind), method).input;
        const double theta = angle_between(tangent(c.in, length(c.in)), tangent(c.out, 0.0));
        if (theta >= kPi - kNearReversalAngle) continue;  // the blender leaves the kink (corner.hpp)
        double previous = -1;
        CornerFit last;
        for (double p = 1e-6; p < 1.0; p *= 1.5) {
          c.spec.parameter = p;
          CornerFit fit;
          switch (method) {
            case Method::kArc: fit = fit_arc_corner(c); break;
            case Method::kBezier: fit = fit_bezier_corner(c); break;
            case Method::kClothoid: fit = fit_clothoid_corner(c); break;
            default: fit = fit_biclothoid_corner(c); break;
          }
          if (!fit.outcome.ok()) {
            previous = -1;
            continue;
          }
          // the deviation the solve sees (the planner's measure: the random tests check it against
          // the independent one)
          const double dev = corner_deviation(fit, c.in, c.out);
          const double slack = 1e-9 * corner_size(fit) + 1e-15;
          // (a Bezier that replaces more than kBezierMonotoneTurn of an arc cuts across the circle,
          // and its deviation falls again before TP reaches the half-turn cap)
          const double turn = std::max(arc_turn(c.in, fit.parameter_used), arc_turn(c.out, fit.parameter_used));
          if (method == Method::kBezier && turn > kBezierMonotoneTurn) break;
          // (seed 004's Algorithm 2, limited by the moves, takes the largest start distance that
          // fits, on some corners a fillet of another branch of Algorithm 1 with a smaller deviation)
          const bool biclothoid = method == Method::kClothoid || method == Method::kBiclothoid;
          const bool same = previous >= 0 && fit.corner_case == last.corner_case && fit.fallback == last.fallback &&
                            (!biclothoid || fit.limited == last.limited);
          if (same) {
            ASSERT_GE(dev, previous - slack) << to_string(method) << " kind " << kind << " p " << p << " " << test::seed_text(seed);
          } else if (previous >= 0 && dev < previous - slack) {
            ++drops_at_a_switch;
          }
          previous = dev;
          last = fit;
        }
      }
    }
    std::printf("%s: %d drops where the construction changes\n", std::string(to_string(method)).c_str(), drops_at_a_switch);
  }
}

// The special cases (docs/methods.md, "Equal tolerance").
TEST(ToleranceFit, SpecialCasesSayWhetherTheToleranceIsReached) {
  const double tol = 0.1e-3;
  // collinear lines (and lines within the G1 threshold of it): nothing to cut, for every method,
  // on long moves and on moves shorter than the tolerance
  for (const auto& [method, theta, len] : {std::tuple{Method::kArc, 0.0, 0.1}, std::tuple{Method::kArc, 1e-11, 0.1},
                                           std::tuple{Method::kArc, 0.0, 0.05e-3}, std::tuple{Method::kBezier, 0.0, 0.1},
                                           std::tuple{Method::kBezier, 1e-11, 0.05e-3}, std::tuple{Method::kClothoid, 0.0, 0.1},
                                           std::tuple{Method::kBiclothoid, 0.0, 0.05e-3}}) {
    const CornerFit fit = fit_as_blended(line_line(theta, len, len, method, tol));
    ASSERT_TRUE(fit.outcome.ok());
    EXPECT_EQ(fit.corner_case, CornerCase::kCollinear) << to_string(method);
    EXPECT_TRUE(fit.transition.empty()) << to_string(method);
    EXPECT_LE(corner_deviation(fit, Line{Vec3(-len, 0, 0), Vec3::Zero()}, Line{Vec3::Zero(), Vec3(len, 0, 0)}), 1e-15);
    EXPECT_NE(fit.note.text().find("nothing to cut"), std::string::npos) << to_string(method) << " " << fit.note.text();
  }
  // a line reversal (seed 001 fig. 7-3): the arc shortens both lines by d, so the corner is d from
  // the kept path: d = T, reached; the curve methods leave the kink (nothing to cut)
  {
    const CornerInput c = line_line(kPi, 0.1, 0.1, Method::kArc, tol);
    const CornerFit fit = fit_as_blended(c);
    EXPECT_EQ(fit.corner_case, CornerCase::kReversal);
    EXPECT_NEAR(fit.parameter_used, tol, 1e-12 * tol);
    EXPECT_NEAR(independent_deviation(c, fit), tol, 1e-9 * tol);
  }
  // a near reversal: every method leaves the kink
  for (const Method method : kMethods) {
    const CornerFit fit = fit_as_blended(line_line(178 * kPi / 180, 0.1, 0.1, method, tol));
    EXPECT_EQ(fit.corner_case, CornerCase::kNearReversal);
    EXPECT_TRUE(fit.transition.empty());
  }
  // moves too short for the tolerance: the largest transition that fits (limited), below T, and
  // the same as the method's own fit at the largest parameter
  for (const Method method : kMethods) {
    CornerInput c = line_line(kPi / 2, 1e-3, 2e-3, method, 1e-3);  // T = 1 mm on a 1 mm move
    const CornerFit fit = fit_as_blended(c);
    ASSERT_TRUE(fit.outcome.ok());
    EXPECT_TRUE(fit.limited) << to_string(method);
    const double dev = independent_deviation(c, fit);
    EXPECT_LT(dev, 0.99e-3) << to_string(method);
    EXPECT_GT(dev, 0.0);
    c.spec.tolerance = 0;
    c.spec.parameter = 1.0;  // far more than fits
    CornerFit largest = method == Method::kArc ? fit_arc_corner(c) : method == Method::kBezier ? fit_bezier_corner(c)
                        : method == Method::kClothoid ? fit_clothoid_corner(c) : fit_biclothoid_corner(c);
    EXPECT_NEAR(independent_deviation(c, largest), dev, 1e-9) << to_string(method);
    EXPECT_NE(fit.note.text().find("not reached"), std::string::npos) << fit.note.text();
  }
  // the clothoid capped in curvature (seed 002 figs. 12-13): clothoid-arc-clothoid at the tolerance
  {
    CornerInput c = line_line(kPi / 2, 0.1, 0.1, Method::kClothoid, tol);
    c.spec.kappa_max = 1 / 0.2e-3;  // the pair at 0.1 mm peaks at 1 / 0.175 mm; an arc of 0.2 mm deviates 0.083 mm
    const CornerFit fit = fit_as_blended(c);
    ASSERT_TRUE(fit.outcome.ok());
    EXPECT_EQ(fit.corner_case, CornerCase::kClothoidArcClothoid);
    const double dev = independent_deviation(c, fit);
    EXPECT_LE(dev, tol * (1 + 1e-9));
    EXPECT_GE(dev, tol * (1 - kToleranceBand));
    EXPECT_LE(test::peak_curvature(fit), c.spec.kappa_max * (1 + 1e-9));
  }
  // arcs on one circle (seed 003): continued the same way, nothing to cut (the arc inserts no piece
  // of it); turned back, both shortened by d and the corner lies a chord of d from the kept path
  {
    const Arc whole = test::arc_leaving(Vec3::Zero(), Vec3::UnitX(), Vec3::UnitZ(), 1.0, 0.05, kPi);
    CornerInput c;
    c.in = sub_segment(whole, 0, 0.5 * length(whole));
    c.out = sub_segment(whole, 0.5 * length(whole), length(whole));
    c.in_available = length(c.in);
    c.out_available = length(c.out);
    c.spec.method = Method::kArc;
    c.spec.tolerance = tol;
    const CornerFit same = fit_as_blended(c);
    EXPECT_EQ(same.corner_case, CornerCase::kSameCircleSameDirection);
    EXPECT_TRUE(same.transition.empty());
    EXPECT_EQ(same.parameter_used, 0.0);
    // the same circle backwards: out runs back along in
    const Arc back = test::arc_leaving(point(c.in, length(c.in)), -tangent(c.in, length(c.in)), Vec3::UnitZ(), -1.0, 0.05,
                                       0.5 * kPi);
    c.out = back;
    c.out_available = length(back);
    const CornerFit opposite = fit_as_blended(c);
    EXPECT_EQ(opposite.corner_case, CornerCase::kSameCircleOppositeDirection);
    const double dev = independent_deviation(c, opposite);
    EXPECT_LE(dev, tol * (1 + 1e-9));
    EXPECT_GE(dev, tol * (1 - kToleranceBand));
    // the chord of d on the circle is T: d = 2 R asin(T / 2R)
    EXPECT_NEAR(opposite.parameter_used, 2 * 0.05 * std::asin(tol / 0.1), 1e-3 * tol);
  }
}

}  // namespace
}  // namespace blendbench
