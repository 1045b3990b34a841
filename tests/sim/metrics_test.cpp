#include "blendbench/sim/metrics.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <vector>

#include "blendbench/corner/blend.hpp"
#include "support/property.hpp"
#include "support/random_geometry.hpp"

namespace blendbench {
namespace {

// Distances built from offsets of a few millimetres on paths of about a metre: rounding only.
constexpr double kDistanceTolerance = 1e-12;  // m
// Third differences of a cubic with dt = 10 ms: the difference is ~1e-5 m on values ~1 m, so
// rounding leaves ~1e-10 of it.
constexpr double kJerkRelativeTolerance = 1e-7;
// Differences of a linear velocity: exact up to rounding.
constexpr double kAccelerationRelativeTolerance = 1e-9;
// A sine well inside a zero-phase Butterworth's pass band keeps its amplitude to this (the
// squared 2nd-order response 1 / (1 + (f / fc)^4) at f = fc / 4 or 4 fc, plus the window's
// sampling of the peaks).
constexpr double kPassBandTolerance = 0.01;
constexpr double kPi = std::numbers::pi;

// A sample at time t with every vector zero (TraceSample leaves its Eigen members uninitialised).
TraceSample sample_at(double t) {
  TraceSample s;
  s.t = t;
  s.q_cmd = s.qd_cmd = s.q_motor_cmd = s.q_measured = s.following_error = s.q_motor = s.qd_motor = s.q = s.qd = s.tau =
      JointVector::Zero();
  s.tcp_cmd = s.tcp = Vec3::Zero();
  s.rotation = s.rotation_cmd = Eigen::Quaterniond::Identity();
  return s;
}

// n samples on a grid of dt; the reference runs through all of them unless `reference_end` says
// when it ended.
Trace zero_trace(std::size_t n, double dt = 1e-3, double reference_end = -1) {
  Trace trace;
  for (std::size_t k = 0; k < n; ++k) trace.samples.push_back(sample_at(static_cast<double>(k) * dt));
  trace.period = dt;
  trace.reference_end = reference_end >= 0 ? reference_end : static_cast<double>(n > 0 ? n - 1 : 0) * dt;
  return trace;
}

Move move_of(const Primitive& geometry) {
  Move m;
  m.geometry = geometry;
  m.limits = {0.1, 1.0, 1.0, 10.0};
  return m;
}

Program program_of(const std::vector<Primitive>& moves) {
  Program p;
  for (const Primitive& g : moves) p.moves.push_back(move_of(g));
  return p;
}

// An arc on the circle of `radius` about `center` in the plane of orthonormal u, v.
Arc arc_of(const Vec3& center, const Vec3& u, const Vec3& v, double radius, double sweep) {
  Arc a;
  a.center = center;
  a.u = u;
  a.v = v;
  a.radius = radius;
  a.sweep = sweep;
  return a;
}


const Program kUnitLine = program_of({Line{Vec3(0, 0, 0), Vec3(1, 0, 0)}});

// A programmed straight line, the command on it, the actual TCP 2 mm to the side: contour and
// tracking error are both the offset.
TEST(MetricsTest, SidewaysOffsetFromALineIsBothContourAndTrackingError) {
  constexpr double kOffset = 2e-3;
  Trace trace = zero_trace(11);
  for (std::size_t k = 0; k < trace.samples.size(); ++k) {
    trace.samples[k].tcp_cmd = Vec3(0.1 * static_cast<double>(k), 0, 0);
    trace.samples[k].tcp = trace.samples[k].tcp_cmd + Vec3(0, kOffset, 0);
  }
  const Metrics m = compute_metrics(trace, kUnitLine, Path{}, MetricsOptions{});
  ASSERT_EQ(m.tracking_error.size(), trace.samples.size());
  ASSERT_EQ(m.contour_error_programmed.size(), trace.samples.size());
  for (std::size_t k = 0; k < trace.samples.size(); ++k) {
    EXPECT_NEAR(m.tracking_error[k], kOffset, kDistanceTolerance) << "sample " << k;
    EXPECT_NEAR(m.contour_error_programmed[k], kOffset, kDistanceTolerance) << "sample " << k;
  }
  EXPECT_NEAR(m.tracking_error_max, kOffset, kDistanceTolerance);
  EXPECT_NEAR(m.tracking_error_rms, kOffset, kDistanceTolerance);
  EXPECT_NEAR(m.contour_error_programmed_max, kOffset, kDistanceTolerance);
}

// Lagging along the line is tracking error but not contour error: actual = command + 3 mm
// along + 2 mm sideways gives contour 2 mm and tracking sqrt(13) mm.
TEST(MetricsTest, LagAlongThePathIsTrackingErrorOnly) {
  const Vec3 offset(3e-3, 2e-3, 0);
  Trace trace = zero_trace(9);
  for (std::size_t k = 0; k < trace.samples.size(); ++k) {
    trace.samples[k].tcp_cmd = Vec3(0.1 + 0.1 * static_cast<double>(k), 0, 0);
    trace.samples[k].tcp = trace.samples[k].tcp_cmd - offset;
  }
  const Metrics m = compute_metrics(trace, kUnitLine, Path{}, MetricsOptions{});
  for (std::size_t k = 0; k < trace.samples.size(); ++k) {
    EXPECT_NEAR(m.tracking_error[k], std::sqrt(13.0) * 1e-3, kDistanceTolerance) << "sample " << k;
    EXPECT_NEAR(m.contour_error_programmed[k], 2e-3, kDistanceTolerance) << "sample " << k;
  }
  EXPECT_NEAR(m.contour_error_programmed_max, 2e-3, kDistanceTolerance);
  EXPECT_NEAR(m.tracking_error_max, std::sqrt(13.0) * 1e-3, kDistanceTolerance);
}

// Beyond the end of the line the contour error is the distance to the end point.
TEST(MetricsTest, ContourErrorPastTheEndIsTheDistanceToTheEndPoint) {
  Trace trace = zero_trace(1);
  trace.samples[0].tcp_cmd = Vec3(1, 0, 0);
  trace.samples[0].tcp = Vec3(1.003, 0.004, 0);
  const Metrics m = compute_metrics(trace, kUnitLine, Path{}, MetricsOptions{});
  EXPECT_NEAR(m.contour_error_programmed[0], 5e-3, kDistanceTolerance);
}

// The RMS of tracking errors 1, 2, 3, 4 mm is sqrt(30 / 4) mm, in any order, and the maximum 4 mm.
TEST(MetricsTest, TrackingErrorRmsOfAKnownSequence) {
  const std::vector<double> errors = {3e-3, 1e-3, 4e-3, 2e-3};
  Trace trace = zero_trace(errors.size());
  for (std::size_t k = 0; k < errors.size(); ++k) {
    trace.samples[k].tcp_cmd = Vec3(0.2, 0.1, 0.3);
    trace.samples[k].tcp = trace.samples[k].tcp_cmd + Vec3(0, 0, errors[k]);
  }
  const Metrics m = compute_metrics(trace, kUnitLine, Path{}, MetricsOptions{});
  EXPECT_NEAR(m.tracking_error_rms, std::sqrt(7.5) * 1e-3, kDistanceTolerance);
  EXPECT_NEAR(m.tracking_error_max, 4e-3, kDistanceTolerance);
  for (std::size_t k = 0; k < errors.size(); ++k) EXPECT_NEAR(m.tracking_error[k], errors[k], kDistanceTolerance);
}

// An empty trace has zero metrics, empty per-sample vectors and no cycle time (no NaN from 0 / 0).
TEST(MetricsTest, EmptyTraceGivesZerosAndNoCycleTime) {
  const Metrics m = compute_metrics(Trace{}, kUnitLine, Path{}, MetricsOptions{});
  EXPECT_FALSE(m.cycle_time.has_value());
  EXPECT_TRUE(m.tracking_error.empty());
  EXPECT_TRUE(m.contour_error_programmed.empty());
  EXPECT_EQ(m.tracking_error_max, 0.0);
  EXPECT_EQ(m.tracking_error_rms, 0.0);
  EXPECT_EQ(m.contour_error_programmed_max, 0.0);
  EXPECT_EQ(m.jerk_commanded_peak, 0.0);
  EXPECT_EQ(m.jerk_actual_peak, 0.0);
}

// Settling: TCP distances from the end point in units of the tolerance (dyadic, so the sample
// exactly at the tolerance is exact in floating point); the speed tolerance is lifted so only
// positions count, and the window is one sample.
struct SettleCase {
  std::vector<double> distance;   // per sample, in tolerances
  std::optional<std::size_t> settled_at;  // expected first sample of the final in-tolerance run
};

Trace settle_trace(const std::vector<double>& distance, const Vec3& end, double tolerance) {
  Trace trace = zero_trace(distance.size(), 1e-3, 0.0);
  for (std::size_t k = 0; k < distance.size(); ++k) {
    trace.samples[k].tcp = end + Vec3(distance[k] * tolerance, 0, 0);
    trace.samples[k].tcp_cmd = end;
  }
  return trace;
}

MetricsOptions position_only(const Vec3& end, double tolerance) {
  MetricsOptions opt;
  opt.end_point = end;
  opt.settle_tolerance = tolerance;
  opt.settle_speed_tolerance = std::numeric_limits<double>::infinity();
  opt.settle_window = 0;
  return opt;
}

TEST(MetricsTest, CycleTimeIsTheFirstInstantFromWhichTheWindowStaysWithinTolerance) {
  const MetricsOptions opt = position_only(Vec3(0.5, 0.25, 0.125), std::ldexp(1.0, -13));  // 0.12 mm
  const std::vector<SettleCase> cases = {
      // enters, leaves again (overshoot), settles at sample 4
      {{8, 4, 0.5, 2, 0.5, 0.25, 0}, 2},
      // exactly at the tolerance counts as within
      {{4, 1, 0.5, 1, 0}, 1},
      // within from the first sample: the cycle time is 0
      {{0.5, 0.25, 0}, 0},
      // never inside
      {{4, 3, 2}, std::nullopt},
  };
  for (const SettleCase& c : cases) {
    const Trace trace = settle_trace(c.distance, opt.end_point, opt.settle_tolerance);
    const Metrics m = compute_metrics(trace, kUnitLine, Path{}, opt);
    ASSERT_EQ(m.cycle_time.has_value(), c.settled_at.has_value()) << "first distance " << c.distance.front();
    if (c.settled_at) {
      EXPECT_EQ(*m.cycle_time, trace.samples[*c.settled_at].t) << "first distance " << c.distance.front();
    }
  }
}

// Settling on the 3D distance: an offset with every component below the tolerance but a norm
// above it is not settled.
TEST(MetricsTest, SettlingUsesTheEuclideanDistance) {
  const MetricsOptions opt = position_only(Vec3(0.4, 0, 0.3), 1e-4);
  Trace trace = zero_trace(3, 1e-3, 0.0);
  for (TraceSample& s : trace.samples) s.tcp = opt.end_point + Vec3(0.8e-4, 0.8e-4, 0);
  EXPECT_FALSE(compute_metrics(trace, kUnitLine, Path{}, opt).cycle_time.has_value());
  trace.samples.back().tcp = opt.end_point;
  const Metrics m = compute_metrics(trace, kUnitLine, Path{}, opt);
  ASSERT_TRUE(m.cycle_time.has_value());
  EXPECT_EQ(*m.cycle_time, trace.samples.back().t);
}

// The three conditions each delay the cycle time: the reference must have ended, the TCP must be
// slow as well as close, and both for the whole window.
TEST(MetricsTest, CycleTimeWaitsForTheReferenceTheSpeedAndTheWindow) {
  MetricsOptions opt;
  opt.end_point = Vec3(0.4, 0.1, 0.3);
  opt.settle_tolerance = 30e-6;
  opt.settle_speed_tolerance = 1e-3;
  opt.settle_window = 0.05;
  // a 1 ms grid over 0.5 s; the TCP at the end point from the start, the reference ends at 0.1 s
  Trace trace = zero_trace(501, 1e-3, 0.1);
  for (TraceSample& s : trace.samples) s.tcp = s.tcp_cmd = opt.end_point;
  Metrics m = compute_metrics(trace, kUnitLine, Path{}, opt);
  ASSERT_TRUE(m.cycle_time.has_value());
  EXPECT_NEAR(*m.cycle_time, 0.1, 1e-12) << "not before the reference ends";
  // creeping at 9 mm/s within 10 um of the end point until 0.2 s: close, but not slow
  for (TraceSample& s : trace.samples) {
    if (s.t < 0.2) s.tcp = opt.end_point + Vec3(10e-6 * std::sin(900 * s.t), 0, 0);
  }
  m = compute_metrics(trace, kUnitLine, Path{}, opt);
  ASSERT_TRUE(m.cycle_time.has_value());
  EXPECT_GT(*m.cycle_time, 0.19);
  EXPECT_LT(*m.cycle_time, 0.202);
  // a 40 um excursion at 0.22 s (within the window after 0.2 s): settled only after it
  trace.samples[220].tcp = opt.end_point + Vec3(40e-6, 0, 0);
  m = compute_metrics(trace, kUnitLine, Path{}, opt);
  ASSERT_TRUE(m.cycle_time.has_value());
  EXPECT_NEAR(*m.cycle_time, 0.222, 1e-9) << "the first sample after the excursion and its speed";
  // the first window that holds counts, whatever comes later (the definition)
  trace.samples[480].tcp = opt.end_point + Vec3(40e-6, 0, 0);
  EXPECT_NEAR(*compute_metrics(trace, kUnitLine, Path{}, opt).cycle_time, 0.222, 1e-9);
  // an excursion in every window: never settled
  for (std::size_t k = 260; k < trace.samples.size(); k += 40) trace.samples[k].tcp = opt.end_point + Vec3(40e-6, 0, 0);
  EXPECT_FALSE(compute_metrics(trace, kUnitLine, Path{}, opt).cycle_time.has_value());
}

// Random distance sequences against the definition checked sample by sample (position only,
// window of w samples).
TEST(MetricsTest, CycleTimeMatchesTheDefinitionOnRandomSequences) {
  const int cases = test::property_cases(300);
  for (int c = 0; c < cases; ++c) {
    const auto seed = static_cast<std::uint64_t>(c);
    auto rng = test::make_rng(seed);
    const auto n = static_cast<std::size_t>(1 + rng() % 40);
    const auto w = static_cast<std::size_t>(rng() % 5);
    MetricsOptions opt = position_only(Vec3(0.3, -0.2, 0.4), 1e-4);
    opt.settle_window = static_cast<double>(w) * 1e-3;
    Trace trace = zero_trace(n, 1e-3, 0.0);
    // mostly settling sequences: the chance of being inside grows along the trace
    for (std::size_t k = 0; k < n; ++k) {
      const bool inside = test::uniform(rng, 0, 1) < 0.3 + 0.7 * static_cast<double>(k) / static_cast<double>(n);
      const double r = inside ? test::uniform(rng, 0, 0.99) : test::uniform(rng, 1.01, 5);
      trace.samples[k].tcp = opt.end_point + r * opt.settle_tolerance * test::random_unit(rng);
    }
    // the definition: the first k such that samples k .. k + w exist and are all inside
    std::optional<double> expected;
    for (std::size_t k = 0; k + w < n; ++k) {
      bool all_inside = true;
      for (std::size_t j = k; j <= k + w; ++j)
        all_inside = all_inside && (trace.samples[j].tcp - opt.end_point).norm() <= opt.settle_tolerance;
      if (all_inside) {
        expected = trace.samples[k].t;
        break;
      }
    }
    const Metrics m = compute_metrics(trace, kUnitLine, Path{}, opt);
    ASSERT_EQ(m.cycle_time.has_value(), expected.has_value()) << test::seed_text(seed);
    if (expected) {
      EXPECT_EQ(*m.cycle_time, *expected) << test::seed_text(seed);
    }
  }
}

// Tracking and orientation errors count while the reference runs; the settle tail does not.
TEST(MetricsTest, TrackingErrorIsTakenOverTheMotionOnly) {
  Trace trace = zero_trace(11, 1e-3, 0.005);
  for (TraceSample& s : trace.samples) {
    // 1 mm during the motion, 3 mm and a 10 degree twist after it
    const bool moving = s.t <= 0.005 + 1e-12;
    s.tcp = s.tcp_cmd + Vec3(0, moving ? 1e-3 : 3e-3, 0);
    s.rotation = Eigen::Quaterniond(Eigen::AngleAxisd(moving ? 0.01 : 0.17, Vec3::UnitZ()));
  }
  const Metrics m = compute_metrics(trace, kUnitLine, Path{}, MetricsOptions{});
  EXPECT_NEAR(m.tracking_error_max, 1e-3, kDistanceTolerance);
  EXPECT_NEAR(m.tracking_error_rms, 1e-3, kDistanceTolerance);
  EXPECT_NEAR(m.orientation_error_max, 0.01, 1e-12);
  EXPECT_NEAR(m.tracking_error.back(), 3e-3, kDistanceTolerance) << "the per-sample series covers the whole run";
  EXPECT_NEAR(m.orientation_error.back(), 0.17, 1e-12);
}

// Per joint: following error over the motion, torque peak and RMS and energy over the run,
// velocity peak and acceleration peak from differences of the link velocity.
TEST(MetricsTest, JointFiguresPerJoint) {
  JointVector tau, speed, following, a;
  tau << 10, -20, 0, 1, 2, -3;
  speed << 1, 0.5, -2, 0, 4, -1;
  following << 1e-4, -2e-4, 0, 3e-4, 0, -1e-4;
  a << 2, -5, 0.5, 0, 10, -1;
  Trace trace = zero_trace(101, 1e-3, 0.05);
  for (TraceSample& s : trace.samples) {
    s.tau = tau;
    s.qd_motor = speed;
    s.qd = a * s.t;
    // the following error doubles after the motion: not counted
    s.following_error = s.t <= 0.05 + 1e-12 ? following : JointVector(2 * following);
  }
  const Metrics m = compute_metrics(trace, kUnitLine, Path{}, MetricsOptions{});
  for (int i = 0; i < 6; ++i) {
    EXPECT_DOUBLE_EQ(m.torque_peak[i], std::abs(tau[i])) << i;
    EXPECT_NEAR(m.torque_rms[i], std::abs(tau[i]), 1e-12) << i;
    // |tau v| over 101 samples of 1 ms
    EXPECT_NEAR(m.energy[i], std::abs(tau[i] * speed[i]) * 0.101, 1e-9) << i;
    EXPECT_NEAR(m.following_error_max[i], std::abs(following[i]), 1e-15) << i;
    EXPECT_NEAR(m.following_error_rms[i], std::abs(following[i]), 1e-15) << i;
    EXPECT_NEAR(m.velocity_peak[i], std::abs(a[i]) * 0.1, 1e-12) << i;
    EXPECT_NEAR(m.acceleration_peak[i], std::abs(a[i]), kAccelerationRelativeTolerance * 10) << i;
  }
}

// A cubic commanded TCP p(t) = c0 + c1 t + c2 t^2 + c3 t^3 has the central third difference
// 6 c3 exactly (the lower terms cancel): peak and RMS |6 c3|.
TEST(MetricsTest, CommandedJerkOfACubicIsSixTimesTheCubicCoefficient) {
  constexpr double kDt = 0.01;
  const Vec3 c0(0.4, -0.1, 0.5), c1(0.2, 0.3, -0.1), c2(-1.0, 0.5, 2.0), c3(2.0, -3.0, 6.0);
  Trace trace = zero_trace(40, kDt);
  for (TraceSample& s : trace.samples) {
    const double t = s.t;
    s.tcp_cmd = c0 + c1 * t + c2 * t * t + c3 * t * t * t;
    s.tcp = s.tcp_cmd;
  }
  const Metrics m = compute_metrics(trace, kUnitLine, Path{}, MetricsOptions{});
  const double expected = 6 * c3.norm();
  EXPECT_NEAR(m.jerk_commanded_peak, expected, kJerkRelativeTolerance * expected);
  EXPECT_NEAR(m.jerk_commanded_rms, expected, kJerkRelativeTolerance * expected);
}

// The actual TCP's jerk is taken after the low-pass: a 5 Hz sine (a tenth of the 50 Hz cut-off)
// keeps its jerk amplitude A w^3, a 400 Hz one of the same amplitude (8 times the cut-off: noise
// to this metric) loses almost all of it.
TEST(MetricsTest, ActualJerkIsFilteredAsStated) {
  constexpr double kDt = 1e-3, kA = 1e-4;
  const auto jerk_of = [&](double f) {
    Trace trace = zero_trace(2001, kDt);
    for (TraceSample& s : trace.samples) s.tcp = Vec3(kA * std::sin(2 * kPi * f * s.t), 0, 0);
    return compute_metrics(trace, kUnitLine, Path{}, MetricsOptions{}).jerk_actual_peak;
  };
  const double w = 2 * kPi * 5;
  EXPECT_NEAR(jerk_of(5), kA * w * w * w, kPassBandTolerance * kA * w * w * w);
  const double w_high = 2 * kPi * 400;
  EXPECT_LT(jerk_of(400), 0.01 * kA * w_high * w_high * w_high);
}

// Residual vibration: a decaying-free 30 Hz oscillation of the error after the stop has a
// peak-to-peak of twice its amplitude and a dominant frequency of 30 Hz; a slow 1 Hz drift (the
// servo settling) is taken out by the high-pass. Corner windows end at the next corner's start.
TEST(MetricsTest, ResidualVibrationAmplitudeAndFrequency) {
  constexpr double kDt = 1e-3, kA = 5e-6, kF = 30;
  MetricsOptions opt;
  opt.vibration_highpass = 8;  // a quarter of the sine's frequency: 0.4 % of its amplitude lost
  opt.corners = {{0, 0.1, 0.2}, {1, 0.4, 0.5}};
  Trace trace = zero_trace(1601, kDt, 1.0);
  for (TraceSample& s : trace.samples) {
    s.tcp_cmd = Vec3(0.4, 0.1, 0.3);
    s.tcp = s.tcp_cmd + Vec3(0, kA * std::sin(2 * kPi * kF * s.t), 2e-4 * std::sin(2 * kPi * 1.0 * s.t));
  }
  const Metrics m = compute_metrics(trace, kUnitLine, Path{}, opt);
  EXPECT_NEAR(m.vibration_final.t_start, 1.0, 1e-12);
  EXPECT_NEAR(m.vibration_final.t_end, 1.5, 1e-12);
  EXPECT_NEAR(m.vibration_final.peak_to_peak, 2 * kA, kPassBandTolerance * 2 * kA);
  EXPECT_NEAR(m.vibration_final.frequency, kF, 0.5);
  ASSERT_EQ(m.vibration_corners.size(), 2u);
  EXPECT_NEAR(m.vibration_corners[0].t_start, 0.2, 1e-12);
  EXPECT_NEAR(m.vibration_corners[0].t_end, 0.4, 1e-12) << "clipped at the next corner";
  EXPECT_NEAR(m.vibration_corners[1].t_end, 1.0, 1e-12) << "clipped at the reference's end";
  for (const Vibration& v : m.vibration_corners) {
    EXPECT_NEAR(v.peak_to_peak, 2 * kA, kPassBandTolerance * 2 * kA);
    EXPECT_NEAR(v.frequency, kF, 1.0);
  }
  ASSERT_EQ(m.vibration.size(), trace.samples.size());
}

// Joint limits: the first sample beyond a limit, on the reference and on the actual motion;
// exactly at the limit is allowed. Saturation share per joint.
TEST(MetricsTest, HealthNamesTheFirstViolationAndTheSaturation) {
  JointLimits limits;
  limits.velocity = JointVector::Constant(3.0);
  limits.acceleration = JointVector::Constant(20.0);
  JointTrajectory reference;
  reference.dt = 0.002;
  for (int k = 0; k < 10; ++k) {
    reference.q.push_back(JointVector::Zero());
    reference.qd.push_back(JointVector::Zero());
    reference.qdd.push_back(JointVector::Zero());
  }
  reference.qd[4][2] = -3.0;  // at the limit: fine
  reference.qd[6][2] = -3.0 * (1 + 1e-6);
  reference.qd[8][0] = 4.0;  // later and beyond: the first one counts
  reference.qdd[3][5] = 25;
  Trace trace = zero_trace(10, 0.002);
  trace.samples[5].qd[1] = 0.1;  // 50 rad/s^2 over one tick
  trace.saturated_ticks = {0, 0, 5, 0, 0, 1};
  trace.servo_ticks = 10;  // a servo at the setpoint rate: one tick per sample
  const Health h = check_health(trace, reference, limits);
  EXPECT_TRUE(h.reference_velocity.exceeded);
  EXPECT_EQ(h.reference_velocity.joint, 2);
  EXPECT_NEAR(h.reference_velocity.t, 0.012, 1e-12);
  EXPECT_TRUE(h.reference_acceleration.exceeded);
  EXPECT_EQ(h.reference_acceleration.joint, 5);
  EXPECT_FALSE(h.actual_velocity.exceeded);
  EXPECT_TRUE(h.actual_acceleration.exceeded);
  EXPECT_EQ(h.actual_acceleration.joint, 1);
  EXPECT_NEAR(h.actual_acceleration.t, 0.010, 1e-12);
  EXPECT_NEAR(h.actual_acceleration.value, 50, 1e-9);
  EXPECT_TRUE(h.saturated);
  EXPECT_NEAR(h.saturated_share[2], 0.5, 1e-12);
  EXPECT_NEAR(h.saturated_share[5], 0.1, 1e-12);
  EXPECT_TRUE(h.limits_exceeded());
  EXPECT_FALSE(check_health(zero_trace(10, 0.002), JointTrajectory{}, limits).limits_exceeded());
}

// Contour error against the planned path: an actual TCP on the blended arc is on the planned
// path (0) but away from the programmed corner; the two contour errors separate the designed
// deviation from the servo's.
TEST(MetricsTest, ContourErrorAgainstThePlannedAndTheProgrammedPath) {
  Program program = program_of({Line{Vec3(0, 0, 0), Vec3(0.1, 0, 0)}, Line{Vec3(0.1, 0, 0), Vec3(0.1, 0.1, 0)}});
  program.moves[0].transition = {Method::kArc, 0.01};
  const Path path = blend(program);
  ASSERT_EQ(path.corners.size(), 1u);
  Trace trace = zero_trace(3);
  // the middle of the arc, on the planned path; then 1 mm off it
  const double mid = path.offset(1) + 0.5 * length(path.pieces()[1].segment);
  trace.samples[0].tcp = path.point(mid);
  trace.samples[1].tcp = path.point(mid) + 1e-3 * (Vec3(0.1, 0, 0) - path.point(mid)).normalized();
  trace.samples[2].tcp = Vec3(0.05, 0, 0);
  const Metrics m = compute_metrics(trace, program, path, MetricsOptions{});
  EXPECT_LT(m.contour_error_planned[0], 1e-9);
  EXPECT_NEAR(m.contour_error_programmed[0], (path.point(mid) - Vec3(0.1, 0, 0)).norm() / std::sqrt(2.0), 1e-6);
  EXPECT_NEAR(m.contour_error_planned[1], 1e-3, 1e-6);
  EXPECT_LT(m.contour_error_planned[2], 1e-12);
  EXPECT_LT(m.contour_error_programmed[2], 1e-12);
}

// Contour error against an arc: the distance to the closest point of the arc, the circle at the
// same angle inside the sweep and the nearer end point outside it.
TEST(MetricsTest, ContourErrorAgainstAnArcIsTheDistanceToItsClosestPoint) {
  const Vec3 c(0.3, 0.1, 0.2), u(1, 0, 0), v(0, 1, 0), w(0, 0, 1);
  constexpr double kR = 0.05;
  // a half circle from c + r u through c + r v to c - r u
  const Program program = program_of({arc_of(c, u, v, kR, kPi)});
  const auto radial = [&](double phi) { return Vec3(std::cos(phi) * u + std::sin(phi) * v); };
  struct Case {
    Vec3 tcp;
    double contour;
  };
  const std::vector<Case> cases = {
      {c + (kR + 2e-3) * radial(0.7), 2e-3},                            // outside the circle
      {c + (kR - 3e-3) * radial(2.0), 3e-3},                            // inside the circle
      {c + (kR + 3e-3) * radial(kPi / 2) + 4e-3 * w, 5e-3},             // off the plane: 3-4-5
      {c + kR * radial(-kPi / 2), kR * std::sqrt(2.0)},                 // beyond the sweep: to an end point
      {c + (kR + 1e-3) * radial(-0.01), (c + (kR + 1e-3) * radial(-0.01) - (c + kR * u)).norm()},  // just before the start
      {c, kR},                                                          // the centre: every point at r
  };
  Trace trace = zero_trace(cases.size());
  for (std::size_t k = 0; k < cases.size(); ++k) {
    trace.samples[k].tcp = cases[k].tcp;
    trace.samples[k].tcp_cmd = cases[k].tcp;
  }
  const Metrics m = compute_metrics(trace, program, Path{}, MetricsOptions{});
  for (std::size_t k = 0; k < cases.size(); ++k) EXPECT_NEAR(m.contour_error_programmed[k], cases[k].contour, kDistanceTolerance) << "case " << k;
  EXPECT_NEAR(m.contour_error_programmed_max, kR * std::sqrt(2.0), kDistanceTolerance);
  EXPECT_EQ(m.tracking_error_max, 0.0);
}

// With several moves the contour error is the distance to the nearest move.
TEST(MetricsTest, ContourErrorIsTheDistanceToTheNearestMove) {
  // an L: along x, then along y
  const Program program = program_of({Line{Vec3(0, 0, 0), Vec3(1, 0, 0)}, Line{Vec3(1, 0, 0), Vec3(1, 1, 0)}});
  struct Case {
    Vec3 tcp;
    double contour;
  };
  const std::vector<Case> cases = {
      {Vec3(0.5, 0.002, 0), 0.002},                         // beside the first move
      {Vec3(1.003, 0.5, 0), 0.003},                         // beside the second move
      {Vec3(0.998, 0.001, 0), 0.001},                       // inside the corner: the nearer move
      {Vec3(1.002, -0.001, 0), std::sqrt(5.0) * 1e-3},      // outside the corner: the corner point
  };
  Trace trace = zero_trace(cases.size());
  for (std::size_t k = 0; k < cases.size(); ++k) trace.samples[k].tcp = cases[k].tcp;
  const Metrics m = compute_metrics(trace, program, Path{}, MetricsOptions{});
  for (std::size_t k = 0; k < cases.size(); ++k) EXPECT_NEAR(m.contour_error_programmed[k], cases[k].contour, kDistanceTolerance) << "case " << k;
}

// Random lines and arcs in 3D: a point offset from an interior point of a line perpendicularly by
// d, or from a point of an arc by dr in the radial direction and h along the normal, has contour
// error d, or sqrt(dr^2 + h^2).
TEST(MetricsTest, ContourErrorOfPerpendicularOffsetsOnRandomPrimitives) {
  const int cases = test::property_cases(300);
  for (int c = 0; c < cases; ++c) {
    const auto seed = static_cast<std::uint64_t>(1000 + c);
    auto rng = test::make_rng(seed);
    const Vec3 start(test::uniform(rng, -0.5, 0.5), test::uniform(rng, -0.5, 0.5), test::uniform(rng, 0, 1));
    const Vec3 e1 = test::random_unit(rng);
    const Vec3 e2 = test::random_perpendicular(rng, e1);
    const Vec3 e3 = e1.cross(e2);
    Program program;
    Vec3 tcp;
    double expected = 0;
    if (c % 2 == 0) {
      // a line along e1; an interior point moved along e2, e3
      const double len = test::uniform(rng, 0.01, 1);
      program = program_of({Line{start, start + len * e1}});
      const double s = test::uniform(rng, 0, len);
      const double d2 = test::uniform(rng, -5e-3, 5e-3), d3 = test::uniform(rng, -5e-3, 5e-3);
      tcp = start + s * e1 + d2 * e2 + d3 * e3;
      expected = std::hypot(d2, d3);
    } else {
      // an arc in the plane of e1, e2; a point on it moved radially and along the normal e3
      const double r = test::uniform(rng, 0.01, 0.5);
      const double sweep = test::uniform(rng, 0.1, 2 * kPi);
      const Arc arc = arc_of(start, e1, e2, r, sweep);
      program = program_of({arc});
      const double phi = test::uniform(rng, 0, sweep);
      const Vec3 radial = std::cos(phi) * e1 + std::sin(phi) * e2;
      const double dr = test::uniform(rng, -0.5, 0.5) * std::min(r, 5e-3), h = test::uniform(rng, -5e-3, 5e-3);
      tcp = start + (r + dr) * radial + h * e3;
      expected = std::hypot(dr, h);
    }
    Trace trace = zero_trace(1);
    trace.samples[0].tcp = tcp;
    const Metrics m = compute_metrics(trace, program, Path{}, MetricsOptions{});
    EXPECT_NEAR(m.contour_error_programmed[0], expected, kDistanceTolerance) << test::seed_text(seed);
  }
}

// Random programs of lines and arcs, commands near the path and actual TCPs near the commands:
// by the triangle inequality the contour error is at most |actual - any path point|, hence at
// most the tracking error plus the command's distance from the path; RMS <= max; nothing NaN.
TEST(MetricsTest, ContourErrorBoundedByTrackingErrorPlusCommandOffset) {
  const int cases = test::property_cases(100);
  for (int c = 0; c < cases; ++c) {
    const auto seed = static_cast<std::uint64_t>(5000 + c);
    auto rng = test::make_rng(seed);
    // a chain of 1..4 moves, each a line or an arc, joined end to start
    std::vector<Primitive> moves;
    Vec3 at(test::uniform(rng, -0.3, 0.3), test::uniform(rng, -0.3, 0.3), test::uniform(rng, 0.2, 0.8));
    const auto count = static_cast<int>(1 + rng() % 4);
    for (int k = 0; k < count; ++k) {
      if (rng() % 2 == 0) {
        const Vec3 end = at + test::uniform(rng, 0.01, 0.3) * test::random_unit(rng);
        moves.emplace_back(Line{at, end});
        at = end;
      } else {
        const Vec3 u = test::random_unit(rng);
        const Vec3 v = test::random_perpendicular(rng, u);
        const double r = test::uniform(rng, 0.01, 0.2);
        const Arc arc = arc_of(at - r * u, u, v, r, test::uniform(rng, 0.1, 2 * kPi));
        moves.emplace_back(arc);
        at = point(arc, length(arc));
      }
    }
    const Program program = program_of(moves);
    // samples: a point q on a random move, command q + e_cmd, actual command + e_act
    const std::size_t n = 30;
    Trace trace = zero_trace(n);
    std::vector<Vec3> on_path(n);
    std::vector<double> cmd_offset(n);
    for (std::size_t k = 0; k < n; ++k) {
      const Primitive& g = moves[rng() % moves.size()];
      on_path[k] = point(g, test::uniform(rng, 0, length(g)));
      const Vec3 e_cmd = test::uniform(rng, 0, 1e-3) * test::random_unit(rng);
      const Vec3 e_act = test::uniform(rng, 0, 5e-3) * test::random_unit(rng);
      cmd_offset[k] = e_cmd.norm();
      trace.samples[k].tcp_cmd = on_path[k] + e_cmd;
      trace.samples[k].tcp = trace.samples[k].tcp_cmd + e_act;
    }
    const Metrics m = compute_metrics(trace, program, Path{}, MetricsOptions{});
    ASSERT_EQ(m.contour_error_programmed.size(), n) << test::seed_text(seed);
    double max_contour = 0, max_tracking = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const TraceSample& s = trace.samples[k];
      ASSERT_TRUE(std::isfinite(m.contour_error_programmed[k])) << test::seed_text(seed) << " sample " << k;
      EXPECT_GE(m.contour_error_programmed[k], 0.0) << test::seed_text(seed);
      EXPECT_LE(m.contour_error_programmed[k], (s.tcp - on_path[k]).norm() + kDistanceTolerance) << test::seed_text(seed) << " sample " << k;
      EXPECT_LE(m.contour_error_programmed[k], m.tracking_error[k] + cmd_offset[k] + kDistanceTolerance)
          << test::seed_text(seed) << " sample " << k;
      EXPECT_NEAR(m.tracking_error[k], (s.tcp - s.tcp_cmd).norm(), kDistanceTolerance) << test::seed_text(seed);
      max_contour = std::max(max_contour, m.contour_error_programmed[k]);
      max_tracking = std::max(max_tracking, m.tracking_error[k]);
    }
    EXPECT_EQ(m.contour_error_programmed_max, max_contour) << test::seed_text(seed);
    EXPECT_EQ(m.tracking_error_max, max_tracking) << test::seed_text(seed);
    EXPECT_LE(m.tracking_error_rms, m.tracking_error_max * (1 + 1e-15)) << test::seed_text(seed);
    EXPECT_GT(m.tracking_error_rms, 0.0) << test::seed_text(seed);
  }
}

// ---- process metrics (gluing, welding): share of path below 90 % of the programmed speed and
// the minimum speed between the first and the last move, on the actual TCP

// A trace that follows s(t) along `path` exactly (actual = commanded = path point), sampled at
// dt until the reference ends at t_end; reference_s filled in as execute() does.
struct Followed {
  Trace trace;
  MetricsOptions options;
};
template <class Profile>
Followed follow(const Path& path, Profile s_of_t, double t_end, double dt) {
  Followed f;
  f.trace = zero_trace(static_cast<std::size_t>(std::llround(t_end / dt)) + 1, dt);
  for (TraceSample& sample : f.trace.samples) {
    const double s = std::clamp(s_of_t(sample.t), 0.0, path.length());
    sample.tcp = sample.tcp_cmd = path.point(s);
    f.options.reference_s.push_back(s);
  }
  f.options.end_point = path.point(path.length());
  return f;
}

// s(t) of a run-up at constant acceleration to v, cruise, and a stop at constant deceleration,
// both ramps `ramp` long (m): the speed is v exactly from s = ramp to s = length - ramp.
auto trapezoid(double v, double ramp, double length) {
  const double a = v * v / (2 * ramp);
  const double t1 = v / a, t2 = t1 + (length - 2 * ramp) / v;
  return [=](double t) {
    if (t <= t1) return 0.5 * a * t * t;
    if (t <= t2) return ramp + v * (t - t1);
    const double u = std::min(t - t2, t1);
    return length - ramp + v * u - 0.5 * a * u * u;
  };
}

// The constant-speed line: collinear moves at their programmed speed between run-up and stop
// (both within the first and last move) give share 0 and min speed = feed; the ramps, slower
// than 90 % of the feed, are outside the window.
TEST(ProcessMetrics, AConstantSpeedLineHasNoShareBelowAndItsFeedAsMinimum) {
  const int cases = test::property_cases(50);
  for (int c = 0; c < cases; ++c) {
    const auto seed = static_cast<std::uint64_t>(1000 + c);
    auto rng = test::make_rng(seed);
    const double v = test::uniform(rng, 0.01, 0.5);     // m/s
    const double piece = test::uniform(rng, 0.02, 0.2);  // m
    const int moves = 3 + static_cast<int>(rng() % 4);
    const Vec3 dir = test::random_unit(rng);
    Program program;
    for (int k = 0; k < moves; ++k) {
      Move m = move_of(Line{k * piece * dir, (k + 1) * piece * dir});
      m.limits.velocity = v;
      m.transition.method = Method::kNone;  // an exact stop: collinear junctions do not stop
      program.moves.push_back(m);
    }
    const Path path = blend(program);
    ASSERT_EQ(path.pieces().size(), static_cast<std::size_t>(moves)) << test::seed_text(seed);
    for (const PathPiece& p : path.pieces()) ASSERT_FALSE(p.stop_before) << test::seed_text(seed);
    const double length = path.length();
    const double ramp = test::uniform(rng, 0.3, 0.9) * piece;
    const double dt = 2e-3;
    const double t_end = 2 * ramp / (0.5 * v) + (length - 2 * ramp) / v;
    const Followed f = follow(path, trapezoid(v, ramp, length), t_end, dt);
    const Metrics m = compute_metrics(f.trace, program, path, f.options);
    ASSERT_TRUE(m.process.has_value()) << test::seed_text(seed);
    EXPECT_NEAR(m.process->s_start, piece, 1e-12) << test::seed_text(seed);
    EXPECT_NEAR(m.process->s_end, length - piece, 1e-12) << test::seed_text(seed);
    EXPECT_EQ(m.process->share_below_90pct_speed, 0.0) << test::seed_text(seed);
    // central differences of a linear s(t): exact up to rounding
    EXPECT_NEAR(m.process->min_speed, v, 1e-9 * v) << test::seed_text(seed);
  }
}

// An exact stop at a 90 degree corner: the window is the corner point, the TCP is at rest there.
TEST(ProcessMetrics, AnExactStopCornerHasMinimumSpeedZero) {
  Program program;
  for (const auto& [a, b] : {std::pair{Vec3(0, 0, 0), Vec3(0.1, 0, 0)}, std::pair{Vec3(0.1, 0, 0), Vec3(0.1, 0.1, 0)}}) {
    Move m = move_of(Line{a, b});
    m.transition.method = Method::kNone;
    program.moves.push_back(m);
  }
  const Path path = blend(program);
  ASSERT_TRUE(path.pieces()[1].stop_before);
  const double v = 0.1;
  // rest to rest on each line (trapezoids with half-length ramps), a 20 ms dwell at the corner
  const auto leg = trapezoid(v, 0.05, 0.1);
  const double t_leg = 2 * 0.05 / (0.5 * v);
  const auto s_of_t = [&](double t) {
    if (t <= t_leg) return leg(t);
    if (t <= t_leg + 0.02) return 0.1;
    return 0.1 + leg(t - t_leg - 0.02);
  };
  const Followed f = follow(path, s_of_t, 2 * t_leg + 0.02, 2e-3);
  const Metrics m = compute_metrics(f.trace, program, path, f.options);
  ASSERT_TRUE(m.process.has_value());
  EXPECT_NEAR(m.process->s_start, 0.1, 1e-12);
  EXPECT_NEAR(m.process->s_end, 0.1, 1e-12);
  EXPECT_LT(m.process->min_speed, 1e-9);
  EXPECT_EQ(m.process->share_below_90pct_speed, 1.0);
}

// A slow-down to half the feed over a known stretch: the share is that stretch over the window
// (to one sample's length at each end of the stretch).
TEST(ProcessMetrics, AShareIsTheSlowStretchOverTheWindow) {
  Program program;
  for (int k = 0; k < 3; ++k) program.moves.push_back(move_of(Line{Vec3(0.1 * k, 0, 0), Vec3(0.1 * (k + 1), 0, 0)}));
  for (Move& m : program.moves) m.transition.method = Method::kNone;
  const Path path = blend(program);
  const double v = 0.1, slow = 0.05, dt = 1e-3;
  // from rest at full speed (a jump: the ramps do not matter here), half speed on s in [0.13, 0.17]
  const auto s_of_t = [&](double t) {
    const double t_a = 0.13 / v, t_b = t_a + 0.04 / slow;
    if (t <= t_a) return v * t;
    if (t <= t_b) return 0.13 + slow * (t - t_a);
    return 0.17 + v * (t - t_b);
  };
  const double t_end = 0.13 / v + 0.04 / slow + 0.13 / v;
  const Followed f = follow(path, s_of_t, t_end, dt);
  const Metrics m = compute_metrics(f.trace, program, path, f.options);
  ASSERT_TRUE(m.process.has_value());
  EXPECT_NEAR(m.process->share_below_90pct_speed, 0.04 / 0.1, 2 * v * dt / 0.1);
  EXPECT_NEAR(m.process->min_speed, slow, 1e-9);
}

// One move has no stretch between a first and a last move: no process figures, never a NaN.
TEST(ProcessMetrics, ASingleMoveHasNone) {
  Program program = program_of({Line{Vec3(0, 0, 0), Vec3(0.1, 0, 0)}});
  const Path path = blend(program);
  const Followed f = follow(path, [](double t) { return 0.1 * t; }, 1.0, 2e-3);
  EXPECT_FALSE(compute_metrics(f.trace, program, path, f.options).process.has_value());
  MetricsOptions none = f.options;
  none.reference_s.clear();
  EXPECT_FALSE(compute_metrics(f.trace, program, path, none).process.has_value());
}

}  // namespace
}  // namespace blendbench
