#include "planner/timing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "planner/blend.hpp"
#include "planner/input_error.hpp"
#include "planner/scurve.hpp"

// The method (issue 4), and where it is conservative:
//
// 1. The path is cut into intervals at every piece junction and, on pieces whose curvature
//    varies along s (clothoids with non-zero sharpness, Bezier curves), into kSubdivisions
//    equal sub-intervals, and at the ends of hand-over zones (below). Each interval gets a cap: the smallest v_lim on it, from the maximum
//    curvature and sharpness over the interval (004 eq. 25-27 are decreasing in both, so this
//    bounds v_lim(s) from below everywhere on the interval). Conservative: within an interval
//    the speed never uses the headroom of its less curved end.
// 2. Every interval boundary (knot) is a point of zero tangential acceleration, with its own
//    velocity bound: 0 at stops, the junction rules at kinks and curvature jumps (below).
//    Neighbouring intervals with identical limits and cap terms and an unconstrained knot
//    between them are merged (collinear lines, equal arcs). Conservative: the profile may not
//    carry acceleration through a knot, e.g. when it speeds up along a clothoid or Bezier.
// 3. A backward pass gives each knot the highest velocity from which the rest of the path can
//    still slow down in time (jerk-limited distance formulas, scurve.hpp), a forward pass the
//    highest reachable from the start; each interval is then one 7-phase S-curve between its
//    knot velocities with the highest peak below its cap that fits (scurve.hpp). Because every
//    S-curve is exact and stays within [min, max] of its knot velocities and peak, v <= cap
//    <= v_lim(s), kappa v^2 <= a, |a_t| and |j_t| hold on the whole continuous profile, hence
//    on every sample, up to rounding.
//
// Junction rules, at a knot where the tangent turns by theta or the curvature vector jumps by
// dk (derived here; the sources only say a controller slows down there, 004 section 3):
//   - a direction change theta at speed v is a velocity step 2 v sin(theta/2) within one servo
//     period dt, i.e. an acceleration pulse 2 v sin(theta/2)/dt. Keeping that pulse within the
//     step the jerk limit allows in one period (j dt) and within the acceleration limit gives
//       v <= min(j dt^2, a dt) / (2 sin(theta/2));
//   - a curvature jump dk (e.g. line -> tangent arc) makes the normal acceleration dk v^2 appear
//     within one period; keeping that step within j dt gives v <= sqrt(j dt / dk);
//   - Buffered stops at a kink;
//   a and j are the lowest of the two pieces' limits.
// The buffer mode of the junction (the earlier piece's) chooses the junction velocity v_J from
// the two programmed velocities (junction_velocity, program.hpp). Where v_J is above a piece's
// programmed velocity, that piece gets a hand-over zone next to the junction (timing.hpp):
// its feed term is v_J over the distance a jerk-limited change between v_J and its own
// velocity needs, so the profile can cross the junction at v_J and reach the slower velocity
// at the end of the zone at the latest. v_J is first lowered to the kink and curvature-jump
// bounds above, so a zone never lets a piece run faster than the junction allows. The
// curvature and sharpness terms are never relaxed.

