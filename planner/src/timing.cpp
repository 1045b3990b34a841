#include "planner/timing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "planner/blend.hpp"
#include "planner/input_error.hpp"
#include "planner/scurve.hpp"

namespace blendbench {
namespace {

// A stretch of path planned as one S-curve between two knots at zero acceleration.
struct Interval {
  double s0 = 0;  // m, global arc length at the start
  double s1 = 0;  // m, at the end
  std::size_t piece = 0;
  double cap = 0;  // m/s, upper bound of v_lim on [s0, s1]
  ScurveLimits limits;
  Scurve curve;
  double t0 = 0;  // s, start time
};

// The terms of v_lim on a piece: programmed velocity, eq. 25 and eq. 26 (004) from the maximum
// curvature and sharpness over [s0, s1] (local arc lengths), which bound v_lim from below.
struct CapTerms {
  double feed;
  double curvature;
  double sharpness;
  [[nodiscard]] double min() const { return std::min({feed, curvature, sharpness}); }
};

CapTerms cap_terms(const PathPiece& piece, double s0, double s1) {
  const double kappa = max_curvature(piece.segment, s0, s1);
  const double c = max_sharpness(piece.segment, s0, s1);
  const double a = piece.limits.acceleration;
  const double j = piece.limits.jerk;
  const double inf = std::numeric_limits<double>::infinity();
  return {piece.limits.velocity, kappa > 0 ? std::sqrt(a / kappa) : inf,
          curvature_speed_limit(0.0, std::hypot(c, kappa * kappa), a, j)};
}

void validate(const Path& path, const TimingOptions& options) {
  if (!(options.dt > 0) || !std::isfinite(options.dt)) {
    throw InputError("", 0, 0, "dt", "servo period must be positive, got " + std::to_string(options.dt) + " s");
  }
  for (std::size_t k = 0; k < path.pieces().size(); ++k) {
    const Limits& lim = path.pieces()[k].limits;
    for (const auto& [name, value] : {std::pair{"velocity", lim.velocity}, std::pair{"acceleration", lim.acceleration},
                                      std::pair{"deceleration", lim.deceleration}, std::pair{"jerk", lim.jerk}}) {
      if (!(value > 0) || !std::isfinite(value)) {
        throw InputError("", 0, 0, name,
                         "piece " + std::to_string(k) + ": " + name + " limit must be positive, got " +
                             std::to_string(value));
      }
    }
  }
}

// Samples the chained intervals at t = k dt; the last sample is the end at rest.
std::vector<TimedSample> sample(const std::vector<Interval>& intervals, double total, double length, double dt) {
  const auto n = static_cast<std::size_t>(std::ceil(total / dt));
  std::vector<TimedSample> samples;
  samples.reserve(n + 1);
  std::size_t i = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) * dt;
    while (i + 1 < intervals.size() && t >= intervals[i + 1].t0) ++i;
    const Interval& iv = intervals[i];
    const ScurveState x = iv.curve.at(t - iv.t0);
    // clamp into the interval so rounding of s0 + s never breaks monotonicity
    samples.push_back({t, std::clamp(iv.s0 + x.s, iv.s0, iv.s1), x.v, x.a, x.j});
  }
  samples.push_back({static_cast<double>(n) * dt, length, 0.0, 0.0, 0.0});
  return samples;
}

}  // namespace

Timing plan_timing(const Path& path, const TimingOptions& options) {
  validate(path, options);
  Timing timing;
  timing.dt = options.dt;
  const auto& pieces = path.pieces();
  if (pieces.empty()) {
    timing.samples.push_back({0, 0, 0, 0, 0});
    return timing;
  }

  // every piece rest to rest, capped by the lowest v_lim on it
  std::vector<Interval> intervals;
  intervals.reserve(pieces.size());
  double t = 0;
  double feed_time = 0;
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const PathPiece& piece = pieces[k];
    Interval iv;
    iv.s0 = path.offset(k);
    iv.s1 = path.offset(k + 1);
    iv.piece = k;
    const double len = length(piece.segment);
    const CapTerms terms = cap_terms(piece, 0.0, len);
    iv.cap = terms.min();
    iv.limits = {iv.cap, piece.limits.acceleration, piece.limits.deceleration, piece.limits.jerk};
    const ScurveResult plan = plan_scurve(len, 0.0, 0.0, iv.limits);
    if (!plan.outcome.ok()) timing.outcome = plan.outcome;
    iv.curve = plan.curve;
    iv.t0 = t;
    t += iv.curve.duration();

    PieceTiming report{k, iv.curve.v_peak, "length"};
    if (len <= 0) {
      report.binding = "stop";
    } else if (iv.curve.v_peak >= (1 - 1e-3) * iv.cap) {
      report.binding = terms.feed <= iv.cap ? "feed" : terms.curvature <= iv.cap ? "curvature" : "sharpness";
    }
    if (iv.curve.v_peak >= (1 - 1e-3) * piece.limits.velocity) feed_time += iv.curve.durations[3];
    timing.pieces.push_back(report);
    intervals.push_back(iv);
  }
  timing.cycle_time = t;
  timing.feed_share = t > 0 ? feed_time / t : 0.0;
  timing.samples = sample(intervals, t, path.length(), options.dt);
  return timing;
}

}  // namespace blendbench
