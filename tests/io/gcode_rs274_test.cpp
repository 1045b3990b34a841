// The RS274/NGC programming features of the G-code reader (parameters, expressions, O-word
// control flow, offsets, tool length offsets, G53, G28/G30): each program whose path is known by
// construction is compared with the same path written out longhand, and each value with one
// computed by hand.

#include "blendbench/core/units.hpp"
#include "blendbench/io/gcode.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cmath>
#include <iomanip>
#include <numbers>
#include <random>
#include <sstream>

#include "support/input_error.hpp"
#include "support/property.hpp"

namespace blendbench {
namespace {

constexpr double kSamePath = 1e-12;  // m: two readings of one path (rounding of sums only)
constexpr double kValueTol = 1e-9;   // mm: a hand-computed expression value
constexpr double kPi = std::numbers::pi;

GcodeOptions options() {
  GcodeOptions opt;
  opt.limits = {0.1, 2.0, 3.0, 50.0};
  return opt;
}

GcodeResult parse(const std::string& text, const GcodeOptions& opt = options()) { return parse_gcode(text, "part.ngc", opt); }

std::string expect_error(const std::string& text, int line, int column, const std::string& word,
                         const GcodeOptions& opt = options()) {
  return test::expect_input_error([&] { (void)parse(text, opt); },
                                  {.file = "part.ngc", .line = line, .column = column, .field = word}, text)
      .detail();
}

std::string notes(const GcodeResult& r) {
  std::string out;
  for (const std::string& s : r.ignored) out += "  " + s + "\n";
  return out;
}

Vec3 mm(double x, double y, double z) { return Vec3(x, y, z) * kMm; }
Vec3 end_of(const Move& m) { return point(m.geometry, length(m.geometry)); }

// The two programs give the same moves: same kinds, same points along each (start, quarter
// points, end), same feed.
void expect_same_path(const std::string& program, const std::string& longhand, const GcodeOptions& opt = options()) {
  const GcodeResult a = parse(program, opt);
  const GcodeResult b = parse(longhand, opt);
  ASSERT_EQ(a.program.moves.size(), b.program.moves.size()) << program << "\n---\n" << longhand;
  for (std::size_t k = 0; k < a.program.moves.size(); ++k) {
    const Move& ma = a.program.moves[k];
    const Move& mb = b.program.moves[k];
    ASSERT_EQ(ma.geometry.index(), mb.geometry.index()) << "move " << k;
    EXPECT_NEAR(length(ma.geometry), length(mb.geometry), kSamePath) << "move " << k;
    for (const double t : {0.0, 0.25, 0.5, 0.75, 1.0}) {
      EXPECT_LE((point(ma.geometry, t * length(ma.geometry)) - point(mb.geometry, t * length(mb.geometry))).norm(), kSamePath)
          << "move " << k << " t=" << t << "\n" << program << "\n---\n" << longhand;
    }
    EXPECT_NEAR(ma.limits.velocity, mb.limits.velocity, 1e-15) << "move " << k;
  }
}

// The x (mm) the program's last move ends at, for "G1 X<value>".
double value_of(const std::string& expression, const std::string& before = "") {
  // (a first move, so that a value of 0 leaves a program with moves)
  const GcodeResult r = parse("G0 Y1\n" + before + "G1 X" + expression + "\n");
  return end_of(r.program.moves.back()).x() / kMm;
}

TEST(GcodeRs274, EveryOperatorAndFunctionAgainstHandValues) {
  struct Case {
    const char* expr;
    double want;
  };
  const double deg = std::numbers::pi / 180;
  const std::vector<Case> cases = {
      {"[1 + 2]", 3},
      {"[1 - 2.5]", -1.5},
      {"[3 * 4]", 12},
      {"[7 / 2]", 3.5},
      {"[2 ** 10]", 1024},
      {"[7 MOD 3]", 1},
      {"[-7 MOD 3]", 2},        // LinuxCNC: a negative remainder is made positive
      {"[7.5 MOD -2]", 1.5},
      {"[1 + 2 * 3]", 7},       // * before +
      {"[2 * 3 ** 2]", 18},     // ** before *
      {"[10 - 4 - 3]", 3},      // equal precedence from the left
      {"[16 / 4 / 2]", 2},
      {"[2 ** 3 ** 2]", 64},    // LinuxCNC groups ** from the left too
      {"[1 + 1 EQ 2]", 1},      // + before EQ
      {"[1 EQ 1.0000001]", 1},  // EQ within LinuxCNC's 1e-6
      {"[1 EQ 1.00001]", 0},
      {"[1 NE 2]", 1},
      {"[1 NE 1]", 0},
      {"[2 GT 1]", 1},
      {"[1 GT 1]", 0},
      {"[1 GE 1]", 1},
      {"[1 LT 2]", 1},
      {"[2 LT 2]", 0},
      {"[2 LE 2]", 1},
      {"[1 AND 2]", 1},
      {"[1 AND 0]", 0},
      {"[0 OR 0]", 0},
      {"[0 OR 3]", 1},
      {"[1 XOR 1]", 0},
      {"[1 XOR 0]", 1},
      {"[1 LT 2 AND 3 LT 2]", 0},  // relations before AND
      {"[0 AND 0 OR 1]", 1},       // AND, OR, XOR equal, from the left
      {"ABS[-2.5]", 2.5},
      {"ACOS[0.5]", 60},
      {"ASIN[0.5]", 30},
      {"ATAN[1]/[1]", 45},
      {"ATAN[1]/[-1]", 135},      // quadrant from the signs (atan2)
      {"COS[60]", 0.5},
      {"SIN[30]", 0.5},
      {"TAN[45]", 1},
      {"EXP[1]", std::exp(1.0)},
      {"LN[EXP[2]]", 2},
      {"SQRT[2]", std::sqrt(2.0)},
      {"FIX[-2.5]", -3},          // toward minus infinity
      {"FUP[2.1]", 3},
      {"ROUND[2.5]", 3},          // halves away from zero
      {"ROUND[-2.5]", -3},
      {"-[1 + 2]", -3},
      {"-ABS[-4]", -4},
      {"[SIN[30] * 2 + COS[0]]", 2},
      {"[[1 + 2] * [3 + 4]]", 21},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.expr);
    EXPECT_NEAR(value_of(c.expr), c.want, kValueTol);
  }
  // degrees, as LinuxCNC: SIN[x] = sin(x deg)
  EXPECT_NEAR(value_of("SIN[37]"), std::sin(37 * deg), kValueTol);
  EXPECT_NEAR(value_of("ATAN[-3]/[-4]"), std::atan2(-3.0, -4.0) / deg, kValueTol);
  // EXISTS: 1 for a named parameter that is set, else 0
  EXPECT_NEAR(value_of("[EXISTS[#<a>] + 10 * EXISTS[#<b>]]", "#<a> = 1\n"), 1, kValueTol);
}

TEST(GcodeRs274, ParametersNumberedNamedGlobalIndirect) {
  // assignments take effect after the line's values are read (RS274/NGC)
  EXPECT_NEAR(value_of("#1 #1 = 5", "#1 = 2\n"), 2, kValueTol);
  EXPECT_NEAR(value_of("#1", "#1 = 2 #1 = 7\n"), 7, kValueTol);  // the last one wins
  // indirection: ##2 is the parameter whose number #2 holds; #[..] computes the number
  EXPECT_NEAR(value_of("##2", "#2 = 100\n#100 = 4.5\n"), 4.5, kValueTol);
  EXPECT_NEAR(value_of("#[50 + 50]", "#100 = 4.5\n"), 4.5, kValueTol);
  // named: case and blanks do not matter (LinuxCNC)
  EXPECT_NEAR(value_of("#<MyDepth>", "#<my depth> = 3\n"), 3, kValueTol);
  EXPECT_NEAR(value_of("#<_glob>", "#<_glob> = 8\n"), 8, kValueTol);
  // an unset numbered parameter is 0
  EXPECT_NEAR(value_of("[#31 + 1]"), 1, kValueTol);
  // predefined: the current position, units
  EXPECT_NEAR(value_of("[#<_x> + #5420]", "G0 X3\n"), 6, kValueTol);
  EXPECT_NEAR(value_of("#<_metric>", "G21\n"), 1, kValueTol);
  expect_error("#<_x> = 1\nG1 X1", 1, 1, "#<_x>");
  expect_error("#5420 = 1\nG1 X1", 1, 1, "#5420");
  expect_error("G1 X#0", 1, 5, "#0");
  expect_error("G1 X#5602", 1, 5, "#5602");
  expect_error("G1 X#1.5", 1, 5, "#1.5");
}

TEST(GcodeRs274, ExpressionErrorsArePositioned) {
  std::string msg = expect_error("G1 X[1/0]", 1, 7, "X[1/");
  EXPECT_NE(msg.find("division by zero"), std::string::npos) << msg;
  expect_error("G1 X[2 MOD 0]", 1, 8, "X[2MOD");
  expect_error("G1 X SQRT[-1]", 1, 6, "XSQRT[-1]");
  expect_error("G1 X LN[0]", 1, 6, "XLN[0]");
  expect_error("G1 X ACOS[2]", 1, 6, "XACOS[2]");
  expect_error("G1 X[-8 ** 0.5]", 1, 9, "X[-8**");
  expect_error("G1 X EXP[1000]", 1, 6, "XEXP[1000]");
  expect_error("G1 X FOO[1]", 1, 6, "XFOO[1]");
  expect_error("G1 X ATAN[1]", 1, 13, "XATAN[1]");
  expect_error("G1 X[1 # 2]", 1, 8, "X[1#");  // blanks do not separate values: [1 2] is [12]
  // nesting is bounded (a fuzzer's [[[[...)
  expect_error("G1 X" + std::string(200, '[') + "1" + std::string(200, ']'), 1, 5 + 65, "X" + std::string(66, '['));
  expect_error("G1 X" + std::string(200, '#') + "1", 1, 5 + 65, "X" + std::string(66, '#'));
  expect_error("G1 X" + std::string(200, '-') + "1", 1, 4, "X-");  // one sign per value
}

TEST(GcodeRs274, SubroutineWithArgumentsIsTheLonghandPath) {
  const std::string program =
      "o<rect> sub\n"
      "  (#1, #2: corner; #3, #4: size; #<w> is local)\n"
      "  #<w> = [#1 + #3]\n"
      "  G1 X#1 Y#2\n"
      "  G1 X#<w>\n"
      "  G1 Y[#2 + #4]\n"
      "  G1 X#1\n"
      "  G1 Y#2\n"
      "o<rect> endsub\n"
      "G21 G90 F600\n"
      "o<rect> call [0] [0] [10] [5]\n"
      "o<rect> call [20] [-5] [3] [4]\n"
      "G1 X[#<w> + 0]\n";  // #<w> was local to the calls: undefined here
  EXPECT_NE(expect_error(program, 13, 6, "#<w>").find("not defined"), std::string::npos);
  const std::string ok = program.substr(0, program.rfind("G1 X[#<w>")) + "G1 X#1 Y#2\n";
  // #1 and #2 of the main program are untouched by the calls (arguments are local): 0, 0
  expect_same_path(ok,
                   "G21 G90 F600\n"
                   "G1 X0 Y0\nG1 X10\nG1 Y5\nG1 X0\nG1 Y0\n"
                   "G1 X20 Y-5\nG1 X23\nG1 Y-1\nG1 X20\nG1 Y-5\n"
                   "G1 X0 Y0\n");
}

TEST(GcodeRs274, NestedCallsReturnValuesAndRecursion) {
  // a recursive subroutine: #1 levels of a staircase, each call one step, returning the depth
  const std::string program =
      "o<stairs> sub\n"
      "  o<s1> if [#1 LE 0]\n"
      "    o<stairs> return [0]\n"
      "  o<s1> endif\n"
      "  G91 G1 X1\n"
      "  G1 Y1\n"
      "  o<stairs> call [#1 - 1]\n"
      "  o<stairs> return [#<_value> + 1]\n"
      "o<stairs> endsub\n"
      "o<stairs> call [4]\n"
      "G90 G1 X[#<_value> * 10] Y0\n";
  expect_same_path(program,
                   "G91 G1 X1\nG1 Y1\nG1 X1\nG1 Y1\nG1 X1\nG1 Y1\nG1 X1\nG1 Y1\n"
                   "G90 G1 X40 Y0\n");
  // recursion without end stops at the call depth limit, naming the call
  const std::string msg = expect_error("o1 sub\nG91 G1 X1\no1 call\no1 endsub\no1 call\n", 3, 1, "o1");
  EXPECT_NE(msg.find("nested deeper than " + std::to_string(kMaxCallDepth)), std::string::npos) << msg;
}

TEST(GcodeRs274, LoopsAreTheLonghandPath) {
  std::string longhand;
  for (int k = 1; k <= 5; ++k) longhand += "G1 X" + std::to_string(k) + " Y" + std::to_string(k % 2) + "\n";
  expect_same_path("#1 = 1\no10 while [#1 LE 5]\n G1 X#1 Y[#1 MOD 2]\n #1 = [#1 + 1]\no10 endwhile\n", longhand);
  expect_same_path("#1 = 1\no11 do\n G1 X#1 Y[#1 MOD 2]\n #1 = [#1 + 1]\no11 while [#1 LE 5]\n", longhand);
  expect_same_path("#1 = 1\no12 repeat [5]\n G1 X#1 Y[#1 MOD 2]\n #1 = [#1 + 1]\no12 endrepeat\n", longhand);
  // a do loop runs its body once even when the condition is false; repeat [0] not at all
  expect_same_path("o13 do\nG1 X1\no13 while [0]\no14 repeat [0]\nG1 X9\no14 endrepeat\nG1 Y1\n", "G1 X1\nG1 Y1\n");
  // break and continue: skip 3, stop after 4
  expect_same_path(
      "#1 = 0\n"
      "o20 while [1]\n"
      "  #1 = [#1 + 1]\n"
      "  o21 if [#1 EQ 3]\n"
      "    o20 continue\n"
      "  o21 elseif [#1 GT 4]\n"
      "    o20 break\n"
      "  o21 endif\n"
      "  G1 X#1\n"
      "o20 endwhile\n"
      "G1 Y1\n",
      "G1 X1\nG1 X2\nG1 X4\nG1 Y1\n");
  // nested repeats, the inner one left by break each time
  expect_same_path(
      "#1 = 0\n"
      "o30 repeat [3]\n"
      "  o31 repeat [10]\n"
      "    #1 = [#1 + 1]\n"
      "    G1 X#1\n"
      "    o31 break\n"
      "  o31 endrepeat\n"
      "  G1 Y#1\n"
      "o30 endrepeat\n",
      "G1 X1\nG1 Y1\nG1 X2\nG1 Y2\nG1 X3\nG1 Y3\n");
}

TEST(GcodeRs274, IfElseifElseChains) {
  for (int v = 0; v < 4; ++v) {
    const std::string program = "#1 = " + std::to_string(v) +
                                "\n"
                                "o1 if [#1 EQ 0]\n G1 X10\n"
                                "o1 elseif [#1 EQ 1]\n G1 X11\n"
                                "o1 elseif [#1 EQ 2]\n G1 X12\n"
                                "o1 else\n G1 X13\n"
                                "o1 endif\n";
    SCOPED_TRACE(v);
    expect_same_path(program, "G1 X" + std::to_string(10 + v) + "\n");
  }
}

TEST(GcodeRs274, StructureErrorsNameTheLine) {
  expect_error("o1 while [1]\nG1 X1\n", 1, 1, "o1");                         // not closed
  expect_error("o1 while [1]\nG1 X1\no2 endwhile\n", 3, 1, "o2");            // another label
  expect_error("o1 if [1]\nG1 X1\no1 endwhile\n", 3, 1, "o1");               // another kind
  expect_error("o1 break\nG1 X1\n", 1, 1, "o1");                             // not in a loop
  expect_error("o1 return\nG1 X1\n", 1, 1, "o1");                            // not in a sub
  expect_error("o1 sub\no2 sub\no2 endsub\no1 endsub\nG1 X1", 2, 1, "o2");   // nested definition
  expect_error("o1 sub\no1 endsub\no1 sub\no1 endsub\nG1 X1", 3, 1, "o1");   // defined twice
  expect_error("o1 if [1]\no1 else\no1 else\no1 endif\n", 3, 1, "o1");       // two else
  expect_error("o1 frobnicate\nG1 X1", 1, 1, "o1");                          // unknown keyword
  expect_error("G1 X1\nN5 o\n", 2, 4, "o");                                  // no label
  expect_error("o1 while\nG1 X1\no1 endwhile", 1, 1, "o1");                  // no condition
  expect_error("o1 if [1] [2]\nG1 X1\no1 endif", 1, 11, "[");                // two conditions
  expect_error("G1 X1 o1 call", 1, 7, "o1");                                 // not first on the line
}

TEST(GcodeRs274, ErrorsInsideASubroutineNameTheBodyLineAndTheCall) {
  const std::string msg = expect_error(
      "o<cut> sub\n"
      "  G1 X[10 / #1]\n"
      "o<cut> endsub\n"
      "o<cut> call [2]\n"
      "o<cut> call [0]\n",
      2, 11, "X[10/");
  EXPECT_NE(msg.find("in o<cut> called from line 5"), std::string::npos) << msg;
}

TEST(GcodeRs274, LoopsThatNeverEndAreBounded) {
  GcodeOptions opt = options();
  opt.max_lines = 100000;
  // no moves: bounded by the lines executed, the error at a line of the loop
  const auto loop_error = [](const std::string& text, const GcodeOptions& o) {
    try {
      (void)parse(text, o);
    } catch (const InputError& e) {
      EXPECT_GE(e.line(), 2);
      EXPECT_LE(e.line(), 4);
      return std::string(e.detail());
    }
    ADD_FAILURE() << "no error for\n" << text;
    return std::string();
  };
  std::string msg = loop_error("G1 X1\no1 while [1]\n#1 = [#1 + 1]\no1 endwhile\n", opt);
  EXPECT_NE(msg.find("more than 100000 lines executed"), std::string::npos) << msg;
  // moves: bounded by the moves of one program
  opt.max_moves = 1000;
  opt.max_lines = kMaxExecutedLines;
  msg = expect_error("G91\no1 while [1]\nG1 X1\no1 endwhile\n", 3, 1, "G1", opt);
  EXPECT_NE(msg.find("more than 1000 moves"), std::string::npos) << msg;
  // the default bound stops `while [1]` too, within seconds
  const auto t0 = std::chrono::steady_clock::now();
  msg = loop_error("G1 X1\no1 while [1]\no1 endwhile\n", options());
  EXPECT_NE(msg.find("more than " + std::to_string(kMaxExecutedLines) + " lines executed"), std::string::npos) << msg;
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), 120.0);
}

