// Plausibility warnings of a scenario (io/src/plausibility.cpp): valid input that looks like a
// mistake loads, and carries a warning that names the file, line and field.

#include "blendbench/io/plausibility.hpp"

#include <gtest/gtest.h>

#include <string>

#include "blendbench/io/data_root.hpp"
#include "blendbench/io/urdf_chain.hpp"
#include "blendbench/robot/kinematics.hpp"

#include "support/property.hpp"
#include "support/scratch.hpp"

namespace blendbench {
namespace {

// A valid scenario in mm (the default UR5e-like arm), with placeholders for the units and feed.
std::string scenario_text(const std::string& units, const std::string& velocity, const std::string& program) {
  return "name: plausible\nunits: " + units + "\nframe: {origin: [400, -50, 250], rpy_deg: [0, 0, 0]}\n" +
         "defaults: {velocity: " + velocity + ", acceleration: 2000, jerk: 20000}\n" + program +
         "variants:\n  - {name: exact, transition: {method: none}}\n";
}

const char* const kLines = "program:\n  start: [0, 0, 0]\n  moves:\n    - line: [60, 0, 0]\n    - line: [60, 60, 0]\n";

Scenario parse(const std::string& text) { return parse_scenario(text, "test.yaml", "."); }

// The one warning about `field`, or a failure.
const LoadWarning* find(const Scenario& sc, const std::string& field) {
  const LoadWarning* found = nullptr;
  for (const LoadWarning& w : sc.warnings) {
    if (w.field != field) continue;
    EXPECT_EQ(found, nullptr) << "two warnings about " << field;
    found = &w;
  }
  return found;
}

TEST(Plausibility, APlainScenarioHasNoWarning) {
  const Scenario sc = parse(scenario_text("mm", "200", kLines));
  EXPECT_TRUE(sc.warnings.empty()) << to_string(sc.warnings.front());
}

// `units: m` with millimetre numbers: a start 400 m away and 120 m of path. Warned at `units`
// (line 2), with the length; the same numbers in mm are not warned about.
TEST(Plausibility, MetresThatLookLikeMillimetresAreWarnedAtUnits) {
  const std::string text = "name: plausible\nunits: m\nframe: {origin: [400, -50, 250], rpy_deg: [0, 0, 0]}\n"
                           "defaults: {velocity: 0.2, acceleration: 2, jerk: 20}\n" +
                           std::string(kLines) + "variants:\n  - {name: exact, transition: {method: none}}\n";
  const Scenario sc = parse(text);
  const LoadWarning* w = find(sc, "units");
  ASSERT_NE(w, nullptr);
  EXPECT_EQ(w->where.file, "test.yaml");
  EXPECT_EQ(w->where.line, 2);
  EXPECT_NE(w->message.find("120 m long"), std::string::npos) << w->message;
  EXPECT_EQ(to_string(*w).rfind("test.yaml:2:", 0), 0u) << to_string(*w);
  EXPECT_EQ(find(parse(scenario_text("mm", "200", kLines)), "units"), nullptr);
}

// The threshold is the path's length: random paths of two lines in metres are warned about
// exactly when they are longer than kLongPathMetres.
TEST(Plausibility, TheUnitWarningFollowsThePathLength) {
  const int cases = test::property_cases(40);
  for (int c = 0; c < cases; ++c) {
    const std::uint64_t seed = 100 + static_cast<std::uint64_t>(c);
    auto rng = test::make_rng(seed);
    const double a = test::uniform(rng, 0.5, 8), b = test::uniform(rng, 0.5, 8);
    Program program;
    Move first, second;
    first.geometry = Line{Vec3::Zero(), Vec3(a, 0, 0)};
    second.geometry = Line{Vec3(a, 0, 0), Vec3(a, b, 0)};
    program.moves = {first, second};
    const bool long_path = a + b > kLongPathMetres;
    EXPECT_EQ(unit_warning(program, true, {"x.yaml", 2, 8}).has_value(), long_path) << test::seed_text(seed) << " " << a + b;
    EXPECT_FALSE(unit_warning(program, false, {"x.yaml", 2, 8}).has_value()) << test::seed_text(seed);
  }
}

// The TCP speed bound holds for every joint speed inside the limits: checked against the speed
// of forward kinematics by finite differences (not the Jacobian) at random poses, for the 64
// corners of the box of joint speeds (where |J qd| is largest, being convex in qd).
TEST(Plausibility, TheTcpSpeedBoundHoldsForEveryJointSpeedWithinTheLimits) {
  const KinematicChain chain = load_urdf_chain(data_file("models/ur5e_like.urdf"));
  const int cases = test::property_cases(20);
  for (int c = 0; c < cases; ++c) {
    const std::uint64_t seed = 200 + static_cast<std::uint64_t>(c);
    auto rng = test::make_rng(seed);
    JointVector q;
    for (int i = 0; i < 6; ++i) q[i] = test::uniform(rng, -3, 3);
    const double bound = tcp_speed_bound(chain, q);
    double fastest = 0;
    for (int corner = 0; corner < 64; ++corner) {
      JointVector qd;
      for (int i = 0; i < 6; ++i) qd[i] = ((corner >> i) & 1 ? 1 : -1) * chain.joints[static_cast<std::size_t>(i)].velocity_limit;
      constexpr double kH = 1e-7;  // s: central difference step
      const Vec3 v = (forward_kinematics(chain, q + kH * qd).translation() - forward_kinematics(chain, q - kH * qd).translation()) / (2 * kH);
      fastest = std::max(fastest, v.norm());
    }
    EXPECT_LE(fastest, bound * (1 + 1e-6)) << test::seed_text(seed);
    // and it is not vacuous: within the joints' reach (UR5e-like, pi rad/s each, reach under 1.4 m)
    EXPECT_GT(bound, 0.5 * fastest) << test::seed_text(seed);
    EXPECT_LT(bound, 6 * 3.15 * 1.4) << test::seed_text(seed);
  }
}

// `velocity: 6000` meant as mm/min (100 mm/s) asks for 6 m/s: beyond what the arm's joints allow
// at the start (about 4.7 m/s there); warned at the first move that asks for it, with the count.
// A move of its own `velocity` is named at its line.
TEST(Plausibility, AFeedBeyondTheArmIsWarnedAtTheFirstMoveThatAsksForIt) {
  const Scenario fast = parse(scenario_text("mm", "6000", kLines));
  const LoadWarning* w = find(fast, "velocity");
  ASSERT_NE(w, nullptr);
  EXPECT_EQ(w->where.line, 8);
  EXPECT_NE(w->message.find("6000 mm/s is beyond the arm"), std::string::npos) << w->message;
  EXPECT_NE(w->message.find("2 of 2 moves"), std::string::npos) << w->message;
  const std::string one = "program:\n  start: [0, 0, 0]\n  moves:\n    - line: [60, 0, 0]\n    - line: [60, 60, 0]\n      velocity: 9000\n";
  const Scenario one_fast = parse(scenario_text("mm", "200", one));
  w = find(one_fast, "velocity");
  ASSERT_NE(w, nullptr);
  EXPECT_EQ(w->where.line, 9);
  EXPECT_NE(w->message.find("1 of 2 moves"), std::string::npos) << w->message;
  EXPECT_EQ(find(parse(scenario_text("mm", "1000", kLines)), "velocity"), nullptr);
}

// A G-code F word other than defaults.velocity: the F words set the feed (as a controller runs
// the program), and the warning stands at the F word in the G-code file. F equal to the
// scenario's feed is not warned about.
TEST(Plausibility, AGcodeFeedThatOverridesTheScenarioIsWarnedAtTheFWord) {
  const test::ScratchDir dir("plausibility");
  const std::string part = dir.write("part.ngc", "G21 G90\nG1 X40\nG1 Y30 F6000\nG1 X0\nM2\n");
  const std::string program = "program:\n  start: [0, 0, 0]\n  gcode: " + part + "\n";
  const Scenario sc = parse(scenario_text("mm", "200", program));
  const LoadWarning* w = find(sc, "F");
  ASSERT_NE(w, nullptr);
  EXPECT_EQ(w->where.file, part);
  EXPECT_EQ(w->where.line, 3);
  EXPECT_NE(w->message.find("100 mm/s"), std::string::npos) << w->message;
  EXPECT_NE(w->message.find("defaults.velocity (200 mm/s"), std::string::npos) << w->message;
  // the precedence stated: the move before the F word runs at defaults.velocity, the ones after at F
  ASSERT_EQ(sc.program.moves.size(), 3u);
  EXPECT_NEAR(sc.program.moves[0].limits.velocity, 0.2, 1e-12);
  EXPECT_NEAR(sc.program.moves[1].limits.velocity, 0.1, 1e-12);
  EXPECT_NEAR(sc.program.moves[2].limits.velocity, 0.1, 1e-12);
  const std::string same = dir.write("same.ngc", "G21 G90\nG1 X40 F12000\nG1 Y30\nM2\n");
  EXPECT_EQ(find(parse(scenario_text("mm", "200", "program:\n  start: [0, 0, 0]\n  gcode: " + same + "\n")), "F"), nullptr);
}

}  // namespace
}  // namespace blendbench
