#pragma once
// One timed path executed on the arm: inverse kinematics of every sample, the simulation, and
// the metrics and health of the trace. The scenario runner and the paper reproductions share it.

#include <optional>
#include <vector>

#include "blendbench/program/corner_placement.hpp"
#include "blendbench/robot/ik.hpp"
#include "blendbench/robot/joint_mapping.hpp"
#include "blendbench/sim/metrics.hpp"
#include "blendbench/sim/simulator.hpp"
#include "blendbench/timing/timing.hpp"

namespace blendbench {

// When the reference passes each corner: the first sample at its transition's start, the last at
// its end (for a stop: when the reference arrives there and when it leaves).
std::vector<CornerTiming> corner_timings(const std::vector<CornerPlacement>& placements, const Timing& timing);

struct ExecutionOptions {
  // the TCP orientation (base frame) on paths that carry none (Path::oriented); an oriented
  // path gives every sample its own (Path::orientation)
  Eigen::Matrix3d tool_rotation = Eigen::Matrix3d::Identity();
  JointVector q0 = JointVector::Zero();  // the IK branch at the path's start (link angles, rad)
  JointMappingOptions mapping;           // whether the reference may change IK branch
  ServoConfig servo;                     // its setpoint period must be the timing's dt
  RunOptions run;                        // settle time and frames
  MetricsOptions metrics;                // corners and end point are filled in from the path
};

// What came of it. `joints` failed (outcome not ok): nothing was simulated. `trace.diverged`:
// no metrics. Otherwise metrics and health describe the run. Wall-clock times in s.
struct Execution {
  JointMapping joints;
  // the joint reference's passages near a singularity (scanned before the run), in time order
  std::vector<SingularityPassage> singularities;
  std::vector<CornerTiming> corners;
  Trace trace;
  std::optional<Metrics> metrics;
  std::optional<Health> health;
  double ik_seconds = 0, simulation_seconds = 0;
};

// Maps every sample of `timing` on `path` to the joints (the path's orientation, or
// tool_rotation where it has none; seeded with q0), runs
// the reference on `sim` and takes the metrics against `program` (programmed) and `path`
// (planned), with the corners' times from the plan. Throws InputError as Simulator::run does.
Execution execute(const Simulator& sim, const IkSolver& ik, const Program& program, const Path& path,
                  const Timing& timing, const ExecutionOptions& options);

// The same for a joint reference already mapped (`joints`, outcome ok: the `joints` of an
// earlier execute of the same timing), run on another `sim`: the plan and the IK do not depend
// on the arm's dynamics, so the perturbed models of a sensitivity run reuse them. The result's
// `joints` and `singularities` are left empty and ik_seconds 0. Throws as execute does.
Execution execute_mapped(const Simulator& sim, const Program& program, const Path& path, const Timing& timing,
                         const JointTrajectory& joints, const ExecutionOptions& options);

}  // namespace blendbench