TEST(GcodeRs274, NotesOfALoopBodyOnceNotPerPass) {
  const GcodeResult r = parse("o1 repeat [50]\nS1000 G91 G1 X1\no1 endrepeat\n");
  EXPECT_EQ(r.program.moves.size(), 50u);
  EXPECT_EQ(std::count(r.ignored.begin(), r.ignored.end(), "S1000 (line 2)"), 1) << notes(r);
}

TEST(GcodeRs274, CoordinateSystemOffsetsG10L2AndL20) {
  // G10 L2 P2 sets G55's offset; the moves under G55 are shifted by it, G54's are not
  // (a change of system does not move the machine: the axes not written keep their machine value)
  expect_same_path("G10 L2 P2 X100 Y50 Z-5\nG1 X1 Y2\nG55 G1 X1 Y2\nG1 Z1\nG54 G1 X3\n",
                   "G1 X1 Y2\nG1 X101 Y52\nG1 Z-4\nG1 X3 Y52 Z-4\n");
  // the offsets as parameters (#5241.. for G55), both ways
  expect_same_path("#5241 = 100\n#5242 = 50\nG55 G1 X1 Y2\nG1 X[#5241 + #5242]\n", "G1 X101 Y52\nG1 X250\n");
  // G10 L20: the current point gets the given coordinates
  expect_same_path("G1 X7 Y8\nG10 L20 P1 X0 Y0\nG1 X1\nG1 Y1\n", "G1 X7 Y8\nG1 X8\nG1 Y9\n");
  // P0: the system in use; G91 does not apply to G10 L2
  expect_same_path("G56\nG10 L2 P0 X10\nG91\nG10 L2 P0 X10\nG90\nG1 X1\n", "G1 X11\n");
  // a rotation R (degrees about Z) turns the programmed points about the system's origin
  const double c = std::cos(30 * std::numbers::pi / 180);
  const double s = std::sin(30 * std::numbers::pi / 180);
  std::ostringstream longhand;
  longhand << std::setprecision(17) << "G1 X" << 5 + 10 * c << " Y" << 10 * s << "\n"
           << "G1 X" << 5 + 10 * c - 10 * s << " Y" << 10 * s + 10 * c << "\n";
  expect_same_path("G10 L2 P1 X5 R30\nG1 X10 Y0\nG1 Y10\n", longhand.str());
  // an arc in a rotated system is the rotated arc
  const GcodeResult r = parse("G10 L2 P1 R90\nG1 X10 Y0\nG3 X0 Y10 I-10 J0\n");
  EXPECT_LE((end_of(r.program.moves[0]) - mm(0, 10, 0)).norm(), kSamePath);
  EXPECT_LE((end_of(r.program.moves[1]) - mm(-10, 0, 0)).norm(), kSamePath);
  EXPECT_NEAR(std::get<Arc>(r.program.moves[1].geometry).radius, 10 * kMm, kSamePath);
}

