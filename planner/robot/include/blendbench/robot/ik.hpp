#pragma once
// Inverse kinematics for UR-type six-axis arms: closed form on the Denavit-Hartenberg geometry,
// then a damped-least-squares polish against the chain's own forward kinematics.
//
// UR-type means the standard DH parameters (frame i-1 -> i: Rz(theta_i) Tz(d_i) Tx(a_i)
// Rx(alpha_i)) have the pattern
//   alpha = (pi/2, 0, 0, pi/2, -pi/2, 0),  a = (0, a2, a3, 0, 0, 0),  d = (d1, 0, 0, d4, d5, d6):
// axis 1 meets axis 2 at a right angle, axes 2, 3, 4 are parallel, axis 5 meets axis 4 and
// axis 6 at right angles. The UR5e has d1 0.1625, a2 -0.425, a3 -0.3922, d4 0.1333,
// d5 0.0997, d6 0.0996 m.

#include <array>
#include <vector>

#include "blendbench/robot/kinematics.hpp"
#include "blendbench/core/status.hpp"

namespace blendbench {

// The six lengths of a UR-type arm (m), signed as in the DH table above.
struct UrGeometry {
  double d1 = 0;
  double a2 = 0;
  double a3 = 0;
  double d4 = 0;
  double d5 = 0;
  double d6 = 0;
};

// The DH transform Rz(theta) Tz(d) Tx(a) Rx(alpha).
Eigen::Isometry3d dh_transform(double theta, double d, double a, double alpha);

// DH frame 6 (the flange) in DH frame 0 for the DH joint angles theta (rad).
Eigen::Isometry3d ur_forward_kinematics(const UrGeometry& geometry, const JointVector& theta);

// All closed-form solutions (DH joint angles, each wrapped to (-pi, pi]) that place DH frame 6
// at `flange_pose` (in DH frame 0): up to 8, two shoulder x two wrist x two elbow branches, in
// that nesting order. Branches whose elbow cannot reach are left out; an empty result means the
// pose is out of reach. At a wrist singularity (sin(theta5) = 0, axes 2, 3, 4, 6 parallel)
// theta6 takes the value from `theta_near` if the elbow can reach with it, else the nearest value
// for which it can; where the arm's lateral offset d4 is zero and the wrist centre lies on
// axis 1, theta1 takes the value from `theta_near`. Never returns NaN for a finite pose.
// Limitation: within about 0.1 mm of the shoulder singularity rounding in theta1 can hide an
// exact wrist singularity; theta6 then comes out exact but arbitrary rather than near theta_near.
// `reach_slack` (m) is how far the wrist centre may lie inside the shoulder cylinder, or beyond
// the elbow's reach, and still be solved (at the singularity): rounding in a pose computed at a
// shoulder-singular or fully stretched configuration.
inline constexpr double kReachSlack = 1e-12;
std::vector<JointVector> ur_closed_form_ik(const UrGeometry& geometry, const Eigen::Isometry3d& flange_pose,
                                    const JointVector& theta_near = JointVector::Zero(), double reach_slack = kReachSlack);

// A KinematicChain with exactly the DH geometry (base frame = DH frame 0, TCP = DH frame 6),
// every joint about its frame's z axis, limits +-2 pi rad, pi rad/s, and 150 N*m for joints 1-3,
// 28 N*m for joints 4-6. For tests and for building synthetic arms.
KinematicChain ur_chain(const UrGeometry& geometry);

// Weights of the joint norm that picks the branch nearest a previous configuration:
// sqrt(sum w_i (q_i - q_near_i)^2). The proximal joints move the most mass and sweep the most
// space, so a branch that keeps them still is preferred.
inline constexpr std::array<double, 6> kBranchWeights = {3.0, 3.0, 2.0, 1.0, 1.0, 1.0};

// Weighted distance between two joint vectors with kBranchWeights (rad).
double branch_distance(const JointVector& a, const JointVector& b);

// IK for one UR-type chain. The constructor finds the DH geometry in the chain at q = 0 (any
// base placement, joint-axis signs, zero offsets and tool transform) and verifies it against
// the chain's forward kinematics; solve() runs the closed form on that geometry and polishes
// each branch with damped least squares against forward_kinematics(chain), so the pose error
// of a returned solution is below kIkPositionTol and kIkAngleTol.
class IkSolver {
 public:
  // Throws InputError (field "urdf") when the chain does not have six joints, or its axes do
  // not follow the UR pattern to within 1e-6 (rad, m).
  explicit IkSolver(KinematicChain chain);

  struct Result {
    Outcome outcome;
    JointVector q = JointVector::Zero();  // rad; q_near when outcome is not ok
  };

  // The solution nearest q_near (kBranchWeights norm) among all branches, with every joint
  // moved by multiples of 2 pi to the representative nearest q_near within its limits.
  // Failures, each with a message giving the pose (mm, deg):
  //   kUnreachable  no branch reaches the pose (beyond reach, or the wrist centre inside the
  //                 cylinder of radius |d4| around axis 1), or the pose is not finite;
  //   kJointLimit   branches exist but every one violates a joint limit;
  //   kSingular     branches exist but none could be polished to the tolerance (at a
  //                 singularity on the edge of the workspace of a chain that is not exactly
  //                 UR-type).
  [[nodiscard]] Result solve(const Eigen::Isometry3d& tcp_pose, const JointVector& q_near) const;

  // All polished branches with each joint wrapped to the representative nearest q_near,
  // limits ignored, sorted by branch_distance to q_near. Empty when none reaches the pose.
  [[nodiscard]] std::vector<JointVector> solutions(const Eigen::Isometry3d& tcp_pose, const JointVector& q_near) const;

  [[nodiscard]] const KinematicChain& chain() const { return chain_; }
  // The DH geometry found in the chain.
  [[nodiscard]] const UrGeometry& geometry() const { return geometry_; }
  // Whether q (rad) lies within every joint limit (with a 1e-9 rad allowance for rounding).
  [[nodiscard]] bool within_limits(const JointVector& q) const;

 private:
  struct Branches {
    std::vector<JointVector> q;    // polished, wrapped nearest q_near, sorted
    std::size_t found = 0;  // closed-form branches before polishing
  };
  [[nodiscard]] Branches branches(const Eigen::Isometry3d& tcp_pose, const JointVector& q_near) const;
  [[nodiscard]] bool polish(const Eigen::Isometry3d& tcp_pose, JointVector& q) const;

  KinematicChain chain_;
  UrGeometry geometry_;
  Eigen::Isometry3d base_;  // chain base -> DH frame 0
  Eigen::Isometry3d tool_;  // DH frame 6 -> TCP
  JointVector sign_;               // theta_i = sign_i * q_i + offset_i
  JointVector offset_;
  double reach_slack_ = kReachSlack;  // m, grows with the chain's deviation from the DH model
};

// Pose accuracy of every solution IkSolver returns.
inline constexpr double kIkPositionTol = 1e-10;  // m
inline constexpr double kIkAngleTol = 1e-10;     // rad

}  // namespace blendbench
