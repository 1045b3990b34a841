#include "blendbench/timing/scurve.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <string>

#include "blendbench/core/format.hpp"

namespace blendbench {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr int kMaxIterations = 200;

// Jerk sign of each of the seven phases.
constexpr std::array<double, 7> kJerkSign{1, 0, -1, 0, -1, 0, 1};

// Distance of the change vp -> v (either direction), the building block of a move.
double change_distance(double v_from, double v_to, double a_max, double j_max) {
  return velocity_change(v_from, v_to, a_max, j_max).distance;
}

// d/dvp of the distance of the change between v and vp (vp > v), for Newton steps.
double change_distance_slope(double v, double vp, double a_max, double j_max) {
  const double dv = vp - v;
  if (dv <= 0) return std::numeric_limits<double>::infinity();
  if (dv * j_max >= a_max * a_max) return 0.5 * (dv / a_max + a_max / j_max) + 0.5 * (v + vp) / a_max;
  const double half = std::sqrt(dv / j_max);
  return half + 0.5 * (v + vp) / (j_max * half);
}

// Distance of the two changes v0 -> vp -> v1 (without cruise).
double ramps_distance(double v0, double vp, double v1, const ScurveLimits& lim) {
  return change_distance(v0, vp, lim.acceleration, lim.jerk) + change_distance(vp, v1, lim.deceleration, lim.jerk);
}

// Largest v in [lo, hi] with fits(v), given fits(lo) and a first guess; `fits` is monotone
// (true below some threshold). Tries the guess shrunk by a few ulps, then bisects.
template <class Fits>
double largest_fitting(double lo, double hi, Fits fits) {
  if (fits(hi)) return hi;
  for (double shrink = 4 * kEps; shrink < 1e-9; shrink *= 8) {
    const double v = lo + (hi - lo) * (1 - shrink);
    if (fits(v)) return v;
  }
  for (int it = 0; it < kMaxIterations && hi - lo > 2 * kEps * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    (fits(mid) ? lo : hi) = mid;
  }
  return lo;
}

// Phase durations of a change dv >= 0 with limits a_max, j_max: ramp, hold, ramp.
std::array<double, 3> change_durations(double dv, double a_max, double j_max) {
  if (dv <= 0) return {0, 0, 0};
  const double a_peak = dv * j_max >= a_max * a_max ? a_max : std::sqrt(dv * j_max);
  const double ramp = a_peak / j_max;
  const double hold = std::max(0.0, dv / a_peak - ramp);
  return {ramp, hold, ramp};
}

// Advances (s, v, a) by time dt under constant jerk j (dt may be negative).
ScurveState advance(const ScurveState& x, double j, double dt) {
  ScurveState y;
  y.s = x.s + dt * (x.v + dt * (0.5 * x.a + dt * j / 6.0));
  y.v = x.v + dt * (x.a + 0.5 * dt * j);
  y.a = x.a + dt * j;
  y.j = j;
  return y;
}

}  // namespace

double Scurve::duration() const {
  double total = 0;
  for (double d : durations) total += d;
  return total;
}

double Scurve::peak_acceleration() const { return jerk * durations[0]; }
double Scurve::peak_deceleration() const { return jerk * durations[4]; }

ScurveState Scurve::at(double t) const {
  const double total = duration();
  // the ends exactly, whatever rounding the phase sums carry
  if (t <= 0) return {0.0, v0, 0.0, durations[0] > 0 ? jerk : 0.0};
  if (t >= total) return {distance, v1, 0.0, durations[6] > 0 ? jerk : 0.0};
  // phases 0-2 forward from the start
  const double t_up = durations[0] + durations[1] + durations[2];
  if (t < t_up) {
    ScurveState x{0.0, v0, 0.0, 0.0};
    double rest = t;
    for (int k = 0; k < 3; ++k) {
      const double jk = kJerkSign[k] * jerk;
      if (rest <= durations[k] || k == 2) {
        const ScurveState y = advance(x, jk, std::min(rest, durations[k]));
        return {std::clamp(y.s, 0.0, distance), std::max(0.0, y.v), y.a, jk};
      }
      x = advance(x, jk, durations[k]);
      rest -= durations[k];
    }
  }
  // phases 6-3 backward from the end, so the end state is exact
  ScurveState x{distance, v1, 0.0, 0.0};
  double rest = total - t;
  for (int k = 6; k >= 3; --k) {
    const double jk = kJerkSign[k] * jerk;
    if (rest <= durations[k] || k == 3) {
      const ScurveState y = advance(x, jk, -std::min(rest, durations[k]));
      return {std::clamp(y.s, 0.0, distance), std::max(0.0, y.v), y.a, jk};
    }
    x = advance(x, jk, -durations[k]);
    rest -= durations[k];
  }
  return x;
}

double Scurve::time_at_distance(double x) const {
  const double total = duration();
  if (x <= 0 || distance <= 0) return 0.0;
  if (x >= distance) return total;
  // bracket [lo, hi] around the crossing; Newton steps with v = ds/dt, bisection when a step
  // leaves the bracket (near rest v is ~0 and Newton is slow)
  double lo = 0;
  double hi = total;
  double t = total * (x / distance);
  const double tol = 2 * kEps * distance;
  for (int it = 0; it < kMaxIterations; ++it) {
    const ScurveState y = at(t);
    if (std::abs(y.s - x) <= tol) return t;
    (y.s < x ? lo : hi) = t;
    double next = y.v > 0 ? t - (y.s - x) / y.v : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (next == t || hi - lo <= kEps * total) break;
    t = next;
  }
  return t;
}

