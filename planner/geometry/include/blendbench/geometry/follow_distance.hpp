#pragma once
// The Hausdorff distance between a long chain of curve pieces and a polyline it follows closely,
// such as a smoothed CAM stream and its programmed lines (m). hausdorff() (closest.hpp) compares
// every sample of one set with every segment of the other; a stream of 10^5 lines needs the
// correspondence the fit knows instead: which stretch of the polyline each piece replaces.

#include <vector>

#include "blendbench/geometry/segment.hpp"

namespace blendbench {

struct FollowDistance {
  double curve_to_polyline = 0;  // m: max over the curve of the distance to the polyline
  double polyline_to_curve = 0;  // m: max over the polyline (points and segments) of the distance to the curve
  [[nodiscard]] double hausdorff() const {
    return curve_to_polyline > polyline_to_curve ? curve_to_polyline : polyline_to_curve;
  }
};

// Both directed distances between `pieces` and the polyline through `polyline` (at least two
// points). Piece i corresponds to the stretch [span_begin[i], span_end[i]] of the polyline's arc
// length (m from its first point, non-decreasing in i), a point of it at the share f of its
// parameter (arc length, or u of a Bezier) to span_begin + f (span_end - span_begin). Every point
// of either is compared with the part of the other that lies within `reach` (m) of that place
// along the polyline: a nearer part farther along is not looked at, so each value bounds the true
// distance from above, and equals it (to the resolution) where the nearest parts lie within
// reach. The cost is linear in the lengths over the resolution, times the segments within reach.
//
// Sampling: the curve is replaced by a chord polygon whose chords deviate from it by at most
// resolution / 2 (from each piece's maximum curvature), and each side is sampled at most
// `resolution` (m, > 0) apart along its length. Each returned value is the largest sampled
// distance plus resolution / 2 (the distance is 1-Lipschitz along a curve) plus, for distances
// to the curve, the chord polygon's deviation: an upper bound of the true value.
FollowDistance follow_distance(const std::vector<Segment>& pieces, const std::vector<double>& span_begin,
                               const std::vector<double>& span_end, const std::vector<Vec3>& polyline, double resolution,
                               double reach);

}  // namespace blendbench
