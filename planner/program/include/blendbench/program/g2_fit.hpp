#pragma once
// The tolerance-bounded G2 fit of a point stream (docs/smoothing.md states the choices).
//
// Representation: a quintic B-spline, clamped at the stream's ends, converted to one Bezier piece
// per knot span (the Segment variant's Bezier, with its arc-length table). It is C4 in its
// parameter, so curvature and sharpness are continuous inside the stream; at a join with a line
// it starts along the line at zero curvature (G2); a closed stream's curve is C2 across its seam.
// Knots follow the stream: a span ends where the lines' direction has turned by 0.2 rad, and is
// 2 to 200 tolerances long, so straight stretches take few pieces and bends enough.
//
// Objective: among the curves within the tolerance of every point, the one with the least
// integral of |d^3p/du^3|^2 (u the chord-length parameter, close to arc length): on a planar
// curve |d^3p/ds^3| = sqrt(kappa'^2 + kappa^4), the term seed 004 (Shahzadeh et al.) eq. 26
// divides the jerk limit by, so the fit keeps the speed the jerk limit allows as high as the
// tolerance lets it. A convex problem (a quadratic objective, a ball constraint per point),
// solved by ADMM whose every step is a banded least-squares spline (Eigen's sparse LDLT, one
// factorisation per penalty weight), with the points' parameters moved to their closest points
// twice. Lines longer than the tolerance are sampled at most a tolerance apart, so the curve
// follows the lines, not only their ends.
//
// Accepted only when the measured Hausdorff distance (follow_distance.hpp, both ways, an upper
// bound) is within the tolerance and the curve neither stops nor turns about a near-cusp;
// otherwise the fit aims lower, then halves the spans where it could not stay within.

#include <vector>

#include "blendbench/program/smoothing.hpp"

namespace blendbench {

// What a g2_fit found, beside the curve.
struct G2FitStats {
  int spans = 0;           // knot spans (= Bezier pieces)
  double spacing = 0;      // m: mean knot spacing
  int iterations = 0;      // ADMM iterations, every pass and refinement
  double distance = 0;     // m: the measured Hausdorff distance (upper bound)
};

// The G2 curve within `tolerance` (m, > 0) of the polyline through `points` (m, at least two;
// consecutive points may repeat), both ways, with the given ends (a closed stream repeats its
// first point last; its curve is C2 across it). Pieces are quintic Beziers; piece_segment and
// the spans as CurveFit says. Infeasible (outcome with the reason, no pieces) when no fit within
// the tolerance was found at the finest knots tried (the spans halved four times where it
// failed), or the curve would stop or turn about a near-cusp (a radius below a tenth of the
// tolerance). `stats`, when given, receives the figures above.
CurveFit g2_fit(const std::vector<Vec3>& points, const CurveEnds& ends, double tolerance, G2FitStats* stats = nullptr);

}  // namespace blendbench
