#include "blendbench/core/format.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <new>
#include <stdexcept>
#include <numbers>
#include <string>
#include <vector>

#include "blendbench/core/input_error.hpp"
#include "support/property.hpp"

namespace blendbench {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
// the largest error of a value printed with six significant digits, relative to the value,
// with room for the rounding of the unit conversion itself
constexpr double kSixDigits = 5e-6 * (1 + 1e-9);

// Each formatter with the unit it prints and the factor from SI to that unit.
struct Unit {
  std::string (*format)(double);
  const char* name;
  double scale;
};
const Unit kUnits[] = {{format_mm, "mm", 1e3}, {format_deg, "deg", 180 / kPi}, {format_per_mm, "1/mm", 1e-3}};

// Significant digits of a printed number: the mantissa's digits without leading or trailing zeros.
int significant_digits(const std::string& number) {
  std::string digits;
  for (const char c : number.substr(0, number.find('e'))) {
    if (c >= '0' && c <= '9') digits += c;
  }
  const std::size_t first = digits.find_first_not_of('0');
  if (first == std::string::npos) return 0;
  return static_cast<int>(digits.find_last_not_of('0') - first + 1);
}

TEST(Format, TheHeaderExamples) {
  EXPECT_EQ(format_mm(0.0125), "12.5 mm");
  EXPECT_EQ(format_deg(kPi / 2), "90 deg");
  EXPECT_EQ(format_per_mm(124.0), "0.124 1/mm");
}

TEST(Format, ConvertsToTheUnitUsersReadWithSixSignificantDigits) {
  // hand-rounded: 1234.56789 mm, 57.29578 deg (1 rad), 1e9 mm
  struct Case {
    std::string text, expected;
  };
  const Case cases[] = {
      {format_mm(0.1), "100 mm"},
      {format_mm(1.23456789), "1234.57 mm"},
      {format_mm(-0.00123456789), "-1.23457 mm"},
      {format_mm(123456.789), "1.23457e+08 mm"},
      {format_mm(1e-9), "1e-06 mm"},
      {format_mm(-2.5e-7), "-0.00025 mm"},
      {format_deg(1.0), "57.2958 deg"},
      {format_deg(kPi), "180 deg"},
      {format_deg(-kPi / 4), "-45 deg"},
      {format_deg(6 * kPi), "1080 deg"},
      {format_per_mm(1.0), "0.001 1/mm"},
      {format_per_mm(1 / 0.0125), "0.08 1/mm"},
      {format_per_mm(-2500.0), "-2.5 1/mm"},
      {format_value(-1e-7), "-1e-07"},
      {format_value(0.2), "0.2"},
      {format_value(1234567.0), "1.23457e+06"},
  };
  for (const Case& c : cases) EXPECT_EQ(c.text, c.expected);
}

TEST(Format, RandomValuesParseBackToTheConvertedValueWithinSixSignificantDigits) {
  // magnitudes from 1e-12 to 1e12 of either sign: the text is "<number> <unit>", the number has
  // at most six significant digits, is the converted value to within half a unit in the sixth
  // digit, and a negative value prints as its magnitude with a minus sign
  const int cases = test::property_cases(5000);
  for (int i = 0; i < cases; ++i) {
    auto rng = test::make_rng(static_cast<std::uint64_t>(i));
    const std::string seed = test::seed_text(static_cast<std::uint64_t>(i));
    const double magnitude = std::pow(10.0, test::uniform(rng, -12, 12));
    const double value = test::uniform(rng, 0, 1) < 0.5 ? -magnitude : magnitude;
    for (const Unit& unit : kUnits) {
      const std::string text = unit.format(value);
      const std::string suffix = std::string(" ") + unit.name;
      ASSERT_GT(text.size(), suffix.size()) << seed << " " << text;
      EXPECT_EQ(text.substr(text.size() - suffix.size()), suffix) << seed << " " << text;
      const std::string number = text.substr(0, text.size() - suffix.size());
      EXPECT_EQ(number, format_value(value * unit.scale)) << seed;
      char* end = nullptr;
      const double printed = std::strtod(number.c_str(), &end);
      EXPECT_EQ(end, number.c_str() + number.size()) << seed << " '" << number << "'";
      const double expected = value * unit.scale;
      EXPECT_LE(std::abs(printed - expected), kSixDigits * std::abs(expected)) << seed << " " << text;
      EXPECT_LE(significant_digits(number), 6) << seed << " " << text;
      EXPECT_EQ(unit.format(-value), value < 0 ? text.substr(1) : "-" + text) << seed;
    }
  }
}

TEST(Format, ZeroPrintsAsZeroWhateverItsSign) {
  for (const double zero : {0.0, -0.0}) {
    EXPECT_EQ(format_mm(zero), "0 mm") << std::signbit(zero);
    EXPECT_EQ(format_deg(zero), "0 deg") << std::signbit(zero);
    EXPECT_EQ(format_per_mm(zero), "0 1/mm") << std::signbit(zero);
    EXPECT_EQ(format_value(zero), "0") << std::signbit(zero);
  }
}

TEST(Format, InfinitiesKeepTheirSign) {
  for (const Unit& unit : kUnits) {
    EXPECT_EQ(unit.format(kInf), std::string("inf ") + unit.name);
    EXPECT_EQ(unit.format(-kInf), std::string("-inf ") + unit.name);
  }
  EXPECT_EQ(format_value(kInf), "inf");
  EXPECT_EQ(format_value(-kInf), "-inf");
}

TEST(Format, NaNPrintsAsNanWhateverItsSign) {
  // a NaN's sign means nothing; x86 arithmetic makes negative ones (inf - inf)
  volatile double inf = kInf;
  const double computed = inf - inf;
  const double nans[] = {kNaN, -kNaN, std::copysign(kNaN, -1.0), computed,
                         -std::numeric_limits<double>::signaling_NaN()};
  ASSERT_TRUE(std::signbit(-kNaN));
  ASSERT_TRUE(std::signbit(std::copysign(kNaN, -1.0)));
  for (const double nan : nans) {
    ASSERT_TRUE(std::isnan(nan));
    for (const Unit& unit : kUnits) EXPECT_EQ(unit.format(nan), std::string("nan ") + unit.name) << std::signbit(nan);
    EXPECT_EQ(format_value(nan), "nan") << std::signbit(nan);
  }
}

// append_mm, the notes' formatter that writes into the note itself, appends exactly format_mm's
// text: random magnitudes of either sign, and zeros, infinities and NaNs of either sign
TEST(Format, AppendMmAppendsFormatMmsText) {
  const int cases = test::property_cases(5000);
  std::vector<double> values = {0.0, -0.0, kInf, -kInf, kNaN, -kNaN};
  for (int i = 0; i < cases; ++i) {
    auto rng = test::make_rng(static_cast<std::uint64_t>(i));
    const double magnitude = std::pow(10.0, test::uniform(rng, -12, 12));
    values.push_back(test::uniform(rng, 0, 1) < 0.5 ? -magnitude : magnitude);
  }
  for (std::size_t i = 0; i < values.size(); ++i) {
    std::string note = "shrunk from ";
    append_mm(note, values[i]);
    EXPECT_EQ(note, "shrunk from " + format_mm(values[i])) << "value " << i << " (" << values[i] << ")";
  }
}

TEST(Printable, KeepsTextAndWellFormedUtf8AndEscapesTheRest) {
  EXPECT_EQ(printable("velocity: 200 mm/s"), "velocity: 200 mm/s");
  EXPECT_EQ(printable("X\u22125 \u00b0"), "X\u22125 \u00b0");  // U+2212 minus, U+00B0 degree
  EXPECT_EQ(printable("a\nb\tc"), "a\\nb\\tc");
  EXPECT_EQ(printable(std::string("\x01\x7f\x1b[2J", 6)), "\\x01\\x7f\\x1b[2J");
  EXPECT_EQ(printable(std::string("nul\0!", 5)), "nul\\x00!");
  EXPECT_EQ(printable("\xff\xfe"), "\\xff\\xfe");                  // never UTF-8
  EXPECT_EQ(printable("\xe2\x88"), "\\xe2\\x88");                  // a sequence cut short
  EXPECT_EQ(printable("\xc0\xaf"), "\\xc0\\xaf");                  // overlong '/'
  EXPECT_EQ(printable("\xed\xa0\x80"), "\\xed\\xa0\\x80");          // a UTF-16 surrogate
  EXPECT_EQ(printable("\xf4\x90\x80\x80"), "\\xf4\\x90\\x80\\x80");  // beyond U+10FFFF
  EXPECT_EQ(printable("\xc2\x85"), "\\xc2\\x85");                  // C1 control NEL
}

TEST(Printable, RandomBytesBecomeOneLineOfPrintableText) {
  const int cases = test::property_cases(2000);
  for (int c = 0; c < cases; ++c) {
    const std::uint64_t seed = 0x9e7ab1e0 + static_cast<std::uint64_t>(c);
    std::mt19937_64 rng = test::make_rng(seed);
    std::string bytes(1 + rng() % 40, '\0');
    for (char& b : bytes) b = static_cast<char>(rng() % 256);
    const std::string out = printable(bytes);
    // no control byte survives, and the result is its own printable form (well-formed UTF-8)
    for (const char b : out) {
      const auto u = static_cast<unsigned char>(b);
      ASSERT_FALSE(u < 0x20 || u == 0x7F) << test::seed_text(seed);
    }
    ASSERT_EQ(printable(out), out) << test::seed_text(seed);
  }
}

// Well-formed UTF-8 by the other formulation of RFC 3629: decode each sequence to its code point
// from the lead byte's length and the continuation bits, then refuse by value (shorter than the
// shortest form, a surrogate, beyond U+10FFFF) -- where is_utf8 checks the bytes' ranges.
bool utf8_by_code_points(const std::string& text) {
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    std::size_t len = 0;
    std::uint32_t point = 0;
    if (c < 0x80) {
      ++i;
      continue;
    }
    if ((c & 0xE0) == 0xC0) {
      len = 2;
      point = c & 0x1F;
    } else if ((c & 0xF0) == 0xE0) {
      len = 3;
      point = c & 0x0F;
    } else if ((c & 0xF8) == 0xF0) {
      len = 4;
      point = c & 0x07;
    } else {
      return false;  // a continuation byte first, or 0xF8-0xFF
    }
    if (i + len > text.size()) return false;
    for (std::size_t k = 1; k < len; ++k) {
      const auto b = static_cast<unsigned char>(text[i + k]);
      if ((b & 0xC0) != 0x80) return false;
      point = (point << 6) | (b & 0x3F);
    }
    const std::uint32_t shortest[] = {0, 0, 0x80, 0x800, 0x10000};
    if (point < shortest[len] || (point >= 0xD800 && point <= 0xDFFF) || point > 0x10FFFF) return false;
    i += len;
  }
  return true;
}

