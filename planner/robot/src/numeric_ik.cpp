#include "blendbench/robot/numeric_ik.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <array>
#include <cmath>

namespace blendbench {
namespace {

// A joint this close to a limit (rad) rests on it.
constexpr double kOnLimit = 1e-9;

JointVector clamped(const KinematicChain& chain, JointVector q) {
  for (std::size_t i = 0; i < 6; ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    q[k] = std::clamp(q[k], chain.joints[i].lower, chain.joints[i].upper);
  }
  return q;
}

// The damped step (J^T J + lambda I) dq = J^T e with the joints that would cross a limit held
// on it (an active set: each pass moves the offending joints exactly onto their limits and
// solves again for the others with their motion subtracted from e), then scaled so no joint
// moves more than max_step. Holding a joint, rather than clamping the step afterwards, keeps
// the step a descent direction for the free joints, so the iteration converges along a limit.
JointVector limited_step(const KinematicChain& chain, const JointVector& q, const Mat6& jac, const Twist& error,
                         double damping, const NumericIkOptions& options) {
  JointVector step = JointVector::Zero();
  std::array<bool, 6> held{};
  for (int pass = 0; pass < 6; ++pass) {
    // solve for the free joints with the held ones' motion taken out of the error
    Twist rest = error;
    for (Eigen::Index i = 0; i < 6; ++i) {
      if (held[static_cast<std::size_t>(i)]) rest -= jac.col(i) * step[i];
    }
    Mat6 free_jac = jac;
    for (Eigen::Index i = 0; i < 6; ++i) {
      if (held[static_cast<std::size_t>(i)]) free_jac.col(i).setZero();
    }
    const JointVector free_step =
        (free_jac.transpose() * free_jac + damping * Mat6::Identity()).ldlt().solve(free_jac.transpose() * rest);
    bool crossed = false;
    for (std::size_t i = 0; i < 6; ++i) {
      const auto k = static_cast<Eigen::Index>(i);
      if (held[i]) continue;
      step[k] = free_step[k];
      if (!options.respect_limits) continue;
      const JointSpec& joint = chain.joints[i];
      if (q[k] + step[k] > joint.upper || q[k] + step[k] < joint.lower) {
        step[k] = std::clamp(q[k] + step[k], joint.lower, joint.upper) - q[k];
        held[i] = true;
        crossed = true;
      }
    }
    if (!crossed) break;
  }
  const double largest = step.cwiseAbs().maxCoeff();
  if (largest > options.max_step) step *= options.max_step / largest;
  return step;
}

}  // namespace

NumericIkResult numeric_ik(const KinematicChain& chain, const Eigen::Isometry3d& target, const JointVector& q_start,
                           const NumericIkOptions& options) {
  NumericIkResult out;
  out.q = q_start;
  if (!target.matrix().allFinite() || !q_start.allFinite()) return out;
  JointVector& q = out.q;
  if (options.respect_limits) q = clamped(chain, q);
  Twist error = pose_error(target, forward_kinematics(chain, q));
  double damping = 0;  // set from J^T J at the first iteration
  double growth = 2;   // Nielsen's factor for the next rejected step
  for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
    if (error.head<3>().norm() <= options.target_position && error.tail<3>().norm() <= options.target_angle) break;
    ++out.iterations;
    // damped least squares: (J^T J + lambda I) dq = J^T e, at most max_step per joint
    const Mat6 jac = jacobian(chain, q);
    const Mat6 jtj = jac.transpose() * jac;
    const JointVector gradient = jac.transpose() * error;
    if (damping == 0) damping = std::max(kNumericIkDampingMin, kNumericIkDampingStart * jtj.diagonal().maxCoeff());
    JointVector step = limited_step(chain, q, jac, error, damping, options);
    const JointVector trial = q + step;
    const Twist trial_error = pose_error(target, forward_kinematics(chain, trial));
    // the gain ratio: the actual decrease of |e|^2 / 2 against the linear model's
    const double actual = 0.5 * (error.squaredNorm() - trial_error.squaredNorm());
    const double predicted = step.dot(gradient) - 0.5 * (jac * step).squaredNorm();
    const double rho = predicted > 0 ? actual / predicted : -1;
    if (trial.allFinite() && actual > 0 && rho > 0) {
      // a good step: less damping (towards Gauss-Newton), the more so the better the model was
      q = trial;
      error = trial_error;
      damping = std::max(kNumericIkDampingMin, damping * std::max(1.0 / 3, 1 - std::pow(2 * rho - 1, 3)));
      growth = 2;
    } else {
      // no progress: more damping (a shorter, more gradient-like step)
      damping *= growth;
      growth *= 2;
      if (damping > kNumericIkDampingMax) break;
    }
  }
  out.position_error = error.head<3>().norm();
  out.angle_error = error.tail<3>().norm();
  if (q.allFinite() && out.position_error <= kIkPositionTol && out.angle_error <= kIkAngleTol) {
    out.status = Status::kOk;
    return out;
  }
  // not a solution: is a joint limit in the way?
  out.status = Status::kNotConverged;
  if (options.respect_limits) {
    for (std::size_t i = 0; i < 6; ++i) {
      const JointSpec& joint = chain.joints[i];
      const double v = q[static_cast<Eigen::Index>(i)];
      if (v <= joint.lower + kOnLimit || v >= joint.upper - kOnLimit) {
        out.status = Status::kJointLimit;
        out.limit_joint = static_cast<int>(i);
        break;
      }
    }
  }
  return out;
}

}  // namespace blendbench
