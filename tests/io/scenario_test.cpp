#include "blendbench/io/scenario.hpp"

#include <gtest/gtest.h>

#include <algorithm>

#include <filesystem>
#include <numbers>

#include "blendbench/corner/blend.hpp"

#include "support/input_error.hpp"
#include "support/property.hpp"
#include "support/shipped_scenarios.hpp"
#include "support/scratch.hpp"

namespace blendbench {
namespace {

const char* const kValid = R"(name: square
units: mm
frame: {origin: [400, 0, 200], rpy_deg: [0, 0, 90]}
defaults: {velocity: 100, acceleration: 1000, jerk: 10000, buffer: Buffered}
program:
  start: [0, 0, 0]
  moves:
    - line: [100, 0, 0]
    - arc: {end: [100, 100, 0], center: [100, 50, 0], direction: ccw}
      velocity: 50
      transition: {method: arc, parameter: 5}
    - line: [0, 100, 0]
variants:
  - {name: exact, transition: {method: none}}
  - {name: arc5, transition: {method: arc, parameter: 2}, buffer: BlendingLow}
)";

Scenario parse(const std::string& text) { return parse_scenario(text, "test.yaml", "."); }

// Asserts that parsing fails with an InputError at the given line and field.
InputError expect_error(const std::string& text, int line, const std::string& field, const std::string& fragment) {
  return test::expect_input_error([&] { (void)parse(text); }, {.file = "test.yaml", .line = line, .field = field, .message = fragment},
                                  text);
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(Scenario, ConvertsToSiAndPlacesTheProgramInTheFrame) {
  const Scenario sc = parse(kValid);
  ASSERT_EQ(sc.program.moves.size(), 3u);
  // frame rotated 90 degrees about z: program x becomes base y
  EXPECT_TRUE(sc.start.isApprox(Vec3(0.4, 0, 0.2), 1e-12));
  const Line& first = std::get<Line>(sc.program.moves[0].geometry);
  EXPECT_TRUE(first.p1.isApprox(Vec3(0.4, 0.1, 0.2), 1e-12));
  const Arc& arc = std::get<Arc>(sc.program.moves[1].geometry);
  EXPECT_NEAR(arc.radius, 0.05, 1e-12);
  EXPECT_NEAR(arc.sweep, std::numbers::pi, 1e-12);
  EXPECT_NEAR(sc.program.moves[1].limits.velocity, 0.05, 1e-15);
  EXPECT_NEAR(sc.program.moves[0].limits.deceleration, 1.0, 1e-15);  // defaults to acceleration
  EXPECT_EQ(sc.program.moves[0].buffer, BufferMode::kBuffered);
  EXPECT_EQ(sc.program.moves[1].where.line, 9);
}

// Orientation targets in the program frame: rpy as robot.tool_rpy_deg reads it, or a
// quaternion [w, x, y, z] (normalised); the frame's rotation applies; the first move starts at
// the robot's tool orientation; angular limits in degrees, defaults from `defaults`.
TEST(Scenario, OrientationTargetsAndAngularLimits) {
  std::string text = replaced(kValid, "    - line: [100, 0, 0]\n",
                              "    - line: [100, 0, 0]\n      orientation: {rpy_deg: [180, 0, 0]}\n      angular_velocity: 90\n");
  text = replaced(text, "    - line: [0, 100, 0]\n", "    - line: [0, 100, 0]\n      orientation: {quaternion: [0, 0, 0, 2]}\n");
  text = replaced(text, "buffer: Buffered}", "buffer: Buffered, angular_acceleration: 360}");
  const Scenario sc = parse(text);
  const double deg = std::numbers::pi / 180;
  // frame yaw 90 degrees: R_base = Rz(90) Rx(180)
  const Quat first(Eigen::AngleAxisd(std::numbers::pi / 2, Vec3::UnitZ()) * Eigen::AngleAxisd(std::numbers::pi, Vec3::UnitX()));
  ASSERT_TRUE(sc.program.moves[0].orientation.has_value());
  EXPECT_LE(rotation_angle(*sc.program.moves[0].orientation, first), 1e-12);
  EXPECT_FALSE(sc.program.moves[1].orientation.has_value());
  // 180 degrees about program z, in a frame turned 90 degrees about z: 270 degrees about base z
  EXPECT_LE(rotation_angle(*sc.program.moves[2].orientation, Quat(Eigen::AngleAxisd(-std::numbers::pi / 2, Vec3::UnitZ()))), 1e-12);
  EXPECT_NEAR(sc.program.moves[0].angular.velocity, 90 * deg, 1e-15);
  EXPECT_NEAR(sc.program.moves[1].angular.velocity, 180 * deg, 1e-15);
  EXPECT_NEAR(sc.program.moves[1].angular.acceleration, 360 * deg, 1e-15);
  EXPECT_NEAR(sc.program.moves[1].angular.jerk, 7200 * deg, 1e-12);
  EXPECT_LE(rotation_angle(sc.program.start_orientation, Quat(Eigen::AngleAxisd(std::numbers::pi, Vec3::UnitX()))), 1e-12);
  // bad input names the line and the field
  expect_error(replaced(text, "{rpy_deg: [180, 0, 0]}", "{rpy_deg: [180, 0, 0], quaternion: [1, 0, 0, 0]}"), 9,
               "program.moves[0].orientation", "exactly one of 'rpy_deg' or 'quaternion'");
  expect_error(replaced(text, "[0, 0, 0, 2]", "[0, 0, 0, 0]"), 15, "program.moves[2].orientation.quaternion", "must not be zero");
  expect_error(replaced(text, "angular_velocity: 90", "angular_velocity: -1"), 10, "program.moves[0].angular_velocity", "");
}

// program.orientation_interpolation: slerp by default, spline when asked, anything else refused
// at its line and key; a variant's program keeps it.
TEST(Scenario, OrientationInterpolationIsReadAndKept) {
  EXPECT_EQ(parse(kValid).program.orientation_interpolation, OrientationInterpolation::kSlerp);
  const std::string text = replaced(kValid, "program:\n", "program:\n  orientation_interpolation: spline\n");
  const Scenario sc = parse(text);
  EXPECT_EQ(sc.program.orientation_interpolation, OrientationInterpolation::kSpline);
  EXPECT_EQ(program_for(sc, find_variant(sc, "arc5")).orientation_interpolation, OrientationInterpolation::kSpline);
  const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(text.find("orientation_interpolation")), '\n'));
  expect_error(replaced(text, "spline\n", "squad\n"), line, "program.orientation_interpolation", "slerp");
}

