// What `compare` runs (app/compare.hpp): the variants it builds, their names, the tolerances it
// takes from the program, and its refusals. (The runs themselves: compare_test.cpp.)

#include "blendbench/app/compare.hpp"

#include <gtest/gtest.h>

#include <set>

#include "support/input_error.hpp"
#include "support/scratch.hpp"

namespace blendbench {
namespace {

const char* const kScenario = R"(name: two
units: mm
frame: {origin: [400, 0, 200]}
defaults: {velocity: 100, acceleration: 1000, jerk: 10000}
program:
  start: [0, 0, 0]
  moves:
    - line: [50, 0, 0]
    - line: [50, 50, 0]
      transition: {method: bezier, parameter: 3}
    - line: [0, 50, 0]
variants:
  - {name: exact, transition: {method: none}}
)";

TEST(ComparePlan, BothBaselinesThenEveryMethodPerToleranceAscending) {
  const Scenario sc = parse_scenario(kScenario, "two.yaml", ".");
  CompareRequest request;
  request.tolerances = {2e-3, 0.5e-3};
  const ComparePlan plan = plan_compare(sc, request);
  std::vector<std::string> names;
  for (const VariantInputs& v : plan.inputs.variants) names.push_back(v.name);
  const std::vector<std::string> expected = {"exact_stop",    "junction_slowdown", "arc_0.5mm",  "bezier_0.5mm",
                                             "clothoid_0.5mm", "biclothoid_0.5mm",  "arc_2mm",    "bezier_2mm",
                                             "clothoid_2mm",   "biclothoid_2mm"};
  EXPECT_EQ(names, expected);
  EXPECT_EQ(plan.tolerances, (std::vector<double>{0.5e-3, 2e-3}));
  EXPECT_EQ(plan.inputs.variants[1].timing.baseline, TimingOptions::Baseline::kJunctionSlowdown);
  // every move takes the compared method at the tolerance, the one that set its own Bezier too
  for (const VariantInputs& v : plan.inputs.variants) {
    for (const Move& m : v.program.moves) {
      EXPECT_EQ(m.transition.method, v.method) << v.name;
      EXPECT_EQ(m.transition.tolerance, v.tolerance) << v.name;
      EXPECT_EQ(m.transition.parameter, 0) << v.name;
    }
  }
  // what it changed and left out, said
  ASSERT_EQ(plan.notes.size(), 2U);
  EXPECT_NE(plan.notes[0].find("set their own transition"), std::string::npos) << plan.notes[0];
  EXPECT_NE(plan.notes[1].find("variant(s) are not run"), std::string::npos) << plan.notes[1];
  EXPECT_EQ(plan.inputs.notes, plan.notes);
  EXPECT_EQ(plan.inputs.name, "two_compare");
}

TEST(ComparePlan, TheProgramsG64ToleranceElseTheDefault) {
  const test::ScratchDir dir("compare-plan");
  const std::string two = dir.write("two.ngc", "G21 G90\nG64 P0.05\nG1 X20 F600\nG1 Y20\nG64 P0.5\nG1 X0\nG1 Y0\nM2\n");
  const Scenario sc = gcode_scenario(two);
  EXPECT_EQ(program_tolerances(sc.program), (std::vector<double>{0.05e-3, 0.5e-3}));
  CompareRequest request;
  request.methods = {Method::kClothoid};
  const ComparePlan plan = plan_compare(sc, request);
  EXPECT_EQ(plan.tolerances, (std::vector<double>{0.05e-3, 0.5e-3}));
  ASSERT_EQ(plan.inputs.variants.size(), 4U);
  EXPECT_EQ(plan.inputs.variants[2].name, "clothoid_0.05mm");
  EXPECT_EQ(plan.inputs.variants[3].name, "clothoid_0.5mm");
  // a G-code INPUT's own two variants are not the user's: no note about them
  for (const std::string& note : plan.notes) EXPECT_EQ(note.find("variant(s) are not run"), std::string::npos) << note;
  // no G64 P: 0.1 mm
  const std::string plain = dir.write("plain.ngc", "G21 G90\nG1 X20 F600\nG1 Y20\nM2\n");
  const ComparePlan fallback = plan_compare(gcode_scenario(plain), request);
  EXPECT_EQ(fallback.tolerances, (std::vector<double>{kDefaultCompareTolerance}));
  // and a command-line tolerance wins over the program's
  request.tolerances = {1e-3};
  EXPECT_EQ(plan_compare(sc, request).tolerances, (std::vector<double>{1e-3}));
}

TEST(ComparePlan, VariantNamesSayMethodAndTolerance) {
  EXPECT_EQ(compare_variant_name(Method::kArc, 0.5e-3), "arc_0.5mm");
  EXPECT_EQ(compare_variant_name(Method::kBiclothoid, 0.05e-3), "biclothoid_0.05mm");
  EXPECT_EQ(compare_variant_name(Method::kClothoid, 2e-3), "clothoid_2mm");
  EXPECT_EQ(compare_variant_name(Method::kBezier, 0.125e-3), "bezier_0.125mm");
  EXPECT_TRUE(folder_name_problem(compare_variant_name(Method::kBezier, 1e-8)).empty());
}

TEST(ComparePlan, MethodListsAndTolerancesAreChecked) {
  EXPECT_EQ(methods_from_list("clothoid,arc,clothoid", "--methods"), (std::vector<Method>{Method::kClothoid, Method::kArc}));
  test::expect_input_error([] { (void)methods_from_list("arc,spline", "--methods"); }, {.field = "--methods", .message = "spline"});
  test::expect_input_error([] { (void)methods_from_list("none", "--methods"); }, {.field = "--methods"});
  test::expect_input_error([] { (void)methods_from_list("", "--methods"); }, {.field = "--methods"});
  const Scenario sc = parse_scenario(kScenario, "two.yaml", ".");
  CompareRequest request;
  request.tolerances = {0.1e-3, -1e-3};
  test::expect_input_error([&] { (void)plan_compare(sc, request); }, {.field = "--tolerance", .message = "> 0"});
  // one tolerance given twice, or in two spellings that name the same variant, runs once
  request.tolerances = {0.5e-3, 0.1e-3, 0.5e-3, 0.1000001e-3};
  const ComparePlan once = plan_compare(sc, request);
  EXPECT_EQ(once.tolerances, (std::vector<double>{0.1e-3, 0.5e-3}));
  std::set<std::string> names;
  for (const auto& v : once.inputs.variants) EXPECT_TRUE(names.insert(v.name).second) << v.name;
  request.tolerances.clear();
  for (std::size_t k = 0; k <= kMaxCompareTolerances; ++k) request.tolerances.push_back(1e-4 * static_cast<double>(k + 1));
  test::expect_input_error([&] { (void)plan_compare(sc, request); }, {.field = "--tolerance", .message = "at most"});
}

}  // namespace
}  // namespace blendbench
