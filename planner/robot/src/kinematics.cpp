#include "blendbench/robot/kinematics.hpp"

#include <cassert>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace blendbench {

Eigen::Isometry3d forward_kinematics(const KinematicChain& chain, const JointVector& q) {
  assert(chain.joints.size() == 6);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  for (std::size_t i = 0; i < 6; ++i) {
    const JointSpec& joint = chain.joints[i];
    pose = pose * joint.origin * Eigen::AngleAxisd(q[static_cast<Eigen::Index>(i)], joint.axis);
  }
  return pose * chain.tcp;
}

Mat6 jacobian(const KinematicChain& chain, const JointVector& q) {
  assert(chain.joints.size() == 6);
  Vec3 origins[6];
  Vec3 axes[6];
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  // joint axes and origins in the base frame, walking the chain once
  for (std::size_t i = 0; i < 6; ++i) {
    const JointSpec& joint = chain.joints[i];
    pose = pose * joint.origin;
    origins[i] = pose.translation();
    axes[i] = pose.linear() * joint.axis;
    pose = pose * Eigen::AngleAxisd(q[static_cast<Eigen::Index>(i)], joint.axis);
  }
  const Vec3 tcp = (pose * chain.tcp).translation();
  // a revolute joint moves the TCP with v = a x (p - o) and turns it with w = a
  Mat6 jac;
  for (Eigen::Index i = 0; i < 6; ++i) {
    const auto k = static_cast<std::size_t>(i);
    jac.block<3, 1>(0, i) = axes[k].cross(tcp - origins[k]);
    jac.block<3, 1>(3, i) = axes[k];
  }
  return jac;
}

Twist pose_error(const Eigen::Isometry3d& target, const Eigen::Isometry3d& actual) {
  Twist error;
  error.head<3>() = target.translation() - actual.translation();
  // the quaternion route stays accurate for tiny angles, where acos of the trace does not
  const Eigen::AngleAxisd delta(Mat3(target.linear() * actual.linear().transpose()));
  error.tail<3>() = delta.angle() * delta.axis();
  return error;
}

Vec3 rpy_from_rotation(const Mat3& r) {
  const double pitch = std::atan2(-r(2, 0), std::hypot(r(0, 0), r(1, 0)));
  // at pitch = +-90 deg roll and yaw are coupled; put everything into yaw
  if (std::hypot(r(0, 0), r(1, 0)) < 1e-12) {
    return Vec3(0.0, pitch, std::atan2(-r(0, 1), r(1, 1)));
  }
  return Vec3(std::atan2(r(2, 1), r(2, 2)), pitch, std::atan2(r(1, 0), r(0, 0)));
}

Mat3 rotation_from_rpy(const Vec3& rpy) {
  return (Eigen::AngleAxisd(rpy.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Vec3::UnitY()) *
          Eigen::AngleAxisd(rpy.x(), Vec3::UnitX()))
      .toRotationMatrix();
}

std::string describe_pose(const Eigen::Isometry3d& pose) {
  // values that print as zero print as 0.000, never -0.000
  const auto tidy = [](const Vec3& v) { return v.unaryExpr([](double x) { return std::abs(x) < 5e-4 ? 0.0 : x; }).eval(); };
  const Vec3 p = tidy(pose.translation() * 1e3);
  const Vec3 rpy = tidy(rpy_from_rotation(pose.linear()) * (180.0 / std::numbers::pi));
  char text[160];
  std::snprintf(text, sizeof text, "position (%.3f, %.3f, %.3f) mm, rpy (%.3f, %.3f, %.3f) deg", p.x(), p.y(),
                p.z(), rpy.x(), rpy.y(), rpy.z());
  return text;
}

}  // namespace blendbench
