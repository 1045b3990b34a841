// The closed-form IK of spherical-wrist arms (spherical_ik.hpp) and the IkSolver on the
// KR 6-class arm of models/kr6_like.urdf: every branch exact, the enumeration complete, any
// placement of the geometry solved, singular poses finite, other chains refused.

#include "blendbench/robot/spherical_ik.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <numbers>
#include <set>

#include "blendbench/core/input_error.hpp"
#include "blendbench/io/urdf_chain.hpp"
#include "blendbench/robot/ik.hpp"
#include "support/property.hpp"

namespace blendbench {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kRoundTripPos = 1e-9;    // m, FK(IK(pose)) against pose
constexpr double kRoundTripAngle = 1e-9;  // rad
constexpr double kSameQ = 1e-6;           // rad, IK returns the configuration the pose came from
// The KR 6 R900 class (models/kr6_like.urdf's header).
constexpr SphericalWristGeometry kKr6{0.400, 0.025, 0.455, 0.0, 0.035, 0.420, 0.080};
// A PUMA-like arm: no shoulder offset, a lateral offset d2 and a negative elbow offset.
constexpr SphericalWristGeometry kPuma{0.66, 0.0, 0.432, 0.149, -0.02, 0.432, 0.056};

KinematicChain model_chain() { return load_urdf_chain(test::source_path("models/kr6_like.urdf")); }

JointVector random_theta(std::mt19937_64& rng) {
  JointVector theta;
  for (Eigen::Index i = 0; i < 6; ++i) theta[i] = test::uniform(rng, -kPi, kPi);
  return theta;
}

JointVector random_q_within(const KinematicChain& chain, std::mt19937_64& rng) {
  JointVector q;
  for (Eigen::Index i = 0; i < 6; ++i) {
    const JointSpec& joint = chain.joints[static_cast<std::size_t>(i)];
    q[i] = test::uniform(rng, joint.lower, joint.upper);
  }
  return q;
}

JointVector wrapped_difference(const JointVector& a, const JointVector& b) {
  JointVector d;
  for (Eigen::Index i = 0; i < 6; ++i) d[i] = std::remainder(a[i] - b[i], 2 * kPi);
  return d;
}

// The branch of a configuration: the signs of its shoulder, elbow and wrist measures.
int branch_label(const SphericalWristGeometry& g, const JointVector& theta) {
  const ArmMeasures m = spherical_measures(g, theta);
  return (m.shoulder > 0 ? 4 : 0) + (m.elbow > 0 ? 2 : 0) + (m.wrist > 0 ? 1 : 0);
}

// Every solution reproduces the pose, the configuration the pose came from is among them, and a
// pose reachable on all eight branches has one solution per branch label (front/back x elbow
// up/down x wrist flip): the eight are the eight distinct branches.
void expect_complete_branches(const SphericalWristGeometry& g, std::uint64_t seed, int cases) {
  auto rng = test::make_rng(seed);
  int eight = 0;
  for (int n = 0; n < cases; ++n) {
    const JointVector theta = random_theta(rng);
    const Eigen::Isometry3d flange = spherical_forward_kinematics(g, theta);
    const std::vector<JointVector> branches = spherical_closed_form_ik(g, flange, theta);
    ASSERT_FALSE(branches.empty()) << test::seed_text(seed) << " case " << n;
    ASSERT_LE(branches.size(), 8u);
    bool found_original = false;
    std::set<int> labels;
    for (const JointVector& branch : branches) {
      ASSERT_TRUE(branch.allFinite());
      const Twist error = pose_error(flange, spherical_forward_kinematics(g, branch));
      ASSERT_LT(error.head<3>().norm(), kRoundTripPos) << test::seed_text(seed) << " case " << n;
      ASSERT_LT(error.tail<3>().norm(), kRoundTripAngle) << test::seed_text(seed) << " case " << n;
      found_original = found_original || wrapped_difference(branch, theta).norm() < kSameQ;
      labels.insert(branch_label(g, branch));
    }
    EXPECT_TRUE(found_original) << test::seed_text(seed) << " case " << n << " theta " << theta.transpose();
    if (branches.size() == 8) {
      ++eight;
      EXPECT_EQ(labels.size(), 8u) << test::seed_text(seed) << " case " << n;
    }
  }
  // most random configurations' poses are reachable on all eight branches
  EXPECT_GT(eight, cases / 2);
}

TEST(SphericalIk, EveryBranchIsExactAndTheEnumerationComplete) {
  expect_complete_branches(kKr6, 41, test::property_cases(1000));
}

TEST(SphericalIk, LateralOffsetAndNegativeElbowOffsetToo) {
  expect_complete_branches(kPuma, 42, test::property_cases(500));
}

TEST(SphericalIk, FindsTheClassGeometryInTheUrdf) {
  const IkSolver ik(model_chain());
  ASSERT_EQ(ik.method(), IkMethod::kSphericalWristClosedForm);
  const SphericalWristGeometry& g = ik.spherical_geometry();
  // signs follow the frames the fit chose (axis 1 points down in the URDF, so d1 < 0)
  EXPECT_NEAR(std::abs(g.d1), kKr6.d1, 1e-12);
  EXPECT_NEAR(std::abs(g.a1), kKr6.a1, 1e-12);
  EXPECT_NEAR(std::abs(g.a2), kKr6.a2, 1e-12);
  EXPECT_NEAR(g.d2, 0, 1e-12);
  EXPECT_NEAR(std::abs(g.a3), kKr6.a3, 1e-12);
  EXPECT_NEAR(std::abs(g.d4), kKr6.d4, 1e-12);
  EXPECT_NEAR(std::abs(g.d6), kKr6.d6, 1e-12);
  EXPECT_LT(ik.placement().deviation, 1e-12);
}

// Through the IkSolver on the model: for random configurations within the limits every polished
// branch reproduces the pose, and the solver returns the configuration itself when seeded near it.
TEST(SphericalIk, RoundTripOnTheModelForAllBranches) {
  const KinematicChain chain = model_chain();
  const IkSolver ik(chain);
  const std::uint64_t seed = 43;
  auto rng = test::make_rng(seed);
  double max_pos = 0, max_angle = 0;
  std::size_t branches = 0;
  for (int n = 0; n < test::property_cases(1000); ++n) {
    const JointVector q = random_q_within(chain, rng);
    const Eigen::Isometry3d pose = forward_kinematics(chain, q);
    const std::vector<JointVector> all = ik.solutions(pose, q);
    ASSERT_FALSE(all.empty()) << test::seed_text(seed) << " case " << n;
    for (const JointVector& s : all) {
      const Twist error = pose_error(pose, forward_kinematics(chain, s));
      max_pos = std::max(max_pos, error.head<3>().norm());
      max_angle = std::max(max_angle, error.tail<3>().norm());
      ASSERT_LT(error.head<3>().norm(), kRoundTripPos) << test::seed_text(seed) << " case " << n;
      ASSERT_LT(error.tail<3>().norm(), kRoundTripAngle) << test::seed_text(seed) << " case " << n;
    }
    branches += all.size();
    JointVector near = q;
    for (Eigen::Index i = 0; i < 6; ++i) near[i] += test::uniform(rng, -0.02, 0.02);
    const IkSolver::Result result = ik.solve(pose, near);
    ASSERT_TRUE(result.outcome.ok()) << test::seed_text(seed) << " case " << n << ": " << result.outcome.message;
    // away from the singularities (where branches meet) the seed's branch comes back
    const ArmMeasures m = spherical_measures(ik.spherical_geometry(), ik.placement().theta(q));
    if (std::abs(m.shoulder) > 0.05 && std::abs(m.elbow) > 0.05 && std::abs(m.wrist) > 0.05) {
      EXPECT_LT((result.q - q).cwiseAbs().maxCoeff(), kSameQ) << test::seed_text(seed) << " case " << n;
    }
  }
  std::cout << "KR6-like IK round trip over " << branches << " branches: " << max_pos << " m, " << max_angle << " rad\n";
}

// A spherical-wrist chain written differently: base moved and tilted, joints 1, 3 and 5 turning
// the other way, the zero of joint 2 moved by 0.4 rad, and a tool 0.15 m out with a tilt.
TEST(SphericalIk, SolvesAnyPlacementOfTheGeometry) {
  KinematicChain chain = spherical_chain(kPuma);
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
  base.translation() = Vec3(0.1, -0.2, 0.05);
  base.linear() = Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  chain.joints[0].origin = base * chain.joints[0].origin;
  chain.joints[0].axis = -Vec3::UnitZ();
  chain.joints[2].axis = -Vec3::UnitZ();
  chain.joints[4].axis = -Vec3::UnitZ();
  chain.joints[1].origin = chain.joints[1].origin * Eigen::AngleAxisd(0.4, Vec3::UnitZ());
  chain.joints[2].origin = chain.joints[2].origin * Eigen::AngleAxisd(-0.4, Vec3::UnitZ());
  Eigen::Isometry3d tool = Eigen::Isometry3d::Identity();
  tool.translation() = Vec3(0.01, -0.02, 0.15);
  tool.linear() = Eigen::AngleAxisd(0.3, Vec3::UnitX()).toRotationMatrix();
  chain.tcp = chain.tcp * tool;
  const IkSolver ik(chain);
  ASSERT_EQ(ik.method(), IkMethod::kSphericalWristClosedForm);
  const std::uint64_t seed = 44;
  auto rng = test::make_rng(seed);
  for (int n = 0; n < test::property_cases(300); ++n) {
    const JointVector q = random_q_within(chain, rng);
    const Eigen::Isometry3d pose = forward_kinematics(chain, q);
    const std::vector<JointVector> all = ik.solutions(pose, q);
    ASSERT_FALSE(all.empty()) << test::seed_text(seed) << " case " << n;
    EXPECT_LT((all.front() - q).cwiseAbs().maxCoeff(), kSameQ) << test::seed_text(seed) << " case " << n;
    for (const JointVector& s : all) {
      const Twist error = pose_error(pose, forward_kinematics(chain, s));
      ASSERT_LT(error.head<3>().norm(), kRoundTripPos) << test::seed_text(seed) << " case " << n;
      ASSERT_LT(error.tail<3>().norm(), kRoundTripAngle) << test::seed_text(seed) << " case " << n;
    }
  }
}

// Singular configurations still give exact, finite solutions: the wrist with axes 4 and 6 in line
// (q6 then keeps the seed's value), the wrist centre on axis 1 (the shoulder), and the stretched
// elbow.
TEST(SphericalIk, SingularPosesHaveFiniteExactSolutions) {
  const SphericalWristGeometry g{0.4, 0.0, 0.455, 0.0, 0.035, 0.42, 0.08};  // no offset: axis 1 reachable
  const double stretched = std::atan2(g.d4, g.a3);                           // psi = 0
  // the wrist centre on axis 1: a2 cos t2 + L3 cos(t2 + psi) = 0 with psi = pi / 2
  const double l3 = std::hypot(g.a3, g.d4);
  const double t2 = std::atan2(g.a2, l3);  // a2 c2 - l3 s2 = 0
  const std::vector<JointVector> singular = {
      (JointVector() << 0.3, 0.7, 1.9, 0.4, 0.0, -0.8).finished(),               // wrist, c5 = 1
      (JointVector() << 0.3, 0.7, 1.9, 0.4, kPi, -0.8).finished(),               // wrist, c5 = -1
      (JointVector() << 0.3, t2, kPi / 2 + stretched, 0.4, 1.0, -0.8).finished(),  // shoulder
      (JointVector() << 0.3, 0.7, stretched, 0.4, 1.0, -0.8).finished()};          // elbow
  for (const JointVector& theta : singular) {
    const Eigen::Isometry3d flange = spherical_forward_kinematics(g, theta);
    JointVector near = theta;
    near[5] += 0.2;
    const std::vector<JointVector> branches = spherical_closed_form_ik(g, flange, near, 1e-9);
    ASSERT_FALSE(branches.empty()) << theta.transpose();
    bool near_seed = false;
    for (const JointVector& b : branches) {
      ASSERT_TRUE(b.allFinite()) << theta.transpose();
      const Twist error = pose_error(flange, spherical_forward_kinematics(g, b));
      EXPECT_LT(error.head<3>().norm(), 1e-8) << theta.transpose();
      EXPECT_LT(error.tail<3>().norm(), 1e-8) << theta.transpose();
      near_seed = near_seed || std::abs(std::remainder(b[5] - near[5], 2 * kPi)) < 1e-9;
    }
    // at the wrist singularity the free q6 is the seed's
    if (std::abs(std::sin(theta[4])) < 1e-12) {
      EXPECT_TRUE(near_seed) << theta.transpose();
    }
  }
}

TEST(SphericalIk, PosesBeyondReachAreUnreachableNotNan) {
  const IkSolver ik(model_chain());
  const JointVector near = (JointVector() << 0, -kPi / 2, kPi / 2, 0, kPi / 2, 0).finished();
  for (const Vec3& p : {Vec3(1.5, 0, 0.5), Vec3(0, 0, 1.6), Vec3(0.8, 0.8, 0.4)}) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = Eigen::AngleAxisd(kPi, Vec3::UnitY()).toRotationMatrix();
    pose.translation() = p;
    const IkSolver::Result result = ik.solve(pose, near);
    EXPECT_EQ(result.outcome.status, Status::kUnreachable) << p.transpose();
    EXPECT_TRUE(result.q.allFinite());
  }
}

