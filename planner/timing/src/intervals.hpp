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

// A junction between two pieces of non-zero length, with its velocity bound (junction_cap).
struct Junction {
  std::size_t prev = 0;
  std::size_t next = 0;
  double cap = 0;
};

// Every junction of the path in order (the first piece of non-zero length has none).
std::vector<Junction> junctions(const Path& path, const TimingOptions& options);

// The hand-over zones of every junction, ordered by piece and start.
std::vector<HandoverZone> all_zones(const Path& path, const std::vector<Junction>& joints);

// Cuts the path into intervals; knot_cap[i] bounds the velocity at the start of interval i
// (knot_cap.back() at the end of the path). Pieces are cut at their sub-interval points and at
// the ends of their hand-over zones.
void build_intervals(const Path& path, const TimingOptions& options, std::vector<Interval>& intervals,
                     std::vector<double>& knot_cap);

// Merges neighbours across a knot that constrains nothing (no stop, kink or curvature jump)
// when their limits and cap terms are identical (e.g. collinear lines, equal tangent arcs in
// one plane). The rule does not depend on the values of the limits, so raising a limit of
// every piece alike never changes the intervals (and the cycle time can only fall).
void merge_intervals(const Path& path, std::vector<Interval>& intervals, std::vector<double>& knot_cap);

}  // namespace blendbench::timing_detail
