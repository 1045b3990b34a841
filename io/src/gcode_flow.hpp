#pragma once
// Private to io/src (not installed): the O-word structure of a part program (LinuxCNC's G-code
// manual, "O Codes"), found once before the program runs: every O-word line, the partner of
// each opening and closing word, and the subroutines by label. The reader (gcode.cpp) follows
// it to jump; a structure that does not close, a closing word with another label, a nested
// subroutine definition or a break outside a loop stops with InputError at its line.

#include <cstddef>
#include <string>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "gcode_lexer.hpp"

namespace blendbench::gcode_detail {

enum class OKind { kSub, kEndsub, kCall, kDo, kWhile, kEndwhile, kIf, kElseif, kElse, kEndif, kRepeat, kEndrepeat, kBreak,
                   kContinue, kReturn };

struct OLine {
  std::size_t offset = 0;  // text offset where the line starts
  std::size_t next = 0;    // text offset where the next line starts
  int line = 0;            // 1-based
  OWordHead head;
  OKind kind = OKind::kCall;
  bool closes_do = false;  // a `while` that closes a `do` loop
  // sub -> endsub, endsub/return -> sub; while -> endwhile and back; do <-> its closing while;
  // repeat <-> endrepeat; if, elseif, else -> endif; break/continue -> the loop's opening line
  int match = -1;
  int next_branch = -1;    // if/elseif -> the next elseif, else or endif of the chain
};

struct Flow {
  std::vector<OLine> lines;  // in text order
  std::unordered_map<std::string, int> subs;  // label -> index of its `sub` line
};

// Finds the O-word lines of `text` (up to a closing '%') and checks their structure.
Flow build_flow(std::string_view text, const std::string& file);

}  // namespace blendbench::gcode_detail
