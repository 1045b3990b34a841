#pragma once
// Internal to the optimal velocity planner: the continuous motion the grid solution describes,
// sampled at the servo period, and the check of every limit on those samples. Not installed.
//
// On a cell the motion is the one cell_shape.hpp describes: a and b = v^2 known in closed form
// along the cell's coordinate w, and the time t(w) = int_0^w x'(w) / sqrt(b(w)) dw by
// Gauss-Legendre quadrature (the integrand is smooth and close to constant: x' / sqrt(b) ~ 2h / S
// where b ~ u^2), inverted by Newton's method at each sample; a rest cell is s = c tau^3 (or its
// mirror into a rest), exact. The quadrature's error is a smooth function of w, so third
// differences of the sampled positions, amplified by 1/dt^3, see the profile and not noise.

#include <cstdint>
#include <vector>

#include "blendbench/program/path.hpp"
#include "blendbench/timing/timing.hpp"
#include "cell_shape.hpp"
#include "optimal_grid.hpp"

namespace blendbench::timing_detail {

// The motion on one cell of the grid.
struct CellMotion {
  double s0 = 0;        // m, global arc length at its start
  double length = 0;    // m
  double t0 = 0;        // s, its start time
  double duration = 0;  // s
  enum class Kind : std::uint8_t { kNormal, kFromRest, kToRest } kind = Kind::kNormal;
  CellShape shape;               // kNormal
  double b0 = 0, a0 = 0, a1 = 0;  // kNormal: v^2 at its start, a at both ends (SI)
  double c = 0;                  // rest cells: s = c tau^3 (m/s^3)
};

// The state of the motion tau (s) after the cell's start: arc length from the cell's start,
// speed, tangential acceleration and jerk.
struct CellState {
  double x, v, a, j;
};
CellState cell_state(const CellMotion& cell, double tau);

// The cells of `grid` between nodes first and last under the node values b (v^2) and a (SI),
// shaped by the linearisation point b_lin, a_lin (cell_shape.hpp), chained in time from 0; false
// (and the cells so far) when a cell's motion does not reach its end (b not positive inside it).
bool make_motion(const Grid& grid, std::size_t first, std::size_t last, const std::vector<double>& b,
                 const std::vector<double>& a, const std::vector<double>& b_lin, const std::vector<double>& a_lin,
                 std::vector<CellMotion>& cells);

// Samples the motion at t = k dt, k = 0..ceil(T/dt) (T the total duration); the last sample is
// the end of the path at rest (timing.hpp's contract).
std::vector<TimedSample> sample_motion(const std::vector<CellMotion>& cells, double path_length, double dt);

// The largest ratios of the limited quantities to their limits over the samples, by how the
// ratio falls when the whole motion is run slower by a factor gamma (v -> gamma v): velocity-like
// (gamma), acceleration-like (gamma^2) and jerk-like (gamma^2 taken for all of them: the third
// difference across a limited curvature step holds its acceleration step, which falls with
// gamma^2 only).
struct ProfileCheck {
  double velocity = 0;
  double acceleration = 0;
  double jerk = 0;
  // per sample: the largest ratio of each kind (a difference stencil's on each of its samples)
  std::vector<double> velocity_ratio;
  std::vector<double> acceleration_any;
  std::vector<double> jerk_any;
  // per sample: the largest ratio of any kind, and of the acceleration and jerk kinds (reports)
  std::vector<double> worst;
  std::vector<double> acceleration_ratio;
  std::vector<double> jerk_ratio;
  std::vector<double> rotation_ratio;
  // The largest gamma <= 1 with every ratio at most 1 after the slow-down (1 when clean), over
  // all samples, or over samples k0..k1.
  [[nodiscard]] double scale() const;
  [[nodiscard]] double scale(std::size_t k0, std::size_t k1) const;
};

// Checks the samples against every limit the optimal plan holds (optimal_problem.hpp), in the
// options' mode: feed; cartesian: |a| and |j| as vectors (analytic from v, a_t, j_t and the
// path's frame) and per axis, and by first, second and third differences of the sampled x, y, z
// (the second and third differences' stencils that cross a kink, or a curvature step that is
// allowed, skipped); path: the tangential limits, eq. 25-27 and the first to third differences
// of s; the tool's angular velocity,
// acceleration and jerk where it rotates.
ProfileCheck check_samples(const Path& path, const TimingOptions& options, const Prepared& prepared,
                           const std::vector<TimedSample>& samples);

}  // namespace blendbench::timing_detail