// Issue 42: a file named "t\xff.yaml" reached nlohmann's JSON writer, which refused it after the
// run (type_error 316). is_utf8 decides what a JSON output can hold: checked against the decoder
// above on random bytes biased to UTF-8's ranges.
TEST(IsUtf8, AgreesWithADecoderByCodePointsOnRandomBytes) {
  EXPECT_TRUE(is_utf8(""));
  EXPECT_TRUE(is_utf8("a\nb\x01 X\u22125 \u00b0 \U0010FFFF"));
  for (const char* bad : {"\xff", "\xe2\x88", "\xc0\xaf", "\xed\xa0\x80", "\xf4\x90\x80\x80", "t\xff.yaml"}) {
    EXPECT_FALSE(is_utf8(bad)) << printable(bad);
    EXPECT_FALSE(utf8_by_code_points(bad)) << printable(bad);
  }
  const int cases = test::property_cases(20000);
  int valid = 0;
  for (int c = 0; c < cases; ++c) {
    const std::uint64_t seed = 0x07f8c0de + static_cast<std::uint64_t>(c);
    std::mt19937_64 rng = test::make_rng(seed);
    std::string bytes(1 + rng() % 6, '\0');
    for (char& b : bytes) {
      // ASCII, a continuation byte, or a lead byte (with its edge values: C0/C1, E0, ED, F0, F4, F5)
      switch (rng() % 4) {
        case 0: b = static_cast<char>(rng() % 0x80); break;
        case 1: b = static_cast<char>(0x80 + rng() % 0x40); break;
        default: b = static_cast<char>(0xC0 + rng() % 0x40); break;
      }
    }
    const bool expected = utf8_by_code_points(bytes);
    valid += expected ? 1 : 0;
    ASSERT_EQ(is_utf8(bytes), expected) << printable(bytes) << " " << test::seed_text(seed);
  }
  // the draw reaches both answers
  EXPECT_GT(valid, cases / 50);
  EXPECT_LT(valid, cases - cases / 50);
}

