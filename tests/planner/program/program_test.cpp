#include "blendbench/program/program.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <numbers>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "support/input_error.hpp"
#include "support/property.hpp"
#include "support/random_geometry.hpp"
#include "blendbench/core/format.hpp"

namespace blendbench {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
// the largest error of a value printed with six significant digits, relative to the value
constexpr double kSixDigits = 5e-6 * (1 + 1e-9);

constexpr BufferMode kBufferModes[] = {BufferMode::kAborting,         BufferMode::kBuffered,
                                       BufferMode::kBlendingLow,      BufferMode::kBlendingPrevious,
                                       BufferMode::kBlendingNext,     BufferMode::kBlendingHigh};
constexpr Method kMethods[] = {Method::kNone, Method::kArc, Method::kBezier, Method::kClothoid, Method::kBiclothoid};

bool contains(const std::string& text, std::string_view part) { return text.find(part) != std::string::npos; }
bool starts_with(const std::string& text, std::string_view prefix) { return text.rfind(prefix, 0) == 0; }

// The name in three spellings that differ from it only in case.
std::vector<std::string> case_variants(std::string_view name) {
  std::string upper(name), lower(name), alternating(name);
  for (std::size_t i = 0; i < name.size(); ++i) {
    const auto c = static_cast<unsigned char>(name[i]);
    upper[i] = static_cast<char>(std::toupper(c));
    lower[i] = static_cast<char>(std::tolower(c));
    alternating[i] = i % 2 ? upper[i] : lower[i];
  }
  return {upper, lower, alternating};
}

// ---- names

TEST(ProgramNames, TheNamesUsedInFilesParseToTheirModeAndMethod) {
  // the PLCopen buffer mode names and the transition method names of the YAML scenarios
  const std::pair<const char*, BufferMode> modes[] = {
      {"Aborting", BufferMode::kAborting},       {"Buffered", BufferMode::kBuffered},
      {"BlendingLow", BufferMode::kBlendingLow}, {"BlendingPrevious", BufferMode::kBlendingPrevious},
      {"BlendingNext", BufferMode::kBlendingNext}, {"BlendingHigh", BufferMode::kBlendingHigh}};
  for (const auto& [name, mode] : modes) {
    EXPECT_EQ(buffer_mode_from_string(name), mode) << name;
    EXPECT_EQ(to_string(mode), name);
  }
  const std::pair<const char*, Method> methods[] = {{"none", Method::kNone},
                                                    {"arc", Method::kArc},
                                                    {"bezier", Method::kBezier},
                                                    {"clothoid", Method::kClothoid},
                                                    {"biclothoid", Method::kBiclothoid}};
  for (const auto& [name, method] : methods) {
    EXPECT_EQ(method_from_string(name), method) << name;
    EXPECT_EQ(to_string(method), name);
  }
}

TEST(ProgramNames, EveryBufferModeRoundTripsThroughADistinctName) {
  std::set<std::string_view> names;
  for (const BufferMode mode : kBufferModes) {
    const std::string_view name = to_string(mode);
    EXPECT_NE(name, "unknown");
    EXPECT_EQ(buffer_mode_from_string(name), mode) << name;
    names.insert(name);
  }
  EXPECT_EQ(names.size(), std::size(kBufferModes));
}

TEST(ProgramNames, EveryMethodRoundTripsThroughADistinctName) {
  std::set<std::string_view> names;
  for (const Method method : kMethods) {
    const std::string_view name = to_string(method);
    EXPECT_NE(name, "unknown");
    EXPECT_EQ(method_from_string(name), method) << name;
    names.insert(name);
  }
  EXPECT_EQ(names.size(), std::size(kMethods));
}

TEST(ProgramNames, ParsingIgnoresCase) {
  for (const BufferMode mode : kBufferModes) {
    for (const std::string& name : case_variants(to_string(mode))) EXPECT_EQ(buffer_mode_from_string(name), mode) << name;
  }
  for (const Method method : kMethods) {
    for (const std::string& name : case_variants(to_string(method))) EXPECT_EQ(method_from_string(name), method) << name;
  }
}

TEST(ProgramNames, UnknownNamesAreNullopt) {
  // near misses: empty, prefixes, extensions, padding, an embedded NUL, the fallback name
  const std::string_view unknown[] = {"",        " ",          "Blending",  "BlendingLowest", " Buffered",
                                      "Buffered ", "Low",      "arcs",      "bi-clothoid",    "clothoid2",
                                      "nan",     "unknown",    std::string_view("arc\0", 4)};
  for (const std::string_view name : unknown) {
    EXPECT_EQ(buffer_mode_from_string(name), std::nullopt) << "'" << name << "'";
    EXPECT_EQ(method_from_string(name), std::nullopt) << "'" << name << "'";
  }
  // a method name is not a buffer mode, nor the other way round
  for (const Method method : kMethods) EXPECT_EQ(buffer_mode_from_string(to_string(method)), std::nullopt);
  for (const BufferMode mode : kBufferModes) EXPECT_EQ(method_from_string(to_string(mode)), std::nullopt);
}

TEST(ProgramNames, AValueOutsideTheEnumIsNamedUnknownWhichDoesNotParse) {
  EXPECT_EQ(to_string(static_cast<BufferMode>(99)), "unknown");
  EXPECT_EQ(to_string(static_cast<Method>(99)), "unknown");
  EXPECT_EQ(buffer_mode_from_string("unknown"), std::nullopt);
  EXPECT_EQ(method_from_string("unknown"), std::nullopt);
}

// ---- junction velocity

TEST(JunctionVelocity, EachBufferModeFollowsThePlcopenRule) {
  // Low (and Buffered where the path keeps no kink): the slower move's; Previous: the first's;
  // Next and Aborting: the second's; High: the faster's
  struct Case {
    BufferMode mode;
    double slow_then_fast, fast_then_slow;  // with (0.1 -> 0.3) and (0.3 -> 0.1) m/s
  };
  const Case cases[] = {{BufferMode::kBlendingLow, 0.1, 0.1},  {BufferMode::kBuffered, 0.1, 0.1},
                        {BufferMode::kBlendingPrevious, 0.1, 0.3}, {BufferMode::kBlendingNext, 0.3, 0.1},
                        {BufferMode::kAborting, 0.3, 0.1},     {BufferMode::kBlendingHigh, 0.3, 0.3}};
  ASSERT_EQ(std::size(cases), std::size(kBufferModes));
  for (const Case& c : cases) {
    EXPECT_EQ(junction_velocity(c.mode, 0.1, 0.3), c.slow_then_fast) << to_string(c.mode);
    EXPECT_EQ(junction_velocity(c.mode, 0.3, 0.1), c.fast_then_slow) << to_string(c.mode);
    EXPECT_EQ(junction_velocity(c.mode, 0.2, 0.2), 0.2) << to_string(c.mode);
  }
}

TEST(JunctionVelocity, ModesAreOrderedAndMirrorEachOther) {
  // for any pair: the junction takes one of the two velocities, Low <= Previous, Next <= High,
  // Low and High do not depend on the order, and Previous of (a, b) is Next of (b, a)
  const int cases = test::property_cases(2000);
  for (int i = 0; i < cases; ++i) {
    auto rng = test::make_rng(static_cast<std::uint64_t>(i));
    const double a = std::pow(10.0, test::uniform(rng, -4, 1));
    const double b = std::pow(10.0, test::uniform(rng, -4, 1));
    const std::string seed = test::seed_text(static_cast<std::uint64_t>(i));
    for (const BufferMode mode : kBufferModes) {
      const double v = junction_velocity(mode, a, b);
      EXPECT_TRUE(v == a || v == b) << seed << " " << to_string(mode);
      EXPECT_LE(junction_velocity(BufferMode::kBlendingLow, a, b), v) << seed << " " << to_string(mode);
      EXPECT_GE(junction_velocity(BufferMode::kBlendingHigh, a, b), v) << seed << " " << to_string(mode);
    }
    for (const BufferMode mode : {BufferMode::kBlendingLow, BufferMode::kBuffered, BufferMode::kBlendingHigh}) {
      EXPECT_EQ(junction_velocity(mode, a, b), junction_velocity(mode, b, a)) << seed << " " << to_string(mode);
    }
    EXPECT_EQ(junction_velocity(BufferMode::kBlendingPrevious, a, b), junction_velocity(BufferMode::kBlendingNext, b, a))
        << seed;
    EXPECT_EQ(junction_velocity(BufferMode::kAborting, a, b), junction_velocity(BufferMode::kBlendingNext, a, b)) << seed;
  }
}

// ---- validate

Limits valid_limits() { return {0.2, 1.0, 2.0, 10.0}; }

Move line_move(const Vec3& a, const Vec3& b) {
  Move move;
  move.geometry = Line{a, b};
  move.limits = valid_limits();
  return move;
}

// A line from (0, 0, 0) to (0.1, 0, 0), a quarter arc of radius 50 mm turning left to
// (0.15, 0.05, 0), a line to (0.15, 0.15, 0); unnamed, written on lines 10, 20, 30 of cell.yaml.
Program three_moves() {
  Program program;
  Move arc;
  arc.geometry = Arc{Vec3(0.1, 0.05, 0), -Vec3::UnitY(), Vec3::UnitX(), 0.05, kPi / 2, 0};
  arc.limits = valid_limits();
  program.moves = {line_move({0, 0, 0}, {0.1, 0, 0}), arc, line_move({0.15, 0.05, 0}, {0.15, 0.15, 0})};
  for (std::size_t k = 0; k < program.moves.size(); ++k) {
    program.moves[k].where = {"cell.yaml", 10 * static_cast<int>(k + 1), 3};
  }
  return program;
}

// The InputError validate throws; a failure (and an empty error) when it throws none.
InputError validation_error(const Program& program) { return test::expect_input_error([&] { validate(program); }, {}); }

// Checks that the error is located where `move` was written and names `field`.
void expect_at(const InputError& e, const Move& move, const std::string& field) {
  EXPECT_EQ(e.file(), move.where.file) << e.what();
  EXPECT_EQ(e.line(), move.where.line) << e.what();
  EXPECT_EQ(e.column(), move.where.column) << e.what();
  EXPECT_EQ(e.field(), field) << e.what();
}

// The number printed after `marker` in text, or a failure and NaN when none parses.
double number_after(const std::string& text, std::string_view marker) {
  const std::size_t at = text.rfind(marker);
  if (at == std::string::npos) {
    ADD_FAILURE() << "no '" << marker << "' in: " << text;
    return kNaN;
  }
  const char* begin = text.c_str() + at + marker.size();
  char* end = nullptr;
  const double value = std::strtod(begin, &end);
  if (end == begin) ADD_FAILURE() << "no number after '" << marker << "' in: " << text;
  return value;
}

// Checks that text prints `value` after `marker` to six significant digits (NaN as "nan", never
// "-nan"), give or take `slack` for a value that is itself computed with rounding.
void expect_prints(const std::string& text, std::string_view marker, double value, double slack = 0) {
  const double printed = number_after(text, marker);
  if (std::isnan(value)) {
    EXPECT_TRUE(std::isnan(printed)) << text;
    EXPECT_FALSE(contains(text, "-nan")) << text;
  } else if (std::isinf(value)) {
    EXPECT_EQ(printed, value) << text;
  } else {
    EXPECT_LE(std::abs(printed - value), kSixDigits * std::abs(value) + slack) << text;
  }
}

TEST(Validate, AValidProgramOfLinesAndArcsPasses) {
  EXPECT_NO_THROW(validate(three_moves()));
  // whatever the buffer mode and transition method
  for (const BufferMode mode : kBufferModes) {
    for (const Method method : kMethods) {
      Program program = three_moves();
      for (Move& move : program.moves) {
        move.buffer = mode;
        move.transition = {.method = method, .parameter = 0.005, .kappa_max = 50, .velocity = 0.1};
      }
      EXPECT_NO_THROW(validate(program)) << to_string(mode) << " " << to_string(method);
    }
  }
}

TEST(Validate, TheBoundsOfEachRangeAreAccepted) {
  // limits from the smallest positive double to the largest; transition values from 0
  for (const double limit : {std::numeric_limits<double>::denorm_min(), std::numeric_limits<double>::max()}) {
    Program program = three_moves();
    program.moves[1].limits = {limit, limit, limit, limit};
    EXPECT_NO_THROW(validate(program)) << limit;
  }
  Program program = three_moves();
  program.moves[0].transition = {.method = Method::kClothoid, .parameter = 0, .kappa_max = 0, .velocity = 0};
  program.moves[1].transition = {.method = Method::kBiclothoid, .start_distance = 0.01};
  program.moves[2].transition = {.method = Method::kNone,
                                 .parameter = std::numeric_limits<double>::max(),
                                 .kappa_max = std::numeric_limits<double>::max(),
                                 .velocity = std::numeric_limits<double>::max()};
  EXPECT_NO_THROW(validate(program));
}

TEST(Validate, AnEmptyProgramIsAnInputErrorOnTheMoves) {
  const InputError e = validation_error(Program{});
  EXPECT_EQ(e.field(), "moves");
  EXPECT_TRUE(contains(e.detail(), "no moves")) << e.what();
}

TEST(Validate, EveryLimitMustBePositiveAndFiniteAndTheErrorNamesLimitMoveAndValue) {
  const double bad[] = {0.0,   -0.0, -1.0, -1e-7, -std::numeric_limits<double>::denorm_min(), -1e300,
                        kNaN, -kNaN, kInf, -kInf};
  const std::pair<double Limits::*, const char*> fields[] = {{&Limits::velocity, "velocity"},
                                                             {&Limits::acceleration, "acceleration"},
                                                             {&Limits::deceleration, "deceleration"},
                                                             {&Limits::jerk, "jerk"}};
  for (const auto& [member, field] : fields) {
    for (const double value : bad) {
      for (const std::string& name : {std::string(), std::string("N20 G2")}) {
        Program program = three_moves();
        Move& move = program.moves[1];
        move.name = name;
        move.limits.*member = value;
        const InputError e = validation_error(program);
        const std::string who = name.empty() ? "move 2" : name;
        expect_at(e, move, field);
        EXPECT_TRUE(starts_with(e.detail(), who + ": " + field + " must be positive and finite")) << e.what();
        expect_prints(e.detail(), "got ", value);
      }
    }
  }
}

TEST(Validate, TransitionValuesMustBeNonNegativeAndFinite) {
  const double bad[] = {-1e-3, -std::numeric_limits<double>::denorm_min(), kNaN, -kNaN, kInf, -kInf};
  // each field with the unit users read and the factor from SI to it
  struct Field {
    double Transition::*member;
    const char* name;
    const char* unit;
    double to_unit;
  };
  const Field fields[] = {{&Transition::parameter, "transition.parameter", " mm", 1e3},
                          {&Transition::start_distance, "transition.start_distance", " mm", 1e3},
                          {&Transition::kappa_max, "transition.kappa_max", " 1/mm", 1e-3},
                          {&Transition::velocity, "transition.velocity", " mm/s", 1e3}};
  for (const auto& [member, field, unit, to_unit] : fields) {
    for (const double value : bad) {
      Program program = three_moves();
      Move& move = program.moves[2];
      move.transition.method = Method::kBiclothoid;
      move.transition.*member = value;
      const InputError e = validation_error(program);
      expect_at(e, move, field);
      EXPECT_TRUE(starts_with(e.detail(), "move 3: ")) << e.what();
      EXPECT_TRUE(contains(e.detail(), ">= 0")) << e.what();
      // the value given, in the user's unit
      EXPECT_TRUE(contains(e.detail(), "got " + format_value(value * to_unit) + unit)) << e.what();
    }
  }
}

TEST(Validate, AStartDistanceSizesOnlyABiclothoidAndNotTogetherWithADeviation) {
  for (const Method method : kMethods) {
    if (method == Method::kBiclothoid) continue;
    Program program = three_moves();
    Move& move = program.moves[0];
    move.transition = {.method = method, .start_distance = 0.005};
    const InputError e = validation_error(program);
    expect_at(e, move, "transition.start_distance");
    EXPECT_TRUE(starts_with(e.detail(), "move 1: ")) << e.what();
    EXPECT_TRUE(contains(e.detail(), "only a biclothoid")) << e.what();
    EXPECT_TRUE(contains(e.detail(), "not " + std::string(to_string(method)))) << e.what();
  }
  Program program = three_moves();
  Move& move = program.moves[0];
  move.transition = {.method = Method::kBiclothoid, .parameter = 0.001, .start_distance = 0.005};
  const InputError e = validation_error(program);
  expect_at(e, move, "transition.start_distance");
  EXPECT_TRUE(contains(e.detail(), "not both")) << e.what();
  // either one alone is fine
  move.transition.parameter = 0;
  EXPECT_NO_THROW(validate(program));
  move.transition = {.method = Method::kBiclothoid, .parameter = 0.001};
  EXPECT_NO_THROW(validate(program));
}

TEST(Validate, AToleranceIsPositiveFiniteAndExclusiveWithTheParameterAndTheStartDistance) {
  // below 0 or not a number: named, with the value in mm (0 is "no tolerance": sized by the parameter)
  for (const double value : {-1e-3, -std::numeric_limits<double>::denorm_min(), kNaN, kInf, -kInf}) {
    Program program = three_moves();
    Move& move = program.moves[1];
    move.transition = {.method = Method::kArc, .tolerance = value};
    const InputError e = validation_error(program);
    expect_at(e, move, "transition.tolerance");
    EXPECT_TRUE(starts_with(e.detail(), "move 2: ")) << e.what();
    EXPECT_TRUE(contains(e.detail(), "> 0")) << e.what();
    EXPECT_TRUE(contains(e.detail(), "got " + format_value(value * 1e3) + " mm")) << e.what();
  }
  // with a parameter or a start distance: an error naming both keys
  for (const Method method : kMethods) {
    Program program = three_moves();
    Move& move = program.moves[0];
    move.transition = {.method = method, .parameter = 0.002, .tolerance = 0.001};
    const InputError e = validation_error(program);
    expect_at(e, move, "transition.tolerance");
    EXPECT_TRUE(contains(e.detail(), "transition.tolerance")) << e.what();
    EXPECT_TRUE(contains(e.detail(), "transition.parameter")) << e.what();
    EXPECT_TRUE(contains(e.detail(), "not both")) << e.what();
  }
  Program program = three_moves();
  Move& move = program.moves[0];
  move.transition = {.method = Method::kBiclothoid, .start_distance = 0.005, .tolerance = 0.001};
  const InputError e = validation_error(program);
  expect_at(e, move, "transition.tolerance");
  EXPECT_TRUE(contains(e.detail(), "transition.start_distance")) << e.what();
  EXPECT_TRUE(contains(e.detail(), "transition.tolerance")) << e.what();
  // alone it is fine, for every method (none included: an exact stop meets any tolerance)
  for (const Method method : {Method::kNone, Method::kArc, Method::kBezier, Method::kClothoid, Method::kBiclothoid}) {
    move.transition = {.method = method, .tolerance = 0.001};
    EXPECT_NO_THROW(validate(program)) << to_string(method);
  }
}

TEST(Validate, MovesThatDoNotJoinAreAnInputErrorAtTheSecondMoveWithTheGapInMm) {
  struct Case {
    Vec3 offset;      // m, of the second move's start from the first move's end
    const char* gap;  // as the message prints it
  };
  const Case cases[] = {{Vec3(0.1, 0, 0), "gap 100 mm"},
                        {Vec3(0.003, -0.004, 0), "gap 5 mm"},
                        {Vec3(0, 0, -1e-6), "gap 0.001 mm"},
                        {Vec3(0, 0.002, 0), "gap 2 mm"}};
  for (const Case& c : cases) {
    Program program;
    program.moves = {line_move({0, 0, 0}, {0.1, 0, 0}), line_move(Vec3(0.1, 0, 0) + c.offset, {0.2, 0.1, 0})};
    program.moves[0].name = "N10 G1";
    program.moves[1].name = "N20 G1";
    program.moves[1].where = {"part.ngc", 2, 1};
    const InputError e = validation_error(program);
    expect_at(e, program.moves[1], "geometry");
    EXPECT_EQ(e.detail(), "N20 G1 does not start where N10 G1 ends (" + std::string(c.gap) + ")");
  }
  // after an arc, the gap is measured from the arc's end
  Program program = three_moves();
  program.moves[2] = line_move({0.15, 0.06, 0}, {0.15, 0.15, 0});
  program.moves[2].where = {"cell.yaml", 30, 3};
  const InputError e = validation_error(program);
  expect_at(e, program.moves[2], "geometry");
  EXPECT_TRUE(starts_with(e.detail(), "move 3 does not start where move 2 ends (gap 10 mm)")) << e.what();
}

TEST(Validate, MovesJoinWithinOneBillionthOfTheProgramSize) {
  // the longest move sets the size; a gap of half the tolerance joins, twice the tolerance does not
  for (const double size : {0.1, 2.0, 30.0}) {
    const double tol = 1e-9 * size;
    for (const Vec3& direction : {Vec3(1, 0, 0), Vec3(0, 0.6, 0.8)}) {
      Program program;
      program.moves = {line_move({0, 0, 0}, {size, 0, 0}), line_move({size, 0, 0}, {size, 0.01, 0})};
      program.moves[1].geometry = Line{Vec3(size, 0, 0) + 0.5 * tol * direction, Vec3(size, 0.01, 0)};
      EXPECT_NO_THROW(validate(program)) << size;
      program.moves[1].geometry = Line{Vec3(size, 0, 0) + 2 * tol * direction, Vec3(size, 0.01, 0)};
      EXPECT_EQ(validation_error(program).field(), "geometry") << size;
    }
  }
}

TEST(Validate, AZeroLengthLineIsAnInputErrorNamingTheMove) {
  // exactly zero, and shorter than the join tolerance (1e-9 of the 100 mm program)
  for (const double length : {0.0, 1e-11}) {
    Program program;
    program.moves = {line_move({0, 0, 0}, {0.1, 0, 0}), line_move({0.1, 0, 0}, {0.1, length, 0})};
    program.moves[1].name = "N20 G1";
    program.moves[1].where = {"part.ngc", 2, 1};
    const InputError e = validation_error(program);
    expect_at(e, program.moves[1], "geometry");
    EXPECT_TRUE(starts_with(e.detail(), "N20 G1 has zero length")) << e.what();
  }
}

// The join tolerance is relative to the longest move, so beside a huge move a normal one is
// below it: the message names that cause (the huge move and the tolerance), not "zero length".
TEST(Validate, AMoveShorterThanTheToleranceOfAHugeMoveNamesTheHugeMove) {
  Program program;
  program.moves = {line_move({0, 0, 0}, {0.01, 0, 0}), line_move({0.01, 0, 0}, {0.01, 1e27, 0})};
  program.moves[0].name = "line 2 G1";
  program.moves[0].where = {"part.ngc", 2, 1};
  program.moves[1].name = "line 3 G1";
  const InputError e = validation_error(program);
  expect_at(e, program.moves[0], "geometry");
  EXPECT_TRUE(starts_with(e.detail(), "line 2 G1 (10 mm) is too short to be told from a point; the join tolerance 1e+21 mm "
                                      "is 1e-9 of the longest move, line 3 G1 of 1e+30 mm"))
      << e.what();
  EXPECT_EQ(e.detail().find("zero length"), std::string::npos) << e.what();
}

TEST(Validate, ANonFiniteCoordinateIsNamedAsSuchWhereverItIs) {
  // on a line, or anywhere on an arc: its centre, axes, radius, sweep or rise; an arc with a NaN
  // centre has a finite radius, sweep and length, so only its points show the NaN
  const Vec3 a(0.1, 0, 0);
  const Vec3 b(0.2, 0.1, 0);
  const Arc arc{Vec3(0.1, 0.05, 0), -Vec3::UnitY(), Vec3::UnitX(), 0.05, kPi / 2, 0};
  std::vector<std::pair<Primitive, std::string>> cases = {
      {Line{a, Vec3(kNaN, 0.1, 0)}, "line end x NaN"},
      {Line{Vec3(0.1, -kNaN, 0), b}, "line start y -NaN"},
      {Line{a, Vec3(0.2, 0.1, kInf)}, "line end z inf"},
      {Line{Vec3(0.1, -kInf, 0), b}, "line start y -inf"},
      {Line{Vec3(kInf, 0, 0), Vec3(kInf, 0, 0)}, "line start and end x inf"},
  };
  for (const double bad : {kNaN, kInf, -kInf}) {
    const std::string value = std::isnan(bad) ? " NaN" : bad > 0 ? " inf" : " -inf";
    for (int i = 0; i < 3; ++i) {
      Arc c = arc;
      c.center[i] = bad;
      cases.push_back({c, "arc centre" + value});
      c = arc;
      c.u[i] = bad;
      cases.push_back({c, "arc u" + value});
      c = arc;
      c.v[i] = bad;
      cases.push_back({c, "arc v" + value});
    }
    for (double Arc::*field : {&Arc::radius, &Arc::sweep, &Arc::rise}) {
      Arc c = arc;
      c.*field = bad;
      cases.push_back({c, "arc radius, sweep or rise" + value});
    }
  }
  for (const auto& [geometry, what] : cases) {
    // as the first move, and as a second move after a valid line
    for (const std::size_t at : {0u, 1u}) {
      Program program;
      program.moves = {line_move({0, 0, 0}, a), line_move(a, b)};
      program.moves[at].geometry = geometry;
      program.moves[at].where = {"cell.yaml", 5, 7};
      const InputError e = validation_error(program);
      expect_at(e, program.moves[at], "geometry");
      EXPECT_TRUE(starts_with(e.detail(), "move " + std::to_string(at + 1) +
                                              " has a coordinate that is not a finite number"))
          << what << ": " << e.what();
    }
  }
}

TEST(Validate, ADegenerateArcIsNamedBeforeItsLengthOrPoints) {
  // zero or negative radius or sweep; its length comes out 0, negative or NaN, and so may its
  // points: the message names the cause
  struct Case {
    double radius, sweep, rise;
    const char* says;
  };
  const Case cases[] = {{0, kPi / 2, 0, "radius 0 mm, sweep 90 deg"},
                        {0.05, 0, 0, "radius 50 mm, sweep 0 deg"},
                        {0, 0, 0, "radius 0 mm, sweep 0 deg"},
                        {-0.05, kPi, 0, "radius -50 mm, sweep 180 deg"},
                        {0.05, -kPi / 2, 0, "radius 50 mm, sweep -90 deg"},
                        {0, kPi, 0.01, "radius 0 mm, sweep 180 deg"},
                        {0.05, 0, 0.01, "radius 50 mm, sweep 0 deg"}};
  for (const Case& c : cases) {
    for (const std::size_t at : {0u, 1u}) {
      Program program = three_moves();
      program.moves[at].geometry = Arc{Vec3(0.1, 0.05, 0), -Vec3::UnitY(), Vec3::UnitX(), c.radius, c.sweep, c.rise};
      const InputError e = validation_error(program);
      expect_at(e, program.moves[at], "geometry");
      EXPECT_EQ(e.detail(), "move " + std::to_string(at + 1) + " is a degenerate arc (" + c.says + ")");
    }
  }
}

bool coin(std::mt19937_64& rng) { return test::uniform(rng, 0, 1) < 0.5; }

// A valid program of 1 to 6 joined lines and arcs (helices too) with random limits, buffer modes
// and transitions, some moves named; move k written on line 10 (k + 1), column k + 1.
Program random_program(std::mt19937_64& rng) {
  Program program;
  const int n = 1 + static_cast<int>(test::uniform(rng, 0, 6));
  Vec3 at(test::uniform(rng, -1, 1), test::uniform(rng, -1, 1), test::uniform(rng, -1, 1));
  for (int k = 0; k < n; ++k) {
    Move move;
    if (coin(rng)) {
      move.geometry = Line{at, at + test::log_uniform(rng, 1e-3, 1.0) * test::random_unit(rng)};
    } else {
      const Vec3 u = test::random_unit(rng);
      const Vec3 v = u.cross(test::random_unit(rng)).normalized();
      const double radius = test::log_uniform(rng, 1e-3, 0.5);
      const double rise = coin(rng) ? 0.0 : test::uniform(rng, -0.1, 0.1);
      move.geometry = Arc{at - radius * u, u, v, radius, test::uniform(rng, 0.05, 3 * kPi), rise};
    }
    at = point(move.geometry, length(move.geometry));
    move.limits = {test::log_uniform(rng, 1e-3, 2), test::log_uniform(rng, 1e-2, 20), test::log_uniform(rng, 1e-2, 20),
                   test::log_uniform(rng, 1e-1, 1e3)};
    move.buffer = kBufferModes[static_cast<std::size_t>(test::uniform(rng, 0, 6))];
    move.transition.method = kMethods[static_cast<std::size_t>(test::uniform(rng, 0, 5))];
    if (move.transition.method == Method::kBiclothoid && coin(rng)) {
      move.transition.start_distance = test::log_uniform(rng, 1e-4, 1e-2);
    } else if (coin(rng)) {
      move.transition.parameter = test::log_uniform(rng, 1e-4, 1e-2);
    }
    if (coin(rng)) move.transition.kappa_max = test::log_uniform(rng, 1, 1e3);
    if (coin(rng)) move.transition.velocity = test::log_uniform(rng, 1e-3, 1);
    if (coin(rng)) move.name = "N" + std::to_string(10 * (k + 1)) + " G1";
    move.where = {"prog.ngc", 10 * (k + 1), k + 1};
    program.moves.push_back(move);
  }
  return program;
}

void translate(Primitive& geometry, const Vec3& offset) {
  if (Line* line = std::get_if<Line>(&geometry)) {
    line->p0 += offset;
    line->p1 += offset;
  } else {
    std::get<Arc>(geometry).center += offset;
  }
}

TEST(Validate, RandomValidProgramsPassAndOneBrokenMoveIsReportedAtThatMove) {
  // break one field of one move of a valid program: validate names that field and that move,
  // located where the move was written, whatever comes before or after it
  const double bad_limits[] = {0.0, -0.0, -0.5, kNaN, kInf, -kInf};
  const double bad_coordinates[] = {kNaN, -kNaN, kInf, -kInf};
  const int cases = test::property_cases(3000);
  for (int i = 0; i < cases; ++i) {
    auto rng = test::make_rng(static_cast<std::uint64_t>(i));
    const std::string seed = test::seed_text(static_cast<std::uint64_t>(i));
    Program program = random_program(rng);
    ASSERT_NO_THROW(validate(program)) << seed;

    const std::size_t k = static_cast<std::size_t>(test::uniform(rng, 0, static_cast<double>(program.moves.size())));
    Move& move = program.moves[k];
    const std::string who = move.name.empty() ? "move " + std::to_string(k + 1) : move.name;
    const auto pick = [&rng](const auto& values) {
      return values[static_cast<std::size_t>(test::uniform(rng, 0, static_cast<double>(std::size(values))))];
    };
    std::string field = "geometry";
    std::string says;
    switch (static_cast<int>(test::uniform(rng, 0, 9))) {
      case 0: {
        double Limits::*const members[] = {&Limits::velocity, &Limits::acceleration, &Limits::deceleration, &Limits::jerk};
        const char* const names[] = {"velocity", "acceleration", "deceleration", "jerk"};
        const std::size_t j = static_cast<std::size_t>(test::uniform(rng, 0, 4));
        move.limits.*members[j] = pick(bad_limits);
        field = names[j];
        says = who + ": " + field + " must be positive and finite";
        break;
      }
      case 1:
        move.transition.parameter = pick(std::array{-1e-3, kNaN, kInf, -kInf});
        move.transition.start_distance = 0;
        field = "transition.parameter";
        says = who + ": the transition parameter must be >= 0";
        break;
      case 2:
        move.transition.kappa_max = -test::log_uniform(rng, 1e-3, 1e3);
        field = "transition.kappa_max";
        says = who + ": the curvature cap must be >= 0";
        break;
      case 3:
        move.transition.velocity = coin(rng) ? kNaN : -test::log_uniform(rng, 1e-3, 1);
        field = "transition.velocity";
        says = who + ": the transition velocity must be >= 0";
        break;
      case 4:
        move.transition.method = pick(std::array{Method::kNone, Method::kArc, Method::kBezier, Method::kClothoid});
        move.transition.parameter = 0;
        move.transition.start_distance = test::log_uniform(rng, 1e-4, 1e-2);
        field = "transition.start_distance";
        says = who + ": a start distance sizes only a biclothoid transition";
        break;
      case 5: {
        const Vec3 start = point(move.geometry, 0.0);
        move.geometry = Line{start, start};
        says = who + " has zero length";
        break;
      }
      case 6: {
        // a non-finite coordinate of a line's end or an arc's centre
        const int axis = static_cast<int>(test::uniform(rng, 0, 3));
        if (Line* line = std::get_if<Line>(&move.geometry)) {
          line->p1[axis] = pick(bad_coordinates);
        } else {
          std::get<Arc>(move.geometry).center[axis] = pick(bad_coordinates);
        }
        says = who + " has a coordinate that is not a finite number";
        break;
      }
      case 7: {
        // a degenerate arc in place of the move, starting where it did
        const Vec3 start = point(move.geometry, 0.0);
        const bool zero_radius = coin(rng);
        const double radius = zero_radius ? 0.0 : 0.01;
        move.geometry = Arc{start - radius * Vec3::UnitX(), Vec3::UnitX(), Vec3::UnitY(), radius,
                            zero_radius ? 1.0 : 0.0, 0};
        says = who + " is a degenerate arc";
        break;
      }
      default: {
        // a gap: this move and the rest shifted away from the previous end
        if (k == 0) continue;
        const Vec3 offset = test::log_uniform(rng, 1e-6, 1e-2) * test::random_unit(rng);
        for (std::size_t j = k; j < program.moves.size(); ++j) translate(program.moves[j].geometry, offset);
        const Move& previous = program.moves[k - 1];
        says = who + " does not start where " + (previous.name.empty() ? "move " + std::to_string(k) : previous.name) +
               " ends (gap ";
        // the gap between points a few metres from the origin, to 1e-12 m (1e-9 mm)
        expect_prints(validation_error(program).detail(), "(gap ", offset.norm() * 1e3, 1e-9);
        break;
      }
    }
    const InputError e = validation_error(program);
    expect_at(e, move, field);
    EXPECT_TRUE(starts_with(e.detail(), says)) << seed << "\n" << e.what() << "\nexpected: " << says;
  }
}

}  // namespace
}  // namespace blendbench
