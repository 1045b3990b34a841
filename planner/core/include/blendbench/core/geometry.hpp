#pragma once
// Small vector helpers shared by every geometry module. SI units (m, rad) throughout.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace blendbench {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

// Relative tolerance used to decide that two directions are parallel or a length is zero,
// measured against the size of the geometry involved.
inline constexpr double kGeomEps = 1e-12;

// Any unit vector perpendicular to the unit vector `n`.
inline Vec3 any_perpendicular(const Vec3& n) {
  const Vec3 trial = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  return n.cross(trial).normalized();
}

// Unsigned angle between two non-zero vectors in [0, pi], accurate near 0 and pi
// (atan2 of cross and dot rather than acos of a rounded dot product).
inline double angle_between(const Vec3& a, const Vec3& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

}  // namespace blendbench