TEST(Printable, InputErrorMessagesAreEscapedButFieldAndFileKeptAsGiven) {
  const InputError e("bin\x01.yaml", 3, 7, "na\x02me", "unknown key '\x1b[31m'");
  EXPECT_EQ(std::string(e.what()), "bin\\x01.yaml:3:7: 'na\\x02me': unknown key '\\x1b[31m'");
  EXPECT_EQ(e.detail(), "unknown key '\\x1b[31m'");
  EXPECT_EQ(e.field(), "na\x02me");
  EXPECT_EQ(e.file(), "bin\x01.yaml");
}

// Issue 42: a library's exception raised by bad input ("number overflow parsing '1e400'",
// "filesystem error: Too many levels of symbolic links") becomes a positioned InputError; an
// InputError, running out of memory and a stop request pass as they are.
TEST(InputErrorBoundary, ALibrarysExceptionBecomesBadInputAtItsPlace) {
  const SourceRef where{"run/summary.json", 0, 0};
  const auto through = [&](const auto& raise) {
    try {
      try {
        raise();
      } catch (...) {
        rethrow_as_input_error(where, "variants", "not a run summary: ");
      }
    } catch (const InputError& e) {
      return std::string(e.what());
    } catch (const std::bad_alloc&) {
      return std::string("bad_alloc");
    } catch (int signal) {
      return "signal " + std::to_string(signal);
    }
    return std::string("nothing");
  };
  EXPECT_EQ(through([] { throw std::out_of_range("number overflow parsing '1e400'\n"); }),
            "run/summary.json: 'variants': not a run summary: number overflow parsing '1e400'\\n");
  EXPECT_EQ(through([] { throw InputError("a.yaml", 2, 3, "key", "as it was"); }), "a.yaml:2:3: 'key': as it was");
  EXPECT_EQ(through([] { throw std::bad_alloc(); }), "bad_alloc");
  EXPECT_EQ(through([] { throw 15; }), "signal 15");
}

}  // namespace
}  // namespace blendbench
