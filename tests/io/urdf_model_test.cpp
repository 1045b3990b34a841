// The MuJoCo model built from a URDF alone (io/urdf_model.hpp): compiled by MuJoCo, it
// reproduces the URDF's kinematics, masses and torque limits; a kinematics-only URDF is refused
// naming what it lacks, or gets the stated estimate, whose torque limits hold the estimated arm
// against gravity in any pose with the stated margin.

#include "blendbench/io/urdf_model.hpp"

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <fstream>
#include <sstream>

#include "blendbench/io/urdf_chain.hpp"
#include "blendbench/sim/simulator.hpp"
#include "support/input_error.hpp"
#include "support/property.hpp"
#include "support/scratch.hpp"

namespace blendbench {
namespace {

constexpr double kPoseTol = 1e-9;  // m and rad

std::string text_of(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Writes `text` to <name>.urdf in this test process's own directory (removed at exit).
std::string write_file(const std::string& name, const std::string& text) {
  static const test::ScratchDir dir("urdf_model_test");
  return dir.write(name + ".urdf", text);
}

// The total mass of the moving bodies (every body but the world).
double moving_mass(const mjModel& m) {
  double sum = 0;
  for (int b = 1; b < m.nbody; ++b) sum += m.body_mass[b];
  return sum;
}

TEST(UrdfModel, ReproducesTheUrdfsKinematicsMassesAndTorqueLimits) {
  const std::string urdf = test::source_path("models/kr6_like.urdf");
  const UrdfModel built = model_from_urdf(urdf, "", "", 0);
  const KinematicChain chain = load_urdf_chain(urdf);
  const Simulator sim = Simulator::from_xml_string(built.mjcf);
  EXPECT_FALSE(sim.elastic());
  const mjModel& m = sim.model();
  // the moving links of models/kr6_like (carousel 10, upper arm 8, elbow 6, forearm 3, wrist 1.6,
  // flange 0.35 kg)
  EXPECT_NEAR(moving_mass(m), 28.95, 1e-12);
  for (int i = 0; i < 6; ++i) EXPECT_EQ(sim.torque_limits()[i], chain.joints[static_cast<std::size_t>(i)].effort_limit) << i;
  for (int i = 0; i < 6; ++i) EXPECT_EQ(sim.limits().velocity[i], chain.joints[static_cast<std::size_t>(i)].velocity_limit) << i;
  // same TCP at random configurations within the limits
  mjData* d = mj_makeData(&m);
  const int tcp = mj_name2id(&m, mjOBJ_SITE, "tcp");
  ASSERT_GE(tcp, 0);
  const std::uint64_t seed = 77;
  auto rng = test::make_rng(seed);
  for (int n = 0; n < test::property_cases(100); ++n) {
    JointVector q;
    for (std::size_t i = 0; i < 6; ++i) {
      q[static_cast<Eigen::Index>(i)] = test::uniform(rng, chain.joints[i].lower, chain.joints[i].upper);
      d->qpos[m.jnt_qposadr[mj_name2id(&m, mjOBJ_JOINT, chain.joints[i].name.c_str())]] = q[static_cast<Eigen::Index>(i)];
    }
    mj_kinematics(&m, d);
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.translation() = Eigen::Map<const Vec3>(d->site_xpos + 3 * tcp);
    pose.linear() = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(d->site_xmat + 9 * tcp);
    const Twist error = pose_error(forward_kinematics(chain, q), pose);
    ASSERT_LT(error.head<3>().norm(), kPoseTol) << test::seed_text(seed) << " case " << n;
    ASSERT_LT(error.tail<3>().norm(), kPoseTol) << test::seed_text(seed) << " case " << n;
  }
  mj_deleteData(d);
  // what was left out is said
  ASSERT_FALSE(built.notes.empty());
  EXPECT_NE(built.notes.front().find("capsules"), std::string::npos) << built.notes.front();
}

TEST(UrdfModel, AKinematicsOnlyUrdfIsRefusedNamingWhatItLacks) {
  const std::string bare = test::source_path("models/offset_wrist_kinematic.urdf");
  test::expect_input_error([&] { (void)model_from_urdf(bare, "", "", 0); },
                           {.file = bare, .field = "inertial",
                            .message = "the links moved by joints 'joint_a1', 'joint_a2', 'joint_a3', 'joint_a4', 'joint_a5', "
                                       "'joint_a6' have no <inertial>"});
  // inertias but no efforts: the joints are named
  std::string text = text_of(test::source_path("models/kr6_like.urdf"));
  for (const char* effort : {"effort=\"333\"", "effort=\"54\""}) {
    for (std::size_t at; (at = text.find(effort)) != std::string::npos;) text.replace(at, std::string(effort).size(), "effort=\"0\"");
  }
  const std::string no_effort = write_file("no_effort", text);
  test::expect_input_error([&] { (void)model_from_urdf(no_effort, "", "", 0); },
                           {.file = no_effort, .field = "effort",
                            .message = "joints 'joint_a1', 'joint_a2', 'joint_a4', 'joint_a5' have no positive effort limit"});
}

TEST(UrdfModel, TheEstimateIsStatedAndItsTorquesHoldTheArmAnywhere) {
  const std::string bare = test::source_path("models/offset_wrist_kinematic.urdf");
  const UrdfModel built = model_from_urdf(bare, "", "", 29);
  const Simulator sim = Simulator::from_xml_string(built.mjcf);
  EXPECT_NEAR(moving_mass(sim.model()), 29, 1e-9);
  // the torque limit is kEffortMargin times a bound of the gravity torque over every
  // configuration: at any of them gravity takes at most 1 / kEffortMargin of it (the bound at
  // q = 0 alone, used before, was exceeded by 1.1e-4 at 1500 random poses)
  const std::uint64_t seed = 78;
  auto rng = test::make_rng(seed);
  double largest_share = 0;
  for (int n = 0; n < test::property_cases(300); ++n) {
    JointVector q;
    for (std::size_t i = 0; i < 6; ++i) {
      q[static_cast<Eigen::Index>(i)] = test::uniform(rng, built.chain.joints[i].lower, built.chain.joints[i].upper);
    }
    const JointVector gravity = sim.gravity_torque(q);
    for (int i = 0; i < 6; ++i) {
      const double share = std::abs(gravity[i]) / sim.torque_limits()[i];
      largest_share = std::max(largest_share, share);
      ASSERT_LE(share, 1 / kEffortMargin + 1e-12) << test::seed_text(seed) << " case " << n << " joint " << i;
    }
  }
  // the bound is reached where the offsets line up, as the stretched arm nearly does: some pose
  // comes close to it
  EXPECT_GT(largest_share, 0.3 / kEffortMargin);
  // the notes say what was estimated and replaced
  std::string notes;
  for (const std::string& note : built.notes) notes += note + "\n";
  EXPECT_NE(notes.find("estimated masses and inertias (robot.estimate_inertia, 29 kg"), std::string::npos) << notes;
  EXPECT_NE(notes.find("estimated torque limits"), std::string::npos) << notes;
  EXPECT_NE(notes.find("7 visual meshes replaced by simple shapes (7 of them missing"), std::string::npos) << notes;
}

TEST(UrdfModel, NamesFromTheUrdfAreTextNeverMarkup) {
  // issue 42: a robot name that closed the model and included another file changed gravity (any
  // file could be included); names are now written escaped, so the model is the URDF's
  static const test::ScratchDir dir("urdf_model_injection");
  const std::string evil = dir.write("evil.xml", "<mujoco><option gravity=\"0 0 100\"/></mujoco>");
  const std::string injected = "\"><include file=\"" + evil + "\"/></mujoco><mujoco model=\"";
  std::string escaped;
  for (const char c : injected) escaped += c == '"' ? std::string("&quot;") : c == '<' ? "&lt;" : c == '>' ? "&gt;" : std::string(1, c);
  std::string text = text_of(test::source_path("models/kr6_like.urdf"));
  const std::size_t name_at = text.find("<robot name=\"");
  ASSERT_NE(name_at, std::string::npos);
  const std::size_t value_at = name_at + std::string("<robot name=\"").size();
  text.replace(value_at, text.find('"', value_at) - value_at, escaped);
  // a joint named with markup as well
  for (std::size_t at; (at = text.find("\"joint_a1\"")) != std::string::npos;) text.replace(at, 10, "\"a1 &lt;/joint&gt;&amp;\"");
  const std::string urdf = write_file("injected", text);
  const UrdfModel built = model_from_urdf(urdf, "", "", 0);
  EXPECT_EQ(built.mjcf.find("<include"), std::string::npos) << built.mjcf.substr(0, 300);
  const Simulator sim = Simulator::from_xml_string(built.mjcf);
  const mjModel& m = sim.model();
  EXPECT_EQ(std::string(m.names), injected + "_from_urdf");
  EXPECT_EQ(m.opt.gravity[2], -9.81);
  EXPECT_EQ(std::string(mj_id2name(&m, mjOBJ_JOINT, 0)), "a1 </joint>&");
  EXPECT_EQ(std::string(mj_id2name(&m, mjOBJ_ACTUATOR, 0)), "a1 </joint>&");
}

}  // namespace
}  // namespace blendbench
