#include "blendbench/robot/ik.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <numbers>
#include <string>
#include <vector>

#include "support/input_error.hpp"
#include "support/property.hpp"
#include "blendbench/core/input_error.hpp"
#include "blendbench/io/urdf_chain.hpp"
#include "blendbench/robot/singularity.hpp"

namespace blendbench {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kRoundTripPos = 1e-9;    // m, FK(IK(pose)) against pose
constexpr double kRoundTripAngle = 1e-9;  // rad
constexpr double kSameQ = 1e-6;           // rad, IK returns the configuration the pose came from
constexpr double kPathStep = 0.01;        // rad per sample on a 1 mm-spaced path, away from singularities
constexpr UrGeometry kUr5e{0.1625, -0.425, -0.3922, 0.1333, 0.0997, 0.0996};
// The model's ready configuration: facing +x, elbow up, tool down (models/ur5e_like.urdf).
const JointVector kReady = (JointVector() << kPi, -kPi / 2, kPi / 2, -kPi / 2, -kPi / 2, 0).finished();

KinematicChain model_chain() { return load_urdf_chain(test::source_path("models/ur5e_like.urdf")); }

JointVector random_q_within(const KinematicChain& chain, std::mt19937_64& rng) {
  JointVector q;
  for (Eigen::Index i = 0; i < 6; ++i) {
    const JointSpec& joint = chain.joints[static_cast<std::size_t>(i)];
    q[i] = test::uniform(rng, joint.lower, joint.upper);
  }
  return q;
}

JointVector perturbed(const JointVector& q, std::mt19937_64& rng, double size) {
  JointVector out = q;
  for (Eigen::Index i = 0; i < 6; ++i) out[i] += test::uniform(rng, -size, size);
  return out;
}

Eigen::Isometry3d tool_down_at(const Vec3& p) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(kPi, Vec3::UnitX()).toRotationMatrix();  // z down, x forward
  pose.translation() = p;
  return pose;
}

// Smallest singular value of the Jacobian: how far q is from every singularity.
double conditioning(const KinematicChain& chain, const JointVector& q) {
  return Eigen::JacobiSVD<Mat6>(jacobian(chain, q)).singularValues()[5];
}

JointVector wrapped_difference(const JointVector& a, const JointVector& b) {
  JointVector d;
  for (Eigen::Index i = 0; i < 6; ++i) d[i] = std::remainder(a[i] - b[i], 2 * kPi);
  return d;
}

TEST(Ik, FindsThePublishedDhGeometryInTheUrdf) {
  const IkSolver ik(model_chain());
  EXPECT_NEAR(ik.geometry().d1, kUr5e.d1, 1e-12);
  EXPECT_NEAR(ik.geometry().a2, kUr5e.a2, 1e-12);
  EXPECT_NEAR(ik.geometry().a3, kUr5e.a3, 1e-12);
  EXPECT_NEAR(ik.geometry().d4, kUr5e.d4, 1e-12);
  EXPECT_NEAR(ik.geometry().d5, kUr5e.d5, 1e-12);
  EXPECT_NEAR(ik.geometry().d6, kUr5e.d6, 1e-12);
}

TEST(Ik, EveryClosedFormBranchSatisfiesForwardKinematics) {
  const std::uint64_t seed = 21;
  auto rng = test::make_rng(seed);
  int eight = 0;
  const int cases = test::property_cases(500);
  for (int n = 0; n < cases; ++n) {
    JointVector theta;
    for (Eigen::Index i = 0; i < 6; ++i) theta[i] = test::uniform(rng, -kPi, kPi);
    const Eigen::Isometry3d flange = ur_forward_kinematics(kUr5e, theta);
    const std::vector<JointVector> branches = ur_closed_form_ik(kUr5e, flange, theta);
    ASSERT_FALSE(branches.empty()) << test::seed_text(seed) << " case " << n;
    ASSERT_LE(branches.size(), 8u);
    eight += branches.size() == 8 ? 1 : 0;
    bool found_original = false;
    for (const JointVector& branch : branches) {
      ASSERT_TRUE(branch.allFinite());
      const Twist error = pose_error(flange, ur_forward_kinematics(kUr5e, branch));
      ASSERT_LT(error.head<3>().norm(), kRoundTripPos) << test::seed_text(seed) << " case " << n;
      ASSERT_LT(error.tail<3>().norm(), kRoundTripAngle) << test::seed_text(seed) << " case " << n;
      found_original = found_original || wrapped_difference(branch, theta).norm() < kSameQ;
    }
    EXPECT_TRUE(found_original) << test::seed_text(seed) << " case " << n << " q " << theta.transpose();
  }
  // most random poses are reachable on all eight branches
  EXPECT_GT(eight, cases / 2);
}

