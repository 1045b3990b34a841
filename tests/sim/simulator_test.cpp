#include "blendbench/sim/simulator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

#include "support/property.hpp"
#include "support/test_arm.hpp"
#include "blendbench/core/input_error.hpp"

namespace blendbench {
namespace {

// Holding still with gravity compensation: the PD error is zero and the bias force is cancelled
// exactly, so only rounding moves the arm.
constexpr double kHoldTolerance = 1e-9;      // rad
// A sag that a gravity-loaded arm under 10 % gains cannot hide.
constexpr double kMinSag = 1e-3;             // rad
// Exact pose evaluation: recorded TCP vs forward kinematics of the recorded joints.
constexpr double kPoseTolerance = 1e-12;     // m
// Servo tick times.
constexpr double kTimeTolerance = 1e-12;     // s
// The tracking-error bound for the smooth reference under default gains.
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
JointReference cosine_reference(const JointVector& q0, double amplitude, double omega, double duration, double dt) {
  JointReference reference;
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
JointReference step_reference(const JointVector& q0, const JointVector& delta, double dt) {
  JointReference reference;
  reference.dt = dt;
  reference.q = {q0, q0 + delta};
  return reference;
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
  try {
    (void)Simulator::from_xml_string("<mujoco>\n<worldbody>\n<body><joint type=\"hing\"/></body></worldbody></mujoco>");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "mjcf");
    EXPECT_EQ(e.file(), "<string>");
    EXPECT_EQ(e.line(), 3);
    EXPECT_NE(e.detail().find("hing"), std::string::npos) << e.what();
    EXPECT_EQ(e.detail().find('\n'), std::string::npos) << e.what();
  }
}

TEST(SimulatorLoad, MissingFileNamesTheFile) {
  try {
    (void)Simulator("/nonexistent/arm.xml");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "/nonexistent/arm.xml");
    EXPECT_EQ(e.field(), "mjcf");
  }
}

TEST(SimulatorLoad, ModelWithoutTcpSiteIsRejected) {
  std::string xml = test::kTestArmXml;
  xml.replace(xml.find("name=\"tcp\""), 10, "name=\"tip\"");
  try {
    (void)Simulator::from_xml_string(xml);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "site");
  }
}

TEST(SimulatorLoad, PositionActuatorIsRejected) {
  std::string xml = test::kTestArmXml;
  xml.replace(xml.find("<motor name=\"elbow\""), 6, "<position");
  try {
    (void)Simulator::from_xml_string(xml);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "actuator");
    EXPECT_NE(e.detail().find("'elbow'"), std::string::npos) << e.what();
  }
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

TEST_F(SimulatorTest, TraceHasOneSamplePerServoTickAtTheRightTimes) {
  // 250 Hz servo, reference at 8 ms: 26 samples over 0.2 s, then 0.1 s settle = 25 ticks more
  ServoConfig servo = default_servo(sim_, q0_, 250);
  const JointReference reference = cosine_reference(q0_, 0.05, 5.0, 0.2, 0.008);
  RunOptions options;
  options.settle_time = 0.1;
  const Trace trace = sim_.run(reference, servo, options);
  ASSERT_FALSE(trace.diverged) << trace.warning;
  ASSERT_EQ(trace.samples.size(), 50u + 25u + 1u);
  for (std::size_t k = 0; k < trace.samples.size(); ++k)
    EXPECT_NEAR(trace.samples[k].t, 0.004 * static_cast<double>(k), kTimeTolerance) << k;

  // ticks between reference samples are interpolated linearly; the settle holds the last sample
  EXPECT_TRUE(trace.samples[1].q_cmd.isApprox(0.5 * (reference.q[0] + reference.q[1]), 1e-14));
  EXPECT_EQ(trace.samples.back().q_cmd, reference.q.back());
  EXPECT_EQ(trace.samples.back().qd_cmd, JointVector::Zero());
}

TEST_F(SimulatorTest, StartsAtRestAtTheFirstReferenceSample) {
  const Trace trace = sim_.run(cosine_reference(q0_, 0.1, 3.0, 0.1, 0.001), default_servo(sim_, q0_), {});
  ASSERT_FALSE(trace.samples.empty());
  EXPECT_EQ(trace.samples[0].q, q0_);
  EXPECT_EQ(trace.samples[0].qd, JointVector::Zero());
  EXPECT_EQ(trace.samples[0].tcp, trace.samples[0].tcp_cmd);
}