TEST(Scenario, VariantTransitionAppliesOnlyWhereTheMoveSetsNone) {
  const Scenario sc = parse(kValid);
  const Program p = program_for(sc, find_variant(sc, "arc5"));
  EXPECT_EQ(p.moves[0].transition.method, Method::kArc);
  EXPECT_NEAR(p.moves[0].transition.parameter, 0.002, 1e-15);
  EXPECT_NEAR(p.moves[1].transition.parameter, 0.005, 1e-15);  // the move's own
  EXPECT_EQ(p.moves[2].buffer, BufferMode::kBlendingLow);
  EXPECT_THROW((void)find_variant(sc, "nope"), InputError);
}

// `sensitivity`: the default models without the key, one model per listed value with it, and a
// positioned refusal of every value that cannot be a perturbed model.
TEST(Scenario, SensitivityKeyListsThePerturbedModels) {
  const Scenario defaults = parse(kValid);
  std::vector<std::string> names;
  for (const Perturbation& p : defaults.sensitivity.perturbations) names.push_back(p.name);
  EXPECT_EQ(names, (std::vector<std::string>{"stiffness x0.5", "stiffness x1.5", "inertia x0.8", "inertia x1.2", "friction x0.5",
                                             "friction x1.5", "delay +1 tick"}));
  EXPECT_EQ(defaults.sensitivity.where.line, 0);
  // the defaults are the table's: one model per value, each changing one parameter
  const std::vector<Perturbation> table = default_perturbations();
  ASSERT_EQ(table.size(), names.size());
  for (std::size_t k = 0; k < names.size(); ++k) {
    const Perturbation& a = defaults.sensitivity.perturbations[k];
    const Perturbation& b = table[k];
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.stiffness_scale, b.stiffness_scale);
    EXPECT_EQ(a.inertia_scale, b.inertia_scale);
    EXPECT_EQ(a.friction_scale, b.friction_scale);
    EXPECT_EQ(a.extra_delay_ticks, b.extra_delay_ticks);
    const int changed = (a.stiffness_scale != 1) + (a.inertia_scale != 1) + (a.friction_scale != 1) + (a.extra_delay_ticks != 0);
    EXPECT_EQ(changed, 1) << a.name;
  }

  const Scenario own = parse(replaced(kValid, "units: mm", "units: mm\nsensitivity: {stiffness_scale: [0.3], inertia_scale: [], extra_delay_ticks: [2, 3]}"));
  ASSERT_EQ(own.sensitivity.perturbations.size(), 5u);  // 1 stiffness, the 2 default frictions, 2 delays
  EXPECT_EQ(own.sensitivity.perturbations[0].name, "stiffness x0.3");
  EXPECT_EQ(own.sensitivity.perturbations[0].stiffness_scale, 0.3);
  EXPECT_EQ(own.sensitivity.perturbations[1].name, "friction x0.5");
  EXPECT_EQ(own.sensitivity.perturbations[3].name, "delay +2 ticks");
  EXPECT_EQ(own.sensitivity.perturbations[4].extra_delay_ticks, 3);
  EXPECT_EQ(own.sensitivity.where.line, 3);

  const auto with = [](const std::string& map) { return replaced(kValid, "units: mm", "units: mm\nsensitivity: " + map); };
  expect_error(with("{stiffness_scale: [-0.5, 1.5]}"), 3, "sensitivity.stiffness_scale[0]", "");
  expect_error(with("{inertia_scale: [0.8, 0]}"), 3, "sensitivity.inertia_scale[1]", "");
  expect_error(with("{friction_scale: [0.5, 1]}"), 3, "sensitivity.friction_scale[1]", "nominal model");
  expect_error(with("{friction_scale: [0.5, 0.5]}"), 3, "sensitivity.friction_scale[1]", "repeats");
  expect_error(with("{extra_delay_ticks: [1.5]}"), 3, "sensitivity.extra_delay_ticks[0]", "whole");
  expect_error(with("{extra_delay_ticks: [0]}"), 3, "sensitivity.extra_delay_ticks[0]", "");
  expect_error(with("{stifness_scale: [0.5]}"), 3, "sensitivity.stifness_scale", "stiffness_scale");
  expect_error(with("{gravity_scale: [0.5]}"), 3, "sensitivity.gravity_scale", "unknown key");
  expect_error(with("{stiffness_scale: 0.5}"), 3, "sensitivity.stiffness_scale", "expected a list of numbers");
  expect_error(with("{stiffness_scale: [], inertia_scale: [], friction_scale: [], extra_delay_ticks: []}"), 3, "sensitivity",
               "at least one perturbed model");
}

TEST(Scenario, BadInputNamesFileLineAndField) {
  expect_error(replaced(kValid, "units: mm", "units: mm\nspeed: 3"), 3, "speed", "unknown key 'speed'");
  expect_error(replaced(kValid, "velocity: 100", "velocity: fast"), 4, "defaults.velocity", "expected a number");
  expect_error(replaced(kValid, "jerk: 10000, ", ""), 4, "defaults.jerk", "missing required field");
  expect_error(replaced(kValid, "direction: ccw", "direction: left"), 9, "program.moves[1].arc.direction",
               "unknown value 'left' (one of: cw, ccw)");
  expect_error(replaced(kValid, "method: arc, parameter: 5", "method: spline, parameter: 5"), 11,
               "program.moves[1].transition.method", "unknown value 'spline' (one of: none, arc, bezier");
  expect_error(replaced(kValid, "method: arc, parameter: 5", "method: bezeir, parameter: 5"), 11,
               "program.moves[1].transition.method", "unknown value 'bezeir' (did you mean 'bezier'?)");
  expect_error(replaced(kValid, "name: arc5", "name: exact"), 15, "variants[1].name", "duplicate variant");
  expect_error(replaced(kValid, "center: [100, 50, 0]", "center: [100, 40, 0]"), 9, "program.moves[1].arc.center",
               "differs from the radius");
  expect_error(replaced(kValid, "line: [0, 100, 0]", "line: [100, 100, 0]"), 12, "program.moves[2].line",
               "zero-length");
  expect_error(replaced(kValid, "acceleration: 1000", "acceleration: -5"), 4, "defaults.acceleration",
               "must be > 0 mm/s^2, got -5");
  expect_error(replaced(kValid, "velocity: 50", "velocity: [50]"), 10, "program.moves[1].velocity", "expected a number");
}

