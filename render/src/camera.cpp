#include "blendbench/render/camera.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <limits>

#include "blendbench/core/units.hpp"

namespace blendbench {
namespace {

// The elevation is kept below the pole, where azimuth and image-up lose their meaning.
constexpr double kMaxElevationDeg = 89.9;
// A best-fit plane is a line when its second spread is below this share of the first.
constexpr double kLineSpread = 1e-6;
// Framing: centring iterations, and distance changes when the field of view leaves its range.
constexpr int kCentringIterations = 12;
constexpr int kDistanceIterations = 12;
constexpr double kCentred = 1e-9;  // normalised image units

// The points' projected extent in normalised image coordinates (x / depth, y / depth).
struct ImageBox {
  double x0 = std::numeric_limits<double>::infinity(), x1 = -std::numeric_limits<double>::infinity();
  double y0 = std::numeric_limits<double>::infinity(), y1 = -std::numeric_limits<double>::infinity();
  int count = 0;
};

ImageBox image_box(const CameraPose& c, const std::vector<Vec3>& points) {
  ImageBox box;
  const Vec3 right = c.right();
  for (const Vec3& p : points) {
    const Vec3 d = p - c.eye;
    const double z = d.dot(c.forward);
    if (!(z > 0)) continue;
    const double x = d.dot(right) / z, y = d.dot(c.up) / z;
    box.x0 = std::min(box.x0, x);
    box.x1 = std::max(box.x1, x);
    box.y0 = std::min(box.y0, y);
    box.y1 = std::max(box.y1, y);
    ++box.count;
  }
  return box;
}

}  // namespace

Projection project(const CameraPose& camera, const Vec3& p, int width, int height) {
  const Vec3 d = p - camera.eye;
  const double z = d.dot(camera.forward);
  const double f = 0.5 * height / std::tan(0.5 * camera.fovy_deg * kDeg);
  return {0.5 * width + f * d.dot(camera.right()) / z, 0.5 * height - f * d.dot(camera.up) / z, z};
}

double pixel_size(const CameraPose& camera, double depth, int height) {
  return depth * 2 * std::tan(0.5 * camera.fovy_deg * kDeg) / height;
}

CameraPose orbit_camera(const Vec3& target, double azimuth_deg, double elevation_deg, double distance, double fovy_deg) {
  const double az = azimuth_deg * kDeg;
  const double el = std::clamp(elevation_deg, -kMaxElevationDeg, kMaxElevationDeg) * kDeg;
  const Vec3 towards_eye(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
  CameraPose c;
  c.eye = target + distance * towards_eye;
  c.forward = -towards_eye;
  // image-right is horizontal at every elevation: forward x world-z, normalised
  const Vec3 right(-std::sin(az), std::cos(az), 0);
  c.up = right.cross(c.forward).normalized();
  c.fovy_deg = fovy_deg;
  return c;
}

CameraPose look_at(const Vec3& eye, const Vec3& target, double fovy_deg) {
  CameraPose c;
  c.eye = eye;
  c.forward = (target - eye).normalized();
  Vec3 right = c.forward.cross(Vec3::UnitZ());
  if (right.norm() < 1e-9) right = c.forward.cross(Vec3::UnitY());
  c.up = right.normalized().cross(c.forward).normalized();
  c.fovy_deg = fovy_deg;
  return c;
}

ViewAngles default_view(const std::vector<Vec3>& points, const Vec3& base) {
  const Vec3 z = Vec3::UnitZ();
  Vec3 centre = Vec3::Zero();
  for (const Vec3& p : points) centre += p;
  if (!points.empty()) centre /= static_cast<double>(points.size());

  // away from the base, horizontally (+x when the part is above the base), from the middle of the
  // bounding box (which, unlike the centroid, does not depend on how densely the path is sampled)
  Vec3 lo = points.empty() ? base : points.front(), hi = lo;
  for (const Vec3& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  Vec3 away = 0.5 * (lo + hi) - base;
  away.z() = 0;
  away = away.norm() > 1e-9 ? Vec3(away.normalized()) : Vec3(Vec3::UnitX());

  // the best-fit plane's normal: the direction of least spread
  Mat3 spread = Mat3::Zero();
  for (const Vec3& p : points) spread += (p - centre) * (p - centre).transpose();
  const Eigen::SelfAdjointEigenSolver<Mat3> axes(spread);
  const Vec3 lambda = axes.eigenvalues();  // ascending
  Vec3 n = z;
  if (points.size() >= 2 && lambda[2] > 0) {
    if (lambda[1] <= kLineSpread * lambda[2]) {
      // a straight path: the plane through it closest to horizontal, or facing the base
      const Vec3 d = axes.eigenvectors().col(2);
      n = z - z.dot(d) * d;
      if (n.norm() < 1e-6) n = -away - (-away).dot(d) * d;
    } else {
      n = axes.eigenvectors().col(0);
    }
    n.normalize();
  }
  // the tool's side of the plane: up for a floor-like part, towards the base for a wall
  if (n.dot(z - away) < 0) n = -n;

  // in the plane: away from the base and up, turned about the normal
  Vec3 h0 = (away + z) - (away + z).dot(n) * n;
  h0 = h0.norm() > 1e-9 ? Vec3(h0.normalized()) : any_perpendicular(n);
  const double turn = kViewTurnDeg * kDeg, tilt = kViewFromNormalDeg * kDeg;
  const Vec3 h = std::cos(turn) * h0 + std::sin(turn) * n.cross(h0);
  const Vec3 towards_eye = std::cos(tilt) * n + std::sin(tilt) * h;
  return {std::atan2(towards_eye.y(), towards_eye.x()) / kDeg, std::asin(std::clamp(towards_eye.z(), -1.0, 1.0)) / kDeg};
}

CameraPose frame_part(const std::vector<Vec3>& points, const Vec3& base, double aspect, const PartFraming& framing) {
  ViewAngles view = default_view(points, base);
  if (framing.azimuth_deg) view.azimuth_deg = *framing.azimuth_deg;
  if (framing.elevation_deg) view.elevation_deg = *framing.elevation_deg;
  if (points.empty()) return orbit_camera(base, view.azimuth_deg, view.elevation_deg, kMinPartDistance, 45);

  // the bounding box: its centre is the first aim, its diagonal sets the distance
  Vec3 lo = points.front(), hi = points.front();
  for (const Vec3& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const Vec3 centre = 0.5 * (lo + hi);
  const double diagonal = (hi - lo).norm();
  if (!(diagonal > 0)) return orbit_camera(centre, view.azimuth_deg, view.elevation_deg, kMinPartDistance, 45);

  double distance = std::max(kMinPartDistance, kPartDistancePerDiagonal * diagonal);
  CameraPose camera;
  for (int attempt = 0; attempt < kDistanceIterations; ++attempt) {
    // centre the projected box: move eye and aim together, parallel to the image plane
    Vec3 target = centre;
    ImageBox box;
    for (int i = 0; i < kCentringIterations; ++i) {
      camera = orbit_camera(target, view.azimuth_deg, view.elevation_deg, distance, 45);
      box = image_box(camera, points);
      const double xc = 0.5 * (box.x0 + box.x1), yc = 0.5 * (box.y0 + box.y1);
      if (std::abs(xc) < kCentred && std::abs(yc) < kCentred) break;
      target += distance * (xc * camera.right() + yc * camera.up);
    }
    // the field of view that makes the larger relative side `fill`: with f = H / (2 tan(fovy/2)),
    // share = f / H * max(box width / aspect, box height) in normalised units
    const double spread = std::max((box.x1 - box.x0) / aspect, box.y1 - box.y0);
    const double tan_half = 0.5 * spread / framing.fill;
    camera.fovy_deg = 2 * std::atan(tan_half) / kDeg;
    // outside the usable range: the distance changes (extents scale about as 1 / distance)
    const double limit = camera.fovy_deg < kMinFovyDeg ? kMinFovyDeg : camera.fovy_deg > kMaxFovyDeg ? kMaxFovyDeg : 0;
    if (limit == 0 || !(spread > 0)) break;
    const double scaled = distance * tan_half / std::tan(0.5 * limit * kDeg);
    // never so close that part of the path comes to lie behind the eye
    if (scaled < 0.75 * diagonal || attempt + 1 == kDistanceIterations) {
      camera.fovy_deg = std::clamp(camera.fovy_deg, kMinFovyDeg, kMaxFovyDeg);
      break;
    }
    distance = scaled;
  }
  return camera;
}

double framed_share(const CameraPose& camera, const std::vector<Vec3>& points, int width, int height) {
  double u0 = std::numeric_limits<double>::infinity(), u1 = -u0, v0 = u0, v1 = -u0;
  int count = 0;
  for (const Vec3& p : points) {
    const Projection q = project(camera, p, width, height);
    if (!(q.depth > 0)) continue;
    u0 = std::min(u0, q.u);
    u1 = std::max(u1, q.u);
    v0 = std::min(v0, q.v);
    v1 = std::max(v1, q.v);
    ++count;
  }
  if (count < 2) return 0;
  return std::max((u1 - u0) / width, (v1 - v0) / height);
}

}  // namespace blendbench