VelocityChange velocity_change(double v0, double v1, double a_max, double j_max) {
  assert(a_max > 0 && j_max > 0);
  const double dv = std::abs(v1 - v0);
  if (dv == 0) return {};
  VelocityChange change;
  if (dv * j_max >= a_max * a_max) {
    change.a_peak = a_max;
    change.duration = dv / a_max + a_max / j_max;
  } else {
    change.a_peak = std::sqrt(dv * j_max);
    change.duration = 2.0 * std::sqrt(dv / j_max);
  }
  change.distance = 0.5 * (v0 + v1) * change.duration;
  return change;
}

double reachable_velocity(double v0, double distance, double a_max, double j_max, double v_cap) {
  assert(v0 >= 0 && a_max > 0 && j_max > 0);
  if (v_cap <= v0 || distance <= 0) return std::min(v0, v_cap);
  const auto fits = [&](double v1) { return change_distance(v0, v1, a_max, j_max) <= distance; };
  if (fits(v_cap)) return v_cap;
  // regime boundary: dv = a^2/j, covered in 2a/j at mean velocity v0 + a^2/(2j)
  const double dv_star = a_max * a_max / j_max;
  const double d_star = (v0 + 0.5 * dv_star) * 2.0 * a_max / j_max;
  double dv = 0;
  if (distance <= d_star) {
    // triangular: with half-duration x, dv = j x^2 and distance = j x^3 + 2 v0 x, i.e. the
    // depressed cubic x^3 + p x = q (p >= 0): the real root by the hyperbolic form, polished
    const double p = 2.0 * v0 / j_max;
    const double q = distance / j_max;
    double x = std::cbrt(q);
    if (p > 0) {
      const double arg = 1.5 * q / p * std::sqrt(3.0 / p);
      if (std::isfinite(arg) && arg < 1e150) x = 2.0 * std::sqrt(p / 3.0) * std::sinh(std::asinh(arg) / 3.0);
    }
    for (int it = 0; it < 3; ++it) {
      const double f = x * (x * x + p) - q;
      const double df = 3.0 * x * x + p;
      if (df <= 0) break;
      x = std::max(0.0, x - f / df);
    }
    dv = j_max * x * x;
  } else {
    // trapezoidal: dv^2 + b dv - c = 0 with b = 2 v0 + a^2/j, c = 2a (L - v0 a / j) > 0
    const double b = 2.0 * v0 + dv_star;
    const double c = 2.0 * a_max * (distance - v0 * a_max / j_max);
    dv = 2.0 * c / (b + std::sqrt(b * b + 4.0 * c));
  }
  const double guess = std::clamp(v0 + dv, v0, v_cap);
  return largest_fitting(v0, guess, fits);
}

ScurveResult plan_scurve(double distance, double v0, double v1, const ScurveLimits& limits) {
  assert(limits.velocity > 0 && limits.acceleration > 0 && limits.deceleration > 0 && limits.jerk > 0);
  assert(distance >= 0 && v0 >= 0 && v1 >= 0);
  ScurveResult result;
  Scurve& c = result.curve;
  c.v0 = v0;
  c.v1 = v1;
  c.jerk = limits.jerk;
  const double v_low = std::max(v0, v1);
  const double v_max = std::max(limits.velocity, v_low);
  if (v_low > limits.velocity) {
    result.outcome = {Status::kInfeasible, "boundary velocity " + format_mm_per_s(v_low) + " above the limit " +
                                               format_mm_per_s(limits.velocity)};
  }

  // shortest distance: the change v0 -> v1 alone
  const double d_min = ramps_distance(v0, v_low, v1, limits);
  double vp = v_low;
  if (d_min > distance) {
    if (result.outcome.ok()) {
      result.outcome = {Status::kInfeasible, "distance " + format_mm(distance) + " too short for " +
                                                 format_mm_per_s(v0) + " -> " + format_mm_per_s(v1) + " (needs " +
                                                 format_mm(d_min) + ")"};
    }
    distance = d_min;
  } else {
    const auto fits = [&](double v) { return ramps_distance(v0, v, v1, limits) <= distance; };
    if (fits(v_max)) {
      vp = v_max;
    } else if (v0 == v1 && limits.acceleration == limits.deceleration) {
      // symmetric: each half covers half the distance (closed form)
      vp = largest_fitting(v_low, reachable_velocity(v0, 0.5 * distance, limits.acceleration, limits.jerk, v_max),
                           fits);
    } else {
      // safeguarded Newton-bisection on f(vp) = ramps(vp) - distance, increasing in vp
      double lo = v_low;
      double hi = v_max;
      double x = 0.5 * (lo + hi);
      for (int it = 0; it < kMaxIterations && hi - lo > 2 * kEps * hi; ++it) {
        const double f = ramps_distance(v0, x, v1, limits) - distance;
        (f <= 0 ? lo : hi) = x;
        const double df = change_distance_slope(v0, x, limits.acceleration, limits.jerk) +
                          change_distance_slope(v1, x, limits.deceleration, limits.jerk);
        double next = x - f / df;
        if (!(next > lo && next < hi) || !std::isfinite(next)) next = 0.5 * (lo + hi);
        if (next == x) break;
        x = next;
      }
      vp = largest_fitting(v_low, lo, fits);
    }
  }

  // phase durations; the remainder of the distance is cruised
  c.v_peak = vp;
  const auto up = change_durations(vp - v0, limits.acceleration, limits.jerk);
  const auto down = change_durations(vp - v1, limits.deceleration, limits.jerk);
  const double cruise = vp > 0 ? std::max(0.0, distance - ramps_distance(v0, vp, v1, limits)) / vp : 0.0;
  c.durations = {up[0], up[1], up[2], cruise, down[0], down[1], down[2]};
  c.distance = distance;
  return result;
}

}  // namespace blendbench
