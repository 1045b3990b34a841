// An MJCF of the user's own as the simulated arm (issue 46): the kinematic chain the simulator
// reads from a model agrees with the URDF's where there is one (models/ur5e_like) and with
// MuJoCo's own kinematics on an arm in MuJoCo Menagerie's style (tests/data/menagerie_style:
// position servos, a mesh, no site "tcp"), whose actuators become direct-torque motors, named,
// or are refused naming what is missing.

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <string>

#include "blendbench/io/urdf_chain.hpp"
#include "blendbench/sim/simulator.hpp"
#include "support/files.hpp"
#include "support/input_error.hpp"
#include "support/property.hpp"
#include "support/scratch.hpp"

namespace blendbench {
namespace {

constexpr double kPoseTol = 1e-9;  // m and rad

std::string menagerie_arm() { return test::source_path("tests/data/menagerie_style/arm.xml"); }

ModelChanges own(const std::string& site, const std::string& body = "") {
  ModelChanges c;
  c.tcp_site = site;
  c.tcp_body = body;
  c.own_actuators_to_motors = true;
  return c;
}

// The pose of `site` (or, when site < 0, of `body`) at link angles q on the motor hinges.
Eigen::Isometry3d mujoco_pose(const Simulator& sim, const std::vector<int>& qpos, const JointVector& q, int site, int body) {
  const mjModel& m = sim.model();
  std::unique_ptr<mjData, void (*)(mjData*)> d(mj_makeData(&m), mj_deleteData);
  for (int i = 0; i < 6; ++i) d->qpos[qpos[static_cast<std::size_t>(i)]] = q[i];
  mj_kinematics(&m, d.get());
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  const double* x = site >= 0 ? d->site_xpos + 3 * site : d->xpos + 3 * body;
  const double* r = site >= 0 ? d->site_xmat + 9 * site : d->xmat + 9 * body;
  pose.translation() = Eigen::Map<const Vec3>(x);
  pose.linear() = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(r);
  return pose;
}

std::vector<int> motor_qpos(const Simulator& sim, const KinematicChain& chain) {
  std::vector<int> out;
  for (const JointSpec& j : chain.joints) out.push_back(sim.model().jnt_qposadr[mj_name2id(&sim.model(), mjOBJ_JOINT, j.name.c_str())]);
  return out;
}

TEST(OwnModel, TheModelsChainIsTheUrdfsOnTheShippedArm) {
  // the chain read from the MJCF (elastic and rigid) against the URDF's, at random poses
  const KinematicChain urdf = load_urdf_chain(test::source_path("models/ur5e_like.urdf"));
  for (const char* file : {"models/ur5e_like.xml", "models/ur5e_like_rigid.xml"}) {
    const Simulator sim(test::source_path(file));
    const KinematicChain chain = sim.kinematic_chain();
    ASSERT_EQ(chain.joints.size(), 6u) << file;
    const std::uint64_t seed = 41;
    auto rng = test::make_rng(seed);
    for (int n = 0; n < test::property_cases(100); ++n) {
      JointVector q;
      for (int i = 0; i < 6; ++i) q[i] = test::uniform(rng, -3, 3);
      const Twist e = pose_error(forward_kinematics(urdf, q), forward_kinematics(chain, q));
      ASSERT_LT(e.norm(), kPoseTol) << file << " " << test::seed_text(seed) << " case " << n;
    }
    for (std::size_t i = 0; i < 6; ++i) {
      EXPECT_EQ(chain.joints[i].name, urdf.joints[i].name);
      EXPECT_EQ(chain.joints[i].velocity_limit, urdf.joints[i].velocity_limit);
      EXPECT_EQ(chain.joints[i].effort_limit, urdf.joints[i].effort_limit);
    }
  }
}

TEST(OwnModel, AMenagerieStyleArmRunsOnMotorsAndItsOwnKinematics) {
  const Simulator sim(menagerie_arm(), own("attachment_site"));
  // its position servos became motors, named, each at its force range
  EXPECT_EQ(sim.replaced_actuators(),
            (std::vector<std::string>{"shoulder_pan", "shoulder_lift", "elbow", "wrist_1", "wrist_2", "wrist_3"}));
  const JointVector torque = sim.torque_limits();
  for (int i = 0; i < 6; ++i) EXPECT_EQ(torque[i], i < 3 ? 150 : 28) << i;
  EXPECT_FALSE(sim.elastic());
  // the chain (anchors off the bodies' origins, a body without joint, quarter turns) against
  // MuJoCo's own kinematics of the site
  const KinematicChain chain = sim.kinematic_chain();
  ASSERT_EQ(chain.joints.size(), 6u);
  EXPECT_EQ(chain.joints[2].lower, -3.1415);
  const std::vector<int> qpos = motor_qpos(sim, chain);
  const int site = mj_name2id(&sim.model(), mjOBJ_SITE, "attachment_site");
  const std::uint64_t seed = 42;
  auto rng = test::make_rng(seed);
  for (int n = 0; n < test::property_cases(200); ++n) {
    JointVector q;
    for (int i = 0; i < 6; ++i) q[i] = test::uniform(rng, -3, 3);
    const Twist e = pose_error(forward_kinematics(chain, q), mujoco_pose(sim, qpos, q, site, -1));
    ASSERT_LT(e.norm(), kPoseTol) << test::seed_text(seed) << " case " << n;
  }
  // the TCP as a body's frame instead
  const Simulator by_body(menagerie_arm(), own("", "wrist_3_link"));
  const KinematicChain body_chain = by_body.kinematic_chain();
  const int body = mj_name2id(&by_body.model(), mjOBJ_BODY, "wrist_3_link");
  JointVector q;
  q << 0.3, -1.2, 1.4, -0.5, 0.8, 2.0;
  EXPECT_LT(pose_error(forward_kinematics(body_chain, q), mujoco_pose(by_body, qpos, q, -1, body)).norm(), kPoseTol);
  // a short motion on the motors: tracked, nothing diverges
  JointTrajectory reference;
  reference.dt = 0.002;
  JointVector start;
  start << 0, -1.57, 1.57, -1.57, -1.57, 0;
  for (int k = 0; k <= 100; ++k) {
    JointVector p = start;
    p[0] += 0.2 * (1 - std::cos(std::numbers::pi * k / 100.0)) / 2;
    reference.q.push_back(p);
  }
  RunOptions options;
  options.settle_time = 0.3;
  const Trace trace = sim.run(reference, tune_servo(sim, start), options);
  ASSERT_FALSE(trace.diverged) << trace.warning;
  EXPECT_LT((trace.samples.back().q_measured - reference.q.back()).cwiseAbs().maxCoeff(), 1e-3);
}

TEST(OwnModel, ItsActuatorsAreReplacedOnlyWhenAskedAndOnlyWhenTheyStateATorqueLimit) {
  const std::string path = menagerie_arm();
  // as is: refused, naming the first actuator and what the simulator needs
  test::expect_input_error([&] { (void)Simulator(path); }, {.field = "actuator", .message = "actuator 'shoulder_pan' must be a direct-torque <motor>"});
  // no site "tcp" and none named: said
  ModelChanges motors_only;
  motors_only.own_actuators_to_motors = true;
  test::expect_input_error([&] { (void)Simulator(path, motors_only); }, {.field = "site", .message = "no site named 'tcp'"});
  test::expect_input_error([&] { (void)Simulator(path, own("flange")); }, {.field = "site", .message = "no site named 'flange'"});
  test::expect_input_error([&] { (void)Simulator(path, own("", "gripper")); }, {.field = "body", .message = "no moving body named 'gripper'"});
  // an actuator without a force range cannot become a motor: named
  static const test::ScratchDir dir("own_model_test");
  std::string text = test::read_file(path);
  const std::string limit = "forcerange=\"-150 150\"";
  text.replace(text.find(limit), limit.size(), "");
  (void)dir.write("base_shell.obj", test::read_file(test::source_path("tests/data/menagerie_style/base_shell.obj")));
  const std::string unlimited = dir.write("arm.xml", text);
  test::expect_input_error([&] { (void)Simulator(unlimited, own("attachment_site")); },
                           {.field = "actuator", .message = "actuator 'shoulder_pan' has no forcerange"});
}

}  // namespace
}  // namespace blendbench
