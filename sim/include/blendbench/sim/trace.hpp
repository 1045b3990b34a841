#pragma once
// What the execution stage produces and what it knows about the arm, as plain values: the
// recorded servo ticks of one run (Trace) and the arm's limits. No MuJoCo types, so metrics and
// reports can use them without the physics engine.
//
// Conventions: SI units (rad, rad/s, N*m, s, m); positions in the world frame of the model,
// which is the robot base frame; joint vectors in the chain's joint order.

#include <Eigen/Geometry>
#include <array>
#include <limits>
#include <string>
#include <vector>

#include "blendbench/core/geometry.hpp"
#include "blendbench/robot/kinematics.hpp"

namespace blendbench {

// Per-joint limits of the arm model: velocity (rad/s) and acceleration (rad/s^2), +inf where the
// model states none, and the actuator torque limit (N*m).
struct JointLimits {
  JointVector velocity = JointVector::Constant(std::numeric_limits<double>::infinity());
  JointVector acceleration = JointVector::Constant(std::numeric_limits<double>::infinity());
  JointVector torque = JointVector::Constant(std::numeric_limits<double>::infinity());
};

// The state at one setpoint t (the drives run faster in between; see servo.hpp).
//   q_cmd, qd_cmd    the link-side joint reference (the planned joints);
//   q_motor_cmd      the drive's motor-angle reference: q_cmd plus the expected gear deflection
//                    when the servo compensates it (equal to q_cmd on a rigid arm or without);
//   q_measured       what the drive's encoder reported at this tick (delayed, quantised motor
//                    angle);
//   following_error  the drive's position error at this tick: the motor reference of the
//                    instant the measurement describes minus q_measured (the "error pulses");
//   q_motor, qd_motor the true motor angle and velocity (joint side);
//   q, qd            the true link angle and velocity (motor angle + gear deflection);
//   tau              the motor torque applied from t to the next servo tick, after saturation;
//   tcp, tcp_cmd     the tool centre point of the actual links and of the reference (m), and
//   rotation, rotation_cmd their orientations (base frame).
// (Every field starts at zero, the rotations at the identity: a sample built field by field,
// as the tests build them, holds no indeterminate values.)
struct TraceSample {
  double t = 0;  // s
  JointVector q_cmd = JointVector::Zero();
  JointVector qd_cmd = JointVector::Zero();
  JointVector q_motor_cmd = JointVector::Zero();
  JointVector q_measured = JointVector::Zero();
  JointVector following_error = JointVector::Zero();
  JointVector q_motor = JointVector::Zero();
  JointVector qd_motor = JointVector::Zero();
  JointVector q = JointVector::Zero();
  JointVector qd = JointVector::Zero();
  JointVector tau = JointVector::Zero();
  Vec3 tcp_cmd = Vec3::Zero();
  Vec3 tcp = Vec3::Zero();
  Eigen::Quaterniond rotation_cmd = Eigen::Quaterniond::Identity();
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
};

// One sample per setpoint, t = k / setpoint_rate_hz, from 0 to the end of the reference plus
// the settle time. A diverged run stops at the first unhealthy step: `diverged` is set, `warning` says why,
// and `samples` holds only the (finite) ticks before it — they are for diagnosis, never for
// tracking metrics. `warning` may also carry non-fatal MuJoCo warnings on a run that did not
// diverge.
struct Trace {
  std::vector<TraceSample> samples;
  double period = 0;         // s, between samples: the setpoint period
  double reference_end = 0;  // s, time of the reference's last sample (the motion's end)
  bool diverged = false;
  std::string warning;
  // servo ticks at which joint i's torque demand exceeded its limit and was clamped
  std::array<long, 6> saturated_ticks{};
  // servo ticks the drive ran (the servo rate is a multiple of the setpoint rate, so there are
  // more of them than samples): what a share of saturated ticks is a share of
  long servo_ticks = 0;
};

}  // namespace blendbench
