#include "blendbench/core/units.hpp"
#include "blendbench/io/gcode.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <numbers>
#include <sstream>

#include "blendbench/corner/blend.hpp"
#include "blendbench/geometry/arc_construction.hpp"
#include "blendbench/program/path.hpp"
#include "support/input_error.hpp"
#include "support/property.hpp"

namespace blendbench {
namespace {

constexpr double kTol = 1e-12;   // m: geometry derived by hand
constexpr double kInch = 0.0254; // m per inch
constexpr double kPi = std::numbers::pi;

GcodeOptions options() {
  GcodeOptions opt;
  opt.limits = {0.1, 2.0, 3.0, 50.0};
  return opt;
}

GcodeResult parse(const std::string& text, const GcodeOptions& opt = options()) {
  return parse_gcode(text, "part.ngc", opt);
}

// Parses text that must fail; checks the location and word, returns the message.
std::string expect_error(const std::string& text, int line, int column, const std::string& word) {
  return test::expect_input_error([&] { (void)parse(text); },
                                  {.file = "part.ngc", .line = line, .column = column, .field = word}, text)
      .detail();
}

const Arc& arc_of(const GcodeResult& r, std::size_t k) {
  const Arc* arc = std::get_if<Arc>(&r.program.moves.at(k).geometry);
  EXPECT_NE(arc, nullptr) << "move " << k << " is not an arc";
  static const Arc kNone{};
  return arc ? *arc : kNone;
}

const Line& line_of(const GcodeResult& r, std::size_t k) {
  const Line* line = std::get_if<Line>(&r.program.moves.at(k).geometry);
  EXPECT_NE(line, nullptr) << "move " << k << " is not a line";
  static const Line kNone{};
  return line ? *line : kNone;
}

Vec3 mm(double x, double y, double z) { return Vec3(x, y, z) * kMm; }
Vec3 end_of(const Primitive& p) { return point(p, length(p)); }
Vec3 mid_of(const Primitive& p) { return point(p, 0.5 * length(p)); }

bool has_note(const GcodeResult& r, const std::string& text) {
  return std::find(r.ignored.begin(), r.ignored.end(), text) != r.ignored.end();
}

std::string notes(const GcodeResult& r) {
  std::string out;
  for (const std::string& s : r.ignored) out += "  " + s + "\n";
  return out;
}

#define EXPECT_VEC_NEAR(a, b, tol) EXPECT_LE(((a) - (b)).norm(), tol) << "got " << (a).transpose() << " expected " << (b).transpose()

// seed 004 (Shahzadeh et al.) section 3, Listing 1, as the extracted text has it (Unicode minus, comments).
const std::string kListing1 =
    "G90\n"
    "F10000\n"
    "G2X\u221210Y10R10 ( red )\n"
    "G1Y50 (black)\n"
    "G2X0Y60R10 (blue)\n"
    "G2X0Y0R30.01 (green)\n";

void check_listing1(const GcodeResult& r) {
  ASSERT_EQ(r.program.moves.size(), 4u);
  EXPECT_VEC_NEAR(r.start, Vec3::Zero(), kTol);
  // red: O (0,0) -> A (-10,10), R10 clockwise, short arc: centre (0,10), a quarter turn
  const Arc& red = arc_of(r, 0);
  EXPECT_VEC_NEAR(red.center, mm(0, 10, 0), kTol);
  EXPECT_NEAR(red.radius, 10 * kMm, kTol);
  EXPECT_NEAR(red.sweep, kPi / 2, 1e-12);
  EXPECT_VEC_NEAR(red.u.cross(red.v), Vec3(0, 0, -1), kTol);  // clockwise seen from +Z
  EXPECT_VEC_NEAR(point(Primitive(red), 0), Vec3::Zero(), kTol);
  EXPECT_VEC_NEAR(end_of(red), mm(-10, 10, 0), kTol);
  EXPECT_VEC_NEAR(tangent(Primitive(red), 0), Vec3(-1, 0, 0), kTol);
  // black: A -> (-10,50), tangent to both arcs
  const Line& black = line_of(r, 1);
  EXPECT_VEC_NEAR(black.p0, mm(-10, 10, 0), kTol);
  EXPECT_VEC_NEAR(black.p1, mm(-10, 50, 0), kTol);
  // blue: B (-10,50) -> C (0,60), R10 clockwise: centre (0,50)
  const Arc& blue = arc_of(r, 2);
  EXPECT_VEC_NEAR(blue.center, mm(0, 50, 0), kTol);
  EXPECT_NEAR(blue.radius, 10 * kMm, kTol);
  EXPECT_NEAR(blue.sweep, kPi / 2, 1e-12);
  EXPECT_VEC_NEAR(end_of(blue), mm(0, 60, 0), kTol);
  // green: C (0,60) -> O, R30.01 clockwise, short arc: centre on y = 30 at
  // x = -sqrt(30.01^2 - 30^2), sweep 2 asin(30 / 30.01); it closes at the origin
  const Arc& green = arc_of(r, 3);
  const double cx = -std::sqrt(30.01 * 30.01 - 30.0 * 30.0);
  EXPECT_VEC_NEAR(green.center, mm(cx, 30, 0), kTol);
  EXPECT_NEAR(green.radius, 30.01 * kMm, kTol);
  EXPECT_NEAR(green.sweep, 2 * std::asin(30 / 30.01), 1e-12);
  EXPECT_LT(green.sweep, kPi);
  EXPECT_VEC_NEAR(green.u.cross(green.v), Vec3(0, 0, -1), kTol);
  EXPECT_VEC_NEAR(end_of(green), Vec3::Zero(), kTol);
  // seed 004: "there is a 1.48 degree angle between the two arcs" at C
  const double kink = angle_between(tangent(Primitive(blue), length(Primitive(blue))), tangent(Primitive(green), 0));
  EXPECT_NEAR(kink * 180 / kPi, std::atan(-cx / 30) * 180 / kPi, 1e-9);
  EXPECT_NEAR(kink * 180 / kPi, 1.48, 0.005);
  // F10000 mm/min on every move
  for (const Move& m : r.program.moves) EXPECT_NEAR(m.limits.velocity, 10000 * kMm / 60, 1e-15);
  EXPECT_NO_THROW(validate(r.program));
}

TEST(Gcode, Listing1Of004AsExtractedWithUnicodeMinus) {
  const GcodeResult r = parse(kListing1);
  check_listing1(r);
  EXPECT_TRUE(has_note(r, "line 3: Unicode minus sign (U+2212) read as '-'")) << notes(r);
  EXPECT_EQ(r.program.moves[0].name, "line 3 G2");
  EXPECT_EQ(r.program.moves[1].name, "line 4 G1");
  EXPECT_EQ(r.program.moves[0].where.line, 3);
  EXPECT_EQ(r.program.moves[0].where.column, 1);
  EXPECT_EQ(r.program.moves[1].where.column, 1);
}

TEST(Gcode, Listing1PartFileLoads) {
  std::ifstream in(test::source_path("scenarios/parts/listing1.ngc"));
  ASSERT_TRUE(in) << "scenarios/parts/listing1.ngc";
  std::stringstream text;
  text << in.rdbuf();
  const GcodeResult r = parse_gcode(text.str(), "listing1.ngc", options());
  check_listing1(r);
}

TEST(Gcode, BracketPartFileLoadsCleanly) {
  std::ifstream in(test::source_path("scenarios/parts/bracket.ngc"));
  ASSERT_TRUE(in) << "scenarios/parts/bracket.ngc";
  std::stringstream text;
  text << in.rdbuf();
  GcodeOptions opt = options();
  opt.tolerance_method = Method::kBiclothoid;
  const GcodeResult r = parse_gcode(text.str(), "bracket.ngc", opt);
  EXPECT_NO_THROW(validate(r.program));
  ASSERT_GE(r.program.moves.size(), 10u);
  // G64 P0.05 is in force on the contour: biclothoid with 0.05 mm deviation
  bool tolerance_seen = false;
  for (const Move& m : r.program.moves) {
    if (m.transition.method == Method::kBiclothoid) {
      EXPECT_NEAR(m.transition.parameter, 0.05 * kMm, 1e-15);
      tolerance_seen = true;
    }
  }
  EXPECT_TRUE(tolerance_seen);
  // the shop words are listed, the program ends at M30
  for (const char* word : {"T1", "M6", "S12000", "M3", "M8", "M9", "M5", "G40", "G94", "G54"}) {
    const bool found = std::any_of(r.ignored.begin(), r.ignored.end(),
                                   [&](const std::string& s) { return s.rfind(std::string(word) + " (line", 0) == 0; });
    EXPECT_TRUE(found) << word << "\n" << notes(r);
  }
  // helix down through the hole: three turns, 6.5 mm deep in total
  double helix_drop = 0;
  for (const Move& m : r.program.moves) {
    if (const Arc* a = std::get_if<Arc>(&m.geometry); a && a->rise != 0) helix_drop += end_of(m.geometry).z() - point(m.geometry, 0).z();
  }
  EXPECT_NEAR(helix_drop, -6.5 * kMm, 1e-12);
}

TEST(Gcode, ArcDirectionInEachPlaneIJ) {
  // G17: G2 clockwise seen from +Z. From (0,0) about (5,0): passes (5,5); G3 passes (5,-5).
  EXPECT_VEC_NEAR(mid_of(parse("G17 G2 X10 Y0 I5 J0").program.moves[0].geometry), mm(5, 5, 0), kTol);
  EXPECT_VEC_NEAR(mid_of(parse("G17 G3 X10 Y0 I5").program.moves[0].geometry), mm(5, -5, 0), kTol);
  // G18: plane (Z, X), G2 clockwise seen from +Y: from (0,0,0) about x = 5 passes z = -5
  EXPECT_VEC_NEAR(mid_of(parse("G18 G2 X10 I5").program.moves[0].geometry), mm(5, 0, -5), kTol);
  EXPECT_VEC_NEAR(mid_of(parse("G18 G3 X10 I5").program.moves[0].geometry), mm(5, 0, 5), kTol);
  // G19: plane (Y, Z), G2 clockwise seen from +X: from the origin about y = 5 passes z = +5
  EXPECT_VEC_NEAR(mid_of(parse("G19 G2 Y10 J5").program.moves[0].geometry), mm(0, 5, 5), kTol);
  EXPECT_VEC_NEAR(mid_of(parse("G19 G3 Y10 J5").program.moves[0].geometry), mm(0, 5, -5), kTol);
  // normal of rotation: G3 about +n, G2 about -n
  const GcodeResult r = parse("G18 G3 X10 I5\nG19 G2 Y10 J5");
  EXPECT_VEC_NEAR(arc_of(r, 0).u.cross(arc_of(r, 0).v), Vec3(0, 1, 0), kTol);
  EXPECT_VEC_NEAR(arc_of(r, 1).u.cross(arc_of(r, 1).v), Vec3(-1, 0, 0), kTol);
  EXPECT_NEAR(arc_of(r, 0).radius, 5 * kMm, kTol);
  EXPECT_NEAR(arc_of(r, 0).sweep, kPi, 1e-12);
}

TEST(Gcode, QuarterArcCentreRadiusSweep) {
  // from (0,0) about (0,5): G3 to (5,5) is a quarter turn; G2 to (5,5) three quarters
  const GcodeResult ccw = parse("G3 X5 Y5 J5");
  EXPECT_VEC_NEAR(arc_of(ccw, 0).center, mm(0, 5, 0), kTol);
  EXPECT_NEAR(arc_of(ccw, 0).sweep, kPi / 2, 1e-12);
  EXPECT_VEC_NEAR(arc_of(ccw, 0).u, Vec3(0, -1, 0), kTol);
  EXPECT_VEC_NEAR(arc_of(ccw, 0).v, Vec3(1, 0, 0), kTol);
  const GcodeResult cw = parse("G2 X5 Y5 J5");
  EXPECT_NEAR(arc_of(cw, 0).sweep, 3 * kPi / 2, 1e-12);
  EXPECT_VEC_NEAR(arc_of(cw, 0).v, Vec3(-1, 0, 0), kTol);
  EXPECT_VEC_NEAR(end_of(cw.program.moves[0].geometry), mm(5, 5, 0), kTol);
}

TEST(Gcode, RadiusFormatChoosesTheCentrePerRs274) {
  const double h = std::sqrt(75.0);  // centre offset from the chord's midpoint for R10, chord 10
  // G2 R+: short arc, centre right of the chord (chord along +X: right is -Y)
  GcodeResult r = parse("G2 X10 R10");
  EXPECT_VEC_NEAR(arc_of(r, 0).center, mm(5, -h, 0), kTol);
  EXPECT_NEAR(arc_of(r, 0).sweep, kPi / 3, 1e-12);
  // G2 R-: long arc, centre on the left
  r = parse("G2 X10 R-10");
  EXPECT_VEC_NEAR(arc_of(r, 0).center, mm(5, h, 0), kTol);
  EXPECT_NEAR(arc_of(r, 0).sweep, 2 * kPi - kPi / 3, 1e-12);
  // G3 R+: short arc, centre on the left; R-: long arc on the right
  r = parse("G3 X10 R10");
  EXPECT_VEC_NEAR(arc_of(r, 0).center, mm(5, h, 0), kTol);
  EXPECT_NEAR(arc_of(r, 0).sweep, kPi / 3, 1e-12);
  r = parse("G3 X10 R-10");
  EXPECT_VEC_NEAR(arc_of(r, 0).center, mm(5, -h, 0), kTol);
  EXPECT_NEAR(arc_of(r, 0).sweep, 5 * kPi / 3, 1e-12);
  // G18 (Z, X plane): chord along +X is along a2; G2 R+ centre "right" = +a1 = +Z
  r = parse("G18 G2 X10 R10");
  EXPECT_VEC_NEAR(arc_of(r, 0).center, mm(5, 0, h), kTol);
  EXPECT_VEC_NEAR(end_of(r.program.moves[0].geometry), mm(10, 0, 0), kTol);
  // G19 (Y, Z plane): chord along +Y is along a1; G3 R+ centre left = +a2 = +Z
  r = parse("G19 G3 Y10 R10");
  EXPECT_VEC_NEAR(arc_of(r, 0).center, mm(0, 5, h), kTol);
  EXPECT_NEAR(arc_of(r, 0).sweep, kPi / 3, 1e-12);
  // R equal to half the chord: a semicircle
  r = parse("G2 X10 R5");
  EXPECT_VEC_NEAR(arc_of(r, 0).center, mm(5, 0, 0), kTol);
  EXPECT_NEAR(arc_of(r, 0).sweep, kPi, 1e-12);
}

TEST(Gcode, RadiusFormatErrors) {
  // half the chord exceeds |R| by more than 0.00127 mm (LinuxCNC RADIUS_TOLERANCE_MM)
  std::string msg = expect_error("G2 X10 R4.998", 1, 8, "R4.998");
  EXPECT_NE(msg.find("radius too small"), std::string::npos) << msg;
  // within that tolerance: a semicircle on the chord
  const GcodeResult r = parse("G2 X10 R4.999");
  EXPECT_NEAR(arc_of(r, 0).radius, 5 * kMm, kTol);
  EXPECT_NEAR(arc_of(r, 0).sweep, kPi, 1e-12);
  // full circles cannot be R format
  msg = expect_error("G1 X1\nG2 X1 Y0 R5", 2, 10, "R5");
  EXPECT_NE(msg.find("full circle"), std::string::npos) << msg;
  // R and offsets together
  expect_error("G2 X10 R5 I5", 1, 11, "I5");
}

TEST(Gcode, FullCirclesAndTurns) {
  // offsets without an end point: a full circle back to the start
  GcodeResult r = parse("G2 I5");
  EXPECT_NEAR(arc_of(r, 0).sweep, 2 * kPi, 1e-15);
  EXPECT_VEC_NEAR(arc_of(r, 0).center, mm(5, 0, 0), kTol);
  EXPECT_VEC_NEAR(end_of(r.program.moves[0].geometry), Vec3::Zero(), kTol);
  // end = start written out, and P turns
  r = parse("G3 X0 Y0 I-3 J4 P3");
  EXPECT_NEAR(arc_of(r, 0).sweep, 6 * kPi, 1e-14);
  EXPECT_NEAR(arc_of(r, 0).radius, 5 * kMm, kTol);
  EXPECT_NEAR(length(r.program.moves[0].geometry), 3 * 2 * kPi * 5 * kMm, 1e-14);
  // P must be a positive integer
  expect_error("G2 I5 P1.5", 1, 7, "P1.5");
  expect_error("G2 I5 P0", 1, 7, "P0");
}

TEST(Gcode, HelixRiseAlongTheNormalAxis) {
  // G17 G3 quarter turn about (0,5) while Z goes to -2: rise along w = +Z is -2 mm
  GcodeResult r = parse("G17 G3 X5 Y5 Z-2 J5");
  EXPECT_NEAR(arc_of(r, 0).rise, -2 * kMm, kTol);
  EXPECT_VEC_NEAR(end_of(r.program.moves[0].geometry), mm(5, 5, -2), kTol);
  EXPECT_VEC_NEAR(mid_of(r.program.moves[0].geometry), mm(5 * std::sin(kPi / 4), 5 - 5 * std::cos(kPi / 4), -1), kTol);
  EXPECT_NEAR(length(r.program.moves[0].geometry), std::hypot(kPi / 2 * 5, 2) * kMm, kTol);
  // G2 reverses w, so the same drop is a positive rise
  r = parse("G17 G2 X-5 Y5 Z-2 J5");
  EXPECT_NEAR(arc_of(r, 0).rise, 2 * kMm, kTol);
  EXPECT_VEC_NEAR(end_of(r.program.moves[0].geometry), mm(-5, 5, -2), kTol);
  // G18: Y is the helix axis; G19: X
  r = parse("G18 G2 X10 Y4 I5");
  EXPECT_VEC_NEAR(mid_of(r.program.moves[0].geometry), mm(5, 2, -5), kTol);
  EXPECT_VEC_NEAR(end_of(r.program.moves[0].geometry), mm(10, 4, 0), kTol);
  r = parse("G19 G3 Y10 X-6 J5");
  EXPECT_VEC_NEAR(mid_of(r.program.moves[0].geometry), mm(-3, 5, -5), kTol);
  // a full-circle helix with turns
  r = parse("G3 Z-6 I5 P3");
  EXPECT_NEAR(arc_of(r, 0).sweep, 6 * kPi, 1e-14);
  EXPECT_VEC_NEAR(end_of(r.program.moves[0].geometry), mm(0, 0, -6), kTol);
  EXPECT_VEC_NEAR(point(r.program.moves[0].geometry, length(r.program.moves[0].geometry) / 3), mm(0, 0, -2), kTol);
}

// P turns are bounded (kMaxArcTurns): the work per arc is known before any is done.
TEST(Gcode, TurnsBeyondTheLimitAreRefusedNamingTheWordAndTheLimit) {
  const std::string limit = std::to_string(kMaxArcTurns);
  EXPECT_NEAR(arc_of(parse("G3 Z-6 I5 P" + limit), 0).sweep, 2 * kPi * kMaxArcTurns, 1e-9);
  for (const std::string& p : {std::to_string(kMaxArcTurns + 1), std::string("10000"), std::string("100000000000000000000"), std::string("2.5")}) {
    const std::string message = expect_error("G21\nG3 Z-6 I5 P" + p, 2, 11, "P" + p);
    EXPECT_NE(message.find("from 1 to " + limit + " (the limit bounds the work per arc)"), std::string::npos) << message;
  }
}

TEST(Gcode, IncrementalAndAbsoluteDistanceModes) {
  GcodeResult r = parse("G91 G1 X10\nY10\nX-10 Y-10 Z5\nG90 X1 Y2 Z3");
  ASSERT_EQ(r.program.moves.size(), 4u);
  EXPECT_VEC_NEAR(line_of(r, 0).p1, mm(10, 0, 0), kTol);
  EXPECT_VEC_NEAR(line_of(r, 1).p1, mm(10, 10, 0), kTol);
  EXPECT_VEC_NEAR(line_of(r, 2).p1, mm(0, 0, 5), kTol);
  EXPECT_VEC_NEAR(line_of(r, 3).p1, mm(1, 2, 3), kTol);
  // G91 arcs: the end is relative; I/J are relative to the start in G91.1 (default)
  r = parse("G0 X20 Y10\nG91 G2 X10 Y0 I5\nG3 X-10 I-5");
  EXPECT_VEC_NEAR(arc_of(r, 1).center, mm(25, 10, 0), kTol);
  EXPECT_VEC_NEAR(end_of(r.program.moves[1].geometry), mm(30, 10, 0), kTol);
  EXPECT_VEC_NEAR(arc_of(r, 2).center, mm(25, 10, 0), kTol);
  EXPECT_VEC_NEAR(end_of(r.program.moves[2].geometry), mm(20, 10, 0), kTol);
  // G90.1: I/J are absolute and both are required
  r = parse("G0 X10\nG90.1 G3 X-10 Y0 I0 J0");
  EXPECT_VEC_NEAR(arc_of(r, 1).center, Vec3::Zero(), kTol);
  EXPECT_VEC_NEAR(mid_of(r.program.moves[1].geometry), mm(0, 10, 0), kTol);
  expect_error("G0 X10\nG90.1 G3 X-10 Y0 I0", 2, 18, "I0");
  // G91.1 restores relative centres
  r = parse("G0 X10\nG90.1\nG91.1 G3 X-10 Y0 I-10");
  EXPECT_VEC_NEAR(arc_of(r, 1).center, Vec3::Zero(), kTol);
}

TEST(Gcode, InchesAndFeed) {
  GcodeOptions opt = options();
  opt.rapid_velocity = 0.5;
  const GcodeResult r = parse("G1 X1\nG20 F10 X1\nG0 Y1\nG21 G1 Y0\nF600 X0", opt);
  ASSERT_EQ(r.program.moves.size(), 5u);
  EXPECT_VEC_NEAR(line_of(r, 0).p1, mm(1, 0, 0), kTol);
  EXPECT_NEAR(r.program.moves[0].limits.velocity, 0.1, 0);  // options until the first F
  EXPECT_VEC_NEAR(line_of(r, 1).p1, Vec3(kInch, 0, 0), kTol);
  EXPECT_NEAR(r.program.moves[1].limits.velocity, 10 * kInch / 60, 1e-15);
  EXPECT_VEC_NEAR(line_of(r, 2).p1, Vec3(kInch, kInch, 0), kTol);
  EXPECT_NEAR(r.program.moves[2].limits.velocity, 0.5, 0);  // G0 at the rapid velocity
  EXPECT_VEC_NEAR(line_of(r, 3).p1, Vec3(kInch, 0, 0), kTol);
  EXPECT_NEAR(r.program.moves[3].limits.velocity, 10 * kInch / 60, 1e-15);  // feed kept in m/s
  EXPECT_NEAR(r.program.moves[4].limits.velocity, 600 * kMm / 60, 1e-15);
  for (const Move& m : r.program.moves) {
    EXPECT_EQ(m.limits.acceleration, 2.0);
    EXPECT_EQ(m.limits.deceleration, 3.0);
    EXPECT_EQ(m.limits.jerk, 50.0);
    EXPECT_EQ(m.buffer, BufferMode::kBlendingLow);
  }
  // G0 without rapid_velocity: limits.velocity
  EXPECT_NEAR(parse("F100 G0 X5").program.moves[0].limits.velocity, 0.1, 0);
  // inch arcs
  const GcodeResult a = parse("G20 G2 X1 Y0 I0.5");
  EXPECT_NEAR(arc_of(a, 0).radius, 0.5 * kInch, kTol);
  // F0 is a setting (LinuxCNC's default_modal_state sets it); a feed move at it is refused at
  // its motion word, rapids are not slowed by it
  const std::string zero = expect_error("G1 X1 F0", 1, 1, "G1");
  EXPECT_NE(zero.find("feed rate 0"), std::string::npos) << zero;
  expect_error("F0\nG0 X1\nG2 X2 R1", 3, 1, "G2");
  expect_error("G1 X1 F10\nF0\nY1", 3, 1, "G1");
  EXPECT_EQ(parse("F0\nG0 X1\nF10 G1 X2").program.moves.size(), 2u);
  expect_error("G1 X1 F-5", 1, 7, "F-5");
}

TEST(Gcode, PathControlModes) {
  GcodeOptions opt = options();
  opt.blending = {Method::kBezier, 0.002, 0, 0};
  opt.tolerance_method = Method::kBiclothoid;
  const GcodeResult r = parse(
      "G1 X1\n"          // start-up mode is G64 without P: options.blending
      "G61 X2\n"         // exact stop
      "G64 P0.05 X3\n"   // tolerance -> biclothoid 0.05 mm
      "G20 G64 P0.001 X1\n"  // inch tolerance
      "G64 X2\n"         // G64 without P: options.blending again
      "G61.1 X3\n"
      "G64 P0 X4\n"      // P0 = no P
      "G64 P0.1 Q0.02 X5\n",
      opt);
  ASSERT_EQ(r.program.moves.size(), 8u);
  const auto& m = r.program.moves;
  EXPECT_EQ(m[0].transition.method, Method::kBezier);
  EXPECT_EQ(m[0].transition.parameter, 0.002);
  EXPECT_EQ(m[1].transition.method, Method::kNone);
  EXPECT_EQ(m[2].transition.method, Method::kBiclothoid);
  EXPECT_NEAR(m[2].transition.parameter, 0.05 * kMm, 1e-15);
  EXPECT_EQ(m[3].transition.method, Method::kBiclothoid);
  EXPECT_NEAR(m[3].transition.parameter, 0.001 * kInch, 1e-15);
  EXPECT_EQ(m[4].transition.method, Method::kBezier);
  EXPECT_EQ(m[5].transition.method, Method::kNone);
  EXPECT_EQ(m[6].transition.method, Method::kBezier);
  EXPECT_NEAR(m[7].transition.parameter, 0.1 * kInch, 1e-15);
  // Q: the naive CAM tolerance, in the units in force (inch here), on the moves that follow
  EXPECT_NEAR(m[7].transition.merge_tolerance, 0.02 * kInch, 1e-15);
  EXPECT_EQ(m[6].transition.merge_tolerance, 0.0);
  // the arc mapping: G64 P is the corner distance
  opt.tolerance_method = Method::kArc;
  const GcodeResult a = parse("G64 P0.2 G1 X1\nY1", opt);
  EXPECT_EQ(a.program.moves[0].transition.method, Method::kArc);
  EXPECT_NEAR(a.program.moves[0].transition.parameter, 0.2 * kMm, 1e-15);
  expect_error("G64 P-1", 1, 5, "P-1");
  expect_error("G1 X1 Q1", 1, 7, "Q1");
  expect_error("G64 P0.1 Q-1", 1, 10, "Q-1");
}

TEST(Gcode, DwellPauseAndToolChangeStopTheMoveBefore) {
  GcodeOptions opt = options();
  opt.blending = {Method::kArc, 0.001, 0, 0};
  const GcodeResult r = parse(
      "G1 X1\n"
      "G4 P0.5\n"
      "X2\n"
      "X3 M0\n"
      "X4\n"
      "T2 M6\n"
      "X5 M1\n"
      "X6\n",
      opt);
  ASSERT_EQ(r.program.moves.size(), 6u);
  const auto& m = r.program.moves;
  EXPECT_EQ(m[0].transition.method, Method::kNone);  // dwell after it
  EXPECT_EQ(m[1].transition.method, Method::kArc);
  EXPECT_EQ(m[2].transition.method, Method::kNone);  // M0 after X3 on its line
  EXPECT_EQ(m[3].transition.method, Method::kNone);  // M6 before the next move
  EXPECT_EQ(m[4].transition.method, Method::kNone);  // M1
  EXPECT_EQ(m[5].transition.method, Method::kArc);
  EXPECT_TRUE(has_note(r, "G4 P0.5 (line 2): dwell treated as an exact stop")) << notes(r);
  EXPECT_TRUE(has_note(r, "M0 (line 4): program pause treated as an exact stop")) << notes(r);
  EXPECT_TRUE(has_note(r, "M6 (line 6): tool change treated as an exact stop")) << notes(r);
  EXPECT_TRUE(has_note(r, "T2 (line 6)")) << notes(r);
  expect_error("G1 X1\nG4", 2, 1, "G4");
  expect_error("G4 P-1", 1, 4, "P-1");
}

TEST(Gcode, IgnoredWordsAreListed) {
  const GcodeResult r = parse(
      "G17 G21 G40 G49 G54 G80 G90 G94\n"
      "T1 M6\n"
      "S1000 M3\n"
      "M8 G1 X10 F100\n"
      "H1 D1 M5 M9\n"
      "G54 X20\n");
  EXPECT_EQ(r.program.moves.size(), 2u);
  for (const char* note : {"G40 (line 1)", "G94 (line 1)", "T1 (line 2)",
                           "S1000 (line 3)", "M3 (line 3)", "M8 (line 4)", "H1 (line 5)", "D1 (line 5)",
                           "M5 (line 5)", "M9 (line 5)"}) {
    EXPECT_TRUE(has_note(r, note)) << note << "\n" << notes(r);
  }
  // a coordinate system whose offsets the program never set has zero offsets here (a machine's
  // own are not known): noted
  EXPECT_TRUE(has_note(r, "G54 (line 1): its offsets are zero (none set by the program with G10 or parameters)")) << notes(r);
  const GcodeResult more = parse("M4 M7 G59.3 G1 X1\nG59.3 X2");
  for (const char* note : {"M4 (line 1)", "M7 (line 1)"}) {
    EXPECT_TRUE(has_note(more, note)) << note << "\n" << notes(more);
  }
  EXPECT_EQ(parse("G55\nG54 G1 X1").program.moves.size(), 1u);
}

TEST(Gcode, SpindleModesOverridesAndRetractModesAreAcceptedAndNoted) {
  // G96 (constant surface speed, D its speed cap) and G97 set the spindle speed; M48-M53 switch
  // overrides (M50-M53 take P); G98/G99 choose where canned cycles retract: none moves the tool
  const GcodeResult r = parse("G96 D2000 S100\nG97 S500\nG98\nG99\nM48\nM49\nM50 P0\nM51\nM52 P1\nM53 P1\nG1 X1 F10\n");
  ASSERT_EQ(r.program.moves.size(), 1u);
  EXPECT_LE((end_of(r.program.moves[0].geometry) - mm(1, 0, 0)).norm(), kTol);
  for (const char* note : {"G96 (line 1)", "G97 (line 2)", "M48 (line 5)", "M53 (line 10)"}) {
    EXPECT_TRUE(has_note(r, note)) << note << "\n" << notes(r);
  }
  expect_error("G96 G97", 1, 5, "G97");
  expect_error("G98 G99", 1, 5, "G99");
  expect_error("M48 M49", 1, 5, "M49");
  expect_error("M48 P1", 1, 5, "P1");  // M48 takes no P
  expect_error("M50 G4 P2", 1, 8, "P2");  // one P, two users
}

TEST(Gcode, G80BesideAnotherMotionCodeIsIgnored) {
  // LinuxCNC's read_g: "G80 on the same line as one other g_code with the same mode ... is
  // simply ignored" (the CAM preamble "G90 G17 G40 G80 G00 G20")
  for (const char* line : {"G80 G0 X1", "G0 G80 X1", "G90 G17 G40 G80 G00 G20 X1"}) {
    const GcodeResult r = parse(line);
    ASSERT_EQ(r.program.moves.size(), 1u) << line;
    EXPECT_LE((end_of(r.program.moves[0].geometry) - mm(1, 0, 0) * (std::string(line).find("G20") != std::string::npos ? 25.4 : 1)).norm(), kTol) << line;
  }
  EXPECT_EQ(parse("G1 X1 F10\nG80 G1 X2").program.moves.size(), 2u);
  // two motion codes other than G80 stay an error, as does G80 with axis words alone
  expect_error("G0 G1 X1", 1, 4, "G1");
  expect_error("G80 X2", 1, 5, "X2");
}

TEST(Gcode, StartPositionFromOptions) {
  GcodeOptions opt = options();
  opt.start = Vec3(0.1, 0.2, 0.3);
  const GcodeResult r = parse("G91 G1 X5\nG90 Y0", opt);
  EXPECT_VEC_NEAR(r.start, opt.start, 0.0);
  EXPECT_VEC_NEAR(line_of(r, 0).p0, opt.start, 0.0);
  EXPECT_VEC_NEAR(line_of(r, 0).p1, Vec3(0.105, 0.2, 0.3), kTol);
  EXPECT_VEC_NEAR(line_of(r, 1).p1, Vec3(0.105, 0, 0.3), kTol);
}

TEST(Gcode, CommentsLineNumbersCaseAndNumbers) {
  const GcodeResult r = parse(
      "(header comment with G41 inside)\n"
      "n10 g1 x.5 (inline) y-10. ; trailing G41 comment\n"
      "N20 X+3 y 1 2 . 5\n"
      "  \t\n"
      "N30G2X5Y12.5I1(no spaces)\n");
  ASSERT_EQ(r.program.moves.size(), 3u);
  EXPECT_VEC_NEAR(line_of(r, 0).p1, mm(0.5, -10, 0), kTol);
  EXPECT_VEC_NEAR(line_of(r, 1).p1, mm(3, 12.5, 0), kTol);
  EXPECT_EQ(r.program.moves[0].name, "N10 G1");
  EXPECT_EQ(r.program.moves[0].where.line, 2);
  EXPECT_EQ(r.program.moves[0].where.column, 5);
  EXPECT_EQ(r.program.moves[1].name, "N20 G1");
  EXPECT_EQ(r.program.moves[1].where.column, 5);  // modal motion: located at the first axis word
  EXPECT_EQ(r.program.moves[2].name, "N30 G2");
  EXPECT_EQ(r.program.moves[2].where.column, 4);
  EXPECT_EQ(r.program.moves[2].where.file, "part.ngc");
  EXPECT_NEAR(arc_of(r, 2).radius, 1 * kMm, kTol);
  // Windows line ends and a byte order mark
  const GcodeResult w = parse("\xEF\xBB\xBFG1 X1\r\nY1\r\n");
  ASSERT_EQ(w.program.moves.size(), 2u);
  EXPECT_EQ(w.program.moves[0].where.column, 1);
}

TEST(Gcode, BlockDeleteAndTapeMarkers) {
  const GcodeResult r = parse(
      "%\n"
      "G1 X1\n"
      "/G1 X5 Y5\n"
      "  / G41 D1\n"
      "X2\n"
      "%\n"
      "G41 this is never read\n"
      "X9\n");
  ASSERT_EQ(r.program.moves.size(), 2u);
  EXPECT_VEC_NEAR(line_of(r, 1).p0, mm(1, 0, 0), kTol);
  EXPECT_VEC_NEAR(line_of(r, 1).p1, mm(2, 0, 0), kTol);
  EXPECT_TRUE(has_note(r, "line 3: block delete '/', line skipped")) << notes(r);
  EXPECT_TRUE(has_note(r, "line 4: block delete '/', line skipped")) << notes(r);
  EXPECT_TRUE(has_note(r, "lines 7-8 after the closing % (line 6) not read")) << notes(r);
  expect_error("G1 X1 / Y2", 1, 7, "/");
  expect_error("G1 X1 %", 1, 7, "%");
}

TEST(Gcode, ProgramEndStopsReading) {
  const GcodeResult r = parse("G1 X1\nX2 M2\n\nG41 X5\n#1 = 2\n");
  ASSERT_EQ(r.program.moves.size(), 2u);
  EXPECT_TRUE(has_note(r, "lines 4-5 after M2 (line 2) not read")) << notes(r);
  const GcodeResult r30 = parse("G1 X1\nM30\nX3");
  EXPECT_EQ(r30.program.moves.size(), 1u);
  EXPECT_TRUE(has_note(r30, "line 3 after M30 (line 2) not read")) << notes(r30);
}

TEST(Gcode, ZeroLengthMovesAreDropped) {
  const GcodeResult r = parse("G1 X0 Y0\nX5\nN40 G1 X5\nG91 X0.0000000000001\nG90 G0 Z0\nG1 Y5");
  ASSERT_EQ(r.program.moves.size(), 2u);
  EXPECT_TRUE(has_note(r, "line 1 G1: zero-length move dropped")) << notes(r);
  EXPECT_TRUE(has_note(r, "N40 G1: zero-length move dropped")) << notes(r);
  EXPECT_TRUE(has_note(r, "line 4 G1: zero-length move dropped")) << notes(r);
  EXPECT_TRUE(has_note(r, "line 5 G0: zero-length move dropped")) << notes(r);
  // the path stays joined: the next move starts where the last kept one ended
  EXPECT_VEC_NEAR(line_of(r, 1).p0, mm(5, 0, 0), 0.0);
  EXPECT_NO_THROW(validate(r.program));
  // a very short move is kept
  const GcodeResult s = parse("G1 X0.00001\nX5");
  EXPECT_EQ(s.program.moves.size(), 2u);
  // nothing but zero-length moves: no program
  test::expect_input_error([] { (void)parse("G1 X0\n"); }, {.file = "part.ngc", .message = "no moves"});
}

TEST(Gcode, UnsupportedWordsStopWithLineColumnAndWord) {
  struct Case {
    std::string text;
    int line;
    int column;
    std::string word;
  };
  const std::vector<Case> cases = {
      {"G1 X1\nG41 D1 X2", 2, 1, "G41"},       // cutter compensation
      {"G42.1 D1", 1, 1, "G42.1"},
      {"G81 X1 Y1 Z-1", 1, 1, "G81"},          // canned cycles: without R
      {"G83 Z-1 R1", 1, 1, "G83"},             // without Q
      {"G73 Z-1 Q1", 1, 1, "G73"},             // without R
      {"G82 Z-1 R1", 1, 1, "G82"},             // without P
      {"G81 Z1 R0", 1, 1, "G81"},              // R below the bottom
      {"G81 X1 Z-1 R1 L0", 1, 15, "L0"},       // zero repeats
      {"G84 Z-1 R1 F10", 1, 1, "G84"},         // tapping without the spindle turning
      {"M4 S100 G84 Z-1 R1 F10", 1, 9, "G84"}, // or turning counter-clockwise
      {"G76 P1", 1, 1, "G76"},                 // lathe threading cycle
      {"G87 X1 Z-1 R1 I1 J1 K1", 1, 1, "G87"}, // back boring
      {"G88 Z-1 R1 P1", 1, 1, "G88"},          // manual retract
      {"G33 Z-1 K1", 1, 1, "G33"},             // spindle-synchronised, the spindle not turning
      {"M3 S100 G33 Z-1", 1, 9, "G33"},        // without K
      {"G5 X1 I1 J1 P1 Q1", 1, 1, "G5"},       // splines
      {"G5.1 X1 I1 J1", 1, 1, "G5.1"},
      {"G5.2 X1 Y1 P1", 1, 1, "G5.2"},
      {"G92", 1, 1, "G92"},                    // offsets without axis words
      {"G1 G92 X1", 1, 1, "G1"},               // axis words of G92 and of a motion
      {"G53 G2 X0 I1", 1, 1, "G53"},           // G53 with an arc
      {"G91 G53 G0 X0", 1, 5, "G53"},          // G53 incremental
      {"G10 L2 X0", 1, 1, "G10"},              // G10 without P
      {"G10 P1 X0", 1, 1, "G10"},              // G10 without L
      {"G10 L3 P1 X0", 1, 5, "L3"},            // G10 L3
      {"G10 L2 P10 X0", 1, 8, "P10"},          // no such coordinate system
      {"G43.1", 1, 1, "G43.1"},                // dynamic offset without axes
      {"G1 X1 L2", 1, 7, "L2"},                // L with no G10
      {"G93 G1 X1 F2", 1, 1, "G93"},
      {"G17.1", 1, 1, "G17.1"},
      {"G999", 1, 1, "G999"},
      {"G1.5 X1", 1, 1, "G1.5"},
      {"o100 sub", 1, 1, "o100"},              // an O-word structure that is not closed
      {"o100 call", 1, 1, "o100"},             // a subroutine not in the file
      {"#1", 1, 1, "#1"},                      // a parameter not assigned
      {"G1 X#<a>", 1, 5, "#<a>"},              // a named parameter never set
      {"G1 X[1+2", 1, 5, "[1+2"},              // an expression not closed
      {"G1 X1 [2]", 1, 7, "["},                // an expression that is no word's value
      {"G1 A10", 1, 4, "A10"},                 // other axes
      {"G1 X1 B2", 1, 7, "B2"},
      {"G1 C2", 1, 4, "C2"},
      {"G1 U2", 1, 4, "U2"},
      {"G1 V2", 1, 4, "V2"},
      {"G1 W2", 1, 4, "W2"},
      {"G1 E2", 1, 4, "E2"},                   // unknown letters
      {"M98 P100", 1, 1, "M98"},
      {"M60", 1, 1, "M60"},
      {"M123456789012345678901", 1, 1, "M123456789012345678901"},
      {"M3.5", 1, 1, "M3.5"},
      {"G1 G2 X1 I1", 1, 4, "G2"},             // two motion words
      {"G90 G91 X1", 1, 5, "G91"},
      {"M3 M4", 1, 4, "M4"},
      {"G1 X1 X2", 1, 7, "X2"},                // a word twice
      {"G17 G2 X10 I5 K1", 1, 15, "K1"},       // offsets outside the plane
      {"G18 G2 X10 I5 J1", 1, 15, "J1"},
      {"G19 G2 Y10 J5 I1", 1, 15, "I1"},
      {"G2 X10 Y0", 1, 1, "G2"},               // arc with neither R nor offsets
      {"X1", 1, 1, "X1"},                      // axis words with no motion mode (start-up G80)
      {"G1 X1\nG80 X2", 2, 5, "X2"},
      {"G1 X1 I2", 1, 7, "I2"},                // arc words with no arc
      {"G0 X1 R2", 1, 7, "R2"},
      {"G1 X1 P2", 1, 7, "P2"},                // P with no user
      {"G64 P0.1 G4", 1, 5, "P0.1"},           // P with two users
      {"G1 X1 (open comment", 1, 7, "("},
      {"G1 X1 (a (nested) one)", 1, 10, "("},
      {"G1 X", 1, 4, "X"},
      {"G1 X-", 1, 4, "X-"},
      {"G1 X1.2.3", 1, 8, "X1.2."},
      {"G1 X1 N10", 1, 7, "N10"},
      {"G1 X1 @", 1, 7, "@"},
      {"G1 X1 \u00b5", 1, 7, "\u00b5"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    expect_error(c.text, c.line, c.column, c.word);
  }
}

TEST(Gcode, InvalidOptionsAreInputErrors) {
  GcodeOptions opt = options();
  opt.limits.jerk = 0;
  EXPECT_THROW(parse("G1 X1", opt), InputError);
  opt = options();
  opt.rapid_velocity = -1;
  EXPECT_THROW(parse("G1 X1", opt), InputError);
}

// LinuxCNC's acceptance of a centre-format arc whose end point is off the circle through its
// start (interp_arc.cc, arc_data_ijk, and its G-code manual's rule): refused when |r1 - r2|
// exceeds 100 times the absolute tolerance 0.02 sqrt(2) mm (0.002 sqrt(2) in), or exceeds it
// with |r1 - r2| / max(r1, r2) beyond 0.1 % as well. From the origin about (r, 0), G2 to
// (r, y) is a quarter turn with r1 = r and r2 = y.
TEST(Gcode, ArcRadiusToleranceIsLinuxCncs) {
  // within the absolute tolerance (0.028284 mm) any relative error passes: 0.0282 mm on 10 mm is 0.28 %
  EXPECT_NO_THROW(parse("G2 X10 Y10.0282 I10"));
  // beyond it with more than 0.1 %: refused, both radii and the rule in the message
  const std::string msg = expect_error("N7 G2 X10 Y10.0284 I10", 1, 4, "G2");
  EXPECT_NE(msg.find("r1 = 10 mm, r2 = 10.0284 mm"), std::string::npos) << msg;
  EXPECT_NE(msg.find("LinuxCNC allows 2.828427125 mm, or 0.02828427125 mm beyond 0.1%"), std::string::npos) << msg;
  // beyond it within 0.1 %: passes up to 100 times the tolerance (2.828 mm: 2.8 mm on 5 m is 0.056 %)
  EXPECT_NO_THROW(parse("G2 X100 Y100.05 I100"));
  EXPECT_NO_THROW(parse("G2 X5000 Y5002.8 I5000"));
  expect_error("G2 X5000 Y5002.9 I5000", 1, 1, "G2");
  // the same in inches (0.0028284 in, 0.28284 in)
  EXPECT_NO_THROW(parse("G20 G2 X1 Y1.0028 I1"));
  expect_error("G20 G2 X1 Y1.0029 I1", 1, 5, "G2");
  EXPECT_NO_THROW(parse("G20 G2 X500 Y500.28 I500"));
  expect_error("G20 G2 X500 Y500.29 I500", 1, 5, "G2");
  // zero radius
  expect_error("G2 X0.001 I0.0001", 1, 1, "G2");
  // an arc smaller than the tolerance itself is an arc (LinuxCNC's spiral_tight_circular ends
  // with R0.002 in, 0.05 mm, below the 0.072 mm tolerance)
  const GcodeResult tiny = parse("G20 G0 X0.004\nG2 X0 R0.002 F10\nG3 X0.004 I0.002");
  ASSERT_EQ(tiny.program.moves.size(), 3u);
  EXPECT_NEAR(arc_of(tiny, 1).radius, 0.002 * kInch, kTol);
  EXPECT_NEAR(arc_of(tiny, 2).radius, 0.002 * kInch, kTol);
  EXPECT_NEAR(arc_of(tiny, 1).sweep, kPi, 1e-9);
}

// LinuxCNC's spiral for an arc in the XY plane, written here from its definition (posemath:
// radius linear in the angle about the programmed centre, height likewise) as the reference:
// p(t) = c + (r1 + (r2 - r1) t) (cos(a0 + sweep t), sin(a0 + sweep t)) + rise t z, t in [0, 1],
// sweep signed (negative clockwise).
struct LinuxCncSpiral {
  Vec3 c;
  double a0 = 0;
  double sweep = 0;
  double r1 = 0;
  double r2 = 0;
  double rise = 0;
  [[nodiscard]] Vec3 at(double t) const {
    const double a = a0 + sweep * t;
    const double r = r1 + (r2 - r1) * t;
    return c + Vec3(r * std::cos(a), r * std::sin(a), rise * t);
  }
};

// The Hausdorff distance between the moves of a program and the spiral, by dense samples of
// both, each sample's nearest point refined by golden-section search.
double distance_to_spiral(const GcodeResult& r, const LinuxCncSpiral& spiral) {
  constexpr int kDense = 3000;
  std::vector<Vec3> ref(kDense + 1);
  for (int k = 0; k <= kDense; ++k) ref[static_cast<std::size_t>(k)] = spiral.at(static_cast<double>(k) / kDense);
  const auto to_spiral = [&](const Vec3& q) {
    std::size_t best = 0;
    for (std::size_t k = 0; k < ref.size(); ++k) {
      if ((ref[k] - q).norm() < (ref[best] - q).norm()) best = k;
    }
    double lo = static_cast<double>(best == 0 ? 0 : best - 1) / kDense;
    double hi = static_cast<double>(std::min<std::size_t>(kDense, best + 1)) / kDense;
    const double g = (std::sqrt(5.0) - 1) / 2;
    for (int i = 0; i < 80; ++i) {
      const double a = hi - g * (hi - lo);
      const double b = lo + g * (hi - lo);
      if ((spiral.at(a) - q).norm() < (spiral.at(b) - q).norm()) {
        hi = b;
      } else {
        lo = a;
      }
    }
    return std::min((ref[best] - q).norm(), (spiral.at(0.5 * (lo + hi)) - q).norm());
  };
  std::vector<Vec3> path;
  for (const Move& m : r.program.moves) {
    for (int k = 0; k <= 200; ++k) path.push_back(point(m.geometry, length(m.geometry) * k / 200));
  }
  double worst = 0;
  for (const Vec3& q : path) worst = std::max(worst, to_spiral(q));
  double spacing = 0;
  for (const Move& m : r.program.moves) spacing = std::max(spacing, 0.5 * length(m.geometry) / 200);
  for (int k = 0; k <= 600; ++k) {
    const Vec3 p = spiral.at(k / 600.0);
    double d = std::numeric_limits<double>::infinity();
    for (const Vec3& q : path) d = std::min(d, (q - p).norm());
    worst = std::max(worst, d - spacing);
  }
  return worst;
}

// The moves of one programmed arc are continuous in position and tangent.
void expect_tangent_chain(const GcodeResult& r) {
  for (std::size_t k = 0; k + 1 < r.program.moves.size(); ++k) {
    const Primitive& a = r.program.moves[k].geometry;
    const Primitive& b = r.program.moves[k + 1].geometry;
    EXPECT_LE((end_of(a) - point(b, 0)).norm(), 1e-15) << "joint " << k;
    EXPECT_LE(angle_between(tangent(a, length(a)), tangent(b, 0)), kG1Angle) << "joint " << k;
  }
}

// Within LinuxCNC's tolerance the path is its spiral's within GcodeOptions::spiral_tolerance (1
// micrometre): one circle where that is close enough, else tangent arcs, ending exactly at the
// programmed end point; measured against the spiral written from its definition.
TEST(Gcode, ArcEndPointOffTheCircleFollowsLinuxCncsSpiral) {
  constexpr double kTolerance = kSpiralTolerance * (1 + 1e-6);
  const double half_pi = kPi / 2;
  // three quarters of a turn of 100 mm growing by 0.0282 mm: no circle through both ends comes
  // within a micrometre, tangent arcs do
  const GcodeResult three = parse("G2 X100 Y-100.0282 I100");
  ASSERT_GT(three.program.moves.size(), 1u);
  EXPECT_VEC_NEAR(end_of(three.program.moves.back().geometry), mm(100, -100.0282, 0), kTol);
  EXPECT_LE(distance_to_spiral(three, {mm(100, 0, 0), kPi, -3 * half_pi, 100 * kMm, 100.0282 * kMm, 0}), kTolerance);
  expect_tangent_chain(three);
  for (const Move& m : three.program.moves) EXPECT_EQ(m.name, "line 1 G2");
  ASSERT_EQ(three.ignored.size(), 1u);
  EXPECT_EQ(three.ignored[0].rfind("line 1 G2: end point 0.0282 mm off the circle: LinuxCNC's spiral followed by " +
                                       std::to_string(three.program.moves.size()) + " tangent arcs within ", 0), 0u)
      << three.ignored[0];
  // a quarter turn of it: the circle through both ends stays within 0.6 um, one arc
  const GcodeResult quarter = parse("G2 X100 Y100.0282 I100");
  ASSERT_EQ(quarter.program.moves.size(), 1u);
  EXPECT_LE(distance_to_spiral(quarter, {mm(100, 0, 0), kPi, -half_pi, 100 * kMm, 100.0282 * kMm, 0}), kTolerance);
  // nearly a full turn counter-clockwise, 0.025 mm off: no single circle comes near, the chain does
  const GcodeResult turn = parse("G3 X-0.015 Y1 I50");
  const Eigen::Vector2d end_rel(-50.015, 1);
  EXPECT_LE(distance_to_spiral(turn, {mm(50, 0, 0), kPi, std::atan2(end_rel.y(), end_rel.x()) - kPi + 2 * kPi, 50 * kMm,
                                      end_rel.norm() * kMm, 0}),
            kTolerance);
  EXPECT_VEC_NEAR(end_of(turn.program.moves.back().geometry), mm(-0.015, 1, 0), kTol);
  expect_tangent_chain(turn);
  // a helix: the height linear in the angle, as LinuxCNC's
  const GcodeResult helix = parse("G2 X100 Y-100.0282 Z5 I100");
  EXPECT_LE(distance_to_spiral(helix, {mm(100, 0, 0), kPi, -3 * half_pi, 100 * kMm, 100.0282 * kMm, 5 * kMm}), kTolerance);
  EXPECT_VEC_NEAR(end_of(helix.program.moves.back().geometry), mm(100, -100.0282, 5), kTol);
  expect_tangent_chain(helix);
  // an end point off by rounding: one arc whose centre moved onto the bisector, noted
  const GcodeResult rounded = parse("G2 X10 Y10.0001 I10");
  ASSERT_EQ(rounded.program.moves.size(), 1u);
  EXPECT_LE(distance_to_spiral(rounded, {mm(10, 0, 0), kPi, -half_pi, 10 * kMm, 10.0001 * kMm, 0}), kTolerance);
  EXPECT_EQ(rounded.ignored.at(0).rfind("line 1 G2: end point 0.0001 mm off the circle; centre moved onto the bisector", 0), 0u)
      << rounded.ignored.at(0);
  // a tighter tolerance takes more arcs, and holds
  GcodeOptions tight = options();
  tight.spiral_tolerance = 1e-6 * kMm;
  const GcodeResult more = parse("G2 X100 Y-100.0282 I100", tight);
  EXPECT_GT(more.program.moves.size(), three.program.moves.size());
  EXPECT_LE(distance_to_spiral(more, {mm(100, 0, 0), kPi, -3 * half_pi, 100 * kMm, 100.0282 * kMm, 0}), 1.1e-6 * kMm);
  GcodeOptions bad = options();
  bad.spiral_tolerance = 0;
  EXPECT_THROW(parse("G1 X1", bad), InputError);
}

// Writes a random program of lines and arcs (all planes, both directions, helices, I/J and R
// formats, G90/G91, G20/G21) as G-code text; parsing it must give back the same geometry.
struct RandomProgram {
  std::string text;
  std::vector<Primitive> moves;
};

// G-code has no exponent notation: fixed point with 20 decimals (values here are below 1e4).
std::string num(double value) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.20f", value);
  return buf;
}

RandomProgram random_program(std::mt19937_64& rng) {
  RandomProgram out;
  std::ostringstream g;
  Vec3 pos = Vec3::Zero();
  const int n = 1 + static_cast<int>(test::uniform(rng, 0, 12));
  bool inch = false;
  bool incremental = false;
  const auto coord = [&](double metres) { return metres / (inch ? kInch : kMm); };
  for (int k = 0; k < n; ++k) {
    if (test::uniform(rng, 0, 1) < 0.3) {
      inch = !inch;
      g << (inch ? "G20\n" : "G21\n");
    }
    if (test::uniform(rng, 0, 1) < 0.3) {
      incremental = !incremental;
      g << (incremental ? "G91\n" : "G90\n");
    }
    const auto write_axes = [&](const Vec3& target, bool all) {
      const char* letters = "XYZ";
      for (int a = 0; a < 3; ++a) {
        if (!all && target[a] == pos[a]) continue;
        g << ' ' << letters[a] << num(coord(incremental ? target[a] - pos[a] : target[a]));
      }
    };
    if (test::uniform(rng, 0, 1) < 0.35) {
      const Vec3 target = pos + Vec3(test::uniform(rng, -0.1, 0.1), test::uniform(rng, -0.1, 0.1), test::uniform(rng, -0.05, 0.05));
      g << "G1";
      write_axes(target, true);
      g << '\n';
      out.moves.push_back(Line{pos, target});
      pos = target;
      continue;
    }
    // an arc: plane axes (a1, a2, n) as in RS274/NGC
    const int plane = static_cast<int>(test::uniform(rng, 0, 3));
    const Vec3 a1 = plane == 0 ? Vec3::UnitX() : plane == 1 ? Vec3::UnitZ() : Vec3::UnitY();
    const Vec3 a2 = plane == 0 ? Vec3::UnitY() : plane == 1 ? Vec3::UnitX() : Vec3::UnitZ();
    const Vec3 nrm = a1.cross(a2);
    const char off1 = plane == 0 ? 'I' : plane == 1 ? 'K' : 'J';
    const char off2 = plane == 0 ? 'J' : plane == 1 ? 'I' : 'K';
    const bool ccw = test::uniform(rng, 0, 1) < 0.5;
    const double sign = ccw ? 1 : -1;
    const double radius = test::uniform(rng, 0.001, 0.1);
    const double alpha = test::uniform(rng, 0, 2 * kPi);
    const Vec3 u = std::cos(alpha) * a1 + std::sin(alpha) * a2;
    const bool r_format = test::uniform(rng, 0, 1) < 0.3;
    const bool full = !r_format && test::uniform(rng, 0, 1) < 0.15;
    const int turns = r_format ? 1 : 1 + static_cast<int>(test::uniform(rng, 0, 1) < 0.2);
    double base = test::uniform(rng, 0.05, 2 * kPi - 0.05);
    // R format is ill-conditioned near a semicircle: keep away from it
    if (r_format && std::abs(base - kPi) < 0.1) base = kPi + (base < kPi ? -0.1 : 0.1);
    if (full) base = 2 * kPi;
    const double rise = test::uniform(rng, 0, 1) < 0.4 ? test::uniform(rng, -0.03, 0.03) : 0.0;
    Arc arc{pos - radius * u, u, sign * nrm.cross(u), radius, base + 2 * kPi * (turns - 1), rise};
    const Vec3 end = full ? Vec3(pos + sign * rise * nrm) : end_of(arc);
    g << (ccw ? "G3" : "G2") << (plane == 0 ? " G17" : plane == 1 ? " G18" : " G19");
    write_axes(end, !full);
    if (r_format) {
      g << " R" << num(coord(base <= kPi ? radius : -radius));
    } else {
      const Vec3 offset = arc.center - pos;
      g << ' ' << off1 << num(coord(offset.dot(a1))) << ' ' << off2 << num(coord(offset.dot(a2)));
      if (turns > 1) g << " P" << turns;
    }
    g << '\n';
    out.moves.push_back(arc);
    pos = end;
  }
  out.text = g.str();
  return out;
}

TEST(Gcode, PropertyRandomProgramsRoundTrip) {
  constexpr double kRoundTripTol = 1e-12;  // m
  const int cases = test::property_cases(300);
  for (int c = 0; c < cases; ++c) {
    const std::uint64_t seed = 0x9c0de000 + static_cast<std::uint64_t>(c);
    std::mt19937_64 rng = test::make_rng(seed);
    const RandomProgram prog = random_program(rng);
    GcodeResult r;
    try {
      r = parse(prog.text);
    } catch (const InputError& e) {
      ADD_FAILURE() << test::seed_text(seed) << ": " << e.what() << "\n" << prog.text;
      continue;
    }
    ASSERT_EQ(r.program.moves.size(), prog.moves.size()) << test::seed_text(seed) << "\n" << prog.text << notes(r);
    for (std::size_t k = 0; k < prog.moves.size(); ++k) {
      const Primitive& want = prog.moves[k];
      const Primitive& got = r.program.moves[k].geometry;
      ASSERT_EQ(want.index(), got.index()) << test::seed_text(seed) << " move " << k;
      const double len_want = length(want);
      EXPECT_NEAR(length(got), len_want, kRoundTripTol) << test::seed_text(seed) << " move " << k;
      for (const double t : {0.0, 0.25, 0.5, 0.75, 1.0}) {
        EXPECT_LE((point(got, t * length(got)) - point(want, t * len_want)).norm(), kRoundTripTol)
            << test::seed_text(seed) << " move " << k << " t=" << t << "\n" << prog.text;
      }
      if (const Arc* a = std::get_if<Arc>(&want)) {
        const Arc& b = std::get<Arc>(got);
        EXPECT_LE((a->center - b.center).norm(), kRoundTripTol) << test::seed_text(seed) << " move " << k;
        EXPECT_NEAR(a->radius, b.radius, kRoundTripTol) << test::seed_text(seed) << " move " << k;
        EXPECT_NEAR(a->rise, b.rise, kRoundTripTol) << test::seed_text(seed) << " move " << k;
        EXPECT_LE((a->u.cross(a->v) - b.u.cross(b.v)).norm(), 1e-12) << test::seed_text(seed) << " move " << k;
      }
    }
    EXPECT_NO_THROW(validate(r.program)) << test::seed_text(seed);
  }
}

// One corner numbering (issue 44): a corner the blender refuses is named in its note as
// corners.json, the report and the plots name it, C<index> (the corner at the end of move
// index), with the moves by their N words; here a line into a helix, which the biclothoid's
// non-planar fallback (seed 000's Bezier) cannot join.
TEST(Gcode, ABlendersNoteNamesTheCornerAsTheReportDoes) {
  const GcodeResult r = parse("N10 G64 P0.1\nN20 G1 X10\nN30 G1 X20\nN40 G3 X20 Y0 Z-4 I0 J5 P2\nN50 G1 X0\n");
  const Path path = blend(r.program);
  ASSERT_EQ(path.corners.size(), 3u);
  const CornerReport& refused = path.corners[1];
  EXPECT_EQ(refused.index, 1);
  EXPECT_EQ(refused.note.text().rfind("C1 (N30 G1 -> N40 G3): ", 0), 0u) << refused.note.text();
  // G64 Q merges the two collinear lines before blending: the corner keeps its number
  const Path merged = blend(parse("N10 G64 P0.1 Q0.01\nN20 G1 X10\nN30 G1 X20\nN40 G3 X20 Y0 Z-4 I0 J5 P2\nN50 G1 X0\n").program);
  ASSERT_EQ(merged.moves_merged, 1);
  ASSERT_EQ(merged.corners.size(), 2u);
  EXPECT_EQ(merged.corners[0].index, 1);
  EXPECT_EQ(merged.corners[0].note.text().rfind("C1 (", 0), 0u) << merged.corners[0].note.text();
}

}  // namespace
}  // namespace blendbench
