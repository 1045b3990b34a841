#pragma once
// Jerk-limited velocity planning along a blended path: the path speed s(t) sampled at the
// servo period, with every limit held on the sampled profile.

#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include <optional>

#include "blendbench/core/status.hpp"
#include "blendbench/program/path.hpp"
#include "blendbench/timing/cartesian.hpp"

namespace blendbench {

struct TimingOptions {
  double dt = 1e-3;  // s, output sample period (the servo period); > 0
  // Which velocity planner times the path:
  //   kOptimal: the minimum-time traversal from rest to rest under every limit below
  //     (optimal.hpp: a sequential convex program on a grid in s, held on the sampled output);
  //   kSeed004: seed 004's (Shahzadeh et al.) method, S-curves under the caps of eq. 25-27 with
  //     lookahead (timing.cpp), kept for the paper reproductions and as a comparison.
  enum class Algorithm { kOptimal, kSeed004 } algorithm = Algorithm::kSeed004;
  // The two "without transitions" baselines: kExactStop stops at every junction between
  // pieces; kJunctionSlowdown ignores exact stops that the blender set (except at Buffered
  // kinks) and slows down at every kink and curvature jump as a controller does.
  enum class Baseline { kNone, kExactStop, kJunctionSlowdown } baseline = Baseline::kNone;
  // true: one S-curve may span several intervals of a curved stretch, carrying acceleration
  // through the knots between them (timing.cpp); false: zero tangential acceleration at every
  // interval boundary (the more conservative method, kept for comparison: its cycle time never
  // grows when a limit is raised in path mode, and the default was never slower on thousands of
  // random paths, timing_test; in cartesian mode one counterexample is known, seed 004's fillet,
  // 0.714 s carried against 0.710 s).
  bool carry_acceleration = true;
  // Which limits the plan holds (cartesian.hpp): as vectors on the TCP (the default), or the
  // tangential model of seed 004 (kPath, kept for the paper reproductions).
  LimitsMode limits = LimitsMode::kCartesian;
  // Optional per-axis acceleration and jerk limits on the TCP (kCartesian only).
  std::optional<AxisLimits> axis_limits;
  // The largest number of samples (>= 1) a plan may have: plan_timing refuses a longer plan
  // before it samples it. 1e7 samples are 2.8 hours of motion at 1 ms and 400 MB of samples.
  double max_samples = 1e7;
  // kOptimal: how many times denser than its own the grid in s is (>= 1; node spacing divided by
  // it). The tests solve the same problem on a 4x finer grid as an independent reference.
  double grid_refinement = 1;
  // kOptimal: a stretch between stops with more grid nodes than this (a CAM stream of thousands
  // of tiny lines is one) is solved once, and what its sampled output exceeds is taken by local
  // slow-downs of the motion; a shorter one is solved again with the cells there tightened and
  // split (optimal.cpp). Each solve costs some 100-250 Newton steps whatever the size, so on a
  // long stretch the re-solves were half the planning time. The tests set it to compare both.
  std::size_t local_refinement_nodes = 3000;
  // kOptimal only: a stretch of at least this many grid cells evaluates its barrier function
  // and derivatives (three quarters of each Newton step) in two halves on two threads. The
  // halves depend on the size alone, so the plan does not depend on the cores there are; the
  // tests lower it to compare both ways on a short path.
  std::size_t parallel_cells = 4096;
};

// One servo tick: time (s), arc length (m), path velocity (m/s), tangential acceleration
// (m/s^2) and tangential jerk (m/s^3).
struct TimedSample {
  double t, s, v, a, j;
};

// What limited the peak velocity `v_peak` (m/s) of one path piece:
//   "feed", "curvature", "sharpness": the piece reaches v_lim(s) (within 0.1 %), and this term
//       of it (programmed velocity, sqrt(a/kappa), cbrt(j/sqrt(c^2+kappa^4)); seed 004 eq. 25-27)
//       is the smallest where it does;
//   "length": the piece holds a local maximum of v below v_lim: too short to reach it between
//       the velocities at its ends;
//   "acceleration", "jerk": the profile ramps through the piece without reaching v_lim, with
//       the tangential acceleration limit reached on it, or only the jerk limit;
//   "rotation": the piece reaches its rotation cap, the speed at which the tool's angular
//       velocity, acceleration or jerk limit binds (orientation.hpp; intervals.cpp derives it);
//   "stop": the piece is pinned at rest (zero length at a stop).
enum class Binding { kFeed, kCurvature, kSharpness, kLength, kAcceleration, kJerk, kStop, kRotation };

struct PieceTiming {
  std::size_t piece;
  double v_peak;
  Binding binding;
};

// The names of the algorithms, baselines and bindings in scenarios and summaries ("optimal",
// "seed004"; "none", "exact_stop", "junction_slowdown"; "feed", "curvature", "sharpness",
// "length", "acceleration", "jerk", "stop", "rotation"), and back (nullopt when unknown).
std::string_view algorithm_name(TimingOptions::Algorithm algorithm);
std::optional<TimingOptions::Algorithm> algorithm_from_string(std::string_view name);
std::string_view baseline_name(TimingOptions::Baseline baseline);
std::optional<TimingOptions::Baseline> baseline_from_string(std::string_view name);
std::string_view binding_name(Binding binding);

struct Timing {
  Outcome outcome;
  double dt = 0;
  LimitsMode limits = LimitsMode::kCartesian;  // the mode it was planned in
  TimingOptions::Algorithm algorithm = TimingOptions::Algorithm::kOptimal;  // the planner that made it
  // kOptimal: the convex subproblems solved (one per linearisation of the jerk limits, summed
  // over the grid refinements); 0 for kSeed004, which iterates nothing of the kind.
  int iterations = 0;
  int newton_steps = 0;  // kOptimal: the Newton steps of the barrier method, in all
  // kOptimal: the stretches between stops on which seed 004's motion was kept (the optimiser's
  // was not found, or not faster); 0 when every stretch is optimised.
  int seed004_stretches = 0;
  double planning_wall_time = 0;  // s, wall clock of plan_timing itself
  double cycle_time = 0;  // s, planned duration from rest to rest
  // t = k*dt, k = 0..N with N = ceil(cycle_time/dt); the last sample is the end of the path at
  // rest (s = length, v = a = j = 0).
  std::vector<TimedSample> samples;
  std::vector<PieceTiming> pieces;  // one per path piece, in order
  double feed_share = 0;            // share of time spent at the programmed feed (within 0.1 %)
  // s: the time-optimal bound of the same path under the same limits without jerk
  // (time_optimal.hpp); no profile that holds them takes less.
  double bound_cycle_time = 0;
  // Per corner (in path.corners order): the largest curvature step its transition leaves (the
  // jump |dK| of the curvature vector at a junction of the corner), the planned speed there and
  // the jerk the step of the normal acceleration implies at the servo period, |dK| v^2 / dt
  // (m/s, m/s^3); all 0 where the corner leaves no curvature step.
  struct CornerStep {
    double dk = 0;
    double velocity = 0;
    double jerk = 0;
  };
  std::vector<CornerStep> corner_steps;
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

// Plans the path speed from rest at s = 0 to rest at the end of the path with the planner of
// options.algorithm; both hold, on every sample, v = 0 at every stop (stop_before, a Buffered
// kink, every junction in the exact-stop baseline), v <= feed(s) (the piece's velocity, or the
// junction velocity in a hand-over zone), and:
//   kSeed004 (seed 004's method: intervals with a cap each, S-curves between knots of zero
//     acceleration, backward and forward passes; timing.cpp says where it is conservative):
//     v <= v_lim(s) = min(feed(s), sqrt(a/kappa(s)), cbrt(j/sqrt(c(s)^2 + kappa(s)^4))) (eq.
//     25-27, a and j the piece's acceleration and jerk limits), |a_t| <= acceleration (speeding
//     up) or deceleration (slowing down), |j_t| <= jerk, kappa v^2 <= acceleration; with
//     options.limits = kCartesian the TCP's acceleration and jerk vectors hold the limits too
//     (cartesian.hpp, and every axis limit), also while the speed changes on a curve. Kinks and
//     curvature jumps that are not stops get the controller-style junction velocity
//     (2 v sin(theta/2) <= min(j dt^2, a dt); dk v^2 <= j dt, dropped where the piece after the
//     junction has curvature_step_allowed).
//   kOptimal (optimal.cpp): the least time under the same limits without seed 004's caps: in
//     kCartesian the TCP's acceleration vector within acceleration (a_t >= 0) or deceleration
//     (a_t <= 0), its jerk vector within jerk, every axis limit; in kPath the tangential limits,
//     kappa v^2 and eq. 25-27; the same kink rule; at a curvature step that is not allowed
//     (kCartesian) the third differences of the sampled positions within the jerk limit: 3/4 of
//     the step dk v^2 / dt plus the jerk on either side within jerk. Checked on the samples
//     (analytically and by second and third differences of x, y, z, except across a kink or an
//     allowed curvature step) and slowed down where they were exceeded; where its own motion is
//     not found on a stretch between stops, or is slower, seed 004's is used there (slowed down as
//     far as the same check asks; Timing::seed004_stretches counts them).
// In both, where the pieces carry an orientation, the tool's angular velocity rho v,
// acceleration and jerk hold the pieces' angular limits (intervals.cpp: (R1)-(R3)); an allowed
// curvature step's jerk is reported in corner_steps.
// Throws InputError for options.dt <= 0, max_samples < 1, an axis limit that is not positive
// or given in kPath mode, a piece with a non-positive limit, and a plan of more than
// max_samples samples (or of no finite duration): located at the move whose limits make it so
// long and naming the limit to raise, checked before any sample is made. An empty path gives
// one sample at rest.
Timing plan_timing(const Path& path, const TimingOptions& options = {});

}  // namespace blendbench
