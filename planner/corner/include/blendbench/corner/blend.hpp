#pragma once
// The blending planner: program in, path with corner reports out.

#include "blendbench/program/path.hpp"
#include "blendbench/program/program.hpp"

#include <cstddef>
#include <vector>

namespace blendbench {

// Inserts the transition of each move's method at the corner at its end (the last move's
// transition is ignored: the program ends at rest). Validates the program first (InputError
// naming the move). A corner the method cannot fit becomes a kink with stop_before set and a
// report whose note says why, or an InputError when the request itself is impossible
// (e.g. tolerance 0 at a tangent discontinuity).
// First merges runs of collinear lines (merge_collinear); the path's move and corner indices
// are those of `program`. With program.smoothing, the program's point streams are replaced by
// their smoothed curves first (smoothing.hpp): their inner vertices get no corner report, and the
// path says what was smoothed (Path::smoothing).
// A program that sets orientations (oriented(program)) gets them on every piece (orient_path);
// merging never joins a move that sets one.
Path blend(const Program& program);

// `blended` (the blend of `program`) with the tool orientation of every piece and each
// transition's orientation change in its report, by the model of orientation.hpp: the slerp of
// every move by its arc length, the quintic blend of the two moves' rotations over each
// transition's arc length, the corner's target at a corner without a transition.
Path orient_path(const Path& blended, const Program& program);

// LinuxCNC's G64 Q ("naive CAM detector") on a program: consecutive moves k..m are merged into
// one line from the start of k to the end of m when they are all lines, none setting an
// orientation, with the same limits and buffer mode, the corners k..m-1 (each at the end of its move) have a transition other
// than none with merge_tolerance > 0, and every inner vertex lies within the smallest of those
// tolerances of that line and ahead of the previous one along it; the merged line keeps move
// k's name, source and limits and move m's transition. Runs are grown greedily, at most
// kMaxMergeRun moves. `first[j]` and `last[j]` are the original indices of merged move j.
struct MergedProgram {
  Program program;
  std::vector<std::size_t> first, last;
  int moves_merged = 0;
  double tolerance = 0;  // m: the largest tolerance a merge used
};
inline constexpr int kMaxMergeRun = 256;
MergedProgram merge_collinear(const Program& program);

// Fills the measured fields of a report (length, deviation, kappa_max, sharpness_max,
// feed_max) from the transition pieces and the programmed moves. `a_max` (m/s^2) and `j_max`
// (m/s^3) feed eq. 25-27 of 004. `exact_deviation` >= 0 (CornerFit::exact_deviation) is the fit's
// own deviation (in closed form, or measured by the fit, e.g. where it solved a tolerance),
// reported as it is; otherwise the deviation is measured here (hausdorff_within; corner_deviation,
// corner.hpp, gives the same value for a fit).
void measure_corner(CornerReport& report, const std::vector<Segment>& transition, const Primitive& in,
                    const Primitive& out, double a_max, double j_max, double exact_deviation = -1);

// seed 004 eq. 25-27: the highest constant path speed (m/s) on a curve of curvature kappa (1/m)
// and sharpness c (1/m^2) that keeps the axis acceleration and jerk within a_max and j_max.
// Infinity on a straight line.
double curvature_speed_limit(double kappa, double sharpness, double a_max, double j_max);

}  // namespace blendbench