namespace blendbench {
namespace {

// Sub-intervals per piece of varying curvature (step 1 above).
constexpr int kSubdivisions = 16;
// Angle (rad) below which a junction counts as tangent (as the blender decides, blend.cpp).
constexpr double kG1Angle = 1e-9;
// Relative margin on the scanned maximum curvature and sharpness of a Bezier (segment.hpp
// gives them to a relative error below 1e-9).
constexpr double kBezierScanMargin = 4e-9;
// A piece reaches its cap, or the feed, when within this share of it (timing.hpp).
constexpr double kReachShare = 1e-3;

const double kInf = std::numeric_limits<double>::infinity();

// The terms of v_lim over [s0, s1] (local arc lengths) of a piece: programmed velocity, eq. 25
// and eq. 26 (004) with the maximum curvature and sharpness there.
struct CapTerms {
  double feed = kInf;
  double curvature = kInf;
  double sharpness = kInf;
  [[nodiscard]] double min() const { return std::min({feed, curvature, sharpness}); }
  [[nodiscard]] const char* binding() const {
    return feed <= min() ? "feed" : curvature <= min() ? "curvature" : "sharpness";
  }
};

CapTerms cap_terms(const PathPiece& piece, double s0, double s1, double feed) {
  double kappa = max_curvature(piece.segment, s0, s1);
  double c = max_sharpness(piece.segment, s0, s1);
  if (std::holds_alternative<Bezier>(piece.segment)) {
    kappa *= 1 + kBezierScanMargin;
    c *= 1 + kBezierScanMargin;
  }
  const double a = piece.limits.acceleration;
  CapTerms terms;
  terms.feed = feed;
  terms.curvature = kappa > 0 ? std::sqrt(a / kappa) : kInf;
  // eq. 26 alone: the combined limit with no curvature term
  terms.sharpness = curvature_speed_limit(0.0, std::hypot(c, kappa * kappa), a, piece.limits.jerk);
  return terms;
}

bool varying_curvature(const Segment& segment) {
  if (std::holds_alternative<Bezier>(segment)) return true;
  if (const auto* c = std::get_if<Clothoid>(&segment)) return c->sharpness != 0;
  return false;
}

// A stretch of path planned as one S-curve between two knots of zero acceleration.
struct Interval {
  double s0 = 0;  // m, global arc length at the start
  double s1 = 0;  // m, at the end
  std::size_t piece = 0;       // the piece it starts on
  std::size_t piece_last = 0;  // the piece it ends on (after merging)
  CapTerms terms;              // its cap is terms.min()
  ScurveLimits limits;
  Scurve curve;
  double t0 = 0;  // s, start time
  [[nodiscard]] double length() const { return s1 - s0; }
};

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

// The velocity bound at the junction from piece `prev` to piece `next` (both of non-zero
// length; `stop` when a piece in between or `next` has stop_before): 0 at a stop, else the
// kink and curvature-jump rules above (infinity where the path is G2). The buffer mode's
// junction velocity is not part of it: the neighbouring intervals' caps carry it.
double junction_cap(const PathPiece& prev, const PathPiece& next, bool stop, const TimingOptions& options) {
  using Baseline = TimingOptions::Baseline;
  if (options.baseline == Baseline::kExactStop) return 0.0;
  const double theta =
      angle_between(tangent(prev.segment, length(prev.segment)), tangent(next.segment, 0.0));
  const bool kink = theta > kG1Angle;
  const bool buffered_kink = kink && prev.buffer == BufferMode::kBuffered;
  // the junction slow-down baseline keeps only the stops of Buffered kinks
  if (options.baseline == Baseline::kJunctionSlowdown) stop = buffered_kink;
  if (stop || buffered_kink) return 0.0;
  const double a = std::min({prev.limits.acceleration, prev.limits.deceleration, next.limits.acceleration,
                             next.limits.deceleration});
  const double j = std::min(prev.limits.jerk, next.limits.jerk);
  const double dt = options.dt;
  double cap = kInf;
  if (kink) cap = std::min(j * dt * dt, a * dt) / (2.0 * std::sin(0.5 * theta));
  const double dk = (curvature_vector(prev.segment, length(prev.segment)) - curvature_vector(next.segment, 0.0)).norm();
  if (dk > 0) cap = std::min(cap, std::sqrt(j * dt / dk));
  return cap;
}

// A junction between two pieces of non-zero length, with its velocity bound (junction_cap).
struct Junction {
  std::size_t prev = 0;
  std::size_t next = 0;
  double cap = 0;
};

// Every junction of the path in order (the first piece of non-zero length has none).
std::vector<Junction> junctions(const Path& path, const TimingOptions& options) {
  const auto& pieces = path.pieces();
  std::vector<Junction> out;
  std::size_t prev = pieces.size();
  bool stop = false;
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    stop = stop || pieces[k].stop_before;
    if (length(pieces[k].segment) <= 0) continue;
    if (prev < pieces.size()) out.push_back({prev, k, junction_cap(pieces[prev], pieces[k], stop, options)});
    stop = false;
    prev = k;
  }
  return out;
}

// The hand-over zones of one junction (see above and timing.hpp), appended to `zones`.
void junction_zones(const Path& path, const Junction& junction, std::vector<HandoverZone>& zones) {
  const PathPiece& prev = path.pieces()[junction.prev];
  const PathPiece& next = path.pieces()[junction.next];
  const double v_j = std::min(junction_velocity(prev.buffer, prev.limits.velocity, next.limits.velocity), junction.cap);
  // the slower next piece slows down from v_J after the junction
  if (v_j > next.limits.velocity) {
    const double d = velocity_change(v_j, next.limits.velocity, next.limits.deceleration, next.limits.jerk).distance;
    zones.push_back({junction.next, 0.0, std::min(d, length(next.segment)), v_j});
  }
  // the slower previous piece speeds up to v_J before the junction
  if (v_j > prev.limits.velocity) {
    const double d = velocity_change(prev.limits.velocity, v_j, prev.limits.acceleration, prev.limits.jerk).distance;
    const double len = length(prev.segment);
    zones.push_back({junction.prev, std::max(0.0, len - d), len, v_j});
  }
}

// The hand-over zones of every junction, ordered by piece and start.
std::vector<HandoverZone> all_zones(const Path& path, const std::vector<Junction>& joints) {
  std::vector<HandoverZone> zones;
  for (const Junction& junction : joints) junction_zones(path, junction, zones);
  std::sort(zones.begin(), zones.end(),
            [](const HandoverZone& a, const HandoverZone& b) { return a.piece != b.piece ? a.piece < b.piece : a.s0 < b.s0; });
  return zones;
}

// Cuts the path into intervals; knot_cap[i] bounds the velocity at the start of interval i
// (knot_cap.back() at the end of the path). Pieces are cut at their sub-interval points and at
// the ends of their hand-over zones.
void build_intervals(const Path& path, const TimingOptions& options, std::vector<Interval>& intervals,
                     std::vector<double>& knot_cap) {
  const auto& pieces = path.pieces();
  const std::vector<Junction> joints = junctions(path, options);
  const std::vector<HandoverZone> zones = all_zones(path, joints);
  std::size_t next_joint = 0;
  std::size_t first_zone = 0;
  std::vector<double> cuts;
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const PathPiece& piece = pieces[k];
    const double len = length(piece.segment);
    if (len <= 0) continue;
    double cap_in = 0.0;
    if (next_joint < joints.size() && joints[next_joint].next == k) cap_in = joints[next_joint++].cap;
    // cut points: sub-intervals of varying curvature, ends of hand-over zones
    const int m = varying_curvature(piece.segment) ? kSubdivisions : 1;
    while (first_zone < zones.size() && zones[first_zone].piece < k) ++first_zone;
    std::size_t end_zone = first_zone;
    while (end_zone < zones.size() && zones[end_zone].piece == k) ++end_zone;
    cuts.clear();
    for (int i = 0; i <= m; ++i) cuts.push_back(i == m ? len : len * i / m);
    for (std::size_t z = first_zone; z < end_zone; ++z) cuts.insert(cuts.end(), {zones[z].s0, zones[z].s1});
    std::sort(cuts.begin(), cuts.end());
    cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
    const ScurveLimits lim{0.0, piece.limits.acceleration, piece.limits.deceleration, piece.limits.jerk};
    for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
      const double a = cuts[i];
      const double b = cuts[i + 1];
      // the feed term: the programmed velocity, or the junction velocity in a hand-over zone
      double feed = piece.limits.velocity;
      for (std::size_t z = first_zone; z < end_zone; ++z) {
        if (zones[z].s0 <= a && b <= zones[z].s1) feed = std::max(feed, zones[z].velocity);
      }
      Interval iv;
      iv.s0 = i == 0 ? path.offset(k) : path.offset(k) + a;
      iv.s1 = i + 2 == cuts.size() ? path.offset(k + 1) : path.offset(k) + b;
      iv.piece = iv.piece_last = k;
      iv.terms = cap_terms(piece, a, b, feed);
      iv.limits = lim;
      iv.limits.velocity = iv.terms.min();
      intervals.push_back(iv);
      knot_cap.push_back(i == 0 ? cap_in : kInf);
    }
  }
  knot_cap.push_back(0.0);
}