TEST_F(SimulatorTest, RecordedTcpIsTheForwardKinematicsOfTheRecordedJoints) {
  // guards against reading poses that describe the state before the last mj_step
  const Trace trace = sim_.run(cosine_reference(q0_, 0.3, 4.0, 0.5, 0.001), default_servo(sim_, q0_), {});
  ASSERT_FALSE(trace.diverged) << trace.warning;
  const Simulator probe = Simulator::from_xml_string(test::kTestArmXml);
  mjData* d = mj_makeData(&probe.model());
  const int site = mj_name2id(&probe.model(), mjOBJ_SITE, "tcp");
  for (std::size_t k = 0; k < trace.samples.size(); k += 37) {
    const TraceSample& s = trace.samples[k];
    for (int i = 0; i < 6; ++i) d->qpos[i] = s.q[i];
    mj_kinematics(&probe.model(), d);
    EXPECT_LT((Eigen::Vector3d(d->site_xpos + 3 * site) - s.tcp).norm(), kPoseTolerance) << "t=" << s.t;
    for (int i = 0; i < 6; ++i) d->qpos[i] = s.q_cmd[i];
    mj_kinematics(&probe.model(), d);
    EXPECT_LT((Eigen::Vector3d(d->site_xpos + 3 * site) - s.tcp_cmd).norm(), kPoseTolerance) << "t=" << s.t;
  }
  mj_deleteData(d);
}

TEST_F(SimulatorTest, HoldingWithGravityCompensationStaysPut) {
  JointReference reference;
  reference.q = {q0_};
  RunOptions options;
  options.settle_time = 2.0;
  ServoConfig servo = default_servo(sim_, q0_, 1000, 0.1 * default_kp());
  const Trace trace = sim_.run(reference, servo, options);
  ASSERT_FALSE(trace.diverged) << trace.warning;
  ASSERT_EQ(trace.samples.size(), 2001u);
  for (const TraceSample& s : trace.samples) ASSERT_LT((s.q - q0_).cwiseAbs().maxCoeff(), kHoldTolerance) << s.t;
}

TEST_F(SimulatorTest, HoldingWithoutGravityCompensationSagsUnderLowGains) {
  JointReference reference;
  reference.q = {q0_};
  RunOptions options;
  options.settle_time = 2.0;
  ServoConfig servo = default_servo(sim_, q0_, 1000, 0.1 * default_kp());
  // at t = 0 the compensated servo applies exactly the gravity torque (its PD error is zero)
  const JointVector gravity = sim_.run(reference, servo, {}).samples.at(0).tau;
  servo.gravity_compensation = false;
  const Trace trace = sim_.run(reference, servo, options);
  ASSERT_FALSE(trace.diverged) << trace.warning;
  // the shoulder carries the arm: it settles where kp * error balances gravity (which changes a
  // little as the arm sags, hence 10 %)
  const double sag = q0_[1] - trace.samples.back().q[1];
  EXPECT_GT(std::abs(sag), kMinSag);
  EXPECT_NEAR(sag, gravity[1] / servo.kp[1], 0.1 * std::abs(gravity[1] / servo.kp[1]));
  EXPECT_GT((trace.samples.back().tcp - trace.samples.front().tcp).norm(), kMinSag);
}

TEST_F(SimulatorTest, TrackingErrorIsBoundedAndFallsAsKpRises) {
  const JointReference reference = cosine_reference(q0_, 0.2, M_PI, 2.0, 0.001);
  RunOptions options;
  options.settle_time = 0.5;
  double previous = std::numeric_limits<double>::infinity();
  for (const double scale : {0.25, 1.0, 4.0}) {
    const Trace trace = sim_.run(reference, default_servo(sim_, q0_, 1000, scale * default_kp()), options);
    ASSERT_FALSE(trace.diverged) << trace.warning;
    const double error = max_abs_error(trace);
    EXPECT_LT(error, previous) << "kp scale " << scale;
    if (scale == 1.0) {
      EXPECT_LT(error, kTrackingBound);
    }
    previous = error;
  }
}

