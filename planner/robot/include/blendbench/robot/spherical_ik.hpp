#pragma once
// Closed-form inverse kinematics of industrial six-axis arms with an offset shoulder and a
// spherical wrist (the KUKA / ABB / Fanuc kind), on their Denavit-Hartenberg geometry.
//
// The standard DH parameters (frame i-1 -> i: Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i)) have the
// pattern
//   alpha = (pi/2, 0, pi/2, -pi/2, pi/2, 0),  a = (a1, a2, a3, 0, 0, 0),  d = (d1, d2, 0, d4, 0, d6):
// axis 1 is perpendicular to axis 2 (the shoulder offset a1 between them), axes 2 and 3 are
// parallel (upper arm a2, lateral offset d2, usually 0), axis 4 is perpendicular to axis 3 (elbow
// offset a3, forearm d4), and axes 4, 5, 6 meet in one point, the wrist centre, with 4 _|_ 5 _|_ 6
// (flange d6 beyond it). A KUKA KR 6 R900-class arm has d1 0.400, a1 0.025, a2 0.455, a3 0.035,
// d4 0.420, d6 0.080 m (models/kr6_like.urdf).

#include <vector>

#include "blendbench/robot/dh.hpp"
#include "blendbench/robot/ur_ik.hpp"

namespace blendbench {

// The lengths of a spherical-wrist arm (m), signed as in the DH table above.
struct SphericalWristGeometry {
  double d1 = 0;  // height of axis 2 above DH frame 0
  double a1 = 0;  // shoulder offset (axis 1 to axis 2)
  double a2 = 0;  // upper arm (axis 2 to axis 3)
  double d2 = 0;  // lateral offset of the arm plane from axis 1 (0 on KUKA / ABB arms)
  double a3 = 0;  // elbow offset (axis 3 to axis 4)
  double d4 = 0;  // forearm (along axis 4 to the wrist centre)
  double d6 = 0;  // wrist centre to the flange along axis 6
};

// DH frame 6 (the flange) in DH frame 0 for the DH joint angles theta (rad).
Eigen::Isometry3d spherical_forward_kinematics(const SphericalWristGeometry& geometry, const JointVector& theta);

// All closed-form solutions (DH joint angles, each wrapped to (-pi, pi]) that place DH frame 6 at
// `flange_pose` (in DH frame 0): up to 8, two shoulder (front, back) x two elbow (up, down) x two
// wrist (sin theta5 > 0, < 0: the wrist flip) branches, in that nesting order. Branches the elbow
// cannot reach are left out; an empty result means the pose is out of reach. Singularities:
//   wrist (sin theta5 = 0, axes 4 and 6 in line): only theta4 +- theta6 is fixed; theta6 takes
//     the value from `theta_near` and theta4 the rest;
//   shoulder (the wrist centre on the cylinder of radius |d2| around axis 1; on axis 1 when
//     d2 = 0): theta1 is free and takes the value from `theta_near` (and that plus pi);
//   elbow (stretched or folded): the two elbow branches coincide.
// `reach_slack` (m): as for ur_closed_form_ik. Never returns NaN for a finite pose.
std::vector<JointVector> spherical_closed_form_ik(const SphericalWristGeometry& geometry, const Eigen::Isometry3d& flange_pose,
                                                  const JointVector& theta_near = JointVector::Zero(),
                                                  double reach_slack = kReachSlack);

// A KinematicChain with exactly the DH geometry (base frame = DH frame 0, TCP = DH frame 6),
// every joint about its frame's z axis, limits +-2 pi rad (+-pi for the elbow), pi rad/s and
// 300 N*m for joints 1-3, 50 N*m for joints 4-6. For tests and synthetic arms.
KinematicChain spherical_chain(const SphericalWristGeometry& geometry);

// The geometry found in a chain at q = 0 and where it sits (dh.hpp), verified against the
// chain's forward kinematics. Throws InputError (field "urdf", "the kinematic chain has no
// spherical wrist of the industrial kind: <why>") when the chain does not have six joints, its
// axes do not follow the pattern above to within 1e-6 (rad, m), or the model found differs from
// the chain by more than 1e-5.
struct SphericalWristFit {
  SphericalWristGeometry geometry;
  DhPlacement placement;
};
SphericalWristFit fit_spherical_wrist(const KinematicChain& chain);

// The closeness to the three singularities at DH angles theta (ArmMeasures, ur_ik.hpp):
//   shoulder: the wrist centre along DH x1 from axis 1 (m), + in front of the shoulder;
//   elbow:    sin(theta3 - atan2(d4, a3)) (zero with the forearm in line with the upper arm);
//   wrist:    sin(theta5) (zero with axes 4 and 6 in line).
ArmMeasures spherical_measures(const SphericalWristGeometry& geometry, const JointVector& theta);

}  // namespace blendbench
