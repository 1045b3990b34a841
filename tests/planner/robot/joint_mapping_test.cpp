#include "blendbench/robot/joint_mapping.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "blendbench/core/input_error.hpp"
#include "support/input_error.hpp"
#include "support/property.hpp"
#include "blendbench/io/urdf_chain.hpp"

namespace blendbench {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kDt = 0.001;              // s, the servo tick
constexpr double kPoseTol = 1e-9;          // m and rad, FK of the mapped joints against the poses
constexpr double kDerivativeTol = 1e-5;    // rad/s, rad/s^2 on exactly quadratic motion
constexpr double kPathStep = 0.01;         // rad per tick on the test paths

KinematicChain model_chain() { return load_urdf_chain(test::source_path("models/ur5e_like.urdf")); }

// The model's ready configuration: facing +x, elbow up, tool down (models/ur5e_like.urdf).
const JointVector kReady = (JointVector() << kPi, -kPi / 2, kPi / 2, -kPi / 2, -kPi / 2, 0).finished();

Eigen::Isometry3d tool_down_at(const Vec3& p, double spin = 0) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = (Eigen::AngleAxisd(spin, Vec3::UnitZ()) * Eigen::AngleAxisd(kPi, Vec3::UnitX())).toRotationMatrix();
  pose.translation() = p;
  return pose;
}

// Rest-to-rest smooth profile s(u) in [0, 1] for u in [0, 1] (zero speed and acceleration at
// both ends).
double smooth(double u) { return u * u * u * (10 - 15 * u + 6 * u * u); }

TEST(JointMapping, QuadraticJointMotionGivesExactDerivatives) {
  const KinematicChain chain = model_chain();
  const IkSolver ik(chain);
  // q(t) = q0 + v t + a t^2 / 2: every stencil used is exact for it, ends included
  const JointVector v = (JointVector() << 0.1, -0.2, 0.15, 0.3, -0.1, 0.25).finished();
  const JointVector a = (JointVector() << 0.5, 0.3, -0.4, 0.2, 0.6, -0.3).finished();
  const double dt = 0.01;
  std::vector<Eigen::Isometry3d> poses;
  for (int i = 0; i <= 50; ++i) {
    const double t = i * dt;
    poses.push_back(forward_kinematics(chain, kReady + v * t + a * (t * t / 2)));
  }
  const JointMapping traj = map_to_joints(ik, poses, dt, kReady);
  ASSERT_TRUE(traj.outcome.ok()) << traj.outcome.message;
  ASSERT_EQ(traj.joints.q.size(), poses.size());
  ASSERT_EQ(traj.joints.qd.size(), poses.size());
  ASSERT_EQ(traj.joints.qdd.size(), poses.size());
  EXPECT_EQ(traj.joints.dt, dt);
  for (std::size_t i = 0; i < poses.size(); ++i) {
    const double t = static_cast<double>(i) * dt;
    EXPECT_LT((traj.joints.q[i] - (kReady + v * t + a * (t * t / 2))).norm(), 1e-9) << i;
    EXPECT_LT((traj.joints.qd[i] - (v + a * t)).norm(), kDerivativeTol) << i;
    EXPECT_LT((traj.joints.qdd[i] - a).norm(), kDerivativeTol) << i;
  }
}

