#include "blendbench/render/render.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>
#include <string>

#include "support/property.hpp"
#include "support/test_arm.hpp"
#include "blendbench/sim/simulator.hpp"

namespace blendbench {
namespace {

constexpr int kWidth = 320;
constexpr int kHeight = 240;
// A rendered scene has structure; a blank or uniform frame has (near) zero variance.
constexpr double kMinVariance = 100;  // (8-bit levels)^2
// Two pixels differ when some channel differs by more than this (renders without multisampling
// are deterministic, so this only absorbs shading noise).
constexpr int kPixelDifference = 8;
// A pixel has a line's colour when every channel is within this of it (the cores of
// antialiased lines keep the exact colour).
constexpr int kColourTolerance = 3;
// How far (pixels) a centroid of drawn pixels may lie from where the projection puts it.
constexpr double kCentroidTolerance = 3;

struct Pixel {
  double u = 0, v = 0;  // column, row (top-down), pixels
};

// The model state at the bent pose, kinematics current.
struct ArmState {
  explicit ArmState(Simulator s) : sim(std::move(s)), d(mj_makeData(&sim.model())) {
    const JointVector q = test::test_arm_bent_pose();
    for (int i = 0; i < 6; ++i) d->qpos[i] = q[i];
    mj_forward(&sim.model(), d);
  }
  ArmState() : ArmState(Simulator::from_xml_string(test::kTestArmXml)) {}
  ~ArmState() { mj_deleteData(d); }
  ArmState(const ArmState&) = delete;
  ArmState& operator=(const ArmState&) = delete;

