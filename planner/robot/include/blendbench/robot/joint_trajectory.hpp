#pragma once
// The joint reference handed from the planner to the simulator: the one joint-trajectory type.

#include <vector>

#include "blendbench/robot/kinematics.hpp"

namespace blendbench {

// Joint reference sampled every `dt` seconds: sample k holds the commanded link-side joint
// state at t = k * dt, q (rad), qd (rad/s), qdd (rad/s^2), in the chain's joint order. qd and
// qdd are either empty (read as zero) or as long as q.
struct JointTrajectory {
  double dt = 0;  // s
  std::vector<JointVector> q, qd, qdd;
};

}  // namespace blendbench
