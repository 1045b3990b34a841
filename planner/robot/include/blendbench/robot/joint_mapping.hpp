#pragma once
// Maps a timed sequence of TCP poses (one per servo tick) to joint positions, velocities and
// accelerations, keeping the IK branch continuous and never clamping a joint silently.

#include <cstddef>
#include <vector>

#include "blendbench/robot/ik.hpp"
#include "blendbench/robot/joint_trajectory.hpp"
#include "blendbench/robot/singularity.hpp"
#include "blendbench/core/status.hpp"

namespace blendbench {

// Largest change of any joint between two consecutive samples (rad) that still counts as the
// same IK branch. At a 1 ms tick it corresponds to 500 rad/s, far beyond any real joint, so only
// a branch flip or a singularity crossing exceeds it.
inline constexpr double kMaxJointStep = 0.5;

// The joint reference of a tool path, one sample per TCP pose. On failure `outcome` says why and
// at which time, `failed_index` is the first pose that failed, joints.q holds the samples before
// it and joints.qd, joints.qdd are empty.
struct JointMapping {
  Outcome outcome;
  JointTrajectory joints;
  std::size_t failed_index = 0;
  std::vector<BranchChange> branch_changes;  // those allowed (JointMappingOptions)
};

struct JointMappingOptions {
  // Whether the reference may change IK branch (singularity.hpp: cross a singularity with
  // continuous joints); the changes are then listed in JointMapping::branch_changes.
  bool allow_branch_change = false;
};

// IK of every pose, each seeded with the previous solution so the branch stays continuous (the
// first pose takes the branch nearest q_seed, however far). Stops at the first pose that is
//   kUnreachable  out of reach (or the pose is not finite),
//   kJointLimit   reachable on the continuous branch only outside a joint limit,
//   kSingular     reachable only by a jump of more than kMaxJointStep in some joint (a branch
//                 flip or a singularity crossing), or not solvable to tolerance, or (unless
//                 options allow it) the first change of IK branch (branch_changes), failed_index
//                 its sample,
// with a message naming the time (index * dt, s) and the pose (mm, deg). qd and qdd are
// second-order finite differences: central inside, one-sided three- and four-point stencils at
// the ends (exact for quadratic and cubic motion respectively, so a path that starts and ends at
// rest gives qd, qdd near zero there). Throws InputError (field "dt") unless dt > 0 and finite.
JointMapping map_to_joints(const IkSolver& ik, const std::vector<Eigen::Isometry3d>& tcp_poses, double dt,
                           const JointVector& q_seed, const JointMappingOptions& options = {});

}  // namespace blendbench
