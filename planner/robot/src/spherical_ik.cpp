#include "blendbench/robot/spherical_ik.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "blendbench/core/format.hpp"
#include "blendbench/core/input_error.hpp"
#include "dh_frames.hpp"

namespace blendbench {
namespace {

using dh::kPi;
using dh::kTwoPi;
using dh::wrap_pi;

constexpr std::array<double, 6> kAlpha = {kPi / 2, 0, kPi / 2, -kPi / 2, kPi / 2, 0};

// Below this distance (m) from the shoulder or elbow degeneracy the free joint's angle cannot be
// computed and is taken from theta_near (spherical_closed_form_ik).
constexpr double kFreeJointEps = 1e-12;
// Below this |sin(theta5)| the wrist counts as singular (as in ur_ik.cpp: a pose computed at
// theta5 = 0 has |sin(theta5)| ~ 1e-15; the pose error of the choice is at most ~pi times this).
constexpr double kWristSingular = 1e-11;

[[noreturn]] void not_spherical(const std::string& what) {
  throw InputError("", 0, 0, "urdf", "the kinematic chain has no spherical wrist of the industrial kind: " + what);
}

std::array<double, 6> d_of(const SphericalWristGeometry& g) { return {g.d1, g.d2, 0, g.d4, 0, g.d6}; }
std::array<double, 6> a_of(const SphericalWristGeometry& g) { return {g.a1, g.a2, g.a3, 0, 0, 0}; }

}  // namespace

Eigen::Isometry3d spherical_forward_kinematics(const SphericalWristGeometry& g, const JointVector& theta) {
  return dh_chain_pose(theta, d_of(g), a_of(g), kAlpha);
}

// Derivation (standard DH, frame i-1 -> i = Rz(t_i) Tz(d_i) Tx(a_i) Rx(alpha_i)):
//  * The wrist centre w = p6 - d6 z6 is the origin of frames 4 and 5 and depends on t1, t2, t3
//    only. Frame 1 has x1 = (c1, s1, 0), y1 = e_z, z1 = (s1, -c1, 0) (alpha1 = pi/2) and origin
//    a1 x1 + d1 e_z; frames 2 and 3 turn about z1, and z3 = (s23, -c23) in (x1, y1) (alpha3 =
//    pi/2), so
//      w = (a1 + X) x1 + d2 z1 + (d1 + Y) e_z,
//      X = a2 c2 + a3 c23 + d4 s23,  Y = a2 s2 + a3 s23 - d4 c23.
//  * Shoulder: w.z1 = d2, i.e. rho sin(t1 - phi) = d2 with w = rho (cos phi, sin phi, .):
//    t1 = phi + asin(d2/rho) (front: w.x1 = R = +sqrt(rho^2 - d2^2)) or phi + pi - asin(d2/rho)
//    (back: R = -sqrt(..)); then X = R - a1 and Y = w_z - d1.
//  * Elbow: (a3 c23 + d4 s23, a3 s23 - d4 c23) = L3 (cos(t23 - g), sin(t23 - g)) with
//    L3 = hypot(a3, d4), g = atan2(d4, a3). With psi = t3 - g, X + iY = e^{i t2} (a2 + L3 e^{i psi}):
//    cos psi = (X^2 + Y^2 - a2^2 - L3^2) / (2 a2 L3), psi = +-acos (elbow up / down),
//    t2 = atan2(Y, X) - atan2(L3 sin psi, a2 + L3 cos psi).
//  * Wrist: R36 = R03^T R06 = Rz(t4) Rx(-pi/2) Rz(t5) Rx(pi/2) Rz(t6) = Rz(t4) Ry(t5) Rz(t6), the
//    ZYZ angles: cos t5 = R36(2,2), t5 = +-atan2(|R36(0:1,2)|, R36(2,2)) (the wrist flip),
//    t4 = atan2(R36(1,2) / s5, R36(0,2) / s5), t6 = atan2(R36(2,1) / s5, -R36(2,0) / s5). At
//    s5 = 0, R36 = Rz(t4 + t6) (c5 = 1) or Rz(t4 - t6) Ry(pi) (c5 = -1): t6 keeps theta_near's.
std::vector<JointVector> spherical_closed_form_ik(const SphericalWristGeometry& g, const Eigen::Isometry3d& flange_pose,
                                                  const JointVector& theta_near, double reach_slack) {
  std::vector<JointVector> out;
  if (!flange_pose.matrix().allFinite()) return out;
  const Mat3 r = flange_pose.linear();
  const Vec3 w = flange_pose.translation() - g.d6 * r.col(2);

  // shoulder: (t1, R) per branch, R the wrist centre's distance along x1
  const double rho = std::hypot(w.x(), w.y());
  if (rho < std::abs(g.d2) - reach_slack) return out;
  std::vector<std::pair<double, double>> shoulders;
  if (rho < kFreeJointEps) {
    shoulders = {{theta_near[0], 0.0}, {theta_near[0] + kPi, 0.0}};
  } else {
    const double phi = std::atan2(w.y(), w.x());
    const double beta = std::asin(std::clamp(g.d2 / rho, -1.0, 1.0));
    const double r_abs = std::sqrt(std::max(0.0, rho * rho - g.d2 * g.d2));
    shoulders = {{phi + beta, r_abs}, {phi + kPi - beta, -r_abs}};
  }

  const double l3 = std::hypot(g.a3, g.d4);
  const double gamma = std::atan2(g.d4, g.a3);
  const double reach_max = std::abs(g.a2) + l3;
  const double reach_min = std::abs(std::abs(g.a2) - l3);
  for (const auto& [t1, radial] : shoulders) {
    // the planar two-link problem of joints 2 and 3 in the arm plane
    const double x = radial - g.a1;
    const double y = w.z() - g.d1;
    const double reach = std::hypot(x, y);
    if (reach > reach_max + reach_slack || reach < reach_min - reach_slack) continue;
    const double c_psi = std::clamp((x * x + y * y - g.a2 * g.a2 - l3 * l3) / (2 * g.a2 * l3), -1.0, 1.0);
    const double s_psi_abs = std::sqrt(1 - c_psi * c_psi);
    for (const double sign_elbow : {1.0, -1.0}) {
      const double psi = std::atan2(sign_elbow * s_psi_abs, c_psi);
      // joint 2 is free only when the wrist centre lies on axis 2 (|a2| = L3, folded)
      const double t2 = reach < kFreeJointEps ? theta_near[1]
                                              : std::atan2(y, x) - std::atan2(l3 * std::sin(psi), g.a2 + l3 * std::cos(psi));
      const double t3 = psi + gamma;
      // the wrist's ZYZ angles in frame 3
      const Mat3 r03 = (dh_transform(t1, g.d1, g.a1, kAlpha[0]) * dh_transform(t2, g.d2, g.a2, kAlpha[1]) *
                        dh_transform(t3, 0, g.a3, kAlpha[2]))
                           .linear();
      const Mat3 r36 = r03.transpose() * r;
      const double c5 = r36(2, 2);
      const double s5_abs = std::hypot(r36(0, 2), r36(1, 2));
      for (const double sign5 : {1.0, -1.0}) {
        const double t5 = std::atan2(sign5 * s5_abs, c5);
        double t4 = 0;
        double t6 = 0;
        if (s5_abs >= kWristSingular) {
          t4 = std::atan2(sign5 * r36(1, 2), sign5 * r36(0, 2));
          t6 = std::atan2(sign5 * r36(2, 1), -sign5 * r36(2, 0));
        } else {
          // axes 4 and 6 in line: keep the previous t6, t4 takes the rest
          t6 = theta_near[5];
          t4 = c5 >= 0 ? std::atan2(r36(1, 0), r36(0, 0)) - t6 : std::atan2(-r36(1, 0), -r36(0, 0)) + t6;
        }
        JointVector theta;
        theta << wrap_pi(t1), wrap_pi(t2), wrap_pi(t3), wrap_pi(t4), wrap_pi(t5), wrap_pi(t6);
        out.push_back(theta);
      }
    }
  }
  return out;
}

KinematicChain spherical_chain(const SphericalWristGeometry& g) {
  const std::array<double, 6> d = d_of(g);
  const std::array<double, 6> a = a_of(g);
  KinematicChain chain = dh_kinematic_chain(d, a, kAlpha);
  for (std::size_t i = 0; i < 6; ++i) {
    JointSpec& joint = chain.joints[i];
    joint.lower = i == 2 ? -kPi : -kTwoPi;
    joint.upper = i == 2 ? kPi : kTwoPi;
    joint.velocity_limit = kPi;
    joint.effort_limit = i < 3 ? 300.0 : 50.0;
  }
  return chain;
}

SphericalWristFit fit_spherical_wrist(const KinematicChain& chain) {
  using dh::closest_point;
  using dh::kStructureTol;
  using dh::line_distance;
  const dh::AxisLines lines = dh::axis_lines(chain, not_spherical);
  const auto& p = lines.p;
  const auto& u = lines.u;

  // the pattern: 1 _|_ 2, 2 || 3, 3 _|_ 4, and 4, 5, 6 meet in one point with 4 _|_ 5 _|_ 6
  if (std::abs(u[0].dot(u[1])) > kStructureTol) not_spherical("axes 1 and 2 are not perpendicular");
  if (u[1].cross(u[2]).norm() > kStructureTol) not_spherical("axes 2 and 3 are not parallel");
  if (std::abs(u[2].dot(u[3])) > kStructureTol) not_spherical("axes 3 and 4 are not perpendicular");
  if (std::abs(u[3].dot(u[4])) > kStructureTol) not_spherical("axes 4 and 5 are not perpendicular");
  if (std::abs(u[4].dot(u[5])) > kStructureTol) not_spherical("axes 5 and 6 are not perpendicular");
  if (line_distance(p[3], u[3], p[4], u[4]) > kStructureTol) not_spherical("axes 4 and 5 do not intersect");
  if (line_distance(p[4], u[4], p[5], u[5]) > kStructureTol) not_spherical("axes 5 and 6 do not intersect");
  const Vec3 wrist = closest_point(p[3], u[3], p[4], u[4]);
  if ((closest_point(p[5], u[5], p[4], u[4]) - wrist).norm() > kStructureTol) {
    not_spherical("axes 4, 5 and 6 do not meet in one point");
  }

  SphericalWristFit fit;
  DhPlacement& placement = fit.placement;
  placement.base = dh::base_frame(p[0], u[0]);
  const Vec3 z0 = u[0];
  const Vec3 o0 = placement.base.translation();
  const Vec3 x0 = placement.base.linear().col(0);
  // frame 1 on axis 2 at the common normal with axis 1 (the shoulder offset a1 along x1)
  const Vec3 foot1 = closest_point(p[0], u[0], p[1], u[1]);
  const Vec3 o1 = closest_point(p[1], u[1], p[0], u[0]);
  const dh::TwistedFrame f1 = dh::twisted_frame(z0, x0, u[1], kAlpha[0]);
  const Vec3 z1 = f1.z;
  // frame 2 on axis 3 at the common normal with axis 4: the upper arm a2 and the lateral d2
  const Vec3 o2 = closest_point(p[2], u[2], p[3], u[3]);
  const double d2 = (o2 - o1).dot(z1);
  if ((o2 - d2 * z1 - o1).norm() < kStructureTol) not_spherical("axes 2 and 3 coincide");
  const dh::ParallelFrame f2 = dh::parallel_frame(z1, f1.x, o1, o2 - d2 * z1);
  // frame 3 on axis 4 at that common normal (elbow offset a3), the wrist centre d4 along it
  const Vec3 o3 = closest_point(p[3], u[3], p[2], u[2]);
  const dh::TwistedFrame f3 = dh::twisted_frame(z1, f2.x, u[3], kAlpha[2]);
  // frames 4 and 5 at the wrist centre, frame 6 on axis 6 level with the TCP
  const dh::TwistedFrame f4 = dh::twisted_frame(f3.z, f3.x, u[4], kAlpha[3]);
  const dh::TwistedFrame f5 = dh::twisted_frame(f4.z, f4.x, u[5], kAlpha[4]);
  const Vec3 x6 = dh::flange_x(lines.tcp0, f5.z);

  SphericalWristGeometry& g = fit.geometry;
  g.d1 = (foot1 - o0).dot(z0);
  g.a1 = (o1 - foot1).dot(f1.x);
  g.a2 = f2.a;
  g.d2 = d2;
  g.a3 = (o3 - o2).dot(f3.x);
  g.d4 = (wrist - o3).dot(f3.z);
  g.d6 = (lines.tcp0.translation() - wrist).dot(f5.z);
  if (std::hypot(g.a3, g.d4) < kStructureTol) not_spherical("the wrist centre lies on axis 3");
  placement.sign << 1.0, f1.axis_sign, (u[2].dot(z1) > 0 ? 1.0 : -1.0), f3.axis_sign, f4.axis_sign, f5.axis_sign;
  placement.offset << f1.offset, f2.offset, f3.offset, f4.offset, f5.offset, dh::angle_about(f5.x, x6, f5.z);
  placement.tool = (placement.base * spherical_forward_kinematics(g, placement.offset)).inverse() * lines.tcp0;

  // the DH model must reproduce the chain away from q = 0 too
  placement.deviation = placement_deviation(
      chain, placement, [&](const JointVector& theta) { return spherical_forward_kinematics(g, theta); });
  if (placement.deviation > dh::kModelTol) {
    not_spherical("its forward kinematics differ from the spherical-wrist model found in it by " +
                  format_value(placement.deviation) + " (m or rad)");
  }
  return fit;
}

ArmMeasures spherical_measures(const SphericalWristGeometry& g, const JointVector& theta) {
  const double l3 = std::hypot(g.a3, g.d4);
  const double psi = theta[2] - std::atan2(g.d4, g.a3);
  ArmMeasures m;
  m.shoulder = g.a1 + g.a2 * std::cos(theta[1]) + l3 * std::cos(theta[1] + psi);
  m.elbow = std::sin(psi);
  m.wrist = std::sin(theta[4]);
  return m;
}

}  // namespace blendbench
