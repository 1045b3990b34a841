#pragma once
// Inverse kinematics of a six-joint chain: closed form where the chain's geometry allows it,
// numeric otherwise, every solution polished against the chain's own forward kinematics.
//
// The solver is picked by the chain's geometry (IkMethod::kAuto), in this order:
//   1. UR-type (ur_ik.hpp: axes 2, 3, 4 parallel, offset wrist): closed form, 8 branches;
//   2. offset shoulder with a spherical wrist (spherical_ik.hpp, the KUKA / ABB kind): closed
//      form, 8 branches;
//   3. anything else with six revolute joints: numeric IK (numeric_ik.hpp), warm-started from
//      the previous joint angles, within the joint limits: one solution, on the branch the
//      start lies on.
// The closed forms run on the ideal DH geometry found in the chain (any base placement, axis
// signs, zero offsets and tool); damped-least-squares polishing against forward_kinematics(chain)
// makes every returned solution exact to kIkPositionTol and kIkAngleTol.

#include <array>
#include <string_view>
#include <vector>

#include "blendbench/core/status.hpp"
#include "blendbench/robot/dh.hpp"
#include "blendbench/robot/kinematics.hpp"
#include "blendbench/robot/numeric_ik.hpp"
#include "blendbench/robot/spherical_ik.hpp"
#include "blendbench/robot/ur_ik.hpp"

namespace blendbench {

// Which solver to use: kAuto picks by geometry as above; kClosedForm is either closed form (an
// error when neither fits); the others name one.
enum class IkMethod { kAuto, kClosedForm, kUrClosedForm, kSphericalWristClosedForm, kNumeric };

// "auto", "closed_form", "ur_closed_form", "spherical_wrist_closed_form", "numeric".
std::string_view to_string(IkMethod method);

// Weights of the joint norm that picks the branch nearest a previous configuration:
// sqrt(sum w_i (q_i - q_near_i)^2). The proximal joints move the most mass and sweep the most
// space, so a branch that keeps them still is preferred.
inline constexpr std::array<double, 6> kBranchWeights = {3.0, 3.0, 2.0, 1.0, 1.0, 1.0};

// Weighted distance between two joint vectors with kBranchWeights (rad).
double branch_distance(const JointVector& a, const JointVector& b);

// IK for one six-joint chain.
class IkSolver {
 public:
  // Throws InputError (field "urdf") when the chain does not have six joints, or when a closed
  // form is asked for (kClosedForm, kUrClosedForm, kSphericalWristClosedForm) and the chain's
  // axes do not follow its pattern (the message says which axes and why).
  explicit IkSolver(KinematicChain chain, IkMethod method = IkMethod::kAuto);

  struct Result {
    Outcome outcome;
    JointVector q = JointVector::Zero();  // rad; q_near when outcome is not ok
  };

  // The solution nearest q_near (kBranchWeights norm) among all branches, with every joint
  // moved by multiples of 2 pi to the representative nearest q_near within its limits. The
  // numeric solver instead iterates from q_near within the limits. Failures, each with a
  // message giving the pose (mm, deg):
  //   kUnreachable  no branch reaches the pose (beyond reach, or the wrist centre inside the
  //                 shoulder's cylinder), the numeric iteration from q_near finds no solution
  //                 (out of reach, or a singularity between), or the pose is not finite;
  //   kJointLimit   branches exist but every one violates a joint limit (numeric: a joint limit
  //                 stops the iteration short of the pose);
  //   kSingular     branches exist but none could be polished to the tolerance (at a
  //                 singularity on the edge of the workspace of a chain that is not exactly of
  //                 its closed form's type).
  [[nodiscard]] Result solve(const Eigen::Isometry3d& tcp_pose, const JointVector& q_near) const;

  // All polished branches with each joint wrapped to the representative nearest q_near, limits
  // ignored, sorted by branch_distance to q_near (numeric: the one solution the iteration from
  // q_near reaches without limits). Empty when none reaches the pose.
  [[nodiscard]] std::vector<JointVector> solutions(const Eigen::Isometry3d& tcp_pose, const JointVector& q_near) const;

  [[nodiscard]] const KinematicChain& chain() const { return chain_; }
  // The solver in use: kUrClosedForm, kSphericalWristClosedForm or kNumeric.
  [[nodiscard]] IkMethod method() const { return method_; }
  // The DH geometry found in the chain (asserts that the solver is that closed form).
  [[nodiscard]] const UrGeometry& geometry() const;
  [[nodiscard]] const SphericalWristGeometry& spherical_geometry() const;
  // Where the closed form's DH model sits in the chain (identity placement for kNumeric).
  [[nodiscard]] const DhPlacement& placement() const { return placement_; }
  // Whether q (rad) lies within every joint limit (with a 1e-9 rad allowance for rounding).
  [[nodiscard]] bool within_limits(const JointVector& q) const;

 private:
  struct Branches {
    std::vector<JointVector> q;    // polished, wrapped nearest q_near, sorted
    std::size_t found = 0;  // closed-form branches before polishing
  };
  [[nodiscard]] Branches branches(const Eigen::Isometry3d& tcp_pose, const JointVector& q_near) const;
  [[nodiscard]] bool polish(const Eigen::Isometry3d& tcp_pose, JointVector& q) const;
  [[nodiscard]] Result solve_numeric(const Eigen::Isometry3d& tcp_pose, const JointVector& q_near) const;

  KinematicChain chain_;
  IkMethod method_ = IkMethod::kNumeric;
  UrGeometry ur_;
  SphericalWristGeometry spherical_;
  DhPlacement placement_;
  double reach_slack_ = kReachSlack;  // m, grows with the chain's deviation from the DH model
};

}  // namespace blendbench
