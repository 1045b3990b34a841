#pragma once
// The answer of a run (issue 44, docs/compare.md): per tolerance the variants ordered by cycle
// time, each with its margin to the next and whether that margin is a tie (below what the run can
// resolve), and a recommendation: the fastest clean variant within the user's constraints, or
// why none is. Pure functions of the variants' figures: the runner fills the candidates from the
// summary (rank_run in run_summary.hpp), the tests feed them directly.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "blendbench/program/program.hpp"

namespace blendbench {

// The regression gate's tolerance on metrics.cycle_time_s (results/baselines/tolerances.json,
// "what a change that matters is"; a test keeps the two equal): 5 ms absolute, 1 % relative.
inline constexpr double kCycleTimeGateAbsolute = 0.005;  // s
inline constexpr double kCycleTimeGateRelative = 0.01;

// How finely a run tells two cycle times apart (docs/compare.md, "Ties"):
// - grid: what the metric itself resolves. A cycle time is the instant the TCP has settled, found
//   on the setpoint grid, so each is known to one setpoint period and a difference to two.
// - absolute, relative: the regression gate's tolerance, the change it treats as one that matters
//   (its relative part also stands in for the arm model's uncertainty until a sensitivity run
//   measures it).
struct CycleResolution {
  double grid = 0;  // s
  double absolute = kCycleTimeGateAbsolute;  // s
  double relative = kCycleTimeGateRelative;
};

// The resolution of a run whose setpoints come every `setpoint_period` s (> 0).
CycleResolution cycle_resolution(double setpoint_period);

// What runs on perturbed arm models say about the nominal order of two variants' cycle times
// (the sensitivity runs, `--sensitivity`): it holds in all of them, in some, or in none.
enum class OrderHolds { kAll, kSome, kNone };

// The spread of the pair (a, b) in either order, nullopt when no sensitivity run covered it.
using OrderSpread = std::function<std::optional<OrderHolds>(const std::string& a, const std::string& b)>;

// The no-spread tie threshold of two cycle times (s): max(grid, absolute, relative x the smaller).
double tie_threshold(double a, double b, const CycleResolution& resolution);

// Whether cycle times a and b (s) tie. Without a spread: |a - b| below tie_threshold. With the
// pair's spread the models decide instead of the gate's slack: a tie unless the order holds in
// every model and |a - b| is at least the grid (a difference the metric resolves); an order that
// holds in some or in none of the models is a tie at any difference.
bool cycle_times_tie(double a, double b, const CycleResolution& resolution, std::optional<OrderHolds> spread = std::nullopt);

// The user's constraints on a recommendation (m): the largest contour error against the
// programmed path, and the largest residual vibration (after the stop or after any corner).
struct Constraints {
  std::optional<double> max_contour_error;
  std::optional<double> max_vibration;
};

// One variant's figures, as the ranking needs them.
struct RankCandidate {
  std::string name;
  Method method = Method::kNone;
  double tolerance = 0;  // m, the equal tolerance it ran at; 0: sized by its parameter (or no transition)
  bool clean = false;    // status ok: clean tracking data
  std::string status;    // its status ("ok", "saturated", ...), for an unranked one
  std::optional<double> cycle_time;  // s; none when it did not settle or has no metrics
  double contour_error = 0;  // m, against the programmed path
  double vibration = 0;      // m, the larger of the residual vibration after the stop and after any corner
};

struct RankedVariant {
  std::string name;
  // 1 the fastest; a variant that ties with the first of the variants sharing the previous rank
  // shares it too, else its rank is its place (1, 1, 3, ...)
  int rank = 1;
  double cycle_time = 0;  // s
  // to the next slower ranked variant (s, and % of this one's cycle time); none for the last
  std::optional<double> margin, margin_percent;
  bool tie = false;  // the margin to the next is below the resolution (cycle_times_tie)
  bool meets_constraints = true;
};

struct UnrankedVariant {
  std::string name;
  std::string reason;  // why it has no place: its status, or no cycle time
};

// The variants run at one tolerance, with the ones without a transition (exact stop, junction
// slow-down: every group's references); tolerance 0 groups the variants sized by a parameter,
// which cut their corners by different amounts (not like for like), or a run with no blends.
struct RankGroup {
  double tolerance = 0;  // m
  bool like_for_like = true;
  std::vector<RankedVariant> ranked;    // by cycle time, fastest first
  std::vector<UnrankedVariant> unranked;  // not clean or not settled, in run order
};

struct Recommendation {
  std::optional<std::string> variant;  // none: no clean variant meets the constraints
  std::string reason;
};

struct Ranking {
  CycleResolution resolution;
  bool spread_used = false;  // some pair's tie was decided by the sensitivity runs
  Constraints constraints;
  std::vector<RankGroup> groups;  // by tolerance, ascending; the parameter group (0) last
  Recommendation recommendation;
};

// Ranks `candidates` (in run order) per tolerance and recommends one. The recommendation is the
// fastest clean variant of any group that meets `constraints`; where others tie with it, the one
// of those with the smallest contour error against the program (then the least vibration), and
// the reason names them. `spread` may be empty (no sensitivity run).
Ranking rank(const std::vector<RankCandidate>& candidates, const Constraints& constraints,
             const CycleResolution& resolution, const OrderSpread& spread = {});

}  // namespace blendbench
