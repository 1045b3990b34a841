#pragma once
// Internal to the velocity planner (timing.cpp): the intervals of step 1, each with one cap,
// and the junction rules and hand-over zones that bound their knots. Not installed.

#include <limits>
#include <vector>

#include "blendbench/program/path.hpp"
#include "blendbench/timing/scurve.hpp"
#include "blendbench/timing/timing.hpp"

namespace blendbench::timing_detail {

inline const double kInf = std::numeric_limits<double>::infinity();

// How one piece is planned under the options' limits mode: the limits its caps hold (the
// piece's own in kPath; lowered by the axis limits in kCartesian: effective_vector_limits) and
// the S-curve's tangential limits on it (the piece's own in kPath; cartesian_tangential_limits
// on a curved piece in kCartesian).
// On a piece where the tool rotates (rotation_budgets, intervals.cpp) the tangential limits are
// lowered and the speed capped so that the angular limits hold as well: rotation_cap is that
// cap (m/s), rotation_speed its part from the angular velocity limit alone (omega / |rho|).
struct PieceModel {
  Limits vector;
  TangentialLimits tangential;
  double rotation_cap = kInf;
  double rotation_speed = kInf;
};

// The model of every piece with its vector limits and, as tangential limits, the same (the
// junction rules use only the vector limits); share_budgets then fills in the tangential limits
// of the curved pieces in kCartesian (the shares used are stated in intervals.cpp).
std::vector<PieceModel> piece_models(const Path& path, const TimingOptions& options);

// The terms of v_lim over [s0, s1] (local arc lengths) of a piece: programmed velocity, and the
// curvature and sharpness terms: eq. 25 and eq. 26 of seed 004 with the maximum curvature and
// sharpness there (kPath), or the acceleration and jerk conditions (C1) and (C2) of
// cartesian.hpp with the maximum curvature and spatial sharpness there (kCartesian).
// `rotation`: the piece's rotation cap (PieceModel::rotation_cap), infinity where the tool does
// not rotate.
struct CapTerms {
  double feed = kInf;
  double curvature = kInf;
  double sharpness = kInf;
  double rotation = kInf;
  [[nodiscard]] double min() const { return std::min({feed, curvature, sharpness, rotation}); }
  [[nodiscard]] Binding binding() const {
    return feed <= min() ? Binding::kFeed : curvature <= min() ? Binding::kCurvature : sharpness <= min() ? Binding::kSharpness : Binding::kRotation;
  }
};

// A stretch of path with one cap (step 1): a piece, a sub-interval of one, or merged pieces.
struct Interval {
  double s0 = 0;  // m, global arc length at the start
  double s1 = 0;  // m, at the end
  std::size_t piece = 0;       // the piece it starts on
  std::size_t piece_last = 0;  // the piece it ends on (after merging)
  CapTerms terms;              // its cap is terms.min()
  ScurveLimits limits;         // the tangential limits; limits.velocity is the cap
  bool flat = true;            // on a piece of constant curvature (the cap is exact there)
  // filled from the span that covers it: the largest velocity on it, and whether it holds a
  // peak of the span strictly above both span ends
  double v_max = 0;
  bool holds_peak = false;
  [[nodiscard]] double length() const { return s1 - s0; }
};

// A junction between two pieces of non-zero length: its velocity bound (the junction rules,
// intervals.cpp), its kink angle (rad) and the jump of the curvature vector (1/m) across it.
struct Junction {
  std::size_t prev = 0;
  std::size_t next = 0;
  double cap = 0;
  double theta = 0;
  double dk = 0;
  // The bound without the curvature-jump rule (the kink and rotation-rate rules alone; 0 at a
  // stop): the optimal planner holds the vector jerk at a curvature step instead (optimal.cpp).
  double cap_kink = 0;
};

// Every junction of the path in order (the first piece of non-zero length has none).
std::vector<Junction> junctions(const Path& path, const TimingOptions& options, const std::vector<PieceModel>& models);

// kCartesian: the tangential limits of every curved piece, chosen knowing the junction bounds at
// its ends (`joints`, from junctions()); then, in either mode, the rotation budgets of every
// piece where the tool rotates (intervals.cpp).
void share_budgets(const Path& path, const TimingOptions& options, const std::vector<Junction>& joints,
                   std::vector<PieceModel>& models);

// The hand-over zones of every junction, ordered by piece and start.
std::vector<HandoverZone> all_zones(const Path& path, const std::vector<Junction>& joints,
                                    const std::vector<PieceModel>& models);

// Cuts the path into intervals; knot_cap[i] bounds the velocity at the start of interval i
// (knot_cap.back() at the end of the path). Pieces are cut at their sub-interval points and at
// the ends of their hand-over zones.
void build_intervals(const Path& path, const TimingOptions& options, const std::vector<PieceModel>& models,
                     const std::vector<Junction>& joints, const std::vector<HandoverZone>& zones,
                     std::vector<Interval>& intervals, std::vector<double>& knot_cap);

// Merges neighbours across a knot that constrains nothing (no stop, kink or curvature jump)
// when their limits and cap terms are identical (e.g. collinear lines, equal tangent arcs in
// one plane). The rule does not depend on the values of the limits, so raising a limit of
// every piece alike never changes the intervals (and the cycle time can only fall).
void merge_intervals(const Path& path, std::vector<Interval>& intervals, std::vector<double>& knot_cap);

// The time-optimal bound (time_optimal.hpp) from the plan's models, junctions and its
// intervals before merging; 0 without intervals.
double time_optimal_bound(const Path& path, const TimingOptions& options, const std::vector<PieceModel>& models,
                          const std::vector<Junction>& joints, const std::vector<Interval>& intervals);

}  // namespace blendbench::timing_detail
