#pragma once
// Standard Denavit-Hartenberg frames and how a closed-form model sits in a kinematic chain.
//
// The closed-form solvers (ur_ik.hpp, spherical_ik.hpp) work on an ideal DH geometry; the chain
// read from a URDF may place its base anywhere, turn its joints the other way, start them at
// another zero and carry any tool. A DhPlacement maps one to the other:
//   TCP pose = base * dh_flange(theta) * tool,   theta_i = sign_i * q_i + offset_i,
// with q the chain's joint angles (rad) and theta the DH ones.

#include <array>
#include <functional>

#include "blendbench/robot/kinematics.hpp"

namespace blendbench {

// The DH transform Rz(theta) Tz(d) Tx(a) Rx(alpha) from frame i-1 to frame i (m, rad).
Eigen::Isometry3d dh_transform(double theta, double d, double a, double alpha);

// The flange pose of a six-joint DH chain at joint angles `theta` (rad): the product of the six
// transforms with the per-joint d, a (m) and alpha (rad).
Eigen::Isometry3d dh_chain_pose(const JointVector& theta, const std::array<double, 6>& d, const std::array<double, 6>& a,
                                const std::array<double, 6>& alpha);

// The same chain as joints: joint i turns about z of DH frame i-1, the constant part Tz Tx Rx
// of each DH transform becomes the next joint's origin (the last one the TCP); joints named
// joint1..joint6, their limits left to the caller.
KinematicChain dh_kinematic_chain(const std::array<double, 6>& d, const std::array<double, 6>& a,
                                  const std::array<double, 6>& alpha);

// Where a DH model sits in a chain (see above). `deviation` (m, rad) is the largest pose
// difference between the chain and the model at random joint angles: zero for an exact model.
struct DhPlacement {
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();  // chain base -> DH frame 0
  Eigen::Isometry3d tool = Eigen::Isometry3d::Identity();  // DH frame 6 -> TCP
  JointVector sign = JointVector::Ones();
  JointVector offset = JointVector::Zero();
  double deviation = 0;

  [[nodiscard]] JointVector theta(const JointVector& q) const { return sign.cwiseProduct(q) + offset; }
  [[nodiscard]] JointVector q(const JointVector& theta) const { return sign.cwiseProduct(theta - offset); }
};

// The flange pose (DH frame 6 in DH frame 0) of a DH model at DH angles theta.
using DhForward = std::function<Eigen::Isometry3d(const JointVector& theta)>;

// The largest position (m) or rotation (rad) difference between forward_kinematics(chain, q) and
// base * flange(theta(q)) * tool over 16 fixed pseudo-random q in [-pi, pi]^6.
double placement_deviation(const KinematicChain& chain, const DhPlacement& placement, const DhForward& flange);

}  // namespace blendbench
