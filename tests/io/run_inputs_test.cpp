// A scenario resolved once into run inputs (io/run_inputs.hpp), a G-code file's own scenario and
// robots named on the command line.

#include "blendbench/io/run_inputs.hpp"

#include <gtest/gtest.h>

#include "blendbench/corner/blend.hpp"
#include "blendbench/io/data_root.hpp"
#include "support/input_error.hpp"
#include "support/scratch.hpp"

namespace blendbench {
namespace {

const char* const kScenario = R"(name: two
units: mm
frame: {origin: [400, 0, 200]}
defaults: {velocity: 100, acceleration: 1000, jerk: 10000}
limits: cartesian
axis_limits: {a: [2000, 2000, 2000], j: [40000, 40000, 40000]}
program:
  start: [0, 0, 0]
  moves:
    - line: [50, 0, 0]
    - line: [50, 50, 0]
      transition: {method: bezier, parameter: 3}
    - line: [0, 50, 0]
variants:
  - {name: exact, transition: {method: none}}
  - {name: arc, transition: {method: arc, parameter: 5}}
  - {name: slow, transition: {method: none}, baseline: junction_slowdown}
)";

Scenario parse(const std::string& text = kScenario) { return parse_scenario(text, "two.yaml", "."); }

TEST(ResolveRun, EveryVariantInOrderWithItsProgramTimingAndIdentity) {
  const Scenario sc = parse();
  const RunInputs in = resolve_run(sc);
  ASSERT_EQ(in.variants.size(), 3U);
  EXPECT_EQ(in.name, "two");
  EXPECT_EQ(in.file, "two.yaml");
  EXPECT_TRUE(in.frame.isApprox(sc.frame));
  for (std::size_t k = 0; k < 3; ++k) {
    const VariantInputs& v = in.variants[k];
    EXPECT_EQ(v.name, sc.variants[k].name);
    // the same program and timing program_for and timing_options give
    const Program expected = program_for(sc, sc.variants[k]);
    ASSERT_EQ(v.program.moves.size(), expected.moves.size());
    for (std::size_t m = 0; m < expected.moves.size(); ++m) {
      EXPECT_EQ(v.program.moves[m].transition.method, expected.moves[m].transition.method);
      EXPECT_EQ(v.program.moves[m].transition.parameter, expected.moves[m].transition.parameter);
    }
    EXPECT_EQ(v.timing.baseline, timing_options(sc, sc.variants[k]).baseline);
    EXPECT_TRUE(v.timing.axis_limits.has_value());
  }
  // the second move sets its own Bezier: the variants change the others only
  EXPECT_EQ(in.variants[1].program.moves[0].transition.method, Method::kArc);
  EXPECT_EQ(in.variants[1].program.moves[1].transition.method, Method::kBezier);
  EXPECT_EQ(in.variants[1].method, Method::kArc);
  EXPECT_DOUBLE_EQ(in.variants[1].parameter, 5e-3);
  EXPECT_EQ(in.variants[2].timing.baseline, TimingOptions::Baseline::kJunctionSlowdown);
}

TEST(ResolveRun, TheSelectionPicksReordersAndOverrides) {
  const Scenario sc = parse();
  RunSelection selection;
  selection.variants = {"arc", "exact"};
  selection.limits = LimitsMode::kPath;
  selection.tolerance = 0.2e-3;
  const RunInputs in = resolve_run(sc, selection);
  ASSERT_EQ(in.variants.size(), 2U);
  EXPECT_EQ(in.variants[0].name, "arc");
  EXPECT_EQ(in.variants[1].name, "exact");
  for (const VariantInputs& v : in.variants) {
    EXPECT_EQ(v.timing.limits, LimitsMode::kPath);
    EXPECT_FALSE(v.timing.axis_limits.has_value());  // the TCP's vectors are not held in path mode
  }
  // the tolerance replaces every parameter of a move with a method, and the summary says so
  for (const Move& m : in.variants[0].program.moves) {
    EXPECT_EQ(m.transition.parameter, 0);
    EXPECT_EQ(m.transition.tolerance, 0.2e-3);
  }
  EXPECT_EQ(in.variants[0].tolerance, 0.2e-3);
  EXPECT_EQ(in.variants[0].parameter, 0);
  // the exact stop has no method: nothing to solve, its moves keep none
  EXPECT_EQ(in.variants[1].tolerance, 0);
  EXPECT_EQ(in.variants[1].program.moves[0].transition.method, Method::kNone);
  EXPECT_EQ(in.variants[1].program.moves[1].transition.method, Method::kBezier);
}

TEST(ResolveRun, AnUnknownVariantIsRefusedListingTheNames) {
  const Scenario sc = parse();
  RunSelection selection;
  selection.variants = {"spline"};
  test::expect_input_error([&] { (void)resolve_run(sc, selection); }, {.field = "--variant", .message = "exact, arc, slow"});
}

TEST(GcodeScenario, APartIsPlacedInFrontOfTheArmWithItsOwnBlendingAndTheExactStop) {
  const test::ScratchDir dir("run-inputs");
  // a helix of two turns and a line: the box holds the arc's extremes, not only its ends
  const std::string file = dir.write("my part (v2).ngc",
                                     "G21 G90 G17\nG64 P0.1\nG1 X20 F600\nG3 X20 Y0 Z-4 I0 J10 P2\nG1 X0\nM2\n");
  const Scenario sc = gcode_scenario(file);
  EXPECT_EQ(sc.name, "my_part__v2_.ngc");
  EXPECT_TRUE(folder_name_problem(sc.name).empty());
  ASSERT_EQ(sc.variants.size(), 2U);
  EXPECT_EQ(sc.variants[0].name, "as_programmed");
  EXPECT_FALSE(sc.variants[0].transition.has_value());
  EXPECT_EQ(sc.variants[1].name, "exact_stop");
  EXPECT_EQ(sc.variants[1].transition->method, Method::kNone);
  // the box: x in [0, 30] (the circle about (20, 10) of radius 10), y in [0, 20], z in [-4, 0]
  const Vec3 centre_in_program(15e-3, 10e-3, -2e-3);
  EXPECT_TRUE((sc.frame * centre_in_program).isApprox(kGcodePartCentre, 1e-4)) << (sc.frame * centre_in_program).transpose();
  EXPECT_TRUE(sc.frame.linear().isIdentity());
  // the file's limits as `plan` reads them, its F word the feed, G64 P its blending
  const Move& line = sc.program.moves.front();
  EXPECT_DOUBLE_EQ(line.limits.velocity, 600e-3 / 60);
  EXPECT_DOUBLE_EQ(line.limits.acceleration, kGcodeAcceleration);
  EXPECT_DOUBLE_EQ(line.limits.jerk, kGcodeJerk);
  EXPECT_EQ(line.transition.method, Method::kBiclothoid);
  EXPECT_DOUBLE_EQ(line.transition.parameter, 0.1e-3);
  EXPECT_EQ(line.where.line, 3);
  // the shipped arm
  EXPECT_EQ(std::filesystem::path(sc.robot.urdf).filename(), "ur5e_like.urdf");
  EXPECT_EQ(sc.robot.model, ArmModel::kElastic);
  // and the corners name the program's lines
  const Path path = blend(program_for(sc, sc.variants[0]));
  ASSERT_FALSE(path.corners.empty());
  EXPECT_EQ(path.corners.front().source.line, 3);
}

TEST(GcodeScenario, AnUnsupportedWordIsTheReadersErrorAtItsLine) {
  const test::ScratchDir dir("run-inputs");
  const std::string file = dir.write("bad.ngc", "G21 G90\nG1 X10 F600\nG41 X20\n");
  test::expect_input_error([&] { (void)gcode_scenario(file); }, {.file = file, .line = 3, .message = "G41"});
}

TEST(NamedRobot, AShippedNameAFileOrARefusal) {
  const RobotSettings kr6 = named_robot("kr6_like", "--robot");
  EXPECT_EQ(std::filesystem::path(kr6.urdf).filename(), "kr6_like.urdf");
  EXPECT_EQ(std::filesystem::path(kr6.mjcf).filename(), "kr6_like.xml");
  EXPECT_FALSE(kr6.mjcf_from_urdf);
  const RobotSettings by_file = named_robot(data_file("models/ur5e_like.urdf"), "--robot");
  EXPECT_EQ(std::filesystem::path(by_file.mjcf).filename(), "ur5e_like.xml");
  // a URDF without a MuJoCo model beside it: the dynamics built from it, rigid
  const RobotSettings bare = named_robot(data_file("models/offset_wrist_kinematic.urdf"), "--robot");
  EXPECT_TRUE(bare.mjcf_from_urdf);
  EXPECT_EQ(bare.model, ArmModel::kRigid);
  test::expect_input_error([] { (void)named_robot("../models/ur5e_like", "--robot"); }, {.field = "--robot"});
  test::expect_input_error([] { (void)named_robot("no_such_arm", "--robot"); },
                           {.field = "--robot", .message = "neither a URDF file nor a shipped robot"});
}

}  // namespace
}  // namespace blendbench
