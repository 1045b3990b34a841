#pragma once
// Building `Arc`s from the ways programs specify them (centre, radius, or a via point).
// All inputs in metres; results carry an Outcome instead of throwing, so each loader can turn a
// failure into an InputError naming its own file, line and field.

#include "blendbench/geometry/segment.hpp"
#include "blendbench/core/status.hpp"

#include <vector>

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

// LinuxCNC's spiral: what it cuts for a centre-format arc whose end point is off the circle
// through its start (posemath's PmCircle with `spiral`; the trajectory planner moves the radius
// linearly in the angle, dr/dphi = spiral / angle, and the height likewise):
//   p(phi) = center + (r0 + (r1 - r0) phi / sweep) (cos(phi) u + sin(phi) v) + rise phi / sweep w,
// phi in [0, sweep], u and v orthonormal (v the direction of motion at the start), w = u x v.
// r0, r1 > 0 and sweep > 0 (more than 2 pi for more turns).
struct Spiral {
  Vec3 center;
  Vec3 u;
  Vec3 v;
  double r0 = 0;
  double r1 = 0;
  double sweep = 0;
  double rise = 0;
};

Vec3 spiral_point(const Spiral& spiral, double phi);
// The unit tangent in the direction of motion at angle phi.
Vec3 spiral_tangent(const Spiral& spiral, double phi);

struct SpiralArcs {
  Outcome outcome;         // kInfeasible with a message when no chain within the tolerance was found
  std::vector<Arc> arcs;   // from the spiral's start to its end, each starting where the last ends
  double deviation = 0;    // m: the bound on the distance to the spiral that was checked (see below)
};

// Arcs that follow `spiral` within `tolerance` (m), continuous in position and tangent (G1) from
// one to the next, starting at its start point and ending at its end point:
// - one arc, the circle through both end points whose centre is the point of their bisector
//   nearest the spiral's centre, when it stays within the tolerance (a small radius difference);
// - else a chain of biarcs (two tangent arcs meeting where the tangent is continuous, equal
//   distances to the control points) between points of the spiral at equal angles, each
//   matching the spiral's point and tangent at both its ends, the count doubled until the
//   chain stays within the tolerance (at most max_arcs arcs). A helical spiral's chain rises at
//   one slope throughout (so the tangent stays continuous), which bounds how closely it can
//   follow a rise linear in the angle: past that the chain is refused, never cut off.
// The deviation bounds the Hausdorff distance between the chain and the spiral both ways, up to
// the sampling (64 points per arc): first as the distance of each chain point to the spiral's
// point at the same angle about its centre; where that exceeds the tolerance (a steep helix is
// far from the spiral at the same angle yet close to it), as the distances to the nearest points
// found by golden-section search near that angle, from the chain and from the spiral. Fails
// (kInfeasible) on a degenerate spiral (zero or non-finite radius or sweep) or when max_arcs
// arcs are not enough.
SpiralArcs arcs_along_spiral(const Spiral& spiral, double tolerance, int max_arcs);

}  // namespace blendbench
