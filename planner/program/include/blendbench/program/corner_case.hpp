#pragma once
// How a corner was handled, as the corner reports name it: the special case hit and the
// documented fallback used. Shared by the corner methods (CornerFit) and the path (CornerReport).

#include <iosfwd>
#include <optional>
#include <string_view>

namespace blendbench {

// The special case a corner fit hit, as the sources name them: the line-line cases of seed 001
// (a motion controller's line-to-line transitions) and the arc-arc cases of seed 003 (its
// arc-to-arc transitions), plus the cases of the curve methods. `kRegular` is none of them.
enum class CornerCase {
  kRegular,
  kExactStop,                    // method none: the corner is left as programmed and stopped at
  kCollinear,                    // 0 degree: the moves continue each other (seed 001)
  kReversal,                     // 180 degree: the path turns back on itself (seed 001)
  kNearReversal,                 // within kNearReversalAngle of 180 degrees (corner.hpp): treated as a reversal
  kZeroDistance,                 // corner distance 0: a zero-length transition (seed 001, seed 003)
  kIntersection,                 // the arcs cross at the corner (seed 003 (controller manual, arc-to-arc))
  kTangent,                      // G1 already: only the curvature jumps
  kTangentOpposite,              // tangent arcs turning in opposite directions (seed 003)
  kLineSegment,                  // the transition has an infinite radius: a line (seed 003)
  kSameCircleSameDirection,      // both arcs on one circle, one sense (seed 003)
  kSameCircleOppositeDirection,  // both arcs on one circle, opposite senses (seed 003)
  kClothoidArcClothoid,          // the clothoid pair capped in curvature (seed 002, Makino, figs. 12-13)
  kCurvatureCapUnmet,            // the curvature cap cannot be met
  kNonPlanar,                    // the two moves do not lie in one plane
};

// A documented fallback: the curve or rule used where the method's own construction does not apply.
enum class Fallback {
  kNone,
  kExactStop,               // the corner cannot be fitted: left as programmed, stopped at
  kBiarc,                   // non-planar arcs: a G1 biarc instead of one circular transition
  kSmallerRadiusShortened,  // seed 003's rule with the roles of the two arcs swapped
  kQuartic,                 // seed 000's quartic Bezier where its coplanar cubic is not usable
  kBezier,                  // a biclothoid at a non-planar corner: seed 000's Bezier instead
  kBiclothoid,              // the clothoid method at a corner with arcs: seed 004's biclothoid
  kBiclothoidBezier,        // the clothoid method at a non-planar corner: biclothoid, then Bezier
};

// The names used in reports and files ("regular", "same_circle_same_direction", ...; a fallback
// as "" for none, "exact_stop", "biarc", ..., "biclothoid, bezier"), and back (nullopt when unknown).
std::string_view to_string(CornerCase corner_case);
std::string_view to_string(Fallback fallback);
std::optional<CornerCase> corner_case_from_string(std::string_view name);
std::ostream& operator<<(std::ostream& out, CornerCase corner_case);
std::ostream& operator<<(std::ostream& out, Fallback fallback);

}  // namespace blendbench
