#include "blendbench/program/orientation.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "support/property.hpp"

namespace blendbench {
namespace {

constexpr double kTight = 1e-12;

Vec3 random_vector(std::mt19937_64& rng, double scale) {
  return Vec3(test::uniform(rng, -1, 1), test::uniform(rng, -1, 1), test::uniform(rng, -1, 1)) * scale;
}

Quat random_rotation(std::mt19937_64& rng) {
  Quat q(test::uniform(rng, -1, 1), test::uniform(rng, -1, 1), test::uniform(rng, -1, 1), test::uniform(rng, -1, 1));
  return q.normalized();
}

// A random transition: rates up to 20 rad/m, leads and length up to 50 mm.
BlendOrientation random_blend(std::mt19937_64& rng) {
  BlendOrientation b;
  b.corner = random_rotation(rng);
  b.rate_in = random_vector(rng, 20);
  b.rate_out = random_vector(rng, 20);
  b.lead_in = test::uniform(rng, 0, 0.05);
  b.lead_out = test::uniform(rng, 0, 0.05);
  b.length = test::uniform(rng, 1e-3, 0.05);
  return b;
}

TEST(Orientation, ExpAndLogAreInverseAndTakeTheShorterWay) {
  const int cases = test::property_cases(2000);
  for (int n = 0; n < cases; ++n) {
    const std::uint64_t seed = 1300 + static_cast<std::uint64_t>(n);
    auto rng = test::make_rng(seed);
    // angles from 1e-9 rad to just below pi
    const Vec3 axis = random_vector(rng, 1).normalized();
    const double angle = test::log_uniform(rng, 1e-9, std::numbers::pi - 1e-6);
    const Vec3 r = angle * axis;
    const Quat q = rotation_exp(r);
    EXPECT_NEAR(q.norm(), 1, kTight) << test::seed_text(seed);
    EXPECT_LE((rotation_log(q) - r).norm(), 1e-12 * std::max(1.0, angle)) << test::seed_text(seed);
    // the same rotation written with the other sign of the quaternion
    const Quat minus(-q.w(), -q.x(), -q.y(), -q.z());
    EXPECT_LE((rotation_log(minus) - r).norm(), 1e-12 * std::max(1.0, angle)) << test::seed_text(seed);
    EXPECT_TRUE(q.toRotationMatrix().isApprox(Eigen::AngleAxisd(angle, axis).toRotationMatrix(), 1e-12)) << test::seed_text(seed);
  }
}

TEST(Orientation, GeodesicTurnsAtItsRateAboutAFixedAxis) {
  const Quat start(Eigen::AngleAxisd(0.3, Vec3::UnitY()));
  const PieceOrientation piece{GeodesicOrientation{start, Vec3(0, 0, 2.0)}, {}};
  // 0.25 m at 2 rad/m: half a radian about z, applied in the base frame
  const Quat expected = Quat(Eigen::AngleAxisd(0.5, Vec3::UnitZ())) * start;
  EXPECT_LE(rotation_angle(orientation_at(piece, 0.25), expected), kTight);
  EXPECT_EQ(angular_rate_at(piece, 0.1), Vec3(0, 0, 2.0));
  const RotationBounds b = rotation_bounds(piece, 1.0, 0.0, 1.0);
  EXPECT_EQ(b.rate, 2.0);
  EXPECT_EQ(b.rate_d1, 0.0);
  EXPECT_EQ(b.rate_d2, 0.0);
}

// At both ends a transition continues the moves it joins: the same orientation, rate and zero
// rate derivative (the moves' slerps have rho' = 0), so angular velocity and acceleration are
// continuous.
TEST(Orientation, BlendJoinsBothMovesWithContinuousRateAndRateDerivative) {
  const int cases = test::property_cases(500);
  for (int n = 0; n < cases; ++n) {
    const std::uint64_t seed = 2300 + static_cast<std::uint64_t>(n);
    auto rng = test::make_rng(seed);
    const BlendOrientation b = random_blend(rng);
    const PieceOrientation piece{b, {}};
    const PieceOrientation in{GeodesicOrientation{rotation_exp(-b.lead_in * b.rate_in) * b.corner, b.rate_in}, {}};
    const PieceOrientation out{GeodesicOrientation{rotation_exp(b.lead_out * b.rate_out) * b.corner, b.rate_out}, {}};
    EXPECT_LE(rotation_angle(orientation_at(piece, 0.0), orientation_at(in, 0.0)), 1e-12) << test::seed_text(seed);
    EXPECT_LE(rotation_angle(orientation_at(piece, b.length), orientation_at(out, 0.0)), 1e-12) << test::seed_text(seed);
    const double scale = std::max(b.rate_in.norm(), b.rate_out.norm());
    EXPECT_LE((angular_rate_at(piece, 0.0) - b.rate_in).norm(), 1e-12 * scale) << test::seed_text(seed);
    EXPECT_LE((angular_rate_at(piece, b.length) - b.rate_out).norm(), 1e-12 * scale) << test::seed_text(seed);
    // rho' at the ends, one-sided, against its size inside: it vanishes like h
    const double h = 1e-6 * b.length;
    const RotationBounds inside = rotation_bounds(piece, b.length, 0.0, b.length);
    const double d_start = (angular_rate_at(piece, h) - angular_rate_at(piece, 0.0)).norm() / h;
    const double d_end = (angular_rate_at(piece, b.length) - angular_rate_at(piece, b.length - h)).norm() / h;
    EXPECT_LE(d_start, 1e-4 * inside.rate_d1 + 1e-9) << test::seed_text(seed);
    EXPECT_LE(d_end, 1e-4 * inside.rate_d1 + 1e-9) << test::seed_text(seed);
    // the rate is the derivative of the orientation: exp(h rho) R(x) = R(x + h) to h^2 rho' (a
    // rate off by 1 % would miss by 1e-2 h rho, four orders more)
    const double x = test::uniform(rng, 0.1, 0.9) * b.length;
    const Quat ahead = rotation_exp(h * angular_rate_at(piece, x)) * orientation_at(piece, x);
    EXPECT_LE(rotation_angle(ahead, orientation_at(piece, x + h)), h * h * inside.rate_d1 + 1e-14) << test::seed_text(seed);
    EXPECT_GT(1e-2 * h * scale, h * h * inside.rate_d1 + 1e-14) << test::seed_text(seed);
  }
}

// The bounds of a transition hold at ten times as many points as they are sampled at.
TEST(Orientation, BlendBoundsHoldOnADenserGrid) {
  const int cases = test::property_cases(200);
  for (int n = 0; n < cases; ++n) {
    const std::uint64_t seed = 3300 + static_cast<std::uint64_t>(n);
    auto rng = test::make_rng(seed);
    const BlendOrientation b = random_blend(rng);
    const PieceOrientation piece{b, {}};
    const double s0 = test::uniform(rng, 0, 0.5) * b.length;
    const double s1 = s0 + test::uniform(rng, 0.1, 0.5) * b.length;
    const RotationBounds bound = rotation_bounds(piece, b.length, s0, s1);
    const int m = 10 * kBoundSamples;
    const double h = (s1 - s0) / m;
    for (int i = 1; i < m; ++i) {
      const double x = s0 + i * h;
      const Vec3 r0 = angular_rate_at(piece, x - h);
      const Vec3 r1 = angular_rate_at(piece, x);
      const Vec3 r2 = angular_rate_at(piece, x + h);
      ASSERT_LE(r1.norm(), bound.rate) << test::seed_text(seed) << " at " << x;
      ASSERT_LE((r2 - r0).norm() / (2 * h), bound.rate_d1) << test::seed_text(seed) << " at " << x;
      ASSERT_LE((r2 - 2 * r1 + r0).norm() / (h * h), bound.rate_d2 * (1 + 1e-6) + 1e-6) << test::seed_text(seed) << " at " << x;
    }
  }
}

}  // namespace
}  // namespace blendbench
