#include "blendbench/robot/ik.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <utility>

#include "blendbench/core/format.hpp"
#include "blendbench/core/input_error.hpp"

namespace blendbench {
namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;
// Rounding allowance (rad) on joint limits.
constexpr double kLimitSlack = 1e-9;
// Polishing a closed-form branch against the chain: the damped least squares of numeric_ik
// from the closed form's angles, without limits (they are applied when choosing a branch), to
// well below the acceptance tolerance.
constexpr NumericIkOptions kPolish{500, 1e-14, 1e-14, std::numeric_limits<double>::infinity(), false};

// The representative value + 2 pi k nearest `near` inside [lower, upper] (+- kLimitSlack), or
// none. The distance to `near` is convex in k, so clamping the unconstrained best k into the
// admissible range gives the constrained best.
std::optional<double> wrap_within(double value, double near, double lower, double upper) {
  const double inf = std::numeric_limits<double>::infinity();
  const double k_min = std::isfinite(lower) ? std::ceil((lower - kLimitSlack - value) / kTwoPi) : -inf;
  const double k_max = std::isfinite(upper) ? std::floor((upper + kLimitSlack - value) / kTwoPi) : inf;
  if (k_min > k_max) return std::nullopt;
  return value + std::clamp(std::round((near - value) / kTwoPi), k_min, k_max) * kTwoPi;
}

std::string limit_text(const JointSpec& joint, double value) {
  return "joint '" + joint.name + "' would be at " + format_value(value) + " rad, limits [" + format_value(joint.lower) +
         ", " + format_value(joint.upper) + "]";
}

}  // namespace

std::string_view to_string(IkMethod method) {
  switch (method) {
    case IkMethod::kAuto: return "auto";
    case IkMethod::kClosedForm: return "closed_form";
    case IkMethod::kUrClosedForm: return "ur_closed_form";
    case IkMethod::kSphericalWristClosedForm: return "spherical_wrist_closed_form";
    case IkMethod::kNumeric: return "numeric";
  }
  return "?";
}

double branch_distance(const JointVector& a, const JointVector& b) {
  double sum = 0;
  for (std::size_t i = 0; i < 6; ++i) {
    const double d = a[static_cast<Eigen::Index>(i)] - b[static_cast<Eigen::Index>(i)];
    sum += kBranchWeights[i] * d * d;
  }
  return std::sqrt(sum);
}

IkSolver::IkSolver(KinematicChain chain, IkMethod method) : chain_(std::move(chain)) {
  if (chain_.joints.size() != 6) {
    throw InputError("", 0, 0, "urdf",
                     "the kinematic chain has " + std::to_string(chain_.joints.size()) + " joints, not 6");
  }
  // the first closed form whose pattern the chain follows, in the order of the header
  const auto use_ur = [&] {
    const UrFit fit = fit_ur(chain_);
    ur_ = fit.geometry;
    placement_ = fit.placement;
    method_ = IkMethod::kUrClosedForm;
  };
  const auto use_spherical = [&] {
    const SphericalWristFit fit = fit_spherical_wrist(chain_);
    spherical_ = fit.geometry;
    placement_ = fit.placement;
    method_ = IkMethod::kSphericalWristClosedForm;
  };
  switch (method) {
    case IkMethod::kUrClosedForm: use_ur(); break;
    case IkMethod::kSphericalWristClosedForm: use_spherical(); break;
    case IkMethod::kNumeric: method_ = IkMethod::kNumeric; break;
    case IkMethod::kAuto:
    case IkMethod::kClosedForm: {
      try {
        use_ur();
      } catch (const InputError& not_ur) {
        try {
          use_spherical();
        } catch (const InputError& not_spherical) {
          if (method == IkMethod::kClosedForm) {
            throw InputError("", 0, 0, "urdf",
                             "no closed-form IK fits the chain: " + not_ur.detail() + "; " + not_spherical.detail());
          }
          method_ = IkMethod::kNumeric;
        }
      }
      break;
    }
  }
  // where the DH model differs slightly from the chain, the closed form may have to accept
  // poses that much beyond the ideal model's reach
  reach_slack_ = std::max(kReachSlack, 10 * placement_.deviation);
}

const UrGeometry& IkSolver::geometry() const {
  assert(method_ == IkMethod::kUrClosedForm);
  return ur_;
}

const SphericalWristGeometry& IkSolver::spherical_geometry() const {
  assert(method_ == IkMethod::kSphericalWristClosedForm);
  return spherical_;
}

bool IkSolver::within_limits(const JointVector& q) const {
  for (std::size_t i = 0; i < 6; ++i) {
    const double v = q[static_cast<Eigen::Index>(i)];
    if (!(v >= chain_.joints[i].lower - kLimitSlack && v <= chain_.joints[i].upper + kLimitSlack)) return false;
  }
  return true;
}

bool IkSolver::polish(const Eigen::Isometry3d& tcp_pose, JointVector& q) const {
  const NumericIkResult polished = numeric_ik(chain_, tcp_pose, q, kPolish);
  q = polished.q;
  return polished.status == Status::kOk;
}

