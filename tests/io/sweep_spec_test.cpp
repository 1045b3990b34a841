// Sweep files and their expansion: key paths, lists and ranges, the product of the axes, values
// set in the scenario tree and validated by the scenario loader, and errors that name the sweep
// file, the axis and the point.

#include "blendbench/io/sweep_spec.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "blendbench/corner/blend.hpp"
#include "blendbench/io/scenario.hpp"
#include "support/input_error.hpp"
#include "support/files.hpp"
#include "support/property.hpp"
#include "support/scratch.hpp"

namespace blendbench {
namespace {

using test::source_path;

// A sweep over tests/data/tiny.yaml (variants exact and arc; defaults velocity, acceleration, jerk).
std::string tiny_sweep(const std::string& rest) { return "scenario: " + source_path("tests/data/tiny.yaml") + "\n" + rest; }

SweepSpec parse(const std::string& text) { return parse_sweep(text, "sweep.yaml", "."); }

// Runs `f`, which must throw an InputError; returns it.
template <typename F>
InputError error_of(F&& f) {
  return test::expect_input_error(std::forward<F>(f), {});
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream out;
  out << in.rdbuf();
  return out.str();
}

TEST(KeyPath, ParsesKeysIndicesAndWildcards) {
  const std::vector<KeyStep> steps = parse_key_path("variants[*].transition.parameter", {}, "f");
  ASSERT_EQ(steps.size(), 4U);
  EXPECT_EQ(steps[0].kind, KeyStep::Kind::kKey);
  EXPECT_EQ(steps[0].key, "variants");
  EXPECT_EQ(steps[1].kind, KeyStep::Kind::kEach);
  EXPECT_EQ(steps[2].key, "transition");
  EXPECT_EQ(steps[3].key, "parameter");

  const std::vector<KeyStep> nested = parse_key_path("a[2][10].b", {}, "f");
  ASSERT_EQ(nested.size(), 4U);
  EXPECT_EQ(nested[1].kind, KeyStep::Kind::kIndex);
  EXPECT_EQ(nested[1].index, 2U);
  EXPECT_EQ(nested[2].index, 10U);
  EXPECT_EQ(nested[3].key, "b");
}

TEST(KeyPath, RefusesMalformedPathsNamingTheField) {
  for (const std::string bad : {"", "[0].a", "a..b", "a.", "a[", "a[x]", "a[-1]", "a]b", "a[0]b"}) {
    const InputError e = error_of([&] { (void)parse_key_path(bad, {"s.yaml", 3, 5}, "axes.x"); });
    EXPECT_EQ(e.field(), "axes.x") << bad;
    EXPECT_EQ(e.line(), 3) << bad;
    EXPECT_TRUE(has(e.detail(), "bad key path")) << bad << ": " << e.what();
  }
}

// Issue 42: a key path of 2*10^4 to 10^5 steps overflowed the recursive setter's stack; a path is
// at most as deep as a scenario may nest.
TEST(KeyPath, APathDeeperThanAnyScenarioIsRefused) {
  std::string path = "a";
  for (std::size_t i = 1; i < kMaxKeyPathSteps; ++i) path += i % 2 == 0 ? ".a" : "[0]";
  EXPECT_EQ(parse_key_path(path, {}, "f").size(), kMaxKeyPathSteps);
  for (const std::size_t steps : {kMaxKeyPathSteps + 1, std::size_t{20000}, std::size_t{100000}}) {
    std::string long_path = "a";
    for (std::size_t i = 1; i < steps; ++i) long_path += ".a";
    const InputError e = error_of([&] { (void)parse_key_path(long_path, {"s.yaml", 3, 5}, "axes.x"); });
    EXPECT_TRUE(has(e.what(), "it has more than 64 steps")) << e.what();
    EXPECT_LT(std::string(e.what()).size(), 600u);
    // in a sweep file, the axis names the path, shortened
    const InputError in_file = error_of([&] { (void)parse(tiny_sweep("axes:\n  ? " + long_path + "\n  : [1]\n")); });
    EXPECT_EQ(in_file.line(), 3);
    EXPECT_TRUE(has(in_file.what(), "characters)': bad key path")) << std::string(in_file.what()).substr(0, 300);
  }
}

// Issue 42: yaml-cpp accepted these silently (the scenario loader refuses them): the sweep file
// passes the loader's YAML rules first.
TEST(SweepFile, TheScenarioLoadersYamlRulesApply) {
  const std::string axes = "axes:\n  defaults.velocity: [150]\n";
  struct Case {
    std::string text;
    int line;
    std::string message;
  };
  const Case cases[] = {
      {tiny_sweep(axes + "---\ndescription: second\n"), 4, "a second YAML document"},
      {tiny_sweep(axes + "axes:\n  defaults.velocity: [170]\n"), 4, "duplicate key 'axes'"},
      {tiny_sweep(axes + std::string("# a NUL \0 here\n", 15)), 4, "control characters are not allowed (byte 0x00)"},
      {tiny_sweep("description: \"\xff\xfe\"\n" + axes), 2, "invalid leading UTF-8 octet (byte 0xff)"},
  };
  for (const Case& c : cases) {
    test::expect_input_error([&] { (void)parse(c.text); }, {.file = "sweep.yaml", .line = c.line, .message = c.message},
                             c.message);
  }
}

TEST(Constraint, ParsesEveryOperatorWithOrWithoutSpaces) {
  struct Case {
    std::string text;
    Comparison op;
    double bound;
  };
  for (const Case& c : {Case{"tracking_error_max_mm <= 0.5", Comparison::kLessEqual, 0.5},
                        Case{"a<2", Comparison::kLess, 2}, Case{"cycle_time_s >= -1e-3", Comparison::kGreaterEqual, -1e-3},
                        Case{"  x >3  ", Comparison::kGreater, 3}}) {
    const Constraint k = parse_constraint(c.text, {}, "constraints[0]");
    EXPECT_EQ(k.op, c.op) << c.text;
    EXPECT_DOUBLE_EQ(k.bound, c.bound) << c.text;
    EXPECT_EQ(k.text, c.text);
  }
  EXPECT_EQ(parse_constraint("torque_peak_nm[2] < 40", {}, "c").metric, "torque_peak_nm[2]");
}

TEST(Constraint, RefusesOtherForms) {
  for (const std::string bad : {"a == 3", "a != 3", "a <> 3", "a << 3", "<= 3", "a <= x", "a <= 3 mm", "a <= inf",
                                "a <=", "two words <= 3", "a"}) {
    const InputError e = error_of([&] { (void)parse_constraint(bad, {"s.yaml", 7, 3}, "constraints[1]"); });
    EXPECT_EQ(e.field(), "constraints[1]") << bad;
    EXPECT_EQ(e.line(), 7) << bad;
  }
}

TEST(Constraint, MeetsComparesAndNeverPassesNaN) {
  const Constraint le = parse_constraint("m <= 1", {}, "c");
  const Constraint lt = parse_constraint("m < 1", {}, "c");
  const Constraint ge = parse_constraint("m >= 1", {}, "c");
  const Constraint gt = parse_constraint("m > 1", {}, "c");
  EXPECT_TRUE(meets(le, 1));
  EXPECT_FALSE(meets(lt, 1));
  EXPECT_TRUE(meets(ge, 1));
  EXPECT_FALSE(meets(gt, 1));
  EXPECT_TRUE(meets(lt, 0.5));
  EXPECT_TRUE(meets(gt, 1.5));
  for (const Constraint* c : {&le, &lt, &ge, &gt}) EXPECT_FALSE(meets(*c, std::nan("")));
}

TEST(SweepFile, ReadsListsRangesMetricsConstraintsAndPareto) {
  const SweepSpec spec = parse(tiny_sweep(R"(variants: [arc]
axes:
  variants[*].transition.parameter: [0.5, 1, 2]
  defaults.velocity: {from: 100, to: 400, steps: 4}
  defaults.jerk: {from: 1000, to: 100000, steps: 3, scale: log}
metrics: [cycle_time_s]
constraints: ["tracking_error_max_mm <= 0.5"]
pareto: {x: cycle_time_s, y: tracking_error_max_mm}
)"));
  ASSERT_EQ(spec.axes.size(), 3U);
  EXPECT_EQ(spec.axes[0].path, "variants[*].transition.parameter");
  EXPECT_EQ(spec.axes[0].labels, (std::vector<std::string>{"0.5", "1", "2"}));
  EXPECT_EQ(spec.axes[1].labels, (std::vector<std::string>{"100", "200", "300", "400"}));
  EXPECT_EQ(spec.axes[2].labels, (std::vector<std::string>{"1000", "10000", "100000"}));
  EXPECT_EQ(spec.axes[1].where.line, 5);
  EXPECT_EQ(spec.variants, std::vector<std::string>{"arc"});
  EXPECT_EQ(spec.metrics, std::vector<std::string>{"cycle_time_s"});
  ASSERT_EQ(spec.constraints.size(), 1U);
  EXPECT_EQ(spec.pareto_y, "tracking_error_max_mm");
  // every name the file uses is kept with its place, for the unknown-metric check
  std::set<std::string> fields;
  for (const MetricName& m : spec.named_metrics) fields.insert(m.field);
  EXPECT_EQ(fields, (std::set<std::string>{"metrics[0]", "constraints[0]", "pareto.x", "pareto.y"}));
}

TEST(SweepFile, DefaultParetoIsCycleTimeAgainstContourError) {
  const SweepSpec spec = parse(tiny_sweep("axes: {defaults.velocity: [100]}\n"));
  EXPECT_EQ(spec.pareto_x, "metrics.cycle_time_s");
  EXPECT_EQ(spec.pareto_y, "metrics.contour_error_programmed_max_mm");
  EXPECT_TRUE(spec.metrics.empty());
}

// Ranges: the ends exactly, evenly spaced (linear) or at a constant ratio (log), for random ends
// and step counts.
TEST(SweepFile, RangesAreEvenlySpacedLinearOrLog) {
  const int cases = test::property_cases(200);
  for (int k = 0; k < cases; ++k) {
    const std::uint64_t seed = 1400 + static_cast<std::uint64_t>(k);
    auto rng = test::make_rng(seed);
    const double from = test::log_uniform(rng, 1e-3, 1e3);
    const double to = test::log_uniform(rng, 1e-3, 1e3);
    const int steps = static_cast<int>(test::uniform(rng, 2, 12));
    const bool log = k % 2 == 1;
    const std::string range = "{from: " + std::to_string(from) + ", to: " + std::to_string(to) +
                              ", steps: " + std::to_string(steps) + (log ? ", scale: log" : "") + "}";
    const SweepSpec spec = parse(tiny_sweep("axes: {defaults.velocity: " + range + "}\n"));
    const std::vector<std::string>& v = spec.axes[0].labels;
    ASSERT_EQ(v.size(), static_cast<std::size_t>(steps)) << test::seed_text(seed);
    const double a = std::stod(std::to_string(from));
    const double b = std::stod(std::to_string(to));
    EXPECT_NEAR(std::stod(v.front()), a, 1e-9 * std::abs(a)) << test::seed_text(seed);
    EXPECT_NEAR(std::stod(v.back()), b, 1e-9 * std::abs(b)) << test::seed_text(seed);
    for (int i = 1; i + 1 < steps; ++i) {
      const double x = std::stod(v[static_cast<std::size_t>(i)]);
      const double expected = log ? a * std::pow(b / a, static_cast<double>(i) / (steps - 1))
                                  : a + (b - a) * i / (steps - 1);
      // ten significant digits are written
      EXPECT_NEAR(x, expected, 1e-9 * std::max(std::abs(a), std::abs(b))) << test::seed_text(seed) << " i=" << i;
    }
  }
}

TEST(SweepFile, ErrorsNameFileLineAndKey) {
  struct Case {
    std::string body;
    int line;
    std::string field;
    std::string fragment;
  };
  const Case cases[] = {
      {"axis: {defaults.velocity: [1]}\n", 2, "axis", "unknown key 'axis'"},
      {"axes: {defaults.velocity: []}\n", 2, "axes.defaults.velocity", "at least one value"},
      {"axes: {defaults.velocity: 100}\n", 2, "axes.defaults.velocity", "a list of values or a range"},
      {"axes:\n  defaults.velocity: {from: 1, to: 2}\n", 3, "axes.defaults.velocity.steps", "missing"},
      {"axes:\n  defaults.velocity: {from: 1, to: 2, steps: 1}\n", 3, "axes.defaults.velocity.steps", "at least 2"},
      // more steps than a sweep may have points, refused before the values are made (found by
      // tests/fuzz/fuzz_sweep: 44,444,443 steps asked for 1 GiB)
      {"axes:\n  defaults.velocity: {from: 1, to: 2, steps: 44444443}\n", 3, "axes.defaults.velocity.steps", "split the sweep"},
      {"axes:\n  defaults.velocity: {from: 1, to: 2, steps: 100001}\n", 3, "axes.defaults.velocity.steps", "exceed the 100000"},
      {"axes:\n  defaults.velocity: {from: 0, to: 2, steps: 3, scale: log}\n", 3, "axes.defaults.velocity", "positive"},
      {"axes:\n  defaults.velocity: {from: 1, to: 2, steps: 3, scale: cubic}\n", 3, "axes.defaults.velocity.scale", "'linear' or 'log'"},
      {"axes:\n  defaults.velocity: {from: 1, to: 2, steps: 3, by: 1}\n", 3, "axes.defaults.velocity.by", "unknown key"},
      {"axes:\n  a..b: [1]\n", 3, "axes.a..b", "bad key path"},
      {"axes: {defaults.velocity: [1]}\nconstraints: [\"x = 1\"]\n", 3, "constraints[0]", "bad constraint"},
      {"axes: {defaults.velocity: [1]}\nvariants: [arc, arc]\n", 3, "variants[1]", "selected twice"},
      {"axes: {defaults.velocity: [1]}\npareto: {x: a, y: a}\n", 3, "pareto", "different"},
      // a list as a key (found by tests/fuzz/fuzz_sweep): refused where it stands, not yaml-cpp's bad conversion
      {"axes:\n  defaults.velocity: {from: 1, [0]: 3, steps: 2}\n", 3, "axes.defaults.velocity", "a key must be a name"},
  };
  for (const Case& c : cases) {
    const InputError e = error_of([&] { (void)parse(tiny_sweep(c.body)); });
    EXPECT_EQ(e.file(), "sweep.yaml") << c.body;
    EXPECT_EQ(e.line(), c.line) << c.body << e.what();
    EXPECT_EQ(e.field(), c.field) << c.body << e.what();
    EXPECT_TRUE(has(e.detail(), c.fragment)) << c.body << e.what();
  }
  const InputError missing = error_of([] { (void)parse("axes: {a: [1]}\n"); });
  EXPECT_EQ(missing.field(), "scenario");
  const InputError absent = error_of([] { (void)parse("scenario: no/such.yaml\naxes: {a: [1]}\n"); });
  EXPECT_TRUE(has(absent.detail(), "file not found")) << absent.what();
  // a name longer than the file system takes (found by tests/fuzz/fuzz_sweep: filesystem_error
  // escaped as std::terminate) is a file that is not found
  const std::string long_name = "scenario: " + std::string(5000, 'x') + ".yaml\naxes: {a: [1]}\n";
  const InputError too_long = error_of([&] { (void)parse(long_name); });
  EXPECT_EQ(too_long.field(), "scenario") << too_long.what();
  EXPECT_TRUE(has(too_long.detail(), "file not found")) << too_long.what();
}

// The product: sizes multiply, the last axis varies fastest, every combination once.
TEST(Expansion, ProductOfAxesInOrderLastFastest) {
  const SweepPlan plan = expand_sweep(parse(tiny_sweep(R"(axes:
  defaults.velocity: [100, 150]
  defaults.acceleration: [1000, 2000, 3000]
  defaults.jerk: {from: 10000, to: 40000, steps: 4}
)")));
  ASSERT_EQ(plan.points.size(), 2U * 3U * 4U);
  std::set<std::vector<std::size_t>> seen;
  for (std::size_t i = 0; i < plan.points.size(); ++i) {
    const SweepPoint& p = plan.points[i];
    EXPECT_EQ(p.index, i);
    EXPECT_EQ(p.choice[2], i % 4);
    EXPECT_EQ(p.choice[1], (i / 4) % 3);
    EXPECT_EQ(p.choice[0], i / 12);
    seen.insert(p.choice);
    // the loader reads back exactly the point's values (mm -> m)
    const Scenario sc = parse_scenario(p.scenario_text, "p.yaml", plan.base_dir);
    const Limits& lim = sc.program.moves.front().limits;
    EXPECT_NEAR(lim.velocity, std::stod(plan.spec.axes[0].labels[p.choice[0]]) * 1e-3, 1e-12);
    EXPECT_NEAR(lim.acceleration, std::stod(plan.spec.axes[1].labels[p.choice[1]]) * 1e-3, 1e-12);
    EXPECT_NEAR(lim.jerk, std::stod(plan.spec.axes[2].labels[p.choice[2]]) * 1e-3, 1e-12);
  }
  EXPECT_EQ(seen.size(), plan.points.size());
}

TEST(Expansion, WildcardSetsEveryElementAndIndexOne) {
  const SweepPlan plan = expand_sweep(parse(tiny_sweep(R"(axes:
  variants[*].transition.parameter: [3]
  program.moves[1].velocity: [50]
)")));
  ASSERT_EQ(plan.points.size(), 1U);
  const SweepPoint& p = plan.points[0];
  EXPECT_EQ(p.targets[0], (std::vector<std::string>{"variants[0].transition.parameter", "variants[1].transition.parameter"}));
  EXPECT_EQ(p.targets[1], std::vector<std::string>{"program.moves[1].velocity"});
  const Scenario sc = parse_scenario(p.scenario_text, "p.yaml", plan.base_dir);
  for (const Variant& v : sc.variants) EXPECT_NEAR(v.transition->parameter, 3e-3, 1e-15) << v.name;
  EXPECT_NEAR(sc.program.moves[0].limits.velocity, 0.2, 1e-12);  // untouched: the defaults' 200 mm/s
  EXPECT_NEAR(sc.program.moves[1].limits.velocity, 0.05, 1e-12);
  EXPECT_EQ(p.variants, (std::vector<std::string>{"exact", "arc"}));
}

// A key the scenario does not have is created where a mapping holds it; the loader then decides.
TEST(Expansion, MissingKeysAreCreatedAndValidatedByTheLoader) {
  const SweepPlan plan = expand_sweep(parse(tiny_sweep(R"(axes:
  defaults.deceleration: [500]
  servo.rate_hz: [500]
)")));
  const Scenario sc = parse_scenario(plan.points[0].scenario_text, "p.yaml", plan.base_dir);
  EXPECT_NEAR(sc.program.moves[0].limits.deceleration, 0.5, 1e-12);
  EXPECT_DOUBLE_EQ(sc.servo.rate_hz, 500);
  validate_point(plan, plan.points[0], "p.yaml");
}

TEST(Expansion, PathsThroughMissingElementsNameTheAxis) {
  struct Case {
    std::string axes;
    std::string field;
    std::string fragment;
  };
  const Case cases[] = {
      {"  program.moves[5].velocity: [1]\n", "axes.program.moves[5].velocity", "has 2 elements"},
      {"  defaults.velocity[*]: [1]\n", "axes.defaults.velocity[*]", "not a list"},
      {"  defaults.velocity.x: [1]\n", "axes.defaults.velocity.x", "not a mapping"},
      {"  servo.kp[0]: [1]\n", "axes.servo.kp[0]", "no list 'servo.kp'"},
  };
  for (const Case& c : cases) {
    const InputError e = error_of([&] { (void)expand_sweep(parse(tiny_sweep("axes:\n" + c.axes))); });
    EXPECT_EQ(e.file(), "sweep.yaml") << c.axes;
    EXPECT_EQ(e.line(), 3) << c.axes;
    EXPECT_EQ(e.field(), c.field) << e.what();
    EXPECT_TRUE(has(e.detail(), c.fragment)) << e.what();
    EXPECT_TRUE(has(e.detail(), "point 0 of 1")) << e.what();
  }
}

TEST(Expansion, TwoAxesSettingOneValueAreRefused) {
  const InputError e = error_of([] {
    (void)expand_sweep(parse(tiny_sweep(R"(axes:
  variants[*].transition: [{method: none}]
  variants[1].transition.parameter: [1]
)")));
  });
  EXPECT_EQ(e.field(), "axes.variants[1].transition.parameter") << e.what();
  EXPECT_TRUE(has(e.detail(), "sets too")) << e.what();
}

TEST(Expansion, SelectedVariantsMustExist) {
  const InputError e = error_of([] { (void)expand_sweep(parse(tiny_sweep("variants: [arc, spline]\naxes: {defaults.velocity: [1]}\n"))); });
  EXPECT_EQ(e.field(), "variants[1]");
  EXPECT_EQ(e.line(), 2);
  EXPECT_TRUE(has(e.detail(), "variants: exact, arc")) << e.what();
}

// A value the loader refuses: the error is at the axis in the sweep file and names the point,
// its values and the loader's own message.
TEST(Expansion, BadValuesNameTheAxisThePointAndTheLoadersMessage) {
  const SweepPlan plan = expand_sweep(parse(tiny_sweep(R"(axes:
  variants[*].transition.parameter: [2, 5]
  defaults.velocity: [100, -3]
)")));
  ASSERT_EQ(plan.points.size(), 4U);
  validate_point(plan, plan.points[0], "p0.yaml");
  const InputError e = error_of([&] { validate_point(plan, plan.points[3], "p3.yaml"); });
  EXPECT_EQ(e.file(), "sweep.yaml");
  EXPECT_EQ(e.line(), 4);
  EXPECT_EQ(e.field(), "axes.defaults.velocity");
  EXPECT_TRUE(has(e.detail(), "point 3 of 4 (variants[*].transition.parameter=5, defaults.velocity=-3)")) << e.what();
  EXPECT_TRUE(has(e.detail(), "p3.yaml:")) << e.what();
  EXPECT_TRUE(has(e.detail(), "'defaults.velocity': must be > 0 mm/s, got -3")) << e.what();

  // a method name the loader does not know, through [*]
  const SweepPlan methods = expand_sweep(parse(tiny_sweep("axes:\n  variants[*].transition.method: [arc, spline]\n")));
  const InputError m = error_of([&] { validate_point(methods, methods.points[1], "p.yaml"); });
  EXPECT_EQ(m.field(), "axes.variants[*].transition.method") << m.what();
  EXPECT_TRUE(has(m.detail(), "unknown value 'spline'")) << m.what();
}

// Equal tolerance as a sweep axis (issue 44): `variants[*].transition.tolerance` sets every
// variant's tolerance; each point's programs carry it, and blended, every corner reports it and
// reaches it (the moves are long). A base whose variant sets a parameter is refused at the axis,
// naming both keys.
TEST(Expansion, ToleranceIsASweepAxis) {
  const test::ScratchDir dir("sweep-tolerance");
  std::string base = read_text(source_path("tests/data/tiny.yaml"));
  const std::string arc = "{name: arc, transition: {method: arc, parameter: 5}}";
  base.replace(base.find(arc), arc.size(),
               "{name: arc, transition: {method: arc, tolerance: 1}}\n  - {name: bezier, transition: {method: bezier, tolerance: 1}}");
  const std::string scenario = dir.write("base.yaml", base);
  const SweepPlan plan = expand_sweep(parse("scenario: " + scenario + "\naxes:\n  variants[*].transition.tolerance: [0.05, 0.5]\n"));
  ASSERT_EQ(plan.points.size(), 2U);
  for (std::size_t i = 0; i < plan.points.size(); ++i) {
    validate_point(plan, plan.points[i], "p.yaml");
    const Scenario sc = parse_scenario(plan.points[i].scenario_text, "p.yaml", plan.base_dir);
    const double tol = i == 0 ? 0.05e-3 : 0.5e-3;
    for (const Variant& v : sc.variants) {
      const Program program = program_for(sc, v);
      const Path path = blend(program);
      ASSERT_EQ(path.corners.size(), 1U);
      if (v.name == "exact") continue;  // none: an exact stop (the axis gives it a tolerance it cannot use)
      EXPECT_EQ(path.corners[0].tolerance, tol) << v.name;
      EXPECT_TRUE(path.corners[0].tolerance_reached) << v.name << ": " << path.corners[0].note.text();
      EXPECT_LE(path.corners[0].deviation, tol) << v.name;
    }
  }
  // tiny.yaml's arc variant sets a parameter: the axis' tolerance is refused naming both
  const SweepPlan clash = expand_sweep(parse(tiny_sweep("axes:\n  variants[*].transition.tolerance: [0.1]\n")));
  const InputError e = error_of([&] { validate_point(clash, clash.points[0], "p.yaml"); });
  EXPECT_EQ(e.field(), "axes.variants[*].transition.tolerance") << e.what();
  EXPECT_TRUE(has(e.detail(), "tolerance and parameter exclude each other")) << e.what();
}

// The first point is checked as soon as it exists, before the rest of the product is expanded:
// an axis path the loader refuses (a key created where none may be) costs one point, not all
// (found by tests/fuzz/fuzz_sweep: such a sweep of 21,000 steps took 5 s to refuse). The message
// counts the whole product.
TEST(Expansion, FirstPointIsCheckedBeforeTheRestIsExpanded) {
  const SweepSpec bad = parse(tiny_sweep("axes:\n  variants[1].transition.no_such_key: {from: 1, to: 2, steps: 5000}\n"));
  int calls = 0;
  const InputError e = error_of([&] {
    (void)expand_sweep(bad, [&](const SweepPlan& plan, const SweepPoint& point) {
      ++calls;
      EXPECT_EQ(plan.points.size(), 1U);
      EXPECT_EQ(point.index, 0U);
      validate_point(plan, point, "p0.yaml");
    });
  });
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(e.field(), "axes.variants[1].transition.no_such_key") << e.what();
  EXPECT_TRUE(has(e.detail(), "point 0 of 5000 (")) << e.what();

  // a sweep the check accepts is expanded whole, the check called on its first point only
  calls = 0;
  const SweepPlan good = expand_sweep(parse(tiny_sweep("axes:\n  defaults.velocity: [100, 150, 200]\n")),
                                      [&](const SweepPlan& plan, const SweepPoint& point) {
                                        ++calls;
                                        validate_point(plan, point, "p0.yaml");
                                      });
  EXPECT_EQ(calls, 1);
  EXPECT_EQ(good.points.size(), 3U);
  EXPECT_EQ(sweep_point_count(good.spec), 3U);
}

// The hash is a function of the content: equal texts and variants give equal hashes, and it
// changes with a value or with the selection.
// Issue 42: a base scenario without `variants` gave yaml-cpp's "invalid node; first invalid key"
// (exit 1); the loader's message names what is missing.
TEST(Expansion, ABaseScenarioWithoutVariantsIsTheLoadersError) {
  const test::ScratchDir dir("sweep_spec_no_variants");
  std::string base = test::read_file(source_path("tests/data/tiny.yaml"));
  base.erase(base.find("variants:"));
  const std::string scenario = dir.write("base.yaml", base);
  const SweepSpec spec = parse("scenario: " + scenario + "\naxes:\n  defaults.velocity: [150]\n");
  const SweepPlan plan = expand_sweep(spec);
  ASSERT_EQ(plan.points.size(), 1u);
  EXPECT_TRUE(plan.points[0].variants.empty());
  test::expect_input_error([&] { validate_point(plan, plan.points[0], "point.yaml"); },
                           {.file = "sweep.yaml", .field = "axes", .message = "'variants': missing required field"});
}

TEST(Expansion, HashFollowsTheContent) {
  const SweepPlan a = expand_sweep(parse(tiny_sweep("axes:\n  defaults.velocity: [100, 150, 100]\n")));
  EXPECT_EQ(a.points[0].hash, a.points[2].hash);
  EXPECT_NE(a.points[0].hash, a.points[1].hash);
  EXPECT_EQ(a.points[0].hash.size(), 16U);
  const SweepPlan b = expand_sweep(parse(tiny_sweep("variants: [arc]\naxes:\n  defaults.velocity: [100]\n")));
  EXPECT_NE(a.points[0].hash, b.points[0].hash);
  const SweepPlan again = expand_sweep(parse(tiny_sweep("axes:\n  defaults.velocity: [100, 150, 100]\n")));
  EXPECT_EQ(again.points[1].hash, a.points[1].hash);
}

// Smoothing is a sweep axis like any other key: each point's variants smooth at its values.
TEST(Expansion, SmoothingIsAnAxis) {
  const SweepPlan plan = expand_sweep(parse(tiny_sweep(R"(axes:
  variants[*].smoothing.method: [clothoid_points, g2_fit]
  variants[*].smoothing.tolerance: [0.01, 0.05]
)")));
  ASSERT_EQ(plan.points.size(), 4U);
  for (const SweepPoint& p : plan.points) {
    validate_point(plan, p, "p.yaml");
    const Scenario sc = parse_scenario(p.scenario_text, "p.yaml", plan.base_dir);
    for (const Variant& v : sc.variants) {
      const Program program = program_for(sc, v);
      EXPECT_EQ(program.smoothing.method, p.choice[0] == 0 ? SmoothingMethod::kClothoidPoints : SmoothingMethod::kG2Fit);
      EXPECT_NEAR(program.smoothing.tolerance, p.choice[1] == 0 ? 1e-5 : 5e-5, 1e-18);
    }
  }
}

}  // namespace
}  // namespace blendbench