// `limits`, `axis_limits` and `curvature_steps`: read in the scenario's units, and every misuse
// refused at its line and key.
TEST(Scenario, LimitsModeAxisLimitsAndCurvatureSteps) {
  const Scenario plain = parse(kValid);
  EXPECT_EQ(plain.limits, LimitsMode::kCartesian);
  EXPECT_FALSE(plain.axis_limits);
  EXPECT_EQ(plain.program.moves[1].transition.curvature_steps, CurvatureSteps::kLimit);
  const std::string text = replaced(replaced(kValid, "units: mm\n", "units: mm\nlimits: cartesian\naxis_limits: {a: [500, 600, 700], j: [5000, 6000, 7000]}\n"),
                                    "transition: {method: arc, parameter: 5}",
                                    "transition: {method: arc, parameter: 5, curvature_steps: allow, merge_tolerance: 0.01}");
  const Scenario sc = parse(text);
  ASSERT_TRUE(sc.axis_limits);
  EXPECT_TRUE(sc.axis_limits->acceleration.isApprox(Vec3(0.5, 0.6, 0.7), 1e-15));
  EXPECT_TRUE(sc.axis_limits->jerk.isApprox(Vec3(5, 6, 7), 1e-15));
  EXPECT_EQ(sc.program.moves[1].transition.curvature_steps, CurvatureSteps::kAllow);
  EXPECT_NEAR(sc.program.moves[1].transition.merge_tolerance, 1e-5, 1e-18);
  const TimingOptions options = timing_options(sc, sc.variants[0]);
  EXPECT_EQ(options.limits, LimitsMode::kCartesian);
  EXPECT_DOUBLE_EQ(options.dt, 1.0 / sc.servo.setpoint_rate_hz);
  ASSERT_TRUE(options.axis_limits);
  EXPECT_EQ(parse(replaced(kValid, "units: mm\n", "units: mm\nlimits: path\n")).limits, LimitsMode::kPath);
  expect_error(replaced(kValid, "units: mm\n", "units: mm\nlimits: tcp\n"), 3, "limits", "unknown value 'tcp' (one of: cartesian, path)");
  expect_error(replaced(kValid, "units: mm\n", "units: mm\nlimits: path\naxis_limits: {a: [1, 1, 1], j: [1, 1, 1]}\n"), 4,
               "axis_limits", "need 'limits: cartesian'");
  expect_error(replaced(kValid, "units: mm\n", "units: mm\naxis_limits: {a: [1, 0, 1], j: [1, 1, 1]}\n"), 3,
               "axis_limits.a[1]", "must be > 0 mm/s^2, got 0");
  expect_error(replaced(kValid, "units: mm\n", "units: mm\naxis_limits: {a: [1, 1, 1]}\n"), 3, "axis_limits.j",
               "missing required field");
  expect_error(replaced(kValid, "transition: {method: arc, parameter: 5}", "transition: {method: arc, parameter: 5, curvature_steps: yes}"),
               11, "program.moves[1].transition.curvature_steps", "unknown value 'yes' (one of: limit, allow)");
}

TEST(Scenario, BiclothoidTakesAStartDistanceInsteadOfADeviation) {
  const Scenario sc = parse(replaced(kValid, "method: arc, parameter: 5", "method: biclothoid, start_distance: 3"));
  const Transition& t = sc.program.moves[1].transition;
  EXPECT_EQ(t.method, Method::kBiclothoid);
  EXPECT_NEAR(t.start_distance, 0.003, 1e-15);
  EXPECT_EQ(t.parameter, 0.0);
  expect_error(replaced(kValid, "method: arc, parameter: 5", "method: arc, start_distance: 5"), 11,
               "program.moves[1].transition.start_distance", "only a biclothoid");
  expect_error(replaced(kValid, "method: arc, parameter: 5", "method: biclothoid, parameter: 1, start_distance: 5"), 11,
               "program.moves[1].transition.start_distance", "not both");
  expect_error(replaced(kValid, "method: arc, parameter: 5", "method: biclothoid, start_distance: 0"), 11,
               "program.moves[1].transition.start_distance", "must be > 0 mm, got 0");
}

TEST(Scenario, ATransitionTakesAToleranceInsteadOfAParameter) {
  // every method, in the file's units; parameter and start distance stay unset
  for (const char* method : {"none", "arc", "bezier", "clothoid", "biclothoid"}) {
    const Scenario sc = parse(replaced(kValid, "method: arc, parameter: 5", std::string("method: ") + method + ", tolerance: 0.25"));
    const Transition& t = sc.program.moves[1].transition;
    EXPECT_NEAR(t.tolerance, 0.25e-3, 1e-18) << method;
    EXPECT_EQ(t.parameter, 0.0);
    EXPECT_EQ(t.start_distance, 0.0);
  }
  // <= 0 or not a number: exit 2 naming the key; with parameter or start_distance: naming both
  const std::string key = "program.moves[1].transition.tolerance";
  expect_error(replaced(kValid, "method: arc, parameter: 5", "method: arc, tolerance: 0"), 11, key, "must be > 0 mm, got 0");
  expect_error(replaced(kValid, "method: arc, parameter: 5", "method: arc, tolerance: -1"), 11, key, "must be > 0 mm, got -1");
  expect_error(replaced(kValid, "method: arc, parameter: 5", "method: arc, tolerance: .nan"), 11, key, "finite");
  expect_error(replaced(kValid, "method: arc, parameter: 5", "method: arc, tolerance: .inf"), 11, key, "finite");
  expect_error(replaced(kValid, "method: arc, parameter: 5", "method: arc, parameter: 5, tolerance: 1"), 11, key,
               "tolerance and parameter exclude each other");
  expect_error(replaced(kValid, "method: arc, parameter: 5", "method: biclothoid, start_distance: 5, tolerance: 1"), 11, key,
               "tolerance and start_distance exclude each other");
  // neither: the parameter is missing, and the message says a tolerance would do
  expect_error(replaced(kValid, "method: arc, parameter: 5", "method: arc"), 11, "program.moves[1].transition.parameter",
               "a parameter or a tolerance");
}

