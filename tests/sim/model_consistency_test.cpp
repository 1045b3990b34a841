// models/ur5e_like.urdf (kinematic truth, read with urdfdom) and models/ur5e_like.xml (MuJoCo)
// describe the same arm: same TCP pose at every configuration, same joint limits, torque limits
// equal to the URDF efforts, same masses, inertias and damping.

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <array>
#include <memory>
#include <stdexcept>
#include <string>

#include "support/property.hpp"
#include "blendbench/robot/kinematics.hpp"
#include "blendbench/io/urdf_chain.hpp"

namespace blendbench {
namespace {

constexpr double kPoseTol = 1e-9;   // m and rad
constexpr double kValueTol = 1e-12;  // limits, masses, inertias as written in both files

// MuJoCo's default error handler exits the process: throw instead, and record warnings so a
// test fails on any of them.
std::string& mujoco_warnings() {
  static std::string text;
  return text;
}
void throw_mujoco_error(const char* message) { throw std::runtime_error(std::string("MuJoCo error: ") + message); }
void record_mujoco_warning(const char* message) { mujoco_warnings() += std::string(message) + "\n"; }

struct ModelDeleter {
  void operator()(mjModel* m) const { mj_deleteModel(m); }
};
struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;
using DataPtr = std::unique_ptr<mjData, DataDeleter>;

class ModelConsistency : public ::testing::Test {
 protected:
  void SetUp() override {
    mju_user_error = throw_mujoco_error;
    mju_user_warning = record_mujoco_warning;
    mujoco_warnings().clear();
  }
  void TearDown() override { EXPECT_EQ(mujoco_warnings(), "") << "MuJoCo warned"; }

  static ModelPtr load(const std::string& relative) {
    std::array<char, 1000> error{};
    ModelPtr model(mj_loadXML(test::source_path(relative).c_str(), nullptr, error.data(), static_cast<int>(error.size())));
    EXPECT_TRUE(model) << relative << ": " << error.data();
    return model;
  }

  // Inertia tensor of body i about its centre of mass, in the body frame (kg*m^2).
  static Mat3 inertia_tensor(const mjModel* m, int i) {
    const double* q = m->body_iquat + 4 * i;
    const Mat3 r = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).toRotationMatrix();
    return r * Eigen::Map<const Vec3>(m->body_inertia + 3 * i).asDiagonal() * r.transpose();
  }

