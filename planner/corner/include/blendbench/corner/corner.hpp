#pragma once
// The interface every transition method implements: fit one corner between two moves. The
// special cases and fallbacks a fit reports are the enums of program/corner_case.hpp.

#include <string>
#include <vector>

#include "blendbench/program/corner_case.hpp"
#include "blendbench/program/program.hpp"
#include "blendbench/geometry/segment.hpp"
#include "blendbench/core/status.hpp"

namespace blendbench {

// The two moves meeting at a corner, as the blender sees them: `in` ends at the corner and
// `out` starts there. A method may consume at most `in_available` of the end of `in` and
// `out_available` of the start of `out` (half a move that is blended at both ends, all of a
// move blended at one end only).
struct CornerInput {
  Primitive in;
  Primitive out;
  double in_available = 0;   // m
  double out_available = 0;  // m
  Transition spec;           // from the incoming move
  BufferMode buffer = BufferMode::kBlendingLow;
  std::string name;  // e.g. "corner 2 (move 2 -> move 3)", for messages
  SourceRef where;   // the incoming move's source, for InputError on impossible requests
};

// The result of fitting one corner. The transition joins point(in, length(in) - trim_in) to
// point(out, trim_out); it is empty when the method leaves a kink or inserts a zero-length
// transition (zero distance, intersection, same circle opposite direction).
struct CornerFit {
  Outcome outcome;  // kInfeasible with a message when the corner cannot be fitted as asked
  double trim_in = 0;
  double trim_out = 0;
  std::vector<Segment> transition;
  CornerCase corner_case = CornerCase::kRegular;
  Fallback fallback = Fallback::kNone;  // documented fallback used
  std::string note;      // e.g. the parameter was shrunk because a move is short
  double parameter_used = 0;
  bool stop = false;  // velocity must go to zero here (Buffered at a remaining kink)
};

CornerFit fit_arc_corner(const CornerInput& corner);         // 001, 003: corner distance
CornerFit fit_bezier_corner(const CornerInput& corner);      // 000: transition parameter TP
CornerFit fit_clothoid_corner(const CornerInput& corner);    // 002: clothoid pair (+ arc)
CornerFit fit_biclothoid_corner(const CornerInput& corner);  // 004: tolerance or start distance

}  // namespace blendbench
