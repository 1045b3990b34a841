#include "blendbench/render/camera.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "support/property.hpp"

namespace blendbench {
namespace {

constexpr double kRad = std::numbers::pi / 180;
constexpr double kTight = 1e-9;
// The framing rule holds to this share of the frame (the solution is closed form after the
// centring iterations) and the box is centred to this many pixels.
constexpr double kShareTolerance = 1e-6;
constexpr double kCentreTolerance = 1e-3;  // pixels

// A rectangle of size a x b (m) in the plane through `centre` spanned by the unit vectors u, v,
// sampled along its edges.
std::vector<Vec3> rectangle(const Vec3& centre, const Vec3& u, const Vec3& v, double a, double b) {
  std::vector<Vec3> points;
  const Vec3 corners[5] = {centre - 0.5 * a * u - 0.5 * b * v, centre + 0.5 * a * u - 0.5 * b * v,
                           centre + 0.5 * a * u + 0.5 * b * v, centre - 0.5 * a * u + 0.5 * b * v,
                           centre - 0.5 * a * u - 0.5 * b * v};
  for (int e = 0; e < 4; ++e) {
    for (int i = 0; i < 20; ++i) points.push_back(corners[e] + (corners[e + 1] - corners[e]) * (i / 20.0));
  }
  points.push_back(corners[4]);
  return points;
}

// The centre of the points' projected bounding rectangle (pixels).
std::pair<double, double> box_centre(const CameraPose& c, const std::vector<Vec3>& points, int w, int h) {
  double u0 = 1e300, u1 = -1e300, v0 = 1e300, v1 = -1e300;
  for (const Vec3& p : points) {
    const Projection q = project(c, p, w, h);
    u0 = std::min(u0, q.u);
    u1 = std::max(u1, q.u);
    v0 = std::min(v0, q.v);
    v1 = std::max(v1, q.v);
  }
  return {0.5 * (u0 + u1), 0.5 * (v0 + v1)};
}

TEST(Camera, OrbitCameraLooksAtItsTargetFromItsAnglesWithAHorizontalImageRight) {
  const Vec3 target(0.4, -0.1, 0.2);
  for (const double az : {-170.0, -30.0, 0.0, 45.0, 120.0}) {
    for (const double el : {-60.0, 0.0, 35.0, 89.0}) {
      const CameraPose c = orbit_camera(target, az, el, 0.8, 40);
      EXPECT_NEAR((c.eye - target).norm(), 0.8, kTight);
      const Vec3 towards_eye = (c.eye - target) / 0.8;
      EXPECT_NEAR(std::asin(towards_eye.z()) / kRad, el, 1e-7);
      EXPECT_NEAR(c.forward.dot(c.up), 0, kTight);
      EXPECT_NEAR(c.up.norm(), 1, kTight);
      EXPECT_NEAR(c.right().z(), 0, kTight) << "image right must stay horizontal";
      EXPECT_GT(c.up.z(), 0) << "image up must point up";
      const Projection q = project(c, target, 640, 480);
      EXPECT_NEAR(q.u, 320, 1e-6);
      EXPECT_NEAR(q.v, 240, 1e-6);
      EXPECT_NEAR(q.depth, 0.8, kTight);
    }
  }
}

TEST(Camera, ProjectionScalesWithTheFieldOfViewAndMeasuresRowsFromTheTop) {
  const CameraPose c = orbit_camera(Vec3::Zero(), 0, 0, 1, 90);  // at +x looking at the origin
  // tan(45 deg) = 1: a point 0.1 m up at depth 1 lies 0.1 of the half height above the centre
  const Projection up = project(c, Vec3(0, 0, 0.1), 400, 200);
  EXPECT_NEAR(up.v, 100 - 0.1 * 100, 1e-9);
  EXPECT_NEAR(up.u, 200, 1e-9);
  // seen from +x, world +y is on the image's right
  EXPECT_GT(project(c, Vec3(0, 0.1, 0), 400, 200).u, 200);
  EXPECT_NEAR(pixel_size(c, 1, 200), 2.0 / 200, 1e-12);
}

TEST(Camera, LookAtHandlesAStraightDownView) {
  const CameraPose c = look_at(Vec3(0.5, 0, 1), Vec3(0.5, 0, 0), 45);
  EXPECT_TRUE(c.forward.isApprox(-Vec3::UnitZ()));
  EXPECT_NEAR(c.up.dot(c.forward), 0, kTight);
  const Projection q = project(c, Vec3(0.5, 0, 0), 100, 100);
  EXPECT_NEAR(q.u, 50, 1e-9);
  EXPECT_NEAR(q.v, 50, 1e-9);
}

TEST(Camera, DefaultViewOfAFloorPartIsObliqueFromTheFarSide) {
  // a part in front of the base (+x), horizontal: 40 degrees from the normal, turned 30 degrees
  const std::vector<Vec3> part = rectangle(Vec3(0.45, 0, 0.2), Vec3::UnitX(), Vec3::UnitY(), 0.12, 0.36);
  const ViewAngles v = default_view(part, Vec3::Zero());
  EXPECT_NEAR(v.elevation_deg, 90 - kViewFromNormalDeg, 1e-9);
  EXPECT_NEAR(v.azimuth_deg, kViewTurnDeg, 1e-9);
}

TEST(Camera, DefaultViewOfAWallLooksAtItFromTheToolsSide) {
  // a wall at x = 0.6 facing the base: the camera stands between base and wall, above
  const Vec3 centre(0.6, 0, 0.4);
  const std::vector<Vec3> wall = rectangle(centre, Vec3::UnitY(), Vec3::UnitZ(), 0.3, 0.2);
  const ViewAngles v = default_view(wall, Vec3::Zero());
  const CameraPose c = orbit_camera(centre, v.azimuth_deg, v.elevation_deg, 1, 45);
  EXPECT_LT(c.eye.x(), centre.x());
  EXPECT_GT(c.eye.z(), centre.z());
  EXPECT_NEAR(std::acos((c.eye - centre).normalized().dot(-Vec3::UnitX())) / kRad, kViewFromNormalDeg, 1e-6);
}

TEST(Camera, DegeneratePathsGetAFiniteCamera) {
  for (const std::vector<Vec3>& points :
       {std::vector<Vec3>{}, std::vector<Vec3>{Vec3(0.4, 0, 0.2)}, std::vector<Vec3>{Vec3(0.4, 0, 0.2), Vec3(0.4, 0, 0.2)},
        std::vector<Vec3>{Vec3(0.4, 0, 0.1), Vec3(0.4, 0, 0.5)},     // vertical line
        std::vector<Vec3>{Vec3(0.3, -0.2, 0.2), Vec3(0.5, 0.2, 0.2)}}) {  // horizontal line
    const CameraPose c = frame_part(points, Vec3::Zero(), 4.0 / 3, {});
    EXPECT_TRUE(c.eye.allFinite() && c.forward.allFinite() && c.up.allFinite()) << points.size();
    EXPECT_TRUE(std::isfinite(c.fovy_deg));
    EXPECT_GE(c.fovy_deg, kMinFovyDeg);
    EXPECT_LE(c.fovy_deg, kMaxFovyDeg);
  }
  // a straight path is framed like any other
  const std::vector<Vec3> line = {Vec3(0.3, -0.2, 0.2), Vec3(0.4, 0, 0.2), Vec3(0.5, 0.2, 0.2)};
  EXPECT_NEAR(framed_share(frame_part(line, Vec3::Zero(), 4.0 / 3, {}), line, 640, 480), 0.6, kShareTolerance);
}

// The framing rule on random planar parts: sizes from 2 cm to 1 m, any plane, any place in reach,
// any aspect and fill: the projected box is centred and its larger relative side is the fill.
TEST(Camera, FramePartMeetsTheFramingRuleOnRandomParts) {
  const int cases = test::property_cases(300);
  for (int k = 0; k < cases; ++k) {
    const auto seed = static_cast<std::uint64_t>(k) + 1;
    auto rng = test::make_rng(seed);
    const Vec3 centre(test::uniform(rng, -0.7, 0.7), test::uniform(rng, -0.7, 0.7), test::uniform(rng, 0, 0.8));
    const Vec3 normal = Vec3(test::uniform(rng, -1, 1), test::uniform(rng, -1, 1), test::uniform(rng, -1, 1)).normalized();
    const Vec3 u = any_perpendicular(normal), v = normal.cross(u);
    const std::vector<Vec3> part =
        rectangle(centre, u, v, test::log_uniform(rng, 0.02, 1.0), test::log_uniform(rng, 0.02, 1.0));
    const int width = 2 * static_cast<int>(test::uniform(rng, 100, 960)), height = 2 * static_cast<int>(test::uniform(rng, 100, 540));
    PartFraming framing;
    framing.fill = test::uniform(rng, 0.3, 0.9);
    const CameraPose c = frame_part(part, Vec3::Zero(), static_cast<double>(width) / height, framing);
    ASSERT_GE(c.fovy_deg, kMinFovyDeg) << test::seed_text(seed);
    ASSERT_LE(c.fovy_deg, kMaxFovyDeg) << test::seed_text(seed);
    for (const Vec3& p : part) ASSERT_GT(project(c, p, width, height).depth, 0) << test::seed_text(seed);
    EXPECT_NEAR(framed_share(c, part, width, height), framing.fill, kShareTolerance) << test::seed_text(seed);
    const auto [uc, vc] = box_centre(c, part, width, height);
    EXPECT_NEAR(uc, 0.5 * width, kCentreTolerance) << test::seed_text(seed);
    EXPECT_NEAR(vc, 0.5 * height, kCentreTolerance) << test::seed_text(seed);
  }
}

TEST(Camera, GivenAnglesOverrideTheDefaultView) {
  const std::vector<Vec3> part = rectangle(Vec3(0.45, 0, 0.2), Vec3::UnitX(), Vec3::UnitY(), 0.12, 0.36);
  PartFraming framing;
  framing.azimuth_deg = -90;
  framing.elevation_deg = 60;
  const CameraPose c = frame_part(part, Vec3::Zero(), 16.0 / 9, framing);
  EXPECT_NEAR(std::asin(-c.forward.z()) / kRad, 60, 1e-7);
  EXPECT_NEAR(std::atan2(-c.forward.y(), -c.forward.x()) / kRad, -90, 1e-7);
  EXPECT_NEAR(framed_share(c, part, 1280, 720), 0.6, kShareTolerance);
}

}  // namespace
}  // namespace blendbench
