#pragma once
// Internal to the velocity planners (timing.cpp, optimal.cpp): the parts of seed 004's planner
// (Shahzadeh et al.; the method is described in timing.cpp) that the optimal planner shares:
// the checks of the options, the pieces' models, junctions and hand-over zones, and the chained
// S-curves before they are sampled (its starting profile). Not installed.

#include <vector>

#include "intervals.hpp"
#include "spans.hpp"

namespace blendbench::timing_detail {

// Throws InputError for bad options or piece limits (plan_timing's contract, timing.hpp).
void validate(const Path& path, const TimingOptions& options);

// Steps 1 and 2 of seed 004's method on a validated path: each piece's model with its budgets,
// the junctions, the hand-over zones and the capped intervals (before merging), shared by the
// plan and the bound.
struct Prepared {
  std::vector<PieceModel> models;
  std::vector<Junction> joints;
  std::vector<HandoverZone> zones;
  std::vector<Interval> intervals;
  std::vector<double> knot_cap;
};
Prepared prepare(const Path& path, const TimingOptions& options);

// Steps 3 and 4: the spans chosen and chained in time (t0 set), unsampled; merges
// prepared.intervals (merge_intervals) on the way. Empty for a path without intervals. Throws
// InputError (refuse_work) where a cap rounds to zero.
struct Seed004Spans {
  std::vector<Span> spans;
  double cycle_time = 0;  // s
  Outcome outcome;
};
Seed004Spans seed004_spans(const Path& path, Prepared& prepared, const TimingOptions& options);

// Refuses a plan of `cycle_time` (s) as too long for options.max_samples (timing.hpp): an
// InputError at the move of `piece`, naming the limit its binding constraint makes the one to
// raise.
[[noreturn]] void refuse_work(const PathPiece& piece, Binding binding, double cycle_time, const TimingOptions& options);

// Refuses a plan of `cycle_time` (s) at the piece on which seed 004's `spans` (over the merged
// `intervals`) take the longest, naming the limit its binding makes the one to raise.
[[noreturn]] void refuse_slowest(const Path& path, std::vector<Interval>& intervals, const std::vector<Span>& spans,
                                 double cycle_time, const TimingOptions& options);

}  // namespace blendbench::timing_detail
