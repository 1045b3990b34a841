#include "blendbench/io/urdf_chain.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <fstream>
#include <numbers>
#include <string>

#include "support/files.hpp"
#include "support/input_error.hpp"
#include "support/property.hpp"
#include "support/scratch.hpp"
#include "blendbench/core/input_error.hpp"

namespace blendbench {
namespace {

constexpr double kExact = 1e-12;  // m, rad: values written in the file

// Writes `text` to <name>.urdf in this test process's own directory (removed at exit) and returns
// its path: the tests run side by side and write files of the same names.
std::string write_file(const std::string& name, const std::string& text) {
  static const test::ScratchDir dir("urdf_chain_test");
  return dir.write(name + ".urdf", text);
}

// A six-joint arm with fixed joints before, between and after the movable ones; `joint4` is
// the fourth joint's element, replaceable to build broken files.
std::string arm_urdf(const std::string& joint4 = R"(
  <joint name="j4" type="continuous">
    <parent link="l3"/><child link="l4"/>
    <origin xyz="0 0 0.1" rpy="0 0 0"/><axis xyz="0 1 0"/>
    <limit velocity="2" effort="20"/>
  </joint>)") {
  std::string text = R"(<?xml version="1.0"?>
<robot name="arm">
  <link name="world"/><link name="base_link"/><link name="l1"/><link name="l2"/><link name="l2b"/>
  <link name="l3"/><link name="l4"/><link name="l5"/><link name="l6"/><link name="flange"/><link name="tcp"/>
  <joint name="mount" type="fixed">
    <parent link="world"/><child link="base_link"/><origin xyz="1 2 3" rpy="0 0 0"/>
  </joint>
  <joint name="j1" type="revolute">
    <parent link="base_link"/><child link="l1"/>
    <origin xyz="0 0 0.2" rpy="0 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-3" upper="3" velocity="3" effort="150"/>
  </joint>
  <joint name="j2" type="revolute">
    <parent link="l1"/><child link="l2"/>
    <origin xyz="0 0 0" rpy="1.5707963267948966 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-2" upper="2" velocity="3" effort="150"/>
  </joint>
  <joint name="bracket" type="fixed">
    <parent link="l2"/><child link="l2b"/><origin xyz="0.3 0 0" rpy="0 0 0.5"/>
  </joint>
  <joint name="j3" type="revolute">
    <parent link="l2b"/><child link="l3"/>
    <origin xyz="0.1 0 0" rpy="0 0 0"/><axis xyz="0 0 2"/>
    <limit lower="-1" upper="1" velocity="3" effort="150"/>
  </joint>)";
  text += joint4;
  text += R"(
  <joint name="j5" type="revolute">
    <parent link="l4"/><child link="l5"/>
    <origin xyz="0 0 0.1" rpy="0 0 0"/><axis xyz="1 0 0"/>
    <limit lower="-4" upper="4" velocity="2" effort="20"/>
  </joint>
  <joint name="j6" type="revolute">
    <parent link="l5"/><child link="l6"/>
    <origin xyz="0 0 0.1" rpy="0 0 0"/><axis xyz="0 0 1"/>
    <limit lower="-5" upper="5" velocity="2" effort="20"/>
  </joint>
  <joint name="to_flange" type="fixed">
    <parent link="l6"/><child link="flange"/><origin xyz="0 0 0.05" rpy="0 0 0"/>
  </joint>
  <joint name="to_tcp" type="fixed">
    <parent link="flange"/><child link="tcp"/><origin xyz="0 0 0.1" rpy="0 0 0"/>
  </joint>
</robot>
)";
  return text;
}

// Expects load_urdf_chain to throw an InputError for `path` with `field` whose message
// contains `words`.
void expect_input_error(const std::string& path, const std::string& field, const std::string& words,
                        const std::string& base = "base_link", const std::string& tip = "tcp") {
  test::expect_input_error([&] { (void)load_urdf_chain(path, base, tip); }, {.file = path, .field = field, .message = words},
                           path);
}

