#pragma once
// Jerk-limited (S-curve) motion along one coordinate: the 7-phase profile that starts and ends
// with zero acceleration, and the distance formulas the lookahead planner builds on.
//
// A velocity change from v0 to v1 (a = 0 at both ends) under acceleration limit A and jerk
// limit J ramps the acceleration up with jerk J, holds it, and ramps it down with jerk -J:
//   |dv| >= A^2/J: peak acceleration A, duration |dv|/A + A/J        (trapezoidal acceleration)
//   |dv| <  A^2/J: peak acceleration sqrt(|dv| J), duration 2 sqrt(|dv|/J)  (triangular)
// The acceleration is symmetric in time, so the distance covered is (v0 + v1)/2 * duration.
// A move over a distance L is such a change v0 -> vp (limit `acceleration`), a cruise at vp,
// and a change vp -> v1 (limit `deceleration`), with vp <= `velocity` the highest peak that
// fits in L. All quantities are SI (m, s, m/s, m/s^2, m/s^3) and non-negative velocities.

#include <array>

#include "blendbench/core/status.hpp"

namespace blendbench {

// Limits of one S-curve move (all > 0): peak velocity, acceleration while speeding up,
// deceleration while slowing down (a magnitude), jerk.
struct ScurveLimits {
  double velocity = 0;
  double acceleration = 0;
  double deceleration = 0;
  double jerk = 0;
};

// Position, velocity, acceleration, jerk of a profile at one instant (m, m/s, m/s^2, m/s^3).
struct ScurveState {
  double s = 0;
  double v = 0;
  double a = 0;
  double j = 0;
};

// A planned 7-phase profile: phase k (0..6) lasts `durations[k]` with jerk +J, 0, -J, 0, -J,
// 0, +J. Phases 0-2 speed up from v0 to v_peak, phase 3 cruises at v_peak, phases 4-6 slow down
// to v1 (any of them may last 0).
struct Scurve {
  double distance = 0;  // m
  double v0 = 0;        // m/s at t = 0, acceleration 0
  double v1 = 0;        // m/s at t = duration(), acceleration 0
  double v_peak = 0;    // m/s, the cruise velocity
  double jerk = 0;      // m/s^3, the jerk magnitude used
  std::array<double, 7> durations{};  // s

  [[nodiscard]] double duration() const;
  // Peak |acceleration| while speeding up (phases 0-2) and while slowing down (phases 4-6).
  [[nodiscard]] double peak_acceleration() const;
  [[nodiscard]] double peak_deceleration() const;
  // The state at time t, clamped to [0, duration()]. Phases 0-3 are integrated forward from
  // the start and phases 4-6 backward from the end, so s(0) = 0 and s(duration()) = distance
  // hold exactly, and s is non-decreasing and v >= 0 up to rounding of one ulp.
  [[nodiscard]] ScurveState at(double t) const;
  // The time (s) at which at(t).s reaches x (m, clamped to [0, distance]): safeguarded Newton
  // on the non-decreasing s(t), to within a few ulps of s. 0 for x <= 0, duration() for
  // x >= distance.
  [[nodiscard]] double time_at_distance(double x) const;
};

// Duration (s) and distance (m) of the velocity change v0 -> v1 with zero acceleration at both
// ends, under acceleration limit `a_max` and jerk limit `j_max` (see the header comment).
struct VelocityChange {
  double duration = 0;
  double distance = 0;
  double a_peak = 0;  // peak |acceleration| reached
};
VelocityChange velocity_change(double v0, double v1, double a_max, double j_max);

// The highest v1 >= v0 (capped at v_cap >= v0) reachable from v0 (a = 0) within `distance`,
// ending with a = 0: velocity_change(v0, v1, a_max, j_max).distance <= distance holds exactly
// in floating point for the returned value. Closed form (004-independent: solved here from the
// distance formula: a depressed cubic in the half-duration for the triangular case, a
// quadratic in dv for the trapezoidal one), then nudged down until the inequality holds.
// Used both forwards (speeding up) and backwards (the highest start velocity that can still
// slow down to v0 within `distance`, since the profile is time-reversible).
double reachable_velocity(double v0, double distance, double a_max, double j_max, double v_cap);

// Plans a move over `distance` >= 0 from v0 to v1 (both <= limits.velocity). The peak velocity
// is the highest vp in [max(v0, v1), limits.velocity] whose two velocity changes fit in the
// distance (closed form when one side has zero length, else a safeguarded Newton-bisection on
// vp); the remainder is cruised, so the distance is covered exactly. Infeasible (with a message
// naming the shortfall) when the distance is too short for the change v0 -> v1 itself; the
// returned profile is then the one for the shortest feasible distance.
struct ScurveResult {
  Outcome outcome;
  Scurve curve;
};
ScurveResult plan_scurve(double distance, double v0, double v1, const ScurveLimits& limits);

}  // namespace blendbench
