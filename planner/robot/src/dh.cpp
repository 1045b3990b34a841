#include "blendbench/robot/dh.hpp"

#include <string>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>

namespace blendbench {

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

Eigen::Isometry3d dh_chain_pose(const JointVector& theta, const std::array<double, 6>& d, const std::array<double, 6>& a,
                                const std::array<double, 6>& alpha) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  for (std::size_t i = 0; i < 6; ++i) pose = pose * dh_transform(theta[static_cast<Eigen::Index>(i)], d[i], a[i], alpha[i]);
  return pose;
}

KinematicChain dh_kinematic_chain(const std::array<double, 6>& d, const std::array<double, 6>& a,
                                  const std::array<double, 6>& alpha) {
  KinematicChain chain;
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
  for (std::size_t i = 0; i < 6; ++i) {
    JointSpec joint;
    joint.name = "joint" + std::to_string(i + 1);
    joint.origin = origin;
    joint.axis = Vec3::UnitZ();
    chain.joints.push_back(joint);
    origin = dh_transform(0, d[i], a[i], alpha[i]);
  }
  chain.tcp = origin;
  return chain;
}

double placement_deviation(const KinematicChain& chain, const DhPlacement& placement, const DhForward& flange) {
  // the same 16 configurations for every chain, so a fit is reproducible
  double deviation = 0;
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> angle(-std::numbers::pi, std::numbers::pi);
  for (int trial = 0; trial < 16; ++trial) {
    JointVector q;
    for (Eigen::Index i = 0; i < 6; ++i) q[i] = angle(rng);
    const Eigen::Isometry3d model = placement.base * flange(placement.theta(q)) * placement.tool;
    const Twist error = pose_error(forward_kinematics(chain, q), model);
    deviation = std::max({deviation, error.head<3>().norm(), error.tail<3>().norm()});
  }
  return deviation;
}

}  // namespace blendbench