TEST(UrdfChain, ReadsTheModelArm) {
  const KinematicChain chain = load_urdf_chain(test::source_path("models/ur5e_like.urdf"));
  ASSERT_EQ(chain.joints.size(), 6u);
  const char* names[] = {"shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint",
                         "wrist_1_joint",      "wrist_2_joint",       "wrist_3_joint"};
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(chain.joints[i].name, names[i]);
    const double limit = i == 2 ? std::numbers::pi : 2 * std::numbers::pi;
    EXPECT_NEAR(chain.joints[i].lower, -limit, kExact);
    EXPECT_NEAR(chain.joints[i].upper, limit, kExact);
    EXPECT_NEAR(chain.joints[i].velocity_limit, std::numbers::pi, kExact);
    EXPECT_EQ(chain.joints[i].effort_limit, i < 3 ? 150.0 : 28.0);
  }
  EXPECT_TRUE(chain.joints[0].origin.translation().isApprox(Vec3(0, 0, 0.1625), kExact));
  // flange and tcp (zero tool offset) fold into the TCP transform
  EXPECT_TRUE(chain.tcp.translation().isApprox(Vec3(0, 0, 0.0996), kExact));
  EXPECT_TRUE(chain.tcp.linear().isIdentity(kExact));
}

TEST(UrdfChain, FoldsFixedJointsAndReadsContinuousJoints) {
  const KinematicChain chain = load_urdf_chain(write_file("arm", arm_urdf()), "base_link");
  ASSERT_EQ(chain.joints.size(), 6u);
  // base_link is the base: the mount above it is not part of the chain
  EXPECT_TRUE(chain.joints[0].origin.translation().isApprox(Vec3(0, 0, 0.2), kExact));
  // the bracket (0.3 along x, turned 0.5 rad about z) folds into j3's origin
  const Eigen::Isometry3d expected = Eigen::Translation3d(0.3, 0, 0) * Eigen::AngleAxisd(0.5, Vec3::UnitZ()) *
                                     Eigen::Translation3d(0.1, 0, 0);
  EXPECT_TRUE(chain.joints[2].origin.isApprox(expected, kExact));
  // axes are normalised
  EXPECT_TRUE(chain.joints[2].axis.isApprox(Vec3::UnitZ(), kExact));
  // a continuous joint has no position limits but keeps velocity and effort
  EXPECT_TRUE(std::isinf(chain.joints[3].lower) && chain.joints[3].lower < 0);
  EXPECT_TRUE(std::isinf(chain.joints[3].upper) && chain.joints[3].upper > 0);
  EXPECT_EQ(chain.joints[3].velocity_limit, 2.0);
  EXPECT_EQ(chain.joints[3].effort_limit, 20.0);
  EXPECT_EQ(chain.joints[4].lower, -4.0);
  // flange and tool fold into the TCP
  EXPECT_TRUE(chain.tcp.translation().isApprox(Vec3(0, 0, 0.15), kExact));
  // starting at l1 leaves five movable joints: not a six-axis arm
  EXPECT_THROW((void)load_urdf_chain(write_file("arm", arm_urdf()), "l1", "tcp"), InputError);
}

TEST(UrdfChain, FindsTheChainFromTheRootToTheOneLeafByDefault) {
  // the root "world" is the base: the mount (1, 2, 3) folds into the first joint's origin
  const KinematicChain chain = load_urdf_chain(write_file("arm", arm_urdf()));
  EXPECT_TRUE(chain.joints[0].origin.translation().isApprox(Vec3(1, 2, 3.2), kExact));
  EXPECT_TRUE(chain.tcp.translation().isApprox(Vec3(0, 0, 0.15), kExact));
  // ROS-Industrial's tool0 is found without being named
  const KinematicChain kr6 = load_urdf_chain(test::source_path("models/kr6_like.urdf"));
  EXPECT_EQ(kr6.joints.back().name, "joint_a6");
  EXPECT_TRUE(kr6.tcp.translation().isApprox(Vec3(0.02, 0, 0), kExact));
  // a second branch (a camera fixed to l2) ends after 2 movable joints, the chain after 6: the
  // camera is no candidate
  std::string text = arm_urdf();
  text.replace(text.rfind("</robot>"), 8, R"(<link name="camera"/>
  <joint name="camera_mount" type="fixed"><parent link="l2"/><child link="camera"/></joint>
</robot>)");
  const std::string branched = write_file("branched", text);
  EXPECT_TRUE(load_urdf_chain(branched, "base_link").tcp.translation().isApprox(Vec3(0, 0, 0.15), kExact));
  test::expect_input_error([&] { (void)load_urdf_chain(branched, "", "camera"); },
                           {.file = branched, .field = "tip_link", .message = "has 2 movable joints"}, branched);
}