TEST(GcodeRs274, G92ThenG92OneAndNestedOffsets) {
  // G92 makes the current point (10, 10) read (0, 0); G92.1 removes the offset
  expect_same_path("G1 X10 Y10\nG92 X0 Y0\nG1 X5\nG92.1\nG1 Y0\n", "G1 X10 Y10\nG1 X15\nG1 Y0\n");
  // G92.2 suspends it, G92.3 brings it back
  expect_same_path("G1 X10\nG92 X0\nG92.2\nG1 X1\nG92.3\nG1 X1\n", "G1 X10\nG1 X1\nG1 X11\n");
  // nested: a G55 offset, a G52 local offset and a tool length offset add up
  GcodeOptions opt = options();
  opt.tool_offsets[3] = mm(0, 0, 25);
  expect_same_path("G10 L2 P2 X100\nG55\nG52 X10 Y20\nT3 M6\nG43\nG1 X1 Y1 Z1\nG52 X0 Y0\nG49\nG1 X1 Y1 Z1\n",
                   "G1 X111 Y21 Z26\nG1 X101 Y1 Z1\n", opt);
  // G92 with the offsets in force keeps the point where it is
  expect_same_path("G10 L2 P1 X3\nG1 X1\nG92 X50\nG1 X51\nG1 X[#5420]\n", "G1 X4\nG1 X5\nG1 X5\n");
  // the offsets are the parameters #5211..
  EXPECT_NEAR(value_of("#1", "G1 X10\nG92 X4\n#1 = #5211\nG92.1\n"), 6, kValueTol);
}

