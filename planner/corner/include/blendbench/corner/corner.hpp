#pragma once
// The interface every transition method implements: fit one corner between two moves. The
// special cases and fallbacks a fit reports are the enums of program/corner_case.hpp.

#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "blendbench/program/corner_case.hpp"
#include "blendbench/program/program.hpp"
#include "blendbench/geometry/segment.hpp"
#include "blendbench/core/note.hpp"
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
  Note note;            // e.g. the parameter was shrunk because a move is short (note.hpp)
  double parameter_used = 0;
  // The parameter asked for did not fit: the method shrank it to the moves' available lengths
  // (or to its own caps, e.g. a half-turn of a Bezier's arc), so a larger parameter gives this
  // same transition. The tolerance solve (fit_corner_at_tolerance) stops growing it here.
  bool limited = false;
  bool stop = false;  // velocity must go to zero here (Buffered at a remaining kink)
  // m, >= 0 where the fit has the Hausdorff distance between its transition and the path it
  // replaces already, to the corner report's precision (then the blender reports it instead of
  // measuring it again): in closed form for the symmetric clothoid pair between two lines, whose
  // farthest points are the corner and the pair's midpoint; measured by the fit for a
  // biclothoid with an arc (seed 004 section 7.1, biclothoid_deviation). -1: the blender
  // measures it.
  double exact_deviation = -1;
};

// Reversals, shared by every method. A corner whose tangent turns by theta >= pi -
// kReversalAngle is a reversal (each method's own rule: seed 001 shortens both lines and keeps the
// kink, seed 003 joins parting arcs by a U-turn arc, seed 000, seed 002 (Makino) and seed 004 leave
// the kink). One that turns
// by theta in [pi - kNearReversalAngle, pi - kReversalAngle) is a near reversal: a fillet there
// is a cusp or close to one (the arc's radius d / tan(theta / 2) is 0.044 d at the threshold
// and nanometres within 1e-6 rad of pi; a Bezier's curvature grows like 1 / (pi - theta)^2,
// seed 003's U-turn arcs between nearly opposite arcs can be as tight), so every method treats it as
// the sources treat a line reversal: no transition, the kink stays (a stop when Buffered, else
// the kink's junction velocity, which is nearly a stop), case "near_reversal". Applied by the
// blender before it calls the method (near_reversal_fit).
inline constexpr double kReversalAngle = 1e-9;                       // rad
inline constexpr double kNearReversalAngle = std::numbers::pi / 36;  // rad: 5 degrees

// The near-reversal rule above for `corner`, whose tangent turns by theta (rad): the kink fit,
// or nullopt when theta is outside [pi - kNearReversalAngle, pi - kReversalAngle).
std::optional<CornerFit> near_reversal_fit(const CornerInput& corner, double theta);

// Cusps, by the same rule for every method: a transition whose smallest radius 1 / kappa_max is
// below kCuspShare of its scale, the smaller of the parameter used (corner distance, TP,
// tolerance or start distance) and the radii of the programmed arcs at the corner, is a cusp
// (outside the near-reversal band it happens to a Bezier, whose curvature grows like
// 1 / (pi - theta)^2, and to fillets between nearly opposite arcs). Such a fit is refused
// (cusp_problem) and the blender leaves the corner as an exact stop (fallback exact_stop, the
// note says why). The arc's line-line fillet has kappa d = tan(theta / 2) <= 22.9 outside the
// near-reversal band, far from the 100 this allows.
inline constexpr double kCuspShare = 0.01;

// Why `fit` of `corner` is a cusp (above), or an empty string when it is not.
std::string cusp_problem(const CornerInput& corner, const CornerFit& fit);

// Equal tolerance (docs/methods.md, "Equal tolerance"): the fit of `corner` by its method
// (spec.method, not none) whose deviation, as the corner report gives it (corner_deviation),
// equals spec.tolerance (> 0) within the band [1 - kToleranceBand, 1] of it: the method's own
// parameter (corner distance, TP, the clothoid's and biclothoid's deviation) solved for it by a
// safeguarded secant search on log(deviation) against log(parameter), from a closed form that is
// exact for two lines. Where the neighbouring moves are too short, the largest transition that
// fits (limited, deviation below the tolerance); where the method cuts nothing (collinear,
// tangent or same-circle corners it leaves as they are, a near reversal), the fit at parameter
// 0. The fit's exact_deviation is the deviation measured at the solution (the report gives it
// as it is); parameter_used is the parameter solved. Outcome
// not ok where the method fits no transition at any parameter (the blender stops there).
CornerFit fit_corner_at_tolerance(const CornerInput& corner);

// The share below the tolerance within which a corner's deviation counts as reaching it
// (CornerReport::tolerance_reached): deviation in [tolerance (1 - kToleranceBand), tolerance],
// 0.1 %, ten times inside the 1 %; the tolerance solve stops in it (seed 004's
// Algorithm 2, which the biclothoid's solve is, in a band ten times narrower still:
// biclothoid_tolerance.cpp, kReached).
inline constexpr double kToleranceBand = 1e-3;

// The deviation of a fitted corner as the blender reports it (measure_corner, blend.hpp): the
// fit's exact_deviation where it has one (>= 0), else the two-sided Hausdorff distance between
// its transition and the stretch of `in` and `out` it replaces (their trimmed ends), to 1e-9 of
// the corner's size; for a fit without a transition, how far the skipped stretch lies from the
// kept path (m).
double corner_deviation(const CornerFit& fit, const Primitive& in, const Primitive& out);

CornerFit fit_arc_corner(const CornerInput& corner);         // seed 001, seed 003: corner distance
CornerFit fit_bezier_corner(const CornerInput& corner);      // seed 000: transition parameter TP
CornerFit fit_clothoid_corner(const CornerInput& corner);    // seed 002: clothoid pair (+ arc)
CornerFit fit_biclothoid_corner(const CornerInput& corner);  // seed 004: tolerance or start distance

}  // namespace blendbench