  static int id(const mjModel* m, mjtObj type, const std::string& name) {
    const int i = mj_name2id(m, type, name.c_str());
    EXPECT_GE(i, 0) << "no object named '" << name << "'";
    return i;
  }
};

TEST_F(ModelConsistency, TcpPoseAgreesAtRandomConfigurations) {
  const KinematicChain chain = load_urdf_chain(test::source_path("models/ur5e_like.urdf"));
  const ModelPtr m = load("models/ur5e_like.xml");
  ASSERT_TRUE(m);
  ASSERT_EQ(m->nq, 6);
  const DataPtr d(mj_makeData(m.get()));
  const int tcp = id(m.get(), mjOBJ_SITE, "tcp");
  std::array<int, 6> qpos_of{};
  for (std::size_t i = 0; i < 6; ++i) qpos_of[i] = m->jnt_qposadr[id(m.get(), mjOBJ_JOINT, chain.joints[i].name)];

  const std::uint64_t seed = 31;
  auto rng = test::make_rng(seed);
  for (int n = 0; n < test::property_cases(200); ++n) {
    Vec6 q;
    for (std::size_t i = 0; i < 6; ++i) {
      const auto k = static_cast<Eigen::Index>(i);
      q[k] = test::uniform(rng, chain.joints[i].lower, chain.joints[i].upper);
      d->qpos[qpos_of[i]] = q[k];
    }
    mj_kinematics(m.get(), d.get());
    Eigen::Isometry3d sim = Eigen::Isometry3d::Identity();
    sim.translation() = Eigen::Map<const Vec3>(d->site_xpos + 3 * tcp);
    sim.linear() = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(d->site_xmat + 9 * tcp);
    const Vec6 error = pose_error(forward_kinematics(chain, q), sim);
    ASSERT_LT(error.head<3>().norm(), kPoseTol) << test::seed_text(seed) << " case " << n << " q " << q.transpose();
    ASSERT_LT(error.tail<3>().norm(), kPoseTol) << test::seed_text(seed) << " case " << n << " q " << q.transpose();
  }
}

TEST_F(ModelConsistency, JointAndTorqueLimitsAgree) {
  const KinematicChain chain = load_urdf_chain(test::source_path("models/ur5e_like.urdf"));
  const ModelPtr m = load("models/ur5e_like.xml");
  ASSERT_TRUE(m);
  ASSERT_EQ(m->nu, 6);
  for (std::size_t i = 0; i < 6; ++i) {
    const JointSpec& joint = chain.joints[i];
    const int j = id(m.get(), mjOBJ_JOINT, joint.name);
    EXPECT_TRUE(m->jnt_limited[j]) << joint.name;
    EXPECT_NEAR(m->jnt_range[2 * j], joint.lower, kValueTol) << joint.name;
    EXPECT_NEAR(m->jnt_range[2 * j + 1], joint.upper, kValueTol) << joint.name;
    // actuator i is the motor of joint i, with the joint's name, gear 1, ctrl = torque
    const int a = id(m.get(), mjOBJ_ACTUATOR, joint.name);
    EXPECT_EQ(a, static_cast<int>(i));
    EXPECT_EQ(m->actuator_trntype[a], mjTRN_JOINT);
    EXPECT_EQ(m->actuator_trnid[2 * a], j);
    EXPECT_EQ(m->actuator_gear[6 * a], 1.0);
    EXPECT_TRUE(m->actuator_ctrllimited[a]) << joint.name;
    EXPECT_NEAR(m->actuator_ctrlrange[2 * a], -joint.effort_limit, kValueTol) << joint.name;
    EXPECT_NEAR(m->actuator_ctrlrange[2 * a + 1], joint.effort_limit, kValueTol) << joint.name;
  }
  // the UR5e's torque limits, read from the URDF
  const std::array<double, 6> effort = {150, 150, 150, 28, 28, 28};
  for (std::size_t i = 0; i < 6; ++i) EXPECT_EQ(chain.joints[i].effort_limit, effort[i]) << chain.joints[i].name;
}

TEST_F(ModelConsistency, MassesInertiasAndDampingAgree) {
  // MuJoCo reads URDF too: compare the bodies it builds from it with the MJCF's (the URDF's
  // root link becomes MuJoCo's world body, so the fixed base is not compared)
  const ModelPtr urdf = load("models/ur5e_like.urdf");
  const ModelPtr mjcf = load("models/ur5e_like.xml");
  ASSERT_TRUE(urdf && mjcf);
  const std::array<std::string, 6> links = {"shoulder_link", "upper_arm_link", "forearm_link",
                                            "wrist_1_link",  "wrist_2_link",   "wrist_3_link"};
  for (const std::string& link : links) {
    const int a = id(urdf.get(), mjOBJ_BODY, link);
    const int b = id(mjcf.get(), mjOBJ_BODY, link);
    EXPECT_NEAR(urdf->body_mass[a], mjcf->body_mass[b], kValueTol) << link;
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(urdf->body_ipos[3 * a + k], mjcf->body_ipos[3 * b + k], kValueTol) << link;
    // MuJoCo stores principal moments and axes, possibly in another order: compare the tensors
    EXPECT_LT((inertia_tensor(urdf.get(), a) - inertia_tensor(mjcf.get(), b)).norm(), kValueTol) << link;
  }
  for (int j = 0; j < 6; ++j) {
    const std::string name = mj_id2name(mjcf.get(), mjOBJ_JOINT, j);
    const int dof_urdf = urdf->jnt_dofadr[id(urdf.get(), mjOBJ_JOINT, name)];
    EXPECT_NEAR(urdf->dof_damping[dof_urdf], mjcf->dof_damping[mjcf->jnt_dofadr[j]], kValueTol) << name;
  }
}

TEST_F(ModelConsistency, SimulationSettingsAreThoseTheServoLoopExpects) {
  const ModelPtr m = load("models/ur5e_like.xml");
  ASSERT_TRUE(m);
  EXPECT_EQ(m->opt.timestep, 0.001);
  EXPECT_EQ(m->opt.integrator, mjINT_EULER);
  EXPECT_GE(id(m.get(), mjOBJ_CAMERA, "overview"), 0);
  EXPECT_EQ(m->vis.global.offwidth, 1280);
  EXPECT_EQ(m->vis.global.offheight, 720);
  // keyframe "ready": facing +x, elbow up, tool down
  const int ready = id(m.get(), mjOBJ_KEY, "ready");
  const std::array<double, 6> q_ready = {mjPI, -mjPI / 2, mjPI / 2, -mjPI / 2, -mjPI / 2, 0};
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(m->key_qpos[6 * ready + i], q_ready[static_cast<std::size_t>(i)], kValueTol);
  for (int j = 0; j < m->nv; ++j) {
    EXPECT_GT(m->dof_armature[j], 0) << "armature keeps stiff PD stable at the 1 ms step";
    EXPECT_GT(m->dof_damping[j], 0);
  }
  // no arm geom takes part in contacts
  for (int g = 0; g < m->ngeom; ++g) {
    if (m->geom_bodyid[g] == 0) continue;
    EXPECT_EQ(m->geom_contype[g], 0) << g;
    EXPECT_EQ(m->geom_conaffinity[g], 0) << g;
  }
}

TEST_F(ModelConsistency, ArmHoldsStillUnderGravityCompensationWithoutWarnings) {
  // a short physics smoke test: ctrl = bias forces keeps the arm at rest for a second
  const ModelPtr m = load("models/ur5e_like.xml");
  ASSERT_TRUE(m);
  const DataPtr d(mj_makeData(m.get()));
  const std::array<double, 6> q0 = {0.2, -1.4, 1.6, -1.8, -1.57, 0.3};
  for (int i = 0; i < 6; ++i) d->qpos[i] = q0[static_cast<std::size_t>(i)];
  for (int step = 0; step < 1000; ++step) {
    mj_forward(m.get(), d.get());
    for (int i = 0; i < 6; ++i) d->ctrl[i] = d->qfrc_bias[i];
    mj_step(m.get(), d.get());
  }
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(d->qpos[i], q0[static_cast<std::size_t>(i)], 1e-6) << i;
  for (int w = 0; w < mjNWARNING; ++w) EXPECT_EQ(d->warning[w].number, 0) << "warning " << w;
}

}  // namespace
}  // namespace blendbench
