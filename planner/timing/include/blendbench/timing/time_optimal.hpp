#pragma once
// The time-optimal bound of a blended path: the least time from rest to rest under the velocity
// and acceleration limits alone (no jerk), the same limits the plan's mode imposes. Every
// profile plan_timing makes holds these constraints (and more), so none is faster: the ratio of
// a plan's cycle time to the bound says how much the jerk limits and the planner's own
// conservatism cost.
//
// Constraints (the plan's, without every term that comes from the jerk limit):
//   v <= feed(s) (the piece's velocity, or the junction velocity of a hand-over zone), and
//     v <= Omega / |rho| where the tool rotates (the angular velocity limit; the angular
//     acceleration and jerk limits are left out);
//   kappa v^2 <= a_n: the acceleration limit (mode path) or the smaller of acceleration and
//     deceleration (mode cartesian: the vector limit at a_t = 0);
//   speeding up: a_t <= A (path), a_t <= sqrt(A^2 - (kappa v^2)^2) (cartesian); slowing down
//     the same with the deceleration D;
//   v = 0 at every stop; at a kink by theta, v <= a dt / (2 sin(theta/2)) (the acceleration part
//     of the junction rule; its jerk part and the curvature-jump rule are jerk limits and left
//     out); a and A, D the pieces' vector limits (axis limits applied in cartesian mode).
//
// Method: reachability on a grid in s, the TOPP family's numerical integration. With y = v^2,
// dy/ds = 2 a_t, the velocity limit curve MVC(s) = min(feed^2, a_n / kappa). A forward pass
// from rest bounds y at every grid point by the fastest speeding up, a backward pass from the
// end (and from every stop) by the hardest braking; the optimum lies under both and under the
// MVC. Every step errs on the fast side, so the result stays a lower bound:
//   - on each cell the MVC is taken at the cell's smallest curvature (exact on lines, arcs and
//     clothoids; on a Bezier the smallest end value less the piece's maximum sharpness times
//     half the cell) and largest feed;
//   - the acceleration available at speed y, sqrt(A^2 - kappa^2 y^2), falls as y grows, so on a
//     cell the reachable y is at most y_0 + 2 x rate(y_0) with the rate at the cell's start
//     (comparison with the exact reachability ODE), and at the cell's smallest curvature;
//   - the time of a cell is the exact integral of dx / sqrt(min(MVC, forward line, backward
//     line)), a pointwise upper bound of the optimal speed there (closed form: a linear y
//     gives 2 dx / (sqrt(y_a) + sqrt(y_b))), and the sum is scaled by (1 - 1e-12) for rounding.
// So the bound is exact for straight lines (L/v + v/a from rest to rest when the feed is reached,
// 2 sqrt(L/a) when not) and for circular arcs at constant speed sqrt(a_n r), and within the
// grid's resolution (at least 32 cells per piece of varying curvature, 8 per arc in cartesian
// mode, time_optimal.cpp) elsewhere.

#include "blendbench/program/path.hpp"
#include "blendbench/timing/timing.hpp"

namespace blendbench {

// The bound (s) for `path` under `options` (its dt, limits mode, axis limits and baseline);
// 0 for an empty path. Throws InputError as plan_timing does for bad options or limits. Also
// filled in by plan_timing as Timing::bound_cycle_time.
double time_optimal_bound(const Path& path, const TimingOptions& options = {});

}  // namespace blendbench
