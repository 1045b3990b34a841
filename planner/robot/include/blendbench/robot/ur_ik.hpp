#pragma once
// Closed-form inverse kinematics of UR-type six-axis arms on their Denavit-Hartenberg geometry.
//
// UR-type means the standard DH parameters (frame i-1 -> i: Rz(theta_i) Tz(d_i) Tx(a_i)
// Rx(alpha_i)) have the pattern
//   alpha = (pi/2, 0, 0, pi/2, -pi/2, 0),  a = (0, a2, a3, 0, 0, 0),  d = (d1, 0, 0, d4, d5, d6):
// axis 1 meets axis 2 at a right angle, axes 2, 3, 4 are parallel, axis 5 meets axis 4 and
// axis 6 at right angles. The UR5e has d1 0.1625, a2 -0.425, a3 -0.3922, d4 0.1333,
// d5 0.0997, d6 0.0996 m.

#include <vector>

#include "blendbench/robot/dh.hpp"

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
                                           const JointVector& theta_near = JointVector::Zero(),
                                           double reach_slack = kReachSlack);

// A KinematicChain with exactly the DH geometry (base frame = DH frame 0, TCP = DH frame 6),
// every joint about its frame's z axis, limits +-2 pi rad, pi rad/s, and 150 N*m for joints 1-3,
// 28 N*m for joints 4-6. For tests and for building synthetic arms.
KinematicChain ur_chain(const UrGeometry& geometry);

// The UR geometry found in a chain at q = 0 (any base placement, joint-axis signs, zero offsets
// and tool transform) and where it sits (dh.hpp), verified against the chain's forward
// kinematics. Throws InputError (field "urdf", "the kinematic chain is not UR-type: <why>") when
// the chain does not have six joints or its axes do not follow the UR pattern to within 1e-6
// (rad, m), or the model found differs from the chain by more than 1e-5.
struct UrFit {
  UrGeometry geometry;
  DhPlacement placement;
};
UrFit fit_ur(const KinematicChain& chain);

// The three measures of closeness to the UR arm's singularities at DH angles theta, each zero at
// its singularity and signed by the IK branch on its side:
//   shoulder: the wrist point p5 (where axes 5 and 6 meet) along DH x1, i.e. its distance from
//             the plane of axis 1 and the arm's lateral offset (m), + in front of the shoulder;
//   elbow:    sin(theta3) (zero stretched or folded);
//   wrist:    sin(theta5) (zero when axes 4 and 6 are parallel).
struct ArmMeasures {
  double shoulder = 0, elbow = 0, wrist = 0;
};
ArmMeasures ur_measures(const UrGeometry& geometry, const JointVector& theta);

}  // namespace blendbench
