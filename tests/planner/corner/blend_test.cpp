#include "blendbench/corner/blend.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace blendbench {
namespace {

Move line_move(const Vec3& a, const Vec3& b, Method method = Method::kNone, double parameter = 0) {
  Move move;
  move.geometry = Line{a, b};
  move.limits = {0.2, 1.0, 1.0, 10.0};
  move.transition.method = method;
  move.transition.parameter = parameter;
  return move;
}

TEST(Blend, ExactStopKeepsTheProgrammedPathAndStopsAtEveryCorner) {
  Program program;
  program.moves = {line_move({0, 0, 0}, {0.1, 0, 0}), line_move({0.1, 0, 0}, {0.1, 0.1, 0}),
                   line_move({0.1, 0.1, 0}, {0, 0.1, 0})};
  const Path path = blend(program);
  ASSERT_EQ(path.pieces().size(), 3u);
  ASSERT_EQ(path.corners.size(), 2u);
  EXPECT_NEAR(path.length(), 0.3, 1e-15);
  EXPECT_FALSE(path.pieces()[0].stop_before);
  EXPECT_TRUE(path.pieces()[1].stop_before);
  EXPECT_TRUE(path.pieces()[2].stop_before);
  EXPECT_NEAR(path.pieces()[1].kink_angle, M_PI / 2, 1e-12);
  EXPECT_EQ(path.corners[0].corner_case, CornerCase::kExactStop);
  EXPECT_EQ(path.corners[0].length, 0.0);
  EXPECT_TRUE(path.point(0.15).isApprox(Vec3(0.1, 0.05, 0), 1e-14));
}

TEST(Blend, TransitionVelocityIsTheBufferModesJunctionVelocity) {
  // a 90 degree corner blended by a 10 mm arc, moves at 0.2 and 0.1 m/s: the arc runs at the
  // velocity the mode gives the junction, unless the transition names its own
  struct Case {
    BufferMode mode;
    double v_fast_first, v_slow_first;  // expected with (0.2 -> 0.1) and (0.1 -> 0.2)
  };
  const Case cases[] = {{BufferMode::kBlendingLow, 0.1, 0.1},      {BufferMode::kBlendingPrevious, 0.2, 0.1},
                        {BufferMode::kBlendingNext, 0.1, 0.2},     {BufferMode::kBlendingHigh, 0.2, 0.2},
                        {BufferMode::kAborting, 0.1, 0.2},         {BufferMode::kBuffered, 0.1, 0.1}};
  for (const Case& c : cases) {
    for (const bool fast_first : {true, false}) {
      Program program;
      program.moves = {line_move({0, 0, 0}, {0.1, 0, 0}, Method::kArc, 0.01), line_move({0.1, 0, 0}, {0.1, 0.1, 0})};
      program.moves[0].buffer = c.mode;
      program.moves[0].limits.velocity = fast_first ? 0.2 : 0.1;
      program.moves[1].limits.velocity = fast_first ? 0.1 : 0.2;
      program.moves[1].limits.acceleration = 3.0;  // the transition takes the next move's
      const Path path = blend(program);
      ASSERT_EQ(path.pieces().size(), 3u);
      const Limits& lim = path.pieces()[1].limits;
      EXPECT_EQ(lim.velocity, fast_first ? c.v_fast_first : c.v_slow_first) << to_string(c.mode) << fast_first;
      EXPECT_EQ(lim.acceleration, 3.0);
      program.moves[0].transition.velocity = 0.15;
      EXPECT_EQ(blend(program).pieces()[1].limits.velocity, 0.15) << to_string(c.mode);
    }
  }
}

TEST(Blend, ValidatesTheProgramFirst) {
  // what validate rejects is in program_test; blend must not plan around it
  Program program;
  program.moves = {line_move({0, 0, 0}, {0.1, 0, 0}), line_move({0.2, 0, 0}, {0.3, 0, 0})};
  EXPECT_THROW((void)blend(program), InputError);
  EXPECT_THROW((void)blend(Program{}), InputError);
}

TEST(Blend, ABiclothoidSizedByAStartDistanceStartsThatFarBeforeTheCorner) {
  Program program;
  program.moves = {line_move({0, 0, 0}, {0.1, 0, 0}), line_move({0.1, 0, 0}, {0.1, 0.1, 0})};
  program.moves[0].transition = {.method = Method::kBiclothoid, .start_distance = 0.005};
  const Path path = blend(program);
  ASSERT_EQ(path.corners.size(), 1u);
  EXPECT_NEAR(path.corners[0].trim_in, 0.005, 1e-15);
  EXPECT_NEAR(path.corners[0].parameter, 0.005, 1e-15);
}

TEST(Blend, NoSpuriousKinkWhereTwoFilletsMeetInTheMiddleOfAMove) {
  // the middle move (20 mm + 0.1 nm) is eaten from both ends by 10 mm corner distances: whatever
  // rounding sliver is left between the arcs must not read as a kink (a stop when Buffered)
  for (const double angle : {0.3, 1.0, 2.0}) {
    Program program;
    const Vec3 a(0.3, 0.1, 0.2);
    const Vec3 b = a + Vec3(0.1, 0, 0);
    const Vec3 c = b + (0.02 + 1e-10) * Vec3(std::cos(angle), std::sin(angle), 0);
    const Vec3 d = c + 0.1 * Vec3(std::cos(2 * angle), std::sin(2 * angle), 0);
    program.moves = {line_move(a, b, Method::kArc, 0.01), line_move(b, c, Method::kArc, 0.01), line_move(c, d)};
    for (Move& m : program.moves) m.buffer = BufferMode::kBuffered;
    const Path path = blend(program);
    for (std::size_t k = 0; k < path.pieces().size(); ++k) {
      EXPECT_FALSE(path.pieces()[k].stop_before) << "angle " << angle << " piece " << k;
      EXPECT_LT(path.pieces()[k].kink_angle, 1e-9) << "angle " << angle << " piece " << k;
    }
  }
}

TEST(Blend, ZeroLengthTransitionReportsTheSkippedPathAsDeviation) {
  // 001 reversal: both moves shortened by the corner distance; the corner point B itself is
  // skipped, d away from where the path turns back
  Program program;
  program.moves = {line_move({0, 0, 0}, {0.1, 0, 0}, Method::kArc, 0.005), line_move({0.1, 0, 0}, {0.03, 0, 0})};
  const Path path = blend(program);
  ASSERT_EQ(path.corners.size(), 1u);
  EXPECT_EQ(path.corners[0].corner_case, CornerCase::kReversal);
  EXPECT_EQ(path.corners[0].length, 0.0);
  EXPECT_NEAR(path.corners[0].deviation, 0.005, 1e-9);
}

TEST(Blend, SpeedLimitOfPaper004Table1) {
  // 004 table 1, fillet S1S2: c = 0.016 1/mm^2, kappa = 0.124 1/mm -> 12486 mm/min
  const double v = curvature_speed_limit(124.0, 16000.0, 9.8, 200.0);
  EXPECT_NEAR(v * 60000.0, 12486.0, 1.0);
}

}  // namespace
}  // namespace blendbench
