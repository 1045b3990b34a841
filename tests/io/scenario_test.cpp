#include "blendbench/io/scenario.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <numbers>

#include "blendbench/corner/blend.hpp"

#include "support/property.hpp"

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
void expect_error(const std::string& text, int line, const std::string& field, const std::string& fragment) {
  try {
    (void)parse(text);
    FAIL() << "expected an InputError for field " << field;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "test.yaml");
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_EQ(e.field(), field) << e.what();
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
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

TEST(Scenario, VariantTransitionAppliesOnlyWhereTheMoveSetsNone) {
  const Scenario sc = parse(kValid);
  const Program p = program_for(sc, find_variant(sc, "arc5"));
  EXPECT_EQ(p.moves[0].transition.method, Method::kArc);
  EXPECT_NEAR(p.moves[0].transition.parameter, 0.002, 1e-15);
  EXPECT_NEAR(p.moves[1].transition.parameter, 0.005, 1e-15);  // the move's own
  EXPECT_EQ(p.moves[2].buffer, BufferMode::kBlendingLow);
  EXPECT_THROW((void)find_variant(sc, "nope"), InputError);
}

TEST(Scenario, BadInputNamesFileLineAndField) {
  expect_error(replaced(kValid, "units: mm", "units: mm\nspeed: 3"), 3, "speed", "unknown key 'speed'");
  expect_error(replaced(kValid, "velocity: 100", "velocity: fast"), 4, "defaults.velocity", "expected a number");
  expect_error(replaced(kValid, "jerk: 10000, ", ""), 4, "defaults.jerk", "missing required field");
  expect_error(replaced(kValid, "direction: ccw", "direction: left"), 9, "program.moves[1].arc.direction",
               "'cw' or 'ccw'");
  expect_error(replaced(kValid, "method: arc, parameter: 5", "method: spline, parameter: 5"), 11,
               "program.moves[1].transition.method", "unknown method");
  expect_error(replaced(kValid, "name: arc5", "name: exact"), 15, "variants[1].name", "duplicate variant");
  expect_error(replaced(kValid, "center: [100, 50, 0]", "center: [100, 40, 0]"), 9, "program.moves[1].arc.center",
               "differs from the radius");
  expect_error(replaced(kValid, "line: [0, 100, 0]", "line: [100, 100, 0]"), 12, "program.moves[2].line",
               "zero-length");
  expect_error(replaced(kValid, "acceleration: 1000", "acceleration: -5"), 4, "defaults.acceleration", "positive");
  expect_error(replaced(kValid, "velocity: 50", "velocity: [50]"), 10, "program.moves[1].velocity", "expected a number");
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
               "program.moves[1].transition.start_distance", "must be positive");
}

TEST(Scenario, InvalidYamlReportsTheParserPosition) {
  try {
    (void)parse("name: x\nprogram: [unclosed\n");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_GE(e.line(), 2);
    EXPECT_NE(std::string(e.what()).find("invalid YAML"), std::string::npos);
  }
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
  for (const auto& entry : std::filesystem::recursive_directory_iterator(test::source_path("scenarios"))) {
    if (entry.path().extension() != ".yaml") continue;
    if (entry.path().parent_path().filename() == "sweeps") continue;  // sweep files (sweep_test runs them)
    ++count;
    SCOPED_TRACE(entry.path().string());
    try {
      const Scenario sc = load_scenario(entry.path().string());
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

}  // namespace
}  // namespace blendbench