TEST(Scenario, InvalidYamlReportsTheParserPosition) {
  const InputError e = test::expect_input_error([] { (void)parse("name: x\nprogram: [unclosed\n"); },
                                                {.file = "test.yaml", .message = "invalid YAML"});
  EXPECT_GE(e.line(), 2);
}

// yaml-cpp and libyaml keep one of two equal keys silently; the loader refuses the second,
// naming both places, at any depth and in maps of any size.
TEST(Scenario, DuplicateKeysAreRefusedWhereTheSecondIs) {
  expect_error(replaced(kValid, "velocity: 100,", "velocity: 200, velocity: -1,"), 4, "defaults.velocity",
               "test.yaml:4:27: 'defaults.velocity': duplicate key 'velocity' (first at line 4, column 12)");
  expect_error(replaced(kValid, "name: square", "name: square\nname: again"), 2, "name", "duplicate key 'name'");
  expect_error(replaced(kValid, "      velocity: 50", "      velocity: 50\n      velocity: 60"), 11,
               "program.moves[1].velocity", "duplicate key 'velocity' (first at line 10, column 7)");
  // a large map is checked through a hash set: the same answer
  std::string many = "name: big\ndescription: x\n";
  for (int i = 0; i < 40; ++i) many.append("k").append(std::to_string(i)).append(": 1\n");
  many += "k17: again\n";
  expect_error(many, 43, "k17", "duplicate key 'k17' (first at line 20, column 1)");
}

// A list or a map as a key used to end in yaml-cpp's "bad conversion" (exit 1).
TEST(Scenario, KeysThatAreNotNamesAreRefusedAtTheirPosition) {
  expect_error(replaced(kValid, "units: mm", "units: mm\n? [a, b]\n: 3"), 3, "", "a key must be a name, not a list");
  expect_error(replaced(kValid, "    - line: [0, 100, 0]", "    - {a: 1}: 2"), 12, "program.moves[2]",
               "a key must be a name, not a map");
  expect_error(replaced(kValid, "units: mm", "units: mm\n? \n: 3"), 3, "", "a key must be a name, not an empty key");
  expect_error(replaced(kValid, "units: mm", "units: &u mm\n*u : 3"), 3, "", "a key must be a name, not an alias");
}

// An unterminated quote runs to the end of the file; it used to read as "'program': missing
// required field". A quote closed by a later one leaves a string over several lines: named too.
TEST(Scenario, AnUnclosedQuoteIsNamedAtItsOpeningQuote) {
  expect_error(replaced(kValid, "name: square", "name: square\ndescription: \"half"), 2, "description",
               "test.yaml:2:14: 'description': the quoted string that opens here is never closed");
  expect_error(replaced(kValid, "units: mm", "units: 'mm"), 2, "units", "the quoted string that opens here is never closed");
  // closed by a quote at the end of the file: the keys in between are text, so one is missing
  const std::string swallowed = replaced(kValid, "name: square", "name: square\ndescription: \"half") + "\"\n";
  expect_error(swallowed, 1, "program",
               "missing required field; the quoted string at line 2, column 14 spans 16 lines: is its closing quote missing?");
  // closed by a later quote in the middle: the parser's error comes with the same hint
  const std::string closed_late = replaced(replaced(kValid, "name: square", "name: square\ndescription: \"half"),
                                           "  - {name: exact", "\"\n  - {name: exact");
  expect_error(closed_late, 16, "", "; the quoted string at line 2, column 14 spans 14 lines: is its closing quote missing?");
}

// Bytes that are not text are refused where they are, and never echoed raw.
TEST(Scenario, BinaryBytesAreRefusedAndEscaped) {
  const InputError e = expect_error(std::string("name: sq\x01uare\n") + kValid, 1, "", "not a text file: control characters");
  EXPECT_EQ(e.column(), 9);
  EXPECT_NE(std::string(e.what()).find("(byte 0x01)"), std::string::npos) << e.what();
  expect_error("name: \xff\xfe\n", 1, "", "invalid leading UTF-8 octet (byte 0xff)");
  // a control character inside a quoted string (an escape) reaches the message escaped
  const InputError q = expect_error(replaced(kValid, "name: square", "name: \"sq\\e[2Juare\""), 1, "name", "scenario name");
  EXPECT_EQ(std::string(q.what()).find('\x1b'), std::string::npos) << q.what();
}

// Bounded work in the document itself: nesting depth, and aliases counted as what they repeat.
TEST(Scenario, DeepNestingAndAliasBombsAreRefusedBeforeTheyCost) {
  const std::string deep = "name: deep\nprogram: " + std::string(100000, '[') + std::string(100000, ']') + "\n";
  expect_error(deep, 2, "program[0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0]"
                        "[0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0][0]",
               "nested deeper than 64 levels of lists and maps");
  // nine aliases of nine aliases of ...: 9^9 nodes from a few hundred bytes
  std::string bomb = "name: bomb\na0: &a0 [x, x, x, x, x, x, x, x, x]\n";
  for (int i = 1; i <= 9; ++i) {
    // appended piece by piece: "literal" + std::string drew GCC 12's -Wrestrict false positive
    const std::string p = "*a" + std::to_string(i - 1);
    const std::string name = std::to_string(i);
    bomb += "a";
    bomb += name;
    bomb += ": &a";
    bomb += name;
    bomb += " [";
    bomb += p;
    for (int k = 1; k < 9; ++k) {
      bomb += ", ";
      bomb += p;
    }
    bomb += "]\n";
  }
  expect_error(bomb, 8, "a6[5]", "more than 4000000 YAML nodes (aliases counted as the nodes they repeat)");
  // aliases within the limit are fine: a shared transition
  const Scenario sc = parse(replaced(replaced(kValid, "{method: arc, parameter: 5}", "&t {method: arc, parameter: 5}"),
                                     "transition: {method: none}", "transition: *t"));
  EXPECT_EQ(sc.variants[0].transition->method, Method::kArc);
  EXPECT_EQ(sc.variants[0].transition->parameter, 0.005);
  expect_error(replaced(kValid, "transition: {method: none}", "transition: *nope"), 14, "variants[0].transition",
               "unknown alias *nope");
  expect_error(std::string(kValid) + "---\nname: second\n", 16, "", "a second YAML document");
}

