#pragma once
// Building `Arc`s from the ways programs specify them (centre, radius, or a via point).
// All inputs in metres; results carry an Outcome instead of throwing, so each loader can turn a
// failure into an InputError naming its own file, line and field.

#include "blendbench/geometry/segment.hpp"
#include "blendbench/core/status.hpp"

namespace blendbench {

// The most full turns one programmed arc (a helix) may make: 100, far beyond a thread-milling
// helix; it bounds the work per arc (sampling, blending, planning) before any is done. Readers
// refuse more (G-code P, a scenario arc's `turns`).
inline constexpr int kMaxArcTurns = 100;

struct ArcBuild {
  Outcome outcome;  // kInfeasible with a message when no arc fits the specification
  Arc arc;
};

// Arc from `start` to `end` about the axis through `center` along the unit `normal`, turning
// counter-clockwise about `normal` (right-handed) when `ccw`, clockwise otherwise, plus `turns`
// extra full turns. The components of start, end and centre along `normal` may differ: the
// change from start to end becomes the helix rise and the centre is projected into the start's
// plane; a rise of at most kRiseRounding of the radius is rounding (a G91 sum, a frame turned
// in floating point), not a helix, and becomes 0, so the arc ends in its start's plane that
// close to `end` and the corners it makes stay planar. end == start (in the plane) gives a full circle. Fails when the start lies on the
// axis or the in-plane radii to start and end differ by more than `radius_tolerance` (m); within
// it, the centre is moved to the nearest point of the chord's perpendicular bisector, so the arc
// starts and ends exactly at `start` and `end` (the centre moves by at most about the
// tolerance).
inline constexpr double kRiseRounding = 1e-9;
ArcBuild arc_from_center(const Vec3& start, const Vec3& end, const Vec3& center, const Vec3& normal, bool ccw,
                         int turns = 0, double radius_tolerance = 1e-9);

// Arc of radius |radius| from `start` to `end` in the plane normal to `normal`, turning ccw or
// cw about it; a negative radius selects the long arc (> 180 degrees), as in RS274. Fails when
// the chord exceeds the diameter (beyond `radius_tolerance`) or end == start.
ArcBuild arc_from_radius(const Vec3& start, const Vec3& end, double radius, const Vec3& normal, bool ccw,
                         double radius_tolerance = 1e-9);

// The circular arc from `start` through `via` to `end`. Fails when the three points are
// (nearly) collinear or coincide.
ArcBuild arc_through(const Vec3& start, const Vec3& via, const Vec3& end);

}  // namespace blendbench