TEST(Ik, HandPickedPoseHasEightDistinctBranches) {
  const JointVector theta = (JointVector() << 0.3, -1.2, 1.5, -1.9, -1.4, 0.6).finished();
  const std::vector<JointVector> branches = ur_closed_form_ik(kUr5e, ur_forward_kinematics(kUr5e, theta));
  ASSERT_EQ(branches.size(), 8u);
  for (std::size_t i = 0; i < 8; ++i) {
    for (std::size_t j = i + 1; j < 8; ++j) {
      EXPECT_GT(wrapped_difference(branches[i], branches[j]).norm(), 0.1) << i << " " << j;
    }
  }
}

TEST(Ik, RoundTripAtRandomReachablePoses) {
  const KinematicChain chain = model_chain();
  const IkSolver ik(chain);
  const std::uint64_t seed = 22;
  auto rng = test::make_rng(seed);
  double max_pos = 0;
  double max_angle = 0;
  for (int n = 0; n < test::property_cases(2000); ++n) {
    const JointVector q = random_q_within(chain, rng);
    const JointVector q_near = perturbed(q, rng, 0.05);
    const Eigen::Isometry3d pose = forward_kinematics(chain, q);
    const IkSolver::Result result = ik.solve(pose, q_near);
    ASSERT_TRUE(result.outcome.ok()) << test::seed_text(seed) << " case " << n << ": " << result.outcome.message;
    const Twist error = pose_error(pose, forward_kinematics(chain, result.q));
    max_pos = std::max(max_pos, error.head<3>().norm());
    max_angle = std::max(max_angle, error.tail<3>().norm());
    ASSERT_LT(error.head<3>().norm(), kRoundTripPos) << test::seed_text(seed) << " case " << n;
    ASSERT_LT(error.tail<3>().norm(), kRoundTripAngle) << test::seed_text(seed) << " case " << n;
    ASSERT_TRUE(ik.within_limits(result.q));
    // away from singularities the branch nearest the perturbed seed is the original one
    if (conditioning(chain, q) > 0.02) {
      ASSERT_LT((result.q - q).cwiseAbs().maxCoeff(), kSameQ)
          << test::seed_text(seed) << " case " << n << "\n q " << q.transpose() << "\n ik " << result.q.transpose();
    }
  }
  std::cout << "IK round trip maxima: " << max_pos << " m, " << max_angle << " rad\n";
  RecordProperty("max_position_error_m", std::to_string(max_pos));
  RecordProperty("max_angle_error_rad", std::to_string(max_angle));
}

TEST(Ik, WrapsEachJointToTheRepresentativeNearestTheSeedWithinLimits) {
  // only one wrist and one shoulder branch admissible, so the choice is about wrapping alone
  KinematicChain chain = model_chain();
  chain.joints[0].lower = -1.0;
  chain.joints[0].upper = 1.0;
  chain.joints[4].lower = -kPi;
  chain.joints[4].upper = 0.0;
  const IkSolver ik(chain);
  const JointVector q = (JointVector() << 0.3, -1.2, 1.5, -1.9, -1.4, -1.0).finished();
  // seed one turn up on wrist 3: -1 + 2 pi lies within +-2 pi and is nearest
  JointVector near = q;
  near[5] += 2 * kPi;
  EXPECT_NEAR(ik.solve(forward_kinematics(chain, q), near).q[5], -1.0 + 2 * kPi, kSameQ);
  // seed almost one turn up from +1: 1 + 2 pi is outside the limit, so 1 is the nearest
  // admissible value
  JointVector q2 = q;
  q2[5] = 1.0;
  near = q2;
  near[5] += 2 * kPi - 0.1;
  EXPECT_NEAR(ik.solve(forward_kinematics(chain, q2), near).q[5], 1.0, kSameQ);
}

