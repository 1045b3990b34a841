#pragma once
// The blending planner: program in, path with corner reports out.

#include "blendbench/program/path.hpp"
#include "blendbench/program/program.hpp"

namespace blendbench {

// Inserts the transition of each move's method at the corner at its end (the last move's
// transition is ignored: the program ends at rest). Validates the program first (InputError
// naming the move). A corner the method cannot fit becomes a kink with stop_before set and a
// report whose note says why, or an InputError when the request itself is impossible
// (e.g. tolerance 0 at a tangent discontinuity).
Path blend(const Program& program);

// Fills the measured fields of a report (length, deviation, kappa_max, sharpness_max,
// feed_max) from the transition pieces and the programmed moves. `a_max` (m/s^2) and `j_max`
// (m/s^3) feed eq. 25-27 of 004.
void measure_corner(CornerReport& report, const std::vector<Segment>& transition, const Primitive& in,
                    const Primitive& out, double a_max, double j_max);

// 004 eq. 25-27: the highest constant path speed (m/s) on a curve of curvature kappa (1/m)
// and sharpness c (1/m^2) that keeps the axis acceleration and jerk within a_max and j_max.
// Infinity on a straight line.
double curvature_speed_limit(double kappa, double sharpness, double a_max, double j_max);

}  // namespace blendbench
