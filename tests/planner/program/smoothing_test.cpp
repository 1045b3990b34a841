#include "blendbench/program/smoothing.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "blendbench/program/program.hpp"
#include "support/property.hpp"

namespace blendbench {
namespace {

constexpr double kDeg = std::numbers::pi / 180;

Move line_move(const Vec3& a, const Vec3& b) {
  Move move;
  move.geometry = Line{a, b};
  move.limits = {0.1, 1.0, 1.0, 10.0};
  move.transition.method = Method::kBiclothoid;
  move.transition.parameter = 0.05e-3;
  return move;
}

// A program through `points` (m), one line each.
Program polyline_program(const std::vector<Vec3>& points) {
  Program program;
  for (std::size_t k = 0; k + 1 < points.size(); ++k) program.moves.push_back(line_move(points[k], points[k + 1]));
  return program;
}

// `count` points on a circle of `radius` from angle `a0`, `step` apart along it.
std::vector<Vec3> arc_points(const Vec3& centre, double radius, double a0, double step, int count) {
  std::vector<Vec3> out;
  for (int k = 0; k < count; ++k) {
    const double a = a0 + step * k / radius;
    out.push_back(centre + radius * Vec3(std::cos(a), std::sin(a), 0));
  }
  return out;
}

TEST(Smoothing, MethodNamesRoundTrip) {
  for (const SmoothingMethod m : {SmoothingMethod::kNone, SmoothingMethod::kClothoidPoints, SmoothingMethod::kG2Fit}) {
    EXPECT_EQ(smoothing_method_from_string(to_string(m)), m);
  }
  EXPECT_EQ(smoothing_method_from_string("G2_FIT"), SmoothingMethod::kG2Fit);
  EXPECT_FALSE(smoothing_method_from_string("spline"));
}

TEST(Smoothing, ValidateNamesTheField) {
  const auto field_of = [](const Smoothing& s) {
    try {
      validate(s);
    } catch (const InputError& e) {
      return e.field();
    }
    return std::string();
  };
  Smoothing s;
  EXPECT_EQ(field_of(s), "");
  s.tolerance = 0;
  EXPECT_EQ(field_of(s), "smoothing.tolerance");
  s = {};
  s.stream_length = std::nan("");
  EXPECT_EQ(field_of(s), "smoothing.stream_length");
  s = {};
  s.max_turn = std::numbers::pi;
  EXPECT_EQ(field_of(s), "smoothing.max_turn_deg");
  s = {};
  s.stream_turn = 0;
  EXPECT_EQ(field_of(s), "smoothing.stream_turn_deg");
  // and through the program's own validation
  Program program = polyline_program({Vec3(0, 0, 0), Vec3(1e-3, 0, 0)});
  program.smoothing.tolerance = -1;
  EXPECT_THROW(validate(program), InputError);
}

TEST(Smoothing, StreamsAreRunsOfShortLinesTurningLittle) {
  // a 10 mm lead-in, 50 lines of 0.1 mm round a circle of 5 mm (1.1 deg each), a 40 deg corner,
  // 30 more lines, a 2 mm line, 2 short lines (too few), a 10 mm lead-out
  std::vector<Vec3> points = {Vec3(-10e-3, 5e-3, 0)};
  for (const Vec3& p : arc_points(Vec3::Zero(), 5e-3, std::numbers::pi / 2, 0.1e-3, 51)) points.push_back(p);
  const Vec3 corner = points.back();
  const Vec3 dir = (corner - points[points.size() - 2]).normalized();
  const Vec3 turned = Eigen::AngleAxisd(40 * kDeg, Vec3::UnitZ()) * dir;
  for (int k = 1; k <= 30; ++k) points.push_back(corner + k * 0.1e-3 * turned);
  points.push_back(points.back() + 2e-3 * turned);
  points.push_back(points.back() + 0.1e-3 * turned);
  points.push_back(points.back() + 0.1e-3 * turned);
  points.push_back(points.back() + 10e-3 * turned);
  const Program program = polyline_program(points);
  Smoothing spec;
  const std::vector<StreamRun> runs = find_streams(program, spec);
  ASSERT_EQ(runs.size(), 2u);
  EXPECT_EQ(runs[0].first, 1u);
  EXPECT_EQ(runs[0].last, 50u);
  EXPECT_EQ(runs[1].first, 51u);
  EXPECT_EQ(runs[1].last, 80u);
  EXPECT_FALSE(runs[0].closed);
  // a wider turn joins them; a shorter length limit finds none
  spec.stream_turn = 45 * kDeg;
  ASSERT_EQ(find_streams(program, spec).size(), 1u);
  spec.stream_length = 0.05e-3;
  EXPECT_TRUE(find_streams(program, spec).empty());
}

TEST(Smoothing, LimitsAndOrientationsEndAStream) {
  Program program = polyline_program(arc_points(Vec3::Zero(), 5e-3, 0, 0.1e-3, 21));
  for (std::size_t k = 10; k < program.moves.size(); ++k) program.moves[k].limits.velocity = 0.2;  // a new feed
  program.moves[15].orientation = Quat::Identity();  // a move that sets an orientation is none
  const std::vector<StreamRun> runs = find_streams(program, Smoothing{});
  ASSERT_EQ(runs.size(), 3u);
  EXPECT_EQ(runs[0].first, 0u);
  EXPECT_EQ(runs[0].last, 9u);
  EXPECT_EQ(runs[1].first, 10u);
  EXPECT_EQ(runs[1].last, 14u);
  EXPECT_EQ(runs[2].first, 16u);
  EXPECT_EQ(runs[2].last, 19u);
}

TEST(Smoothing, AClosedStreamIsTheWholeProgramEndingWhereItStarts) {
  std::vector<Vec3> points = arc_points(Vec3::Zero(), 5e-3, 0, 2 * std::numbers::pi * 5e-3 / 100, 100);
  points.push_back(points.front());
  EXPECT_TRUE(find_streams(polyline_program(points), Smoothing{}).front().closed);
  points.back() += Vec3(1e-6, 0, 0);  // a gap of 1 um: open
  EXPECT_FALSE(find_streams(polyline_program(points), Smoothing{}).front().closed);
}

TEST(Smoothing, SmoothStreamsFitsEachStreamAndMeasuresIt) {
  // the circle arc between two long lines, for both methods: anchored at both ends, the pieces'
  // moves in order within the stream, the distance within the tolerance (g2_fit)
  std::vector<Vec3> points = {Vec3(-10e-3, 5e-3, 0)};
  for (const Vec3& p : arc_points(Vec3::Zero(), 5e-3, std::numbers::pi / 2, 0.1e-3, 101)) points.push_back(p);
  points.push_back(points.back() + Vec3(0, -10e-3, 0));
  Program program = polyline_program(points);
  for (const SmoothingMethod method : {SmoothingMethod::kG2Fit, SmoothingMethod::kClothoidPoints}) {
    program.smoothing.method = method;
    const SmoothedProgram smoothed = smooth_streams(program);
    ASSERT_EQ(smoothed.runs.size(), 1u) << to_string(method);
    const SmoothedRun& run = smoothed.runs.front();
    EXPECT_TRUE(run.start_anchored && run.end_anchored);
    EXPECT_EQ(run.points, 101);
    EXPECT_EQ(run.piece_move.size(), run.curve.size());
    EXPECT_TRUE(std::is_sorted(run.piece_move.begin(), run.piece_move.end()));
    EXPECT_GE(run.piece_move.front(), 1u);
    EXPECT_LE(run.piece_move.back(), 100u);
    // from the middle of the first line to the middle of the last
    EXPECT_TRUE(start_point(run.curve.front()).isApprox(0.5 * (points[1] + points[2]), 1e-12));
    EXPECT_TRUE(end_point(run.curve.back()).isApprox(0.5 * (points[100] + points[101]), 1e-12));
    const SmoothingReport& r = smoothed.report;
    EXPECT_EQ(r.method, method);
    EXPECT_EQ(r.runs, 1);
    EXPECT_EQ(r.points, 101);
    EXPECT_EQ(r.pieces, static_cast<int>(run.curve.size()));
    EXPECT_GT(r.max_distance, 0);
    EXPECT_GE(r.wall_time, 0);
    if (method == SmoothingMethod::kG2Fit) {
      EXPECT_LE(r.max_distance, program.smoothing.tolerance);
      EXPECT_EQ(r.tolerance, program.smoothing.tolerance);
    } else {
      EXPECT_EQ(r.tolerance, 0);
      EXPECT_EQ(r.max_turn, program.smoothing.max_turn);
    }
  }
  program.smoothing.method = SmoothingMethod::kNone;
  EXPECT_TRUE(smooth_streams(program).runs.empty());
}

TEST(Smoothing, ASpikyStreamIsSmoothedWithinTheToleranceOrKeptAsLinesWithANote) {
  // a zigzag of 0.1 mm lines turning back by 170 deg at every vertex, let into a stream by a
  // stream turn of 179 deg: each method smooths it within its own terms or keeps it as lines,
  // with a note naming the moves and why; never a curve outside the tolerance
  std::vector<Vec3> points;
  for (int k = 0; k <= 20; ++k) points.push_back(Vec3(k * 0.1e-3 * std::cos(85 * kDeg), (k % 2) * 0.1e-3 * std::sin(85 * kDeg), 0));
  Program program = polyline_program(points);
  program.smoothing.stream_turn = 179 * kDeg;
  for (const SmoothingMethod method : {SmoothingMethod::kG2Fit, SmoothingMethod::kClothoidPoints}) {
    program.smoothing.method = method;
    const SmoothedProgram smoothed = smooth_streams(program);
    const std::string what(to_string(method));
    if (smoothed.runs.empty()) {
      ASSERT_EQ(smoothed.report.notes.size(), 1u) << what;
      EXPECT_NE(smoothed.report.notes.front().find("move 1 to move 20 (a stream of 20 lines) kept as lines: " + what + ": "),
                std::string::npos)
          << smoothed.report.notes.front();
      EXPECT_EQ(smoothed.report.runs, 0) << what;
      continue;
    }
    EXPECT_TRUE(smoothed.report.notes.empty()) << what;
    EXPECT_EQ(smoothed.report.runs, 1) << what;
    if (method == SmoothingMethod::kG2Fit) {
      EXPECT_LE(smoothed.report.max_distance, program.smoothing.tolerance) << what;
    }
    for (const Segment& piece : smoothed.runs.front().curve) {
      EXPECT_TRUE(std::isfinite(length(piece)) && length(piece) > 0) << what;
    }
  }
}

}  // namespace
}  // namespace blendbench
