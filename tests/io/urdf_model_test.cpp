// The MuJoCo model built from a URDF alone (io/urdf_model.hpp): compiled by MuJoCo, it
// reproduces the URDF's kinematics, masses and torque limits; a kinematics-only URDF is refused
// naming what it lacks, or gets the stated estimate, whose torque limits hold the estimated arm
// against gravity in any pose with the stated margin.

#include "blendbench/io/urdf_model.hpp"

#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "blendbench/core/format.hpp"
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
  // each joint's rotor inertia is the link inertia it moves at the URDF's zero pose, as MuJoCo's
  // own mass matrix gives it (an independent computation: composite rigid bodies)
  for (int i = 0; i < 6; ++i) {
    const double link = sim.link_inertia(JointVector::Zero())[i];
    EXPECT_GT(sim.motor_inertia()[i], 0) << i;
    EXPECT_NEAR(sim.motor_inertia()[i], link, 1e-9 * link) << i;
  }
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

// The smallest of A + B - C over the permutations of a body's principal moments, over their sum:
// MuJoCo refuses a body below 0 (within its tolerance). An estimated rod of length l (at least
// kMinLinkLength, radius r = kRodRadius) keeps min(r^2 / 2, l^2 / 6) / (r^2 + l^2 / 6): 0.207 at
// l = kMinLinkLength, falling as a long rod thins (0.013 at 0.6 m, 0.0048 at 1 m); a rod of
// zero length, as estimated before, had 0 (and MuJoCo refused it by rounding).
double triangle_margin(const mjModel& m, int body) {
  const double* d = m.body_inertia + 3 * body;
  double worst = std::numeric_limits<double>::infinity();
  for (int c = 0; c < 3; ++c) worst = std::min(worst, (d[(c + 1) % 3] + d[(c + 2) % 3] - d[c]) / (d[0] + d[1] + d[2]));
  return worst;
}

TEST(UrdfModel, ARosIndustrialStyleUrdfRunsWithOnlyAMassEstimate) {
  // tests/data/ros_industrial_style.urdf: `base` beside the chain, flange and tool0 side by side
  // on link_6, no <inertial>, effort 0, package:// meshes, zero-length links (link_4: joint_5 at
  // joint_4; link_6: tool0 at joint_6) and coincident frames (joint_1 at base_link). Before: the
  // tip was refused as ambiguous ('base', 'flange', 'tool0'), and naming tool0, MuJoCo refused
  // joint_6_body's estimate (A + B >= C: a rod of zero length).
  const std::string urdf = test::source_path("tests/data/ros_industrial_style.urdf");
  const UrdfModel built = model_from_urdf(urdf, "", "", 25);
  EXPECT_EQ(built.chain.joints.back().name, "joint_6");
  const Simulator sim = Simulator::from_xml_string(built.mjcf);
  const mjModel& m = sim.model();
  EXPECT_NEAR(moving_mass(m), 25, 1e-9);
  // every body a valid inertia with margin (its links are at most 0.37 m long: at least 0.02);
  // the zero-length ones the margin of a rod of kMinLinkLength
  for (int b = 1; b < m.nbody; ++b) EXPECT_GT(triangle_margin(m, b), 0.02) << mj_id2name(&m, mjOBJ_BODY, b);
  // the zero-length links get the mass share of kMinLinkLength, centred at their joint
  const int link4 = mj_name2id(&m, mjOBJ_BODY, "joint_4_body");
  const int link6 = mj_name2id(&m, mjOBJ_BODY, "joint_6_body");
  ASSERT_GE(link4, 0);
  ASSERT_GE(link6, 0);
  EXPECT_NEAR(m.body_mass[link4], m.body_mass[link6], 1e-12);
  EXPECT_GT(triangle_margin(m, link4), 0.2);
  EXPECT_GT(triangle_margin(m, link6), 0.2);
  EXPECT_LT(Eigen::Map<const Vec3>(m.body_ipos + 3 * link6).norm(), 1e-12);
  // the model holds still under its estimated torque limits, and gravity at the stretched pose
  // takes no more than 1 / kEffortMargin of them
  const JointVector gravity = sim.gravity_torque(JointVector::Zero());
  for (int i = 0; i < 6; ++i) EXPECT_LE(std::abs(gravity[i]), sim.torque_limits()[i] / kEffortMargin + 1e-12) << i;
  // the meshes are listed as replaced (7 visual meshes, none of them here)
  std::string notes;
  for (const std::string& note : built.notes) notes += note + "\n";
  EXPECT_NE(notes.find("7 visual meshes replaced by simple shapes (7 of them missing here, e.g. 'package://style_support/"),
            std::string::npos)
      << notes;
  EXPECT_NE(notes.find("estimated masses and inertias (robot.estimate_inertia, 25 kg"), std::string::npos) << notes;
}