// Merges neighbours across a knot that constrains nothing (no stop, kink or curvature jump)
// when their limits and cap terms are identical (e.g. collinear lines, equal tangent arcs in
// one plane). The rule does not depend on the values of the limits, so raising a limit of
// every piece alike never changes the intervals (and the cycle time can only fall).
void merge_intervals(const Path& path, std::vector<Interval>& intervals, std::vector<double>& knot_cap) {
  if (intervals.empty()) return;
  std::vector<Interval> merged{intervals.front()};
  std::vector<double> caps{knot_cap.front()};
  for (std::size_t i = 1; i < intervals.size(); ++i) {
    Interval& last = merged.back();
    const Interval& iv = intervals[i];
    const Limits& a = path.pieces()[last.piece_last].limits;
    const Limits& b = path.pieces()[iv.piece].limits;
    const bool same = a.velocity == b.velocity && a.acceleration == b.acceleration &&
                      a.deceleration == b.deceleration && a.jerk == b.jerk && iv.terms.feed == last.terms.feed &&
                      iv.terms.curvature == last.terms.curvature && iv.terms.sharpness == last.terms.sharpness;
    if (same && knot_cap[i] == kInf) {
      last.s1 = iv.s1;
      last.piece_last = iv.piece_last;
      continue;
    }
    merged.push_back(iv);
    caps.push_back(knot_cap[i]);
  }
  caps.push_back(knot_cap.back());
  intervals = std::move(merged);
  knot_cap = std::move(caps);
}