TEST(UrdfChain, ATrueTieIsAnErrorNamingTheCandidates) {
  // two fingers on revolute joints of l6: two ends through 7 movable joints each, moving apart
  std::string text = arm_urdf();
  text.replace(text.rfind("</robot>"), 8, R"(<link name="finger_a"/><link name="finger_b"/>
  <joint name="fa" type="revolute"><parent link="l6"/><child link="finger_a"/><axis xyz="1 0 0"/>
    <limit lower="0" upper="1" velocity="1" effort="1"/></joint>
  <joint name="fb" type="revolute"><parent link="l6"/><child link="finger_b"/><axis xyz="1 0 0"/>
    <limit lower="0" upper="1" velocity="1" effort="1"/></joint>
</robot>)");
  const std::string fingers = write_file("fingers", text);
  expect_input_error(fingers, "tip_link",
                     "branches below 'base_link' into 2 ends reached through 7 movable joints each ('finger_a', 'finger_b')",
                     "base_link", "");
  EXPECT_EQ(load_urdf_chain(fingers, "base_link", "tcp").joints.size(), 6u);
  // two frames fixed to the last link side by side, neither named tool0: a tie as well
  text = arm_urdf();
  text.replace(text.rfind("</robot>"), 8, R"(<link name="camera"/>
  <joint name="camera_mount" type="fixed"><parent link="l6"/><child link="camera"/></joint>
</robot>)");
  expect_input_error(write_file("frames", text), "tip_link", "into 2 ends reached through 6 movable joints each ('camera', 'tcp')",
                     "base_link", "");
}

TEST(UrdfChain, AnyRosIndustrialStyleUrdfFindsTool0) {
  // tests/data/ros_industrial_style.urdf: a `base` frame link beside the chain, `flange` and
  // `tool0` fixed to link_6 side by side: tool0 is the end, flange and base are passed over.
  // (Its effort="0" is refused here, where the efforts are the motors' limits, naming the
  // estimate: tests/io/urdf_model_test.cpp runs it with one; here its efforts are made 10 N*m.)
  const std::string original = test::source_path("tests/data/ros_industrial_style.urdf");
  expect_input_error(original, "joint_1", "effort limit must be positive, got 0 N*m (a kinematics-only URDF: robot.estimate_inertia", "", "");
  std::string text = test::read_file(original);
  for (std::size_t at; (at = text.find("effort=\"0\"")) != std::string::npos;) text.replace(at, 10, "effort=\"10\"");
  const std::string path = write_file("ros_industrial_style", text);
  const KinematicChain chain = load_urdf_chain(path, "", "");
  ASSERT_EQ(chain.joints.size(), 6u);
  EXPECT_EQ(chain.joints.front().name, "joint_1");
  EXPECT_EQ(chain.joints.back().name, "joint_6");
  // tool0's frame: at joint_6's origin, turned 90 degrees about y (z along the flange's normal x)
  EXPECT_LT(chain.tcp.translation().norm(), kExact);
  EXPECT_TRUE(chain.tcp.linear().col(2).isApprox(Vec3(1, 0, 0), 1e-12));
  // the same chain as when tool0 is named
  const KinematicChain named = load_urdf_chain(path, "base_link", "tool0");
  EXPECT_TRUE(named.tcp.isApprox(chain.tcp, kExact));
  // naming the flange gives the flange
  EXPECT_TRUE(load_urdf_chain(path, "", "flange").tcp.linear().isApprox(Mat3::Identity(), kExact));
}

TEST(UrdfChain, RejectsUnreadableAndInvalidFiles) {
  const test::ScratchDir dir("urdf_chain_test");
  const std::string missing = (dir / "no_such_file.urdf").string();
  expect_input_error(missing, "", "cannot open");
  const std::string broken = write_file("broken", "<robot name='x'><link name='a'></robot>");
  expect_input_error(broken, "", "not well-formed XML: mismatched tag");
}

