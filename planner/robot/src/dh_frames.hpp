#pragma once
// Private to planner/robot: the geometry shared by the closed-form solvers' fits (ur_ik.cpp,
// spherical_ik.cpp) that find a DH model in a chain from its joint axis lines at q = 0.

#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "blendbench/robot/dh.hpp"

namespace blendbench::dh {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kTwoPi = 2 * std::numbers::pi;
// How far (rad, m) a chain may deviate from a closed-form pattern and still be solved; the
// closed form runs on the ideal geometry and polishing against the real chain removes the
// difference.
inline constexpr double kStructureTol = 1e-6;
// How closely (m, rad) the DH model found in a chain must reproduce its forward kinematics.
inline constexpr double kModelTol = 1e-5;

// Angle wrapped into (-pi, pi].
inline double wrap_pi(double angle) {
  const double a = std::remainder(angle, kTwoPi);
  return a <= -kPi ? a + kTwoPi : a;
}

// Signed angle (rad) that turns `from` into `to` about `axis`; all three unit, from and to
// perpendicular to axis.
inline double angle_about(const Vec3& from, const Vec3& to, const Vec3& axis) {
  return std::atan2(from.cross(to).dot(axis), from.dot(to));
}

// The unit part of v perpendicular to the unit vector n.
inline Vec3 perpendicular_unit(const Vec3& v, const Vec3& n) { return (v - v.dot(n) * n).normalized(); }

// The point of line (p, u) closest to line (q, v); u, v unit and not parallel. Minimising
// |p + s u - q - t v|^2 gives s - b t = -u.w and b s - t = -v.w with b = u.v, w = p - q.
inline Vec3 closest_point(const Vec3& p, const Vec3& u, const Vec3& q, const Vec3& v) {
  const Vec3 w = p - q;
  const double b = u.dot(v);
  const double s = (b * v.dot(w) - u.dot(w)) / (1 - b * b);
  return p + s * u;
}

// Distance between line (p, u) and line (q, v); u, v unit and not parallel.
inline double line_distance(const Vec3& p, const Vec3& u, const Vec3& q, const Vec3& v) {
  return (closest_point(p, u, q, v) - closest_point(q, v, p, u)).norm();
}

// A DH frame whose axis is twisted by alpha = +-pi/2 against the previous one: z is the next
// joint axis u (made perpendicular to z_prev), x the common normal (z_prev x z for +pi/2,
// z x z_prev for -pi/2). Flipping z flips x and shifts the joint's zero offset by pi; the sign
// is chosen so |offset| <= pi/2, i.e. the DH zero is as close to the chain's zero as possible.
struct TwistedFrame {
  Vec3 z, x;
  double axis_sign;  // of the next joint: u = axis_sign * z
  double offset;     // of this frame's joint: angle from x_prev to x about z_prev at q = 0
};
inline TwistedFrame twisted_frame(const Vec3& z_prev, const Vec3& x_prev, const Vec3& u, double alpha) {
  TwistedFrame f;
  f.z = perpendicular_unit(u, z_prev);
  f.x = (alpha > 0 ? z_prev.cross(f.z) : f.z.cross(z_prev)).normalized();
  f.axis_sign = 1;
  f.offset = angle_about(x_prev, f.x, z_prev);
  if (std::abs(f.offset) > kPi / 2) {
    f.z = -f.z;
    f.x = -f.x;
    f.axis_sign = -1;
    f.offset = wrap_pi(f.offset + kPi);
  }
  return f;
}

// A DH frame on a joint axis parallel to the previous one (alpha = 0): x points along the
// common normal from o_prev to o (both in one plane perpendicular to z), the signed length
// a = (o - o_prev).x, and the sign of x is chosen so |offset| <= pi/2.
struct ParallelFrame {
  Vec3 x;
  double a;
  double offset;
};
inline ParallelFrame parallel_frame(const Vec3& z, const Vec3& x_prev, const Vec3& o_prev, const Vec3& o) {
  ParallelFrame f;
  const Vec3 v = o - o_prev;
  f.a = v.norm();
  f.x = v / f.a;
  f.offset = angle_about(x_prev, f.x, z);
  if (std::abs(f.offset) > kPi / 2) {
    f.x = -f.x;
    f.a = -f.a;
    f.offset = wrap_pi(f.offset + kPi);
  }
  return f;
}

// The chain at q = 0 in its base frame: each joint's axis line (a point p on it, unit direction
// u) and the TCP pose. Calls fail(message) for a chain without six valid joints.
struct AxisLines {
  std::array<Vec3, 6> p, u;
  Eigen::Isometry3d tcp0 = Eigen::Isometry3d::Identity();
};
template <class Fail>
AxisLines axis_lines(const KinematicChain& chain, const Fail& fail) {
  if (chain.joints.size() != 6) fail("it has " + std::to_string(chain.joints.size()) + " joints, not 6");
  AxisLines out;
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  for (std::size_t i = 0; i < 6; ++i) {
    const JointSpec& joint = chain.joints[i];
    if (!(joint.axis.norm() > 0.5) || !joint.origin.matrix().allFinite()) {
      fail("joint '" + joint.name + "' has no valid axis or origin");
    }
    frame = frame * joint.origin;
    out.p[i] = frame.translation();
    out.u[i] = (frame.linear() * joint.axis).normalized();
  }
  out.tcp0 = frame * chain.tcp;
  return out;
}

// DH frame 0 of a chain whose first axis is z0 through p0: origin at the foot of the base
// origin on axis 1, x as close to the base x as possible.
inline Eigen::Isometry3d base_frame(const Vec3& p0, const Vec3& z0) {
  const Vec3 o0 = p0 - p0.dot(z0) * z0;
  const Vec3 base_x = Vec3::UnitX() - z0.x() * z0;
  const Vec3 x0 = base_x.norm() > 0.1 ? base_x.normalized() : perpendicular_unit(Vec3::UnitY(), z0);
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
  base.linear() << x0, z0.cross(x0), z0;
  base.translation() = o0;
  return base;
}

// The x axis of DH frame 6 on axis z5: as close to the TCP's x at q = 0 as possible.
inline Vec3 flange_x(const Eigen::Isometry3d& tcp0, const Vec3& z5) {
  const Mat3 r = tcp0.linear();
  const Vec3 tcp_x = r.col(0) - r.col(0).dot(z5) * z5;
  return tcp_x.norm() > 0.1 ? tcp_x.normalized() : perpendicular_unit(r.col(1), z5);
}

}  // namespace blendbench::dh