  [[nodiscard]] CameraPose overview() const { return model_camera(sim.model(), *d, "overview").value(); }

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

// Pixels that match a predicate: their count, centroid and bounding box.
struct Found {
  int count = 0;
  Pixel centroid;
  int u0 = 1 << 30, u1 = -1, v0 = 1 << 30, v1 = -1;
};

template <class Predicate>
Found find_pixels(const std::vector<std::uint8_t>& rgb, int width, Predicate match) {
  Found out;
  for (std::size_t i = 0; i + 2 < rgb.size(); i += 3) {
    if (!match(i)) continue;
    const auto pixel = static_cast<int>(i / 3);
    const int u = pixel % width, v = pixel / width;
    out.centroid.u += u;
    out.centroid.v += v;
    out.u0 = std::min(out.u0, u);
    out.u1 = std::max(out.u1, u);
    out.v0 = std::min(out.v0, v);
    out.v1 = std::max(out.v1, v);
    ++out.count;
  }
  if (out.count > 0) {
    out.centroid.u /= out.count;
    out.centroid.v /= out.count;
  }
  return out;
}

Found differing(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b, int width) {
  return find_pixels(a, width, [&](std::size_t i) {
    for (std::size_t c = 0; c < 3; ++c)
      if (std::abs(int{a[i + c]} - int{b[i + c]}) > kPixelDifference) return true;
    return false;
  });
}

Found coloured(const std::vector<std::uint8_t>& rgb, int width, const Rgba& colour) {
  const int want[3] = {static_cast<int>(std::lround(colour.r * 255)), static_cast<int>(std::lround(colour.g * 255)),
                       static_cast<int>(std::lround(colour.b * 255))};
  return find_pixels(rgb, width, [&](std::size_t i) {
    for (std::size_t c = 0; c < 3; ++c)
      if (std::abs(int{rgb[i + c]} - want[c]) > kColourTolerance) return false;
    return true;
  });
}

// One frame of the posed arm through `camera` with `lines`, read back.
std::vector<std::uint8_t> frame(OffscreenRenderer& r, const CameraPose& camera, std::span<const Polyline> lines = {},
                                SceneStyle style = {}) {
  r.draw_scene({0, 0, r.width(), r.height()}, camera, lines, {}, style);
  return r.read();
}

TEST(OffscreenRenderer, FrameOfTheArmIsNotBlankAndShowsTheArmWhereItStands) {
  const ArmState arm;
  OffscreenRenderer r(arm.sim.model(), kWidth, kHeight);
  r.pose(*arm.d);
  const std::vector<std::uint8_t> with = frame(r, arm.overview());
  const std::vector<std::uint8_t> without = frame(r, arm.overview(), {}, {.hide_arm = true});
  ASSERT_EQ(with.size(), static_cast<std::size_t>(kWidth * kHeight * 3));
  EXPECT_GT(variance(with), kMinVariance);

  // the arm covers a few percent of the frame, around the projection of its middle (the elbow)
  const Found arm_pixels = differing(with, without, kWidth);
  EXPECT_GT(arm_pixels.count, kWidth * kHeight / 50);
  EXPECT_LT(arm_pixels.count, kWidth * kHeight / 2);
  const int forearm = mj_name2id(&arm.sim.model(), mjOBJ_BODY, "forearm");
  const Projection elbow = project(arm.overview(), Vec3(arm.d->xpos + 3 * forearm), kWidth, kHeight);
  EXPECT_LT(std::hypot(arm_pixels.centroid.u - elbow.u, arm_pixels.centroid.v - elbow.v), 0.15 * kWidth)
      << "centroid " << arm_pixels.centroid.u << "," << arm_pixels.centroid.v << " elbow " << elbow.u << "," << elbow.v;
  EXPECT_EQ(take_mujoco_warnings(), "");
}

TEST(OffscreenRenderer, PolylineIsDrawnInItsColourWhereItProjectsEvenBehindTheArm) {
  // a straight line through the arm's elbow: drawn over the arm, in its exact colour
  const ArmState arm;
  OffscreenRenderer r(arm.sim.model(), kWidth, kHeight);
  r.pose(*arm.d);
  const int forearm = mj_name2id(&arm.sim.model(), mjOBJ_BODY, "forearm");
  const Vec3 elbow(arm.d->xpos + 3 * forearm);
  const Vec3 a = elbow - Vec3(0, 0.3, 0), b = elbow + Vec3(0, 0.3, 0);
  const std::vector<Vec3> points = {a, 0.5 * (a + b), b};
  const Polyline line{points, std::nullopt, kProgrammedColour, 4};
  const Found drawn = coloured(frame(r, arm.overview(), {&line, 1}), kWidth, kProgrammedColour);
  const Projection pa = project(arm.overview(), a, kWidth, kHeight), pb = project(arm.overview(), b, kWidth, kHeight);
  const double length = std::hypot(pb.u - pa.u, pb.v - pa.v);
  EXPECT_GT(drawn.count, static_cast<int>(2 * length));  // a few pixels wide along its whole length
  EXPECT_LT(drawn.count, static_cast<int>(6 * length));
  EXPECT_NEAR(drawn.centroid.u, 0.5 * (pa.u + pb.u), kCentroidTolerance);
  EXPECT_NEAR(drawn.centroid.v, 0.5 * (pa.v + pb.v), kCentroidTolerance);
}

TEST(OffscreenRenderer, CoincidingLinesAllShowAndATipExtendsALine) {
  // programmed, planned and trail on the same segment, each narrower: three colours show
  const ArmState arm;
  OffscreenRenderer r(arm.sim.model(), kWidth, kHeight);
  r.pose(*arm.d);
  const std::vector<Vec3> segment = {Vec3(0.45, -0.35, 0.05), Vec3(0.45, 0.05, 0.05)};
  const std::vector<Vec3> start = {segment[0]};
  const std::array<Polyline, 3> lines = {Polyline{segment, std::nullopt, kProgrammedColour, 8},
                                         Polyline{segment, std::nullopt, method_colour("clothoid"), 5},
                                         Polyline{start, segment[1], kTrailColour, 2}};
  const std::vector<std::uint8_t> rgb = frame(r, arm.overview(), lines);
  for (const Rgba& c : {kProgrammedColour, method_colour("clothoid"), kTrailColour}) {
    EXPECT_GT(coloured(rgb, kWidth, c).count, 50) << c.r << " " << c.g << " " << c.b;
  }
}

TEST(OffscreenRenderer, AMarkerIsADiscWhereItsPointProjects) {
  const ArmState arm;
  OffscreenRenderer r(arm.sim.model(), kWidth, kHeight);
  r.pose(*arm.d);
  const Vec3 p(0.5, -0.2, 0.05);
  const Marker m{p, kTrailColour, 6};
  r.draw_scene({0, 0, kWidth, kHeight}, arm.overview(), {}, {&m, 1});
  const Found disc = coloured(r.read(), kWidth, kTrailColour);
  const Projection q = project(arm.overview(), p, kWidth, kHeight);
  EXPECT_NEAR(disc.centroid.u, q.u, 1);
  EXPECT_NEAR(disc.centroid.v, q.v, 1);
  // the coloured inside of a 6-pixel disc with its rim: radius 4.2, area ~55
  EXPECT_NEAR(disc.count, 55, 15);
}

// Distance (pixels) from pixel (u, v) to the segment a-b of the image.
double to_segment(double u, double v, const Projection& a, const Projection& b) {
  const Eigen::Vector2d p(u, v), pa(a.u, a.v), pb(b.u, b.v);
  const Eigen::Vector2d d = pb - pa;
  const double t = d.squaredNorm() > 0 ? std::clamp((p - pa).dot(d) / d.squaredNorm(), 0.0, 1.0) : 0.0;
  return (p - (pa + t * d)).norm();
}

// The tool on the flange: a yellow body from the flange (site "tcp") to the TCP and a reddish
// purple rod along the tool's z axis, drawn as decorations where they project; without a tool
// none of those pixels; with the arm hidden, no tool either; nothing else changes.
TEST(OffscreenRenderer, TheToolIsDrawnFromTheFlangeToTheTcpInItsColours) {
  constexpr int kW = 2 * kWidth, kH = 2 * kHeight;
  const ArmState arm;
  OffscreenRenderer r(arm.sim.model(), kW, kH);
  r.pose(*arm.d);
  const mjModel& m = arm.sim.model();
  const int site = mj_name2id(&m, mjOBJ_SITE, "tcp");
  ASSERT_GE(site, 0);
  // a 15 cm tool along the flange axis that lies most across the view, its z axis across the
  // view too (perpendicular to the offset and the line of sight)
  const CameraPose camera = arm.overview();
  const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> flange_rot(arm.d->site_xmat + 9 * site);
  int across = 0;
  for (int k = 1; k < 3; ++k) {
    if (std::abs(flange_rot.col(k).dot(camera.forward)) < std::abs(flange_rot.col(across).dot(camera.forward))) across = k;
  }
  const Vec3 axis_world = flange_rot.col(across).cross(camera.forward).normalized();
  Eigen::Isometry3d tool = Eigen::Isometry3d::Identity();
  tool.translation() = 0.15 * Vec3::Unit(across);
  tool.linear() = Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), flange_rot.transpose() * axis_world).toRotationMatrix();
  const Vec3 flange = Eigen::Map<const Vec3>(arm.d->site_xpos + 3 * site);
  const Vec3 tcp = flange + flange_rot * tool.translation();
  const Vec3 axis_tip = tcp + kToolAxisLength * axis_world;
  const Projection a = project(camera, flange, kW, kH);
  const Projection b = project(camera, tcp, kW, kH);
  const Projection c = project(camera, axis_tip, kW, kH);
  ASSERT_GT(std::hypot(a.u - b.u, a.v - b.v), 20) << "the tool must show as more than a dot";

