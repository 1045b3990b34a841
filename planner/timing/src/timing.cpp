#include "blendbench/timing/timing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "blendbench/corner/blend.hpp"
#include "blendbench/core/format.hpp"
#include "blendbench/core/input_error.hpp"
#include "blendbench/timing/scurve.hpp"

// The method (issue 4), and where it is conservative:
//
// 1. The path is cut into intervals at every piece junction, at the ends of hand-over zones
//    (below) and, on pieces whose curvature varies along s (clothoids with non-zero sharpness,
//    Bezier curves), into kSubdivisions equal sub-intervals. Each interval gets a cap: the
//    smallest v_lim on it, from the maximum curvature and sharpness over the interval (004
//    eq. 25-27 are decreasing in both, so this bounds v_lim(s) from below everywhere on the
//    interval). Neighbouring intervals with identical limits and cap terms and an
//    unconstrained knot between them are merged (collinear lines, equal arcs). Conservative:
//    within an interval the speed never uses the headroom of its less curved end. Intervals on
//    pieces of constant curvature are "flat" (their cap is v_lim itself).
// 2. The profile is a chain of 7-phase S-curves, each between two knots of zero tangential
//    acceleration and spanning one interval or a run of them (a span). Anchors, the knots that
//    always keep zero acceleration: the ends, every knot with a bound (0 at stops, the junction
//    rules at kinks and curvature jumps, below), changes of acceleration, deceleration or jerk,
//    cap changes next to a flat interval, and both ends of every plateau of equal caps that is
//    a local minimum or maximum of the caps. Between two anchors the caps are monotone (a
//    clothoid entering a corner, one flank of a Bezier, ...), and one span covers them, so the
//    profile carries acceleration through the inner knots. Conservative: zero acceleration at
//    the anchors, e.g. where a line meets a clothoid whose cap is below the line's.
// 3. A backward pass gives each span end the highest velocity from which the rest of the path
//    can still slow down in time (jerk-limited distance formulas, scurve.hpp), a forward pass
//    the highest reachable from the start. A span must then go between its knot velocities
//    under the cap of every interval it covers: the monotone change between them (cruising at
//    the higher velocity, changing at the far end) is checked against each cap (the profile is
//    unimodal in s, so its largest velocity on an interval is at an end of it or its peak).
//    Where it leaves a cap, the span's higher end gets a knot bound, the highest velocity for
//    which it fits (bisection; the fit is monotone in that velocity, both changes being
//    time-optimal from a common state), unless a chain of zero-acceleration knots at every
//    interval would reach higher: then the span falls back to that. The passes then run
//    again, at most kLowerRounds times; spans still leaving a cap after that fall back, and
//    after kFallbackRounds more every knot does (the method of option carry_acceleration =
//    false, where every span is one interval and fits by construction).
// 4. Each span gets the highest peak under its caps that fits (bisection on the peak bound, the
//    profile rising pointwise with it), and is replaced by the zero-acceleration chain between
//    the same knot velocities where that is faster, so a span never loses time
//    against the chain. Because every S-curve is exact and its velocity is checked against the
//    caps at every knot it crosses and at its peak, v <= cap <= v_lim(s), kappa v^2 <= a,
//    |a_t| and |j_t| hold on the whole continuous profile, hence on every sample, up to
//    rounding.
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
// Relative difference under which two caps count as equal (plateaus, step 2).
constexpr double kSameCap = 1e-12;
// Rounds of lowering span ends (step 3) before the knots of a span that still leaves its caps
// fall back to zero acceleration, and rounds of that before every knot does.
constexpr int kLowerRounds = 8;
constexpr int kFallbackRounds = 2;
// Bisection of the highest end velocity or peak under the caps: steps and relative width.
constexpr int kBisections = 40;
constexpr double kBisectionTol = 1e-6;

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

