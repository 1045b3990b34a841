// blend() on programs with point streams (smooth_blend.cpp): the streams' curves between the
// moves around them, G2 where they join, the real corners blended as any other.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "blendbench/corner/blend.hpp"
#include "blendbench/timing/timing.hpp"
#include "support/property.hpp"

namespace blendbench {
namespace {

constexpr double kDeg = std::numbers::pi / 180;
// Joints: tangent turn (rad) and curvature-vector jump (1/m) counted as continuous (as
// g2_fit_test states).
constexpr double kJointAngle = 1e-9;
constexpr double kJointCurvature = 1e-6;

Move line_move(const Vec3& a, const Vec3& b) {
  Move move;
  move.geometry = Line{a, b};
  move.limits = {0.1, 1.0, 1.0, 10.0};
  move.transition.method = Method::kBiclothoid;
  move.transition.parameter = 0.05e-3;
  return move;
}

// A part as CAM writes it: a 10 mm lead-in, a quarter circle of R 5 mm as 0.05 mm lines, a 104 deg
// corner, a wave as 0.05 mm lines, a 10 mm lead-out; every coordinate to 0.1 um.
Program cam_part() {
  std::vector<Vec3> p = {Vec3(-10e-3, 5e-3, 0), Vec3(0, 5e-3, 0)};
  const int arc_lines = static_cast<int>(std::round(5e-3 * std::numbers::pi / 2 / 0.05e-3));
  for (int k = 1; k <= arc_lines; ++k) {
    const double a = std::numbers::pi / 2 - std::numbers::pi / 2 * k / arc_lines;
    p.push_back(Vec3(5e-3 * std::cos(a), 5e-3 * std::sin(a), 0));
  }
  // the corner at (5, 0), from -y to about +x: the wave runs along +x after it
  const Vec3 corner = p.back();
  for (int k = 1; k <= 200; ++k) {
    const double x = 0.05e-3 * k;
    p.push_back(corner + Vec3(x, 0.5e-3 * std::sin(x / 2e-3), 0));
  }
  p.push_back(p.back() + Vec3(10e-3, 0, 0));
  // written with four decimals of a millimetre, as G-code is
  for (Vec3& q : p) q = (q * 1e7).array().round() / 1e7;
  Program program;
  for (std::size_t k = 0; k + 1 < p.size(); ++k) program.moves.push_back(line_move(p[k], p[k + 1]));
  return program;
}

struct Jumps {
  double angle = 0, curvature = 0;
};
Jumps path_jumps(const Path& path) {
  Jumps out;
  for (std::size_t k = 1; k < path.pieces().size(); ++k) {
    const Segment& a = path.pieces()[k - 1].segment;
    const Segment& b = path.pieces()[k].segment;
    out.angle = std::max(out.angle, angle_between(tangent(a, length(a)), tangent(b, 0.0)));
    out.curvature = std::max(out.curvature, (curvature_vector(a, length(a)) - curvature_vector(b, 0.0)).norm());
  }
  return out;
}

TEST(SmoothBlend, StreamsBecomeCurvesAndRealCornersKeepTheirMethod) {
  Program program = cam_part();
  const std::size_t n = program.moves.size();
  const Path lines = blend(program);
  ASSERT_EQ(lines.corners.size(), n - 1);
  for (const SmoothingMethod method : {SmoothingMethod::kG2Fit, SmoothingMethod::kClothoidPoints}) {
    program.smoothing.method = method;
    const Path path = blend(program);
    const std::string what(to_string(method));
    EXPECT_EQ(path.smoothing.runs, 2) << what;
    // the corners left: the lead-in's, the 90 deg one, the lead-out's; each biclothoid, G2
    ASSERT_EQ(path.corners.size(), 3u) << what;
    EXPECT_EQ(path.corners[0].index, 0);
    EXPECT_EQ(path.corners[2].index, static_cast<int>(n) - 2);
    for (const CornerReport& c : path.corners) EXPECT_EQ(c.method, Method::kBiclothoid) << what;
    const auto middle = static_cast<std::size_t>(path.corners[1].index);
    EXPECT_GT(angle_between(tangent(program.moves[middle].geometry, 0.0), tangent(program.moves[middle + 1].geometry, 0.0)),
              90 * kDeg);
    // G2 everywhere: biclothoids, lines and the curves all meet at zero curvature or continuously
    const Jumps jumps = path_jumps(path);
    EXPECT_LE(jumps.angle, kJointAngle) << what;
    EXPECT_LE(jumps.curvature, kJointCurvature) << what;
    for (const PathPiece& piece : path.pieces()) EXPECT_LE(piece.kink_angle, kJointAngle) << what;
    // from the program's start to its end, moves in order
    EXPECT_EQ(start_point(path.pieces().front().segment), std::get<Line>(program.moves.front().geometry).p0);
    EXPECT_EQ(end_point(path.pieces().back().segment), std::get<Line>(program.moves.back().geometry).p1);
    int last_move = 0;
    for (const PathPiece& piece : path.pieces()) {
      const int at = piece.move >= 0 ? piece.move : piece.corner;
      EXPECT_GE(at, last_move) << what;
      last_move = at;
    }
    // and it times faster than the lines' tiny fillets
    const Timing smooth = plan_timing(path);
    const Timing rough = plan_timing(lines);
    ASSERT_TRUE(smooth.outcome.ok()) << smooth.outcome.message;
    EXPECT_GT(smooth.bound_cycle_time, 0);
    if (method == SmoothingMethod::kG2Fit) {
      EXPECT_LT(smooth.cycle_time, 0.75 * rough.cycle_time) << what;
    }
  }
}

TEST(SmoothBlend, AClosedContourIsOneCurveWithoutCorners) {
  Program program;
  std::vector<Vec3> p;
  for (int k = 0; k < 400; ++k) {
    const double t = 2 * std::numbers::pi * k / 400;
    const double r = 10e-3 * (1.25 + std::cos(t));
    p.push_back(Vec3(r * std::cos(t), r * std::sin(t), 0));
  }
  p.push_back(p.front());
  for (std::size_t k = 0; k + 1 < p.size(); ++k) program.moves.push_back(line_move(p[k], p[k + 1]));
  program.smoothing.method = SmoothingMethod::kG2Fit;
  const Path path = blend(program);
  EXPECT_TRUE(path.corners.empty());
  EXPECT_EQ(path.smoothing.runs, 1);
  EXPECT_EQ(start_point(path.pieces().front().segment), p.front());
  EXPECT_EQ(end_point(path.pieces().back().segment), p.front());
  const Segment& last = path.pieces().back().segment;
  const Segment& first = path.pieces().front().segment;
  EXPECT_LE(angle_between(tangent(last, length(last)), tangent(first, 0.0)), kJointAngle);
  EXPECT_LE((curvature_vector(last, length(last)) - curvature_vector(first, 0.0)).norm(),
            kJointCurvature * curvature_vector(first, 0.0).norm() + kJointCurvature);
}

TEST(SmoothBlend, OrientationsAndMergingStillApply) {
  // a move that sets an orientation ends a stream and keeps its target; G64 Q merges the
  // collinear moves outside the streams, but not the streams' half lines (that would leave a kink)
  Program program = cam_part();
  program.moves.back().orientation = Quat(Eigen::AngleAxisd(20 * kDeg, Vec3::UnitZ()));
  program.moves.front().transition.merge_tolerance = 1e-6;
  program.moves.insert(program.moves.begin(), line_move(Vec3(-20e-3, 5e-3, 0), Vec3(-10e-3, 5e-3, 0)));
  program.moves.front().transition.merge_tolerance = 1e-6;
  program.smoothing.method = SmoothingMethod::kG2Fit;
  const Path path = blend(program);
  ASSERT_TRUE(path.oriented());
  EXPECT_EQ(path.moves_merged, 1);
  EXPECT_EQ(path.smoothing.runs, 2);
  EXPECT_TRUE(path.orientation(path.length()).isApprox(*program.moves.back().orientation, 1e-9));
  EXPECT_TRUE(path.orientation(0.5 * path.length()).isApprox(Quat::Identity(), 1e-12));
}

TEST(SmoothBlend, WithoutStreamsTheBlendIsThePlainOne) {
  // smoothing on a program without streams (long lines) blends as without it, and says so
  Program program;
  program.moves = {line_move(Vec3(0, 0, 0), Vec3(10e-3, 0, 0)), line_move(Vec3(10e-3, 0, 0), Vec3(10e-3, 10e-3, 0))};
  const Path plain = blend(program);
  program.smoothing.method = SmoothingMethod::kG2Fit;
  const Path smoothed = blend(program);
  ASSERT_EQ(plain.pieces().size(), smoothed.pieces().size());
  EXPECT_EQ(plain.length(), smoothed.length());
  EXPECT_EQ(smoothed.smoothing.method, SmoothingMethod::kG2Fit);
  EXPECT_EQ(smoothed.smoothing.runs, 0);
}

}  // namespace
}  // namespace blendbench