TEST(GcodeRs274, ToolLengthOffsets) {
  GcodeOptions opt = options();
  opt.tool_offsets[1] = mm(0, 0, 40);
  // G43 H1 moves every programmed point by the tool's offset; G49 cancels it
  // (a new offset applies to the axes written from then on: the machine does not move by itself)
  expect_same_path("G1 X1\nG43 H1\nG1 Z0\nG1 X2\nG49\nG1 X3\nG1 Z0\n", "G1 X1\nG1 Z40\nG1 X2\nG1 X3\nG1 Z0\n", opt);
  // G43.1: the offset as axis words; G43.2 adds a tool's
  expect_same_path("G43.1 Z5\nG1 X1 Z0\nG43.2 H1\nG1 X2 Z0\n", "G1 X1 Z5\nG1 X2 Z45\n", opt);
  // G10 L1 writes the tool table
  expect_same_path("G10 L1 P7 Z12\nG43 H7\nG1 X1 Z0\n", "G1 X1 Z12\n", opt);
  // a tool not in the table: zero offset, noted
  const GcodeResult r = parse("G43 H9\nG1 X1\n", opt);
  EXPECT_LE((end_of(r.program.moves[0]) - mm(1, 0, 0)).norm(), kSamePath);
  EXPECT_NE(notes(r).find("tool 9 has no entry in the tool table"), std::string::npos) << notes(r);
}

