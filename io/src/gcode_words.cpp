// The words of one G-code block sorted and checked (gcode_words.hpp).

#include "gcode_words.hpp"

#include <algorithm>
#include <cmath>

#include "blendbench/core/input_error.hpp"

namespace blendbench::gcode_detail {
namespace {

// G code numbers are handled as ten times their value (G90.1 -> 901), as in LinuxCNC.
std::optional<int> code_times_ten(double value) {
  const double scaled = value * 10;
  const double rounded = std::round(scaled);
  if (std::abs(scaled - rounded) > 1e-6 || rounded < 0 || rounded > 10000) return std::nullopt;
  return static_cast<int>(rounded);
}

// What is wrong with a G code the reader does not support; nullptr for unknown codes.
const char* rejected_g_reason(int code) {
  switch (code) {
    case 410: case 411: case 420: case 421:
      return "cutter radius compensation (G41/G42) changes the path and is not supported";
    case 700: case 710: case 711: case 712: case 720: case 721: case 722: case 740: case 760:
      return "lathe canned cycles (G70-G72, G74, G76) are not supported";
    case 870:
      return "back boring (G87) is not supported (it orients the spindle and moves around the hole)";
    case 880:
      return "G88 is not supported (the operator retracts the tool by hand: the path is not the program's)";
    case 50: case 51: case 52: case 53:
      return "splines and NURBS (G5, G5.1, G5.2, G5.3) are not supported";
    case 382: case 383: case 384: case 385:
      return "probing (G38) is not supported";
    case 930:
      return "inverse-time feed (G93) is not supported (units per minute G94 and per revolution G95 are)";
    case 171: case 181: case 191:
      return "planes G17.1, G18.1, G19.1 are not supported (LinuxCNC does not support them either)";
    default:
      return nullptr;
  }
}

// Throws InputError at a word of line `line` of `file`.
struct Fail {
  const std::string& file;
  int line;
  [[noreturn]] void operator()(int column, const std::string& word, const std::string& message) const {
    throw InputError(file, line, column, word, message);
  }
};

}  // namespace

std::optional<GGroup> group_of(int code) {
  switch (code) {
    case 0: case 10: case 20: case 30: case 330: case 331: case 730: case 800: case 810: case 820: case 830: case 840:
    case 850: case 860: case 890:
      return GGroup::kMotion;
    case 40: case 100: case 280: case 281: case 300: case 301: case 520: case 530: case 920: case 921: case 922: case 923:
      return GGroup::kNonModal;
    case 170: case 180: case 190: return GGroup::kPlane;
    case 900: case 910: return GGroup::kDistance;
    case 901: case 911: return GGroup::kArcDistance;
    case 940: case 950: return GGroup::kFeedMode;
    case 70: case 80: return GGroup::kLatheDiameter;
    case 200: case 210: return GGroup::kUnits;
    case 400: return GGroup::kCutterComp;
    case 430: case 431: case 432: case 490: return GGroup::kToolLength;
    case 540: case 550: case 560: case 570: case 580: case 590: case 591: case 592: case 593:
      return GGroup::kCoordSystem;
    case 610: case 611: case 640: return GGroup::kPathControl;
    case 960: case 970: return GGroup::kSpindleMode;
    case 980: case 990: return GGroup::kRetractMode;
    default: return std::nullopt;
  }
}

std::optional<MGroup> m_group_of(int code) {
  switch (code) {
    case 0: case 1: case 2: case 30: return MGroup::kStop;
    case 6: return MGroup::kToolChange;
    case 3: case 4: case 5: return MGroup::kSpindle;
    case 7: case 8: case 9: return MGroup::kCoolant;
    case 48: case 49: case 50: case 51: case 52: case 53: return MGroup::kOverride;
    default: return std::nullopt;
  }
}

std::optional<Code> LineWords::g_in(GGroup group) const {
  for (const Code& g : g_codes) {
    if (group_of(g.first) == group) return g;
  }
  return std::nullopt;
}

const Word* LineWords::first_of(std::string_view letters) const {
  for (const Word* w : in_order) {
    if (letters.find(w->letter) != std::string_view::npos) return w;
  }
  return nullptr;
}

LineWords sort_words(const std::vector<Word>& words, int line, const std::string& file, bool tool_angles) {
  const Fail fail{file, line};
  LineWords out;
  // one of each letter (G and M may repeat across modal groups)
  for (const Word& w : words) {
    switch (w.letter) {
      case 'G': {
        const std::optional<int> code = code_times_ten(w.value);
        if (!code) fail(w.column, w.text, "not a G code");
        if (const char* reason = rejected_g_reason(*code)) fail(w.column, w.text, reason);
        if (!group_of(*code)) fail(w.column, w.text, "unsupported G code");
        out.g_codes.emplace_back(*code, &w);
        continue;
      }
      case 'M': {
        const double rounded = std::round(w.value);
        if (rounded != w.value || rounded < 0 || rounded > 10000) fail(w.column, w.text, "not an M code");
        const int code = static_cast<int>(rounded);
        if (code == 98 || code == 99) fail(w.column, w.text, "subprogram calls (M98/M99) are not supported");
        if (!m_group_of(code)) fail(w.column, w.text, "unsupported M code");
        out.m_codes.emplace_back(code, &w);
        continue;
      }
      case 'A': case 'B': case 'C':
        if (tool_angles) break;
        fail(w.column, w.text, std::string("axis ") + w.letter +
                                   " is not supported (only X, Y, Z; a scenario's program.gcode_angles maps A, B, C to tool angles)");
      case 'U': case 'V': case 'W':
        fail(w.column, w.text, std::string("axis ") + w.letter + " is not supported (only X, Y, Z)");
      case 'N':
        fail(w.column, w.text, "the line number N must be the first word of the line");
      case 'X': case 'Y': case 'Z': case 'I': case 'J': case 'K': case 'R': case 'P': case 'Q':
      case 'F': case 'S': case 'T': case 'H': case 'D': case 'L': case '@': case '^':
        break;
      default:
        fail(w.column, w.text, std::string("unknown word letter '") + w.letter + "'");
    }
    const Word*& slot = out.by_letter[LineWords::slot_of(w.letter)];
    if (slot) fail(w.column, w.text, std::string("word '") + w.letter + "' given twice on one line");
    slot = &w;
    out.in_order.push_back(&w);
  }

  // LinuxCNC (interp_read.cc, read_g) ignores G80 on a line with another motion code
  const auto motion_codes = std::count_if(out.g_codes.begin(), out.g_codes.end(),
                                          [](const Code& c) { return group_of(c.first) == GGroup::kMotion; });
  if (motion_codes > 1) {
    const auto g80 = std::find_if(out.g_codes.begin(), out.g_codes.end(), [](const Code& c) { return c.first == 800; });
    if (g80 != out.g_codes.end()) out.g_codes.erase(g80);
  }
  // one G code per modal group, one M code per group
  const auto one_per_group = [&](const std::vector<Code>& codes, const char* kind, const auto& group) {
    for (std::size_t a = 0; a < codes.size(); ++a) {
      for (std::size_t b = 0; b < a; ++b) {
        if (group(codes[a].first) != group(codes[b].first)) continue;
        fail(codes[a].second->column, codes[a].second->text,
             std::string("two ") + kind + " codes of one modal group on a line (" + codes[b].second->text + " and " +
                 codes[a].second->text + ")");
      }
    }
  };
  one_per_group(out.g_codes, "G", group_of);
  one_per_group(out.m_codes, "M", m_group_of);
  return out;
}

}  // namespace blendbench::gcode_detail