TEST(Ik, PosesBeyondReachAreUnreachableNotNan) {
  const IkSolver ik(model_chain());
  const JointVector near = (JointVector() << 0, -1.5, 1.5, -1.5, -1.5, 0).finished();
  // far beyond the stretched arm (about 0.95 m)
  for (const Vec3& p : {Vec3(2, 0, 0.5), Vec3(0.7, 0.7, 0.4), Vec3(0, 0, 1.2)}) {
    const IkSolver::Result result = ik.solve(tool_down_at(p), near);
    EXPECT_EQ(result.outcome.status, Status::kUnreachable) << p.transpose();
    EXPECT_NE(result.outcome.message.find("mm"), std::string::npos) << result.outcome.message;
    EXPECT_TRUE(result.q.allFinite());
    EXPECT_EQ(result.q, near);
  }
  // the wrist centre on the base axis: inside the cylinder of radius d4 the shoulder cannot reach
  EXPECT_EQ(ik.solve(tool_down_at(Vec3(0, 0, 0.5)), near).outcome.status, Status::kUnreachable);
  // a non-finite pose
  Eigen::Isometry3d bad = tool_down_at(Vec3(0.5, 0, 0.2));
  bad.translation().x() = std::nan("");
  EXPECT_EQ(ik.solve(bad, near).outcome.status, Status::kUnreachable);
}

TEST(Ik, WristSingularPoseKeepsWrist3AtItsPreviousValue) {
  const KinematicChain chain = model_chain();
  const IkSolver ik(chain);
  // q5 = 0: axes 2, 3, 4 and 6 are parallel and only q2, q3, q4, q6 together are determined;
  // in the middle of the workspace the elbow reaches with the seed's q6, which is kept
  const JointVector q = (JointVector() << 0.3, -1.2, 1.5, -1.9, 0.0, 0.6).finished();
  JointVector near = q;
  near[5] += 0.3;
  const IkSolver::Result result = ik.solve(forward_kinematics(chain, q), near);
  ASSERT_TRUE(result.outcome.ok()) << result.outcome.message;
  EXPECT_NEAR(result.q[5], near[5], kSameQ);
  EXPECT_LT(pose_error(forward_kinematics(chain, q), forward_kinematics(chain, result.q)).norm(), kRoundTripPos);
}

