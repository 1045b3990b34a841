#pragma once
// Plausibility checks of a loaded scenario: input that is valid but looks like a mistake gets a
// warning (LoadWarning, scenario.hpp), never an error. Each check returns its warning or none.

#include <optional>

#include "blendbench/io/gcode.hpp"
#include "blendbench/io/scenario.hpp"

namespace blendbench {

// A programmed path (the sum of its moves' lengths) longer than this, in a scenario that says
// `units: m`, reads like millimetre numbers taken as metres: the largest six-axis arms reach about
// 3.5 m, so one pass over a part of that size is a few metres; 10 m is the threshold.
inline constexpr double kLongPathMetres = 10;

// `units: m` and a path longer than kLongPathMetres: warns at `units_where`.
std::optional<LoadWarning> unit_warning(const Program& program, bool units_metres, const SourceRef& units_where);

// A G-code program's first F word sets a feed other than the scenario's defaults.velocity (m/s):
// the F words win (the program's feed, as a controller runs it), and the warning says so.
std::optional<LoadWarning> gcode_feed_warning(const GcodeResult& parsed, double defaults_velocity);

// The largest TCP speed the joints' velocity limits allow at joint angles q: the sum over the
// joints of limit_i times the norm of the i-th column of the position Jacobian (m/s). It bounds
// |J_v qd| for every |qd_i| <= limit_i (triangle inequality), so a feed above it cannot be held at
// that pose by any joint motion.
double tcp_speed_bound(const KinematicChain& chain, const JointVector& q);

// A move whose velocity is above tcp_speed_bound at the program's start pose (the URDF's chain
// with the scenario's tool, the IK solution there from robot.q_seed): warns at the first such
// move, with their count. No warning when the chain cannot be loaded or the start is not
// reachable: `run` refuses those with their own error.
std::optional<LoadWarning> feed_speed_warning(const Scenario& scenario);

}  // namespace blendbench