// Issue 42: inputs that crashed or exhausted the program before urdfdom's parser saw them.
TEST(UrdfChain, RefusesWhatWouldCrashOrExhaustTheParser) {
  const test::ScratchDir dir("urdf_chain_hostile");
  // 10^5 nested elements: TinyXML's recursion overflowed the stack (SIGSEGV)
  std::string deep = "<robot name='x'>";
  for (int i = 0; i < 100000; ++i) deep += "<a>";
  for (int i = 0; i < 100000; ++i) deep += "</a>";
  deep += "</robot>";
  const std::string deep_file = dir.write("deep.urdf", deep);
  test::expect_input_error([&] { (void)load_urdf_chain(deep_file); },
                           {.file = deep_file, .line = 1, .message = "elements are nested more than 64 deep"});
  // a file of 1.5 GB (sparse: no disk used) is refused by its size, before a byte is read
  const std::string huge = (dir / "huge.urdf").string();
  ASSERT_EQ(::truncate(dir.write("huge.urdf", "<robot/>").c_str(), off_t{1536} << 20), 0);
  test::expect_input_error([&] { (void)load_urdf_chain(huge); }, {.file = huge, .message = "the URDF file is 1536 MiB; the limit is 64 MiB"});
  // a FIFO is not opened (it would wait for a writer forever)
  const std::string fifo = (dir / "fifo.urdf").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  test::expect_input_error([&] { (void)load_urdf_chain(fifo); }, {.file = fifo, .message = "a FIFO (named pipe), not a regular file"});
  // entities that expand exponentially ("billion laughs"): refused by expat's amplification limit
  std::string laughs = "<?xml version='1.0'?><!DOCTYPE robot [<!ENTITY a0 'ha'>";
  for (int i = 1; i <= 30; ++i) laughs += "<!ENTITY a" + std::to_string(i) + " '&a" + std::to_string(i - 1) + ";&a" + std::to_string(i - 1) + ";'>";
  laughs += "]><robot name='&a30;'/>";
  const std::string laughs_file = dir.write("laughs.urdf", laughs);
  test::expect_input_error([&] { (void)load_urdf_chain(laughs_file); }, {.file = laughs_file, .message = "not well-formed XML"});
}

TEST(UrdfChain, RejectsMissingOrUnconnectedLinks) {
  const std::string path = write_file("arm", arm_urdf());
  expect_input_error(path, "base_link", "no link named 'base'", "base", "tcp");
  expect_input_error(path, "tip_link", "no link named 'tool0'", "base_link", "tool0");
  expect_input_error(path, "tip_link", "not below", "l3", "l1");
}

TEST(UrdfChain, RejectsUnsupportedJointsAndBadLimits) {
  expect_input_error(write_file("prismatic", arm_urdf(R"(
  <joint name="j4" type="prismatic">
    <parent link="l3"/><child link="l4"/><axis xyz="0 1 0"/>
    <limit lower="0" upper="1" velocity="2" effort="20"/>
  </joint>)")),
                     "j4", "only revolute, continuous and fixed");
  expect_input_error(write_file("no_limit", arm_urdf(R"(
  <joint name="j4" type="continuous">
    <parent link="l3"/><child link="l4"/><axis xyz="0 1 0"/>
  </joint>)")),
                     "j4", "no <limit>");
  expect_input_error(write_file("no_velocity", arm_urdf(R"(
  <joint name="j4" type="revolute">
    <parent link="l3"/><child link="l4"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" velocity="0" effort="20"/>
  </joint>)")),
                     "j4", "velocity limit must be positive");
  expect_input_error(write_file("inverted", arm_urdf(R"(
  <joint name="j4" type="revolute">
    <parent link="l3"/><child link="l4"/><axis xyz="0 1 0"/>
    <limit lower="1" upper="-1" velocity="2" effort="20"/>
  </joint>)")),
                     "j4", "above upper limit");
  expect_input_error(write_file("five", arm_urdf(R"(
  <joint name="j4" type="fixed">
    <parent link="l3"/><child link="l4"/>
  </joint>)")),
                     "tip_link", "5 movable joints");
}

}  // namespace
}  // namespace blendbench