// Every spelling of a value that is not a finite number, and numbers beyond a double.
TEST(Scenario, NanAndInfinitySpellingsAreRefusedNamingTheKey) {
  for (const std::string v : {".nan", ".NaN", "nan", "NaN", ".inf", "-.inf", "+.Inf", "inf", "-Infinity", "1e999", "-1e400"}) {
    expect_error(replaced(kValid, "velocity: 100", "velocity: " + v), 4, "defaults.velocity", "expected a finite number");
  }
  for (const std::string v : {"0x10", "1_000", "12abc", "1.2.3", "--1", "e5", "."}) {
    expect_error(replaced(kValid, "velocity: 100", "velocity: " + v), 4, "defaults.velocity", "expected a number, got '" + v);
  }
  // below the smallest double: zero, then the range says why
  expect_error(replaced(kValid, "velocity: 100", "velocity: 1e-400"), 4, "defaults.velocity", "must be > 0 mm/s, got 1e-400");
}

// Every range check names its key and position: rates, delays, counts, durations, filters, pixels.
TEST(Scenario, RangeChecksCarryTheirPosition) {
  const std::string base = std::string(kValid) +
                           "servo: {rate_hz: 2000, measurement_delay_ticks: 1, encoder_counts_per_turn: 4096}\n"
                           "simulation: {settle_time_s: 1, vibration_highpass_hz: 12}\nvideo: {width: 640}\n";
  EXPECT_NO_THROW((void)parse(base));
  expect_error(replaced(base, "measurement_delay_ticks: 1", "measurement_delay_ticks: -1"), 16,
               "servo.measurement_delay_ticks", "must be in [0, 100], got -1");
  expect_error(replaced(base, "encoder_counts_per_turn: 4096", "encoder_counts_per_turn: -4096"), 16,
               "servo.encoder_counts_per_turn", "must be >= 0, got -4096");
  expect_error(replaced(base, "encoder_counts_per_turn: 4096", "encoder_counts_per_turn: 4096.5"), 16,
               "servo.encoder_counts_per_turn", "counts per turn must be a whole number");
  expect_error(replaced(base, "rate_hz: 2000", "rate_hz: 1e-300"), 16, "servo.rate_hz", "must be in [125, 8000] Hz, got 1e-300");
  expect_error(replaced(base, "rate_hz: 2000", "rate_hz: 2000, setpoint_rate_hz: 300"), 16, "servo.setpoint_rate_hz",
               "the servo rate (2000 Hz) must be a whole multiple of the setpoint rate");
  expect_error(replaced(base, "rate_hz: 2000", "rate_hz: 1000, setpoint_rate_hz: 2000"), 16, "servo.setpoint_rate_hz",
               "the setpoint rate must be at most the servo rate (1000 Hz), got 2000");
  expect_error(replaced(base, "settle_time_s: 1", "settle_time_s: 1e308"), 17, "simulation.settle_time_s",
               "must be in [0, 60] s, got 1e308");
  expect_error(replaced(base, "settle_time_s: 1", "settle_time_s: 0.1"), 17, "simulation.settle_time_s",
               "settle_time_s (0.1 s) must be at least the settle window settle_window_s (0.2 s)");
  // the default settle time is refused where the window is: the key the user wrote
  expect_error(replaced(base, "settle_time_s: 1,", "settle_window_s: 5,"), 17, "simulation.settle_window_s",
               "settle_time_s (1 s) must be at least the settle window settle_window_s (5 s)");
  expect_error(replaced(base, "vibration_highpass_hz: 12", "vibration_highpass_hz: 1e-300"), 17,
               "simulation.vibration_highpass_hz", "must be in [1, 4000] Hz, got 1e-300");
  expect_error(replaced(base, "width: 640", "width: 641"), 18, "video.width", "must be an even number of pixels, got 641");
  expect_error(replaced(base, "width: 640", "width: 640.0"), 18, "video.width", "expected an integer (digits only), got '640.0'");
  expect_error(replaced(base, "width: 640", "width: 99999999999999999999999"), 18, "video.width",
               "expected an integer in [64, 1920] px");
  expect_error(replaced(kValid, "direction: ccw}", "direction: ccw, turns: 1000000}"), 9, "program.moves[1].arc.turns",
               "must be in [0, 100], got 1000000");
  // in a file in metres, the unit of a length says m
  expect_error(replaced(replaced(kValid, "units: mm", "units: m"), "acceleration: 1000", "acceleration: 0"), 4,
               "defaults.acceleration", "must be > 0 m/s^2, got 0");
}

// video.camera: the part camera by default; each mode reads its own keys (lengths in the file's
// unit, in the base frame) and refuses another mode's by name.
TEST(Scenario, VideoCameraModesReadTheirOwnKeys) {
  const VideoCamera part = parse(kValid).video.camera;
  EXPECT_EQ(part.mode, CameraMode::kPart);
  EXPECT_EQ(part.fill, 0.6);
  EXPECT_FALSE(part.azimuth_deg);
  const VideoCamera framed =
      parse(std::string(kValid) + "video: {camera: {fill: 0.8, azimuth_deg: -30, elevation_deg: 50}}\n").video.camera;
  EXPECT_EQ(framed.fill, 0.8);
  EXPECT_EQ(framed.azimuth_deg.value_or(0), -30);
  EXPECT_EQ(framed.elevation_deg.value_or(0), 50);
  const VideoCamera fixed =
      parse(std::string(kValid) + "video: {camera: {mode: fixed, position: [1200, -800, 900], look_at: [400, 0, 200], fovy_deg: 30}}\n")
          .video.camera;
  EXPECT_EQ(fixed.mode, CameraMode::kFixed);
  EXPECT_TRUE(fixed.position.isApprox(Vec3(1.2, -0.8, 0.9), 1e-12));
  EXPECT_TRUE(fixed.look_at.isApprox(Vec3(0.4, 0, 0.2), 1e-12));
  EXPECT_EQ(fixed.fovy_deg, 30);
  const VideoCamera tcp = parse(std::string(kValid) + "video: {camera: {mode: tcp, distance: 250}}\n").video.camera;
  EXPECT_EQ(tcp.mode, CameraMode::kTcp);
  EXPECT_NEAR(tcp.distance, 0.25, 1e-15);
  EXPECT_EQ(tcp.fovy_deg, 45);

  expect_error(std::string(kValid) + "video: {camera: {mode: part, distance: 250}}\n", 16, "video.camera.distance",
               "not used with camera mode part (its keys: mode, fill, azimuth_deg, elevation_deg)");
  expect_error(std::string(kValid) + "video: {camera: {mode: tcp, look_at: [0, 0, 0]}}\n", 16, "video.camera.look_at",
               "not used with camera mode tcp");
  expect_error(std::string(kValid) + "video: {camera: {mode: fixed, look_at: [0, 0, 0]}}\n", 16, "video.camera.position",
               "missing required field");
  expect_error(std::string(kValid) + "video: {camera: {mode: fixed, position: [1, 2, 3], look_at: [1, 2, 3]}}\n", 16,
               "video.camera.look_at", "the camera must look at a point other than its position");
  expect_error(std::string(kValid) + "video: {camera: {fill: 0.05}}\n", 16, "video.camera.fill", "must be in [0.1, 1]");
  expect_error(std::string(kValid) + "video: {camera: {mode: orbit}}\n", 16, "video.camera.mode", "unknown value 'orbit'");
  expect_error(std::string(kValid) + "video: {camera: {elevaton_deg: 10}}\n", 16, "video.camera.elevaton_deg",
               "did you mean 'elevation_deg'");
}

