// Singularity measures, the scan of a joint reference for passages near a singularity, and
// branch changes (singularity.hpp), on both closed-form arms and the numeric solver's measure.

#include "blendbench/robot/singularity.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "blendbench/io/urdf_chain.hpp"
#include "support/property.hpp"

namespace blendbench {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr UrGeometry kUr5e{0.1625, -0.425, -0.3922, 0.1333, 0.0997, 0.0996};
constexpr SphericalWristGeometry kKr6{0.400, 0.025, 0.455, 0.0, 0.035, 0.420, 0.080};
constexpr double kZero = 1e-12;

// On DH chains (chain angles = DH angles) each measure vanishes at its singularity and not at the
// others, and the numeric solver's Jacobian measure vanishes at all of them.
TEST(Singularity, EachMeasureVanishesAtItsSingularity) {
  // UR: wrist q5 = 0; elbow q3 = 0; shoulder with q234 = 0 and a2 c2 + a3 c23 = 0
  const double t3 = 0.5;
  const double t2 = std::atan((kUr5e.a2 + kUr5e.a3 * std::cos(t3)) / (kUr5e.a3 * std::sin(t3)));
  const IkSolver ur(ur_chain(kUr5e));
  ASSERT_EQ(ur.method(), IkMethod::kUrClosedForm);
  // spherical: wrist q5 = 0; elbow psi = 0; shoulder: the wrist centre on axis 1
  const double gamma = std::atan2(kKr6.d4, kKr6.a3);
  const double l3 = std::hypot(kKr6.a3, kKr6.d4);
  // a1 + a2 c2 + l3 cos(t2 + pi/2) = 0 -> a1 + a2 c2 - l3 s2 = 0
  const double rr = std::hypot(kKr6.a2, l3);
  const double s2 = std::acos(-kKr6.a1 / rr) + std::atan2(-l3, kKr6.a2);
  const IkSolver kr6(spherical_chain(kKr6));
  ASSERT_EQ(kr6.method(), IkMethod::kSphericalWristClosedForm);
  struct Case {
    const IkSolver* ik;
    JointVector q;
    SingularityKind kind;
  };
  const std::vector<Case> cases = {
      {&ur, (JointVector() << 0.4, -1.0, 1.2, -0.7, 0.0, 0.3).finished(), SingularityKind::kWrist},
      {&ur, (JointVector() << 0.4, -1.0, 0.0, -0.7, 1.0, 0.3).finished(), SingularityKind::kElbow},
      {&ur, (JointVector() << 0.4, t2, t3, -t2 - t3, 1.0, 0.3).finished(), SingularityKind::kShoulder},
      {&kr6, (JointVector() << 0.4, 0.7, 1.9, 0.3, 0.0, 0.3).finished(), SingularityKind::kWrist},
      {&kr6, (JointVector() << 0.4, 0.7, gamma, 0.3, 1.0, 0.3).finished(), SingularityKind::kElbow},
      {&kr6, (JointVector() << 0.4, s2, kPi / 2 + gamma, 0.3, 1.0, 0.3).finished(), SingularityKind::kShoulder}};
  for (const Case& c : cases) {
    SCOPED_TRACE(std::string(to_string(c.kind)) + " " + (c.ik == &ur ? "UR" : "KR6"));
    const std::vector<SingularityMeasure> measures = singularity_measures(*c.ik, c.q);
    ASSERT_EQ(measures.size(), 3u);
    for (const SingularityMeasure& m : measures) {
      if (m.kind == c.kind) {
        EXPECT_LT(std::abs(m.value), kZero);
      } else {
        EXPECT_GT(std::abs(m.value), m.threshold);
      }
    }
    // the Jacobian loses rank there: the numeric solver's measure is zero too
    const IkSolver numeric(c.ik->chain(), IkMethod::kNumeric);
    const std::vector<SingularityMeasure> generic = singularity_measures(numeric, c.q);
    ASSERT_EQ(generic.size(), 1u);
    EXPECT_EQ(generic.front().kind, SingularityKind::kJacobian);
    EXPECT_LT(std::abs(generic.front().value), 1e-9);
  }
  // and away from them it is well above its threshold
  const IkSolver numeric(ur.chain(), IkMethod::kNumeric);
  EXPECT_GT(std::abs(singularity_measures(numeric, (JointVector() << 0.4, -1.0, 1.2, -0.7, 1.2, 0.3).finished())
                         .front()
                         .value),
            2 * kJacobianRatio);
}

// Each measure's sign is the branch: across a sign change the Jacobian's determinant changes sign.
TEST(Singularity, SignsFollowTheDeterminant) {
  const KinematicChain chain = load_urdf_chain(test::source_path("models/kr6_like.urdf"));
  const IkSolver ik(chain);
  const std::uint64_t seed = 61;
  auto rng = test::make_rng(seed);
  for (int n = 0; n < test::property_cases(500); ++n) {
    JointVector q;
    for (Eigen::Index i = 0; i < 6; ++i) q[i] = test::uniform(rng, -kPi, kPi);
    double product = 1;
    for (const SingularityMeasure& m : singularity_measures(ik, q)) product *= m.value;
    const double det = jacobian(chain, q).determinant();
    if (std::abs(product) < 1e-6) continue;
    // det J = c * shoulder * elbow * wrist with a constant c of one sign for the arm
    static const double sign = det * product > 0 ? 1.0 : -1.0;
    EXPECT_GT(sign * det * product, 0) << test::seed_text(seed) << " case " << n;
  }
}

// The wrist passes near its singularity and away again: one passage with its closest approach.
TEST(Singularity, ScanReportsEachPassageAtItsClosestApproach) {
  const IkSolver ik(load_urdf_chain(test::source_path("models/ur5e_like.urdf")));
  std::vector<JointVector> q;
  const double dt = 0.002;
  const JointVector ready = (JointVector() << kPi, -kPi / 2, kPi / 2, -kPi / 2, -kPi / 2, 0).finished();
  for (int k = 0; k <= 1000; ++k) {
    JointVector s = ready;
    // q5 from -pi/2 up to -0.05 rad at k = 600, then back
    const double u = k <= 600 ? k / 600.0 : (1000 - k) / 400.0;
    s[4] = -kPi / 2 + u * (kPi / 2 - 0.05);
    q.push_back(s);
  }
  const std::vector<SingularityPassage> passages = scan_singularities(ik, q, dt);
  ASSERT_EQ(passages.size(), 1u);
  const SingularityPassage& p = passages.front();
  EXPECT_EQ(p.kind, SingularityKind::kWrist);
  EXPECT_NEAR(p.t, 600 * dt, 1e-12);
  EXPECT_NEAR(p.measure, std::sin(0.05), 1e-9);
  EXPECT_EQ(p.threshold, kWristSine);
  // it starts and ends where |sin q5| falls below the threshold
  EXPECT_LT(p.t_start, p.t);
  EXPECT_GT(p.t_end, p.t);
  EXPECT_LT(std::abs(std::sin(q[static_cast<std::size_t>(std::lround(p.t_start / dt))][4])), kWristSine);
  EXPECT_GE(std::abs(std::sin(q[static_cast<std::size_t>(std::lround(p.t_start / dt)) - 1][4])), kWristSine);
  EXPECT_TRUE(p.pose.isApprox(forward_kinematics(ik.chain(), q[600]), 1e-12));
  // no branch changed: q5 never crossed zero
  EXPECT_TRUE(branch_changes(ik, q, dt).empty());
}

// A continuous crossing of q5 = 0 changes the wrist branch; the numeric solver's measure sees the
// same crossing.
TEST(Singularity, ACrossingIsABranchChange) {
  const KinematicChain chain = load_urdf_chain(test::source_path("models/kr6_like.urdf"));
  std::vector<JointVector> q;
  for (int k = 0; k <= 100; ++k) q.push_back((JointVector() << 0.1, -1.4, 1.5, 0.3, 0.3 - 0.006 * k, 0.2).finished());
  for (const IkMethod method : {IkMethod::kAuto, IkMethod::kNumeric}) {
    const IkSolver ik(chain, method);
    const std::vector<BranchChange> changes = branch_changes(ik, q, 0.01);
    ASSERT_EQ(changes.size(), 1u) << to_string(method);
    EXPECT_EQ(changes.front().kind, method == IkMethod::kAuto ? SingularityKind::kWrist : SingularityKind::kJacobian);
    EXPECT_EQ(changes.front().index, 51u);  // q5 = 0 at k = 50 exactly: the sign is taken on its far side
    EXPECT_NEAR(changes.front().t, 0.51, 1e-12);
    EXPECT_GT(changes.front().before * changes.front().after, -1e300);
    EXPECT_LT(changes.front().before * changes.front().after, 0);
  }
}

}  // namespace
}  // namespace blendbench
