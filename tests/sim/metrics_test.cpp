#include "blendbench/sim/metrics.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <vector>

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
constexpr double kPi = std::numbers::pi;

// A sample at time t with every vector zero (TraceSample leaves its Eigen members uninitialised).
TraceSample sample_at(double t) {
  TraceSample s;
  s.t = t;
  s.q_cmd = s.qd_cmd = s.q = s.qd = s.tau = JointVector::Zero();
  s.tcp_cmd = s.tcp = Vec3::Zero();
  return s;
}

// n samples on a 1 ms grid.
Trace zero_trace(std::size_t n, double dt = 1e-3) {
  Trace trace;
  for (std::size_t k = 0; k < n; ++k) trace.samples.push_back(sample_at(static_cast<double>(k) * dt));
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
  ASSERT_EQ(m.contour_error.size(), trace.samples.size());
  for (std::size_t k = 0; k < trace.samples.size(); ++k) {
    EXPECT_NEAR(m.tracking_error[k], kOffset, kDistanceTolerance) << "sample " << k;
    EXPECT_NEAR(m.contour_error[k], kOffset, kDistanceTolerance) << "sample " << k;
  }
  EXPECT_NEAR(m.tracking_error_max, kOffset, kDistanceTolerance);
  EXPECT_NEAR(m.tracking_error_rms, kOffset, kDistanceTolerance);
  EXPECT_NEAR(m.contour_error_max, kOffset, kDistanceTolerance);
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
    EXPECT_NEAR(m.contour_error[k], 2e-3, kDistanceTolerance) << "sample " << k;
  }
  EXPECT_NEAR(m.contour_error_max, 2e-3, kDistanceTolerance);
  EXPECT_NEAR(m.tracking_error_max, std::sqrt(13.0) * 1e-3, kDistanceTolerance);
}

// Beyond the end of the line the contour error is the distance to the end point.
TEST(MetricsTest, ContourErrorPastTheEndIsTheDistanceToTheEndPoint) {
  Trace trace = zero_trace(1);
  trace.samples[0].tcp_cmd = Vec3(1, 0, 0);
  trace.samples[0].tcp = Vec3(1.003, 0.004, 0);
  const Metrics m = compute_metrics(trace, kUnitLine, Path{}, MetricsOptions{});
  EXPECT_NEAR(m.contour_error[0], 5e-3, kDistanceTolerance);
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
  EXPECT_TRUE(m.contour_error.empty());
  EXPECT_EQ(m.tracking_error_max, 0.0);
  EXPECT_EQ(m.tracking_error_rms, 0.0);
  EXPECT_EQ(m.contour_error_max, 0.0);
  EXPECT_EQ(m.cartesian_jerk_peak, 0.0);
  EXPECT_EQ(m.joint_jerk_peak, 0.0);
  EXPECT_FALSE(m.joint_velocity_limit_exceeded);
  EXPECT_FALSE(m.torque_limit_reached);
}

// Settling: TCP distances from the end point in units of the tolerance (dyadic, so the sample
// exactly at the tolerance is exact in floating point).
struct SettleCase {
  std::vector<double> distance;   // per sample, in tolerances
  std::optional<std::size_t> settled_at;  // expected first sample of the final in-tolerance run
};

Trace settle_trace(const std::vector<double>& distance, const Vec3& end, double tolerance) {
  Trace trace = zero_trace(distance.size());
  for (std::size_t k = 0; k < distance.size(); ++k) {
    trace.samples[k].tcp = end + Vec3(distance[k] * tolerance, 0, 0);
    trace.samples[k].tcp_cmd = end;
  }
  return trace;
}

