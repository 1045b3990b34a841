// Other arms through the whole pipeline: the second arm (models/kr6_like.*, offset shoulder and
// spherical wrist) running the default program (scenarios/kr6_default.yaml), the singularity
// scan and the refused IK branch change on it, and a tool frame on the UR5e-like arm. Without
// video or plots, two variants at most, so it stays fast.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "blendbench/app/runner.hpp"
#include "blendbench/io/scenario.hpp"
#include "blendbench/io/urdf_chain.hpp"
#include "blendbench/robot/kinematics.hpp"
#include "support/files.hpp"
#include "support/input_error.hpp"
#include "support/scratch.hpp"
#include "support/property.hpp"

namespace blendbench {
namespace {

namespace fs = std::filesystem;

// The tracking error the tuned cascade keeps on either arm at 250 mm/s (m): the UR5e-like arm's
// end-to-end bound.
constexpr double kTrackingBound = 0.3e-3;

class Robots : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("blendbench_robots_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  RunResult run(const Scenario& sc, std::vector<std::string> variants) {
    RunRequest request;
    request.out_dir = dir_;
    request.video = false;
    request.plots = false;
    RunSelection selection;
    selection.variants = std::move(variants);
    return run_pipeline(resolve_run(sc, selection), request);
  }

  // scenarios/kr6_default.yaml with one text replacement, parsed where it lies.
  static Scenario kr6_with(const std::string& from, const std::string& to) {
    std::ifstream in(test::source_path("scenarios/kr6_default.yaml"));
    std::stringstream text;
    text << in.rdbuf();
    std::string s = text.str();
    if (!from.empty()) {
      const auto at = s.find(from);
      EXPECT_NE(at, std::string::npos) << from;
      s.replace(at, from.size(), to);
    }
    return parse_scenario(s, "kr6.yaml", test::source_path("scenarios"));
  }