// The servo's rates: a rate given alone keeps 500 Hz setpoints when it can, its own otherwise.
TEST(Scenario, SetpointRateFollowsTheServoRateWhenNotGiven) {
  EXPECT_EQ(parse(kValid).servo.setpoint_rate_hz, 500);
  EXPECT_EQ(parse(std::string(kValid) + "servo: {rate_hz: 4000}\n").servo.setpoint_rate_hz, 500);
  EXPECT_EQ(parse(std::string(kValid) + "servo: {rate_hz: 250}\n").servo.setpoint_rate_hz, 250);
  EXPECT_EQ(parse(std::string(kValid) + "servo: {rate_hz: 1200}\n").servo.setpoint_rate_hz, 1200);
  const Scenario sc = parse(std::string(kValid) + "servo: {rate_hz: 4000, setpoint_rate_hz: 1000}\n");
  EXPECT_EQ(sc.servo.setpoint_rate_hz, 1000);
  EXPECT_EQ(sc.servo.rate_where.line, 16);
  EXPECT_EQ(parse(kValid).servo.rate_where.line, 0);
}

// Where a key is valid but in another map, the message says where it belongs.
TEST(Scenario, AKeyInTheWrongMapIsToldWhereItBelongs) {
  expect_error(std::string(kValid) + "simulation: {rate_hz: 500}\n", 16, "simulation.rate_hz",
               "unknown key 'rate_hz' here; it belongs in servo");
  expect_error(replaced(kValid, "units: mm", "units: mm\nvelocty: 3"), 3, "velocty", "unknown key 'velocty' (allowed: name,");
  expect_error(replaced(kValid, "velocity: 100,", "velocty: 100,"), 4, "defaults.velocty",
               "unknown key 'velocty' (did you mean 'velocity'?)");
}

// Counts are bounded before the work: the number of moves and of variants.
TEST(Scenario, TooManyVariantsAreRefusedAtTheFirstBeyondTheLimit) {
  std::string text = replaced(kValid, "  - {name: exact, transition: {method: none}}\n  - {name: arc5, transition: {method: arc, parameter: 2}, buffer: BlendingLow}\n", "");
  for (std::size_t i = 0; i <= kMaxVariants; ++i) text += "  - {name: v" + std::to_string(i) + "}\n";
  expect_error(text, 14 + static_cast<int>(kMaxVariants), "variants[1000]", "more than 1000 variants");
}

TEST(Scenario, ArcFormsAgree) {
  // the same half circle by centre, by radius and by a via point
  const std::string base = R"(name: arcs
defaults: {velocity: 100, acceleration: 1000, jerk: 10000}
program:
  moves:
    - ARC
variants: [{name: v}]
)";
  const Scenario a = parse(replaced(base, "ARC", "arc: {end: [100, 0, 0], center: [50, 0, 0], direction: cw}"));
  const Scenario b = parse(replaced(base, "ARC", "arc: {end: [100, 0, 0], radius: 50, direction: cw}"));
  const Scenario c = parse(replaced(base, "ARC", "arc: {end: [100, 0, 0], via: [50, 50, 0]}"));
  for (double s = 0; s <= 0.157; s += 0.01) {
    const Vec3 pa = point(a.program.moves[0].geometry, s);
    EXPECT_LT((pa - point(b.program.moves[0].geometry, s)).norm(), 1e-9) << s;
    EXPECT_LT((pa - point(c.program.moves[0].geometry, s)).norm(), 1e-9) << s;
  }
  EXPECT_GT(point(a.program.moves[0].geometry, 0.0785).y(), 0.049);  // cw about +z from (0,0) to (0.1,0) goes up
}

TEST(Scenario, EveryShippedScenarioLoadsAndBlends) {
  int count = 0;
  for (const std::filesystem::path& file : test::shipped_scenarios()) {
    ++count;
    SCOPED_TRACE(file.string());
    try {
      const Scenario sc = load_scenario(file.string());
      for (const Variant& v : sc.variants) {
        const Path path = blend(program_for(sc, v));
        EXPECT_GT(path.length(), 0.0) << v.name;
      }
    } catch (const InputError& e) {
      ADD_FAILURE() << e.what();
    }
  }
  EXPECT_GT(count, 10);
}

