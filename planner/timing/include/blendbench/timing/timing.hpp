#pragma once
// Jerk-limited velocity planning along a blended path: the path speed s(t) sampled at the
// servo period, with every limit held on the sampled profile.

#include <cstddef>
#include <string>
#include <vector>

#include "blendbench/program/path.hpp"
#include "blendbench/core/status.hpp"

namespace blendbench {

struct TimingOptions {
  double dt = 1e-3;  // s, output sample period (the servo period); > 0
  // The two "without transitions" baselines of issue 4: kExactStop stops at every junction
  // between pieces; kJunctionSlowdown ignores exact stops that the blender set (except at
  // Buffered kinks) and slows down at every kink and curvature jump as a controller does.
  enum class Baseline { kNone, kExactStop, kJunctionSlowdown } baseline = Baseline::kNone;
  // true: one S-curve may span several intervals of a curved stretch, carrying acceleration
  // through the knots between them (timing.cpp); false: zero tangential acceleration at every
  // interval boundary (the more conservative method, kept for comparison: its cycle time never
  // grows when a limit is raised, and the default was never slower on thousands of random
  // paths, timing_test).
  bool carry_acceleration = true;
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

// PLCopen buffer modes at a junction that is not a stop. The earlier piece's mode chooses the
// junction velocity v_J = junction_velocity(mode, v_prev, v_next) (program.hpp: Low min,
// Previous v_prev, Next and Aborting v_next, High max) from the two programmed velocities,
// lowered to the junction's kink and curvature-jump bounds (plan_timing). When v_J is above
// a piece's programmed velocity, that slower piece gets a hand-over zone next to the junction,
// over which its feed term is v_J instead of its programmed velocity:
//   - v_J > v_next (Previous or High after a faster move): the first
//     min(L_next, D(v_J -> v_next)) of the next piece, D with its deceleration and jerk;
//   - v_J > v_prev (Next, Aborting or High before a faster move): the last
//     min(L_prev, D(v_prev -> v_J)) of the previous piece, D with its acceleration and jerk;
// D the jerk-limited distance of the velocity change with zero acceleration at both ends
// (velocity_change, scurve.hpp). So the slower move starts (ends) at the faster velocity and
// reaches its own by the end (from the start) of the zone. Where zones of a piece overlap, the
// higher velocity applies. Only the feed term is relaxed: the curvature and sharpness terms
// and the junction bounds always hold. Low (and Buffered at a junction it does not stop)
// never makes a zone.
struct HandoverZone {
  std::size_t piece;  // index in path.pieces()
  double s0, s1;      // m, local arc lengths on the piece, 0 <= s0 < s1 <= its length
  double velocity;    // m/s, the feed term over [s0, s1]: the junction velocity v_J
};

// The hand-over zones of `path` under `options`, ordered by piece and s0; empty in the
// exact-stop baseline. Throws InputError as plan_timing does.
std::vector<HandoverZone> handover_zones(const Path& path, const TimingOptions& options = {});

// Plans the fastest profile the method below finds from rest at s = 0 to rest at the end of
// the path. On the result, with v_lim(s) = min(feed(s), sqrt(a/kappa(s)),
// cbrt(j/sqrt(c(s)^2 + kappa(s)^4))) (004 eq. 25-27, a and j the piece's acceleration and
// jerk limits; feed(s) the piece's velocity, or the junction velocity in a hand-over zone):
// 0 <= v <= v_lim(s), |a_t| <= acceleration (speeding up) or deceleration (slowing down),
// |j_t| <= jerk, kappa v^2 <= acceleration, and v = 0 at every stop_before.
// Kinks and curvature jumps that are not stops get the controller-style junction velocity
// (2 v sin(theta/2) <= min(j dt^2, a dt); dk v^2 <= j dt); a Buffered kink is a stop.
// The method (intervals with a cap each; S-curves between knots of zero acceleration, each
// spanning one interval or a run of them under their caps; backward and forward passes) and
// where it is conservative are described in timing.cpp.
// Throws InputError for options.dt <= 0 or a piece with a non-positive limit. An empty path
// gives one sample at rest.
Timing plan_timing(const Path& path, const TimingOptions& options = {});

}  // namespace blendbench