TEST(GcodeRs274, G53InAnOffsetFrame) {
  // G53 moves to machine coordinates whatever the offsets; the next move is in the offset frame
  expect_same_path("G10 L2 P1 X100 Y100\nG1 X1 Y1\nG53 G0 X0 Y0\nG1 X2\n", "G1 X101 Y101\nG0 X0 Y0\nG1 X102 Y0\n");
  // axes not given keep their machine value
  expect_same_path("G10 L2 P1 Z10\nG1 X1 Z1\nG53 G1 X0\n", "G1 X1 Z11\nG1 X0\n");
}

TEST(GcodeRs274, G28AndG30GoThroughThePointToTheStoredPosition) {
  expect_same_path("G1 X5 Y5 Z5\nG28.1\nG1 X9 Y9 Z9\nG28 Z10\nG1 X1\nG30\n",
                   "G1 X5 Y5 Z5\nG1 X9 Y9 Z9\nG0 Z10\nG0 Z5\nG1 X1\nG0 X0 Y0 Z0\n");
}

// Random polylines written three ways (longhand; as a subroutine per point with the point as
// arguments, in a loop over parameters #100..; under random offsets undone by hand) give one path.
TEST(GcodeRs274, PropertyProgramsWrittenThreeWaysAgree) {
  const int cases = test::property_cases(100);
  for (int c = 0; c < cases; ++c) {
    const std::uint64_t seed = 0x45a0000 + static_cast<std::uint64_t>(c);
    std::mt19937_64 rng = test::make_rng(seed);
    std::uniform_real_distribution<double> coord(-200, 200);
    std::uniform_int_distribution<int> count(2, 30);
    const int n = count(rng);
    std::vector<Vec3> pts;
    for (int k = 0; k < n; ++k) pts.emplace_back(coord(rng), coord(rng), coord(rng));
    const Vec3 offset(coord(rng), coord(rng), coord(rng));
    const double angle = std::uniform_real_distribution<double>(-180, 180)(rng);

    std::ostringstream longhand, by_sub, by_loop, by_offset;
    for (auto* s : {&longhand, &by_sub, &by_loop, &by_offset}) *s << std::setprecision(17);
    by_sub << "o<pt> sub\nG1 X#1 Y#2 Z#3\no<pt> endsub\n";
    const double a = angle * std::numbers::pi / 180;
    by_offset << "G10 L2 P3 X" << offset.x() << " Y" << offset.y() << " Z" << offset.z() << " R" << angle << "\nG56\n";
    for (int k = 0; k < n; ++k) {
      const Vec3& p = pts[static_cast<std::size_t>(k)];
      longhand << "G1 X" << p.x() << " Y" << p.y() << " Z" << p.z() << "\n";
      by_sub << "o<pt> call [" << p.x() << "] [" << p.y() << "] [" << p.z() << "]\n";
      by_loop << "#" << 100 + 3 * k << " = " << p.x() << " #" << 101 + 3 * k << " = " << p.y() << " #" << 102 + 3 * k
              << " = " << p.z() << "\n";
      // the program point whose rotated, shifted image is p
      const Vec3 q = p - offset;
      const Vec3 prog(std::cos(a) * q.x() + std::sin(a) * q.y(), -std::sin(a) * q.x() + std::cos(a) * q.y(), q.z());
      by_offset << "G1 X" << prog.x() << " Y" << prog.y() << " Z" << prog.z() << "\n";
    }
    by_loop << "#1 = 0\no1 while [#1 LT " << n << "]\nG1 X#[100 + 3 * #1] Y#[101 + 3 * #1] Z#[102 + 3 * #1]\n#1 = [#1 + 1]\no1 endwhile\n";
    SCOPED_TRACE(test::seed_text(seed));
    expect_same_path(by_sub.str(), longhand.str());
    expect_same_path(by_loop.str(), longhand.str());
    // the rotation costs a few ulps of 200 mm
    const GcodeResult x = parse(by_offset.str());
    const GcodeResult y = parse(longhand.str());
    ASSERT_EQ(x.program.moves.size(), y.program.moves.size());
    for (std::size_t k = 0; k < x.program.moves.size(); ++k) {
      EXPECT_LE((end_of(x.program.moves[k]) - end_of(y.program.moves[k])).norm(), 1e-15 * 1e3) << "move " << k;
    }
  }
}