// Whether interval i can go from w0 to w1 (the change alone fits in its length).
bool fits(const Interval& iv, double w0, double w1) {
  const ScurveLimits& lim = iv.limits;
  const double d = w0 >= w1 ? velocity_change(w0, w1, lim.deceleration, lim.jerk).distance
                            : velocity_change(w0, w1, lim.acceleration, lim.jerk).distance;
  return d <= iv.length();
}

// Knot velocities: bounded by the knot caps and the neighbouring interval caps, reachable
// backward (braking in time) and forward (speeding up) with the jerk-limited formulas.
std::vector<double> knot_velocities(const std::vector<Interval>& intervals, const std::vector<double>& knot_cap) {
  const std::size_t n = intervals.size();
  std::vector<double> w(n + 1);
  for (std::size_t i = 0; i <= n; ++i) {
    w[i] = knot_cap[i];
    if (i > 0) w[i] = std::min(w[i], intervals[i - 1].limits.velocity);
    if (i < n) w[i] = std::min(w[i], intervals[i].limits.velocity);
  }
  // backward: the highest velocity that still slows down to the next knot's
  for (std::size_t i = n; i-- > 0;) {
    const Interval& iv = intervals[i];
    if (w[i] > w[i + 1]) {
      w[i] = reachable_velocity(w[i + 1], iv.length(), iv.limits.deceleration, iv.limits.jerk, w[i]);
    }
  }
  // forward: the highest velocity reachable from the previous knot's
  for (std::size_t i = 0; i < n; ++i) {
    const Interval& iv = intervals[i];
    if (w[i + 1] > w[i]) {
      w[i + 1] = reachable_velocity(w[i], iv.length(), iv.limits.acceleration, iv.limits.jerk, w[i + 1]);
    }
  }
  // repair the rare interval where rounding across the two regimes of the distance formula
  // breaks exact monotonicity; velocities only go down, so this terminates
  for (std::size_t i = 0, guard = 0; i < n && guard < 8 * n + 64; ++guard) {
    const Interval& iv = intervals[i];
    if (fits(iv, w[i], w[i + 1])) {
      ++i;
    } else if (w[i] > w[i + 1]) {
      w[i] = std::nextafter(reachable_velocity(w[i + 1], iv.length(), iv.limits.deceleration, iv.limits.jerk, w[i]), 0.0);
      if (i > 0) --i;
    } else {
      w[i + 1] = std::nextafter(reachable_velocity(w[i], iv.length(), iv.limits.acceleration, iv.limits.jerk, w[i + 1]), 0.0);
    }
  }
  return w;
}

// Time t in [t_lo, t_hi] where the monotone v of `c` crosses `v` (bisection).
double crossing_time(const Scurve& c, double v, double t_lo, double t_hi, bool rising) {
  for (int it = 0; it < 100 && t_hi - t_lo > 0; ++it) {
    const double mid = 0.5 * (t_lo + t_hi);
    if (mid <= t_lo || mid >= t_hi) break;
    ((c.at(mid).v >= v) == rising ? t_hi : t_lo) = mid;
  }
  return 0.5 * (t_lo + t_hi);
}

// Time (s) the profile spends at or above velocity v.
double time_at_or_above(const Scurve& c, double v) {
  if (c.v_peak < v) return 0.0;
  const double t_up = c.durations[0] + c.durations[1] + c.durations[2];
  const double t_down = t_up + c.durations[3];
  const double total = c.duration();
  const double rise = c.v0 >= v ? 0.0 : crossing_time(c, v, 0.0, t_up, true);
  const double fall = c.v1 >= v ? total : crossing_time(c, v, t_down, total, false);
  return std::max(0.0, fall - rise);
}

// Time (s) at which the profile has covered distance s (bisection on the monotone s(t)).
double time_at_distance(const Scurve& c, double s) {
  double lo = 0;
  double hi = c.duration();
  for (int it = 0; it < 100; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (mid <= lo || mid >= hi) break;
    (c.at(mid).s < s ? lo : hi) = mid;
  }
  return hi;
}

