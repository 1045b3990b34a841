#pragma once
// Numeric inverse kinematics of any six-joint chain: damped least squares (Levenberg-Marquardt)
// on forward_kinematics and the geometric Jacobian, warm-started, within the joint limits.
//
// Each iteration solves (J^T J + lambda I) dq = J^T e for the pose error e = [dp; dw]
// (pose_error: m and rad, base frame), scales dq down so no joint moves more than max_step, and
// clamps q + dq into the joint limits (a projected step). lambda starts at
// kNumericIkDampingStart * max diag(J^T J) and follows Nielsen's rule (Madsen, Nielsen and
// Tingleff, "Methods for non-linear least squares problems", 2004, sec. 3.2): a step is kept
// when it lowers |e|, and lambda then shrinks by max(1/3, 1 - (2 rho - 1)^3), rho the ratio of
// the actual to the predicted decrease (towards Gauss-Newton, quadratic convergence near the
// solution); a rejected step multiplies lambda by 2, 4, 8, ... (towards a short gradient step,
// safe next to a singularity).
//
// Convergence criterion: |dp| <= target_position and |dw| <= target_angle. The iteration also
// stops after max_iterations, or when lambda exceeds kNumericIkDampingMax (no step helps: a
// local minimum of |e|, a joint limit in the way, or rounding at the solution). The result counts
// as a solution when |dp| <= kIkPositionTol and |dw| <= kIkAngleTol (ik.hpp), whatever stopped it.
//
// A local solver: seeded near a solution that lies close to a singularity, it may flow to
// another branch (the elbow's mirror, 2 q3 away) and converge there, or, where that one lies
// beyond a limit, stop on the limit (kJointLimit, the iterate within the limits).
// NumericIk.AgreesWithBothClosedFormsWhenSeededNearTheBranch measures it at seeds up to 0.05 rad
// off on every joint: about 1.4e-4 of the solves fail, all of them within a sine of 0.2 of a
// singularity, and beyond that every solve keeps its branch. In a run each sample is seeded
// from the one before it, far closer.

#include "blendbench/core/status.hpp"
#include "blendbench/robot/kinematics.hpp"

namespace blendbench {

// Pose accuracy of every solution the solvers return (m, rad).
inline constexpr double kIkPositionTol = 1e-10;
inline constexpr double kIkAngleTol = 1e-10;

// The damping (lambda, added to J^T J whose entries are ~m^2 or 1): its start relative to J^T J
// (small: a warm start is close to the solution), and its bounds: the smallest is negligible
// against J^T J away from singularities and keeps the step bounded next to one; beyond the
// largest no step can help.
inline constexpr double kNumericIkDampingStart = 1e-6;
inline constexpr double kNumericIkDampingMin = 1e-15;
inline constexpr double kNumericIkDampingMax = 1e6;

struct NumericIkOptions {
  int max_iterations = 100;
  double target_position = 1e-13;  // m
  double target_angle = 1e-13;     // rad
  double max_step = 0.3;           // rad: the largest joint change per iteration
  bool respect_limits = true;      // clamp every iterate into the chain's joint limits
};

// What the iteration reached. status: kOk (a solution, see above); kJointLimit (not a solution,
// and a joint rests on its limit: the limit is in the way); kNotConverged (not a solution: the
// pose may be out of reach or separated from the start by a singularity). q is the last iterate
// (finite; within the limits when respect_limits); errors are |dp| (m) and |dw| (rad) there.
struct NumericIkResult {
  Status status = Status::kNotConverged;
  JointVector q = JointVector::Zero();
  int iterations = 0;
  double position_error = 0;
  double angle_error = 0;
  int limit_joint = -1;  // index of a joint on its limit when status is kJointLimit
};

// Solves for the TCP pose `target` (chain base frame) from `q_start` (rad). A non-finite target
// or start gives kNotConverged with q = q_start and no iteration.
NumericIkResult numeric_ik(const KinematicChain& chain, const Eigen::Isometry3d& target, const JointVector& q_start,
                           const NumericIkOptions& options = {});

}  // namespace blendbench
