#pragma once
// The tolerance-bounded G2 fit of a point stream (docs/smoothing.md states the choices).
//
// Representation: a quintic B-spline on uniform knots, clamped at the stream's ends, converted
// to one Bezier piece per knot span (the Segment variant's Bezier, with its arc-length table).
// It is C4 in its parameter, so curvature and sharpness are continuous inside the stream; at a
// join with a line it starts along the line at zero curvature (G2).
//
// Objective: among the curves within the tolerance of every point, the one with the least
// integral of |d^3p/du^3|^2 (u the chord-length parameter, close to arc length): on a planar
// curve |d^3p/ds^3| = sqrt(kappa'^2 + kappa^4), the term seed 004 (Shahzadeh et al.) eq. 26
// divides the jerk limit by, so the fit keeps the speed the jerk limit allows as high as the
// tolerance lets it. Solved as a sequence of weighted least-squares problems (penalised
// spline, banded normal equations, Eigen's sparse LDLT), the weights of the points that leave
// the tolerance raised and of the others lowered until the active points sit at it (an
// iteratively reweighted method for the inequality-constrained problem), with the points'
// parameters corrected to their closest points twice. Lines longer than the tolerance are
// sampled at most a tolerance apart, so the curve follows the lines, not only their ends.
//
// Accepted only when the measured Hausdorff distance (follow_distance.hpp, both ways, an upper
// bound) is within the tolerance; otherwise the fit aims lower, then halves the knot spacing.

#include <vector>

#include "blendbench/program/smoothing.hpp"

namespace blendbench {

// What a g2_fit found, beside the curve.
struct G2FitStats {
  int spans = 0;           // knot spans (= Bezier pieces)
  double spacing = 0;      // m: knot spacing
  int iterations = 0;      // weighted least-squares solves
  double distance = 0;     // m: the measured Hausdorff distance (upper bound)
};

// The G2 curve within `tolerance` (m, > 0) of the polyline through `points` (m, at least two;
// consecutive points may repeat), both ways, with the given ends (a closed stream repeats its
// first point last; its curve is C2 across it). Pieces are quintic Beziers; piece_segment and
// the spans as CurveFit says. Infeasible (outcome with the reason, no pieces) when no fit within
// the tolerance was found at the finest knot spacing tried, or the curve would stop (a speed
// near zero in its parameter: a cusp). `stats`, when given, receives the figures above.
CurveFit g2_fit(const std::vector<Vec3>& points, const CurveEnds& ends, double tolerance, G2FitStats* stats = nullptr);

}  // namespace blendbench