IkSolver::Branches IkSolver::branches(const Eigen::Isometry3d& tcp_pose, const JointVector& q_near) const {
  Branches out;
  if (method_ == IkMethod::kNumeric) {
    // the one solution the iteration from q_near reaches, limits ignored
    NumericIkOptions options;
    options.respect_limits = false;
    const NumericIkResult result = numeric_ik(chain_, tcp_pose, q_near, options);
    out.found = 1;
    if (result.status == Status::kOk) out.q.push_back(result.q);
    return out;
  }
  // closed form on the DH geometry for DH frame 6, then back to chain joint angles
  const Eigen::Isometry3d flange = placement_.base.inverse() * tcp_pose * placement_.tool.inverse();
  const JointVector theta_near = placement_.theta(q_near);
  const std::vector<JointVector> thetas = method_ == IkMethod::kUrClosedForm
                                              ? ur_closed_form_ik(ur_, flange, theta_near, reach_slack_)
                                              : spherical_closed_form_ik(spherical_, flange, theta_near, reach_slack_);
  out.found = thetas.size();
  for (const JointVector& theta : thetas) {
    JointVector q = placement_.q(theta);
    for (Eigen::Index i = 0; i < 6; ++i) q[i] = q_near[i] + std::remainder(q[i] - q_near[i], kTwoPi);
    if (polish(tcp_pose, q)) out.q.push_back(q);
  }
  std::stable_sort(out.q.begin(), out.q.end(), [&](const JointVector& a, const JointVector& b) {
    return branch_distance(a, q_near) < branch_distance(b, q_near);
  });
  return out;
}

std::vector<JointVector> IkSolver::solutions(const Eigen::Isometry3d& tcp_pose, const JointVector& q_near) const {
  if (!tcp_pose.matrix().allFinite() || !q_near.allFinite()) return {};
  return branches(tcp_pose, q_near).q;
}

IkSolver::Result IkSolver::solve_numeric(const Eigen::Isometry3d& tcp_pose, const JointVector& q_near) const {
  Result result;
  result.q = q_near;
  const NumericIkResult found = numeric_ik(chain_, tcp_pose, q_near);
  if (found.status == Status::kOk) {
    result.q = found.q;
    return result;
  }
  const std::string tail = " after " + std::to_string(found.iterations) + " iterations (remaining error " +
                           format_value(found.position_error * 1e3) + " mm, " + format_value(found.angle_error) + " rad)";
  if (found.status == Status::kJointLimit) {
    const JointSpec& joint = chain_.joints[static_cast<std::size_t>(found.limit_joint)];
    result.outcome = {Status::kJointLimit, "numeric IK stopped at joint '" + joint.name + "''s limit short of " +
                                               describe_pose(tcp_pose) + tail};
    return result;
  }
  result.outcome = {Status::kUnreachable, "numeric IK found no solution near the previous joint angles for " +
                                              describe_pose(tcp_pose) + tail +
                                              ": out of reach, or a singularity lies between"};
  return result;
}

IkSolver::Result IkSolver::solve(const Eigen::Isometry3d& tcp_pose, const JointVector& q_near) const {
  Result result;
  result.q = q_near;
  if (!tcp_pose.matrix().allFinite() || !q_near.allFinite()) {
    result.outcome = {Status::kUnreachable, "the pose or the previous joint angles are not finite"};
    return result;
  }
  if (method_ == IkMethod::kNumeric) return solve_numeric(tcp_pose, q_near);
  const Branches found = branches(tcp_pose, q_near);
  if (found.found == 0) {
    result.outcome = {Status::kUnreachable, "pose out of reach: " + describe_pose(tcp_pose)};
    return result;
  }
  if (found.q.empty()) {
    result.outcome = {Status::kSingular, "no IK branch converges (singular configuration) at " + describe_pose(tcp_pose)};
    return result;
  }

  // the nearest branch whose joints all have a representative within their limits
  double best = std::numeric_limits<double>::infinity();
  for (const JointVector& candidate : found.q) {
    JointVector q;
    bool inside = true;
    for (std::size_t i = 0; i < 6 && inside; ++i) {
      const auto k = static_cast<Eigen::Index>(i);
      const std::optional<double> v = wrap_within(candidate[k], q_near[k], chain_.joints[i].lower, chain_.joints[i].upper);
      inside = v.has_value();
      if (inside) q[k] = *v;
    }
    if (inside && branch_distance(q, q_near) < best) {
      best = branch_distance(q, q_near);
      result.q = q;
    }
  }
  if (std::isfinite(best)) return result;

  // name the joint that keeps the nearest branch outside its limits
  const JointVector& nearest = found.q.front();
  std::string which;
  for (std::size_t i = 0; i < 6 && which.empty(); ++i) {
    const JointSpec& joint = chain_.joints[i];
    const auto k = static_cast<Eigen::Index>(i);
    if (!wrap_within(nearest[k], q_near[k], joint.lower, joint.upper)) which = limit_text(joint, nearest[k]);
  }
  result.outcome = {Status::kJointLimit,
                    "every IK solution violates a joint limit at " + describe_pose(tcp_pose) + " (nearest: " + which + ")"};
  return result;
}

}  // namespace blendbench
