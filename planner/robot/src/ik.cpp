#include "blendbench/robot/ik.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <optional>
#include <random>
#include <utility>

#include "blendbench/core/format.hpp"
#include "blendbench/core/input_error.hpp"

namespace blendbench {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2 * std::numbers::pi;
constexpr std::array<double, 6> kAlpha = {kPi / 2, 0, 0, kPi / 2, -kPi / 2, 0};

// Below this distance (m) from the shoulder or elbow degeneracy the angle of the free joint
// cannot be computed and is chosen as documented at ur_closed_form_ik.
constexpr double kFreeJointEps = 1e-12;
// Below this |sin(theta5)| the wrist counts as singular and theta6 is chosen as documented at
// ur_closed_form_ik instead of from rounding noise. A pose computed by forward kinematics at
// theta5 = 0 has |sin(theta5)| ~ 1e-15, or ~ 1e-12 when the shoulder is nearly singular too
// (theta1 then carries more rounding); the pose error of the choice is at most about pi times
// this value, below kIkPositionTol and kIkAngleTol.
constexpr double kWristSingular = 1e-11;
// How far (rad, m) a chain may deviate from the UR pattern and still be solved; the closed form
// runs on the ideal geometry and polishing against the real chain removes the difference.
constexpr double kStructureTol = 1e-6;
// How closely (m, rad) the DH model found in a chain must reproduce its forward kinematics.
constexpr double kModelTol = 1e-5;
// Rounding allowance (rad) on joint limits.
constexpr double kLimitSlack = 1e-9;
// Damped-least-squares polishing (Levenberg-Marquardt): iterations, the smallest and largest
// squared damping (the smallest is negligible against J^T J away from singularities and keeps
// the step bounded next to one; the damping grows tenfold after a step that does not help),
// and the error at which to stop (m, rad).
constexpr int kPolishIterations = 500;
constexpr double kPolishDampingMin = 1e-12;
constexpr double kPolishDampingMax = 1e2;
constexpr double kPolishTarget = 1e-14;

// Angle wrapped into (-pi, pi].
double wrap_pi(double angle) {
  const double a = std::remainder(angle, kTwoPi);
  return a <= -kPi ? a + kTwoPi : a;
}

// Signed angle (rad) that turns `from` into `to` about `axis`; all three unit, from and to
// perpendicular to axis.
double angle_about(const Vec3& from, const Vec3& to, const Vec3& axis) {
  return std::atan2(from.cross(to).dot(axis), from.dot(to));
}

// The unit part of v perpendicular to the unit vector n.
Vec3 perpendicular_unit(const Vec3& v, const Vec3& n) { return (v - v.dot(n) * n).normalized(); }

// The point of line (p, u) closest to line (q, v); u, v unit and not parallel. Minimising
// |p + s u - q - t v|^2 gives s - b t = -u.w and b s - t = -v.w with b = u.v, w = p - q.
Vec3 closest_point(const Vec3& p, const Vec3& u, const Vec3& q, const Vec3& v) {
  const Vec3 w = p - q;
  const double b = u.dot(v);
  const double s = (b * v.dot(w) - u.dot(w)) / (1 - b * b);
  return p + s * u;
}

// Distance between line (p, u) and line (q, v); u, v unit and not parallel.
double line_distance(const Vec3& p, const Vec3& u, const Vec3& q, const Vec3& v) {
  const Vec3 a = closest_point(p, u, q, v);
  const Vec3 b = closest_point(q, v, p, u);
  return (a - b).norm();
}

[[noreturn]] void not_ur(const std::string& what) {
  throw InputError("", 0, 0, "urdf", "the kinematic chain is not UR-type: " + what);
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
TwistedFrame twisted_frame(const Vec3& z_prev, const Vec3& x_prev, const Vec3& u, double alpha) {
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

// A DH frame on a joint axis parallel to the previous one (alpha = 0, d = 0): x points along
// the common normal from o_prev to o (both in one plane perpendicular to z), the signed length
// a = (o - o_prev).x, and the sign of x is chosen so |offset| <= pi/2.
struct ParallelFrame {
  Vec3 x;
  double a;
  double offset;
};
ParallelFrame parallel_frame(const Vec3& z, const Vec3& x_prev, const Vec3& o_prev, const Vec3& o) {
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

// The representative value + 2 pi k nearest `near` inside [lower, upper] (+- kLimitSlack), or
// none. The distance to `near` is convex in k, so clamping the unconstrained best k into the
// admissible range gives the constrained best.
std::optional<double> wrap_within(double value, double near, double lower, double upper) {
  const double inf = std::numeric_limits<double>::infinity();
  const double k_min = std::isfinite(lower) ? std::ceil((lower - kLimitSlack - value) / kTwoPi) : -inf;
  const double k_max = std::isfinite(upper) ? std::floor((upper + kLimitSlack - value) / kTwoPi) : inf;
  if (k_min > k_max) return std::nullopt;
  return value + std::clamp(std::round((near - value) / kTwoPi), k_min, k_max) * kTwoPi;
}

// At a wrist singularity (theta5 = 0 or pi) only theta234 +- theta6 is fixed, and the elbow
// must still reach o3 = o5 - d5 z4 with z4 = (sin theta234, -cos theta234) in frame 1. With the
// wrist centre o5 = (x, y) in frame 1, rho = |(x, y)|, gamma = atan2(y, x):
//   |o3|^2 = rho^2 + d5^2 - 2 d5 rho sin(theta234 - gamma),
// which must lie in [r_min^2, r_max^2]: sin(theta234 - gamma) in an interval. Returns `target`
// if it satisfies that, else the nearest end of the admissible arcs; none if no angle does.
std::optional<double> reachable_theta234(double target, const Vec3& o5, const UrGeometry& g) {
  const double rho = std::hypot(o5.x(), o5.y());
  if (rho < kFreeJointEps || std::abs(g.d5) < kFreeJointEps) return target;
  const double r_max = std::abs(g.a2) + std::abs(g.a3);
  const double r_min = std::abs(std::abs(g.a2) - std::abs(g.a3));
  const double b1 = (rho * rho + g.d5 * g.d5 - r_max * r_max) / (2 * g.d5 * rho);
  const double b2 = (rho * rho + g.d5 * g.d5 - r_min * r_min) / (2 * g.d5 * rho);
  const double lo = std::min(b1, b2);
  const double hi = std::max(b1, b2);
  if (lo > 1 || hi < -1) return std::nullopt;
  const double gamma = std::atan2(o5.y(), o5.x());
  const double u0 = wrap_pi(target - gamma);
  if (std::sin(u0) >= lo && std::sin(u0) <= hi) return target;
  const double a_lo = std::asin(std::max(lo, -1.0));
  const double a_hi = std::asin(std::min(hi, 1.0));
  double best = a_lo;
  for (const double u : {a_hi, kPi - a_lo, kPi - a_hi}) {
    if (std::abs(wrap_pi(u - u0)) < std::abs(wrap_pi(best - u0))) best = u;
  }
  return gamma + best;
}

}  // namespace

Eigen::Isometry3d dh_transform(double theta, double d, double a, double alpha) {
  const double ct = std::cos(theta);
  const double st = std::sin(theta);
  const double ca = std::cos(alpha);
  const double sa = std::sin(alpha);
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() << ct, -st * ca, st * sa, st, ct * ca, -ct * sa, 0, sa, ca;
  t.translation() << a * ct, a * st, d;
  return t;
}

Eigen::Isometry3d ur_forward_kinematics(const UrGeometry& g, const JointVector& theta) {
  const std::array<double, 6> d = {g.d1, 0, 0, g.d4, g.d5, g.d6};
  const std::array<double, 6> a = {0, g.a2, g.a3, 0, 0, 0};
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  for (std::size_t i = 0; i < 6; ++i) {
    pose = pose * dh_transform(theta[static_cast<Eigen::Index>(i)], d[i], a[i], kAlpha[i]);
  }
  return pose;
}

// Derivation (standard DH, frame i-1 -> i = Rz(t_i) Tz(d_i) Tx(a_i) Rx(alpha_i)):
//  * z1 = (sin t1, -cos t1, 0) is the axis of joints 2, 3, 4 (alpha2 = alpha3 = 0). The origins
//    of frames 1..3 lie in the plane z1.x = 0 through the base origin; frame 4 adds d4 along
//    z3 = z1 and frame 5 adds d5 along z4, which is perpendicular to z1. So the wrist centre
//    p5 = p6 - d6 z6 satisfies z1.p5 = d4: with p5 = rho (cos phi, sin phi, .),
//    rho sin(t1 - phi) = d4, t1 = phi + asin(d4/rho) or phi + pi - asin(d4/rho) (two shoulder
//    branches; rho < |d4| is out of reach, rho = |d4| the shoulder singularity).
//  * Seen from frame 4, z3 = y4 and z5 = Rz(t5) Rx(-pi/2) e_z = (-sin t5, cos t5, 0), so
//    cos t5 = z1.z6 (z6 = z5): t5 = +-atan2(|z1 x z6|, z1.z6) (two wrist branches).
//  * z1 expressed in frame 6 is Rz(-t6) Rx(pi/2) Rz(-t5) (0, 1, 0) = (s5 c6, -s5 s6, c5), and
//    also (x6.z1, y6.z1, z6.z1), so t6 = atan2(-y6.z1 / s5, x6.z1 / s5). When s5 = 0 axes 2, 3,
//    4 and 6 are parallel and only t234 +- t6 is determined (a one-parameter self-motion): t6
//    keeps its previous value if the elbow can reach with it, else takes the nearest value for
//    which it can (reachable_theta234).
//  * With t1, t5, t6 known, T14 = A1^-1 T06 A6^-1 A5^-1 = Rz(t2) Tx(a2) Rz(t3) Tx(a3) Rz(t4)
//    Tz(d4) Rx(pi/2). Its translation is (a2 c2 + a3 c23, a2 s2 + a3 s23, d4): a planar
//    two-link arm, cos t3 = (x^2 + y^2 - a2^2 - a3^2) / (2 a2 a3), t3 = +-acos (two elbow
//    branches), t2 = atan2(y, x) - atan2(a3 s3, a2 + a3 c3). Its first column is
//    (c234, s234, 0), so t4 = atan2(T14(1,0), T14(0,0)) - t2 - t3.
std::vector<JointVector> ur_closed_form_ik(const UrGeometry& g, const Eigen::Isometry3d& flange_pose,
                                    const JointVector& theta_near, double reach_slack) {
  std::vector<JointVector> out;
  if (!flange_pose.matrix().allFinite()) return out;
  const Mat3 r = flange_pose.linear();
  const Vec3 x6 = r.col(0);
  const Vec3 y6 = r.col(1);
  const Vec3 z6 = r.col(2);

  // shoulder: the wrist centre must lie at the lateral offset d4 along axis 2
  const Vec3 p5 = flange_pose.translation() - g.d6 * z6;
  const double rho = std::hypot(p5.x(), p5.y());
  if (rho < std::abs(g.d4) - reach_slack) return out;
  std::vector<double> theta1;
  if (rho < kFreeJointEps) {
    theta1 = {theta_near[0]};
  } else {
    const double phi = std::atan2(p5.y(), p5.x());
    const double beta = std::asin(std::clamp(g.d4 / rho, -1.0, 1.0));
    theta1 = {phi + beta, phi + kPi - beta};
  }

  const double reach_max = std::abs(g.a2) + std::abs(g.a3);
  const double reach_min = std::abs(std::abs(g.a2) - std::abs(g.a3));
  for (const double t1 : theta1) {
    const Vec3 z1(std::sin(t1), -std::cos(t1), 0.0);
    // wrist 2 from the angle between axis 2 and the flange axis
    const double c5 = z1.dot(z6);
    const double s5_abs = z1.cross(z6).norm();
    for (const double sign5 : {1.0, -1.0}) {
      const double t5 = std::atan2(sign5 * s5_abs, c5);
      const Eigen::Isometry3d a1_inv = dh_transform(t1, g.d1, 0, kAlpha[0]).inverse();
      // wrist 3 from axis 2 seen in the flange frame
      double t6 = 0;
      if (s5_abs >= kWristSingular) {
        t6 = std::atan2(-sign5 * y6.dot(z1), sign5 * x6.dot(z1));
      } else {
        // wrist singular: R16 = Rz(t234 + sigma t6 + shift) with sigma = cos t5 = +-1, shift 0
        // or pi; keep the previous t6 unless the elbow cannot reach with it
        const double sigma = c5 >= 0 ? 1.0 : -1.0;
        const double shift = c5 >= 0 ? 0.0 : kPi;
        const Mat3 r16 = a1_inv.linear() * r;
        const double psi = std::atan2(r16(1, 0), r16(0, 0));
        const std::optional<double> t234 = reachable_theta234(psi - sigma * theta_near[5] - shift, a1_inv * p5, g);
        if (!t234) continue;
        t6 = sigma * (psi - *t234 - shift);
      }
      // the planar two-link problem of joints 2 and 3 in frame 1
      const Eigen::Isometry3d t14 = a1_inv * flange_pose * dh_transform(t6, g.d6, 0, kAlpha[5]).inverse() *
                                    dh_transform(t5, g.d5, 0, kAlpha[4]).inverse();
      const double px = t14.translation().x();
      const double py = t14.translation().y();
      const double reach = std::hypot(px, py);
      if (reach > reach_max + reach_slack || reach < reach_min - reach_slack) continue;
      const double c3 = std::clamp((px * px + py * py - g.a2 * g.a2 - g.a3 * g.a3) / (2 * g.a2 * g.a3), -1.0, 1.0);
      const double s3_abs = std::sqrt(1 - c3 * c3);
      const double t234 = std::atan2(t14.linear()(1, 0), t14.linear()(0, 0));
      for (const double sign3 : {1.0, -1.0}) {
        const double s3 = sign3 * s3_abs;
        const double t3 = std::atan2(s3, c3);
        // joint 2 is free only if the elbow folds onto the shoulder (|a2| = |a3|)
        const double t2 =
            reach < kFreeJointEps ? theta_near[1] : std::atan2(py, px) - std::atan2(g.a3 * s3, g.a2 + g.a3 * c3);
        const double t4 = t234 - t2 - t3;
        JointVector theta;
        theta << wrap_pi(t1), wrap_pi(t2), wrap_pi(t3), wrap_pi(t4), wrap_pi(t5), wrap_pi(t6);
        out.push_back(theta);
      }
    }
  }
  return out;
}

KinematicChain ur_chain(const UrGeometry& g) {
  const std::array<double, 6> d = {g.d1, 0, 0, g.d4, g.d5, g.d6};
  const std::array<double, 6> a = {0, g.a2, g.a3, 0, 0, 0};
  KinematicChain chain;
  // joint i turns about z of DH frame i-1; the constant part Tz Tx Rx of each DH transform
  // becomes the next joint's origin (the last one the TCP)
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
  for (std::size_t i = 0; i < 6; ++i) {
    JointSpec joint;
    joint.name = "joint" + std::to_string(i + 1);
    joint.origin = origin;
    joint.axis = Vec3::UnitZ();
    joint.lower = -kTwoPi;
    joint.upper = kTwoPi;
    joint.velocity_limit = kPi;
    joint.effort_limit = i < 3 ? 150.0 : 28.0;
    chain.joints.push_back(joint);
    origin = dh_transform(0, d[i], a[i], kAlpha[i]);
  }
  chain.tcp = origin;
  return chain;
}

double branch_distance(const JointVector& a, const JointVector& b) {
  double sum = 0;
  for (std::size_t i = 0; i < 6; ++i) {
    const double d = a[static_cast<Eigen::Index>(i)] - b[static_cast<Eigen::Index>(i)];
    sum += kBranchWeights[i] * d * d;
  }
  return std::sqrt(sum);
}

IkSolver::IkSolver(KinematicChain chain) : chain_(std::move(chain)) {
  if (chain_.joints.size() != 6) not_ur("it has " + std::to_string(chain_.joints.size()) + " joints, not 6");

  // joint axis lines (point p, unit direction u) and the TCP at q = 0, in the base frame
  std::array<Vec3, 6> p;
  std::array<Vec3, 6> u;
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  for (std::size_t i = 0; i < 6; ++i) {
    const JointSpec& joint = chain_.joints[i];
    if (!(joint.axis.norm() > 0.5) || !joint.origin.matrix().allFinite()) {
      not_ur("joint '" + joint.name + "' has no valid axis or origin");
    }
    frame = frame * joint.origin;
    p[i] = frame.translation();
    u[i] = (frame.linear() * joint.axis).normalized();
  }
  const Eigen::Isometry3d tcp0 = frame * chain_.tcp;

  // the UR pattern: 1 meets 2 at a right angle, 2 || 3 || 4, 5 meets 4 and 6 at right angles
  if (std::abs(u[0].dot(u[1])) > kStructureTol) not_ur("axes 1 and 2 are not perpendicular");
  if (u[1].cross(u[2]).norm() > kStructureTol || u[2].cross(u[3]).norm() > kStructureTol) {
    not_ur("axes 2, 3 and 4 are not parallel");
  }
  if (std::abs(u[3].dot(u[4])) > kStructureTol) not_ur("axes 4 and 5 are not perpendicular");
  if (std::abs(u[4].dot(u[5])) > kStructureTol) not_ur("axes 5 and 6 are not perpendicular");
  if (line_distance(p[0], u[0], p[1], u[1]) > kStructureTol) not_ur("axes 1 and 2 do not intersect");
  if (line_distance(p[3], u[3], p[4], u[4]) > kStructureTol) not_ur("axes 4 and 5 do not intersect");
  if (line_distance(p[4], u[4], p[5], u[5]) > kStructureTol) not_ur("axes 5 and 6 do not intersect");

  // DH frame 0: z on axis 1 at the foot of the base origin, x as close to the base x as possible
  const Vec3 z0 = u[0];
  const Vec3 o0 = p[0] - p[0].dot(z0) * z0;
  const Vec3 base_x = Vec3::UnitX() - z0.x() * z0;
  const Vec3 x0 = base_x.norm() > 0.1 ? base_x.normalized() : perpendicular_unit(Vec3::UnitY(), z0);
  // frame 1 at the shoulder, where axes 1 and 2 meet
  const Vec3 o1 = closest_point(p[0], u[0], p[1], u[1]);
  const TwistedFrame f1 = twisted_frame(z0, x0, u[1], kAlpha[0]);
  const Vec3 z1 = f1.z;
  // frames 2 and 3 on axes 3 and 4, in the plane through the shoulder perpendicular to them
  const Vec3 o2 = p[2] + (o1 - p[2]).dot(z1) * z1;
  const Vec3 o3 = p[3] + (o1 - p[3]).dot(z1) * z1;
  if ((o2 - o1).norm() < kStructureTol || (o3 - o2).norm() < kStructureTol) not_ur("two of axes 2, 3, 4 coincide");
  const ParallelFrame f2 = parallel_frame(z1, f1.x, o1, o2);
  const ParallelFrame f3 = parallel_frame(z1, f2.x, o2, o3);
  // frame 4 where axes 4 and 5 meet, frame 5 where axes 5 and 6 meet
  const Vec3 o4 = closest_point(o3, z1, p[4], u[4]);
  const TwistedFrame f4 = twisted_frame(z1, f3.x, u[4], kAlpha[3]);
  const Vec3 o5 = closest_point(o4, f4.z, p[5], u[5]);
  const TwistedFrame f5 = twisted_frame(f4.z, f4.x, u[5], kAlpha[4]);
  // frame 6 on axis 6 level with the TCP, x as close to the TCP's x as possible
  const Mat3 tcp_r = tcp0.linear();
  const Vec3 tcp_x = tcp_r.col(0) - tcp_r.col(0).dot(f5.z) * f5.z;
  const Vec3 x6 = tcp_x.norm() > 0.1 ? tcp_x.normalized() : perpendicular_unit(tcp_r.col(1), f5.z);

  geometry_.d1 = (o1 - o0).dot(z0);
  geometry_.a2 = f2.a;
  geometry_.a3 = f3.a;
  geometry_.d4 = (o4 - o3).dot(z1);
  geometry_.d5 = (o5 - o4).dot(f4.z);
  geometry_.d6 = (tcp0.translation() - o5).dot(f5.z);
  sign_ << 1.0, f1.axis_sign, (u[2].dot(z1) > 0 ? 1.0 : -1.0), (u[3].dot(z1) > 0 ? 1.0 : -1.0), f4.axis_sign,
      f5.axis_sign;
  offset_ << f1.offset, f2.offset, f3.offset, f4.offset, f5.offset, angle_about(f5.x, x6, f5.z);
  base_ = Eigen::Isometry3d::Identity();
  base_.linear() << x0, z0.cross(x0), z0;
  base_.translation() = o0;
  tool_ = (base_ * ur_forward_kinematics(geometry_, offset_)).inverse() * tcp0;

  // the DH model must reproduce the chain away from q = 0 too; where it differs slightly, the
  // closed form may have to accept poses that much beyond the ideal model's reach
  double deviation = 0;
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> angle(-kPi, kPi);
  for (int trial = 0; trial < 16; ++trial) {
    JointVector q;
    for (Eigen::Index i = 0; i < 6; ++i) q[i] = angle(rng);
    const Eigen::Isometry3d model = base_ * ur_forward_kinematics(geometry_, sign_.cwiseProduct(q) + offset_) * tool_;
    const Twist error = pose_error(forward_kinematics(chain_, q), model);
    deviation = std::max({deviation, error.head<3>().norm(), error.tail<3>().norm()});
    if (error.head<3>().norm() > kModelTol || error.tail<3>().norm() > kModelTol) {
      not_ur("its forward kinematics differ from the UR model found in it by " + format_value(error.head<3>().norm()) +
             " m, " + format_value(error.tail<3>().norm()) + " rad");
    }
  }
  reach_slack_ = std::max(kReachSlack, 10 * deviation);
}

bool IkSolver::within_limits(const JointVector& q) const {
  for (std::size_t i = 0; i < 6; ++i) {
    const double v = q[static_cast<Eigen::Index>(i)];
    if (!(v >= chain_.joints[i].lower - kLimitSlack && v <= chain_.joints[i].upper + kLimitSlack)) return false;
  }
  return true;
}

bool IkSolver::polish(const Eigen::Isometry3d& tcp_pose, JointVector& q) const {
  Twist error = pose_error(tcp_pose, forward_kinematics(chain_, q));
  double damping = kPolishDampingMin;
  for (int iteration = 0; iteration < kPolishIterations; ++iteration) {
    if (error.head<3>().norm() < kPolishTarget && error.tail<3>().norm() < kPolishTarget) break;
    // damped least squares: (J^T J + lambda^2 I) dq = J^T e; keep the step only if it helps,
    // else damp more (near a singularity the undamped step overshoots)
    const Mat6 jac = jacobian(chain_, q);
    const Mat6 normal = jac.transpose() * jac + damping * Mat6::Identity();
    const JointVector trial = q + normal.ldlt().solve(jac.transpose() * error);
    const Twist trial_error = pose_error(tcp_pose, forward_kinematics(chain_, trial));
    if (trial.allFinite() && trial_error.norm() < error.norm()) {
      q = trial;
      error = trial_error;
      damping = std::max(kPolishDampingMin, damping / 10);
    } else {
      damping *= 10;
      if (damping > kPolishDampingMax) break;
    }
  }
  return q.allFinite() && error.head<3>().norm() <= kIkPositionTol && error.tail<3>().norm() <= kIkAngleTol;
}

IkSolver::Branches IkSolver::branches(const Eigen::Isometry3d& tcp_pose, const JointVector& q_near) const {
  Branches out;
  // closed form on the DH geometry for DH frame 6, then back to chain joint angles
  const Eigen::Isometry3d flange = base_.inverse() * tcp_pose * tool_.inverse();
  const JointVector theta_near = sign_.cwiseProduct(q_near) + offset_;
  const std::vector<JointVector> thetas = ur_closed_form_ik(geometry_, flange, theta_near, reach_slack_);
  out.found = thetas.size();
  for (const JointVector& theta : thetas) {
    JointVector q = sign_.cwiseProduct(theta - offset_);
    for (Eigen::Index i = 0; i < 6; ++i) q[i] = q_near[i] + std::remainder(q[i] - q_near[i], kTwoPi);
    if (polish(tcp_pose, q)) out.q.push_back(q);
  }
  std::stable_sort(out.q.begin(), out.q.end(), [&](const JointVector& a, const JointVector& b) {
    return branch_distance(a, q_near) < branch_distance(b, q_near);
  });
  return out;
}

std::vector<JointVector> IkSolver::solutions(const Eigen::Isometry3d& tcp_pose, const JointVector& q_near) const {
  if (!tcp_pose.matrix().allFinite() || !q_near.allFinite()) return {};
  return branches(tcp_pose, q_near).q;
}

IkSolver::Result IkSolver::solve(const Eigen::Isometry3d& tcp_pose, const JointVector& q_near) const {
  Result result;
  result.q = q_near;
  if (!tcp_pose.matrix().allFinite() || !q_near.allFinite()) {
    result.outcome = {Status::kUnreachable, "the pose or the previous joint angles are not finite"};
    return result;
  }
  const Branches found = branches(tcp_pose, q_near);
  if (found.found == 0) {
    result.outcome = {Status::kUnreachable, "pose out of reach: " + describe_pose(tcp_pose)};
    return result;
  }
  if (found.q.empty()) {
    result.outcome = {Status::kSingular, "no IK branch converges (singular configuration) at " + describe_pose(tcp_pose)};
    return result;
  }

  // the nearest branch whose joints all have a representative within their limits
  double best = std::numeric_limits<double>::infinity();
  for (const JointVector& candidate : found.q) {
    JointVector q;
    bool inside = true;
    for (std::size_t i = 0; i < 6 && inside; ++i) {
      const auto k = static_cast<Eigen::Index>(i);
      const std::optional<double> v = wrap_within(candidate[k], q_near[k], chain_.joints[i].lower, chain_.joints[i].upper);
      inside = v.has_value();
      if (inside) q[k] = *v;
    }
    if (inside && branch_distance(q, q_near) < best) {
      best = branch_distance(q, q_near);
      result.q = q;
    }
  }
  if (std::isfinite(best)) return result;

  // name the joint that keeps the nearest branch outside its limits
  const JointVector& nearest = found.q.front();
  std::string which;
  for (std::size_t i = 0; i < 6 && which.empty(); ++i) {
    const JointSpec& joint = chain_.joints[i];
    const auto k = static_cast<Eigen::Index>(i);
    if (!wrap_within(nearest[k], q_near[k], joint.lower, joint.upper)) {
      which = "joint '" + joint.name + "' would be at " + format_value(nearest[k]) + " rad, limits [" + format_value(joint.lower) +
              ", " + format_value(joint.upper) + "]";
    }
  }
  result.outcome = {Status::kJointLimit,
                    "every IK solution violates a joint limit at " + describe_pose(tcp_pose) + " (nearest: " + which + ")"};
  return result;
}

}  // namespace blendbench