TEST(Ik, WristSingularPosesHaveFiniteSolutionsEverywhere) {
  const KinematicChain chain = model_chain();
  const IkSolver ik(chain);
  const std::uint64_t seed = 23;
  auto rng = test::make_rng(seed);
  int singular_branch = 0;
  const int cases = test::property_cases(300);
  for (int n = 0; n < cases; ++n) {
    JointVector q = random_q_within(chain, rng);
    q[4] = n % 2 == 0 ? 0.0 : kPi;  // z6 parallel or antiparallel to axis 2
    const Eigen::Isometry3d pose = forward_kinematics(chain, q);
    const JointVector near = perturbed(q, rng, 0.05);
    const IkSolver::Result result = ik.solve(pose, near);
    ASSERT_TRUE(result.outcome.ok()) << test::seed_text(seed) << " case " << n << ": " << result.outcome.message;
    ASSERT_TRUE(result.q.allFinite());
    const Twist error = pose_error(pose, forward_kinematics(chain, result.q));
    ASSERT_LT(error.head<3>().norm(), kRoundTripPos) << test::seed_text(seed) << " case " << n;
    ASSERT_LT(error.tail<3>().norm(), kRoundTripAngle) << test::seed_text(seed) << " case " << n;
    // on the singular branch the free q6 is the seed's, or, where the elbow cannot reach with
    // that, the nearest one it can reach with: never farther from the seed than the original.
    // Not checked within 0.1 mm of the shoulder singularity, where rounding in q1 (~1e-16 over
    // that distance) exceeds the wrist threshold and q6 is exact but arbitrary.
    const Vec3 p5 = pose.translation() - kUr5e.d6 * pose.linear().col(2);
    const double shoulder_distance = std::sqrt(std::max(0.0, p5.head<2>().squaredNorm() - kUr5e.d4 * kUr5e.d4));
    if (std::abs(std::sin(result.q[4])) < 1e-6 && shoulder_distance > 1e-4) {
      EXPECT_LE(std::abs(std::remainder(result.q[5] - near[5], 2 * kPi)),
                std::abs(std::remainder(q[5] - near[5], 2 * kPi)) + kSameQ)
          << test::seed_text(seed) << " case " << n;
      ++singular_branch;
    }
  }
  // mostly the singular branch itself is the nearest
  EXPECT_GT(singular_branch, cases / 2);
}

TEST(Ik, ShoulderAndElbowSingularPosesHaveFiniteSolutions) {
  const KinematicChain chain = model_chain();
  const IkSolver ik(chain);
  // shoulder: with theta234 = 0 the wrist centre lies on the cylinder of radius d4 around axis 1
  // when a2 cos t2 + a3 cos(t2 + t3) = 0, i.e. tan t2 = (a2 + a3 cos t3) / (a3 sin t3)
  const double t3 = 0.5;
  const double t2 = std::atan((kUr5e.a2 + kUr5e.a3 * std::cos(t3)) / (kUr5e.a3 * std::sin(t3)));
  const JointVector shoulder = (JointVector() << 0.4, t2, t3, -t2 - t3, 1.0, 0.3).finished();
  // elbow fully stretched and fully folded (the elbow limit is +-pi)
  const JointVector stretched = (JointVector() << 0.4, -1.0, 0.0, -1.2, 1.0, 0.3).finished();
  const JointVector folded = (JointVector() << 0.4, -1.0, kPi, -1.2, 1.0, 0.3).finished();
  for (const JointVector& q : {shoulder, stretched, folded}) {
    const Eigen::Isometry3d pose = forward_kinematics(chain, q);
    const IkSolver::Result result = ik.solve(pose, q);
    ASSERT_TRUE(result.outcome.ok()) << q.transpose() << ": " << result.outcome.message;
    const Twist error = pose_error(pose, forward_kinematics(chain, result.q));
    EXPECT_LT(error.head<3>().norm(), kRoundTripPos) << q.transpose();
    EXPECT_LT(error.tail<3>().norm(), kRoundTripAngle) << q.transpose();
    EXPECT_LT((result.q - q).cwiseAbs().maxCoeff(), 1e-6) << q.transpose() << "\n" << result.q.transpose();
  }
}

TEST(Ik, LineAndCircleToolDownAreContinuous) {
  const KinematicChain chain = model_chain();
  const IkSolver ik(chain);
  std::vector<Eigen::Isometry3d> poses;
  // a 0.72 m diagonal line at 0.2 m height, then a circle of radius 0.15 m, 1 mm apart or less
  for (int i = 0; i <= 720; ++i) poses.push_back(tool_down_at(Vec3(0.3 + 0.4 * i / 720.0, -0.3 + 0.6 * i / 720.0, 0.2)));
  for (int i = 0; i <= 1000; ++i) {
    const double phi = 2 * kPi * i / 1000.0;
    poses.push_back(tool_down_at(Vec3(0.5 + 0.15 * std::cos(phi), 0.15 * std::sin(phi), 0.3)));
  }
  JointVector previous = kReady;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const IkSolver::Result result = ik.solve(poses[i], previous);
    ASSERT_TRUE(result.outcome.ok()) << i << ": " << result.outcome.message;
    const Twist error = pose_error(poses[i], forward_kinematics(chain, result.q));
    ASSERT_LT(error.norm(), kRoundTripPos) << i;
    // the line starts far from the seed; from there every step is small
    if (i > 0 && i != 721) {
      ASSERT_LT((result.q - previous).cwiseAbs().maxCoeff(), kPathStep) << "sample " << i;
    }
    previous = result.q;
  }
}