// A number written with every digit it has (G-code has no exponents: fixed point).
std::string digits(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17f", v);
  return buf;
}

// LinuxCNC's polar coordinates: '@' the distance from the origin, '^' the angle; under G91 they
// add to the current point's. A spiral of lines as LinuxCNC's sam-circle_lines writes it (a
// repeat of G91 @-.0025 ^4.5) is the same path as its points computed here and written as X, Y.
TEST(GcodeRs274, PolarCoordinatesAreTheirPointsInXY) {
  std::ostringstream longhand;
  longhand << "G20 G0 X1 Y0\nG1 F999\n";
  double r = 1;
  double a = 0;
  for (int k = 0; k < 370; ++k) {
    r += -0.0025;             // @ first
    a += 4.5 * kPi / 180;     // then ^
    longhand << "X" << digits(r * std::cos(a)) << " Y" << digits(r * std::sin(a)) << "\n";
  }
  expect_same_path("G20 G0 X1 Y0\nG1 F999\no100 repeat [370]\nG91 G1 @-.0025 ^4.5\no100 endrepeat\n", longhand.str());
  // absolute: both, or one with the other kept from the current point
  expect_same_path("G0 X3 Y4\nG1 @10 ^90 F60\n@5\n^180\n", "G0 X3 Y4\nG1 X0 Y10 F60\nY5\nX-5 Y" + digits(5 * std::sin(kPi)) + "\n");
  // with offsets: program coordinates
  expect_same_path("G10 L2 P1 X100\nG0 X0 Y0\nG1 @2 ^0 F60\n", "G0 X100 Y0\nG1 X102 F60\n");
  expect_error("G0 X1\nG18 G1 @1 ^2 F60", 2, 8, "@1");
  expect_error("G0 X1\nG1 X2 @1 F60", 2, 4, "X2");
  expect_error("G91 G1 @1 F60", 1, 8, "@1");     // incremental at the origin
  expect_error("G1 @1 F60", 1, 4, "@1");         // no angle at the origin
  expect_error("G0 X1\nG92 @1", 2, 5, "@1");     // not an offset's coordinate
  expect_error("G0 X1\nG53 G0 @1 ^2", 2, 8, "@1");
}