// The two orientation scenarios do what their headers say, for every variant: on the seam's
// arc the torch keeps its angle to the tangent (its axis, projected on the seam's plane, turns
// with the tangent; its tilt stays 30 degrees), and the pick-and-place gripper has turned by 150
// degrees where the traverse ends and back where the return ends.
TEST(Scenario, OrientationScenariosHoldTheTorchAngleAndTurnTheGripper) {
  const Scenario seam = load_scenario(test::source_path("scenarios/torch_seam.yaml"));
  for (const Variant& v : seam.variants) {
    const Path path = blend(program_for(seam, v));
    ASSERT_TRUE(path.oriented()) << v.name;
    for (std::size_t k = 0; k < path.pieces().size(); ++k) {
      const PathPiece& piece = path.pieces()[k];
      if (piece.move != 1) continue;  // the arc
      for (int i = 0; i <= 20; ++i) {
        const double s = length(piece.segment) * i / 20;
        const Vec3 axis = orientation_at(*piece.orientation, s).toRotationMatrix().col(2);
        const Vec3 t = tangent(piece.segment, s);
        const Vec3 flat(axis.x(), axis.y(), 0);
        // the torch's lean lies along the tangent (pitch about the seam's normal) at 30 degrees
        EXPECT_NEAR(std::abs(flat.normalized().dot(t)), 1.0, 1e-9) << v.name << " s = " << s;
        EXPECT_NEAR(std::atan2(flat.norm(), -axis.z()), 30 * std::numbers::pi / 180, 1e-9) << v.name << " s = " << s;
      }
    }
  }
  const Scenario pick = load_scenario(test::source_path("scenarios/reorient_pick_place.yaml"));
  const Quat down(Eigen::AngleAxisd(std::numbers::pi, Vec3::UnitX()));
  const Quat turned = Quat(Eigen::AngleAxisd(150 * std::numbers::pi / 180, Vec3::UnitZ())) * down;
  for (const Variant& v : pick.variants) {
    const Path path = blend(program_for(pick, v));
    // the place descent (move 3) and the final descent (move 6) run at the targets
    for (const PathPiece& piece : path.pieces()) {
      if (piece.move != 2 && piece.move != 5) continue;
      const Quat expected = piece.move == 2 ? turned : down;
      EXPECT_LE(rotation_angle(orientation_at(*piece.orientation, 0.5 * length(piece.segment)), expected), 1e-9) << v.name;
    }
  }
}

// The execution settings: defaults as documented (elastic arm, cascade at 2 kHz under 500 Hz
// setpoints, one tick of delay, a 2^14-count motor encoder through ratio 100; settled within
// 0.03 mm and 1 mm/s for 0.2 s), every key read and converted, bad values refused at the key.
TEST(Scenario, RobotServoAndSimulationSettings) {
  const Scenario d = parse(kValid);
  EXPECT_EQ(d.robot.model, ArmModel::kElastic);
  EXPECT_NE(d.robot.mjcf.find("models/ur5e_like.xml"), std::string::npos);
  EXPECT_EQ(d.servo.controller, ServoController::kCascade);
  EXPECT_EQ(d.servo.rate_hz, 2000);
  EXPECT_EQ(d.servo.setpoint_rate_hz, 500);
  EXPECT_EQ(d.servo.measurement_delay_ticks, 1);
  EXPECT_EQ(d.servo.encoder_counts_per_turn, 1638400);
  EXPECT_FALSE(d.servo.acceleration_feedforward.has_value());
  EXPECT_DOUBLE_EQ(d.simulation.settle_tolerance, 0.03e-3);
  EXPECT_DOUBLE_EQ(d.simulation.settle_speed_tolerance, 1e-3);
  EXPECT_DOUBLE_EQ(d.simulation.settle_window, 0.2);

  const Scenario s = parse(replaced(kValid, "units: mm\n",
                                    "units: mm\nrobot: {model: rigid}\n"
                                    "servo: {controller: pd, rate_hz: 4000, setpoint_rate_hz: 1000, measurement_delay_ticks: 2,"
                                    " encoder_counts_per_turn: 0, acceleration_feedforward: false, gravity_compensation: false}\n"
                                    "simulation: {settle_tolerance: 0.05, settle_speed_tolerance: 2, settle_window_s: 0.1,"
                                    " settle_time_s: 0.4, vibration_window_s: 0.3, vibration_highpass_hz: 10, jerk_lowpass_hz: 40}\n"));
  EXPECT_EQ(s.robot.model, ArmModel::kRigid);
  EXPECT_NE(s.robot.mjcf.find("models/ur5e_like_rigid.xml"), std::string::npos);
  EXPECT_EQ(s.robot.model_where.line, 3);
  EXPECT_EQ(s.servo.controller, ServoController::kPd);
  EXPECT_EQ(s.servo.rate_hz, 4000);
  EXPECT_EQ(s.servo.setpoint_rate_hz, 1000);
  EXPECT_EQ(s.servo.rate_where.line, 4);
  EXPECT_EQ(s.servo.measurement_delay_ticks, 2);
  EXPECT_EQ(s.servo.encoder_counts_per_turn, 0);
  EXPECT_EQ(s.servo.acceleration_feedforward, std::optional<bool>(false));
  EXPECT_EQ(s.servo.gravity_compensation, std::optional<bool>(false));
  EXPECT_DOUBLE_EQ(s.simulation.settle_tolerance, 0.05e-3);
  EXPECT_DOUBLE_EQ(s.simulation.settle_speed_tolerance, 2e-3);
  EXPECT_DOUBLE_EQ(s.simulation.settle_window, 0.1);
  EXPECT_DOUBLE_EQ(s.simulation.settle_time, 0.4);
  EXPECT_DOUBLE_EQ(s.simulation.vibration_window, 0.3);
  EXPECT_DOUBLE_EQ(s.simulation.vibration_highpass, 10);
  EXPECT_DOUBLE_EQ(s.simulation.jerk_lowpass, 40);
  // a servo rate alone that 500 Hz setpoints do not divide: the setpoints take its rate
  EXPECT_EQ(parse(replaced(kValid, "units: mm\n", "units: mm\nservo: {rate_hz: 250}\n")).servo.setpoint_rate_hz, 250);

  const std::string at = "units: mm\n";
  expect_error(replaced(kValid, at, at + "servo: {rate_hz: 9000}\n"), 3, "servo.rate_hz", "must be in [125, 8000] Hz, got 9000");
  expect_error(replaced(kValid, at, at + "servo: {setpoint_rate_hz: 3000}\n"), 3, "servo.setpoint_rate_hz",
               "the setpoint rate must be at most the servo rate (2000 Hz), got 3000");
  expect_error(replaced(kValid, at, at + "servo: {encoder_counts_per_turn: 10.5}\n"), 3, "servo.encoder_counts_per_turn",
               "whole number");
  expect_error(replaced(kValid, at, at + "servo: {kp: [1, 2, 3, 4, 5, 6]}\n"), 3, "servo.kp", "unknown key 'kp'");
  expect_error(replaced(kValid, at, at + "robot: {model: flexible}\n"), 3, "robot.model", "unknown value 'flexible' (one of: elastic, rigid)");
  expect_error(replaced(kValid, at, at + "simulation: {settle_window_s: 2}\n"), 3, "simulation.settle_window_s",
               "must be at least the settle window");
}

