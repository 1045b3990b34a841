#pragma once
// Metrics of one simulated run (DESIGN: Metrics, per variant). Inputs are plain values; no
// MuJoCo calls. Lengths in m, times in s; the summary writer converts to the units in its keys.

#include <optional>
#include <vector>

#include "blendbench/program/path.hpp"
#include "blendbench/program/program.hpp"
#include "blendbench/sim/simulator.hpp"

namespace blendbench {

struct MetricsOptions {
  Vec3 end_point = Vec3::Zero();       // programmed end point (m, world)
  double settle_tolerance = 1e-4;      // m
  JointVector velocity_limits = JointVector::Constant(1e300);  // rad/s per joint
  JointVector torque_limits = JointVector::Constant(1e300);    // N m per joint
};

struct Metrics {
  // start to the first instant after which the actual TCP stays within the settle tolerance of
  // the end point; empty when it never settles within the simulated time
  std::optional<double> cycle_time;
  double tracking_error_max = 0;  // m: |actual TCP - commanded TCP| at the same instant
  double tracking_error_rms = 0;  // m
  double contour_error_max = 0;   // m: actual TCP to the programmed path (closest point)
  double path_deviation_max = 0;  // m: planned (blended) path to the programmed path, from the corner reports
  double cartesian_jerk_peak = 0;  // m/s^3: commanded TCP, third differences
  double joint_jerk_peak = 0;      // rad/s^3: commanded joints, max over joints
  JointVector joint_velocity_peak = JointVector::Zero();      // rad/s, actual
  JointVector joint_acceleration_peak = JointVector::Zero();  // rad/s^2, actual (differences of qd)
  JointVector torque_peak = JointVector::Zero();              // N m
  bool joint_velocity_limit_exceeded = false;
  bool torque_limit_reached = false;
  // per trace sample, for trace.csv and plots
  std::vector<double> tracking_error;  // m
  std::vector<double> contour_error;   // m
};

// Computes the metrics of a run that did not diverge (asserted: a diverged trace is not
// tracking data). `program` is the programmed path, `path` the blended one.
Metrics compute_metrics(const Trace& trace, const Program& program, const Path& path, const MetricsOptions& options);

}  // namespace blendbench
