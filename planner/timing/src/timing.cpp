#include "blendbench/timing/timing.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <tuple>

#include "blendbench/corner/blend.hpp"
#include "blendbench/core/format.hpp"
#include "blendbench/core/units.hpp"
#include "blendbench/core/input_error.hpp"
#include "blendbench/timing/scurve.hpp"
#include "blendbench/timing/time_optimal.hpp"
#include "intervals.hpp"
#include "optimal.hpp"
#include "seed004.hpp"
#include "spans.hpp"

// The method (every limit held on the sampled profile), and where it is conservative:
//
// 1. The path is cut into intervals at every piece junction, at the ends of hand-over zones
//    (below) and, on pieces whose curvature varies along s (clothoids with non-zero sharpness,
//    Bezier curves), into kSubdivisions equal sub-intervals. Each interval gets a cap: the
//    smallest v_lim on it, from the maximum curvature and sharpness over the interval (seed 004
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
// The junction rules and hand-over zones are described in intervals.cpp.

namespace blendbench {
namespace timing_detail {

void validate(const Path& path, const TimingOptions& options) {
  if (!(options.dt > 0) || !std::isfinite(options.dt)) {
    throw InputError("", 0, 0, "dt", "servo period must be positive, got " + format_value(options.dt) + " s");
  }
  if (!(options.max_samples >= 1) || !std::isfinite(options.max_samples)) {
    throw InputError("", 0, 0, "max_samples", "must be at least 1, got " + format_value(options.max_samples));
  }
  if (!(options.grid_refinement >= 1) || !std::isfinite(options.grid_refinement)) {
    throw InputError("", 0, 0, "grid_refinement", "must be at least 1, got " + format_value(options.grid_refinement));
  }
  if (options.axis_limits) {
    if (options.limits != LimitsMode::kCartesian) {
      throw InputError("", 0, 0, "axis_limits", "per-axis limits need the cartesian limits mode (path mode bounds no vector)");
    }
    for (int i = 0; i < 3; ++i) {
      for (const auto& [name, value, unit] : {std::tuple{"axis_limits.a", options.axis_limits->acceleration[i], " mm/s^2"},
                                              std::tuple{"axis_limits.j", options.axis_limits->jerk[i], " mm/s^3"}}) {
        if (!(value > 0) || !std::isfinite(value)) {
          throw InputError("", 0, 0, name, std::string("axis ") + "xyz"[i] + ": must be positive, got " +
                                               format_value(value * 1e3) + unit);
        }
      }
    }
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

}  // namespace timing_detail

using namespace timing_detail;

namespace {

// A piece reaches its cap, or the feed, when within this share of it (timing.hpp).
constexpr double kReachShare = 1e-3;

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
  for (std::size_t k = 0; k < pieces.size(); ++k) reports[k] = {k, 0.0, Binding::kStop};
  struct Seen {
    bool any = false, at_cap = false, holds_peak = false, acceleration = false;
    Binding cap_binding = Binding::kFeed;
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
    reports[k].binding = s.at_cap        ? s.cap_binding
                         : s.holds_peak  ? Binding::kLength
                         : s.acceleration ? Binding::kAcceleration
                                          : Binding::kJerk;
  }
  return reports;
}

// The time (s) the chained spans spend on each piece.
std::vector<double> piece_times(const Path& path, const std::vector<Span>& spans) {
  std::vector<double> times(path.pieces().size(), 0.0);
  for (const Span& sp : spans) {
    for (std::size_t k = path.locate(sp.s0).piece; k < path.pieces().size() && path.offset(k) < sp.s1; ++k) {
      const double a = std::max(path.offset(k), sp.s0) - sp.s0;
      const double b = std::min(path.offset(k + 1), sp.s1) - sp.s0;
      if (b > a) times[k] += sp.curve.time_at_distance(b) - sp.curve.time_at_distance(a);
    }
  }
  return times;
}

}  // namespace

namespace timing_detail {

[[noreturn]] void refuse_work(const PathPiece& piece, Binding binding, double cycle_time, const TimingOptions& options) {
  if (binding == Binding::kRotation && piece.orientation) {
    const std::string at = piece.move >= 0 ? " on move " + std::to_string(piece.move + 1) : " on corner " + std::to_string(piece.corner + 1);
    throw InputError(piece.where.file, piece.where.line, piece.where.column, "angular_velocity",
                     "the plan would take " + format_value(cycle_time, 3) + " s = " +
                         format_value(cycle_time / options.dt, 3) + " samples; limit " +
                         format_value(options.max_samples, 3) + " samples; the tool's rotation binds" + at +
                         ": raise `angular_velocity`, `angular_acceleration` or `angular_jerk` (" +
                         format_value(piece.orientation->limits.velocity / kDeg, 3) + " deg/s)");
  }
  const bool feed = binding == Binding::kFeed || binding == Binding::kStop;
  const bool jerk = binding == Binding::kSharpness || binding == Binding::kJerk;
  const char* field = feed ? "velocity" : jerk ? "jerk" : "acceleration";
  const double value = feed ? piece.limits.velocity : jerk ? piece.limits.jerk : piece.limits.acceleration;
  const char* unit = feed ? " mm/s" : jerk ? " mm/s^3" : " mm/s^2";
  std::string at = piece.where.line > 0 ? " at line " + std::to_string(piece.where.line) : "";
  if (at.empty()) {
    at = piece.move >= 0 ? " on move " + std::to_string(piece.move + 1) : " on corner " + std::to_string(piece.corner + 1);
  }
  throw InputError(piece.where.file, piece.where.line, piece.where.column, field,
                   "the plan would take " + format_value(cycle_time, 3) + " s = " +
                       format_value(cycle_time / options.dt, 3) + " samples at " + format_value(options.dt * 1e3, 3) +
                       " ms; limit " + format_value(options.max_samples, 3) + " samples; raise `" + field + "` (" +
                       format_value(value * 1e3, 3) + unit + at + ")");
}


void refuse_slowest(const Path& path, std::vector<Interval>& intervals, const std::vector<Span>& spans,
                    double cycle_time, const TimingOptions& options) {
  for (const Span& sp : spans) {
    walk_intervals(sp, intervals, [&](std::size_t k, double v, bool holds_peak) {
      intervals[k].v_max = v;
      intervals[k].holds_peak = holds_peak;
      return true;
    });
  }
  const std::vector<PieceTiming> reports = piece_reports(path, intervals, spans);
  const std::vector<double> times = piece_times(path, spans);
  std::size_t worst = 0;
  for (std::size_t k = 0; k < times.size(); ++k) {
    if (!(times[k] <= times[worst])) worst = k;
  }
  refuse_work(path.pieces()[worst], reports[worst].binding, cycle_time, options);
}

}  // namespace timing_detail

namespace {

// Refuses (refuse_work) a plan of more samples than options.max_samples, or of no finite
// duration, before it is sampled: at the piece that takes the longest.
void check_work(const Path& path, const std::vector<Span>& spans, const std::vector<PieceTiming>& reports,
                double cycle_time, const TimingOptions& options) {
  if (cycle_time / options.dt <= options.max_samples - 1) return;
  const std::vector<double> times = piece_times(path, spans);
  std::size_t worst = 0;
  for (std::size_t k = 0; k < times.size(); ++k) {
    if (!(times[k] <= times[worst])) worst = k;
  }
  refuse_work(path.pieces()[worst], reports[worst].binding, cycle_time, options);
}

// The largest curvature step of every corner (Timing::corner_steps): at each junction with a
// curvature jump that is not a stop, the planned velocity and |dK| v^2 / dt.
std::vector<Timing::CornerStep> corner_steps(const Path& path, const std::vector<Junction>& joints,
                                             const std::vector<Span>& spans, double dt) {
  std::vector<Timing::CornerStep> out(path.corners.size());
  for (const Junction& jn : joints) {
    if (!(jn.dk > 0)) continue;
    const PathPiece& prev = path.pieces()[jn.prev];
    const PathPiece& next = path.pieces()[jn.next];
    // the corner the junction belongs to: a transition's, else the one between the two moves
    // (at the end of the move before the next one), as its report's index
    const int index = next.corner >= 0 ? next.corner : prev.corner >= 0 ? prev.corner : next.move - 1;
    const auto at = std::lower_bound(path.corners.begin(), path.corners.end(), index,
                                     [](const CornerReport& r, int i) { return r.index < i; });
    if (at == path.corners.end() || at->index != index) continue;
    const auto corner = at - path.corners.begin();
    const double s = path.offset(jn.next);
    const auto it = std::upper_bound(spans.begin(), spans.end(), s, [](double x, const Span& sp) { return x < sp.s0; });
    const Span& sp = it == spans.begin() ? spans.front() : *std::prev(it);
    const double v = sp.velocity_at(std::clamp(s - sp.s0, 0.0, sp.length()));
    Timing::CornerStep& step = out[static_cast<std::size_t>(corner)];
    const double jerk = jn.dk * v * v / dt;
    if (jerk >= step.jerk) step = {jn.dk, v, jerk};
  }
  return out;
}

}  // namespace

namespace timing_detail {

Prepared prepare(const Path& path, const TimingOptions& options) {
  Prepared p;
  p.models = piece_models(path, options);
  p.joints = junctions(path, options, p.models);
  share_budgets(path, options, p.joints, p.models);
  p.zones = all_zones(path, p.joints, p.models);
  build_intervals(path, options, p.models, p.joints, p.zones, p.intervals, p.knot_cap);
  return p;
}

Seed004Spans seed004_spans(const Path& path, Prepared& prepared, const TimingOptions& options) {
  Seed004Spans out;
  std::vector<Interval>& intervals = prepared.intervals;
  std::vector<double>& knot_cap = prepared.knot_cap;
  merge_intervals(path, intervals, knot_cap);
  if (intervals.empty()) return out;

  // an interval whose cap rounds to zero (limits near the smallest doubles) is never crossed
  for (const Interval& iv : intervals) {
    if (!(iv.limits.velocity > 0)) refuse_work(path.pieces()[iv.piece], iv.terms.binding(), kInf, options);
  }

  // spans and knot velocities; each span's curve, or its fine alternative where that is faster
  std::vector<Span> spans;
  std::vector<double> w;
  std::vector<double> cap;
  plan_spans(intervals, knot_cap, options.carry_acceleration, spans, w, cap);
  std::vector<Span>& chosen = out.spans;
  chosen.reserve(spans.size());
  for (std::size_t i = 0; i < spans.size(); ++i) {
    Span sp = spans[i];
    const Outcome outcome = shape(sp, w[i], w[i + 1], intervals);
    if (!outcome.ok() && out.outcome.ok()) {
      out.outcome = {outcome.status, "span at s = " + format_mm(sp.s0) + ": " + outcome.message};
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
  for (Span& sp : chosen) {
    sp.t0 = t;
    t += sp.curve.duration();
  }
  out.cycle_time = t;
  return out;
}

}  // namespace timing_detail

std::vector<HandoverZone> handover_zones(const Path& path, const TimingOptions& options) {
  timing_detail::validate(path, options);
  std::vector<PieceModel> models = piece_models(path, options);
  const std::vector<Junction> joints = junctions(path, options, models);
  share_budgets(path, options, joints, models);
  return all_zones(path, joints, models);
}

double time_optimal_bound(const Path& path, const TimingOptions& options) {
  timing_detail::validate(path, options);
  const Prepared p = prepare(path, options);
  return timing_detail::time_optimal_bound(path, options, p.models, p.joints, p.intervals);
}

std::string_view algorithm_name(TimingOptions::Algorithm algorithm) {
  return algorithm == TimingOptions::Algorithm::kSeed004 ? "seed004" : "optimal";
}

std::optional<TimingOptions::Algorithm> algorithm_from_string(std::string_view name) {
  for (auto a : {TimingOptions::Algorithm::kOptimal, TimingOptions::Algorithm::kSeed004}) {
    if (algorithm_name(a) == name) return a;
  }
  return std::nullopt;
}

std::string_view baseline_name(TimingOptions::Baseline baseline) {
  switch (baseline) {
    case TimingOptions::Baseline::kNone: return "none";
    case TimingOptions::Baseline::kExactStop: return "exact_stop";
    case TimingOptions::Baseline::kJunctionSlowdown: return "junction_slowdown";
  }
  return "none";
}

std::optional<TimingOptions::Baseline> baseline_from_string(std::string_view name) {
  for (auto b : {TimingOptions::Baseline::kNone, TimingOptions::Baseline::kExactStop,
                 TimingOptions::Baseline::kJunctionSlowdown}) {
    if (baseline_name(b) == name) return b;
  }
  return std::nullopt;
}

std::string_view binding_name(Binding binding) {
  switch (binding) {
    case Binding::kFeed: return "feed";
    case Binding::kCurvature: return "curvature";
    case Binding::kSharpness: return "sharpness";
    case Binding::kLength: return "length";
    case Binding::kAcceleration: return "acceleration";
    case Binding::kJerk: return "jerk";
    case Binding::kStop: return "stop";
    case Binding::kRotation: return "rotation";
  }
  return "stop";
}

namespace timing_detail {

Timing plan_seed004(const Path& path, const TimingOptions& options) {
  Timing timing;
  timing.dt = options.dt;
  timing.limits = options.limits;
  timing.algorithm = TimingOptions::Algorithm::kSeed004;
  timing.corner_steps.resize(path.corners.size());
  Prepared prepared = prepare(path, options);
  const std::vector<Junction>& joints = prepared.joints;
  timing.bound_cycle_time = timing_detail::time_optimal_bound(path, options, prepared.models, joints, prepared.intervals);
  Seed004Spans planned = seed004_spans(path, prepared, options);
  const std::vector<Interval>& merged = prepared.intervals;
  if (merged.empty()) {
    timing.samples.push_back({0, path.length(), 0, 0, 0});
    for (std::size_t k = 0; k < path.pieces().size(); ++k) timing.pieces.push_back({k, 0.0, Binding::kStop});
    return timing;
  }
  timing.outcome = planned.outcome;
  std::vector<Interval>& intervals = prepared.intervals;
  std::vector<Span>& chosen = planned.spans;
  double feed = 0;
  for (Span& sp : chosen) {
    walk_intervals(sp, intervals, [&](std::size_t k, double v, bool holds_peak) {
      intervals[k].v_max = v;
      intervals[k].holds_peak = holds_peak;
      return true;
    });
    feed += feed_time(sp, intervals, path);
  }
  const double t = planned.cycle_time;
  timing.cycle_time = t;
  timing.feed_share = t > 0 ? feed / t : 0.0;
  timing.pieces = piece_reports(path, intervals, chosen);
  check_work(path, chosen, timing.pieces, t, options);
  timing.samples = sample(chosen, t, path.length(), options.dt);
  timing.corner_steps = corner_steps(path, joints, chosen, options.dt);
  return timing;
}

}  // namespace timing_detail

Timing plan_timing(const Path& path, const TimingOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  timing_detail::validate(path, options);
  Timing timing = options.algorithm == TimingOptions::Algorithm::kSeed004 ? timing_detail::plan_seed004(path, options)
                                                                          : timing_detail::plan_optimal(path, options);
  timing.planning_wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return timing;
}

}  // namespace blendbench