// A stretch of path with one cap (step 1): a piece, a sub-interval of one, or merged pieces.
struct Interval {
  double s0 = 0;  // m, global arc length at the start
  double s1 = 0;  // m, at the end
  std::size_t piece = 0;       // the piece it starts on
  std::size_t piece_last = 0;  // the piece it ends on (after merging)
  CapTerms terms;              // its cap is terms.min()
  ScurveLimits limits;         // limits.velocity is the cap
  bool flat = true;            // on a piece of constant curvature (the cap is exact there)
  // filled from the span that covers it: the largest velocity on it, and whether it holds a
  // peak of the span strictly above both span ends
  double v_max = 0;
  bool holds_peak = false;
  [[nodiscard]] double length() const { return s1 - s0; }
};

// A run of intervals [first, last) between two knots of zero acceleration, planned as one
// S-curve (steps 2-4).
struct Span {
  std::size_t first = 0;
  std::size_t last = 0;
  double s0 = 0;  // m, global arc lengths of its ends
  double s1 = 0;
  ScurveLimits limits;  // acceleration, deceleration, jerk of its intervals; velocity: peak bound
  Scurve curve;
  double t0 = 0;  // s, start time
  [[nodiscard]] double length() const { return s1 - s0; }
  // The velocity where the curve has covered x (m from the span's start).
  [[nodiscard]] double velocity_at(double x) const { return curve.at(curve.time_at_distance(x)).v; }
};

