#include "spans.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace blendbench::timing_detail {
namespace {

// Relative difference under which two caps count as equal (plateaus, step 2).
constexpr double kSameCap = 1e-12;
// Rounds of lowering span ends (step 3) before the knots of a span that still leaves its caps
// fall back to zero acceleration, and rounds of that before every knot does.
constexpr int kLowerRounds = 8;
constexpr int kFallbackRounds = 2;
// Bisection of the highest end velocity or peak under the caps: steps and relative width.
constexpr int kBisections = 40;
constexpr double kBisectionTol = 1e-6;

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

// The spans between consecutive active knots, into `spans` (cleared; its memory is kept, so
// that the rounds of plan_spans write the same pages again).
void make_spans(const std::vector<Interval>& iv, const std::vector<char>& active, std::vector<Span>& spans) {
  spans.clear();
  std::size_t count = 1;  // a span from each active inner knot, and the first
  for (std::size_t k = 1; k < iv.size(); ++k) count += active[k] != 0 ? 1 : 0;
  spans.reserve(count);
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
}

// Distance (m) of the change between w0 and w1 on span sp.
double change_distance(const Span& sp, double w0, double w1) {
  const ScurveLimits& lim = sp.limits;
  return w0 >= w1 ? velocity_change(w0, w1, lim.deceleration, lim.jerk).distance
                  : velocity_change(w0, w1, lim.acceleration, lim.jerk).distance;
}

// Whether a span can go from w0 to w1 (the change alone fits in its length).
bool fits(const Span& sp, double w0, double w1) { return change_distance(sp, w0, w1) <= sp.length(); }

// Knot velocities of the spans, in place of the caps in `w` (one per span end): bounded by
// them, reachable backward (braking in time) and forward (speeding up) with the jerk-limited
// formulas.
void knot_velocities(const std::vector<Span>& spans, std::vector<double>& w) {
  const std::size_t n = spans.size();
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
}

// Plans the curve of span sp from w0 to w1 with peak bound v_peak (>= both); returns
// plan_scurve's outcome.
Outcome set_profile(Span& sp, double w0, double w1, double v_peak) {
  sp.limits.velocity = v_peak;
  ScurveResult plan = plan_scurve(sp.length(), w0, w1, sp.limits);
  sp.curve = plan.curve;
  return plan.outcome;
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

}  // namespace

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

std::vector<Span> fine_alternative(const Span& sp, double w0, double w1, const std::vector<Interval>& iv,
                                   const std::vector<double>& cap) {
  std::vector<Span> fine;
  std::vector<double> w;  // the knots' bounds, then their velocities
  for (std::size_t i = sp.first; i < sp.last; ++i) {
    Span one = sp;
    one.first = i;
    one.last = i + 1;
    one.s0 = i == sp.first ? sp.s0 : iv[i].s0;
    one.s1 = i + 1 == sp.last ? sp.s1 : iv[i].s1;
    fine.push_back(one);
    w.push_back(i == sp.first ? w0 : cap[i]);
  }
  w.push_back(w1);
  knot_velocities(fine, w);
  if (w.front() != w0 || w.back() != w1) return {};
  for (std::size_t k = 0; k < fine.size(); ++k) {
    if (!shape(fine[k], w[k], w[k + 1], iv).ok()) return {};
  }
  return fine;
}

namespace {

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

}  // namespace

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
    make_spans(iv, active, spans);
    w.resize(spans.size() + 1);
    for (std::size_t i = 0; i < spans.size(); ++i) w[i] = cap[spans[i].first];
    w.back() = cap[n];
    knot_velocities(spans, w);
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

}  // namespace blendbench::timing_detail