// G7 (LinuxCNC's lathe diameter mode): X words are diameters, so the tool goes to half of
// them; G8 back to radii. I stays a radius.
TEST(GcodeRs274, LatheDiameterModeHalvesX) {
  expect_same_path("G18 G7 G0 X20 Z1\nG1 X10 Z-2 F60\nG91 X4\nG90 G8 X20\nG7 G2 X30 Z-2 I-2.5\n",
                   "G18 G0 X10 Z1\nG1 X5 Z-2 F60\nX7\nX20\nG2 X15 Z-2 I-2.5\n");
  expect_same_path("G0 X1\nG7 G92 X10\nG1 X12 F60\n", "G0 X1\nG1 X2 F60\n");
}

// G95: F units per spindle revolution, at the spindle speed S: a feed of F S per minute, what
// LinuxCNC's g95_blend programs; G94 returns to units per minute with the number as written.
TEST(GcodeRs274, FeedPerRevolutionIsFTimesTheSpindleSpeed) {
  const GcodeResult r = parse("G20 M3 S1000\nG95 G1 X0.1 F0.01\nG94 X0.2 F60\nG95\nX0.3 F0.002\n");
  ASSERT_EQ(r.program.moves.size(), 3u);
  EXPECT_NEAR(r.program.moves[0].limits.velocity, 0.01 * 1000 * 0.0254 / 60, 1e-15);
  EXPECT_NEAR(r.program.moves[1].limits.velocity, 60 * 0.0254 / 60, 1e-15);
  EXPECT_NEAR(r.program.moves[2].limits.velocity, 0.002 * 1000 * 0.0254 / 60, 1e-15);
  const std::string off = expect_error("S1000\nG95 G1 X1 F0.01", 2, 5, "G1");
  EXPECT_NE(off.find("needs the spindle turning"), std::string::npos) << off;
  expect_error("M3 S1000\nM5\nG95 G1 X1 F0.01", 3, 5, "G1");
  const std::string css = expect_error("M3 G96 S100\nG95 G1 X1 F0.01", 2, 5, "G1");
  EXPECT_NE(css.find("constant surface speed (G96)"), std::string::npos) << css;
}

// G33 moves along its line by K per revolution, so at S K per minute; G33.1 taps down and comes
// back along the same line, stopping at the bottom where the spindle reverses.
TEST(GcodeRs274, SpindleSynchronisedMotionAndRigidTapping) {
  const GcodeResult thread = parse("G20 G0 X1 Z0.1\nS200 M3\nG33 Z-2 K0.025\nG0 X1.25\n");
  ASSERT_EQ(thread.program.moves.size(), 3u);
  EXPECT_LE((end_of(thread.program.moves[1]) - Vec3(1, 0, -2) * 0.0254).norm(), kSamePath);
  EXPECT_NEAR(thread.program.moves[1].limits.velocity, 0.025 * 200 * 0.0254 / 60, 1e-15);
  EXPECT_EQ(thread.program.moves[1].name, "line 3 G33");
  const GcodeResult tap = parse("G20 G0 X1 Y1 Z0.1\nM3 S200\nG33.1 Z-0.75 K0.05\nG0 X2\n");
  ASSERT_EQ(tap.program.moves.size(), 4u);
  EXPECT_LE((end_of(tap.program.moves[1]) - Vec3(1, 1, -0.75) * 0.0254).norm(), kSamePath);
  EXPECT_LE((end_of(tap.program.moves[2]) - Vec3(1, 1, 0.1) * 0.0254).norm(), kSamePath);
  EXPECT_EQ(tap.program.moves[1].transition.method, Method::kNone);  // the spindle reverses
  EXPECT_EQ(tap.program.moves[2].transition.method, Method::kNone);
  EXPECT_NEAR(tap.program.moves[2].limits.velocity, 0.05 * 200 * 0.0254 / 60, 1e-15);
  expect_error("G0 X1\nG33 Z-2 K0.025", 2, 1, "G33");            // the spindle not turning
  expect_error("M3 S200\nG33 Z-2", 2, 1, "G33");                // no K
  expect_error("M3 S200\nG33 Z-2 K-1", 2, 9, "K-1");
  expect_error("M3 G96 S200\nG33.1 Z-2 K1", 2, 1, "G33.1");     // constant surface speed
  expect_error("G1 X1 K1 F60", 1, 7, "K1");                     // K with no user
}

