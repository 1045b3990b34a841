// Numeric IK (numeric_ik.hpp): agrees with both closed forms at random reachable poses when
// seeded near a closed-form branch, keeps to the joint limits, fails cleanly, and drives the
// IkSolver of a chain no closed form fits.

#include "blendbench/robot/numeric_ik.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <numbers>

#include "blendbench/io/urdf_chain.hpp"
#include "blendbench/robot/ik.hpp"
#include "blendbench/robot/joint_mapping.hpp"
#include "blendbench/robot/singularity.hpp"
#include "support/property.hpp"

namespace blendbench {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kPoseTol = 1e-9;       // m and rad: FK(numeric IK) against the pose
constexpr double kSameBranch = 1e-6;    // rad: the numeric solution is the closed form's branch
constexpr double kSeedDistance = 0.05;  // rad per joint: "near the branch"
// Away from every singularity by this much (the closed forms' measures) the branches lie far
// apart, so a seed kSeedDistance from one can only converge to it. At 0.1 they did not: the
// elbow's mirrored branch lies 2 q3 away, 0.2 rad at a sine of 0.1, and a seed up to 0.05 rad
// off on every joint converged to it (seed 51 at BLENDBENCH_PROPERTY_SEED=70000000, 20x, case
// 4054: q3 = 0.101, the solution 0.202 rad away); others there failed. At 0.2 the mirror is
// 0.4 rad away: over 10 offsets at 20x (360,000 solves, 61-72 % of them clear) every clear
// solve converged to its seed's branch.
constexpr double kClear = 0.2;

JointVector random_q_within(const KinematicChain& chain, std::mt19937_64& rng) {
  JointVector q;
  for (Eigen::Index i = 0; i < 6; ++i) {
    const JointSpec& joint = chain.joints[static_cast<std::size_t>(i)];
    q[i] = test::uniform(rng, std::max(joint.lower, -2 * kPi), std::min(joint.upper, 2 * kPi));
  }
  return q;
}

bool clear_of_singularities(const IkSolver& ik, const JointVector& q) {
  for (const SingularityMeasure& m : singularity_measures(ik, q)) {
    const double scale = m.kind == SingularityKind::kShoulder ? m.threshold / kShoulderShare : 1.0;
    if (std::abs(m.value) < kClear * scale) return false;
  }
  return true;
}

// For every arm with a closed form: random configurations within the limits, every closed-form
// branch within the limits, numeric IK from a seed up to kSeedDistance away on every joint.
TEST(NumericIk, AgreesWithBothClosedFormsWhenSeededNearTheBranch) {
  for (const char* model : {"models/ur5e_like.urdf", "models/kr6_like.urdf"}) {
    SCOPED_TRACE(model);
    const KinematicChain chain = load_urdf_chain(test::source_path(model));
    const IkSolver closed(chain);
    ASSERT_NE(closed.method(), IkMethod::kNumeric);
    const std::uint64_t seed = 51;
    auto rng = test::make_rng(seed);
    double max_pos = 0, max_angle = 0, max_joint = 0, agreement_pos = 0, agreement_angle = 0;
    long iterations = 0, solves = 0, clear = 0, near_failures = 0;
    int max_iterations = 0;
    const int cases = test::property_cases(300);
    for (int n = 0; n < cases; ++n) {
      const JointVector q = random_q_within(chain, rng);
      const Eigen::Isometry3d pose = forward_kinematics(chain, q);
      for (const JointVector& branch : closed.solutions(pose, q)) {
        if (!closed.within_limits(branch)) continue;
        JointVector start = branch;
        for (Eigen::Index i = 0; i < 6; ++i) start[i] += test::uniform(rng, -kSeedDistance, kSeedDistance);
        const NumericIkResult r = numeric_ik(chain, pose, start);
        const bool clear_branch = clear_of_singularities(closed, branch);
        if (r.status != Status::kOk && !clear_branch) {
          // Near a singularity the iteration may leave the seed's branch: at 20x the cases
          // (seed 51, case 2489, UR) a seed 0.05 rad from a branch 0.07 from the wrist
          // singularity and 0.09 rad inside q4's limit flowed across the elbow to a mirrored
          // solution that needs q4 beyond its limit, and stopped on the limit (3e-4 m short; a
          // smaller max_step flows there too). A local solver promises no more there: the
          // failure must be a clean one, within the limits, and rare.
          ASSERT_TRUE(r.status == Status::kJointLimit || r.status == Status::kNotConverged)
              << test::seed_text(seed) << " case " << n;
          ASSERT_TRUE(r.q.allFinite() && closed.within_limits(r.q)) << test::seed_text(seed) << " case " << n;
          ++near_failures;
          continue;
        }
        ASSERT_EQ(r.status, Status::kOk) << test::seed_text(seed) << " case " << n << " branch " << branch.transpose();
        const Twist error = pose_error(pose, forward_kinematics(chain, r.q));
        const Twist agreement = pose_error(forward_kinematics(chain, branch), forward_kinematics(chain, r.q));
        ASSERT_LE(error.head<3>().norm(), kPoseTol) << test::seed_text(seed) << " case " << n;
        ASSERT_LE(error.tail<3>().norm(), kPoseTol) << test::seed_text(seed) << " case " << n;
        max_pos = std::max(max_pos, error.head<3>().norm());
        max_angle = std::max(max_angle, error.tail<3>().norm());
        agreement_pos = std::max(agreement_pos, agreement.head<3>().norm());
        agreement_angle = std::max(agreement_angle, agreement.tail<3>().norm());
        if (clear_branch) {
          ++clear;
          const double joint = (r.q - branch).cwiseAbs().maxCoeff();
          max_joint = std::max(max_joint, joint);
          ASSERT_LE(joint, kSameBranch) << test::seed_text(seed) << " case " << n << " branch " << branch.transpose();
        }
        ++solves;
        iterations += r.iterations;
        max_iterations = std::max(max_iterations, r.iterations);
      }
    }
    // most solves start clear of the singularities, so the branch check is not vacuous
    EXPECT_GT(clear, solves / 2);
    // the failures near a singularity are rare: over 10 offsets at 20x, 1-5 (mean 2.7) of
    // about 19,500 solves on the UR and 0-2 of 16,600 on the KR 6, about 1.4e-4; allowed, two
    // and one in 2,000 (so that the bound holds at any case count: a Poisson count of that mean
    // passes it but for about 3e-5 of offsets at 20x, 4e-4 at 1x)
    EXPECT_LE(near_failures, 2 + (solves + near_failures) / 2000)
        << near_failures << " failures near a singularity; " << test::seed_text(seed);
    std::cout << model << ": " << solves << " numeric solves over " << cases << " poses: pose error max " << max_pos
              << " m, " << max_angle << " rad; against the closed form " << agreement_pos << " m, " << agreement_angle
              << " rad, joints " << max_joint << " rad (" << clear << " clear of singularities); iterations mean "
              << static_cast<double>(iterations) / static_cast<double>(solves) << ", max " << max_iterations << "; "
              << near_failures << " failed near a singularity\n";
  }
}

TEST(NumericIk, StopsAtAJointLimitInsteadOfCrossingIt) {
  KinematicChain chain = load_urdf_chain(test::source_path("models/kr6_like.urdf"));
  const JointVector q = (JointVector() << 0.2, -1.2, 1.3, 0.3, 1.2, 0.4).finished();
  const Eigen::Isometry3d pose = forward_kinematics(chain, q);
  // the wrist's upper limit below the pose's q5
  chain.joints[4].upper = 1.0;
  JointVector start = q;
  start[4] = 0.9;
  const NumericIkResult r = numeric_ik(chain, pose, start);
  EXPECT_EQ(r.status, Status::kJointLimit);
  EXPECT_EQ(r.limit_joint, 4);
  EXPECT_LE(r.q[4], 1.0);
  EXPECT_TRUE(r.q.allFinite());
  // without the limits it gets there
  NumericIkOptions free;
  free.respect_limits = false;
  EXPECT_EQ(numeric_ik(chain, pose, start, free).status, Status::kOk);
}

TEST(NumericIk, FailsCleanlyOutOfReachAndOnBadInput) {
  const KinematicChain chain = load_urdf_chain(test::source_path("models/kr6_like.urdf"));
  const JointVector start = (JointVector() << 0, -kPi / 2, kPi / 2, 0, kPi / 2, 0).finished();
  Eigen::Isometry3d far = forward_kinematics(chain, start);
  far.translation() = Vec3(2.5, 0, 0.5);
  NumericIkOptions options;
  options.max_iterations = 40;
  const NumericIkResult r = numeric_ik(chain, far, start, options);
  EXPECT_NE(r.status, Status::kOk);
  EXPECT_LE(r.iterations, 40);
  EXPECT_TRUE(r.q.allFinite());
  EXPECT_GT(r.position_error, 0.5);
  Eigen::Isometry3d bad = far;
  bad.translation().x() = std::nan("");
  const NumericIkResult nan = numeric_ik(chain, bad, start);
  EXPECT_EQ(nan.status, Status::kNotConverged);
  EXPECT_EQ(nan.iterations, 0);
  EXPECT_EQ(nan.q, start);
}

// A chain no closed form fits (the KR 6 class with its flange axis 20 mm off the wrist centre):
// the IkSolver falls back to the numeric solver, which follows a path continuously and exactly.
TEST(NumericIk, SolvesAChainWithoutAClosedFormAlongAPath) {
  KinematicChain chain = spherical_chain(SphericalWristGeometry{0.4, 0.025, 0.455, 0.0, 0.035, 0.42, 0.08});
  chain.joints[5].origin = chain.joints[5].origin * Eigen::Translation3d(0.02, 0, 0);
  const IkSolver ik(chain);
  ASSERT_EQ(ik.method(), IkMethod::kNumeric);
  // a smooth joint motion's poses, 2 ms apart, from a start 0.1 rad off the first sample; the
  // motion stays clear of the chain's singularities (further on, at s = 0.96, it would cross one)
  std::vector<Eigen::Isometry3d> poses;
  std::vector<JointVector> truth;
  for (int k = 0; k <= 500; ++k) {
    const double s = 0.4 * k / 500.0;
    const JointVector q = (JointVector() << 0.3 * s, 0.8 - 0.4 * s, 1.2 + 0.3 * s, 0.2, 0.9 - 0.5 * s, 0.5 * s).finished();
    ASSERT_GT(std::abs(singularity_measures(ik, q).front().value), kJacobianRatio) << k;
    truth.push_back(q);
    poses.push_back(forward_kinematics(chain, q));
  }
  const JointVector seed = truth.front() + JointVector::Constant(0.1);
  const JointMapping mapping = map_to_joints(ik, poses, 0.002, seed);
  ASSERT_TRUE(mapping.outcome.ok()) << mapping.outcome.message;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const Twist error = pose_error(poses[k], forward_kinematics(chain, mapping.joints.q[k]));
    ASSERT_LE(error.head<3>().norm(), kPoseTol) << k;
    ASSERT_LE(error.tail<3>().norm(), kPoseTol) << k;
    ASSERT_LE((mapping.joints.q[k] - truth[k]).cwiseAbs().maxCoeff(), kSameBranch) << k;
  }
}

}  // namespace
}  // namespace blendbench
