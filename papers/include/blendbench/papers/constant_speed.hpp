#pragma once
// A timing law at constant path speed: the reference that the experiment of seed 002 (Makino) runs (a pen at a
// constant line speed through the corner), and the one on which a G1 and a G2 corner are
// compared at equal speed. Unlike plan_timing it ignores curvature: the speed stays `speed`
// through every transition, so a circular arc's curvature steps become acceleration steps
// kappa v^2, as on a controller that lets them through.

#include "blendbench/program/path.hpp"
#include "blendbench/timing/timing.hpp"

namespace blendbench {

// Rest -> `speed` over the first `ramp` m of the path, `speed` until `ramp` m before its end,
// -> rest over the last `ramp` m; each ramp with a sinusoidal acceleration (v = V (1 - cos(pi t
// / T)) / 2, T = 2 ramp / V: acceleration pi V / (2 T) at most, continuous, zero at both ends).
// Samples every dt from t = 0 to the first multiple of dt at or after the end, the last at rest
// at the end of the path. Throws std::invalid_argument unless speed, ramp and dt are positive
// and 2 ramp <= the path's length.
Timing constant_speed_timing(const Path& path, double speed, double ramp, double dt);

}  // namespace blendbench