// Canned cycles (LinuxCNC's interp_cycles.cc) against the same moves written longhand: the
// preliminary motion, the body of each cycle, G98 to the initial level and G99 to R, G91 with
// L repeats, a run of cycles continued by lines of positions, another plane; every move of a
// cycle stops (exact path).
TEST(GcodeRs274, CannedCyclesAreTheirMovesWrittenOut) {
  // G81, G98 (back to Z10, the level the run started at), a second hole by X alone
  expect_same_path("G0 X0 Y0 Z10\nG98 G81 X5 Y5 Z-2 R2 F100\nX10\nG80\nG0 X0\n",
                   "G0 X0 Y0 Z10\nX5 Y5\nZ2\nG1 Z-2 F100\nG0 Z10\nX10\nZ2\nG1 Z-2\nG0 Z10\nX0\n");
  // G99: back to R; the next hole moves at R
  expect_same_path("G0 X0 Y0 Z10\nG99 G81 X5 Y5 Z-2 R2 F100\nX10\n",
                   "G0 X0 Y0 Z10\nX5 Y5\nZ2\nG1 Z-2 F100\nG0 Z2\nX10\nG1 Z-2\nG0 Z2\n");
  // starting below R: straight up to R first
  expect_same_path("G0 X0 Y0 Z0\nG98 G81 X5 Z-2 R2 F100\n", "G0 X0 Y0 Z0\nZ2\nX5\nG1 Z-2 F100\nG0 Z2\n");
  // G91: R from the initial level, the bottom from R, three holes 5 apart
  expect_same_path("G0 X0 Y0 Z10\nG91 G99 G81 X5 Z-3 R-8 L3 F100\n",
                   "G0 X0 Y0 Z10\nX5\nZ2\nG1 Z-1 F100\nG0 Z2\nX10\nG1 Z-1\nG0 Z2\nX15\nG1 Z-1\nG0 Z2\n");
  // G83: pecks of Q, out to R after each, back down to 0.254 mm (0.010 in) above the last one
  std::ostringstream peck;
  std::ostringstream chip;
  peck << "G0 X0 Y0 Z5\nX1\nZ1\n";
  chip << "G0 X0 Y0 Z5\nX1\nZ1\n";
  for (double depth = 1 - 0.4; depth > -1; depth -= 0.4) {
    peck << "G1 Z" << digits(depth) << " F100\nG0 Z1\nZ" << digits(depth + 0.254) << "\n";
    chip << "G1 Z" << digits(depth) << " F100\nG0 Z" << digits(depth + 0.254) << "\n";
  }
  peck << "G1 Z-1\nG0 Z5\n";
  chip << "G1 Z-1\nG0 Z5\n";
  expect_same_path("G0 X0 Y0 Z5\nG98 G83 X1 Z-1 R1 Q0.4 F100\n", peck.str());
  expect_same_path("G0 X0 Y0 Z5\nG98 G73 X1 Z-1 R1 Q0.4 F100\n", chip.str());
  // G85 feeds out to R, G89 feeds out after its dwell, G82 rapids out after it
  expect_same_path("G0 X0 Y0 Z5\nG98 G85 X1 Z-1 R1 F100\n", "G0 X0 Y0 Z5\nX1\nZ1\nG1 Z-1 F100\nZ1\nG0 Z5\n");
  expect_same_path("G0 X0 Y0 Z5\nG98 G89 X1 Z-1 R1 P0.5 F100\n", "G0 X0 Y0 Z5\nX1\nZ1\nG1 Z-1 F100\nZ5\n");
  expect_same_path("G0 X0 Y0 Z5\nG98 G82 X1 Z-1 R1 P0.5 F100\n", "G0 X0 Y0 Z5\nX1\nZ1\nG1 Z-1 F100\nG0 Z5\n");
  expect_same_path("G0 X0 Y0 Z5\nM3 S500\nG98 G84 X1 Z-1 R1 F100\n", "G0 X0 Y0 Z5\nX1\nZ1\nG1 Z-1 F100\nZ5\n");
  expect_same_path("G0 X0 Y0 Z5\nM3 S500\nG98 G86 X1 Z-1 R1 P0 F100\n", "G0 X0 Y0 Z5\nX1\nZ1\nG1 Z-1 F100\nG0 Z5\n");
  // G18: the hole along Y, positions in Z and X
  expect_same_path("G18 G0 X0 Y10 Z0\nG98 G81 X5 Z5 Y-2 R2 F100\n", "G0 X0 Y10 Z0\nX5 Z5\nY2\nG1 Y-2 F100\nG0 Y10\n");
  // every move of a cycle stops at its end; the mode in force before it returns after it
  GcodeOptions opt = options();
  opt.blending = {Method::kArc, 0.001, 0, 0};
  const GcodeResult r = parse("G0 X0 Y0 Z10\nG98 G81 X5 Y5 Z-2 R2 F100\nG80 G1 X20\nY20\n", opt);
  ASSERT_EQ(r.program.moves.size(), 7u);
  for (std::size_t k = 1; k <= 4; ++k) EXPECT_EQ(r.program.moves[k].transition.method, Method::kNone) << k;
  EXPECT_EQ(r.program.moves[5].transition.method, Method::kArc);
  EXPECT_EQ(r.program.moves[1].name, "line 2 G81");
  // pecks that cannot deepen the hole in floating point (found by fuzz_gcode: R 1.8e122, Q 1.7)
  // are refused, not repeated without end
  expect_error("G0 X0 Z10\nG99 G83 X15 Z-3 R1777777777777777777777777777777777777777777777777777777777777777777777777777777777777777777777777777777777777777777777777 Q1.7 F100",
               2, 5, "G83");
  // a note where LinuxCNC's default retract mode would matter and the program set none
  const GcodeResult unset = parse("G0 X0 Y0 Z10\nG81 X5 Z-2 R2 F100\n");
  EXPECT_EQ(unset.ignored.size(), 1u);
  EXPECT_NE(unset.ignored.at(0).find("neither G98 nor G99 given"), std::string::npos) << unset.ignored.at(0);
}

}  // namespace
}  // namespace blendbench