  fs::path dir_;
};

TEST_F(Robots, SecondArmRunsTheDefaultProgram) {
  const RunResult r = run(load_scenario(test::source_path("scenarios/kr6_default.yaml")), {"exact_stop", "biclothoid_2mm"});
  EXPECT_TRUE(r.all_ok);
  EXPECT_EQ(r.summary.robot.ik_method, IkMethod::kSphericalWristClosedForm);
  EXPECT_TRUE(r.summary.robot.mjcf.ends_with("models/kr6_like.xml")) << r.summary.robot.mjcf;
  ASSERT_EQ(r.summary.robot.joints.size(), 6u);
  EXPECT_EQ(r.summary.robot.joints[0].name, "joint_a1");
  // its own elastic model: the first arm mode of a KR 6-class arm, 20-30 Hz
  EXPECT_GT(r.summary.robot.natural_frequency_arm[0], 20);
  EXPECT_LT(r.summary.robot.natural_frequency_arm[0], 30);
  ASSERT_EQ(r.summary.variants.size(), 2u);
  for (const VariantSummary& v : r.summary.variants) {
    SCOPED_TRACE(v.name);
    ASSERT_TRUE(v.metrics.has_value());
    EXPECT_TRUE(v.metrics->cycle_time.has_value());
    EXPECT_LT(v.metrics->tracking_error_max, kTrackingBound);
    EXPECT_LT(v.metrics->contour_error_planned_max, kTrackingBound);
    // placed where its wrist stays well away from the singularity
    EXPECT_TRUE(v.singularities.empty()) << v.singularities.size() << " passages";
    EXPECT_TRUE(v.branch_changes.empty());
    // the joint-space limits of this arm, used within bounds: shares of its own limits, and the
    // URDF's position range never left
    ASSERT_TRUE(v.joint_usage.has_value());
    const JointUsage& u = *v.joint_usage;
    for (int i = 0; i < 6; ++i) {
      EXPECT_NEAR(u.velocity_share[i], v.metrics->velocity_peak[i] / r.summary.robot.limits.velocity[i], 1e-15) << i;
      EXPECT_NEAR(u.torque_share[i], v.metrics->torque_peak[i] / r.summary.robot.joints[static_cast<std::size_t>(i)].effort_limit,
                  1e-12) << i;
      EXPECT_GT(u.velocity_share[i], 0) << i;
      EXPECT_LE(u.velocity_share[i], 1) << i;
      EXPECT_LE(u.acceleration_share[i], 1) << i;
      EXPECT_LE(u.torque_share[i], 1) << i;
      EXPECT_GT(u.position_margin[i], 0) << i;
    }
  }
  // the blend saves cycle time on this arm as on the other
  EXPECT_LT(*r.summary.variants[1].metrics->cycle_time, *r.summary.variants[0].metrics->cycle_time);
}

TEST_F(Robots, AtTableHeightTheWristPassesNearItsSingularityAndBelowItCrossesIt) {
  // at z 200 mm the forearm hangs nearly vertical: the scan reports the wrist passage with its
  // time, pose and measure (sin q5), and the run still goes through
  const RunResult near = run(kr6_with("origin: [450, -180, 450]", "origin: [400, -180, 200]"), {"exact_stop"});
  ASSERT_EQ(near.summary.variants.size(), 1u);
  const VariantSummary& v = near.summary.variants[0];
  ASSERT_FALSE(v.singularities.empty());
  const SingularityPassage& p = v.singularities.front();
  EXPECT_EQ(p.kind, SingularityKind::kWrist);
  EXPECT_LT(p.measure, 0.01);
  EXPECT_EQ(p.threshold, kWristSine);
  EXPECT_LE(p.t_start, p.t);
  EXPECT_LE(p.t, p.t_end);
  EXPECT_NEAR(p.pose.translation().z(), 0.200, 1e-9);
  EXPECT_TRUE(v.branch_changes.empty());
  // at z 150 mm it crosses: the variant fails alone, naming the move and the pose, unless the
  // scenario allows it
  const RunResult refused = run(kr6_with("origin: [450, -180, 450]", "origin: [400, -180, 150]"), {"exact_stop"});
  ASSERT_EQ(refused.summary.variants.size(), 1u);
  EXPECT_FALSE(refused.all_ok);
  const VariantSummary& r = refused.summary.variants[0];
  EXPECT_EQ(r.status, VariantStatus::kFailed);
  EXPECT_NE(r.message.find("IK branch change: the wrist measure changes sign"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("program.moves[0]"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("150.000) mm"), std::string::npos) << r.message;
  EXPECT_NE(r.message.find("at t = "), std::string::npos) << r.message;
  Scenario allowed = kr6_with("origin: [450, -180, 450]", "origin: [400, -180, 150]");
  allowed.robot.allow_branch_change = true;
  const RunResult crossed = run(allowed, {"exact_stop"});
  ASSERT_EQ(crossed.summary.variants.size(), 1u);
  const VariantSummary& c = crossed.summary.variants[0];
  ASSERT_FALSE(c.branch_changes.empty());
  EXPECT_EQ(c.branch_changes.front().kind, SingularityKind::kWrist);
  EXPECT_LT(c.branch_changes.front().before * c.branch_changes.front().after, 0);
}

TEST_F(Robots, AUrdfAloneRuns) {
  // scenarios/urdf_only.yaml: a kinematics-only URDF without a closed form, the dynamics built
  // from it with the stated estimate, the notes in the summary
  const RunResult r = run(load_scenario(test::source_path("scenarios/urdf_only.yaml")), {"exact_stop"});
  EXPECT_TRUE(r.all_ok);
  EXPECT_EQ(r.summary.robot.ik_method, IkMethod::kNumeric);
  EXPECT_EQ(r.summary.robot.model, ArmModel::kRigid);
  EXPECT_EQ(fs::path(r.summary.robot.mjcf), dir_ / "robot_from_urdf.xml");
  EXPECT_TRUE(fs::is_regular_file(r.summary.robot.mjcf));
  ASSERT_GE(r.summary.robot.notes.size(), 3u);
  EXPECT_NE(r.summary.robot.notes[0].find("estimated masses"), std::string::npos) << r.summary.robot.notes[0];
  for (const JointSpec& j : r.summary.robot.joints) EXPECT_GT(j.effort_limit, 0) << j.name;
  ASSERT_EQ(r.summary.variants.size(), 1u);
  ASSERT_TRUE(r.summary.variants[0].metrics.has_value());
  EXPECT_LT(r.summary.variants[0].metrics->tracking_error_max, kTrackingBound);
  // elastic joints cannot come from a URDF: named at the key
  Scenario elastic = load_scenario(test::source_path("scenarios/urdf_only.yaml"));
  elastic.robot.model_where.line = 13;
  test::expect_input_error([&] { (void)run(elastic, {"exact_stop"}); },
                           {.line = 13, .field = "robot.model", .message = "elastic joints need gear stiffnesses"});
}

TEST_F(Robots, AnMjcfOfTheUsersOwnRuns) {
  // tests/data/menagerie_style/scenario.yaml: robot.mjcf with tip_site and no URDF, the arm in
  // MuJoCo Menagerie's style (position servos, a mesh, no site "tcp"); the chain comes from the
  // MJCF, its servos become motors, both said in the notes
  const RunResult r = run(load_scenario(test::source_path("tests/data/menagerie_style/scenario.yaml")), {"exact"});
  EXPECT_TRUE(r.all_ok);
  EXPECT_EQ(r.summary.robot.urdf, "");
  EXPECT_EQ(r.summary.robot.model, ArmModel::kRigid);
  ASSERT_EQ(r.summary.robot.notes.size(), 2u);
  EXPECT_NE(r.summary.robot.notes[0].find("read from the MJCF"), std::string::npos) << r.summary.robot.notes[0];
  EXPECT_NE(r.summary.robot.notes[1].find("'shoulder_pan', 'shoulder_lift', 'elbow', 'wrist_1', 'wrist_2', 'wrist_3' replaced"),
            std::string::npos)
      << r.summary.robot.notes[1];
  ASSERT_EQ(r.summary.variants.size(), 1u);
  ASSERT_TRUE(r.summary.variants[0].metrics.has_value());
  EXPECT_LT(r.summary.variants[0].metrics->tracking_error_max, kTrackingBound);
  // the keys are checked where they are given
  static const test::ScratchDir dir("robots_own_mjcf");
  const std::string text = test::read_file(test::source_path("tests/data/menagerie_style/scenario.yaml"));
  const auto variant = [&](const std::string& from, const std::string& to) {
    std::string t = text;
    t.replace(t.find(from), from.size(), to);
    (void)dir.write("arm.xml", test::read_file(test::source_path("tests/data/menagerie_style/arm.xml")));
    (void)dir.write("base_shell.obj", test::read_file(test::source_path("tests/data/menagerie_style/base_shell.obj")));
    return dir.write("scenario.yaml", t);
  };
  const std::string with_urdf = variant("  tip_site: attachment_site", "  tip_site: attachment_site\n  urdf: arm.xml");
  test::expect_input_error([&] { (void)load_scenario(with_urdf); }, {.field = "robot.urdf", .message = "not both"});
  const std::string no_mjcf = variant("  mjcf: arm.xml\n", "");
  test::expect_input_error([&] { (void)load_scenario(no_mjcf); }, {.field = "robot.tip_site", .message = "give robot.mjcf"});
  const std::string no_site = variant("tip_site: attachment_site", "tip_site: flange");
  test::expect_input_error([&] { (void)run(load_scenario(no_site), {"exact"}); }, {.message = "no site named 'flange'"});
}

TEST_F(Robots, ToolFrameCarriesTheTcp) {
  // a 100 mm tool along the flange's z: the path is the tool's, the flange runs 100 mm above it
  const char* const text = R"(name: tool
units: mm
frame: {origin: [400, -50, 250], rpy_deg: [0, 0, 0]}
robot: {tool: {offset: [0, 0, 100]}}
defaults: {velocity: 200, acceleration: 2000, jerk: 20000}
simulation: {settle_tolerance: 0.05, settle_time_s: 0.5}
program:
  start: [0, 0, 0]
  moves:
    - line: [100, 0, 0]
variants:
  - {name: exact, transition: {method: none}}
)";
  const RunResult r = run(parse_scenario(text, "tool.yaml", test::source_path("scenarios")), {});
  EXPECT_TRUE(r.all_ok);
  EXPECT_TRUE(r.summary.robot.tool.translation().isApprox(Vec3(0, 0, 0.1), 1e-15));
  const KinematicChain flange = load_urdf_chain(test::source_path("models/ur5e_like.urdf"));
  const Eigen::Isometry3d at_start = forward_kinematics(flange, r.summary.robot.start_q);
  EXPECT_LT((at_start.translation() - Vec3(0.4, -0.05, 0.35)).norm(), 1e-9) << at_start.translation().transpose();
  ASSERT_EQ(r.summary.variants.size(), 1u);
  ASSERT_TRUE(r.summary.variants[0].metrics.has_value());
  // the errors are the tool's: a 100 mm lever on the wrist's small tracking errors, still bounded
  EXPECT_LT(r.summary.variants[0].metrics->contour_error_planned_max, kTrackingBound);
}

}  // namespace
}  // namespace blendbench