void validate(const Path& path, const TimingOptions& options) {
  if (!(options.dt > 0) || !std::isfinite(options.dt)) {
    throw InputError("", 0, 0, "dt", "servo period must be positive, got " + format_value(options.dt) + " s");
  }
  for (std::size_t k = 0; k < path.pieces().size(); ++k) {
    const Limits& lim = path.pieces()[k].limits;
    struct Named {
      const char* name;
      double value;  // SI
      const char* unit;  // after conversion to mm
    };
    for (const auto& [name, value, unit] : {Named{"velocity", lim.velocity, " mm/s"},
                                            Named{"acceleration", lim.acceleration, " mm/s^2"},
                                            Named{"deceleration", lim.deceleration, " mm/s^2"},
                                            Named{"jerk", lim.jerk, " mm/s^3"}}) {
      if (!(value > 0) || !std::isfinite(value)) {
        throw InputError("", 0, 0, name,
                         "piece " + std::to_string(k) + ": " + name + " limit must be positive, got " +
                             format_value(value * 1e3) + unit);
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
  // reserved once: on long programs growing these vectors (and faulting in their pages) cost
  // more than building the intervals
  std::size_t count = 2 * zones.size();
  for (const PathPiece& piece : pieces) count += varying_curvature(piece.segment) ? kSubdivisions : 1;
  intervals.reserve(intervals.size() + count);
  knot_cap.reserve(knot_cap.size() + count + 1);
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
      iv.flat = m == 1;
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
  // compacted in place: intervals[0..kept] are the merged ones, knot_cap[i] their start caps
  std::size_t kept = 0;
  const double end_cap = knot_cap.back();
  for (std::size_t i = 1; i < intervals.size(); ++i) {
    Interval& last = intervals[kept];
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
    ++kept;
    intervals[kept] = iv;
    knot_cap[kept] = knot_cap[i];
  }
  intervals.resize(kept + 1);
  knot_cap.resize(kept + 2);
  knot_cap[kept + 1] = end_cap;
}

bool same_cap(double a, double b) { return std::abs(a - b) <= kSameCap * std::max(a, b); }

// Whether two intervals can share one S-curve: the same acceleration, deceleration and jerk.
bool same_limits(const ScurveLimits& a, const ScurveLimits& b) {
  return a.acceleration == b.acceleration && a.deceleration == b.deceleration && a.jerk == b.jerk;
}

// The knots that keep zero acceleration (step 2): the ends of the path, knots with a bound
// (stops, kinks, curvature jumps), changes of the S-curve limits, cap changes next to a flat
// interval, and both ends of every plateau of equal caps between them that is a local
// extremum (lower, or higher, than the caps on either side, where a neighbouring anchor counts
// as lower). Between two anchors the caps are then monotone.
std::vector<char> anchor_knots(const std::vector<Interval>& iv, const std::vector<double>& knot_cap) {
  const std::size_t n = iv.size();
  std::vector<char> anchor(n + 1, 1);
  for (std::size_t k = 1; k < n; ++k) {
    const Interval& a = iv[k - 1];
    const Interval& b = iv[k];
    anchor[k] = knot_cap[k] != kInf || !same_limits(a.limits, b.limits) ||
                ((a.flat || b.flat) && !same_cap(a.limits.velocity, b.limits.velocity));
  }
  // plateaus between the anchors above
  std::vector<char> extremum(n + 1, 0);
  for (std::size_t i = 0; i < n;) {
    // the plateau [i, j)
    const double c = iv[i].limits.velocity;
    std::size_t j = i + 1;
    while (j < n && anchor[j] == 0 && same_cap(iv[j].limits.velocity, c)) ++j;
    // an anchor on a side counts as lower (it is a junction or a change of limits)
    const double before = anchor[i] != 0 ? 0.0 : iv[i - 1].limits.velocity;
    const double after = anchor[j] != 0 ? 0.0 : iv[j].limits.velocity;
    const bool valley = anchor[i] == 0 && anchor[j] == 0 && before > c && after > c;
    if (valley || (before < c && after < c)) extremum[i] = extremum[j] = 1;
    i = j;
  }
  for (std::size_t k = 0; k <= n; ++k) anchor[k] = static_cast<char>(anchor[k] | extremum[k]);
  return anchor;
}

// The spans between consecutive active knots.
std::vector<Span> make_spans(const std::vector<Interval>& iv, const std::vector<char>& active) {
  std::vector<Span> spans;
  for (std::size_t i = 0; i < iv.size();) {
    std::size_t j = i + 1;
    while (j < iv.size() && active[j] == 0) ++j;
    Span sp;
    sp.first = i;
    sp.last = j;
    sp.s0 = iv[i].s0;
    sp.s1 = iv[j - 1].s1;
    sp.limits = iv[i].limits;
    spans.push_back(sp);
    i = j;
  }
  return spans;
}

// Distance (m) of the change between w0 and w1 on span sp.
double change_distance(const Span& sp, double w0, double w1) {
  const ScurveLimits& lim = sp.limits;
  return w0 >= w1 ? velocity_change(w0, w1, lim.deceleration, lim.jerk).distance
                  : velocity_change(w0, w1, lim.acceleration, lim.jerk).distance;
}

// Whether a span can go from w0 to w1 (the change alone fits in its length).
bool fits(const Span& sp, double w0, double w1) { return change_distance(sp, w0, w1) <= sp.length(); }

// Knot velocities of the spans: bounded by `cap` (one per span end), reachable backward
// (braking in time) and forward (speeding up) with the jerk-limited formulas.
std::vector<double> knot_velocities(const std::vector<Span>& spans, const std::vector<double>& cap) {
  const std::size_t n = spans.size();
  std::vector<double> w = cap;
  // backward: the highest velocity that still slows down to the next knot's
  for (std::size_t i = n; i-- > 0;) {
    const Span& sp = spans[i];
    if (w[i] > w[i + 1]) {
      w[i] = reachable_velocity(w[i + 1], sp.length(), sp.limits.deceleration, sp.limits.jerk, w[i]);
    }
  }
  // forward: the highest velocity reachable from the previous knot's
  for (std::size_t i = 0; i < n; ++i) {
    const Span& sp = spans[i];
    if (w[i + 1] > w[i]) {
      w[i + 1] = reachable_velocity(w[i], sp.length(), sp.limits.acceleration, sp.limits.jerk, w[i + 1]);
    }
  }
  // repair the rare span where rounding across the two regimes of the distance formula
  // breaks exact monotonicity; velocities only go down, so this terminates
  for (std::size_t i = 0, guard = 0; i < n && guard < 8 * n + 64; ++guard) {
    const Span& sp = spans[i];
    if (fits(sp, w[i], w[i + 1])) {
      ++i;
    } else if (w[i] > w[i + 1]) {
      w[i] = std::nextafter(reachable_velocity(w[i + 1], sp.length(), sp.limits.deceleration, sp.limits.jerk, w[i]), 0.0);
      if (i > 0) --i;
    } else {
      w[i + 1] = std::nextafter(reachable_velocity(w[i], sp.length(), sp.limits.acceleration, sp.limits.jerk, w[i + 1]), 0.0);
    }
  }
  return w;
}

// Plans the curve of span sp from w0 to w1 with peak bound v_peak (>= both); returns
// plan_scurve's outcome.
Outcome set_profile(Span& sp, double w0, double w1, double v_peak) {
  sp.limits.velocity = v_peak;
  ScurveResult plan = plan_scurve(sp.length(), w0, w1, sp.limits);
  sp.curve = plan.curve;
  return plan.outcome;
}

// Walks the intervals of span sp under its profile: f(i, v_max, holds_peak) for each, with the
// largest velocity on interval i (the profile is unimodal in s: the peak where its peak range
// meets the interval, else the larger end) and whether it holds a peak strictly above both
// span ends. Stops when f returns false; returns whether it walked them all.
template <class F>
bool walk_intervals(const Span& sp, const std::vector<Interval>& iv, F f) {
  const Scurve& c = sp.curve;
  const double t_up = c.durations[0] + c.durations[1] + c.durations[2];
  const double x_up = c.at(t_up).s;
  const double x_down = c.at(t_up + c.durations[3]).s;
  const bool bump = c.v_peak > std::max(c.v0, c.v1);
  double x0 = 0;
  double v0 = c.v0;
  for (std::size_t i = sp.first; i < sp.last; ++i) {
    const bool end = i + 1 == sp.last;
    const double x1 = end ? sp.length() : iv[i].s1 - sp.s0;
    const double v1 = end ? c.v1 : sp.velocity_at(x1);
    const bool peak = x0 <= x_down && x1 >= x_up;
    const double v_max = std::max({v0, v1, peak ? c.v_peak : 0.0});
    if (!f(i, v_max, peak && bump)) return false;
    x0 = x1;
    v0 = v1;
  }
  return true;
}

// Whether the profile of span sp stays under the cap of every interval of the span.
bool under_caps(const Span& sp, const std::vector<Interval>& iv) {
  return walk_intervals(sp, iv, [&](std::size_t i, double v, bool) { return v <= iv[i].limits.velocity; });
}

// Whether the curve of span sp from w0 to w1 with peak bound v_peak stays under the caps.
bool fits_under_caps(Span sp, double w0, double w1, double v_peak, const std::vector<Interval>& iv) {
  (void)set_profile(sp, w0, w1, v_peak);
  return under_caps(sp, iv);
}

// Bisection between a value where ok fails and one where it holds; returns the last one that
// held (`good`), within kBisections steps or a relative width of kBisectionTol.
template <class Ok>
double bisect(double bad, double good, Ok ok) {
  for (int it = 0; it < kBisections && std::abs(good - bad) > kBisectionTol * std::max(std::abs(good), std::abs(bad)); ++it) {
    const double mid = 0.5 * (bad + good);
    (ok(mid) ? good : bad) = mid;
  }
  return good;
}

// Step 3: whether span sp can go from w0 to w1 under its caps: the monotone change between
// them (cruising at the higher one) does. At rest at both ends (a span from stop to stop) it is
// standing still, under every cap; plan_scurve needs a positive peak, so it is not asked.
bool feasible(const Span& sp, double w0, double w1, const std::vector<Interval>& iv) {
  if (std::max(w0, w1) <= 0) return true;
  return fits_under_caps(sp, w0, w1, std::max(w0, w1), iv);
}

// Step 3: the highest velocity at the higher end of span sp (w0 at the start, w1 at the end)
// that is feasible with the other end kept; NaN when not even the lower end's velocity is.
double highest_end(const Span& sp, double w0, double w1, const std::vector<Interval>& iv) {
  const double low = std::min(w0, w1);
  if (!feasible(sp, low, low, iv)) return std::numeric_limits<double>::quiet_NaN();
  if (w0 > w1) return bisect(w0, w1, [&](double v) { return feasible(sp, v, w1, iv); });
  return bisect(w1, w0, [&](double v) { return feasible(sp, w0, v, iv); });
}

// Step 4: the curve of span sp between feasible knot velocities w0 and w1 with the highest
// peak under the caps. Returns plan_scurve's outcome.
Outcome shape(Span& sp, double w0, double w1, const std::vector<Interval>& iv) {
  double cap = 0;
  for (std::size_t i = sp.first; i < sp.last; ++i) cap = std::max(cap, iv[i].limits.velocity);
  const double top = std::max(w0, w1);
  double v_peak = std::max(cap, top);
  if (sp.last - sp.first > 1 && cap > top && !fits_under_caps(sp, w0, w1, cap, iv)) {
    v_peak = bisect(cap, top, [&](double v) { return fits_under_caps(sp, w0, w1, v, iv); });
  }
  return set_profile(sp, w0, w1, v_peak);
}

// Step 4: the fine alternative of span sp between the same knot velocities w0 and w1: one span
// per interval, the inner knot velocities (bounded by `cap`) from local passes, each curve as
// in step 4. Empty when such a chain cannot start at w0 and end at w1.
std::vector<Span> fine_alternative(const Span& sp, double w0, double w1, const std::vector<Interval>& iv,
                                   const std::vector<double>& cap) {
  std::vector<Span> fine;
  std::vector<double> bound;
  for (std::size_t i = sp.first; i < sp.last; ++i) {
    Span one = sp;
    one.first = i;
    one.last = i + 1;
    one.s0 = i == sp.first ? sp.s0 : iv[i].s0;
    one.s1 = i + 1 == sp.last ? sp.s1 : iv[i].s1;
    fine.push_back(one);
    bound.push_back(i == sp.first ? w0 : cap[i]);
  }
  bound.push_back(w1);
  const std::vector<double> w = knot_velocities(fine, bound);
  if (w.front() != w0 || w.back() != w1) return {};
  for (std::size_t k = 0; k < fine.size(); ++k) {
    if (!shape(fine[k], w[k], w[k + 1], iv).ok()) return {};
  }
  return fine;
}

// The velocity a chain of zero-acceleration knots at every interval of span sp (bounded by
// `cap` at each knot) reaches at the span's higher end from the velocity at its other end.
double fine_reach(const Span& sp, double w0, double w1, const std::vector<Interval>& iv, const std::vector<double>& cap) {
  const ScurveLimits& lim = sp.limits;
  if (w0 > w1) {
    double v = w1;
    for (std::size_t i = sp.last; i-- > sp.first;) v = reachable_velocity(v, iv[i].length(), lim.deceleration, lim.jerk, cap[i]);
    return v;
  }
  double v = w0;
  for (std::size_t i = sp.first; i < sp.last; ++i) v = reachable_velocity(v, iv[i].length(), lim.acceleration, lim.jerk, cap[i + 1]);
  return v;
}

// Steps 2-3: the spans and their knot velocities. Starts from the anchors; a span that cannot
// go between its knot velocities under its caps gets its higher end lowered (a knot bound) and
// the passes run again; after kLowerRounds its knots fall back to zero acceleration, and after
// kFallbackRounds more every knot does (every span is then one interval, which always fits).
void plan_spans(const std::vector<Interval>& iv, const std::vector<double>& knot_cap, bool carry_acceleration,
                std::vector<Span>& spans, std::vector<double>& w, std::vector<double>& cap) {
  const std::size_t n = iv.size();
  cap.assign(n + 1, 0.0);
  for (std::size_t k = 0; k <= n; ++k) {
    cap[k] = knot_cap[k];
    if (k > 0) cap[k] = std::min(cap[k], iv[k - 1].limits.velocity);
    if (k < n) cap[k] = std::min(cap[k], iv[k].limits.velocity);
  }
  std::vector<char> active = anchor_knots(iv, knot_cap);
  if (!carry_acceleration) std::fill(active.begin(), active.end(), 1);
  // the span each first interval last started, and the knot velocities it was feasible with
  struct Checked {
    std::size_t last = 0;
    double w0 = -1, w1 = -1;
  };
  std::vector<Checked> checked(n);
  for (int round = 0;; ++round) {
    spans = make_spans(iv, active);
    std::vector<double> span_cap(spans.size() + 1);
    for (std::size_t i = 0; i < spans.size(); ++i) span_cap[i] = cap[spans[i].first];
    span_cap.back() = cap[n];
    w = knot_velocities(spans, span_cap);
    bool clean = true;
    for (std::size_t i = 0; i < spans.size(); ++i) {
      const Span& sp = spans[i];
      Checked& seen = checked[sp.first];
      if (sp.last - sp.first == 1 || (seen.last == sp.last && seen.w0 == w[i] && seen.w1 == w[i + 1])) continue;
      if (feasible(sp, w[i], w[i + 1], iv)) {
        seen = {sp.last, w[i], w[i + 1]};
        continue;
      }
      clean = false;
      if (round < kLowerRounds) {
        const double v = highest_end(sp, w[i], w[i + 1], iv);
        const double fine = std::min(fine_reach(sp, w[i], w[i + 1], iv, cap), std::max(w[i], w[i + 1]));
        if (!std::isnan(v) && fine <= v) {
          double& bound = w[i] > w[i + 1] ? cap[sp.first] : cap[sp.last];
          bound = std::min(bound, v);
          continue;
        }
      }
      if (round < kLowerRounds + kFallbackRounds) {
        for (std::size_t k = sp.first + 1; k < sp.last; ++k) active[k] = 1;
      } else {
        std::fill(active.begin(), active.end(), 1);
      }
    }
    if (clean) return;
  }
}

// Time (s) span sp spends at or above (1 - kReachShare) of the programmed velocity of the
// piece under it.
double feed_time(const Span& sp, const std::vector<Interval>& iv, const Path& path) {
  const Scurve& c = sp.curve;
  // the window of the S-curve at or above v, in span time (bisection on its monotone ramps)
  const auto window = [&](double v) -> std::pair<double, double> {
    if (c.v_peak < v) return {1.0, 0.0};
    const double t_up = c.durations[0] + c.durations[1] + c.durations[2];
    const double t_down = t_up + c.durations[3];
    const auto crossing = [&](double lo, double hi, bool rising) {
      for (int it = 0; it < 100 && hi - lo > 0; ++it) {
        const double mid = 0.5 * (lo + hi);
        if (mid <= lo || mid >= hi) break;
        ((c.at(mid).v >= v) == rising ? hi : lo) = mid;
      }
      return 0.5 * (lo + hi);
    };
    return {c.v0 >= v ? 0.0 : crossing(0.0, t_up, true), c.v1 >= v ? c.duration() : crossing(t_down, c.duration(), false)};
  };
  double total = 0;
  // groups of intervals on pieces of the same programmed velocity
  for (std::size_t i = sp.first; i < sp.last;) {
    const double feed = path.pieces()[iv[i].piece].limits.velocity;
    std::size_t j = i + 1;
    while (j < sp.last && path.pieces()[iv[j].piece].limits.velocity == feed) ++j;
    const double ta = i == sp.first ? 0.0 : c.time_at_distance(iv[i].s0 - sp.s0);
    const double tb = j == sp.last ? c.duration() : c.time_at_distance(iv[j].s0 - sp.s0);
    const auto [rise, fall] = window((1 - kReachShare) * feed);
    total += std::max(0.0, std::min(fall, tb) - std::max(rise, ta));
    i = j;
  }
  return total;
}

// Largest velocity (m/s) of span sp on global [a, b], and whether that part holds a peak
// strictly above both span ends.
std::pair<double, bool> peak_on(const Span& sp, double a, double b) {
  const Scurve& c = sp.curve;
  const double t_up = c.durations[0] + c.durations[1] + c.durations[2];
  const double x_up = c.at(t_up).s;
  const double x_down = c.at(t_up + c.durations[3]).s;
  const double xa = std::max(0.0, a - sp.s0);
  const double xb = std::min(c.distance, b - sp.s0);
  const bool peak = xa <= x_down && xb >= x_up;
  return {std::max({sp.velocity_at(xa), sp.velocity_at(xb), peak ? c.v_peak : 0.0}),
          peak && c.v_peak > std::max(c.v0, c.v1)};
}

// Samples the chained spans at t = k dt; the last sample is the end at rest.
std::vector<TimedSample> sample(const std::vector<Span>& spans, double total, double length, double dt) {
  const auto n = static_cast<std::size_t>(std::ceil(total / dt));
  std::vector<TimedSample> samples;
  samples.reserve(n + 1);
  std::size_t i = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) * dt;
    while (i + 1 < spans.size() && t >= spans[i + 1].t0) ++i;
    const Span& sp = spans[i];
    const ScurveState x = sp.curve.at(t - sp.t0);
    // clamp into the span so rounding of s0 + s never breaks monotonicity
    samples.push_back({t, std::clamp(sp.s0 + x.s, sp.s0, sp.s1), x.v, x.a, x.j});
  }
  samples.push_back({static_cast<double>(n) * dt, length, 0.0, 0.0, 0.0});
  return samples;
}

// The binding constraint of every piece (timing.hpp), from the largest velocity on each
// interval (filled by the caller) and the spans' accelerations.
std::vector<PieceTiming> piece_reports(const Path& path, const std::vector<Interval>& intervals,
                                       const std::vector<Span>& spans) {
  const auto& pieces = path.pieces();
  std::vector<PieceTiming> reports(pieces.size());
  for (std::size_t k = 0; k < pieces.size(); ++k) reports[k] = {k, 0.0, "stop"};
  struct Seen {
    bool any = false, at_cap = false, holds_peak = false, acceleration = false;
    const char* cap_binding = "feed";
  };
  std::vector<Seen> seen(pieces.size());
  for (const Span& sp : spans) {
    const Scurve& c = sp.curve;
    const bool at_limit = std::max(c.peak_acceleration() / sp.limits.acceleration,
                                   c.peak_deceleration() / sp.limits.deceleration) >= 1 - kReachShare;
    for (std::size_t i = sp.first; i < sp.last; ++i) {
      const Interval& iv = intervals[i];
      for (std::size_t k = iv.piece; k <= iv.piece_last; ++k) {
        if (length(pieces[k].segment) <= 0) continue;
        // a merged interval: the piece's own part of it
        const auto [v, holds_peak] = iv.piece == iv.piece_last ? std::pair{iv.v_max, iv.holds_peak}
                                                                : peak_on(sp, path.offset(k), path.offset(k + 1));
        Seen& s = seen[k];
        PieceTiming& r = reports[k];
        const bool at_cap = v >= (1 - kReachShare) * iv.limits.velocity;
        if (!s.any || v > r.v_peak) r.v_peak = v;
        if (at_cap && !s.at_cap) s.cap_binding = iv.terms.binding();
        s.any = true;
        s.at_cap = s.at_cap || at_cap;
        s.holds_peak = s.holds_peak || holds_peak;
        s.acceleration = s.acceleration || at_limit;
      }
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

  // spans and knot velocities; each span's curve, or its fine alternative where that is faster
  std::vector<Span> spans;
  std::vector<double> w;
  std::vector<double> cap;
  plan_spans(intervals, knot_cap, options.carry_acceleration, spans, w, cap);
  std::vector<Span> chosen;
  chosen.reserve(spans.size());
  for (std::size_t i = 0; i < spans.size(); ++i) {
    Span sp = spans[i];
    const Outcome outcome = shape(sp, w[i], w[i + 1], intervals);
    if (!outcome.ok() && timing.outcome.ok()) {
      timing.outcome = {outcome.status, "span at s = " + format_mm(sp.s0) + ": " + outcome.message};
    }
    if (sp.last - sp.first > 1) {
      const std::vector<Span> fine = fine_alternative(spans[i], w[i], w[i + 1], intervals, cap);
      double fine_time = 0;
      for (const Span& one : fine) fine_time += one.curve.duration();
      if (!fine.empty() && fine_time < sp.curve.duration()) {
        chosen.insert(chosen.end(), fine.begin(), fine.end());
        continue;
      }
    }
    chosen.push_back(sp);
  }

  // chain them in time
  double t = 0;
  double feed = 0;
  for (Span& sp : chosen) {
    sp.t0 = t;
    t += sp.curve.duration();
    walk_intervals(sp, intervals, [&](std::size_t k, double v, bool holds_peak) {
      intervals[k].v_max = v;
      intervals[k].holds_peak = holds_peak;
      return true;
    });
    feed += feed_time(sp, intervals, path);
  }
  timing.cycle_time = t;
  timing.feed_share = t > 0 ? feed / t : 0.0;
  timing.samples = sample(chosen, t, path.length(), options.dt);
  timing.pieces = piece_reports(path, intervals, chosen);
  return timing;
}

}  // namespace blendbench