// Largest velocity (m/s) of interval iv on its part over global [a, b], and whether that part
// holds the interval's peak (a local maximum strictly above both knot velocities).
std::pair<double, bool> peak_on(const Interval& iv, double a, double b) {
  const Scurve& c = iv.curve;
  const double t_up = c.durations[0] + c.durations[1] + c.durations[2];
  const double t_down = t_up + c.durations[3];
  const double ta = a <= iv.s0 ? 0.0 : time_at_distance(c, a - iv.s0);
  const double tb = b >= iv.s1 ? c.duration() : time_at_distance(c, b - iv.s0);
  const bool holds_peak = ta <= t_down && tb >= t_up;
  if (holds_peak) return {c.v_peak, c.v_peak > std::max(c.v0, c.v1)};
  return {std::max(c.at(ta).v, c.at(tb).v), false};
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

// The binding constraint of every piece (timing.hpp).
std::vector<PieceTiming> piece_reports(const Path& path, const std::vector<Interval>& intervals) {
  const auto& pieces = path.pieces();
  std::vector<PieceTiming> reports(pieces.size());
  for (std::size_t k = 0; k < pieces.size(); ++k) reports[k] = {k, 0.0, "stop"};
  struct Seen {
    bool any = false, at_cap = false, holds_peak = false, acceleration = false;
    const char* cap_binding = "feed";
  };
  std::vector<Seen> seen(pieces.size());
  for (const Interval& iv : intervals) {
    for (std::size_t k = iv.piece; k <= iv.piece_last; ++k) {
      if (length(pieces[k].segment) <= 0) continue;
      const auto [v, holds_peak] = peak_on(iv, path.offset(k), path.offset(k + 1));
      Seen& s = seen[k];
      PieceTiming& r = reports[k];
      const bool at_cap = v >= (1 - kReachShare) * iv.limits.velocity;
      if (!s.any || v > r.v_peak) r.v_peak = v;
      if (at_cap && !s.at_cap) s.cap_binding = iv.terms.binding();
      s.any = true;
      s.at_cap = s.at_cap || at_cap;
      s.holds_peak = s.holds_peak || holds_peak;
      const double acc = std::max(iv.curve.peak_acceleration() / iv.limits.acceleration,
                                  iv.curve.peak_deceleration() / iv.limits.deceleration);
      s.acceleration = s.acceleration || acc >= 1 - kReachShare;
    }
  }
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const Seen& s = seen[k];
    if (!s.any) continue;
    reports[k].binding = s.at_cap ? s.cap_binding : s.holds_peak ? "length" : s.acceleration ? "acceleration" : "jerk";
  }
  return reports;
}

}  // namespace

std::vector<HandoverZone> handover_zones(const Path& path, const TimingOptions& options) {
  validate(path, options);
  return all_zones(path, junctions(path, options));
}

Timing plan_timing(const Path& path, const TimingOptions& options) {
  validate(path, options);
  Timing timing;
  timing.dt = options.dt;
  std::vector<Interval> intervals;
  std::vector<double> knot_cap;
  build_intervals(path, options, intervals, knot_cap);
  merge_intervals(path, intervals, knot_cap);
  if (intervals.empty()) {
    timing.samples.push_back({0, path.length(), 0, 0, 0});
    for (std::size_t k = 0; k < path.pieces().size(); ++k) timing.pieces.push_back({k, 0.0, "stop"});
    return timing;
  }

  // knot velocities, then one S-curve per interval
  const std::vector<double> w = knot_velocities(intervals, knot_cap);
  double t = 0;
  double feed_time = 0;
  for (std::size_t i = 0; i < intervals.size(); ++i) {
    Interval& iv = intervals[i];
    const ScurveResult plan = plan_scurve(iv.length(), w[i], w[i + 1], iv.limits);
    if (!plan.outcome.ok() && timing.outcome.ok()) {
      timing.outcome = {plan.outcome.status, "interval at s = " + std::to_string(iv.s0) + " m: " + plan.outcome.message};
    }
    iv.curve = plan.curve;
    iv.t0 = t;
    t += iv.curve.duration();
    feed_time += time_at_or_above(iv.curve, (1 - kReachShare) * path.pieces()[iv.piece].limits.velocity);
  }
  timing.cycle_time = t;
  timing.feed_share = t > 0 ? feed_time / t : 0.0;
  timing.samples = sample(intervals, t, path.length(), options.dt);
  timing.pieces = piece_reports(path, intervals);
  return timing;
}

}  // namespace blendbench