TEST_F(SimulatorTest, FeedforwardCutsTheTrackingError) {
  const JointReference reference = cosine_reference(q0_, 0.2, M_PI, 2.0, 0.001);
  ServoConfig servo = default_servo(sim_, q0_);
  const double without = max_abs_error(sim_.run(reference, servo, {}));
  servo.feedforward = true;
  const double with = max_abs_error(sim_.run(reference, servo, {}));
  EXPECT_LT(with, 0.1 * without);
  // feed-forward alone (no gravity compensation) carries the reference's bias forces itself
  servo.gravity_compensation = false;
  EXPECT_LT(max_abs_error(sim_.run(reference, servo, {})), 0.1 * without);
}

TEST_F(SimulatorTest, TorqueIsClampedAtTheLimitsAndFlagged) {
  // a 1 rad step under absurd gains: bang-bang at the limits, bounded, not diverged
  ServoConfig servo;
  servo.kp.setConstant(1e8);
  servo.kd.setConstant(1e2);
  RunOptions options;
  options.settle_time = 0.5;
  options.frame_rate = 1000;
  const JointVector limits = sim_.torque_limits();
  bool actuator_within = true;
  options.on_frame = [&](const mjModel& m, const mjData& d, double) {
    for (int a = 0; a < m.nu; ++a) actuator_within = actuator_within && std::abs(d.ctrl[a]) <= limits[a] + 1e-9;
  };
  const Trace trace = sim_.run(step_reference(q0_, JointVector::Constant(1.0), 0.001), servo, options);
  EXPECT_FALSE(trace.diverged) << trace.warning;
  EXPECT_TRUE(trace.torque_saturated);
  EXPECT_TRUE(actuator_within);
  for (const TraceSample& s : trace.samples)
    ASSERT_TRUE((s.tau.cwiseAbs().array() <= limits.array()).all()) << s.t;
  EXPECT_EQ(trace.peak_abs_tau, limits);
}

TEST_F(SimulatorTest, GentleMotionDoesNotSaturate) {
  const Trace trace = sim_.run(cosine_reference(q0_, 0.05, 2.0, 1.0, 0.001), default_servo(sim_, q0_), {});
  EXPECT_FALSE(trace.torque_saturated);
  EXPECT_TRUE((trace.peak_abs_tau.array() < sim_.torque_limits().array()).all());
  EXPECT_TRUE((trace.peak_abs_tau.array() > 0).all());
}

TEST(SimulatorDivergence, AbsurdDampingIsReportedAsDivergedWithoutNan) {
  // kd h / I >> 2 on every joint: the discrete loop is unstable (see kMaxOmegaT)
  const Simulator sim = Simulator::from_xml_string(unlimited_arm_xml());
  ServoConfig servo;
  servo.kp.setConstant(1e3);
  servo.kd.setConstant(1e3);
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
  ServoConfig servo;
  servo.kp.setConstant(1e10);
  const Trace trace = sim.run(step_reference(test::test_arm_bent_pose(), JointVector::Constant(0.1), 0.001), servo, {});
  EXPECT_TRUE(trace.diverged);
  EXPECT_NE(trace.warning.find("QACC"), std::string::npos) << trace.warning;
  EXPECT_TRUE(all_finite(trace));
  for (const TraceSample& s : trace.samples) EXPECT_LT((s.q - test::test_arm_bent_pose()).norm(), 1.0) << s.t;
  (void)take_mujoco_warnings();
}

TEST_F(SimulatorTest, SlowServoHoldsTheTorqueBetweenTicks) {
  // 250 Hz servo on 1 ms physics: ctrl changes only every fourth step
  const ServoConfig servo = default_servo(sim_, q0_, 250);
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
  JointReference reference;
  reference.q = {q0_};
  (void)sim_.run(reference, default_servo(sim_, q0_), options);
  ASSERT_EQ(times.size(), 16u);  // t = 0, 1/30, ..., 15/30 = 0.5
  for (std::size_t j = 0; j < times.size(); ++j) EXPECT_NEAR(times[j], static_cast<double>(j) / 30, 0.0005 + 1e-12);
}

