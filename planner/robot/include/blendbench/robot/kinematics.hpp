#pragma once
// Forward kinematics and the geometric Jacobian of a serial chain of six revolute joints.
//
// A chain is what the URDF reader produces (sim/urdf_chain.hpp) and what the IK solver
// (planner/ik.hpp) works on: one rigid transform per joint from the parent joint frame to this
// joint's frame at q = 0 (fixed joints folded in), the joint axis in its own frame, and the
// transform from the last joint frame to the tool centre point. All lengths in m, angles in
// rad, poses in the chain's base frame.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "blendbench/core/geometry.hpp"

namespace blendbench {

// The one joint-space vector of the six-joint arm, in the chain's joint order: angles (rad),
// velocities (rad/s), accelerations (rad/s^2), torques (N*m) or per-joint gains and limits.
// Every stage (IK, joint mapping, scenario, simulator, metrics) uses this type.
using JointVector = Eigen::Matrix<double, 6, 1>;
// A spatial difference [dp; dw]: position (m) over rotation vector (rad), base frame.
using Twist = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

// One revolute joint. `origin` maps the previous joint frame (the base frame for the first
// joint) to this joint's frame at q = 0; the joint then rotates by q about `axis` (a unit vector
// in its own frame). Limits: lower/upper in rad (+-infinity for a continuous joint),
// velocity_limit in rad/s, effort_limit in N*m.
struct JointSpec {
  std::string name;
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
  Vec3 axis = Vec3::UnitZ();
  double lower = 0;
  double upper = 0;
  double velocity_limit = 0;
  double effort_limit = 0;
};

// A serial chain base -> joint 1 -> ... -> joint 6 -> TCP. `tcp` maps the last joint frame
// (after its rotation) to the tool centre point.
struct KinematicChain {
  std::vector<JointSpec> joints;
  Eigen::Isometry3d tcp = Eigen::Isometry3d::Identity();
};

// Pose of the TCP in the base frame at joint angles q (rad). The chain must have six joints
// (asserted).
Eigen::Isometry3d forward_kinematics(const KinematicChain& chain, const JointVector& q);

// Geometric Jacobian of the TCP at q in the base frame: rows 0-2 map qd to the TCP's linear
// velocity (m/s), rows 3-5 to its angular velocity (rad/s).
Mat6 jacobian(const KinematicChain& chain, const JointVector& q);

// Pose error `target` relative to `actual` in the base frame: [dp; dw] with dp the position
// difference (m) and dw the rotation vector (axis * angle, rad) of target * actual^-1.
Twist pose_error(const Eigen::Isometry3d& target, const Eigen::Isometry3d& actual);

// Roll, pitch, yaw (rad) with R = Rz(yaw) Ry(pitch) Rx(roll), the URDF convention; pitch in
// [-pi/2, pi/2], roll and yaw in (-pi, pi].
Vec3 rpy_from_rotation(const Mat3& rotation);
// The rotation R = Rz(yaw) Ry(pitch) Rx(roll) of rpy = (roll, pitch, yaw) in rad: roll about x,
// then pitch about y, then yaw about z, all fixed axes (URDF's rpy); any finite angles.
Mat3 rotation_from_rpy(const Vec3& rpy);

// "position (x, y, z) mm, rpy (r, p, y) deg" with three decimals, for messages that name a pose.
std::string describe_pose(const Eigen::Isometry3d& pose);

}  // namespace blendbench
