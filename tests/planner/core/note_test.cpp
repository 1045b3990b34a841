#include "blendbench/core/note.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>

#include "blendbench/core/format.hpp"
#include "support/property.hpp"

namespace blendbench {
namespace {

TEST(Note, ADeferredNoteReadsAsTheLengthsNoteBuiltAtOnce) {
  // random lengths of either sign from 1e-12 m to 1e3 m, and the zero, infinite and NaN ones:
  // the text made when the note is read is lengths_note's, with any appended text after it
  const int cases = test::property_cases(2000);
  for (int i = 0; i < cases; ++i) {
    auto rng = test::make_rng(static_cast<std::uint64_t>(i));
    const std::string seed = test::seed_text(static_cast<std::uint64_t>(i));
    const auto length = [&] {
      const double magnitude = std::pow(10.0, test::uniform(rng, -12, 3));
      return test::uniform(rng, 0, 1) < 0.5 ? -magnitude : magnitude;
    };
    const double special[] = {0.0, -0.0, HUGE_VAL, -HUGE_VAL, std::nan("")};
    const double first = i < 5 ? special[i] : length();
    const double second = length();
    const std::string eager =
        lengths_note("deviation ", first, " below the tolerance ", second, "the fillet is limited by the move lengths");
    Note note = Note::lengths("deviation ", first, " below the tolerance ", second, "the fillet is limited by the move lengths");
    EXPECT_FALSE(note.empty()) << seed;
    EXPECT_EQ(note.text(), eager) << seed;
    note += "; and more";
    EXPECT_EQ(note.text(), eager + "; and more") << seed;
    std::ostringstream printed;
    printed << note;
    EXPECT_EQ(printed.str(), eager + "; and more") << seed;
    EXPECT_EQ(note, Note(eager + "; and more")) << seed;  // equal by their text
    EXPECT_NE(note, Note(eager)) << seed;
  }
}

TEST(Note, PlainTextEmptinessAndClear) {
  Note note;
  EXPECT_TRUE(note.empty());
  EXPECT_EQ(note.text(), "");
  note += "the moves part";
  EXPECT_FALSE(note.empty());
  EXPECT_EQ(note.text(), "the moves part");
  EXPECT_EQ(Note(std::string("x")).text(), "x");
  Note lengths = Note::lengths("shrunk from ", 2e-3, " to ", 1e-3, "a move is short");
  EXPECT_EQ(lengths.text(), "shrunk from 2 mm to 1 mm: a move is short");
  lengths.clear();
  EXPECT_TRUE(lengths.empty());
  EXPECT_EQ(lengths.text(), "");
}

}  // namespace
}  // namespace blendbench