TEST(JointMapping, ShortSequencesHaveConsistentDerivatives) {
  const KinematicChain chain = model_chain();
  const IkSolver ik(chain);
  const JointVector a = (JointVector() << 0.5, 0.3, -0.4, 0.2, 0.6, -0.3).finished();
  const double dt = 0.01;
  // one sample: at rest
  JointMapping one = map_to_joints(ik, {forward_kinematics(chain, kReady)}, dt, kReady);
  ASSERT_TRUE(one.outcome.ok());
  EXPECT_EQ(one.joints.qd[0], JointVector::Zero());
  EXPECT_EQ(one.joints.qdd[0], JointVector::Zero());
  // two samples: the one velocity there is, no acceleration
  const JointVector q1 = kReady + a * 0.01;
  JointMapping two = map_to_joints(ik, {forward_kinematics(chain, kReady), forward_kinematics(chain, q1)}, dt, kReady);
  ASSERT_TRUE(two.outcome.ok());
  EXPECT_LT((two.joints.qd[0] - a).norm(), kDerivativeTol);
  EXPECT_LT((two.joints.qd[1] - a).norm(), kDerivativeTol);
  EXPECT_EQ(two.joints.qdd[1], JointVector::Zero());
  // three samples of q = q0 + a t^2 / 2: exact velocity and the constant acceleration everywhere
  std::vector<Eigen::Isometry3d> poses;
  for (int i = 0; i < 3; ++i) poses.push_back(forward_kinematics(chain, kReady + a * (i * dt * i * dt / 2)));
  JointMapping three = map_to_joints(ik, poses, dt, kReady);
  ASSERT_TRUE(three.outcome.ok());
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_LT((three.joints.qd[i] - a * (static_cast<double>(i) * dt)).norm(), kDerivativeTol) << i;
    EXPECT_LT((three.joints.qdd[i] - a).norm(), kDerivativeTol) << i;
  }
  // nothing at all
  EXPECT_TRUE(map_to_joints(ik, {}, dt, kReady).outcome.ok());
}

TEST(JointMapping, LineAndCircleAreMappedContinuouslyAndStartAtRest) {
  const KinematicChain chain = model_chain();
  const IkSolver ik(chain);
  // a 0.6 m line in 1.5 s and a full circle of radius 0.15 m in 2 s, both rest to rest
  std::vector<Eigen::Isometry3d> line;
  for (int i = 0; i <= 1500; ++i) {
    const double s = smooth(i / 1500.0);
    line.push_back(tool_down_at(Vec3(0.35 + 0.3 * s, -0.25 + 0.5 * s, 0.15 + 0.2 * s)));
  }
  std::vector<Eigen::Isometry3d> circle;
  for (int i = 0; i <= 2000; ++i) {
    const double phi = 2 * kPi * smooth(i / 2000.0);
    circle.push_back(tool_down_at(Vec3(0.5 + 0.15 * std::cos(phi), 0.15 * std::sin(phi), 0.25), 0.5 * phi));
  }
  for (const auto* poses : {&line, &circle}) {
    const JointMapping traj = map_to_joints(ik, *poses, kDt, kReady);
    ASSERT_TRUE(traj.outcome.ok()) << traj.outcome.message;
    ASSERT_EQ(traj.joints.q.size(), poses->size());
    for (std::size_t i = 0; i < poses->size(); ++i) {
      const Twist error = pose_error((*poses)[i], forward_kinematics(chain, traj.joints.q[i]));
      ASSERT_LT(error.norm(), kPoseTol) << i;
      ASSERT_TRUE(traj.joints.qd[i].allFinite() && traj.joints.qdd[i].allFinite()) << i;
      if (i > 0) {
        ASSERT_LT((traj.joints.q[i] - traj.joints.q[i - 1]).cwiseAbs().maxCoeff(), kPathStep) << i;
      }
    }
    // rest to rest: the end-point velocities are those of a quintic's first tick, almost zero
    EXPECT_LT(traj.joints.qd.front().norm(), 1e-3);
    EXPECT_LT(traj.joints.qd.back().norm(), 1e-3);
  }
}

TEST(JointMapping, UnreachablePoseStopsWithTimeAndPose) {
  const IkSolver ik(model_chain());
  std::vector<Eigen::Isometry3d> poses;
  for (int i = 0; i < 10; ++i) poses.push_back(tool_down_at(Vec3(0.5 + 0.0005 * i, 0, 0.2)));
  poses[5] = tool_down_at(Vec3(3, 0, 0.2));
  const JointMapping traj = map_to_joints(ik, poses, kDt, kReady);
  EXPECT_EQ(traj.outcome.status, Status::kUnreachable);
  EXPECT_EQ(traj.failed_index, 5u);
  EXPECT_EQ(traj.joints.q.size(), 5u);
  EXPECT_TRUE(traj.joints.qd.empty());
  EXPECT_NE(traj.outcome.message.find("t = 0.005 s"), std::string::npos) << traj.outcome.message;
  EXPECT_NE(traj.outcome.message.find("3000.000, 0.000, 200.000) mm"), std::string::npos) << traj.outcome.message;
}

