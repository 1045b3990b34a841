#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <variant>

#include "blendbench/core/input_error.hpp"
#include "blendbench/corner/blend.hpp"
#include "support/property.hpp"
#include "support/oriented_program.hpp"

namespace blendbench {
namespace {

using test::random_program;

constexpr double kJoin = 1e-9;  // rad, and relative for rates

// The target at the end of move k (the last one set before it, or the start).
Quat target_of(const Program& program, int k) {
  for (int i = k; i >= 0; --i) {
    if (program.moves[static_cast<std::size_t>(i)].orientation) return *program.moves[static_cast<std::size_t>(i)].orientation;
  }
  return program.start_orientation;
}

// At the junction from piece a to piece b: dtheta/ds continuous (to kJoin relative), and its
// derivative too (one-sided differences on either side, against the largest rho' on the two).
// A program from the identity along a 100 mm line on x to `target` (0.2 m/s, 2 m/s^2, 20 m/s^3).
Program one_line_to(const Quat& target) {
  Program program;
  program.start_orientation = Quat::Identity();
  Move a;
  a.geometry = Line{Vec3::Zero(), Vec3(0.1, 0, 0)};
  a.limits = {0.2, 2.0, 2.0, 20.0};
  a.orientation = target;
  program.moves = {a};
  return program;
}

void expect_rate_continuous(const PathPiece& a, const PathPiece& b, std::uint64_t seed, std::size_t k) {
  const double la = length(a.segment);
  const double lb = length(b.segment);
  const Vec3 ra = angular_rate_at(*a.orientation, la);
  const Vec3 rb = angular_rate_at(*b.orientation, 0.0);
  const double scale = std::max({1.0, ra.norm(), rb.norm()});
  ASSERT_LE((ra - rb).norm(), kJoin * scale) << test::seed_text(seed) << " junction " << k;
  const double h = 1e-7 * std::min(la, lb);
  const Vec3 da = (ra - angular_rate_at(*a.orientation, la - h)) / h;
  const Vec3 db = (angular_rate_at(*b.orientation, h) - rb) / h;
  const double d_max = std::max(rotation_bounds(*a.orientation, la, 0, la).rate_d1, rotation_bounds(*b.orientation, lb, 0, lb).rate_d1);
  ASSERT_LE((da - db).norm(), 1e-4 * d_max + 1e-6 * scale / std::min(la, lb)) << test::seed_text(seed) << " junction " << k;
}

// Every junction of every blended random program: the orientation is continuous; where a
// transition joins, so are dtheta/ds and d2theta/ds2 (angular velocity and acceleration at
// any profile); every exact stop holds its corner's target and the path ends on the last one
// (position and orientation arrive together); each corner's orientation change is what its
// transition turns by.
TEST(OrientPath, ContinuousAtEveryJunctionAndArrivesWithThePosition) {
  const int cases = test::property_cases(300);
  int transitions = 0;
  for (int c = 0; c < cases; ++c) {
    const std::uint64_t seed = 7100 + static_cast<std::uint64_t>(c);
    auto rng = test::make_rng(seed);
    const Program program = random_program(rng);
    const Path path = blend(program);
    ASSERT_TRUE(path.oriented()) << test::seed_text(seed);
    const auto& pieces = path.pieces();
    for (std::size_t k = 0; k + 1 < pieces.size(); ++k) {
      const PathPiece& a = pieces[k];
      const PathPiece& b = pieces[k + 1];
      const double la = length(a.segment);
      const Quat qa = orientation_at(*a.orientation, la);
      const Quat qb = orientation_at(*b.orientation, 0.0);
      ASSERT_LE(rotation_angle(qa, qb), kJoin) << test::seed_text(seed) << " junction " << k;
      // at a stop the rate may jump (the tool is at rest there)
      if ((a.corner < 0 && b.corner < 0) || b.stop_before) continue;
      ++transitions;
      expect_rate_continuous(a, b, seed, k);
      if (::testing::Test::HasFatalFailure()) return;
    }
    // exact stops: the corner's target
    for (const CornerReport& r : path.corners) {
      if (r.corner_case != CornerCase::kExactStop) continue;
      // the first piece past the corner starts at it (an exact stop trims nothing)
      std::size_t k = 0;
      while (k < pieces.size() && pieces[k].move <= r.index && pieces[k].corner < r.index + 1) ++k;
      ASSERT_LT(k, pieces.size()) << test::seed_text(seed);
      const double s = path.offset(k);
      ASSERT_LE(rotation_angle(path.orientation(s), target_of(program, r.index)), kJoin) << test::seed_text(seed);
    }
    ASSERT_LE(rotation_angle(path.orientation(path.length()), target_of(program, static_cast<int>(program.moves.size()) - 1)), kJoin)
        << test::seed_text(seed);
    // the reported change of each transition
    for (std::size_t k = 0; k < pieces.size(); ++k) {
      if (pieces[k].corner < 0 || (k > 0 && pieces[k - 1].corner == pieces[k].corner)) continue;
      std::size_t last = k;
      while (last + 1 < pieces.size() && pieces[last + 1].corner == pieces[k].corner) ++last;
      const double turned = rotation_angle(orientation_at(*pieces[k].orientation, 0.0),
                                           orientation_at(*pieces[last].orientation, length(pieces[last].segment)));
      const auto report = std::find_if(path.corners.begin(), path.corners.end(),
                                       [&](const CornerReport& r) { return r.index == pieces[k].corner; });
      ASSERT_NE(report, path.corners.end());
      ASSERT_NEAR(report->orientation_change, turned, 1e-9) << test::seed_text(seed);
    }
  }
  EXPECT_GT(transitions, cases);  // the property was exercised on transitions
}

// A program without orientation is blended exactly as before: no piece carries one.
TEST(OrientPath, ProgramWithoutOrientationCarriesNone) {
  auto rng = test::make_rng(7000);
  Program program = random_program(rng);
  for (Move& m : program.moves) m.orientation.reset();
  const Path path = blend(program);
  EXPECT_FALSE(path.oriented());
  for (const PathPiece& piece : path.pieces()) EXPECT_FALSE(piece.orientation.has_value());
  for (const CornerReport& r : path.corners) EXPECT_EQ(r.orientation_change, 0.0);
}

// A slerp by arc length about one axis: a quarter turn over a 100 mm line turns 45 degrees by
// its middle; the transition at the corner turns by about what the trimmed parts would have.
TEST(OrientPath, SlerpByArcLengthOnAMove) {
  Program program = one_line_to(Quat(Eigen::AngleAxisd(std::numbers::pi / 2, Vec3::UnitZ())));
  program.moves[0].transition = {Method::kArc, 0.01};
  Move b = program.moves[0];
  b.geometry = Line{Vec3(0.1, 0, 0), Vec3(0.1, 0.1, 0)};
  b.orientation.reset();
  program.moves.push_back(b);
  const Path path = blend(program);
  EXPECT_LE(rotation_angle(path.orientation(0.05), Quat(Eigen::AngleAxisd(std::numbers::pi / 4, Vec3::UnitZ()))), 1e-12);
  EXPECT_LE((path.angular_rate(0.02) - Vec3(0, 0, std::numbers::pi / 2 / 0.1)).norm(), 1e-12);
  ASSERT_EQ(path.corners.size(), 1u);
  // 10 mm of the first move at 15.7 rad/m would turn 9 degrees; the second move does not turn
  EXPECT_NEAR(path.corners[0].orientation_change, 0.01 * std::numbers::pi / 2 / 0.1, 2e-3);
}

// The option spline on random programs: one law over the whole path, continuous with its rate
// and the rate's derivative at every junction (also at exact stops and between moves, where the
// slerp's rate may step); it passes each target where its knot is (the middle of the corner's
// transition, the end of the move at a corner without one) and ends on the last; each corner's
// orientation change is what its transition turns by.
TEST(OrientPath, SplineIsC2AlongTheWholePathAndPassesEveryTarget) {
  const int cases = test::property_cases(200);
  for (int c = 0; c < cases; ++c) {
    const std::uint64_t seed = 7600 + static_cast<std::uint64_t>(c);
    auto rng = test::make_rng(seed);
    Program program = random_program(rng, 0.6);
    program.orientation_interpolation = OrientationInterpolation::kSpline;
    const Path path = blend(program);
    const auto& pieces = path.pieces();
    for (const PathPiece& piece : pieces) ASSERT_TRUE(std::holds_alternative<SplineOrientation>(piece.orientation->law));
    for (std::size_t k = 0; k + 1 < pieces.size(); ++k) {
      const PathPiece& a = pieces[k];
      const PathPiece& b = pieces[k + 1];
      const double la = length(a.segment);
      ASSERT_LE(rotation_angle(orientation_at(*a.orientation, la), orientation_at(*b.orientation, 0.0)), kJoin) << test::seed_text(seed);
      expect_rate_continuous(a, b, seed, k);
      if (::testing::Test::HasFatalFailure()) return;
    }
    // each corner's target where the path passes it: the middle of its transition, or where the
    // first piece past it starts (also when the move before it was used up by a transition)
    for (const CornerReport& r : path.corners) {
      double start = -1, span = 0, past = -1;
      for (std::size_t k = 0; k < pieces.size(); ++k) {
        if (pieces[k].corner == r.index) {
          if (start < 0) start = path.offset(k);
          span += length(pieces[k].segment);
        }
        if (past < 0 && (pieces[k].move > r.index || pieces[k].corner > r.index)) past = path.offset(k);
      }
      const double at = span > 0 ? start + 0.5 * span : past;
      ASSERT_GE(at, 0.0) << test::seed_text(seed) << " corner " << r.index;
      ASSERT_LE(rotation_angle(path.orientation(at), target_of(program, r.index)), 1e-9) << test::seed_text(seed) << " corner " << r.index;
      if (span > 0) {
        ASSERT_NEAR(r.orientation_change, rotation_angle(path.orientation(start), path.orientation(start + span)), 1e-9) << test::seed_text(seed);
      }
    }
    ASSERT_LE(rotation_angle(path.orientation(path.length()), target_of(program, static_cast<int>(program.moves.size()) - 1)), 1e-9)
        << test::seed_text(seed);
    ASSERT_LE(rotation_angle(path.orientation(0.0), program.start_orientation), 1e-12) << test::seed_text(seed);
  }
}

// One move: the spline through two knots is the slerp by arc length.
TEST(OrientPath, SplineOfOneMoveIsTheSlerp) {
  Program program = one_line_to(Quat(Eigen::AngleAxisd(2.0, Vec3(1, 2, 3).normalized())));
  const Path slerp = blend(program);
  program.orientation_interpolation = OrientationInterpolation::kSpline;
  const Path spline = blend(program);
  for (int i = 0; i <= 10; ++i) {
    const double s = 0.01 * i;
    EXPECT_LE(rotation_angle(slerp.orientation(s), spline.orientation(s)), 1e-12) << s;
    EXPECT_LE((slerp.angular_rate(s) - spline.angular_rate(s)).norm(), 1e-9) << s;
  }
}

// Targets that turn the tool past 270 degrees from the start are refused at the move that sets
// the first of them, naming its field; the slerp takes them.
TEST(OrientPath, SplineRefusesTargetsPastItsRange) {
  Program program;
  program.start_orientation = Quat::Identity();
  Vec3 p = Vec3::Zero();
  for (int k = 0; k < 4; ++k) {  // quarter turns about z, the fourth past a full turn (389 deg)
    Move m;
    const Vec3 next = p + (k % 2 == 0 ? Vec3(0.1, 0, 0) : Vec3(0, 0.1, 0));
    m.geometry = Line{p, next};
    p = next;
    m.limits = {0.2, 2.0, 2.0, 20.0};
    m.orientation = Quat(Eigen::AngleAxisd(std::numbers::pi / 2 * (k + 1) + (k == 3 ? 0.5 : 0.0), Vec3::UnitZ()));
    m.name = "move " + std::to_string(k + 1);
    m.where = {"prog.yaml", 10 + k, 5};
    program.moves.push_back(m);
  }
  EXPECT_NO_THROW(blend(program));
  program.orientation_interpolation = OrientationInterpolation::kSpline;
  try {
    blend(program);
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "prog.yaml");
    EXPECT_EQ(e.line(), 13);
    EXPECT_EQ(e.field(), "orientation");
    EXPECT_NE(std::string(e.what()).find("move 4"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("270"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace blendbench
