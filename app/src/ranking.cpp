#include "blendbench/app/ranking.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

namespace blendbench {
namespace {

// Two tolerances (m) are one group when they differ by less than this: the same value typed
// twice, or converted from mm along two routes.
constexpr double kSameTolerance = 1e-12;

// A number for a sentence, `decimals` after the point.
std::string fixed(double value, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  return buffer;
}

std::string seconds(double s) { return fixed(s, 3) + " s"; }
std::string millimetres(double m) { return fixed(m * 1e3, 3) + " mm"; }
// the reason goes into summary.json and the report (UTF-8): micrometres as "µm" (docs/units.md); the
// command line prints it through terminal_text
std::string micrometres(double m) { return fixed(m * 1e6, 1) + " \xC2\xB5m"; }

bool meets(const RankCandidate& c, const Constraints& k) {
  return (!k.max_contour_error || c.contour_error <= *k.max_contour_error) &&
         (!k.max_vibration || c.vibration <= *k.max_vibration);
}

// The constraints as a sentence's clause, "" when none is given.
std::string constraints_text(const Constraints& k) {
  std::string out;
  if (k.max_contour_error) out += "contour error against the program <= " + millimetres(*k.max_contour_error);
  if (k.max_vibration) out += std::string(out.empty() ? "" : ", ") + "residual vibration <= " + micrometres(*k.max_vibration);
  return out;
}

// How far a candidate is from the constraints: its worst ratio of figure to limit (<= 1 meets them).
double violation(const RankCandidate& c, const Constraints& k) {
  double worst = 0;
  if (k.max_contour_error) worst = std::max(worst, c.contour_error / std::max(*k.max_contour_error, 1e-300));
  if (k.max_vibration) worst = std::max(worst, c.vibration / std::max(*k.max_vibration, 1e-300));
  return worst;
}

// Ties between a and b (by name), asking the spread first; records whether it answered.
struct TieRule {
  const CycleResolution& resolution;
  const OrderSpread& spread;
  bool used = false;

