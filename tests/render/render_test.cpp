#include "blendbench/render/render.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "support/test_arm.hpp"
#include "blendbench/sim/simulator.hpp"

namespace blendbench {
namespace {

constexpr int kWidth = 320;
constexpr int kHeight = 240;
// A rendered scene has structure; a blank or uniform frame has (near) zero variance.
constexpr double kMinVariance = 100;  // (8-bit levels)²
// Two pixels differ when some channel differs by more than this (antialiasing-free renders are
// deterministic, so this only absorbs shading noise).
constexpr int kPixelDifference = 8;
// How far (pixels) the centroid of changed pixels may lie from where the projection puts them.
constexpr double kCentroidTolerance = 6;

struct Pixel {
  double u, v;  // column, row (top-down), pixels
};

// The model state at the bent pose, kinematics current.
struct ArmState {
  explicit ArmState(const std::string& xml) : sim(Simulator::from_xml_string(xml)), d(mj_makeData(&sim.model())) {
    const JointVector q = test::test_arm_bent_pose();
    for (int i = 0; i < 6; ++i) d->qpos[i] = q[i];
    mj_forward(&sim.model(), d);
  }
  ~ArmState() { mj_deleteData(d); }
  ArmState(const ArmState&) = delete;
  ArmState& operator=(const ArmState&) = delete;

  // Pinhole projection through the model camera `name` (MuJoCo: the camera looks along its -z,
  // y up, cam_fovy is the vertical field of view in degrees).
  [[nodiscard]] Pixel project(const std::string& name, const Eigen::Vector3d& p, int width, int height) const {
    const int cam = mj_name2id(&sim.model(), mjOBJ_CAMERA, name.c_str());
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> r(d->cam_xmat + 9 * cam);
    const Eigen::Vector3d local = r.transpose() * (p - Eigen::Vector3d(d->cam_xpos + 3 * cam));
    const double f = 0.5 * height / std::tan(0.5 * sim.model().cam_fovy[cam] * M_PI / 180);
    return {0.5 * width + f * local.x() / -local.z(), 0.5 * height - f * local.y() / -local.z()};
  }

