// The simulator's contract on a small inline rigid arm (tests/support/test_arm.hpp): loading,
// the servo-tick trace, the drive's encoder (delay, quantisation), torque limits, divergence,
// frames and bad input. The elastic UR5e-like model's physics is tested in elastic_model_test.

#include "blendbench/sim/simulator.hpp"
#include "blendbench/sim/metrics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "support/input_error.hpp"
#include "support/property.hpp"
#include "support/test_arm.hpp"
#include "blendbench/core/input_error.hpp"

namespace blendbench {
namespace {

// Holding still with gravity compensation and an exact encoder: the servo's error is zero and
// gravity is cancelled exactly, so only rounding moves the arm.
constexpr double kHoldTolerance = 1e-9;      // rad
// A sag that a gravity-loaded arm under a PD servo without gravity compensation cannot hide
// (gravity over the tuned PD's stiffness is several times this).
constexpr double kMinSag = 1e-4;             // rad, and m at the TCP
// Exact pose evaluation: recorded TCP vs forward kinematics of the recorded joints.
constexpr double kPoseTolerance = 1e-12;     // m
// Servo tick times.
constexpr double kTimeTolerance = 1e-12;     // s
// The tracking-error bound for the smooth reference under the tuned servo without feed-forward.
constexpr double kTrackingBound = 5e-3;      // rad

// Fails the test on any MuJoCo warning (MuJoCo's own test fixture does the same).
class SimulatorTest : public ::testing::Test {
 protected:
  void TearDown() override { EXPECT_EQ(take_mujoco_warnings(), ""); }
  Simulator sim_ = Simulator::from_xml_string(test::kTestArmXml);
  JointVector q0_ = test::test_arm_bent_pose();
};

// The test arm without any torque limit.
std::string unlimited_arm_xml() {
  std::string xml = test::kTestArmXml;
  for (auto p = xml.find(" ctrlrange=\""); p != std::string::npos; p = xml.find(" ctrlrange=\"")) {
    const auto close = xml.find('"', p + 12);
    xml.erase(p, close - p + 1);
  }
  return xml;
}

// q0 + amplitude (1 - cos(omega t)) on every joint, sampled at dt: starts at rest.
JointTrajectory cosine_reference(const JointVector& q0, double amplitude, double omega, double duration, double dt) {
  JointTrajectory reference;
  reference.dt = dt;
  const auto n = static_cast<int>(std::lround(duration / dt));
  for (int k = 0; k <= n; ++k) {
    const double t = k * dt;
    reference.q.push_back(q0 + JointVector::Constant(amplitude * (1 - std::cos(omega * t))));
    reference.qd.push_back(JointVector::Constant(amplitude * omega * std::sin(omega * t)));
    reference.qdd.push_back(JointVector::Constant(amplitude * omega * omega * std::cos(omega * t)));
  }
  return reference;
}

// A step from q0 to q0 + delta after one sample.
JointTrajectory step_reference(const JointVector& q0, const JointVector& delta, double dt) {
  JointTrajectory reference;
  reference.dt = dt;
  reference.q = {q0, q0 + delta};
  return reference;
}

// The tuned servo at `rate_hz`, setpoints at the same rate, with an exact encoder (the tests
// below compare with exact values).
ServoConfig servo_at(const Simulator& sim, const JointVector& q, double rate_hz = 1000) {
  ServoTuning tuning;
  tuning.rate_hz = rate_hz;
  tuning.setpoint_rate_hz = rate_hz;
  tuning.encoder_counts_per_turn = 0;
  return tune_servo(sim, q, tuning);
}

// The same without feed-forward or integral action: the plain PD.
ServoConfig pd_at(const Simulator& sim, const JointVector& q, double rate_hz = 1000) {
  return with_controller(servo_at(sim, q, rate_hz), Controller::kPd);
}

double max_abs_error(const Trace& trace) {
  double e = 0;
  for (const TraceSample& s : trace.samples) e = std::max(e, (s.q - s.q_cmd).cwiseAbs().maxCoeff());
  return e;
}

bool all_finite(const Trace& trace) {
  for (const TraceSample& s : trace.samples) {
    if (!std::isfinite(s.t) || !s.q.allFinite() || !s.qd.allFinite() || !s.q_cmd.allFinite() ||
        !s.qd_cmd.allFinite() || !s.tau.allFinite() || !s.tcp.allFinite() || !s.tcp_cmd.allFinite())
      return false;
  }
  return true;
}

TEST(SimulatorLoad, InvalidXmlIsAnInputErrorWithMujocosMessageAndLine) {
  const InputError e = test::expect_input_error(
      [] { (void)Simulator::from_xml_string("<mujoco>\n<worldbody>\n<body><joint type=\"hing\"/></body></worldbody></mujoco>"); },
      {.file = "<string>", .line = 3, .field = "mjcf", .message = "hing"});
  EXPECT_EQ(e.detail().find('\n'), std::string::npos) << e.what();
}

TEST(SimulatorLoad, MissingFileNamesTheFile) {
  test::expect_input_error([] { (void)Simulator("/nonexistent/arm.xml"); }, {.file = "/nonexistent/arm.xml", .field = "mjcf"});
}

// Issue 42: values of a model that made what is computed from them overflow are refused, naming
// the model's element: a NaN timestep (a library's "vector::reserve"), a timestep of 1e-290 s (a
// servo period of -9e-282 s), a body of 1e308 kg (blamed on 'servo.kv').
TEST(SimulatorLoad, ValuesBeyondWhatAnArmHasAreRefusedNamingThem) {
  struct Case {
    std::string from, to, field, message;
  };
  const Case cases[] = {
      {"timestep=\"0.001\"", "timestep=\"nan\"", "option.timestep", "the timestep nan s is outside [1e-06, 0.008] s"},
      {"timestep=\"0.001\"", "timestep=\"1e-290\"", "option.timestep", "the timestep 1e-290 s is outside"},
      {"timestep=\"0.001\"", "timestep=\"0.5\"", "option.timestep", "the timestep 0.5 s is outside"},
      {"mass=\"3.7\"", "mass=\"1e308\"", "body.mass", "has a mass of 1e+308 kg; at most 100000 kg are accepted"},
  };
  for (const Case& c : cases) {
    std::string xml = test::kTestArmXml;
    const std::size_t at = xml.find(c.from);
    ASSERT_NE(at, std::string::npos) << c.from;
    xml.replace(at, c.from.size(), c.to);
    test::expect_input_error([&] { (void)Simulator::from_xml_string(xml); },
                             {.file = "<string>", .field = c.field, .message = c.message}, c.to);
  }
  ModelChanges changes;
  changes.timestep = 1e-300;
  test::expect_input_error([&] { (void)Simulator::from_xml_string(test::kTestArmXml, changes); },
                           {.field = "mjcf", .message = "timestep must be 0 (the model's) or in"});
}

TEST(SimulatorLoad, ModelWithoutTcpSiteIsRejected) {
  std::string xml = test::kTestArmXml;
  xml.replace(xml.find("name=\"tcp\""), 10, "name=\"tip\"");
  test::expect_input_error([&] { (void)Simulator::from_xml_string(xml); }, {.field = "site"});
}

TEST(SimulatorLoad, PositionActuatorIsRejected) {
  std::string xml = test::kTestArmXml;
  xml.replace(xml.find("<motor name=\"elbow\""), 6, "<position");
  test::expect_input_error([&] { (void)Simulator::from_xml_string(xml); }, {.field = "actuator", .message = "'elbow'"});
}

TEST(SimulatorLoad, FiveActuatorsAreRejected) {
  std::string xml = test::kTestArmXml;
  const auto p = xml.find("<motor name=\"wrist_3\"");
  xml.erase(p, xml.find("/>", p) + 2 - p);
  EXPECT_THROW((void)Simulator::from_xml_string(xml), InputError);
}

TEST(SimulatorLoad, TorqueLimitsComeFromCtrlRangeForceRangeAndGear) {
  // ctrlrange 150/28 N·m with gear 1; then wrist_3 with gear 2 and forcerange 10: 2 * min(28, 10)
  const Simulator sim = Simulator::from_xml_string(test::kTestArmXml);
  JointVector expected;
  expected << 150, 150, 150, 28, 28, 28;
  EXPECT_EQ(sim.torque_limits(), expected);

  std::string xml = test::kTestArmXml;
  xml.replace(xml.find("joint=\"wrist_3\" ctrlrange=\"-28 28\""), 34,
              "joint=\"wrist_3\" ctrlrange=\"-28 28\" gear=\"2\" forcerange=\"-10 10\"");
  EXPECT_DOUBLE_EQ(Simulator::from_xml_string(xml).torque_limits()[5], 20.0);

  EXPECT_TRUE(std::isinf(Simulator::from_xml_string(unlimited_arm_xml()).torque_limits()[0]));
}

TEST_F(SimulatorTest, TestArmIsRigidWithTheStatedLimits) {
  EXPECT_FALSE(sim_.elastic());
  EXPECT_TRUE(std::isinf(sim_.stiffness()[0]));
  EXPECT_TRUE(std::isinf(sim_.limits().velocity[0])) << "the test arm states no velocity limits";
  EXPECT_EQ(sim_.natural_frequencies(q0_).per_joint, JointVector::Zero());
}

TEST_F(SimulatorTest, TraceHasOneSamplePerServoTickAtTheRightTimes) {
  // 250 Hz servo, reference at 8 ms: 26 samples over 0.2 s, then 0.1 s settle = 25 ticks more
  const ServoConfig servo = servo_at(sim_, q0_, 250);
  const JointTrajectory reference = cosine_reference(q0_, 0.05, 5.0, 0.2, 0.008);
  RunOptions options;
  options.settle_time = 0.1;
  const Trace trace = sim_.run(reference, servo, options);
  ASSERT_FALSE(trace.diverged) << trace.warning;
  ASSERT_EQ(trace.samples.size(), 50u + 25u + 1u);
  EXPECT_NEAR(trace.period, 0.004, kTimeTolerance);
  EXPECT_NEAR(trace.reference_end, 0.2, kTimeTolerance);
  for (std::size_t k = 0; k < trace.samples.size(); ++k)
    EXPECT_NEAR(trace.samples[k].t, 0.004 * static_cast<double>(k), kTimeTolerance) << k;

  // ticks between reference samples are interpolated linearly; the settle holds the last sample
  EXPECT_TRUE(trace.samples[1].q_cmd.isApprox(0.5 * (reference.q[0] + reference.q[1]), 1e-14));
  EXPECT_EQ(trace.samples.back().q_cmd, reference.q.back());
  EXPECT_EQ(trace.samples.back().qd_cmd, JointVector::Zero());
}

TEST_F(SimulatorTest, StartsAtRestAtTheFirstReferenceSample) {
  const Trace trace = sim_.run(cosine_reference(q0_, 0.1, 3.0, 0.1, 0.001), servo_at(sim_, q0_), {});
  ASSERT_FALSE(trace.samples.empty());
  EXPECT_EQ(trace.samples[0].q, q0_);
  EXPECT_EQ(trace.samples[0].q_motor, q0_) << "a rigid arm: motor and link turn together";
  EXPECT_EQ(trace.samples[0].qd, JointVector::Zero());
  EXPECT_EQ(trace.samples[0].tcp, trace.samples[0].tcp_cmd);
  EXPECT_EQ(trace.samples[0].rotation.coeffs(), trace.samples[0].rotation_cmd.coeffs());
}

TEST_F(SimulatorTest, RecordedTcpIsTheForwardKinematicsOfTheRecordedJoints) {
  // guards against reading poses that describe the state before the last mj_step
  const Trace trace = sim_.run(cosine_reference(q0_, 0.3, 4.0, 0.5, 0.001), servo_at(sim_, q0_), {});
  ASSERT_FALSE(trace.diverged) << trace.warning;
  const Simulator probe = Simulator::from_xml_string(test::kTestArmXml);
  mjData* d = mj_makeData(&probe.model());
  const int site = mj_name2id(&probe.model(), mjOBJ_SITE, "tcp");
  const auto rotation_of = [&]() {
    double wxyz[4];
    mju_mat2Quat(wxyz, d->site_xmat + 9 * site);
    return Eigen::Quaterniond(wxyz[0], wxyz[1], wxyz[2], wxyz[3]);
  };
  for (std::size_t k = 0; k < trace.samples.size(); k += 37) {
    const TraceSample& s = trace.samples[k];
    for (int i = 0; i < 6; ++i) d->qpos[i] = s.q[i];
    mj_kinematics(&probe.model(), d);
    EXPECT_LT((Eigen::Vector3d(d->site_xpos + 3 * site) - s.tcp).norm(), kPoseTolerance) << "t=" << s.t;
    EXPECT_LT(rotation_of().angularDistance(s.rotation), kPoseTolerance) << "t=" << s.t;
    for (int i = 0; i < 6; ++i) d->qpos[i] = s.q_cmd[i];
    mj_kinematics(&probe.model(), d);
    EXPECT_LT((Eigen::Vector3d(d->site_xpos + 3 * site) - s.tcp_cmd).norm(), kPoseTolerance) << "t=" << s.t;
    EXPECT_LT(rotation_of().angularDistance(s.rotation_cmd), kPoseTolerance) << "t=" << s.t;
  }
  mj_deleteData(d);
}

TEST_F(SimulatorTest, TraceFollowsTheToolCentrePoint) {
  // a tool 0.15 m out along the flange's z and 0.02 m along its x, turned 30 deg about its x:
  // the same run traces the point and frame the tool carries, commanded and actual
  const JointTrajectory reference = cosine_reference(q0_, 0.3, 4.0, 0.3, 0.001);
  const Trace flange = sim_.run(reference, servo_at(sim_, q0_), {});
  RunOptions options;
  options.tool.translation() = Vec3(0.02, 0, 0.15);
  options.tool.linear() = Eigen::AngleAxisd(std::numbers::pi / 6, Vec3::UnitX()).toRotationMatrix();
  const Trace tool = sim_.run(reference, servo_at(sim_, q0_), options);
  ASSERT_EQ(flange.samples.size(), tool.samples.size());
  const Eigen::Quaterniond turn(options.tool.linear());
  for (std::size_t k = 0; k < tool.samples.size(); k += 23) {
    const TraceSample& a = flange.samples[k];
    const TraceSample& b = tool.samples[k];
    EXPECT_LT((a.tcp + a.rotation * options.tool.translation() - b.tcp).norm(), kPoseTolerance) << "t=" << a.t;
    EXPECT_LT((a.tcp_cmd + a.rotation_cmd * options.tool.translation() - b.tcp_cmd).norm(), kPoseTolerance) << "t=" << a.t;
    EXPECT_LT((a.rotation * turn).angularDistance(b.rotation), kPoseTolerance) << "t=" << a.t;
    EXPECT_LT((a.rotation_cmd * turn).angularDistance(b.rotation_cmd), kPoseTolerance) << "t=" << a.t;
    // the tool moves the point, not the joints
    EXPECT_EQ(a.q, b.q) << "t=" << a.t;
  }
}

TEST_F(SimulatorTest, EncoderReportsTheMotorAngleDelayedAndQuantised) {
  // a 3-tick delay and 2^12 counts per turn: measured(k) = round(motor(k - 3) / q) q
  ServoTuning tuning;
  tuning.rate_hz = 500;
  tuning.setpoint_rate_hz = 500;
  tuning.measurement_delay_ticks = 3;
  tuning.encoder_counts_per_turn = 4096;
  const ServoConfig servo = tune_servo(sim_, q0_, tuning);
  const Trace trace = sim_.run(cosine_reference(q0_, 0.2, 6.0, 0.5, 0.002), servo, {});
  ASSERT_FALSE(trace.diverged) << trace.warning;
  const double quantum = 2 * std::numbers::pi / 4096;
  for (std::size_t k = 3; k < trace.samples.size(); ++k) {
    for (int i = 0; i < 6; ++i) {
      const double measured = trace.samples[k].q_measured[i];
      EXPECT_NEAR(measured, std::round(trace.samples[k - 3].q_motor[i] / quantum) * quantum, 1e-12) << k << " " << i;
      EXPECT_NEAR(measured / quantum, std::round(measured / quantum), 1e-9) << "a whole number of counts";
    }
  }
}

TEST_F(SimulatorTest, HoldingWithGravityCompensationStaysPut) {
  JointTrajectory reference;
  reference.q = {q0_};
  RunOptions options;
  options.settle_time = 2.0;
  const Trace trace = sim_.run(reference, servo_at(sim_, q0_), options);
  ASSERT_FALSE(trace.diverged) << trace.warning;
  ASSERT_EQ(trace.samples.size(), 2001u);
  for (const TraceSample& s : trace.samples) ASSERT_LT((s.q - q0_).cwiseAbs().maxCoeff(), kHoldTolerance) << s.t;
}

TEST_F(SimulatorTest, HoldingWithoutGravityCompensationSagsUnderAPd) {
  JointTrajectory reference;
  reference.q = {q0_};
  RunOptions options;
  options.settle_time = 2.0;
  ServoConfig servo = pd_at(sim_, q0_);
  // at t = 0 the compensated servo applies exactly the gravity torque (its error is zero)
  const JointVector gravity = sim_.run(reference, servo, {}).samples.at(0).tau;
  EXPECT_TRUE(gravity.isApprox(sim_.gravity_torque(q0_), 1e-12));
  servo.gravity_compensation = false;
  const Trace trace = sim_.run(reference, servo, options);
  ASSERT_FALSE(trace.diverged) << trace.warning;
  // the shoulder carries the arm: it settles where the PD's stiffness kv kp balances gravity
  // (which changes a little as the arm sags, hence 10 %)
  const double stiffness = servo.kv[1] * servo.kp[1];
  const double sag = q0_[1] - trace.samples.back().q[1];
  EXPECT_GT(std::abs(sag), kMinSag);
  EXPECT_NEAR(sag, gravity[1] / stiffness, 0.1 * std::abs(gravity[1] / stiffness));
  EXPECT_GT((trace.samples.back().tcp - trace.samples.front().tcp).norm(), kMinSag);
}

TEST_F(SimulatorTest, TrackingErrorIsBoundedAndFallsAsTheGainsRise) {
  const JointTrajectory reference = cosine_reference(q0_, 0.2, std::numbers::pi, 2.0, 0.001);
  RunOptions options;
  options.settle_time = 0.5;
  double previous = std::numeric_limits<double>::infinity();
  for (const double scale : {0.25, 0.5, 1.0}) {
    ServoConfig servo = pd_at(sim_, q0_);
    servo.kp *= scale;
    servo.kv *= scale;
    const Trace trace = sim_.run(reference, servo, options);
    ASSERT_FALSE(trace.diverged) << trace.warning;
    const double error = max_abs_error(trace);
    EXPECT_LT(error, previous) << "gain scale " << scale;
    if (scale == 1.0) {
      EXPECT_LT(error, kTrackingBound);
    }
    previous = error;
  }
}

TEST_F(SimulatorTest, FeedforwardCutsTheTrackingError) {
  const JointTrajectory reference = cosine_reference(q0_, 0.2, std::numbers::pi, 2.0, 0.001);
  const ServoConfig pd = pd_at(sim_, q0_);
  const double without = max_abs_error(sim_.run(reference, pd, {}));
  ServoConfig servo = pd;
  servo.acceleration_feedforward = true;
  const double with = max_abs_error(sim_.run(reference, servo, {}));
  EXPECT_LT(with, 0.1 * without);
  // the cascade as tuned (integral action, every feed-forward) as well
  EXPECT_LT(max_abs_error(sim_.run(reference, servo_at(sim_, q0_), {})), 0.1 * without);
}

TEST_F(SimulatorTest, TorqueIsClampedAtTheLimitsAndCountedPerJoint) {
  // a 1 rad step under absurd gains: bang-bang at the limits, bounded, not diverged
  ServoConfig servo = servo_at(sim_, q0_);
  servo.kp.setConstant(1e4);
  servo.kv.setConstant(1e2);
  servo.setpoint_rate_hz = 250;  // four servo ticks per sample, as a drive runs
  RunOptions options;
  options.settle_time = 0.5;
  options.frame_rate = 1000;
  const JointVector limits = sim_.torque_limits();
  bool actuator_within = true;
  options.on_frame = [&](const mjModel& m, const mjData& d, double) {
    for (int a = 0; a < m.nu; ++a) actuator_within = actuator_within && std::abs(d.ctrl[a]) <= limits[a] + 1e-9;
  };
  const Trace trace = sim_.run(step_reference(q0_, JointVector::Constant(1.0), 0.004), servo, options);
  EXPECT_FALSE(trace.diverged) << trace.warning;
  EXPECT_TRUE(actuator_within);
  JointVector peak = JointVector::Zero();
  for (const TraceSample& s : trace.samples) {
    ASSERT_TRUE((s.tau.cwiseAbs().array() <= limits.array()).all()) << s.t;
    peak = peak.cwiseMax(s.tau.cwiseAbs());
  }
  EXPECT_EQ(peak, limits);
  // every joint saturated for a while, but not for the whole run: the ticks counted are servo
  // ticks, (samples - 1) * (servo rate / setpoint rate) + 1 of them, and the share of them is at
  // most 1 (issue 42: a share of samples reached 399.5 %)
  const long ticks_per_sample = std::lround(servo.rate_hz / servo.setpoint_rate_hz);
  EXPECT_EQ(trace.servo_ticks, static_cast<long>(trace.samples.size() - 1) * ticks_per_sample + 1);
  const Health health = check_health(trace, JointTrajectory{}, sim_.limits());
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_GT(trace.saturated_ticks[i], 0) << i;
    EXPECT_LT(trace.saturated_ticks[i], trace.servo_ticks) << i;
    EXPECT_DOUBLE_EQ(health.saturated_share[static_cast<Eigen::Index>(i)],
                     static_cast<double>(trace.saturated_ticks[i]) / static_cast<double>(trace.servo_ticks));
    EXPECT_LE(health.saturated_share[static_cast<Eigen::Index>(i)], 1.0);
  }
}

TEST_F(SimulatorTest, GentleMotionDoesNotSaturate) {
  const Trace trace = sim_.run(cosine_reference(q0_, 0.05, 2.0, 1.0, 0.001), servo_at(sim_, q0_), {});
  ASSERT_FALSE(trace.diverged) << trace.warning;
  for (std::size_t i = 0; i < 6; ++i) EXPECT_EQ(trace.saturated_ticks[i], 0) << i;
  JointVector peak = JointVector::Zero();
  for (const TraceSample& s : trace.samples) peak = peak.cwiseMax(s.tau.cwiseAbs());
  EXPECT_TRUE((peak.array() < sim_.torque_limits().array()).all());
  EXPECT_TRUE((peak.array() > 0).all());
}

TEST(SimulatorDivergence, AbsurdDampingIsReportedAsDivergedWithoutNan) {
  // kv h / I >> 2 on every joint: the discrete velocity loop is unstable
  const Simulator sim = Simulator::from_xml_string(unlimited_arm_xml());
  ServoConfig servo = servo_at(sim, test::test_arm_bent_pose());
  servo.kp.setConstant(1.0);
  servo.kv.setConstant(1e3);
  const Trace trace = sim.run(step_reference(test::test_arm_bent_pose(), JointVector::Constant(0.1), 0.001), servo, {});
  EXPECT_TRUE(trace.diverged);
  EXPECT_NE(trace.warning.find("unstable"), std::string::npos) << trace.warning;
  EXPECT_LT(trace.samples.size(), 1002u);
  EXPECT_TRUE(all_finite(trace));
  (void)take_mujoco_warnings();
}

TEST(SimulatorDivergence, MujocosBadAccelerationIsReportedNotSilentlyReset) {
  // a stiffness so large that one step gives qacc beyond MuJoCo's 1e10 limit (torque 1e9 N·m on
  // a wrist of 0.02 kg·m², while the control stays below the 1e10 bad-control limit): MuJoCo
  // resets the state to qpos0 and raises mjWARN_BADQACC, which the run must report
  const Simulator sim = Simulator::from_xml_string(unlimited_arm_xml());
  ServoConfig servo = servo_at(sim, test::test_arm_bent_pose());
  servo.kp.setConstant(1e5);
  servo.kv.setConstant(1e5);
  servo.ki.setZero();
  const Trace trace = sim.run(step_reference(test::test_arm_bent_pose(), JointVector::Constant(0.1), 0.001), servo, {});
  EXPECT_TRUE(trace.diverged);
  EXPECT_NE(trace.warning.find("QACC"), std::string::npos) << trace.warning;
  EXPECT_TRUE(all_finite(trace));
  for (const TraceSample& s : trace.samples) EXPECT_LT((s.q - test::test_arm_bent_pose()).norm(), 1.0) << s.t;
  (void)take_mujoco_warnings();
}

TEST_F(SimulatorTest, TraceIsRecordedAtTheSetpointsAndTheDriveInterpolatesThem) {
  // a 1 kHz drive under 250 Hz setpoints: one sample every 4 ms; between setpoints the torque
  // changes every 1 ms drive tick
  ServoTuning tuning;
  tuning.rate_hz = 1000;
  tuning.setpoint_rate_hz = 250;
  const ServoConfig servo = tune_servo(sim_, q0_, tuning);
  RunOptions options;
  options.settle_time = 0.1;
  options.frame_rate = 1000;
  std::vector<JointVector> ctrl;
  options.on_frame = [&](const mjModel&, const mjData& d, double) { ctrl.push_back(Eigen::Map<const JointVector>(d.ctrl)); };
  const Trace trace = sim_.run(cosine_reference(q0_, 0.2, 6.0, 0.2, 0.004), servo, options);
  ASSERT_FALSE(trace.diverged) << trace.warning;
  EXPECT_NEAR(trace.period, 0.004, kTimeTolerance);
  ASSERT_EQ(trace.samples.size(), 76u);
  for (std::size_t s = 1; s < 200; ++s) EXPECT_NE(ctrl[s], ctrl[s - 1]) << "step " << s;
  // the reference must come at a multiple of the setpoint period
  EXPECT_THROW((void)sim_.run(cosine_reference(q0_, 0.2, 6.0, 0.2, 0.002), servo, options), InputError);
}

TEST_F(SimulatorTest, SlowServoHoldsTheTorqueBetweenTicks) {
  // 250 Hz servo on 1 ms physics: ctrl changes only every fourth step
  const ServoConfig servo = servo_at(sim_, q0_, 250);
  RunOptions options;
  options.settle_time = 0;
  options.frame_rate = 1000;
  std::vector<JointVector> ctrl;
  std::vector<double> times;
  options.on_frame = [&](const mjModel&, const mjData& d, double t) {
    ctrl.push_back(Eigen::Map<const JointVector>(d.ctrl));
    times.push_back(t);
  };
  const Trace trace = sim_.run(cosine_reference(q0_, 0.2, 6.0, 0.2, 0.004), servo, options);
  ASSERT_FALSE(trace.diverged) << trace.warning;
  ASSERT_EQ(ctrl.size(), 201u);
  for (std::size_t s = 1; s < ctrl.size(); ++s) {
    EXPECT_NEAR(times[s], 0.001 * static_cast<double>(s), kTimeTolerance);
    if (s % 4 != 0) {
      EXPECT_EQ(ctrl[s], ctrl[s - 1]) << "step " << s;
    } else {
      EXPECT_NE(ctrl[s], ctrl[s - 1]) << "step " << s;
    }
  }
}

TEST_F(SimulatorTest, FramesComeAtTheRequestedRate) {
  RunOptions options;
  options.settle_time = 0.5;
  options.frame_rate = 30;
  std::vector<double> times;
  options.on_frame = [&](const mjModel&, const mjData&, double t) { times.push_back(t); };
  JointTrajectory reference;
  reference.q = {q0_};
  (void)sim_.run(reference, servo_at(sim_, q0_), options);
  ASSERT_EQ(times.size(), 16u);  // t = 0, 1/30, ..., 15/30 = 0.5
  for (std::size_t j = 0; j < times.size(); ++j) EXPECT_NEAR(times[j], static_cast<double>(j) / 30, 0.0005 + 1e-12);
}

TEST_F(SimulatorTest, MalformedReferenceOrServoIsAnInputError) {
  const ServoConfig servo = servo_at(sim_, q0_);
  const auto field_of = [&](const JointTrajectory& reference, const ServoConfig& s) {
    return test::expect_input_error([&] { (void)sim_.run(reference, s, {}); }, {}).field();
  };
  EXPECT_EQ(field_of(JointTrajectory{}, servo), "reference.q");
  JointTrajectory reference = cosine_reference(q0_, 0.1, 1.0, 0.1, 0.001);
  reference.dt = 0.0015;
  EXPECT_EQ(field_of(reference, servo), "reference.dt");
  reference.dt = 0.001;
  reference.qd.pop_back();
  EXPECT_EQ(field_of(reference, servo), "reference.qd");
  reference.qd.clear();
  reference.q[3][2] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(field_of(reference, servo), "reference.q");
  reference.q[3][2] = 0;
  ServoConfig odd = servo;
  odd.rate_hz = odd.setpoint_rate_hz = 300;  // 3.33 ms is not a whole number of 1 ms steps
  EXPECT_EQ(field_of(reference, odd), "servo.rate_hz");
  ServoConfig uneven = servo;
  uneven.setpoint_rate_hz = 300;  // 3.33 ms is not a whole number of 1 ms drive ticks
  EXPECT_EQ(field_of(reference, uneven), "servo.setpoint_rate_hz");
  ServoConfig slow = servo;
  slow.rate_hz = slow.setpoint_rate_hz = 100;  // below the 125 Hz a drive runs at
  EXPECT_EQ(field_of(reference, slow), "servo.rate_hz");
  ServoConfig negative = servo;
  negative.kv[2] = -1;
  EXPECT_EQ(field_of(reference, negative), "servo.kv");
  ServoConfig delayed = servo;
  delayed.measurement_delay_ticks = -1;
  EXPECT_EQ(field_of(reference, delayed), "servo.measurement_delay_ticks");
  // a reference at 1 ms cannot feed 250 Hz setpoints
  EXPECT_EQ(field_of(reference, servo_at(sim_, q0_, 250)), "reference.dt");
}

TEST_F(SimulatorTest, TuningFollowsTheStatedRuleOnARigidArm) {
  // rigid: the velocity loop is delay-limited, omega_v = (pi / 6) / ((d + 1) T); kv = omega_v
  // (rotor + link inertia), ki = kv omega_v / 4, kp = omega_v / 4
  ServoTuning tuning;
  tuning.rate_hz = 500;
  tuning.setpoint_rate_hz = 250;
  tuning.measurement_delay_ticks = 2;
  const ServoConfig servo = tune_servo(sim_, q0_, tuning);
  EXPECT_EQ(servo.setpoint_rate_hz, 250);
  const double omega_v = (std::numbers::pi / 6) / (3 / 500.0);
  const JointVector inertia = sim_.link_inertia(q0_) + sim_.motor_inertia();
  for (int i = 0; i < 6; ++i) {
    EXPECT_NEAR(servo.velocity_bandwidth[i], omega_v, 1e-9) << i;
    EXPECT_NEAR(servo.kv[i], omega_v * inertia[i], 1e-9) << i;
    EXPECT_NEAR(servo.ki[i], servo.kv[i] * omega_v / 4, 1e-9) << i;
    EXPECT_NEAR(servo.kp[i], omega_v / 4, 1e-9) << i;
  }
  EXPECT_TRUE(servo.velocity_feedforward && servo.acceleration_feedforward && servo.gravity_compensation);
  const ServoConfig pd = with_controller(servo, Controller::kPd);
  EXPECT_EQ(pd.ki, JointVector::Zero());
  EXPECT_FALSE(pd.acceleration_feedforward);
  EXPECT_FALSE(pd.deflection_compensation);
  ServoTuning fast;
  fast.rate_hz = 10000;
  EXPECT_THROW((void)tune_servo(sim_, q0_, fast), InputError);
}

TEST_F(SimulatorTest, RandomServosNeverYieldNanOrExceedTheLimits) {
  // property: whatever the gains, delay and reference, samples are finite, torques within
  // limits, and a run that did not diverge covers every tick
  const int cases = test::property_cases(12);
  const JointVector limits = sim_.torque_limits();
  for (int c = 0; c < cases; ++c) {
    const std::uint64_t seed = 1000 + static_cast<std::uint64_t>(c);
    auto rng = test::make_rng(seed);
    ServoTuning tuning;
    tuning.rate_hz = test::uniform(rng, 0, 1) < 0.5 ? 1000 : 500;
    tuning.setpoint_rate_hz = 500;
    tuning.measurement_delay_ticks = static_cast<int>(test::uniform(rng, 0, 3.99));
    tuning.encoder_counts_per_turn = test::uniform(rng, 0, 1) < 0.5 ? 0 : 65536;
    ServoConfig servo = tune_servo(sim_, q0_, tuning);
    servo.kp *= std::pow(10.0, test::uniform(rng, -2, 2));
    servo.kv *= std::pow(10.0, test::uniform(rng, -2, 2));
    servo.ki *= std::pow(10.0, test::uniform(rng, -2, 2));
    servo.gravity_compensation = test::uniform(rng, 0, 1) < 0.5;
    servo.acceleration_feedforward = test::uniform(rng, 0, 1) < 0.5;
    servo.velocity_feedforward = test::uniform(rng, 0, 1) < 0.5;
    const JointTrajectory reference =
        cosine_reference(q0_, test::uniform(rng, -0.5, 0.5), test::uniform(rng, 0.5, 20), 0.3, 0.002);
    RunOptions options;
    options.settle_time = 0.1;
    const Trace trace = sim_.run(reference, servo, options);
    ASSERT_TRUE(all_finite(trace)) << test::seed_text(seed);
    for (const TraceSample& s : trace.samples)
      ASSERT_TRUE((s.tau.cwiseAbs().array() <= limits.array()).all()) << test::seed_text(seed);
    if (!trace.diverged) {
      EXPECT_EQ(trace.samples.size(), static_cast<std::size_t>(std::lround(0.4 * tuning.setpoint_rate_hz)) + 1)
          << test::seed_text(seed);
    }
    (void)take_mujoco_warnings();
  }
}

}  // namespace
}  // namespace blendbench
