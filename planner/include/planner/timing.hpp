#pragma once
// Jerk-limited velocity planning along a blended path: the path speed s(t) sampled at the
// servo period, with every limit held on the sampled profile.

#include <cstddef>
#include <string>
#include <vector>

#include "planner/path.hpp"
#include "planner/status.hpp"

namespace blendbench {

struct TimingOptions {
  double dt = 1e-3;  // s, output sample period (the servo period); > 0
  // The two "without transitions" baselines of issue 4: kExactStop stops at every junction
  // between pieces; kJunctionSlowdown ignores exact stops that the blender set (except at
  // Buffered kinks) and slows down at every kink and curvature jump as a controller does.
  enum class Baseline { kNone, kExactStop, kJunctionSlowdown } baseline = Baseline::kNone;
};

// One servo tick: time (s), arc length (m), path velocity (m/s), tangential acceleration
// (m/s^2) and tangential jerk (m/s^3).
struct TimedSample {
  double t, s, v, a, j;
};

// What limited the peak velocity `v_peak` (m/s) of one path piece:
//   "feed", "curvature", "sharpness": the piece reaches v_lim(s) (within 0.1 %), and this term
//       of it (programmed velocity, sqrt(a/kappa), cbrt(j/sqrt(c^2+kappa^4)); 004 eq. 25-27)
//       is the smallest where it does;
//   "length": the piece holds a local maximum of v below v_lim: too short to reach it between
//       the velocities at its ends;
//   "acceleration", "jerk": the profile ramps through the piece without reaching v_lim, with
//       the tangential acceleration limit reached on it, or only the jerk limit;
//   "stop": the piece is pinned at rest (zero length at a stop).
struct PieceTiming {
  std::size_t piece;
  double v_peak;
  std::string binding;
};

struct Timing {
  Outcome outcome;
  double dt = 0;
  double cycle_time = 0;  // s, planned duration from rest to rest
  // t = k*dt, k = 0..N with N = ceil(cycle_time/dt); the last sample is the end of the path at
  // rest (s = length, v = a = j = 0).
  std::vector<TimedSample> samples;
  std::vector<PieceTiming> pieces;  // one per path piece, in order
  double feed_share = 0;            // share of time spent at the programmed feed (within 0.1 %)
};

// Plans the fastest profile the method below finds from rest at s = 0 to rest at the end of
// the path. On the result, with v_lim(s) = min(piece velocity, sqrt(a/kappa(s)),
// cbrt(j/sqrt(c(s)^2 + kappa(s)^4))) (004 eq. 25-27, a and j the piece's acceleration and
// jerk limits): 0 <= v <= v_lim(s), |a_t| <= acceleration (speeding up) or deceleration
// (slowing down), |j_t| <= jerk, kappa v^2 <= acceleration, and v = 0 at every stop_before.
// Kinks and curvature jumps that are not stops get the controller-style junction velocity
// (2 v sin(theta/2) <= min(j dt^2, a dt); dk v^2 <= j dt) and the buffer mode's choice.
// The method (intervals with zero acceleration at their ends, backward and forward passes,
// one S-curve per interval) and where it is conservative are described in timing.cpp.
// Throws InputError for options.dt <= 0 or a piece with a non-positive limit. An empty path
// gives one sample at rest.
Timing plan_timing(const Path& path, const TimingOptions& options = {});

}  // namespace blendbench