// A UR-type chain written differently: base moved and tilted, joint 2 and 5 axes flipped, the
// zero of joint 3 moved by 0.4 rad, and a tool 0.15 m out with a small offset and tilt.
KinematicChain disguised_chain() {
  KinematicChain chain = ur_chain(kUr5e);
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
  base.translation() = Vec3(0.1, -0.2, 0.05);
  base.linear() = Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  chain.joints[0].origin = base * chain.joints[0].origin;
  chain.joints[1].axis = -Vec3::UnitZ();
  chain.joints[4].axis = -Vec3::UnitZ();
  chain.joints[2].origin = chain.joints[2].origin * Eigen::AngleAxisd(0.4, Vec3::UnitZ());
  chain.joints[3].origin = chain.joints[3].origin * Eigen::AngleAxisd(-0.4, Vec3::UnitZ());
  Eigen::Isometry3d tool = Eigen::Isometry3d::Identity();
  tool.translation() = Vec3(0.01, -0.02, 0.15);
  tool.linear() = Eigen::AngleAxisd(0.3, Vec3::UnitX()).toRotationMatrix();
  chain.tcp = chain.tcp * tool;
  return chain;
}

TEST(Ik, SolvesAnyPlacementOfTheUrGeometry) {
  const KinematicChain chain = disguised_chain();
  const IkSolver ik(chain);
  const std::uint64_t seed = 24;
  auto rng = test::make_rng(seed);
  for (int n = 0; n < test::property_cases(300); ++n) {
    const JointVector q = random_q_within(chain, rng);
    const Eigen::Isometry3d pose = forward_kinematics(chain, q);
    const IkSolver::Result result = ik.solve(pose, perturbed(q, rng, 0.05));
    ASSERT_TRUE(result.outcome.ok()) << test::seed_text(seed) << " case " << n << ": " << result.outcome.message;
    const Twist error = pose_error(pose, forward_kinematics(chain, result.q));
    ASSERT_LT(error.head<3>().norm(), kRoundTripPos) << test::seed_text(seed) << " case " << n;
    ASSERT_LT(error.tail<3>().norm(), kRoundTripAngle) << test::seed_text(seed) << " case " << n;
  }
}

TEST(Ik, PolishingAbsorbsASmallDeviationFromTheUrPattern) {
  // axis 6 tilted by 2e-7 rad and moved by 3e-7 m: still accepted, still exact. Within a
  // singularity's threshold (singularity.hpp) the polishing may find no solution: at 20x the
  // cases (seed 25 at BLENDBENCH_PROPERTY_SEED=70000000, case 3111) a configuration 5e-4 rad
  // from the stretched elbow; there the failure must be clean, say why, and be rare.
  KinematicChain chain = ur_chain(kUr5e);
  chain.joints[5].origin = chain.joints[5].origin * Eigen::Translation3d(3e-7, 0, 0) *
                           Eigen::AngleAxisd(2e-7, Vec3::UnitY());
  const IkSolver ik(chain);
  const std::uint64_t seed = 25;
  auto rng = test::make_rng(seed);
  const int cases = test::property_cases(200);
  int near_failures = 0;
  for (int n = 0; n < cases; ++n) {
    const JointVector q = random_q_within(chain, rng);
    const Eigen::Isometry3d pose = forward_kinematics(chain, q);
    const IkSolver::Result result = ik.solve(pose, perturbed(q, rng, 0.05));
    if (!result.outcome.ok()) {
      const std::vector<SingularityMeasure> measures = singularity_measures(ik, q);
      const bool near = std::any_of(measures.begin(), measures.end(),
                                    [](const SingularityMeasure& m) { return std::abs(m.value) < m.threshold; });
      ASSERT_TRUE(near) << test::seed_text(seed) << " case " << n << ": " << result.outcome.message;
      EXPECT_NE(result.outcome.message.find("singular"), std::string::npos) << test::seed_text(seed) << " case " << n;
      ++near_failures;
      continue;
    }
    const Twist error = pose_error(pose, forward_kinematics(chain, result.q));
    ASSERT_LT(error.head<3>().norm(), kRoundTripPos) << test::seed_text(seed) << " case " << n;
    ASSERT_LT(error.tail<3>().norm(), kRoundTripAngle) << test::seed_text(seed) << " case " << n;
  }
  // measured: 4 of 40,000 cases over 10 offsets at 20x (0-2 per offset)
  EXPECT_LE(near_failures, 1 + cases / 1000) << near_failures << " failures near a singularity; " << test::seed_text(seed);
  std::cout << near_failures << " of " << cases << " polishings failed near a singularity\n";
}

