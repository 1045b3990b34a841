#pragma once
// A timed profile checked against its path: the limits that apply at an arc length, and the
// largest ratio of each limited quantity to its limit over the samples (<= 1: within it). The
// path-level terms are what plan_timing guarantees (timing.hpp); the axis terms are what one
// machine axis sees. Shared by the timing tests and the paper reproductions.

#include <cstddef>
#include <limits>
#include <vector>

#include "blendbench/program/path.hpp"
#include "blendbench/timing/timing.hpp"

namespace blendbench {

// The limits at path arc length s over every piece touching s (both at a junction). The speed
// limit and the curvature are the strictest of the pieces; the rate limits are the largest, so
// a sample on a junction (or a difference stencil across one) is held to the side that allows
// more, as the profile may use either side's limit there.
struct LocalLimits {
  double v_lim = std::numeric_limits<double>::infinity();     // m/s: v_lim(s), seed 004 eq. 25-27
  double kappa = 0;                                           // 1/m: the largest curvature
  double a_normal = std::numeric_limits<double>::infinity();  // m/s^2: the bound on kappa v^2
  // seed 004 eq. 24: sqrt(c^2 + kappa^4) (1/m^2) of the piece where it is largest against its jerk
  // limit, and that limit (m/s^3), for the constant-speed axis jerk sqrt(c^2 + kappa^4) v^3
  double eq24_factor = 0;
  double eq24_jerk = std::numeric_limits<double>::infinity();
  double acceleration = 0, deceleration = 0, jerk = 0, feed = 0;  // the largest of the pieces
};

// The feed limit (m/s) at local arc length `local` (m) of piece k: its velocity, or the highest
// junction velocity of the hand-over zones (ordered by piece, handover_zones) that contain it.
double feed_at(const Path& path, const std::vector<HandoverZone>& zones, std::size_t k, double local);

// The limits at path arc length s (m); `zones` as for feed_at.
LocalLimits limits_at(const Path& path, double s, const std::vector<HandoverZone>& zones = {});

// The largest feed and rate limits (feed, acceleration, deceleration, jerk; the other fields
// left at their defaults) of samples k0..k1 (k0 <= k1 < lim.size()): the limits a difference
// stencil over those samples is held to.
LocalLimits widest(const std::vector<LocalLimits>& lim, std::size_t k0, std::size_t k1);

// The largest feed and rate limits of the pieces wholly between arc lengths s0 <= s1, past the
// pieces at s0 and at s1 (fields as widest's; zero where there are none). A piece shorter than
// a sample period can fall between two samples and carry none of them, while a difference
// stencil over those samples spans its motion, under its own limits.
LocalLimits limits_between(const Path& path, double s0, double s1, const std::vector<HandoverZone>& zones = {});

// widest over samples k0..k1 of `samples` together with limits_between their arc lengths: the
// limits of every piece the stencil's motion touches.
LocalLimits widest(const Path& path, const std::vector<TimedSample>& samples, const std::vector<LocalLimits>& lim,
                   std::size_t k0, std::size_t k1, const std::vector<HandoverZone>& zones = {});

// The largest ratio value / limit found on a sampled profile (<= 1: within the limit), with the
// limits of limits_at at each sample. The axis terms come from finite differences of the sampled
// positions at the servo period (centred second and third differences), in the frame of the
// path, against the largest limits the stencil touches.
struct ProfileMargins {
  double velocity = 0;                 // v / v_lim(s): programmed feed and seed 004 eq. 25-27 at s
  double tangential_acceleration = 0;  // |a_t| / (acceleration or deceleration limit)
  double tangential_jerk = 0;          // |j_t| / jerk limit
  double normal_acceleration = 0;      // kappa v^2 / acceleration limit
  double eq24_jerk = 0;                // sqrt(c^2 + kappa^4) v^3 / jerk limit (seed 004 eq. 24)
  double axis_acceleration = 0;        // max over x, y, z of |d2x/dt2| / acceleration limit
  double axis_jerk = 0;                // max over x, y, z of |d3x/dt3| / jerk limit
  double axis_jerk_time = 0;           // s: where axis_jerk is reached (the stencil's centre)
  double axis_jerk_s = 0;              // m: path arc length there
  double axis_jerk_over_time = 0;      // s: total time (stencils x dt) with an axis jerk above its limit
};

// Checks the profile `timing` planned along `path`; `zones` are the hand-over zones it was
// planned with (handover_zones(path, options)), empty for none. All zero for an empty profile.
ProfileMargins profile_margins(const Path& path, const Timing& timing, const std::vector<HandoverZone>& zones = {});
// The same with the limits at every sample already found (lim[k] = limits_at(path,
// timing.samples[k].s, zones); lim.size() == timing.samples.size()).
ProfileMargins profile_margins(const Path& path, const Timing& timing, const std::vector<LocalLimits>& lim);

}  // namespace blendbench