// robot.tool in the file's units from the flange, the branch switch, the chain's ends and a
// URDF without an MJCF (the dynamics built from it; estimate_inertia only then).
TEST(Scenario, ToolFrameBranchChangeAndUrdfOnlySettings) {
  const Scenario d = parse(kValid);
  EXPECT_TRUE(d.robot.tool.isApprox(Eigen::Isometry3d::Identity()));
  EXPECT_FALSE(d.robot.allow_branch_change);
  EXPECT_EQ(d.robot.base_link, "");  // the URDF's root
  EXPECT_EQ(d.robot.tip_link, "");   // its one leaf
  EXPECT_FALSE(d.robot.mjcf_from_urdf);
  const std::string at = "units: mm\n";
  const Scenario t = parse(replaced(kValid, at, at + "robot: {tool: {offset: [10, 0, 150], rpy_deg: [0, 90, 0]}, allow_branch_change: true}\n"));
  EXPECT_TRUE(t.robot.tool.translation().isApprox(Vec3(0.010, 0, 0.150), 1e-15));
  EXPECT_TRUE(t.robot.tool.linear().col(2).isApprox(Vec3(1, 0, 0), 1e-15));  // pitch 90: z onto x
  EXPECT_TRUE(t.robot.allow_branch_change);
  const Scenario m = parse(replaced(kValid, at, "units: m\nrobot: {tool: {offset: [0, 0.2, 0]}}\n"));
  EXPECT_TRUE(m.robot.tool.translation().isApprox(Vec3(0, 0.2, 0), 1e-15));
  // another URDF runs with the MJCF beside it, of the model asked for
  const Scenario k = parse(replaced(kValid, at, at + "robot: {urdf: models/kr6_like.urdf, model: rigid}\n"));
  EXPECT_TRUE(k.robot.mjcf.ends_with("models/kr6_like_rigid.xml")) << k.robot.mjcf;
  EXPECT_FALSE(k.robot.mjcf_from_urdf);
  // a URDF alone (no MJCF beside it): the dynamics from the URDF, with an inertia estimate if asked
  const test::ScratchDir scratch("scenario_test");
  const std::string alone = (scratch / "alone.urdf").string();
  std::filesystem::copy_file(test::source_path("models/kr6_like.urdf"), alone);
  const Scenario u = parse(replaced(kValid, at, at + "robot: {urdf: " + alone + ", estimate_inertia: {total_mass_kg: 30}}\n"));
  EXPECT_TRUE(u.robot.mjcf_from_urdf);
  EXPECT_EQ(u.robot.mjcf, "");
  EXPECT_EQ(u.robot.estimate_total_mass, 30);
  EXPECT_EQ(u.robot.estimate_where.line, 3);
  expect_error(replaced(kValid, at, at + "robot: {tool: {length: 3}}\n"), 3, "robot.tool.length", "unknown key 'length'");
  expect_error(replaced(kValid, at, at + "robot: {tool: {offset: [1, 2]}}\n"), 3, "robot.tool.offset", "3");
  expect_error(replaced(kValid, at, at + "robot: {urdf: models/kr6_like.urdf, estimate_inertia: {total_mass_kg: 0}}\n"), 3,
               "robot.estimate_inertia.total_mass_kg", "must be");
}

// `program.smoothing` for every variant, a variant's `smoothing` keys on top of it, in the file's
// units; bad values named by key.
TEST(Scenario, SmoothingIsAProgramDefaultThatVariantsRefine) {
  const std::string text = replaced(
      replaced(kValid, "  start: [0, 0, 0]\n", "  start: [0, 0, 0]\n  smoothing: {method: g2_fit, tolerance: 0.01, stream_length: 2}\n"),
      "  - {name: exact, transition: {method: none}}\n",
      "  - {name: exact, transition: {method: none}}\n  - {name: points, smoothing: {method: clothoid_points, max_turn_deg: 30, stream_turn_deg: 20}}\n"
      "  - {name: plain, smoothing: {method: none}}\n");
  const Scenario sc = parse(text);
  ASSERT_EQ(sc.variants.size(), 4u);
  const Program exact = program_for(sc, sc.variants[0]);
  EXPECT_EQ(exact.smoothing.method, SmoothingMethod::kG2Fit);
  EXPECT_NEAR(exact.smoothing.tolerance, 1e-5, 1e-18);
  EXPECT_NEAR(exact.smoothing.stream_length, 2e-3, 1e-18);
  EXPECT_NEAR(exact.smoothing.stream_turn, kDefaultStreamTurn, 1e-15);
  const Program points = program_for(sc, sc.variants[1]);
  EXPECT_EQ(points.smoothing.method, SmoothingMethod::kClothoidPoints);
  EXPECT_NEAR(points.smoothing.max_turn, 30 * std::numbers::pi / 180, 1e-15);
  EXPECT_NEAR(points.smoothing.stream_turn, 20 * std::numbers::pi / 180, 1e-15);
  EXPECT_NEAR(points.smoothing.stream_length, 2e-3, 1e-18);  // the program's
  EXPECT_EQ(program_for(sc, sc.variants[2]).smoothing.method, SmoothingMethod::kNone);
  EXPECT_EQ(program_for(parse(kValid), parse(kValid).variants[0]).smoothing.method, SmoothingMethod::kNone);
  // in metres
  const Scenario metres = parse(replaced(replaced(text, "units: mm", "units: m"), "frame: {origin: [400, 0, 200]", "frame: {origin: [0.4, 0, 0.2]"));
  EXPECT_NEAR(metres.program.smoothing.tolerance, 0.01, 1e-15);
  // errors
  const std::string program_line = "  smoothing: {method: g2_fit, tolerance: 0.01, stream_length: 2}\n";
  const auto with = [&](const std::string& line) { return replaced(text, program_line, line); };
  expect_error(with("  smoothing: {method: spline}\n"), 7, "program.smoothing.method", "unknown value 'spline'");
  expect_error(with("  smoothing: {method: g2_fit, tolerance: 0}\n"), 7, "program.smoothing.tolerance", "> 0");
  expect_error(with("  smoothing: {method: g2_fit, max_turn_deg: 180}\n"), 7, "program.smoothing.max_turn_deg", "(0, 180)");
  expect_error(with("  smoothing: {method: g2_fit, tolerence: 0.1}\n"), 7, "program.smoothing.tolerence", "did you mean 'tolerance'");
}

}  // namespace
}  // namespace blendbench
