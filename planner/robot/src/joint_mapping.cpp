#include "blendbench/robot/joint_mapping.hpp"

#include <cmath>
#include <cstdio>
#include <string>
#include <utility>

#include "blendbench/core/format.hpp"
#include "blendbench/core/input_error.hpp"

namespace blendbench {
namespace {

std::string time_text(std::size_t index, double dt) {
  char text[48];
  std::snprintf(text, sizeof text, "t = %.6g s", static_cast<double>(index) * dt);
  return text;
}

// The joint that moves most from `a` to `b`, and by how much (rad).
std::pair<std::size_t, double> largest_step(const JointVector& a, const JointVector& b) {
  Eigen::Index k = 0;
  const double step = (b - a).cwiseAbs().maxCoeff(&k);
  return {static_cast<std::size_t>(k), step};
}

// Second-order finite differences of q (see map_to_joints).
void differentiate(JointTrajectory& traj) {
  const std::vector<JointVector>& q = traj.q;
  const std::size_t n = q.size();
  const double dt = traj.dt;
  traj.qd.assign(n, JointVector::Zero());
  traj.qdd.assign(n, JointVector::Zero());
  if (n < 2) return;
  if (n == 2) {
    traj.qd[0] = traj.qd[1] = (q[1] - q[0]) / dt;
    return;
  }
  // velocity: central inside, three-point one-sided at the ends
  for (std::size_t i = 1; i + 1 < n; ++i) traj.qd[i] = (q[i + 1] - q[i - 1]) / (2 * dt);
  traj.qd[0] = (-3 * q[0] + 4 * q[1] - q[2]) / (2 * dt);
  traj.qd[n - 1] = (3 * q[n - 1] - 4 * q[n - 2] + q[n - 3]) / (2 * dt);
  // acceleration: central inside, four-point one-sided at the ends (constant for three samples)
  for (std::size_t i = 1; i + 1 < n; ++i) traj.qdd[i] = (q[i + 1] - 2 * q[i] + q[i - 1]) / (dt * dt);
  if (n == 3) {
    traj.qdd[0] = traj.qdd[2] = traj.qdd[1];
    return;
  }
  traj.qdd[0] = (2 * q[0] - 5 * q[1] + 4 * q[2] - q[3]) / (dt * dt);
  traj.qdd[n - 1] = (2 * q[n - 1] - 5 * q[n - 2] + 4 * q[n - 3] - q[n - 4]) / (dt * dt);
}

}  // namespace

JointMapping map_to_joints(const IkSolver& ik, const std::vector<Eigen::Isometry3d>& tcp_poses, double dt,
                           const JointVector& q_seed, const JointMappingOptions& options) {
  if (!(dt > 0) || !std::isfinite(dt)) {
    throw InputError("", 0, 0, "dt", "the servo period must be positive and finite, got " + format_value(dt) + " s");
  }
  JointMapping mapping;
  JointTrajectory& traj = mapping.joints;
  traj.dt = dt;
  traj.q.reserve(tcp_poses.size());
  const auto fail = [&](std::size_t index, Status status, const std::string& what) {
    mapping.outcome = {status, time_text(index, dt) + ": " + what};
    mapping.failed_index = index;
    return mapping;
  };

  JointVector previous = q_seed;
  for (std::size_t i = 0; i < tcp_poses.size(); ++i) {
    const Eigen::Isometry3d& pose = tcp_poses[i];
    const IkSolver::Result solved = ik.solve(pose, previous);
    // the first sample may pick any branch; later ones must continue the previous one
    if (solved.outcome.ok() && (i == 0 || largest_step(previous, solved.q).second <= kMaxJointStep)) {
      traj.q.push_back(solved.q);
      previous = solved.q;
      continue;
    }
    if (solved.outcome.status == Status::kUnreachable || i == 0) {
      return fail(i, solved.outcome.status, solved.outcome.message);
    }
    // the continuous branch (limits ignored) tells a joint limit from a branch flip
    const std::vector<JointVector> branches = ik.solutions(pose, previous);
    if (!branches.empty() && largest_step(previous, branches.front()).second <= kMaxJointStep &&
        !ik.within_limits(branches.front())) {
      for (std::size_t j = 0; j < 6; ++j) {
        const JointSpec& joint = ik.chain().joints[j];
        const double v = branches.front()[static_cast<Eigen::Index>(j)];
        if (v < joint.lower || v > joint.upper) {
          return fail(i, Status::kJointLimit,
                      "joint '" + joint.name + "' would reach " + format_value(v) + " rad, outside its limits [" +
                          format_value(joint.lower) + ", " + format_value(joint.upper) + "] rad, at " + describe_pose(pose));
        }
      }
    }
    if (!solved.outcome.ok()) return fail(i, solved.outcome.status, solved.outcome.message);
    const auto [joint, step] = largest_step(previous, solved.q);
    return fail(i, Status::kSingular,
                "IK branch flip: joint '" + ik.chain().joints[joint].name + "' jumps by " + format_value(step) +
                    " rad in one sample (more than " + format_value(kMaxJointStep) + " rad) at " + describe_pose(pose) +
                    "; the path crosses a singularity or leaves the reachable branch");
  }

  // a continuous crossing of a singularity changes the branch: an error unless allowed
  mapping.branch_changes = branch_changes(ik, traj.q, dt);
  if (!mapping.branch_changes.empty() && !options.allow_branch_change) {
    const BranchChange change = mapping.branch_changes.front();
    traj.q.resize(change.index);
    const std::size_t index = change.index;
    const std::string kind(to_string(change.kind));
    mapping.branch_changes.clear();
    return fail(index, Status::kSingular,
                "IK branch change: the " + kind + " measure changes sign (" + format_value(change.before) + " -> " +
                    format_value(change.after) + ") at " + describe_pose(change.pose) + ", the path crosses a " + kind +
                    " singularity; robot.allow_branch_change: true lets it through (reported)");
  }
  differentiate(traj);
  return mapping;
}

}  // namespace blendbench
