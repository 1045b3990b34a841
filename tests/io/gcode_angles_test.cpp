// The G-code reader's tool angles (io/src/gcode_angles.cpp and their use in gcode.cpp) and the
// scenario key that maps them (program.gcode_angles): the convention by hand, modal and G91
// angles, the located errors, and a round trip against the same program written as YAML moves.

#include "blendbench/core/units.hpp"
#include "blendbench/corner/blend.hpp"
#include "blendbench/io/gcode.hpp"
#include "blendbench/io/scenario.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <filesystem>
#include <fstream>
#include <random>
#include <stdexcept>
#include <string>
#include <system_error>

#include "support/input_error.hpp"
#include "support/property.hpp"
#include "support/random_geometry.hpp"
#include "support/scratch.hpp"

namespace blendbench {
namespace {

constexpr double kTol = 1e-12;  // m and rad: derived by hand

GcodeOptions options() {
  GcodeOptions opt;
  opt.limits = {0.1, 2.0, 3.0, 50.0};
  return opt;
}

GcodeResult parse(const std::string& text, const GcodeOptions& opt = options()) { return parse_gcode(text, "part.ngc", opt); }

// Parses text that must fail; checks the location and word, returns the message.
std::string expect_error(const std::string& text, int line, int column, const std::string& word) {
  return test::expect_input_error([&] { (void)parse(text); },
                                  {.file = "part.ngc", .line = line, .column = column, .field = word}, text)
      .detail();
}

Vec3 mm(double x, double y, double z) { return Vec3(x, y, z) * kMm; }
Vec3 end_of(const Primitive& p) { return point(p, length(p)); }
bool has_note(const GcodeResult& r, const std::string& text) {
  return std::find(r.ignored.begin(), r.ignored.end(), text) != r.ignored.end();
}
#define EXPECT_VEC_NEAR(a, b, tol) EXPECT_LE(((a) - (b)).norm(), tol) << "got " << (a).transpose() << " expected " << (b).transpose()

Scenario parse_yaml(const std::string& text) { return parse_scenario(text, "test.yaml", "."); }

// Asserts that a scenario fails with an InputError at the given line and field.
void expect_scenario_error(const std::string& text, int line, const std::string& field, const std::string& fragment) {
  (void)test::expect_input_error([&] { (void)parse_yaml(text); },
                                 {.file = "test.yaml", .line = line, .field = field, .message = fragment}, text);
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

// Tool angles: A, B, C mapped to roll, pitch, yaw (gcode.hpp, "Tool angles").
GcodeOptions with_angles(ToolAngle a, ToolAngle b, ToolAngle c) {
  GcodeOptions opt = options();
  opt.angles = GcodeAngles{{a, b, c}};
  return opt;
}

Quat rpy(double roll_deg, double pitch_deg, double yaw_deg) {
  return Quat(Eigen::AngleAxisd(yaw_deg * kDeg, Vec3::UnitZ()) * Eigen::AngleAxisd(pitch_deg * kDeg, Vec3::UnitY()) *
              Eigen::AngleAxisd(roll_deg * kDeg, Vec3::UnitX()));
}

// By hand: KUKA's A, B, C = {yaw, pitch, roll}: A90 B0 C180 is Rz(90) Rx(180), which takes x to
// y and z to -z; the RS274 naming {roll, pitch, yaw} reads the same angles as Rx(90) Rz(180).
TEST(Gcode, ToolAnglesGiveTheMoveOrientationByTheMapping) {
  const auto kuka = with_angles(ToolAngle::kYaw, ToolAngle::kPitch, ToolAngle::kRoll);
  const GcodeResult r = parse("G1 X10 A90 B0 C180\nG1 Y10", kuka);
  ASSERT_EQ(r.program.moves.size(), 2U);
  ASSERT_TRUE(r.program.moves[0].orientation.has_value());
  const Eigen::Matrix3d m = r.program.moves[0].orientation->toRotationMatrix();
  EXPECT_VEC_NEAR(Vec3(m * Vec3::UnitX()), Vec3::UnitY(), kTol);
  EXPECT_VEC_NEAR(Vec3(m * Vec3::UnitZ()), Vec3(-Vec3::UnitZ()), kTol);
  EXPECT_FALSE(r.program.moves[1].orientation.has_value());  // no angle words: it keeps the orientation
  const GcodeResult rs = parse("G1 X10 A90 B0 C180", with_angles(ToolAngle::kRoll, ToolAngle::kPitch, ToolAngle::kYaw));
  EXPECT_LE(rotation_angle(*rs.program.moves[0].orientation, rpy(90, 0, 180)), kTol);
  // inches do not scale degrees; an arc takes angles as a line does
  const GcodeResult arc = parse("G20 G1 X1 A0 B30 C0\nG3 X0 Y1 I-1 C90", kuka);
  ASSERT_EQ(arc.program.moves.size(), 2U);
  EXPECT_LE(rotation_angle(*arc.program.moves[0].orientation, rpy(0, 30, 0)), kTol);
  EXPECT_LE(rotation_angle(*arc.program.moves[1].orientation, rpy(90, 30, 0)), kTol);
  EXPECT_NE(std::get_if<Arc>(&arc.program.moves[1].geometry), nullptr);
}

// Modal like X, Y, Z: an angle not written keeps its value, G91 adds to the angle (Euler
// angles, not a rotation), G90 sets it again.
TEST(Gcode, ToolAnglesAreModalAndIncrementalUnderG91) {
  const auto opt = with_angles(ToolAngle::kRoll, ToolAngle::kPitch, ToolAngle::kYaw);
  const GcodeResult r = parse("G1 X10 A170 B20 C30\nG91 X10 A15\nX10 C-40 B5\nG90 X0 B0", opt);
  ASSERT_EQ(r.program.moves.size(), 4U);
  EXPECT_LE(rotation_angle(*r.program.moves[0].orientation, rpy(170, 20, 30)), kTol);
  EXPECT_LE(rotation_angle(*r.program.moves[1].orientation, rpy(185, 20, 30)), kTol);
  EXPECT_LE(rotation_angle(*r.program.moves[2].orientation, rpy(185, 25, -10)), kTol);
  EXPECT_LE(rotation_angle(*r.program.moves[3].orientation, rpy(185, 0, -10)), kTol);
  EXPECT_VEC_NEAR(end_of(r.program.moves[2].geometry), mm(30, 0, 0), kTol);
  // a zero-length move that keeps the orientation is dropped as before
  const GcodeResult same = parse("G1 X10 A0 B0 C0\nG1 X10 C360\nG1 X20", opt);
  EXPECT_EQ(same.program.moves.size(), 2U);
  EXPECT_TRUE(has_note(same, "line 2 G1: zero-length move dropped"));
}

// Without a mapping A, B, C stay refused where they stand; with one, the angles' own errors are
// located at the word.
// An arc that becomes a chain of tangent arcs (its end point off the circle: LinuxCNC's spiral)
// still reaches its orientation at its end, and on the way turns as the one move would: each arc
// of the chain takes the slerp at its share of the chain's length.
TEST(Gcode, ToolAnglesOfAnArcSplitAlongLinuxCncsSpiralAreReachedAtItsEnd) {
  const GcodeOptions opt = with_angles(ToolAngle::kRoll, ToolAngle::kPitch, ToolAngle::kYaw);
  const GcodeResult r = parse("G1 X0.001 A0 B0 C0 F600\nG2 X100 Y-100.0282 I99.999 A0 B0 C120\n", opt);
  ASSERT_GT(r.program.moves.size(), 3u);
  const Quat to = rpy(0, 0, 120);
  double total = 0;
  for (std::size_t k = 1; k < r.program.moves.size(); ++k) total += length(r.program.moves[k].geometry);
  double done = 0;
  for (std::size_t k = 1; k < r.program.moves.size(); ++k) {
    done += length(r.program.moves[k].geometry);
    ASSERT_TRUE(r.program.moves[k].orientation.has_value()) << k;
    // the yaw turns in proportion to the length travelled: 120 degrees over the chain
    EXPECT_LE(rotation_angle(*r.program.moves[k].orientation, rpy(0, 0, 120 * done / total)), 1e-12) << k;
  }
  EXPECT_LE(rotation_angle(*r.program.moves.back().orientation, to), 1e-12);
}

TEST(Gcode, ToolAngleErrorsAreLocated) {
  const std::string unmapped = expect_error("G1 X1\nG1 X2 B3", 2, 7, "B3");
  EXPECT_NE(unmapped.find("program.gcode_angles"), std::string::npos) << unmapped;
  const auto opt = with_angles(ToolAngle::kRoll, ToolAngle::kPitch, ToolAngle::kYaw);
  const auto error_with = [&](const std::string& text, int line, int column, const std::string& word, const std::string& words) {
    const InputError e = test::expect_input_error([&] { (void)parse(text, opt); },
                                                  {.file = "part.ngc", .line = line, .column = column, .field = word, .message = words},
                                                  text);
    (void)e;
  };
  error_with("G1 X10 A10 C5", 1, 8, "A10", "B is missing");                   // the first angles: all three
  error_with("G91 G1 X10 A10 B0 C0", 1, 12, "A10", "must be absolute (G90)");  // ... absolute
  error_with("G1 X1 A0 B0 C0\nG1 X1 A90", 2, 1, "G1", "cannot turn in place");  // a rotation without a move
  error_with("G1 X0 A0 B0 C10", 1, 1, "G1", "cannot turn in place");           // from the start orientation
  error_with("A0 B0 C0", 1, 1, "A0", "no motion mode");
  error_with("G1 X1 A0 B0 C0\nG91 X1 A30000\nX1 A30000", 3, 4, "A30000", "beyond +-36000");
  error_with("G1 X1 A0 B0 C0 U1", 1, 16, "U1", "axis U is not supported");
  error_with("G1 X1 A0 A1 B0 C0", 1, 10, "A1", "given twice");
  // the mapping must be a permutation
  EXPECT_THROW((void)parse("G1 X1", with_angles(ToolAngle::kRoll, ToolAngle::kRoll, ToolAngle::kYaw)), InputError);
}

// A G-code program with tool angles and the same program written as YAML moves.
struct TwinPrograms {
  std::string gcode;  // the .ngc text
  std::string moves;  // the YAML list of moves (indented for `program:`)
};

// A value read back as the same double, in fixed notation: G-code numbers have no exponent, so
// %.17g's 1.2e-05 (an angle or offset that changes by that much under G91) is no G-code word.
std::string exact(double v) {
  std::array<char, 400> text{};  // the longest fixed double within this test's range is far shorter
  const auto [end, error] = std::to_chars(text.data(), text.data() + text.size(), v, std::chars_format::fixed);
  if (error != std::errc()) throw std::runtime_error("exact: no room for the value");
  return std::string(text.data(), end);
}

// A random program of 2-8 lines and XY arcs (G2/G3 by I, J) in mm, with random tool angles on
// most moves; A, B, C name the angles by the permutation `abc` (0 roll, 1 pitch, 2 yaw). Each
// line is written under G90 or G91 at random (angles and X, Y, Z incremental under G91), and
// an angle the line does not change is left out half the time (modal).
TwinPrograms random_twins(std::mt19937_64& rng, const std::array<int, 3>& abc) {
  TwinPrograms out;
  out.gcode = "G21 G17 G90\n";  // the feed: defaults.velocity, as the YAML moves
  Vec3 p = Vec3::Zero();
  Vec3 rpy = Vec3::Zero();
  bool angles_set = false;
  bool incremental = false;
  const int n = 2 + static_cast<int>(test::uniform(rng, 0, 7));
  for (int k = 0; k < n; ++k) {
    // the geometry: a line, or an arc about a centre in the XY plane at the start's height
    const bool arc = test::uniform(rng, 0, 1) < 0.3;
    Vec3 end = Vec3::Zero();
    Vec3 centre = Vec3::Zero();
    const bool ccw = test::uniform(rng, 0, 1) < 0.5;
    if (arc) {
      const double radius = test::uniform(rng, 10, 60);
      const double a0 = test::uniform(rng, -3.1, 3.1);
      const double sweep = test::uniform(rng, 0.3, 2.5) * (ccw ? 1 : -1);
      centre = p - radius * Vec3(std::cos(a0), std::sin(a0), 0);
      end = centre + radius * Vec3(std::cos(a0 + sweep), std::sin(a0 + sweep), 0);
    } else {
      end = p + test::uniform(rng, 10, 80) * test::random_unit(rng);
    }
    // the angles: all three the first time, later some of them
    const bool set = (!angles_set && test::uniform(rng, 0, 1) < 0.7) || (angles_set && test::uniform(rng, 0, 1) < 0.8);
    Vec3 next = rpy;
    std::array<bool, 3> write{};
    if (set) {
      for (int i = 0; i < 3; ++i) {
        write[static_cast<std::size_t>(i)] = !angles_set || test::uniform(rng, 0, 1) < 0.5;
        if (write[static_cast<std::size_t>(i)]) next[i] = test::uniform(rng, -180, 180);
      }
      write[static_cast<std::size_t>(test::uniform(rng, 0, 3))] = true;  // at least one word
    }
    // G91 only once the angles are set (the first angles are absolute)
    const bool g91 = angles_set && test::uniform(rng, 0, 1) < 0.4;
    std::string line = g91 == incremental ? "" : (g91 ? "G91 " : "G90 ");
    incremental = g91;
    line += arc ? (ccw ? "G3" : "G2") : "G1";
    const Vec3 e = g91 ? Vec3(end - p) : end;
    line += " X" + exact(e.x()) + " Y" + exact(e.y()) + " Z" + exact(e.z());
    if (arc) line += " I" + exact(centre.x() - p.x()) + " J" + exact(centre.y() - p.y());
    const char letters[] = {'A', 'B', 'C'};
    for (std::size_t w = 0; w < 3; ++w) {
      const int angle = abc[w];
      if (!set || !write[static_cast<std::size_t>(angle)]) continue;
      line += std::string(" ") + letters[w] + exact(g91 ? next[angle] - rpy[angle] : next[angle]);
    }
    out.gcode += line + "\n";
    // the YAML move: the same end (and centre), the absolute angles
    out.moves += arc ? "    - arc: {end: [" + exact(end.x()) + ", " + exact(end.y()) + ", " + exact(end.z()) + "], center: [" +
                           exact(centre.x()) + ", " + exact(centre.y()) + ", " + exact(centre.z()) + "], direction: " +
                           (ccw ? "ccw" : "cw") + "}\n"
                     : "    - line: [" + exact(end.x()) + ", " + exact(end.y()) + ", " + exact(end.z()) + "]\n";
    if (set) {
      out.moves += "      orientation: {rpy_deg: [" + exact(next[0]) + ", " + exact(next[1]) + ", " + exact(next[2]) + "]}\n";
    }
    angles_set = angles_set || set;
    rpy = next;
    p = end;
  }
  return out;
}

// A scenario around `program` (the text after `program:`), placed by a turned frame.
std::string twin_scenario(const std::string& program) {
  return "name: twin\nunits: mm\nframe: {origin: [400, -50, 300], rpy_deg: [10, -20, 30]}\nrobot: {tool_rpy_deg: [170, 5, 0]}\n"
         "defaults: {velocity: 100, acceleration: 1000, jerk: 10000}\nprogram:\n" + program +
         "variants:\n  - {name: arc, transition: {method: arc, parameter: 2}}\n";
}

// Round trip: a G-code program whose A, B, C are mapped to tool angles loads as the same
// program as its YAML twin (geometry and every orientation target, in the base frame), and
// blends to the same path with the same orientation along it, over random programs, mappings
// and G90/G91 mixes.
TEST(Scenario, GcodeAnglesLoadAsTheSameProgramAsTheYamlMoves) {
  constexpr double kSamePoint = 1e-9;  // m: written with 17 digits, incremental sums round
  constexpr double kSameAngle = 1e-9;  // rad
  const char* names[] = {"roll", "pitch", "yaw"};
  const test::ScratchDir scratch("gcode_angles_test");
  const std::filesystem::path& dir = scratch.path();
  const int cases = test::property_cases(200);
  int oriented_moves = 0;
  for (int c = 0; c < cases; ++c) {
    const std::uint64_t seed = 0x6a0c0de + static_cast<std::uint64_t>(c);
    SCOPED_TRACE(test::seed_text(seed));
    auto rng = test::make_rng(seed);
    std::array<int, 3> abc = {0, 1, 2};
    std::shuffle(abc.begin(), abc.end(), rng);
    const TwinPrograms twins = random_twins(rng, abc);
    const std::filesystem::path file = dir / ("part_" + std::to_string(seed) + ".ngc");
    std::ofstream(file) << twins.gcode;
    const Scenario from_gcode = parse_yaml(twin_scenario("  gcode: \"" + file.string() + "\"\n  gcode_angles: {a: " + names[abc[0]] +
                                                    ", b: " + names[abc[1]] + ", c: " + names[abc[2]] + "}\n"));
    const Scenario from_yaml = parse_yaml(twin_scenario("  moves:\n" + twins.moves));
    std::filesystem::remove(file);
    const Program g = program_for(from_gcode, from_gcode.variants[0]);
    const Program y = program_for(from_yaml, from_yaml.variants[0]);
    ASSERT_EQ(g.moves.size(), y.moves.size()) << twins.gcode;
    EXPECT_LE(rotation_angle(g.start_orientation, y.start_orientation), kSameAngle);
    for (std::size_t k = 0; k < g.moves.size(); ++k) {
      for (const double f : {0.0, 0.37, 1.0}) {
        EXPECT_LE((point(g.moves[k].geometry, f * length(g.moves[k].geometry)) -
                   point(y.moves[k].geometry, f * length(y.moves[k].geometry))).norm(), kSamePoint)
            << "move " << k << "\n" << twins.gcode;
      }
      ASSERT_EQ(g.moves[k].orientation.has_value(), y.moves[k].orientation.has_value()) << "move " << k << "\n" << twins.gcode;
      if (!g.moves[k].orientation) continue;
      ++oriented_moves;
      EXPECT_LE(rotation_angle(*g.moves[k].orientation, *y.moves[k].orientation), kSameAngle) << "move " << k << "\n" << twins.gcode;
    }
    // the same blended path and orientation along it
    const Path pg = blend(g);
    const Path py = blend(y);
    ASSERT_NEAR(pg.length(), py.length(), kSamePoint);
    ASSERT_EQ(pg.oriented(), py.oriented());
    for (int i = 0; i <= 50; ++i) {
      const double s = pg.length() * i / 50;
      EXPECT_LE((pg.point(s) - py.point(s)).norm(), kSamePoint) << "s = " << s;
      EXPECT_LE(rotation_angle(pg.orientation(s), py.orientation(s)), kSameAngle) << "s = " << s;
    }
  }
  EXPECT_GT(oriented_moves, cases);
}

// The shipped G-code torch seam is the YAML torch seam: the same blended path and the same torch
// orientation along it, for every variant of the G-code scenario (found by name in the YAML one).
TEST(Scenario, TheTorchSeamInGcodeIsTheTorchSeam) {
  const Scenario yaml = load_scenario(test::source_path("scenarios/torch_seam.yaml"));
  const Scenario gcode = load_scenario(test::source_path("scenarios/torch_seam_gcode.yaml"));
  EXPECT_NEAR(gcode.robot.tool.translation().z(), 0.12, 1e-15);
  for (const Variant& v : gcode.variants) {
    const Path pg = blend(program_for(gcode, v));
    const Path py = blend(program_for(yaml, find_variant(yaml, v.name)));
    ASSERT_NEAR(pg.length(), py.length(), 1e-9) << v.name;
    for (int i = 0; i <= 200; ++i) {
      const double s = pg.length() * i / 200;
      EXPECT_LE((pg.point(s) - py.point(s)).norm(), 1e-9) << v.name << " s = " << s;
      EXPECT_LE(rotation_angle(pg.orientation(s), py.orientation(s)), 1e-9) << v.name << " s = " << s;
    }
  }
}

// The mapping is checked where it is written: each of roll, pitch, yaw once, all three given,
// only with a G-code program; without it the program's A, B, C are refused at their place.
TEST(Scenario, GcodeAnglesMappingIsCheckedWhereItIsWritten) {
  const test::ScratchDir scratch("gcode_angles_test");
  const std::filesystem::path& dir = scratch.path();
  const std::filesystem::path file = dir / "angles.ngc";
  std::ofstream(file) << "G21 G90 F600\nG1 X10 A180 B0 C0\nG1 Y10 C45\n";
  const std::string program = "  gcode: \"" + file.string() + "\"\n";
  const std::string mapped = twin_scenario(program + "  gcode_angles: {a: roll, b: pitch, c: yaw}\n");
  const Scenario sc = parse_yaml(mapped);
  ASSERT_EQ(sc.program.moves.size(), 2U);
  ASSERT_TRUE(sc.program.moves[1].orientation.has_value());
  expect_scenario_error(replaced(mapped, "c: yaw", "c: pitch"), 8, "program.gcode_angles.c", "pitch is named by both b and c");
  expect_scenario_error(replaced(mapped, ", c: yaw", ""), 8, "program.gcode_angles.c", "missing required field");
  expect_scenario_error(replaced(mapped, "c: yaw", "c: spin"), 8, "program.gcode_angles.c", "unknown value 'spin'");
  // unmapped: the G-code file's own line and column
  test::expect_input_error([&] { (void)parse_yaml(twin_scenario(program)); },
                           {.file = file.string(), .line = 2, .column = 8, .field = "A180", .message = "program.gcode_angles"});
  // moves take their orientation directly
  expect_scenario_error(twin_scenario("  moves:\n    - line: [10, 0, 0]\n  gcode_angles: {a: roll, b: pitch, c: yaw}\n"), 9,
               "program.gcode_angles", "has no 'gcode'");
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace blendbench
