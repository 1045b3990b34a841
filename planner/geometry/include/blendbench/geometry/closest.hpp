#pragma once
// Closest points and distances between points and path primitives (m).

#include "blendbench/geometry/segment.hpp"

namespace blendbench {

struct Closest {
  double s = 0;         // arc length of the closest point on the segment
  Vec3 point;           // the closest point
  double distance = 0;  // |query - point|
};

// Exact for lines and planar arcs; for helices, Bezier curves and clothoids a dense scan (128
// samples) whose every local minimum is refined by golden-section search (relative error below
// 1e-10 of the segment length; a helix needs no more than ~1/10 turn between samples, i.e.
// up to ~12 turns, for the scan to see every turn's minimum).
Closest closest_point(const Segment& segment, const Vec3& query);
Closest closest_point(const Primitive& primitive, const Vec3& query);

// Hausdorff distance between two sets of segments (each treated as one curve), m: the larger of
// the two directed distances max_{a in A} min_{b in B} |a - b| and the reverse, each measured
// by sampling the first set every `step` m (at least 64 and at most 2^20 samples a segment; a
// Bezier takes as many samples, evenly in its parameter u rather than in arc length) and
// finding exact or refined closest points on the second (its segments tried nearest first, and
// one that cannot come nearer than the best so far passed over).
double hausdorff(const std::vector<Segment>& a, const std::vector<Segment>& b, double step);

// The directed part alone: max over points of `from` of the distance to the closest point of
// `to` (m), sampled as above. 0 when either set is empty.
double directed_hausdorff(const std::vector<Segment>& from, const std::vector<Segment>& to, double step);

// The same distances for short chains (a corner's transition against the path it replaces)
// without dense sampling (hausdorff.cpp): each chain sampled by the turning and length of its
// segments (one sample per 0.05 rad, at least 8 a segment), distances to the other chain exact
// on lines and planar arcs and by a bracketed Newton search elsewhere, and every sampled local
// maximum refined by Brent's method until its bracket is below `tolerance` (m, > 0) of arc
// length. The result is a distance realised between the chains.
double hausdorff_within(const std::vector<Segment>& a, const std::vector<Segment>& b, double tolerance);
double directed_hausdorff_within(const std::vector<Segment>& from, const std::vector<Segment>& to, double tolerance);

}  // namespace blendbench
