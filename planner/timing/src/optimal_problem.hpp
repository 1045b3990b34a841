#pragma once
// Internal to the optimal velocity planner: the minimum-time problem on one stretch of the grid
// (optimal_grid.hpp) from rest to rest, and the barrier method that solves it. Not installed.
//
// Variables at each inner node i of the stretch: b_i = v^2 and the tangential acceleration a_i
// (the rests at both ends have b = a = 0). Between nodes (a cell of length h) a is linear in s,
// so b' = 2a makes b quadratic and
//   (E)  b_{i+1} - b_i = h (a_i + a_{i+1}),   a' = (a_{i+1} - a_i) / h on the cell.
// At a rest the motion starts as s = c t^3 (constant jerk): on the first cell b_1 = 1.5 h a_1, its
// time 3 h / sqrt(b_1) and a' = a_1 / (3 h) at its far end (mirrored into the last cell); the
// naive cell time 2 h / sqrt(b_1) would undercount it by a third.
//
// Objective: the time, on each cell h / (sqrt(b_0) + sqrt(b_m)) + h / (sqrt(b_m) + sqrt(b_1)) with
// b_m = b(h / 2) = b_0 + h (3 a_0 + a_1) / 4 (exact for b linear on each half; convex: 1 / (sqrt x +
// sqrt y) is convex and b_m is linear), the rest cells 3 h / sqrt(b).
//
// Constraints at each node, on each side with that side's geometry (optimal_grid.hpp), with the
// TCP's acceleration a T + b k and jerk sqrt(b) w, w = a' T + 3 a k + b k' (cartesian.hpp):
//   b <= b_max (feed, junction rules, path-mode and angular velocity caps);
//   cartesian: |a T + b k| <= A where a >= 0 and <= D where a <= 0: max(a,0)^2 + |k|^2 b^2 <= A^2
//     and min(a,0)^2 + |k|^2 b^2 <= D^2 (for A != D an inner approximation of that union: it also
//     holds |k| b <= min(A, D)); each axis component |a T_x + b k_x| <= A_x;
//   path: -D <= a <= A;
//   jerk, on each side with that cell's a': cartesian |w| <= J / sqrt(b) - |step| sqrt(b) (the
//     step term where a curvature step is limited: its normal acceleration steps by
//     |k_prev - k_next| v^2 within one servo period, which together with the jerk on either side
//     is held to J), and per axis |w_x| <= J_x / sqrt(b) - |step_x| sqrt(b); path |a'| <= J / sqrt(b);
//   rotation (orientation.hpp, with rho, rho', rho'' at the side): |rho a + rho' b| <= Alpha and
//     |rho a' + 3 rho' a + rho'' b| <= Eta / sqrt(b).
// Every constraint is convex in (b, a) except the jerk's right-hand side g(b) = J b^(-1/2) - q
// b^(1/2), which is convex in b (g'' > 0) on the wrong side: it is replaced by its tangent at the
// linearisation point b^ (an inner approximation: g lies above its tangents), and the
// linearisation is repeated at each solution (sequential convex programming: every iterate is
// feasible for the true constraints at the nodes, and the time never grows from one to the
// next; the fixed point is a KKT point of the true problem, since tangent and g agree there in
// value and slope).
//
// The solver (no Debian package gives C++ a second-order-cone or convex-NLP solver; platform
// notes): a primal log-barrier method (Boyd & Vandenberghe, ch. 11), Newton steps on
// t T(x) + sum -log(c_j(x)) with the second-order cones written as -log(t^2 - |u|^2), under the
// equalities (E) (infeasible-start Newton until they hold, then feasible Newton with backtracking
// on the barrier). Each constraint couples the nodes of one cell, so the KKT system, ordered by
// node (equality multiplier, b, a), is block tridiagonal with 3x3 blocks and is solved by a
// block LDL^T in time linear in the nodes.

#include <cstddef>
#include <vector>

#include "optimal_grid.hpp"

namespace blendbench::timing_detail {

// The solution on one stretch and what it took.
struct StretchResult {
  std::vector<double> b;  // m^2/s^2 at the stretch's nodes (0 at both rests)
  std::vector<double> a;  // m/s^2
  // m^2/s^2, m/s^2: the point the cells' shapes come from (cell_shape.hpp)
  std::vector<double> b_lin;
  std::vector<double> a_lin;
  int linearisations = 0;
  int newton_steps = 0;
  bool converged = false;  // the result holds every constraint and the equalities
  bool stalled = false;    // the barrier method stopped short of its gap (the result is feasible)
  const char* failure = "";  // why converged is false: "start" (no scale of the start holds every
                             // constraint), "equalities" (the iterate never reached them)
};

// Solves the stretch between rest nodes grid.nodes[first] and grid.nodes[last] (last - first >=
// 4) from the starting profile (b0, a0) at its nodes (SI, one value per node of the stretch,
// b0 > 0 at the inner nodes): linearised there, scaled down uniformly (b and a alike, i.e. the
// same motion run slower) as far as it takes to hold every constraint strictly, then optimised.
// `max_linearisations` bounds the sequential convex programming. The result holds every
// constraint at the nodes; converged is false (and the result the scaled start) when no scale
// of the start holds them. A stretch of at least `parallel_cells` cells is evaluated on two
// threads (TimingOptions::parallel_cells).
StretchResult solve_stretch(const Grid& grid, std::size_t first, std::size_t last, const std::vector<double>& b0,
                            const std::vector<double>& a0, int max_linearisations, std::size_t parallel_cells);

}  // namespace blendbench::timing_detail