TEST(JointMapping, JointLimitOnTheContinuousBranchIsReportedNotClamped) {
  const Vec3 p(0.5, 0.05, 0.2);
  // the spin of the tool about its (downward) axis at which wrist 3 is at 0: q6 = q6(0) - spin
  const double spin0 = IkSolver(model_chain()).solve(tool_down_at(p), kReady).q[5];
  KinematicChain chain = model_chain();
  chain.joints[5].lower = -1.0;
  chain.joints[5].upper = 1.0;
  const IkSolver ik(chain);
  // spin on by 2 rad over 2000 ticks: wrist 3 follows from 0 to -2 and leaves its limits at -1
  std::vector<Eigen::Isometry3d> poses;
  for (int i = 0; i <= 2000; ++i) poses.push_back(tool_down_at(p, spin0 + 2.0 * i / 2000.0));
  const IkSolver::Result start = ik.solve(poses[0], kReady);
  ASSERT_TRUE(start.outcome.ok()) << start.outcome.message;
  ASSERT_LT(std::abs(start.q[5]), 1e-6);
  const JointMapping traj = map_to_joints(ik, poses, kDt, start.q);
  EXPECT_EQ(traj.outcome.status, Status::kJointLimit) << traj.outcome.message;
  EXPECT_NE(traj.outcome.message.find("wrist_3_joint"), std::string::npos) << traj.outcome.message;
  EXPECT_NE(traj.outcome.message.find("t = 1.001 s"), std::string::npos) << traj.outcome.message;
  EXPECT_EQ(traj.failed_index, 1001u);
  // every accepted sample is inside the limits: nothing was clamped
  for (const JointVector& q : traj.joints.q) EXPECT_TRUE(ik.within_limits(q));
  EXPECT_NEAR(traj.joints.q.back()[5], -1.0, 1e-9);
}

TEST(JointMapping, AJumpBetweenBranchesIsABranchFlip) {
  const IkSolver ik(model_chain());
  // two poses far apart in consecutive ticks: no continuous motion joins them
  const std::vector<Eigen::Isometry3d> poses = {tool_down_at(Vec3(0.5, -0.3, 0.2)), tool_down_at(Vec3(0.5, 0.3, 0.2))};
  const JointMapping traj = map_to_joints(ik, poses, kDt, kReady);
  EXPECT_EQ(traj.outcome.status, Status::kSingular);
  EXPECT_EQ(traj.failed_index, 1u);
  EXPECT_NE(traj.outcome.message.find("t = 0.001 s"), std::string::npos) << traj.outcome.message;
  EXPECT_NE(traj.outcome.message.find("jumps"), std::string::npos) << traj.outcome.message;
}

TEST(JointMapping, UnreachableFirstPoseFailsAtTimeZero) {
  const IkSolver ik(model_chain());
  const JointMapping traj = map_to_joints(ik, {tool_down_at(Vec3(0, 0, 2))}, kDt, kReady);
  EXPECT_EQ(traj.outcome.status, Status::kUnreachable);
  EXPECT_EQ(traj.failed_index, 0u);
  EXPECT_NE(traj.outcome.message.find("t = 0 s"), std::string::npos) << traj.outcome.message;
}

TEST(JointMapping, NonPositiveTickIsBadInput) {
  const IkSolver ik(model_chain());
  for (const double dt : {0.0, -0.001, std::nan("")}) {
    test::expect_input_error([&] { (void)map_to_joints(ik, {tool_down_at(Vec3(0.5, 0, 0.2))}, dt, kReady); },
                             {.field = "dt"}, "dt = " + std::to_string(dt));
  }
}

}  // namespace
}  // namespace blendbench