TEST(SphericalIk, RejectsChainsWithoutASphericalWrist) {
  const auto expect_refused = [](const KinematicChain& chain, const std::string& why) {
    try {
      const IkSolver ik(chain, IkMethod::kSphericalWristClosedForm);
      ADD_FAILURE() << "accepted: " << why;
    } catch (const InputError& error) {
      EXPECT_EQ(error.field(), "urdf");
      EXPECT_NE(std::string(error.what()).find(why), std::string::npos) << error.what();
    }
  };
  // the UR arm: axis 4 parallel to axis 3
  expect_refused(ur_chain(UrGeometry{0.1625, -0.425, -0.3922, 0.1333, 0.0997, 0.0996}), "axes 3 and 4 are not perpendicular");
  // axis 6 moved off the wrist centre
  KinematicChain chain = spherical_chain(kKr6);
  chain.joints[5].origin = chain.joints[5].origin * Eigen::Translation3d(0.02, 0, 0);
  expect_refused(chain, "axes 5 and 6 do not intersect");
  // ... and the automatic choice falls back to the numeric solver, a closed form refuses it
  EXPECT_EQ(IkSolver(chain).method(), IkMethod::kNumeric);
  try {
    const IkSolver ik(chain, IkMethod::kClosedForm);
    ADD_FAILURE() << "a closed form accepted an offset wrist";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("no closed-form IK fits"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace blendbench