TEST_F(SimulatorTest, MalformedReferenceOrServoIsAnInputError) {
  const ServoConfig servo = default_servo(sim_, q0_);
  const auto field_of = [&](const JointReference& reference, const ServoConfig& s) -> std::string {
    try {
      (void)sim_.run(reference, s, {});
    } catch (const InputError& e) {
      return e.field();
    }
    return "no error";
  };
  EXPECT_EQ(field_of(JointReference{}, servo), "reference.q");
  JointReference reference = cosine_reference(q0_, 0.1, 1.0, 0.1, 0.001);
  reference.dt = 0.0015;
  EXPECT_EQ(field_of(reference, servo), "reference.dt");
  reference.dt = 0.001;
  reference.qd.pop_back();
  EXPECT_EQ(field_of(reference, servo), "reference.qd");
  reference.qd.clear();
  reference.q[3][2] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(field_of(reference, servo), "reference.q");
  reference.q[3][2] = 0;
  ServoConfig slow = servo;
  slow.rate_hz = 300;  // 3.33 ms is not a whole number of 1 ms steps
  EXPECT_EQ(field_of(reference, slow), "servo.rate_hz");
  ServoConfig negative = servo;
  negative.kd[2] = -1;
  EXPECT_EQ(field_of(reference, negative), "servo.kd");
  // a reference at 1 ms cannot drive a 250 Hz servo
  EXPECT_EQ(field_of(reference, default_servo(sim_, q0_, 250)), "reference.dt");
}

TEST_F(SimulatorTest, DefaultServoCapsKpByTheInertiaAndDampsCritically) {
  // at 100 Hz the wrist's natural frequency would exceed kMaxOmegaT / T: kp drops to (25 rad/s)² I
  const JointVector inertia = sim_.inertia_diagonal(q0_);
  const ServoConfig servo = default_servo(sim_, q0_, 100);
  for (int i = 0; i < 6; ++i) {
    EXPECT_LE(servo.kp[i], default_kp()[i]);
    EXPECT_LE(std::sqrt(servo.kp[i] / inertia[i]) / 100, kMaxOmegaT * (1 + 1e-12)) << i;
    EXPECT_NEAR(servo.kd[i], 2 * std::sqrt(servo.kp[i] * inertia[i]), 1e-9) << i;
  }
  EXPECT_NEAR(servo.kp[5], 625 * inertia[5], 1e-9);
}

TEST_F(SimulatorTest, RandomServosNeverYieldNanOrExceedTheLimits) {
  // property: whatever the gains and the reference, samples are finite, torques within limits,
  // and a run that did not diverge covers every tick
  const int cases = test::property_cases(12);
  const JointVector limits = sim_.torque_limits();
  for (int c = 0; c < cases; ++c) {
    const std::uint64_t seed = 1000 + static_cast<std::uint64_t>(c);
    auto rng = test::make_rng(seed);
    ServoConfig servo = default_servo(sim_, q0_, test::uniform(rng, 0, 1) < 0.5 ? 1000 : 500);
    servo.kp *= std::pow(10.0, test::uniform(rng, -2, 3));
    servo.kd *= std::pow(10.0, test::uniform(rng, -2, 3));
    servo.gravity_compensation = test::uniform(rng, 0, 1) < 0.5;
    servo.feedforward = test::uniform(rng, 0, 1) < 0.5;
    const JointReference reference =
        cosine_reference(q0_, test::uniform(rng, -0.5, 0.5), test::uniform(rng, 0.5, 20), 0.3, 0.002);
    RunOptions options;
    options.settle_time = 0.1;
    const Trace trace = sim_.run(reference, servo, options);
    ASSERT_TRUE(all_finite(trace)) << test::seed_text(seed);
    for (const TraceSample& s : trace.samples)
      ASSERT_TRUE((s.tau.cwiseAbs().array() <= limits.array()).all()) << test::seed_text(seed);
    if (!trace.diverged) {
      EXPECT_EQ(trace.samples.size(), static_cast<std::size_t>(std::lround(0.4 * servo.rate_hz)) + 1)
          << test::seed_text(seed);
    }
    (void)take_mujoco_warnings();
  }
}

}  // namespace
}  // namespace blendbench