  Simulator sim;
  mjData* d;
};

double variance(const std::vector<std::uint8_t>& rgb) {
  double sum = 0, sum2 = 0;
  for (const std::uint8_t c : rgb) {
    sum += c;
    sum2 += static_cast<double>(c) * c;
  }
  const double n = static_cast<double>(rgb.size());
  return sum2 / n - (sum / n) * (sum / n);
}

// Pixels where the two frames differ: their count and centroid.
struct Difference {
  int count = 0;
  Pixel centroid{0, 0};
};

Difference difference(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b, int width) {
  Difference out;
  for (std::size_t i = 0; i < a.size(); i += 3) {
    bool differs = false;
    for (std::size_t c = 0; c < 3; ++c) differs = differs || std::abs(int{a[i + c]} - int{b[i + c]}) > kPixelDifference;
    if (!differs) continue;
    const auto pixel = static_cast<int>(i / 3);
    out.centroid.u += pixel % width;
    out.centroid.v += pixel / width;
    ++out.count;
  }
  if (out.count > 0) {
    out.centroid.u /= out.count;
    out.centroid.v /= out.count;
  }
  return out;
}

// The test arm with its links hidden (geom group 3 is not drawn by default) but the floor kept.
std::string hidden_arm_xml() {
  std::string xml = test::kTestArmXml;
  const std::string link_default = "<geom type=\"capsule\" rgba=\"0.75 0.78 0.82 1\"";
  const std::string floor = "name=\"floor\"";
  const std::string base = "<geom type=\"cylinder\" size=\"0.075 0.04\"";
  xml.insert(xml.find(link_default) + link_default.size(), " group=\"3\"");
  xml.insert(xml.find(floor) + floor.size(), " group=\"0\"");
  xml.insert(xml.find(base) + base.size(), " group=\"0\"");
  return xml;
}

RenderOptions small() {
  RenderOptions options;
  options.width = kWidth;
  options.height = kHeight;
  options.draw_tcp_trail = false;
  options.line_radius = 0.01;  // 320x240 pixels are ~6 mm wide here
  return options;
}

TEST(OffscreenRenderer, FrameOfTheArmIsNotBlankAndShowsTheArmWhereItStands) {
  const ArmState arm(test::kTestArmXml);
  const ArmState hidden(hidden_arm_xml());
  OffscreenRenderer with(arm.sim.model(), small());
  OffscreenRenderer without(hidden.sim.model(), small());
  const std::vector<std::uint8_t> frame = with.render(*arm.d);
  const std::vector<std::uint8_t> background = without.render(*hidden.d);
  ASSERT_EQ(frame.size(), static_cast<std::size_t>(kWidth * kHeight * 3));
  EXPECT_GT(variance(frame), kMinVariance);

  // the arm covers a few percent of the frame, around the projection of its middle (the elbow)
  const Difference arm_pixels = difference(frame, background, kWidth);
  EXPECT_GT(arm_pixels.count, kWidth * kHeight / 50);
  EXPECT_LT(arm_pixels.count, kWidth * kHeight / 2);
  const int forearm = mj_name2id(&arm.sim.model(), mjOBJ_BODY, "forearm");
  const Pixel elbow = arm.project("overview", Eigen::Vector3d(arm.d->xpos + 3 * forearm), kWidth, kHeight);
  EXPECT_LT(std::hypot(arm_pixels.centroid.u - elbow.u, arm_pixels.centroid.v - elbow.v), 0.15 * kWidth)
      << "centroid " << arm_pixels.centroid.u << "," << arm_pixels.centroid.v << " elbow " << elbow.u << ","
      << elbow.v;
  EXPECT_EQ(take_mujoco_warnings(), "");
}

TEST(OffscreenRenderer, PathPolylineIsDrawnWhereItProjects) {
  // a short straight path in front of the arm, away from it, near the floor
  const ArmState arm(test::kTestArmXml);
  RenderOptions options = small();
  const Eigen::Vector3d a(0.45, -0.35, 0.05), b(0.45, 0.05, 0.05);
  OffscreenRenderer plain(arm.sim.model(), options);
  options.path_polyline = {a, 0.5 * (a + b), b};
  OffscreenRenderer with_path(arm.sim.model(), options);
  const Difference path_pixels = difference(plain.render(*arm.d), with_path.render(*arm.d), kWidth);
  const Pixel pa = arm.project("overview", a, kWidth, kHeight);
  const Pixel pb = arm.project("overview", b, kWidth, kHeight);
  const double length = std::hypot(pb.u - pa.u, pb.v - pa.v);
  EXPECT_GT(path_pixels.count, static_cast<int>(2 * length));  // a few pixels wide along its length
  EXPECT_LT(path_pixels.count, static_cast<int>(10 * length));
  EXPECT_NEAR(path_pixels.centroid.u, 0.5 * (pa.u + pb.u), kCentroidTolerance);
  EXPECT_NEAR(path_pixels.centroid.v, 0.5 * (pa.v + pb.v), kCentroidTolerance);
}

TEST(OffscreenRenderer, PlannedPathAndTrailAddPixelsAndClearTrailRemovesThem) {
  const ArmState arm(test::kTestArmXml);
  RenderOptions options = small();
  options.draw_tcp_trail = true;
  OffscreenRenderer renderer(arm.sim.model(), options);
  const std::vector<std::uint8_t> first = renderer.render(*arm.d);

  // move the arm a little: the second frame carries a trail segment between the two TCPs
  mjData* d = arm.d;
  d->qpos[0] += 0.3;
  mj_forward(&arm.sim.model(), d);
  const std::vector<std::uint8_t> trail = renderer.render(*d);
  renderer.clear_trail();
  const std::vector<std::uint8_t> no_trail = renderer.render(*d);
  EXPECT_GT(difference(trail, no_trail, kWidth).count, 10);
  EXPECT_GT(difference(first, no_trail, kWidth).count, 10);

  options.draw_tcp_trail = false;
  options.planned_polyline = {Eigen::Vector3d(0.4, -0.3, 0.3), Eigen::Vector3d(0.4, 0.3, 0.3)};
  OffscreenRenderer planned(arm.sim.model(), options);
  options.planned_polyline.clear();
  OffscreenRenderer plain(arm.sim.model(), options);
  EXPECT_GT(difference(planned.render(*d), plain.render(*d), kWidth).count, 50);
}

TEST(OffscreenRenderer, MissingCameraFallsBackToAFreeCameraAndLargerSizesWork) {
  // 800x600 exceeds the model's 640x480 off-screen buffer: the renderer's copy is enlarged
  const ArmState arm(test::kTestArmXml);
  RenderOptions options;
  options.width = 800;
  options.height = 600;
  options.camera = "no_such_camera";
  OffscreenRenderer renderer(arm.sim.model(), options);
  const std::vector<std::uint8_t>& frame = renderer.render(*arm.d);
  EXPECT_EQ(frame.size(), 800u * 600u * 3u);
  EXPECT_GT(variance(frame), kMinVariance);
}

TEST(OffscreenRenderer, ModelWithoutFloorGetsOne) {
  std::string xml = test::kTestArmXml;
  const auto p = xml.find("<geom name=\"floor\"");
  xml.erase(p, xml.find("/>", p) + 2 - p);
  const ArmState arm(xml);
  RenderOptions options = small();
  OffscreenRenderer renderer(arm.sim.model(), options);
  // the floor fills the bottom row (the camera looks down on it)
  const std::vector<std::uint8_t>& frame = renderer.render(*arm.d);
  const std::size_t bottom = static_cast<std::size_t>((kHeight - 1) * kWidth + kWidth / 2) * 3;
  EXPECT_GT(frame[bottom] + frame[bottom + 1] + frame[bottom + 2], 60);
}

TEST(OffscreenRenderer, SizeBeyondTheGlLimitIsAClearError) {
  const ArmState arm(test::kTestArmXml);
  RenderOptions options;
  options.width = 40000;
  options.height = 8;
  try {
    OffscreenRenderer renderer(arm.sim.model(), options);
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("40000x8 exceeds"), std::string::npos) << e.what();
  }
  // the failed renderer left nothing behind that breaks the next one
  options.width = 64;
  options.height = 48;
  EXPECT_EQ(OffscreenRenderer(arm.sim.model(), options).render(*arm.d).size(), 64u * 48u * 3u);
}

TEST(OffscreenRenderer, NonPositiveSizeIsRejected) {
  const ArmState arm(test::kTestArmXml);
  RenderOptions options;
  options.width = 0;
  EXPECT_THROW(OffscreenRenderer(arm.sim.model(), options), std::invalid_argument);
}

}  // namespace
}  // namespace blendbench