  const std::vector<std::uint8_t> without = frame(r, camera);
  const std::vector<std::uint8_t> with = frame(r, camera, {}, {.tool = tool});
  const std::vector<std::uint8_t> hidden = frame(r, camera, {}, {.hide_arm = true, .tool = tool});
  const std::vector<std::uint8_t> hidden_no_tool = frame(r, camera, {}, {.hide_arm = true});
  // lit shades: yellow has red and green well above blue, the purple red and blue above green
  const auto yellow = [](const std::vector<std::uint8_t>& rgb, std::size_t i) {
    return rgb[i] > rgb[i + 2] + 80 && rgb[i + 1] > rgb[i + 2] + 80 && std::abs(int{rgb[i]} - int{rgb[i + 1]}) < 40;
  };
  const auto purple = [](const std::vector<std::uint8_t>& rgb, std::size_t i) {
    return rgb[i] > rgb[i + 1] + 25 && rgb[i + 2] > rgb[i + 1] + 10;
  };
  const double slack = kToolRadius / pixel_size(camera, b.depth, kH) + 3;  // pixels
  const auto uv = [&](std::size_t i) { return Pixel{static_cast<double>((i / 3) % kW), static_cast<double>((i / 3) / kW)}; };
  int body = 0, rod = 0, yellow_off_body = 0, purple_off_rod = 0, changed_elsewhere = 0;
  int yellow_before = 0, purple_before = 0;
  // how far along the body (0 flange, 1 TCP) its pixels reach (the flange end may hide in the wrist)
  double t_min = 1, t_max = 0;
  for (std::size_t i = 0; i + 2 < with.size(); i += 3) {
    const Pixel p = uv(i);
    const double to_body = to_segment(p.u, p.v, a, b);
    const double to_rod = to_segment(p.u, p.v, b, c);
    bool changed = false;
    for (std::size_t ch = 0; ch < 3; ++ch) changed = changed || std::abs(int{with[i + ch]} - int{without[i + ch]}) > kPixelDifference;
    // near the tool: its colours with it, none without it
    if (std::min(to_body, to_rod) <= slack) {
      yellow_before += yellow(without, i) ? 1 : 0;
      purple_before += purple(without, i) ? 1 : 0;
    }
    if (!changed) continue;
    if (yellow(with, i)) {
      ++body;
      yellow_off_body += to_body > slack ? 1 : 0;
      const Eigen::Vector2d d(b.u - a.u, b.v - a.v);
      const double t = Eigen::Vector2d(p.u - a.u, p.v - a.v).dot(d) / d.squaredNorm();
      t_min = std::min(t_min, t);
      t_max = std::max(t_max, t);
    }
    if (purple(with, i)) {
      ++rod;
      purple_off_rod += to_rod > slack ? 1 : 0;
    }
    changed_elsewhere += std::min(to_body, to_rod) > slack + 3 ? 1 : 0;
  }
  EXPECT_GT(body, 100);
  EXPECT_GT(rod, 20);
  EXPECT_EQ(yellow_off_body, 0);
  EXPECT_EQ(purple_off_rod, 0);
  EXPECT_GT(t_max, 0.9);
  EXPECT_GT(t_max - t_min, 0.6);
  EXPECT_EQ(yellow_before, 0);
  EXPECT_EQ(purple_before, 0);
  EXPECT_EQ(changed_elsewhere, 0);
  EXPECT_EQ(differing(hidden, hidden_no_tool, kW).count, 0);
  if (const char* dump = std::getenv("BLENDBENCH_TOOL_FRAME")) {
    std::FILE* f = std::fopen(dump, "wb");
    std::fprintf(f, "P6\n%d %d\n255\n", kW, kH);
    std::fwrite(with.data(), 1, with.size(), f);
    std::fclose(f);
  }
}

TEST(OffscreenRenderer, PointsBehindTheEyeBreakALineInsteadOfWrappingAround) {
  const ArmState arm;
  OffscreenRenderer r(arm.sim.model(), kWidth, kHeight);
  r.pose(*arm.d);
  const CameraPose c = arm.overview();
  // from a point in view to one behind the camera: nothing may be drawn for that segment
  const std::vector<Vec3> points = {Vec3(0.4, 0, 0.1), c.eye - 0.5 * c.forward};
  const Polyline line{points, std::nullopt, method_colour("clothoid"), 4};
  EXPECT_EQ(coloured(frame(r, c, {&line, 1}), kWidth, method_colour("clothoid")).count, 0);
}

TEST(OffscreenRenderer, ViewsSideBySideAreDrawnIntoTheirRectanglesAndReadOnce) {
  const ArmState arm;
  OffscreenRenderer r(arm.sim.model(), 2 * kWidth, kHeight);
  OffscreenRenderer single(arm.sim.model(), kWidth, kHeight);
  r.pose(*arm.d);
  single.pose(*arm.d);
  r.draw_scene({0, 0, kWidth, kHeight}, arm.overview(), {});
  r.draw_scene({kWidth, 0, kWidth, kHeight}, arm.overview(), {}, {}, {.hide_arm = true});
  const std::vector<std::uint8_t> both = r.read();
  const std::vector<std::uint8_t> alone = frame(single, arm.overview());
  // the left half is the single view, pixel for pixel; the right half lacks the arm
  std::vector<std::uint8_t> left(alone.size()), right(alone.size());
  for (int y = 0; y < kHeight; ++y) {
    const auto row = static_cast<std::size_t>(kWidth) * 3;
    std::copy_n(both.begin() + static_cast<std::ptrdiff_t>(y * 2 * row), row, left.begin() + static_cast<std::ptrdiff_t>(y * row));
    std::copy_n(both.begin() + static_cast<std::ptrdiff_t>(y * 2 * row + row), row, right.begin() + static_cast<std::ptrdiff_t>(y * row));
  }
  EXPECT_EQ(differing(left, alone, kWidth).count, 0);
  EXPECT_GT(differing(right, alone, kWidth).count, kWidth * kHeight / 50);
}

TEST(OffscreenRenderer, PanelLegendAndLabelDrawReadableTextAndTheLegendColours) {
  const ArmState arm;
  OffscreenRenderer r(arm.sim.model(), 640, 480);
  r.pose(*arm.d);
  r.draw_scene({0, 0, 640, 480}, arm.overview(), {});
  r.draw_panel({0, 0, 640, 480}, Corner::kTopLeft, {{"time", "1.23 s"}, {"tracking error", "41.0 \u00b5m"}});
  const PixelRect box = r.draw_legend({0, 0, 640, 480}, Corner::kBottomRight,
                                      {{kProgrammedColour, "programmed path"}, {method_colour("clothoid"), "planned path"}});
  const std::vector<std::uint8_t> rgb = r.read();
  // the panel: white text on a dark box in the top left (the box darkens whatever is behind it)
  const auto in = [&](std::size_t i, int u0, int v0, int u1, int v1) {
    const auto pixel = static_cast<int>(i / 3);
    return pixel % 640 >= u0 && pixel % 640 < u1 && pixel / 640 >= v0 && pixel / 640 < v1;
  };
  const Found text = find_pixels(rgb, 640, [&](std::size_t i) {
    return in(i, 0, 0, 200, 60) && rgb[i] > 200 && rgb[i + 1] > 200 && rgb[i + 2] > 200;
  });
  EXPECT_GT(text.count, 60);
  EXPECT_EQ(r.text_height(), 18);
  // the legend: in the bottom right, its colour bars inside its box
  EXPECT_GT(box.left, 320);
  EXPECT_GT(box.top, 240);
  for (const Rgba& c : {kProgrammedColour, method_colour("clothoid")}) {
    const Found bar = coloured(rgb, 640, c);
    EXPECT_GT(bar.count, 20);
    EXPECT_GE(bar.u0, box.left);
    EXPECT_LE(bar.u1, box.left + box.width);
    EXPECT_GE(bar.v0, box.top);
    EXPECT_LE(bar.v1, box.top + box.height);
  }
}

// Text alone on a black frame: the pixels of `text` drawn white at (x, y).
std::vector<std::uint8_t> text_frame(OffscreenRenderer& r, const std::string& text, int x, int y) {
  r.fill({0, 0, r.width(), r.height()}, {0, 0, 0, 1});
  r.draw_text(x, y, text, {1, 1, 1, 1});
  return r.read();
}

bool lit(const std::vector<std::uint8_t>& rgb, int width, int u, int v) {
  const auto i = static_cast<std::size_t>(v * width + u) * 3;
  return rgb[i] > 128;
}

// MuJoCo's font has no micro sign; draw_text composes it from "u" and the descender of "p". The
// glyph has every pixel of "u", more pixels below the baseline (the descender, where "p" has
// its own), none above, and the advance of "u"; the rest of the text is unchanged. A character
// the font cannot draw is a "?", never skipped.
TEST(OffscreenRenderer, TheMicroSignIsDrawnAsAuWithADescender) {
  const ArmState arm;
  for (const int scale : {100, 150, 200}) {
    OffscreenRenderer r(arm.sim.model(), 200, 60, {}, scale);
    const int h = r.text_height();
    EXPECT_EQ(r.text_width("41.0 \u00b5m"), r.text_width("41.0 um")) << scale;
    EXPECT_EQ(r.text_width("\xCE\xBC"), r.text_width("u")) << scale << ": the Greek mu is the micro sign";
    const std::vector<std::uint8_t> micro = text_frame(r, "4 \u00b5m", 10, 10);
    const std::vector<std::uint8_t> u = text_frame(r, "4 um", 10, 10);
    const std::vector<std::uint8_t> p = text_frame(r, "4 pm", 10, 10);
    // the glyph's cell: from the end of "4 " for the width of "u"
    const int left = 10 + r.text_width("4 "), right = left + r.text_width("u");
    // the baseline: the lowest row of "u"
    int baseline = 0;
    for (int v = 0; v < 60; ++v)
      for (int x = left; x < right; ++x)
        if (lit(u, 200, x, v)) baseline = std::max(baseline, v);
    int extra = 0, missing = 0, above = 0, outside = 0, descender = 0, p_descender = 0;
    for (int v = 0; v < 60; ++v) {
      for (int x = 0; x < 200; ++x) {
        const bool m = lit(micro, 200, x, v), plain = lit(u, 200, x, v);
        if (x < left || x >= right) {
          outside += m != plain ? 1 : 0;
          continue;
        }
        missing += plain && !m ? 1 : 0;
        extra += m && !plain ? 1 : 0;
        above += m && !plain && v <= baseline ? 1 : 0;
        descender += m && v > baseline ? 1 : 0;
        p_descender += lit(p, 200, x, v) && v > baseline ? 1 : 0;
      }
    }
    EXPECT_EQ(missing, 0) << scale;
    EXPECT_EQ(above, 0) << scale;
    EXPECT_EQ(outside, 0) << scale;
    EXPECT_GT(extra, h / 8) << scale << ": a descender of at least a few pixels";
    EXPECT_EQ(descender, p_descender) << scale << ": the descender is the font's own (of p)";
    // beyond ASCII, other than the micro sign: a question mark
    const std::vector<std::uint8_t> question = text_frame(r, "a?b", 10, 10);
    EXPECT_EQ(differing(text_frame(r, "a\xC3\xA9" "b", 10, 10), question, 200).count, 0) << scale;
    EXPECT_EQ(differing(text_frame(r, "a\xE2\x82\xAC" "b", 10, 10), question, 200).count, 0) << scale;
    EXPECT_EQ(differing(text_frame(r, "a\xB5" "b", 10, 10), question, 200).count, 0) << scale << ": a stray byte";
  }
}

// The panel's box is where its text is: draw_panel returns panel_box's box, in the corner asked,
// with every white pixel of its text inside, in each corner.
TEST(OffscreenRenderer, ThePanelIsDrawnInTheBoxItReports) {
  const ArmState arm;
  OffscreenRenderer r(arm.sim.model(), 320, 240);
  const std::vector<TextRow> rows = {{"time", "1.23 s"}, {"tracking error", "41.0 \u00b5m"}};
  const PixelRect all{0, 0, 320, 240};
  for (const Corner c : {Corner::kTopLeft, Corner::kTopRight, Corner::kBottomLeft, Corner::kBottomRight}) {
    r.fill(all, {0, 0, 0, 1});
    const PixelRect box = r.draw_panel(all, c, rows);
    const PixelRect expected = r.panel_box(all, c, rows);
    EXPECT_EQ(box.left, expected.left);
    EXPECT_EQ(box.top, expected.top);
    EXPECT_EQ(box.width, expected.width);
    EXPECT_EQ(box.height, expected.height);
    EXPECT_EQ(box.left + box.width / 2 < 160, c == Corner::kTopLeft || c == Corner::kBottomLeft);
    EXPECT_EQ(box.top + box.height / 2 < 120, c == Corner::kTopLeft || c == Corner::kTopRight);
    const std::vector<std::uint8_t> rgb = r.read();
    const Found text = find_pixels(rgb, 320, [&](std::size_t i) { return rgb[i] > 200 && rgb[i + 1] > 200 && rgb[i + 2] > 200; });
    EXPECT_GT(text.count, 60);
    EXPECT_GE(text.u0, box.left);
    EXPECT_LT(text.u1, box.left + box.width);
    EXPECT_GE(text.v0, box.top);
    EXPECT_LT(text.v1, box.top + box.height);
  }
}

// The methods' colours in the videos are those of the report's plots: plotio.method_colour (which
// reads render/method_colours.json at run time) and method_colour (compiled from it) agree for
// every listed method and for names not listed (the fallback pick), and no two listed methods share
// a colour.
TEST(MethodColour, TheVideosUseTheReportsColourOfEveryMethod) {
  const std::vector<std::string> methods = {"none", "arc", "bezier", "clothoid", "biclothoid", "spline", "x", "", "optimal_g3"};
  std::string list;
  for (const std::string& m : methods) list += "'" + m + "',";
  const std::string command = "/usr/bin/python3 -c \"import sys; sys.path.insert(0, '" + test::source_path("report/scripts") +
                              "'); import plotio; print(' '.join(plotio.method_colour(m) for m in [" + list + "]))\"";
  FILE* pipe = ::popen(command.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  char buffer[512] = {};
  const std::size_t n = std::fread(buffer, 1, sizeof buffer - 1, pipe);
  ASSERT_EQ(::pclose(pipe), 0) << command;
  std::istringstream python(std::string(buffer, n));
  std::vector<std::string> distinct;
  for (std::size_t i = 0; i < methods.size(); ++i) {
    std::string expected;
    ASSERT_TRUE(python >> expected) << "plotio printed too few colours";
    const Rgba c = method_colour(methods[i]);
    EXPECT_EQ(c.a, 1.0f);
    char hex[8];
    std::snprintf(hex, sizeof hex, "#%02x%02x%02x", static_cast<int>(std::lround(c.r * 255)), static_cast<int>(std::lround(c.g * 255)),
                  static_cast<int>(std::lround(c.b * 255)));
    EXPECT_EQ(std::string(hex), expected) << "method '" << methods[i] << "'";
    if (i < 5) distinct.push_back(hex);
  }
  std::sort(distinct.begin(), distinct.end());
  EXPECT_EQ(std::unique(distinct.begin(), distinct.end()), distinct.end()) << "two methods share a colour";
}

TEST(OffscreenRenderer, ModelWithoutFloorGetsOne) {
  std::string xml = test::kTestArmXml;
  const auto p = xml.find("<geom name=\"floor\"");
  xml.erase(p, xml.find("/>", p) + 2 - p);
  const ArmState arm(Simulator::from_xml_string(xml));
  OffscreenRenderer r(arm.sim.model(), kWidth, kHeight);
  r.pose(*arm.d);
  // the floor fills the bottom row (the camera looks down on it)
  const std::vector<std::uint8_t> rgb = frame(r, arm.overview());
  const std::size_t bottom = static_cast<std::size_t>((kHeight - 1) * kWidth + kWidth / 2) * 3;
  EXPECT_GT(rgb[bottom] + rgb[bottom + 1] + rgb[bottom + 2], 60);
}

TEST(OffscreenRenderer, SizesBeyondTheModelsBufferWorkAndBeyondTheGlLimitAreAClearError) {
  // 800x600 exceeds the test model's 640x480 off-screen buffer: the renderer's copy is enlarged
  const ArmState arm;
  OffscreenRenderer large(arm.sim.model(), 800, 600);
  large.pose(*arm.d);
  EXPECT_GT(variance(frame(large, arm.overview())), kMinVariance);
  try {
    OffscreenRenderer renderer(arm.sim.model(), 40000, 8);
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("40000x8 exceeds"), std::string::npos) << e.what();
  }
  // the failed renderer left nothing behind that breaks the next one
  OffscreenRenderer small(arm.sim.model(), 64, 48);
  small.pose(*arm.d);
  EXPECT_EQ(frame(small, arm.overview()).size(), 64u * 48u * 3u);
}

TEST(OffscreenRenderer, BadSizesAndFontScalesAreRejected) {
  const ArmState arm;
  EXPECT_THROW(OffscreenRenderer(arm.sim.model(), 0, 10), std::invalid_argument);
  EXPECT_THROW(OffscreenRenderer(arm.sim.model(), 10, 10, {.shadows = false, .samples = -1}), std::invalid_argument);
  EXPECT_THROW(OffscreenRenderer(arm.sim.model(), 10, 10, {}, 120), std::invalid_argument);
}

TEST(OffscreenRenderer, ModelCameraIsNamedOrAbsent) {
  const ArmState arm;
  EXPECT_FALSE(model_camera(arm.sim.model(), *arm.d, "no_such_camera"));
  const CameraPose c = arm.overview();
  EXPECT_NEAR(c.forward.norm(), 1, 1e-9);
  EXPECT_NEAR(c.forward.dot(c.up), 0, 1e-9);
  EXPECT_NEAR(c.fovy_deg, 45, 1e-9);  // MuJoCo's default
}

// Douglas-Peucker on random wiggly polylines: ends kept, indices ascending, every dropped point
// within the tolerance of the kept polyline.
TEST(Simplify, KeepsEveryDroppedPointWithinTheTolerance) {
  const int cases = test::property_cases(200);
  for (int k = 0; k < cases; ++k) {
    const auto seed = static_cast<std::uint64_t>(k) + 1;
    auto rng = test::make_rng(seed);
    std::vector<Vec3> points;
    Vec3 p = Vec3::Zero();
    const int n = static_cast<int>(test::uniform(rng, 0, 400));
    for (int i = 0; i < n; ++i) {
      p += Vec3(test::uniform(rng, 0, 1e-3), test::uniform(rng, -1e-3, 1e-3), test::uniform(rng, -2e-4, 2e-4));
      points.push_back(p);
    }
    const double tolerance = test::log_uniform(rng, 1e-6, 1e-3);
    const std::vector<std::size_t> kept = simplify(points, tolerance);
    if (points.empty()) {
      EXPECT_TRUE(kept.empty());
      continue;
    }
    ASSERT_EQ(kept.front(), 0u) << test::seed_text(seed);
    ASSERT_EQ(kept.back(), points.size() - 1) << test::seed_text(seed);
    for (std::size_t j = 1; j < kept.size(); ++j) {
      ASSERT_LT(kept[j - 1], kept[j]) << test::seed_text(seed);
      const Vec3 a = points[kept[j - 1]], d = points[kept[j]] - a;
      for (std::size_t i = kept[j - 1] + 1; i < kept[j]; ++i) {
        const double t = std::clamp((points[i] - a).dot(d) / d.squaredNorm(), 0.0, 1.0);
        EXPECT_LE((points[i] - a - t * d).norm(), tolerance * (1 + 1e-9)) << test::seed_text(seed);
      }
    }
  }
}

}  // namespace
}  // namespace blendbench
