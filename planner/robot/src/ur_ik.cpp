#include "blendbench/robot/ur_ik.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include "blendbench/core/format.hpp"
#include "blendbench/core/input_error.hpp"
#include "dh_frames.hpp"

namespace blendbench {
namespace {

using dh::kPi;
using dh::kTwoPi;
using dh::wrap_pi;

constexpr std::array<double, 6> kAlpha = {kPi / 2, 0, 0, kPi / 2, -kPi / 2, 0};

// Below this distance (m) from the shoulder or elbow degeneracy the angle of the free joint
// cannot be computed and is chosen as documented at ur_closed_form_ik.
constexpr double kFreeJointEps = 1e-12;
// Below this |sin(theta5)| the wrist counts as singular and theta6 is chosen as documented at
// ur_closed_form_ik instead of from rounding noise. A pose computed by forward kinematics at
// theta5 = 0 has |sin(theta5)| ~ 1e-15, or ~ 1e-12 when the shoulder is nearly singular too
// (theta1 then carries more rounding); the pose error of the choice is at most about pi times
// this value, below the solvers' tolerance (1e-10 m, rad).
constexpr double kWristSingular = 1e-11;

[[noreturn]] void not_ur(const std::string& what) {
  throw InputError("", 0, 0, "urdf", "the kinematic chain is not UR-type: " + what);
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

Eigen::Isometry3d ur_forward_kinematics(const UrGeometry& g, const JointVector& theta) {
  return dh_chain_pose(theta, {g.d1, 0, 0, g.d4, g.d5, g.d6}, {0, g.a2, g.a3, 0, 0, 0}, kAlpha);
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
  KinematicChain chain = dh_kinematic_chain(d, a, kAlpha);
  for (std::size_t i = 0; i < 6; ++i) {
    JointSpec& joint = chain.joints[i];
    joint.lower = -kTwoPi;
    joint.upper = kTwoPi;
    joint.velocity_limit = kPi;
    joint.effort_limit = i < 3 ? 150.0 : 28.0;
  }
  return chain;
}

UrFit fit_ur(const KinematicChain& chain) {
  using dh::closest_point;
  using dh::kStructureTol;
  using dh::line_distance;
  const dh::AxisLines lines = dh::axis_lines(chain, not_ur);
  const auto& p = lines.p;
  const auto& u = lines.u;

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
  UrFit fit;
  DhPlacement& placement = fit.placement;
  placement.base = dh::base_frame(p[0], u[0]);
  const Vec3 z0 = u[0];
  const Vec3 o0 = placement.base.translation();
  const Vec3 x0 = placement.base.linear().col(0);
  // frame 1 at the shoulder, where axes 1 and 2 meet
  const Vec3 o1 = closest_point(p[0], u[0], p[1], u[1]);
  const dh::TwistedFrame f1 = dh::twisted_frame(z0, x0, u[1], kAlpha[0]);
  const Vec3 z1 = f1.z;
  // frames 2 and 3 on axes 3 and 4, in the plane through the shoulder perpendicular to them
  const Vec3 o2 = p[2] + (o1 - p[2]).dot(z1) * z1;
  const Vec3 o3 = p[3] + (o1 - p[3]).dot(z1) * z1;
  if ((o2 - o1).norm() < kStructureTol || (o3 - o2).norm() < kStructureTol) not_ur("two of axes 2, 3, 4 coincide");
  const dh::ParallelFrame f2 = dh::parallel_frame(z1, f1.x, o1, o2);
  const dh::ParallelFrame f3 = dh::parallel_frame(z1, f2.x, o2, o3);
  // frame 4 where axes 4 and 5 meet, frame 5 where axes 5 and 6 meet
  const Vec3 o4 = closest_point(o3, z1, p[4], u[4]);
  const dh::TwistedFrame f4 = dh::twisted_frame(z1, f3.x, u[4], kAlpha[3]);
  const Vec3 o5 = closest_point(o4, f4.z, p[5], u[5]);
  const dh::TwistedFrame f5 = dh::twisted_frame(f4.z, f4.x, u[5], kAlpha[4]);
  // frame 6 on axis 6 level with the TCP, x as close to the TCP's x as possible
  const Vec3 x6 = dh::flange_x(lines.tcp0, f5.z);

  UrGeometry& g = fit.geometry;
  g.d1 = (o1 - o0).dot(z0);
  g.a2 = f2.a;
  g.a3 = f3.a;
  g.d4 = (o4 - o3).dot(z1);
  g.d5 = (o5 - o4).dot(f4.z);
  g.d6 = (lines.tcp0.translation() - o5).dot(f5.z);
  placement.sign << 1.0, f1.axis_sign, (u[2].dot(z1) > 0 ? 1.0 : -1.0), (u[3].dot(z1) > 0 ? 1.0 : -1.0), f4.axis_sign,
      f5.axis_sign;
  placement.offset << f1.offset, f2.offset, f3.offset, f4.offset, f5.offset, dh::angle_about(f5.x, x6, f5.z);
  placement.tool = (placement.base * ur_forward_kinematics(g, placement.offset)).inverse() * lines.tcp0;

  // the DH model must reproduce the chain away from q = 0 too
  placement.deviation =
      placement_deviation(chain, placement, [&](const JointVector& theta) { return ur_forward_kinematics(g, theta); });
  if (placement.deviation > dh::kModelTol) {
    not_ur("its forward kinematics differ from the UR model found in it by " + format_value(placement.deviation) +
           " (m or rad)");
  }
  return fit;
}

ArmMeasures ur_measures(const UrGeometry& g, const JointVector& theta) {
  // p5 in DH frame 1: (a2 c2 + a3 c23 + d5 s234, ., d4); its x is the shoulder's measure
  const double t2 = theta[1], t23 = theta[1] + theta[2], t234 = t23 + theta[3];
  ArmMeasures m;
  m.shoulder = g.a2 * std::cos(t2) + g.a3 * std::cos(t23) + g.d5 * std::sin(t234);
  m.elbow = std::sin(theta[2]);
  m.wrist = std::sin(theta[4]);
  return m;
}

}  // namespace blendbench