TEST(UrdfModel, EveryEstimatedBodyIsValidWhateverItsLength) {
  // random kinematics-only arms whose offsets are zero, tiny (1e-9 .. 1e-3 m) or ordinary, in
  // random directions and with random frame rotations: MuJoCo compiles every estimate, each body
  // keeps a clear triangle margin, and the masses add up
  const std::uint64_t seed = 79;
  auto rng = test::make_rng(seed);
  const char* axes[] = {"1 0 0", "0 1 0", "0 0 1"};
  for (int n = 0; n < test::property_cases(60); ++n) {
    std::string text = "<robot name='random'><link name='base_link'/>";
    for (int i = 1; i <= 6; ++i) text += "<link name='l" + std::to_string(i) + "'/>";
    text += "<link name='tool0'/><link name='flange'/><link name='base'/>";
    const auto offset = [&] {
      const double kind = test::uniform(rng, 0, 3);
      const double length = kind < 1 ? 0 : kind < 2 ? test::log_uniform(rng, 1e-9, 1e-3) : test::uniform(rng, 0.01, 0.6);
      Vec3 dir(test::uniform(rng, -1, 1), test::uniform(rng, -1, 1), test::uniform(rng, -1, 1));
      if (dir.norm() < 1e-3) dir = Vec3::UnitX();
      const Vec3 v = length * dir.normalized();
      return format_value(v.x(), 17) + " " + format_value(v.y(), 17) + " " + format_value(v.z(), 17);
    };
    const auto rpy = [&] {
      return format_value(test::uniform(rng, -3, 3), 17) + " " + format_value(test::uniform(rng, -1.5, 1.5), 17) + " " +
             format_value(test::uniform(rng, -3, 3), 17);
    };
    std::string parent = "base_link";
    for (int i = 1; i <= 6; ++i) {
      const std::string number = std::to_string(i);  // (named: GCC 12's -Wrestrict on "l" + a temporary)
      const std::string child = "l" + number;
      text += "<joint name='j" + number + "' type='revolute'><parent link='" + parent + "'/><child link='" + child +
              "'/><origin xyz='" + offset() + "' rpy='" + rpy() + "'/><axis xyz='" +
              axes[static_cast<int>(test::uniform(rng, 0, 2.999))] +
              "'/><limit effort='0' lower='-2' upper='2' velocity='3'/></joint>";
      parent = child;
    }
    text += "<joint name='t' type='fixed'><parent link='l6'/><child link='tool0'/><origin xyz='" + offset() + "'/></joint>";
    text += "<joint name='f' type='fixed'><parent link='l6'/><child link='flange'/></joint>";
    text += "<joint name='b' type='fixed'><parent link='base_link'/><child link='base'/></joint></robot>";
    const std::string urdf = write_file("random", text);
    const double mass = test::uniform(rng, 1, 500);
    const UrdfModel built = model_from_urdf(urdf, "", "", mass);
    const Simulator sim = Simulator::from_xml_string(built.mjcf);
    const mjModel& m = sim.model();
    ASSERT_NEAR(moving_mass(m), mass, 1e-9 * mass) << test::seed_text(seed) << " case " << n;
    for (int b = 1; b < m.nbody; ++b) {
      ASSERT_GT(triangle_margin(m, b), 0.004) << test::seed_text(seed) << " case " << n << " body " << b << "\n" << text;
      ASSERT_TRUE(std::isfinite(m.body_inertia[3 * b]) && m.body_inertia[3 * b] > 0) << test::seed_text(seed) << " case " << n;
    }
  }
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
