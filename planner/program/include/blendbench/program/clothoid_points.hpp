#pragma once
// Seed 002 (Makino, section 6, Fig. 11): point-series interpolation by clothoid pairs. "The
// easier method is to connect each points by Clothoid pairs ... To limit the change of the
// direction to some value (in the figure 45 deg), several points are added." The curvature is
// zero at every given point; the seed calls the result "a little dedicated" and says better
// solutions are being studied (g2_fit.hpp is ours).
//
// What the seed leaves open, and what is chosen here (docs/smoothing.md):
//   - the direction at each point: the tangent of the circle through it and its two neighbours
//     (exact on points of a circle; at the ends of an open stream the end tangent of the circle
//     through the first or last three points, unless the stream joins a line there);
//   - how a pair joins two points whose directions are not symmetric about the chord between
//     them (a symmetric pair, eq. 9, needs them symmetric; an asymmetric pair exists only for
//     nearly symmetric directions and cannot make an S): a point is added where the biarc of
//     the two points and directions (equal tangent legs) changes from one arc to the other.
//     Each arc's directions are symmetric about its chord, so each gets the symmetric pair;
//   - the points added for the 45 deg limit: on that arc, dividing it into equal parts that
//     turn by at most max_turn each;
//   - 3D: each pair lies in the plane of its arc; pairs meet at zero curvature, so the curve is
//     G2 where the plane changes.

#include <vector>

#include "blendbench/program/smoothing.hpp"

namespace blendbench {

// The curve through `points` (m) by clothoid pairs of at most `max_turn` (rad, in (0, pi)) each,
// with the given ends (a closed stream repeats its first point last). Consecutive points closer
// than 1e-12 m count as one. Pieces are clothoids, and lines where a pair does not turn
// (below 1e-12 rad). Infeasible (outcome, no pieces) when fewer than two distinct points remain,
// or when no direction is defined at a point (the stream reverses there) or a biarc does not
// exist (the two directions are equal and point away from each other's point).
CurveFit clothoid_points(const std::vector<Vec3>& points, const CurveEnds& ends, double max_turn);

}  // namespace blendbench
