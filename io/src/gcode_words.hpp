#pragma once
// Private to io/src (not installed): the words of one G-code block sorted and checked against
// the RS274/NGC tables for the reader (gcode.cpp) — which letters and G/M codes are supported,
// their modal groups, and the one-word-per-letter and one-code-per-group rules of a line.

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "gcode_lexer.hpp"

namespace blendbench::gcode_detail {

// Modal groups of the supported G codes (RS274/NGC table 4), for the one-per-line rule.
enum class GGroup { kNonModal, kMotion, kPlane, kDistance, kArcDistance, kFeedMode, kUnits, kCutterComp,
                    kToolLength, kCoordSystem, kPathControl, kSpindleMode, kRetractMode, kLatheDiameter };
// The group of a supported G code given as ten times its number (G90.1 -> 901), else nullopt.
std::optional<GGroup> group_of(int code);

// M codes: groups for the one-per-line rule (RS274/NGC), nullopt when unsupported.
enum class MGroup { kStop, kToolChange, kSpindle, kCoolant, kOverride };
std::optional<MGroup> m_group_of(int code);

// A G or M code of the line (G codes as ten times their number) and the word that gave it.
using Code = std::pair<int, const Word*>;

// The words of one line after the checks: each letter once (G and M may repeat across modal
// groups), G and M codes in the order written. Points into the words given to sort_words.
struct LineWords {
  std::array<const Word*, 28> by_letter{};  // A-Z, then '@' and '^' (polar radius and angle)
  std::vector<const Word*> in_order;  // the words other than G and M, as written
  std::vector<Code> g_codes;
  std::vector<Code> m_codes;

  // The word with this (upper-case) letter, or nullptr.
  [[nodiscard]] const Word* get(char letter) const { return by_letter[slot_of(letter)]; }
  // The index of a letter in by_letter.
  static std::size_t slot_of(char letter) {
    return letter == '@' ? 26 : letter == '^' ? 27 : static_cast<std::size_t>(letter - 'A');
  }
  // The first word written whose letter is one of `letters`, or nullptr.
  [[nodiscard]] const Word* first_of(std::string_view letters) const;
  // The line's G code of this modal group, or nullopt.
  [[nodiscard]] std::optional<Code> g_in(GGroup group) const;
};

// Sorts the words of line `line` (without its N word) and checks them: unsupported letters,
// axes (A, B, C are accepted when `tool_angles`), G and M codes, a letter given twice, two codes
// of one modal group (except G80 beside another motion code, which LinuxCNC ignores: read_g). Throws InputError(file, line, column, word, message) at the first word
// that breaks a rule.
LineWords sort_words(const std::vector<Word>& words, int line, const std::string& file, bool tool_angles);

}  // namespace blendbench::gcode_detail