  bool operator()(const RankCandidate& a, const RankCandidate& b) {
    std::optional<OrderHolds> holds;
    if (spread) holds = spread(a.name, b.name);
    used = used || holds.has_value();
    return cycle_times_tie(*a.cycle_time, *b.cycle_time, resolution, holds);
  }
};

RankGroup rank_group(const std::vector<const RankCandidate*>& members, double tolerance, bool like_for_like,
                     const Constraints& constraints, TieRule& tie) {
  RankGroup group;
  group.tolerance = tolerance;
  group.like_for_like = like_for_like;
  std::vector<const RankCandidate*> ranked;
  for (const RankCandidate* c : members) {
    if (c->clean && c->cycle_time) {
      ranked.push_back(c);
    } else {
      group.unranked.push_back({c->name, !c->clean ? "status " + c->status + ": not clean tracking data"
                                                    : std::string("no cycle time: it did not settle")});
    }
  }
  std::stable_sort(ranked.begin(), ranked.end(),
                   [](const RankCandidate* a, const RankCandidate* b) { return *a->cycle_time < *b->cycle_time; });
  // a rank is shared with the first variant of a run of ties (its leader) by those that tie with
  // the leader itself: ties need not chain (a ~ b and b ~ c with a and c apart), ranks do not
  std::size_t leader = 0;
  for (std::size_t k = 0; k < ranked.size(); ++k) {
    RankedVariant v;
    v.name = ranked[k]->name;
    v.cycle_time = *ranked[k]->cycle_time;
    v.meets_constraints = meets(*ranked[k], constraints);
    if (k > 0) {
      if (tie(*ranked[leader], *ranked[k])) {
        v.rank = group.ranked[leader].rank;
      } else {
        v.rank = static_cast<int>(k) + 1;
        leader = k;
      }
    }
    if (k + 1 < ranked.size()) {
      v.margin = *ranked[k + 1]->cycle_time - v.cycle_time;
      v.margin_percent = v.cycle_time > 0 ? std::optional<double>(100 * *v.margin / v.cycle_time) : std::nullopt;
      v.tie = tie(*ranked[k], *ranked[k + 1]);
    }
    group.ranked.push_back(std::move(v));
  }
  return group;
}

Recommendation recommend(const std::vector<RankCandidate>& candidates, const Constraints& constraints, TieRule& tie) {
  std::vector<const RankCandidate*> clean;
  std::string others;
  for (const RankCandidate& c : candidates) {
    if (c.clean && c.cycle_time) {
      clean.push_back(&c);
    } else {
      others += (others.empty() ? "" : ", ") + c.name + " " + (c.clean ? "not settled" : c.status);
    }
  }
  Recommendation out;
  if (clean.empty()) {
    out.reason = candidates.empty() ? "no variant ran" : "no variant ran clean (" + others + "): nothing to recommend";
    return out;
  }
  std::vector<const RankCandidate*> feasible;
  for (const RankCandidate* c : clean) {
    if (meets(*c, constraints)) feasible.push_back(c);
  }
  const std::string limits = constraints_text(constraints);
  if (feasible.empty()) {
    const RankCandidate* closest = *std::min_element(clean.begin(), clean.end(), [&](const auto* a, const auto* b) {
      return violation(*a, constraints) < violation(*b, constraints);
    });
    out.reason = "none of the " + std::to_string(clean.size()) + " clean variants meets the constraints (" + limits +
                 "); the closest is " + closest->name + " (contour error " + millimetres(closest->contour_error) +
                 ", residual vibration " + micrometres(closest->vibration) + ", cycle " + seconds(*closest->cycle_time) + ")";
    return out;
  }
  std::stable_sort(feasible.begin(), feasible.end(),
                   [](const RankCandidate* a, const RankCandidate* b) { return *a->cycle_time < *b->cycle_time; });
  const RankCandidate& fastest = *feasible.front();
  // the variants the fastest cannot be told apart from: the most accurate of them is the answer
  std::vector<const RankCandidate*> tied = {&fastest};
  for (std::size_t k = 1; k < feasible.size(); ++k) {
    if (tie(fastest, *feasible[k])) tied.push_back(feasible[k]);
  }
  const RankCandidate& best = **std::min_element(tied.begin(), tied.end(), [](const auto* a, const auto* b) {
    if (a->contour_error != b->contour_error) return a->contour_error < b->contour_error;
    if (a->vibration != b->vibration) return a->vibration < b->vibration;
    return *a->cycle_time < *b->cycle_time;
  });
  out.variant = best.name;
  const std::string within = limits.empty() ? "no constraints given" : "within " + limits;
  out.reason = "the fastest clean variant (" + within + "), cycle " + seconds(*best.cycle_time);
  if (tied.size() > 1) {
    std::string names;
    for (const RankCandidate* c : tied) {
      if (c != &best) names += (names.empty() ? "" : ", ") + c->name + " (" + seconds(*c->cycle_time) + ")";
    }
    out.reason += "; it ties on cycle time with " + names +
                  " (the differences are below the resolution) and of those it has the smallest contour error "
                  "against the program (" +
                  millimetres(best.contour_error) + ")";
  }
  // the first variant that is not tied with it: by how much the answer wins
  const auto next = std::find_if(feasible.begin(), feasible.end(), [&](const RankCandidate* c) {
    return std::find(tied.begin(), tied.end(), c) == tied.end();
  });
  if (next != feasible.end()) {
    const double margin = *(*next)->cycle_time - *best.cycle_time;
    out.reason += "; the next, " + (*next)->name + ", takes " + fixed(margin * 1e3, 0) + " ms (" +
                  fixed(100 * margin / *best.cycle_time, 1) + " %) longer";
  } else if (feasible.size() == 1 && clean.size() > 1) {
    out.reason += "; the only clean variant that meets the constraints";
  }
  return out;
}

}  // namespace

CycleResolution cycle_resolution(double setpoint_period) {
  CycleResolution r;
  r.grid = 2 * setpoint_period;
  return r;
}

double tie_threshold(double a, double b, const CycleResolution& r) {
  return std::max({r.grid, r.absolute, r.relative * std::min(a, b)});
}

bool cycle_times_tie(double a, double b, const CycleResolution& r, std::optional<OrderHolds> spread) {
  const double difference = std::abs(a - b);
  if (!spread) return difference < tie_threshold(a, b, r);
  return *spread != OrderHolds::kAll || difference < r.grid;
}

Ranking rank(const std::vector<RankCandidate>& candidates, const Constraints& constraints, const CycleResolution& resolution,
             const OrderSpread& spread) {
  Ranking out;
  out.resolution = resolution;
  out.constraints = constraints;
  TieRule tie{resolution, spread};

  // the tolerances of the blended variants, ascending; baselines (no transition) join every group
  std::vector<double> tolerances;
  bool parameter_sized = false;
  std::vector<const RankCandidate*> baselines;
  for (const RankCandidate& c : candidates) {
    if (c.method == Method::kNone) {
      baselines.push_back(&c);
    } else if (c.tolerance > 0) {
      if (std::none_of(tolerances.begin(), tolerances.end(),
                       [&](double t) { return std::abs(t - c.tolerance) <= kSameTolerance; })) {
        tolerances.push_back(c.tolerance);
      }
    } else {
      parameter_sized = true;
    }
  }
  std::sort(tolerances.begin(), tolerances.end());
  for (const double t : tolerances) {
    std::vector<const RankCandidate*> members;
    for (const RankCandidate& c : candidates) {
      if (c.method == Method::kNone || (c.tolerance > 0 && std::abs(c.tolerance - t) <= kSameTolerance)) members.push_back(&c);
    }
    out.groups.push_back(rank_group(members, t, true, constraints, tie));
  }
  if (parameter_sized || tolerances.empty()) {
    std::vector<const RankCandidate*> members;
    for (const RankCandidate& c : candidates) {
      if (c.method == Method::kNone || c.tolerance <= 0) members.push_back(&c);
    }
    // a run of baselines alone compares like with like: nothing is cut
    out.groups.push_back(rank_group(members, 0, !parameter_sized, constraints, tie));
  }
  out.recommendation = recommend(candidates, constraints, tie);
  out.spread_used = tie.used;
  return out;
}

}  // namespace blendbench