void expect_not_ur(const KinematicChain& chain, const std::string& why) {
  test::expect_input_error([&] { const IkSolver ik(chain, IkMethod::kUrClosedForm); }, {.field = "urdf", .message = why},
                           "not UR-type: " + why);
}

TEST(Ik, RejectsChainsThatAreNotUrType) {
  KinematicChain chain = ur_chain(kUr5e);
  chain.joints.pop_back();
  expect_not_ur(chain, "5 joints");

  chain = ur_chain(kUr5e);
  chain.joints[2].axis = Vec3::UnitX();
  expect_not_ur(chain, "not parallel");

  chain = ur_chain(kUr5e);
  chain.joints[5].origin = chain.joints[5].origin * Eigen::Translation3d(0.01, 0, 0);
  expect_not_ur(chain, "axes 5 and 6 do not intersect");

  chain = ur_chain(kUr5e);
  chain.joints[1].origin = Eigen::Translation3d(0.02, 0, 0) * chain.joints[1].origin;
  expect_not_ur(chain, "axes 1 and 2 do not intersect");
}

TEST(Ik, AllBranchesOutsideTheLimitsIsAJointLimit) {
  KinematicChain chain = model_chain();
  chain.joints[0].lower = -0.1;
  chain.joints[0].upper = 0.1;
  const IkSolver ik(chain);
  const JointVector q = (JointVector() << 1.0, -1.2, 1.5, -1.9, -1.4, 0.6).finished();
  const IkSolver::Result result = ik.solve(forward_kinematics(chain, q), q);
  EXPECT_EQ(result.outcome.status, Status::kJointLimit);
  EXPECT_NE(result.outcome.message.find("shoulder_pan_joint"), std::string::npos) << result.outcome.message;
  EXPECT_NE(result.outcome.message.find("deg"), std::string::npos) << result.outcome.message;
  // the same arm reaches a pose whose shoulder angle is inside the limits
  JointVector inside = q;
  inside[0] = 0.05;
  EXPECT_TRUE(ik.solve(forward_kinematics(chain, inside), inside).outcome.ok());
}

TEST(Ik, SolutionsAreSortedByBranchDistance) {
  const KinematicChain chain = model_chain();
  const IkSolver ik(chain);
  const JointVector q = (JointVector() << 0.3, -1.2, 1.5, -1.9, -1.4, 0.6).finished();
  const std::vector<JointVector> all = ik.solutions(forward_kinematics(chain, q), q);
  ASSERT_EQ(all.size(), 8u);
  EXPECT_LT((all.front() - q).norm(), kSameQ);
  for (std::size_t i = 1; i < all.size(); ++i) EXPECT_LE(branch_distance(all[i - 1], q), branch_distance(all[i], q));
}

}  // namespace
}  // namespace blendbench