TEST(MetricsTest, CycleTimeIsTheStartOfTheFinalRunWithinTolerance) {
  MetricsOptions opt;
  opt.end_point = Vec3(0.5, 0.25, 0.125);
  opt.settle_tolerance = std::ldexp(1.0, -13);  // 0.12 mm, a power of two
  const std::vector<SettleCase> cases = {
      // enters, leaves again (overshoot), settles at sample 4
      {{8, 4, 0.5, 2, 0.5, 0.25, 0}, 4},
      // exactly at the tolerance counts as within
      {{4, 1, 0.5, 1, 0}, 1},
      // within from the first sample: the cycle time is 0
      {{0.5, 0.25, 0}, 0},
      // settles only at the last sample
      {{3, 2, 1}, 2},
      // inside earlier but outside at the end: never settles
      {{4, 0.5, 0.25, 1.5}, std::nullopt},
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
  MetricsOptions opt;
  opt.end_point = Vec3(0.4, 0, 0.3);
  opt.settle_tolerance = 1e-4;
  Trace trace = zero_trace(3);
  for (TraceSample& s : trace.samples) s.tcp = opt.end_point + Vec3(0.8e-4, 0.8e-4, 0);
  EXPECT_FALSE(compute_metrics(trace, kUnitLine, Path{}, opt).cycle_time.has_value());
  trace.samples.back().tcp = opt.end_point;
  const Metrics m = compute_metrics(trace, kUnitLine, Path{}, opt);
  ASSERT_TRUE(m.cycle_time.has_value());
  EXPECT_EQ(*m.cycle_time, trace.samples.back().t);
}

// Random distance sequences against the definition checked sample by sample.
TEST(MetricsTest, CycleTimeMatchesTheDefinitionOnRandomSequences) {
  const int cases = test::property_cases(300);
  MetricsOptions opt;
  opt.end_point = Vec3(0.3, -0.2, 0.4);
  opt.settle_tolerance = 1e-4;
  for (int c = 0; c < cases; ++c) {
    const auto seed = static_cast<std::uint64_t>(c);
    auto rng = test::make_rng(seed);
    const auto n = static_cast<std::size_t>(1 + rng() % 40);
    Trace trace = zero_trace(n);
    // mostly settling sequences: the chance of being inside grows along the trace
    for (std::size_t k = 0; k < n; ++k) {
      const bool inside = test::uniform(rng, 0, 1) < 0.3 + 0.7 * static_cast<double>(k) / static_cast<double>(n);
      const double r = inside ? test::uniform(rng, 0, 0.99) : test::uniform(rng, 1.01, 5);
      trace.samples[k].tcp = opt.end_point + r * opt.settle_tolerance * test::random_unit(rng);
    }
    // the definition: the first k such that every sample from k on is within the tolerance
    std::optional<double> expected;
    for (std::size_t k = 0; k < n; ++k) {
      bool all_inside = true;
      for (std::size_t j = k; j < n; ++j)
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

// Peaks of |qd| and |tau| per joint, whatever the sign.
TEST(MetricsTest, JointVelocityAndTorquePeaksPerJoint) {
  Trace trace = zero_trace(3);
  trace.samples[0].qd << 1.0, -2.0, 0.5, 0, 0, -0.25;
  trace.samples[1].qd << -1.5, 1.0, 0.25, 0, 3, 0;
  trace.samples[2].qd << 0.5, 0.5, -0.75, 0, -3.5, 0.125;
  trace.samples[0].tau << 10, -20, 0, 1, 2, 3;
  trace.samples[1].tau << -30, 5, 0, -4, 2, 1;
  trace.samples[2].tau << 0, 0, 7, 0, -2.5, 0;
  const Metrics m = compute_metrics(trace, kUnitLine, Path{}, MetricsOptions{});
  JointVector qd_peak, tau_peak;
  qd_peak << 1.5, 2.0, 0.75, 0, 3.5, 0.25;
  tau_peak << 30, 20, 7, 4, 2.5, 3;
  EXPECT_EQ(m.joint_velocity_peak, qd_peak) << m.joint_velocity_peak.transpose();
  EXPECT_EQ(m.torque_peak, tau_peak) << m.torque_peak.transpose();
  // the default limits are unbounded
  EXPECT_FALSE(m.joint_velocity_limit_exceeded);
  EXPECT_FALSE(m.torque_limit_reached);
}

// The velocity limit is exceeded only strictly above it; reaching it exactly is allowed.
TEST(MetricsTest, VelocityLimitExceededOnlyAboveTheLimit) {
  MetricsOptions opt;
  opt.velocity_limits = JointVector::Constant(3.0);
  Trace trace = zero_trace(2);
  trace.samples[0].qd = JointVector::Constant(1.0);
  // exactly at the limit on one joint, negative direction
  trace.samples[1].qd << 0, 0, -3.0, 0, 0, 0;
  EXPECT_FALSE(compute_metrics(trace, kUnitLine, Path{}, opt).joint_velocity_limit_exceeded);
  // just above on one joint
  trace.samples[1].qd[2] = -std::nextafter(3.0, 4.0);
  EXPECT_TRUE(compute_metrics(trace, kUnitLine, Path{}, opt).joint_velocity_limit_exceeded);
  // above on a joint whose own limit is higher: not exceeded
  opt.velocity_limits[2] = 3.5;
  EXPECT_FALSE(compute_metrics(trace, kUnitLine, Path{}, opt).joint_velocity_limit_exceeded);
}

// The torque limit is reached at the limit (the simulator clamps to it, so a saturated joint sits
// exactly there) or when the trace says a torque was clamped; below it is not.
TEST(MetricsTest, TorqueLimitReachedAtTheLimitOrWhenSaturated) {
  MetricsOptions opt;
  opt.torque_limits << 150, 150, 150, 28, 28, 28;
  Trace trace = zero_trace(2);
  trace.samples[1].tau << 100, -120, 80, 20, -27, 10;
  EXPECT_FALSE(compute_metrics(trace, kUnitLine, Path{}, opt).torque_limit_reached);
  // just below the limit (relative 1e-9) is not reached
  trace.samples[1].tau[4] = -28 * (1 - 1e-9);
  EXPECT_FALSE(compute_metrics(trace, kUnitLine, Path{}, opt).torque_limit_reached);
  // exactly at the limit is reached
  trace.samples[1].tau[4] = -28;
  EXPECT_TRUE(compute_metrics(trace, kUnitLine, Path{}, opt).torque_limit_reached);
  // and so is a clamped torque that lost a few ulps on the way back (the code's band: 1e-12 relative)
  trace.samples[1].tau[4] = -28 * (1 - 1e-13);
  EXPECT_TRUE(compute_metrics(trace, kUnitLine, Path{}, opt).torque_limit_reached);
  // below every limit but flagged as clamped by the simulator
  trace.samples[1].tau[4] = 0;
  trace.torque_saturated = true;
  EXPECT_TRUE(compute_metrics(trace, kUnitLine, Path{}, opt).torque_limit_reached);
}

// A cubic commanded trajectory p(t) = c0 + c1 t + c2 t^2 + c3 t^3 has third difference
// 6 c3 dt^3 exactly (the lower terms cancel), so the jerk peak is |6 c3| (per joint: the largest).
TEST(MetricsTest, JerkPeaksOfACubicAreSixTimesTheCubicCoefficient) {
  constexpr double kDt = 0.01;
  const Vec3 c0(0.4, -0.1, 0.5), c1(0.2, 0.3, -0.1), c2(-1.0, 0.5, 2.0), c3(2.0, -3.0, 6.0);
  JointVector j0, j1, j2, j3;
  j0 << 0.1, -1.2, 1.5, -0.3, 1.57, 0;
  j1 << 0.5, -0.2, 0.1, 0, 0.3, -1;
  j2 << 1, 2, -3, 0.5, 0, 4;
  j3 << 4, -7, 2, 0.5, 0, -3;  // joint 1 has the largest |c3|: jerk 42 rad/s^3
  Trace trace = zero_trace(40, kDt);
  for (TraceSample& s : trace.samples) {
    const double t = s.t;
    s.tcp_cmd = c0 + c1 * t + c2 * t * t + c3 * t * t * t;
    s.tcp = s.tcp_cmd;
    s.q_cmd = j0 + j1 * t + j2 * t * t + j3 * t * t * t;
  }
  const Metrics m = compute_metrics(trace, kUnitLine, Path{}, MetricsOptions{});
  const double cartesian = 6 * c3.norm();
  EXPECT_NEAR(m.cartesian_jerk_peak, cartesian, kJerkRelativeTolerance * cartesian);
  EXPECT_NEAR(m.joint_jerk_peak, 42.0, kJerkRelativeTolerance * 42.0);
}

// A quadratic has no jerk; the measured peak is rounding only.
TEST(MetricsTest, JerkOfAQuadraticIsZero) {
  constexpr double kDt = 0.01;
  Trace trace = zero_trace(20, kDt);
  for (TraceSample& s : trace.samples) {
    s.tcp_cmd = Vec3(0.3, 0.2, 0.1) + Vec3(1, -2, 3) * s.t * s.t;
    s.q_cmd = JointVector::Constant(0.5) + JointVector::Constant(4.0) * s.t * s.t;
  }
  const Metrics m = compute_metrics(trace, kUnitLine, Path{}, MetricsOptions{});
  EXPECT_LT(m.cartesian_jerk_peak, kJerkRelativeTolerance * 6);
  EXPECT_LT(m.joint_jerk_peak, kJerkRelativeTolerance * 6);
}

// A single 1 um bump of one joint's command in the middle of the trace gives the third
// differences 1, -3, 3, -1 um / dt^3 on the following samples: the peak is the largest of them
// (3), not the first or the last, and the Cartesian command, unchanged, has none.
TEST(MetricsTest, JerkPeakIsTheLargestThirdDifference) {
  constexpr double kDt = 1e-3;
  Trace trace = zero_trace(12, kDt);
  trace.samples[6].q_cmd[3] = 1e-6;
  const Metrics m = compute_metrics(trace, kUnitLine, Path{}, MetricsOptions{});
  EXPECT_NEAR(m.joint_jerk_peak, 3 * 1e-6 / (kDt * kDt * kDt), 1e-6 * 3e3);
  EXPECT_EQ(m.cartesian_jerk_peak, 0.0);
}

// Fewer than four samples give no third difference: the jerk peaks stay zero.
TEST(MetricsTest, NoJerkFromFewerThanFourSamples) {
  Trace trace = zero_trace(3);
  trace.samples[1].tcp_cmd = Vec3(1, 0, 0);
  trace.samples[1].q_cmd = JointVector::Constant(1);
  const Metrics m = compute_metrics(trace, kUnitLine, Path{}, MetricsOptions{});
  EXPECT_EQ(m.cartesian_jerk_peak, 0.0);
  EXPECT_EQ(m.joint_jerk_peak, 0.0);
}

// Joint acceleration from differences of the actual velocity: qd = a t gives the peak |a|.
TEST(MetricsTest, JointAccelerationPeakFromVelocityDifferences) {
  JointVector a;
  a << 2, -5, 0.5, 0, 10, -1;
  Trace trace = zero_trace(10);
  for (TraceSample& s : trace.samples) s.qd = a * s.t;
  const Metrics m = compute_metrics(trace, kUnitLine, Path{}, MetricsOptions{});
  for (int i = 0; i < 6; ++i)
    EXPECT_NEAR(m.joint_acceleration_peak[i], std::abs(a[i]), kAccelerationRelativeTolerance * 10) << "joint " << i;
}

// The path deviation is the largest corner deviation the blender reported; no corners, none.
TEST(MetricsTest, PathDeviationMaxFromTheCornerReports) {
  const Trace trace = zero_trace(2);
  Path path;
  EXPECT_EQ(compute_metrics(trace, kUnitLine, path, MetricsOptions{}).path_deviation_max, 0.0);
  for (const double d : {1e-3, 4e-3, 0.0, 2.5e-3}) {
    CornerReport c;
    c.index = static_cast<int>(path.corners.size());
    c.deviation = d;
    path.corners.push_back(c);
  }
  EXPECT_EQ(compute_metrics(trace, kUnitLine, path, MetricsOptions{}).path_deviation_max, 4e-3);
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
  for (std::size_t k = 0; k < cases.size(); ++k) EXPECT_NEAR(m.contour_error[k], cases[k].contour, kDistanceTolerance) << "case " << k;
  EXPECT_NEAR(m.contour_error_max, kR * std::sqrt(2.0), kDistanceTolerance);
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
  for (std::size_t k = 0; k < cases.size(); ++k) EXPECT_NEAR(m.contour_error[k], cases[k].contour, kDistanceTolerance) << "case " << k;
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
    EXPECT_NEAR(m.contour_error[0], expected, kDistanceTolerance) << test::seed_text(seed);
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
    ASSERT_EQ(m.contour_error.size(), n) << test::seed_text(seed);
    double max_contour = 0, max_tracking = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const TraceSample& s = trace.samples[k];
      ASSERT_TRUE(std::isfinite(m.contour_error[k])) << test::seed_text(seed) << " sample " << k;
      EXPECT_GE(m.contour_error[k], 0.0) << test::seed_text(seed);
      EXPECT_LE(m.contour_error[k], (s.tcp - on_path[k]).norm() + kDistanceTolerance) << test::seed_text(seed) << " sample " << k;
      EXPECT_LE(m.contour_error[k], m.tracking_error[k] + cmd_offset[k] + kDistanceTolerance)
          << test::seed_text(seed) << " sample " << k;
      EXPECT_NEAR(m.tracking_error[k], (s.tcp - s.tcp_cmd).norm(), kDistanceTolerance) << test::seed_text(seed);
      max_contour = std::max(max_contour, m.contour_error[k]);
      max_tracking = std::max(max_tracking, m.tracking_error[k]);
    }
    EXPECT_EQ(m.contour_error_max, max_contour) << test::seed_text(seed);
    EXPECT_EQ(m.tracking_error_max, max_tracking) << test::seed_text(seed);
    EXPECT_LE(m.tracking_error_rms, m.tracking_error_max * (1 + 1e-15)) << test::seed_text(seed);
    EXPECT_GT(m.tracking_error_rms, 0.0) << test::seed_text(seed);
  }
}

}  // namespace
}  // namespace blendbench
