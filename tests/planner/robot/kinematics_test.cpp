#include "blendbench/robot/kinematics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "support/property.hpp"
#include "blendbench/robot/ik.hpp"
#include "blendbench/io/urdf_chain.hpp"

namespace blendbench {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kExact = 1e-12;        // m, rad: hand-derived values
constexpr double kFiniteDiff = 1e-7;    // central differences with h = 1e-5
constexpr UrGeometry kUr5e{0.1625, -0.425, -0.3922, 0.1333, 0.0997, 0.0996};

KinematicChain model_chain() { return load_urdf_chain(test::source_path("models/ur5e_like.urdf")); }

JointVector random_q(std::mt19937_64& rng) {
  JointVector q;
  for (Eigen::Index i = 0; i < 6; ++i) q[i] = test::uniform(rng, -kPi, kPi);
  return q;
}

TEST(Kinematics, ZeroPoseOfTheModelIsTheStretchedArm) {
  // DH at q = 0: x1 = e_x, z1 = -e_y; the arm reaches a2 + a3 along x, the wrist offsets d4 and
  // d6 point along -y and d5 down; the flange axis z6 = -e_y, x6 = e_x, y6 = e_z
  const Eigen::Isometry3d pose = forward_kinematics(model_chain(), JointVector::Zero());
  EXPECT_TRUE(pose.translation().isApprox(Vec3(-0.8172, -0.2329, 0.0628), kExact)) << pose.translation().transpose();
  Mat3 expected;
  expected.col(0) = Vec3::UnitX();
  expected.col(1) = Vec3::UnitZ();
  expected.col(2) = -Vec3::UnitY();
  EXPECT_LT((pose.linear() - expected).norm(), kExact);
}

TEST(Kinematics, ShoulderPanTurnsTheWholeArmAboutTheBaseAxis) {
  const KinematicChain chain = model_chain();
  JointVector q = JointVector::Zero();
  q[0] = kPi / 2;
  // a quarter turn maps (x, y, z) to (-y, x, z)
  EXPECT_TRUE(forward_kinematics(chain, q).translation().isApprox(Vec3(0.2329, -0.8172, 0.0628), kExact));
}

TEST(Kinematics, ModelChainEqualsTheDhChain) {
  const KinematicChain model = model_chain();
  const KinematicChain dh = ur_chain(kUr5e);
  const std::uint64_t seed = 11;
  auto rng = test::make_rng(seed);
  for (int n = 0; n < test::property_cases(200); ++n) {
    const JointVector q = random_q(rng);
    const Twist error = pose_error(forward_kinematics(model, q), forward_kinematics(dh, q));
    ASSERT_LT(error.norm(), kExact) << test::seed_text(seed) << " case " << n;
    const Twist dh_error = pose_error(forward_kinematics(dh, q), ur_forward_kinematics(kUr5e, q));
    ASSERT_LT(dh_error.norm(), kExact) << test::seed_text(seed) << " case " << n;
  }
}

TEST(Kinematics, JacobianMatchesFiniteDifferences) {
  const KinematicChain chain = model_chain();
  const std::uint64_t seed = 12;
  auto rng = test::make_rng(seed);
  const double h = 1e-5;
  for (int n = 0; n < test::property_cases(200); ++n) {
    const JointVector q = random_q(rng);
    const Mat6 jac = jacobian(chain, q);
    for (Eigen::Index i = 0; i < 6; ++i) {
      JointVector step = JointVector::Zero();
      step[i] = h;
      // pose_error(T(q + h), T(q - h)) = [dp; dw] over a 2h step
      const Twist column = pose_error(forward_kinematics(chain, q + step), forward_kinematics(chain, q - step)) / (2 * h);
      ASSERT_LT((jac.col(i) - column).norm(), kFiniteDiff) << test::seed_text(seed) << " case " << n << " joint " << i;
    }
  }
}

TEST(Kinematics, PoseErrorIsTranslationAndRotationVector) {
  Eigen::Isometry3d actual = Eigen::Isometry3d::Identity();
  actual.translation() = Vec3(0.1, 0.2, 0.3);
  actual.linear() = Eigen::AngleAxisd(0.4, Vec3::UnitX()).toRotationMatrix();
  Eigen::Isometry3d target = actual;
  target.translation() += Vec3(0.01, 0, -0.02);
  target.linear() = Eigen::AngleAxisd(0.3, Vec3::UnitZ()).toRotationMatrix() * actual.linear();
  const Twist error = pose_error(target, actual);
  EXPECT_TRUE(error.head<3>().isApprox(Vec3(0.01, 0, -0.02), kExact));
  EXPECT_TRUE(error.tail<3>().isApprox(Vec3(0, 0, 0.3), kExact));
  // tiny rotations keep their size (no acos of a rounded trace)
  target.linear() = Eigen::AngleAxisd(1e-11, Vec3::UnitY()).toRotationMatrix() * actual.linear();
  EXPECT_NEAR(pose_error(target, actual)[4], 1e-11, 1e-20);
}

TEST(Kinematics, RpyRoundTripsAndHandlesGimbalLock) {
  const std::uint64_t seed = 13;
  auto rng = test::make_rng(seed);
  for (int n = 0; n < test::property_cases(200); ++n) {
    const Vec3 rpy(test::uniform(rng, -3, 3), test::uniform(rng, -1.5, 1.5), test::uniform(rng, -3, 3));
    const Mat3 r = (Eigen::AngleAxisd(rpy.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Vec3::UnitY()) *
                    Eigen::AngleAxisd(rpy.x(), Vec3::UnitX()))
                       .toRotationMatrix();
    ASSERT_TRUE(rpy_from_rotation(r).isApprox(rpy, 1e-9)) << test::seed_text(seed) << " case " << n;
  }
  // pitch = 90 deg: roll and yaw are coupled, all of it goes to yaw
  const Mat3 r = (Eigen::AngleAxisd(0.7, Vec3::UnitZ()) * Eigen::AngleAxisd(kPi / 2, Vec3::UnitY())).toRotationMatrix();
  EXPECT_TRUE(rpy_from_rotation(r).isApprox(Vec3(0, kPi / 2, 0.7), 1e-9)) << rpy_from_rotation(r).transpose();
}

TEST(Kinematics, DescribePoseGivesMillimetresAndDegrees) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Vec3(0.5, -0.1, 0.25);
  pose.linear() = Eigen::AngleAxisd(kPi, Vec3::UnitX()).toRotationMatrix();
  EXPECT_EQ(describe_pose(pose), "position (500.000, -100.000, 250.000) mm, rpy (180.000, 0.000, 0.000) deg");
}

}  // namespace
}  // namespace blendbench
