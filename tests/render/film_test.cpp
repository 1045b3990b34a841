#include "blendbench/render/film.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>

#include "support/property.hpp"
#include "blendbench/sim/simulator.hpp"

namespace blendbench {
namespace {

// A pixel has a colour when every channel is within this of it (lines and bars keep their exact
// colour in their cores).
constexpr int kColourTolerance = 3;
// The framing test draws the path this wide (its core keeps the exact colour), so its pixel box
// is wider than its projection by up to the width and a pixel of rounding on each side.
constexpr double kTestLineWidth = 3;
constexpr double kLinePixels = kTestLineWidth + 2;

// The arm of the videos at keyframe "ready", and its nq.
struct Arm {
  Arm() : sim(test::source_path("models/ur5e_like.xml")) {
    const int key = mj_name2id(&sim.model(), mjOBJ_KEY, "ready");
    ready.assign(sim.model().key_qpos + key * sim.model().nq, sim.model().key_qpos + (key + 1) * sim.model().nq);
  }
  Simulator sim;
  std::vector<double> ready;
};

const Arm& arm() {
  static const Arm a;
  return a;
}

// A closed rectangle of a x b (m) about `centre` in the plane of u, v, sampled every mm.
std::vector<Vec3> rectangle(const Vec3& centre, const Vec3& u, const Vec3& v, double a, double b) {
  const Vec3 c[5] = {centre - 0.5 * a * u - 0.5 * b * v, centre + 0.5 * a * u - 0.5 * b * v, centre + 0.5 * a * u + 0.5 * b * v,
                     centre - 0.5 * a * u + 0.5 * b * v, centre - 0.5 * a * u - 0.5 * b * v};
  std::vector<Vec3> points;
  for (int e = 0; e < 4; ++e) {
    const int n = static_cast<int>(std::ceil((c[e + 1] - c[e]).norm() / 1e-3));
    for (int i = 0; i < n; ++i) points.push_back(c[e] + (c[e + 1] - c[e]) * (static_cast<double>(i) / n));
  }
  points.push_back(c[4]);
  return points;
}

// The part of the default scenario's size, in front of the arm.
std::vector<Vec3> floor_part() { return rectangle(Vec3(0.46, 0, 0.2), Vec3::UnitX(), Vec3::UnitY(), 0.12, 0.36); }

// A film of the arm standing at "ready" while its TCP runs once round `path` in `duration` s.
VariantFilm film_along(const std::string& name, const std::vector<Vec3>& path, double duration, std::optional<double> done,
                       const std::string& method = "arc") {
  VariantFilm f;
  f.name = name;
  f.method = method;
  f.planned = path;
  f.pose_rate_hz = 30.0 * CompareVideo::kSlowMotion;
  const int poses = static_cast<int>(duration * f.pose_rate_hz) + 1;
  for (int k = 0; k < poses; ++k) f.qpos.insert(f.qpos.end(), arm().ready.begin(), arm().ready.end());
  f.sample_period = 2e-3;
  const int samples = static_cast<int>(duration / f.sample_period) + 1;
  for (int i = 0; i < samples; ++i) {
    const auto at = static_cast<std::size_t>(static_cast<double>(i) / (samples - 1) * static_cast<double>(path.size() - 1));
    f.tcp.push_back(path[at]);
    f.speed.push_back(0.25);
    f.tracking_error.push_back(40e-6);
    f.contour_error.push_back(10e-6);
  }
  f.reference_end = 0.8 * duration;
  f.done_time = done;
  return f;
}

FilmSettings settings_for(const std::vector<Vec3>& programmed, int width, int height) {
  FilmSettings s;
  s.width = width;
  s.height = height;
  s.fps = 30;
  s.scenario = "test";
  s.programmed = programmed;
  return s;
}

struct Box {
  int count = 0, u0 = 1 << 30, u1 = -1, v0 = 1 << 30, v1 = -1;
};

// Pixels of a colour inside a region of the frame: their count and bounding box.
Box find(const std::vector<std::uint8_t>& rgb, int width, const Rgba& colour, const PixelRect& region) {
  const int want[3] = {static_cast<int>(std::lround(colour.r * 255)), static_cast<int>(std::lround(colour.g * 255)),
                       static_cast<int>(std::lround(colour.b * 255))};
  Box box;
  for (int v = region.top; v < region.top + region.height; ++v) {
    for (int u = region.left; u < region.left + region.width; ++u) {
      const auto i = static_cast<std::size_t>(v * width + u) * 3;
      bool match = true;
      for (std::size_t c = 0; c < 3; ++c) match = match && std::abs(int{rgb[i + c]} - want[c]) <= kColourTolerance;
      if (!match) continue;
      ++box.count;
      box.u0 = std::min(box.u0, u);
      box.u1 = std::max(box.u1, u);
      box.v0 = std::min(box.v0, v);
      box.v1 = std::max(box.v1, v);
    }
  }
  return box;
}

// Pixels in a region for which `match(r, g, b)` holds.
template <class Match>
int count(const std::vector<std::uint8_t>& rgb, int width, const PixelRect& region, Match match) {
  int n = 0;
  for (int v = region.top; v < region.top + region.height; ++v) {
    for (int u = region.left; u < region.left + region.width; ++u) {
      const auto i = static_cast<std::size_t>(v * width + u) * 3;
      n += match(int{rgb[i]}, int{rgb[i + 1]}, int{rgb[i + 2]}) ? 1 : 0;
    }
  }
  return n;
}

// The framing rule, measured: render the programmed path alone through the part camera, find
// its blue pixels, and compare their box with the frame.
void expect_framed(const std::vector<Vec3>& path, int width, int height, double fill) {
  OffscreenRenderer r(arm().sim.model(), width, height);
  r.pose(arm().ready);
  PartFraming framing;
  framing.fill = fill;
  const CameraPose camera = frame_part(path, Vec3::Zero(), static_cast<double>(width) / height, framing);
  const Polyline line{path, std::nullopt, kProgrammedColour, kTestLineWidth};
  r.draw_scene({0, 0, width, height}, camera, {&line, 1});
  const Box blue = find(r.read(), width, kProgrammedColour, {0, 0, width, height});
  ASSERT_GT(blue.count, 50) << width << "x" << height;
  const double share = std::max(static_cast<double>(blue.u1 - blue.u0 + 1) / width, static_cast<double>(blue.v1 - blue.v0 + 1) / height);
  EXPECT_NEAR(share, fill, kLinePixels / std::min(width, height)) << width << "x" << height;
  // centred, and the smaller frame dimension spanned at least `fill`
  EXPECT_NEAR(0.5 * (blue.u0 + blue.u1), 0.5 * width, kLinePixels) << width << "x" << height;
  EXPECT_NEAR(0.5 * (blue.v0 + blue.v1), 0.5 * height, kLinePixels) << width << "x" << height;
  EXPECT_GE(std::max(blue.u1 - blue.u0 + 1, blue.v1 - blue.v0 + 1) + kLinePixels, fill * std::min(width, height));
}

TEST(Framing, ThePathsPixelsFillTheStatedShareOfTheFrame) {
  expect_framed(floor_part(), 640, 480, 0.6);
  // a wall facing the robot, at 1280x720
  expect_framed(rectangle(Vec3(0.55, 0.1, 0.35), Vec3::UnitY(), Vec3::UnitZ(), 0.3, 0.15), 1280, 720, 0.6);
  // a small part (4 cm, the distance shortened to keep the view wide enough), filling more
  expect_framed(rectangle(Vec3(0.4, -0.1, 0.1), Vec3::UnitX(), Vec3::UnitY(), 0.04, 0.03), 320, 240, 0.8);
}

TEST(VariantVideo, AFrameHasTheLegendTheOverlayAndLaterTheDoneLabel) {
  const std::vector<Vec3> path = floor_part();
  const VariantFilm film = film_along("arc_5mm", path, 2, 1.5);
  const FilmSettings settings = settings_for(path, 640, 480);
  VariantVideo video(arm().sim.model(), film, settings);
  EXPECT_EQ(video.frames(), 61);  // 2 s at 30 fps, both ends
  const std::vector<std::uint8_t> first = video.frame(0);
  const std::vector<std::uint8_t> second = video.frame(30);

  // the legend, bottom left: a bar of each colour (the path lies in the middle 60 %, above it)
  const PixelRect legend{0, 395, 200, 85};
  for (const Rgba& c : {kProgrammedColour, method_colour("arc"), kTrailColour}) EXPECT_GT(find(first, 640, c, legend).count, 40);
  // the overlay, top left: white text on a dark box, and it changes with the time shown
  const PixelRect panel{0, 0, 220, 105};
  const auto white = [](int r, int g, int b) { return r > 200 && g > 200 && b > 200; };
  EXPECT_GT(count(first, 640, panel, white), 150);
  EXPECT_GT(count(first, 640, panel, [](int r, int g, int b) { return r + g + b < 420; }), 10000);
  int changed = 0;
  for (int v = 0; v < 30; ++v)
    for (int u = 0; u < 220; ++u) {
      const auto i = static_cast<std::size_t>(v * 640 + u) * 3;
      changed += first[i] != second[i] ? 1 : 0;
    }
  EXPECT_GT(changed, 10) << "the time in the panel should change";
  // the trail: green pixels outside the legend only once the TCP has moved
  const PixelRect scene{200, 100, 440, 290};
  EXPECT_EQ(find(first, 640, kTrailColour, scene).count, 0);
  EXPECT_GT(find(second, 640, kTrailColour, scene).count, 100);
  // after done_time the label "done at t = ..." (green) shows along the bottom
  const PixelRect bottom{213, 420, 427, 60};
  const auto label_green = [](int r, int g, int b) { return g > r + 40 && g > b + 20 && g < 160; };
  EXPECT_LT(count(first, 640, bottom, label_green), 20);
  EXPECT_GT(count(video.frame(55), 640, bottom, label_green), 1000);
}

bool intersect(const PixelRect& a, const Box& b) {
  return b.count > 0 && a.left <= b.u1 && b.u0 < a.left + a.width && a.top <= b.v1 && b.v0 < a.top + a.height;
}

// Pixels of a line under an overlay's box: the box is black at render's alpha 0.55 over the
// frame, so a line it covers shows as 0.45 of the line's colour.
int hidden(const std::vector<std::uint8_t>& rgb, int width, const PixelRect& box, const Rgba& colour) {
  constexpr float kBehindPanel = 0.45f;
  return find(rgb, width, {colour.r * kBehindPanel, colour.g * kBehindPanel, colour.b * kBehindPanel, 1}, box).count;
}

// The overlays give way to the path: a fixed camera puts a part in the top left of the view,
// where the panel used to be drawn; the panel and the legend go where the path is not. The path's
// box is measured independently of the placement: its lines rendered alone through the frame's
// camera, their pixels found by colour.
TEST(VariantVideo, ThePanelAndTheLegendDoNotCoverThePath) {
  const Vec3 centre(0.46, 0, 0.2);
  const std::vector<Vec3> path = rectangle(centre, Vec3::UnitX(), Vec3::UnitY(), 0.3, 0.3);
  const VariantFilm film = film_along("clothoid_0.1mm", path, 1, 0.8, "clothoid");
  FilmSettings settings = settings_for(path, 640, 480);
  // aimed below right of the part, so the part lands near pixel (130, 110)
  const Vec3 eye(1.5, -1.0, 1.1);
  const CameraPose straight = look_at(eye, centre, 45);
  const double pixel = pixel_size(straight, (centre - eye).dot(straight.forward), 480);
  settings.camera.mode = CameraSpec::Mode::kFixed;
  settings.camera.position = eye;
  settings.camera.look_at = centre + 190 * pixel * straight.right() - 210 * pixel * straight.up;
  VariantVideo video(arm().sim.model(), film, settings);
  for (const int k : {0, 15, 29}) {
    const std::vector<std::uint8_t> frame = video.frame(k);
    const OverlayBoxes boxes = video.overlays();
    OffscreenRenderer alone(arm().sim.model(), 640, 480);
    alone.pose(arm().ready);
    const std::array<Polyline, 2> lines = {Polyline{path, std::nullopt, kProgrammedColour, 8},
                                           Polyline{film.planned, std::nullopt, method_colour("clothoid"), 5}};
    alone.draw_scene({0, 0, 640, 480}, video.camera(k), lines);
    const std::vector<std::uint8_t> rgb = alone.read();
    Box box = find(rgb, 640, kProgrammedColour, {0, 0, 640, 480});
    const Box planned = find(rgb, 640, method_colour("clothoid"), {0, 0, 640, 480});
    box = {box.count + planned.count, std::min(box.u0, planned.u0), std::max(box.u1, planned.u1), std::min(box.v0, planned.v0),
           std::max(box.v1, planned.v1)};
    ASSERT_GT(box.count, 500) << k;
    // the test's premise: the path covers where the panel was drawn before (the top left)
    ASSERT_TRUE(intersect({5, 5, boxes.panel.width, boxes.panel.height}, box)) << k << ": path box " << box.u0 << ".." << box.u1
                                                                                 << " x " << box.v0 << ".." << box.v1;
    EXPECT_FALSE(intersect(boxes.panel, box)) << k << ": panel at " << boxes.panel.left << "," << boxes.panel.top;
    // in the frame itself: no line darkened under either box, and the lines in the clear where
    // the panel used to be
    for (const Rgba& c : {kProgrammedColour, method_colour("clothoid")}) {
      EXPECT_EQ(hidden(frame, 640, boxes.panel, c), 0) << k;
      EXPECT_EQ(hidden(frame, 640, boxes.legend, c), 0) << k;
    }
    EXPECT_GT(find(frame, 640, method_colour("clothoid"), {5, 5, boxes.panel.width, boxes.panel.height}).count, 20) << k;
    EXPECT_FALSE(intersect(boxes.legend, box)) << k << ": legend at " << boxes.legend.left << "," << boxes.legend.top;
    // both drawn, in different places, inside the frame
    EXPECT_GT(boxes.panel.width * boxes.panel.height, 0);
    EXPECT_GT(boxes.legend.width * boxes.legend.height, 0);
    EXPECT_TRUE(boxes.panel.left >= boxes.legend.left + boxes.legend.width || boxes.legend.left >= boxes.panel.left + boxes.panel.width ||
                boxes.panel.top >= boxes.legend.top + boxes.legend.height || boxes.legend.top >= boxes.panel.top + boxes.panel.height);
    // the method's colour is in the frame: the path, and the legend's bar
    EXPECT_GT(find(frame, 640, method_colour("clothoid"), {0, 0, 640, 480}).count, 300) << k;
    EXPECT_GT(find(frame, 640, method_colour("clothoid"), boxes.legend).count, 20) << k;
  }
}

TEST(VariantVideo, FixedAndTcpCamerasLookWhereTheyAreTold) {
  const std::vector<Vec3> path = floor_part();
  const VariantFilm film = film_along("v", path, 1, 1);
  FilmSettings settings = settings_for(path, 320, 240);
  settings.camera.mode = CameraSpec::Mode::kFixed;
  settings.camera.position = Vec3(1.2, -0.8, 0.9);
  settings.camera.look_at = Vec3(0.4, 0, 0.2);
  const CameraPose fixed = VariantVideo(arm().sim.model(), film, settings).camera(10);
  EXPECT_TRUE(fixed.eye.isApprox(settings.camera.position));
  const Projection aim = project(fixed, settings.camera.look_at, 320, 240);
  EXPECT_NEAR(aim.u, 160, 1e-6);
  EXPECT_NEAR(aim.v, 120, 1e-6);

  settings.camera.mode = CameraSpec::Mode::kTcp;
  settings.camera.distance = 0.3;
  const VariantVideo video(arm().sim.model(), film, settings);
  for (const int k : {0, 10, 25}) {
    const CameraPose c = video.camera(k);
    const Vec3 tcp = film.tcp[static_cast<std::size_t>(std::lround(k / 30.0 / film.sample_period))];
    const Projection q = project(c, tcp, 320, 240);
    EXPECT_NEAR(q.u, 160, 1e-6) << k;
    EXPECT_NEAR(q.v, 120, 1e-6) << k;
    EXPECT_NEAR((c.eye - tcp).norm(), 0.3, 1e-9) << k;
  }
}

TEST(VariantVideo, AFilmWithoutPosesIsRefused) {
  VariantFilm film;
  film.name = "failed";
  EXPECT_THROW(VariantVideo(arm().sim.model(), film, settings_for(floor_part(), 64, 64)), std::invalid_argument);
}

TEST(CompareLayout, CellsCoverTheVariantsFitFullHdAndKeepTheirAspect) {
  for (const auto& [w, h] : {std::pair{640, 480}, std::pair{320, 240}, std::pair{1280, 720}, std::pair{1920, 1080}}) {
    for (int n = 1; n <= 12; ++n) {
      const CompareLayout l = compare_layout(n, w, h);
      EXPECT_GE(l.columns * l.rows, n);
      EXPECT_LT((l.rows - 1) * l.columns, n) << "no empty row";
      EXPECT_EQ(l.columns, n <= 3 ? n : static_cast<int>(std::ceil(std::sqrt(n))));
      EXPECT_LE(l.width, 1920);
      EXPECT_LE(l.height, 1080);
      EXPECT_LE(l.cell_width, w);
      EXPECT_EQ(l.cell_width % 2, 0);
      EXPECT_EQ(l.cell_height % 2, 0);
      EXPECT_EQ(l.header % 2, 0);
      EXPECT_NEAR(static_cast<double>(l.cell_width) / l.cell_height, static_cast<double>(w) / h, 0.02);
      EXPECT_EQ(l.height, l.header + l.rows * l.cell_height);
      const PixelRect last = l.cell(n - 1);
      EXPECT_LE(last.left + last.width, l.width);
      EXPECT_LE(last.top + last.height, l.height);
    }
  }
  // the tiny scenario's comparison: two 320x240 cells below a 52-pixel header
  const CompareLayout tiny = compare_layout(2, 320, 240);
  EXPECT_EQ(tiny.width, 640);
  EXPECT_EQ(tiny.height, 292);
}

// Two films with one corner each; the second's contour error there is larger.
std::vector<VariantFilm> two_films_with_a_corner() {
  const std::vector<Vec3> path = floor_part();
  std::vector<VariantFilm> films = {film_along("exact", path, 2, 1.8, "none"), film_along("blend", path, 1.6, 1.3, "bezier")};
  films[0].corners = {{2, 0.50, 0.60}};
  films[1].corners = {{2, 0.40, 0.45}};
  films[1].contour_error[static_cast<std::size_t>(0.42 / 2e-3)] = 1.5e-3;
  films[0].contour_error[static_cast<std::size_t>(1.0 / 2e-3)] = 5e-3;  // far from any corner: not counted
  return films;
}

// The comparison's cells place their panels as the variant video does: a fixed camera puts the
// part in the top left of every cell, where the panel used to be; no cell's panel darkens a line,
// and the lines are in the clear where the panel was.
TEST(CompareVideo, CellPanelsDoNotCoverThePath) {
  const Vec3 centre(0.46, 0, 0.2);
  const std::vector<Vec3> path = rectangle(centre, Vec3::UnitX(), Vec3::UnitY(), 0.3, 0.3);
  const std::vector<VariantFilm> films = {film_along("arc_0.1mm", path, 1, 0.8, "arc"), film_along("bezier_0.1mm", path, 1, 0.9, "bezier")};
  FilmSettings settings = settings_for(path, 320, 240);
  const Vec3 eye(1.5, -1.0, 1.1);
  const CameraPose straight = look_at(eye, centre, 45);
  const double pixel = pixel_size(straight, (centre - eye).dot(straight.forward), 240);
  settings.camera.mode = CameraSpec::Mode::kFixed;
  settings.camera.position = eye;
  settings.camera.look_at = centre + 80 * pixel * straight.right() - 70 * pixel * straight.up;
  CompareVideo video(arm().sim.model(), films, settings);
  const CompareLayout& l = video.layout();
  for (const int k : {0, 20}) {
    const std::vector<std::uint8_t> frame = video.frame(k);
    for (int i = 0; i < 2; ++i) {
      const Rgba colour = method_colour(films[static_cast<std::size_t>(i)].method);
      const PixelRect cell = l.cell(i), panel = video.overlays(i).panel;
      ASSERT_GT(panel.width * panel.height, 0);
      EXPECT_GT(find(frame, l.width, colour, {cell.left + 5, cell.top + 5, panel.width, panel.height}).count, 20)
          << k << " " << i << ": the premise, the path where the panel used to be";
      EXPECT_EQ(hidden(frame, l.width, panel, colour), 0) << k << " " << i << ": panel at " << panel.left << "," << panel.top;
      EXPECT_EQ(hidden(frame, l.width, panel, kProgrammedColour), 0) << k << " " << i;
    }
  }
}

TEST(CompareVideo, WorstCornerIsTheLargestContourErrorNearACorner) {
  const std::vector<VariantFilm> films = two_films_with_a_corner();
  const std::vector<CornerPlacement> corners = {{2, Vec3(0.52, 0.18, 0.2), 0.1, 0.09, 0.11}};
  const WorstCorner worst = worst_corner(films, corners);
  EXPECT_EQ(worst.index, 2);
  EXPECT_NEAR(worst.contour_error, 1.5e-3, 1e-12);
  EXPECT_TRUE(worst.point.isApprox(corners[0].point));
  EXPECT_EQ(worst_corner(films, {}).index, -1) << "a corner without a placement is no corner to show";
}

TEST(CompareVideo, GridHoldsEveryVariantThenZoomsOnTheWorstCorner) {
  std::vector<VariantFilm> films = two_films_with_a_corner();
  VariantFilm failed;
  failed.name = "broken";
  failed.failure = "planning_failed: no room";
  films.push_back(failed);
  FilmSettings settings = settings_for(floor_part(), 320, 240);
  settings.corners = {{2, Vec3(0.52, 0.18, 0.2), 0.1, 0.09, 0.11}};
  CompareVideo video(arm().sim.model(), films, settings);
  const CompareLayout& l = video.layout();
  EXPECT_EQ(l.columns, 3);
  EXPECT_EQ(l.rows, 1);
  // synchronised until the last is done (1.8 s) and half a second more, clamped to the longest
  // recording (2 s): 61 frames; then the zoom, 2 x (0.05 + 0.25) s four times slower at 30 fps
  EXPECT_EQ(video.synchronised_frames(), 61);
  EXPECT_EQ(video.frames() - video.synchronised_frames(), 73);
  EXPECT_EQ(video.corner().index, 2);

  const std::vector<std::uint8_t> frame = video.frame(50);  // t = 1.67 s: blend done, exact not yet
  // the header: dark, with white text
  EXPECT_GT(count(frame, l.width, {0, 0, l.width, l.header}, [](int r, int g, int b) { return r + g + b < 150; }),
            l.width * l.header / 2);
  EXPECT_GT(count(frame, l.width, {0, 0, l.width, l.header}, [](int r, int g, int b) { return r > 200 && g > 200 && b > 200; }), 100);
  // "done at" in the blend's cell only; the failed cell's red label
  const auto label_green = [](int r, int g, int b) { return g > r + 40 && g > b + 20 && g < 160; };
  const auto bottom = [&](int i) {
    const PixelRect c = l.cell(i);
    return PixelRect{c.left, c.top + c.height - 50, c.width, 50};
  };
  EXPECT_LT(count(frame, l.width, bottom(0), label_green), 20);
  EXPECT_GT(count(frame, l.width, bottom(1), label_green), 500);
  EXPECT_GT(count(frame, l.width, l.cell(2), [](int r, int g, int b) { return r > 90 && r < 130 && g < 40 && b < 40; }), 1000);
  // each cell's planned path in its method's colour (bezier's green only in the bezier cell: the
  // exact stop's grey also shades the arm); both colours in the header's legend
  for (int i = 0; i < 2; ++i) {
    const Rgba colour = method_colour(films[static_cast<std::size_t>(i)].method);
    EXPECT_GT(find(frame, l.width, colour, l.cell(i)).count, 50) << i;
    EXPECT_GT(find(frame, l.width, colour, {0, 0, l.width, l.header}).count, 20) << i;
  }
  EXPECT_EQ(find(frame, l.width, method_colour("bezier"), l.cell(0)).count, 0);
  // no cell's panel over its lines (the exact stop's grey is left out: the arm's shading takes it
  // too), here and in the zoom below
  const auto expect_panels_clear = [&](const std::vector<std::uint8_t>& rgb, const std::string& when) {
    for (int i = 0; i < 2; ++i) {
      const PixelRect panel = video.overlays(i).panel;
      EXPECT_GT(panel.width * panel.height, 0) << when << " " << i;
      EXPECT_EQ(hidden(rgb, l.width, panel, kProgrammedColour), 0) << when << " " << i;
      EXPECT_EQ(hidden(rgb, l.width, panel, method_colour("bezier")), 0) << when << " " << i;
    }
  };
  expect_panels_clear(frame, "synchronised");
  // the zoom: the path's corner, magnified: it lies in the middle of the cell and its edges run
  // from there out of the cell (in the overview the whole part spans 60 % of the cell), in both
  // cells with motion
  const std::vector<std::uint8_t> zoom = video.frame(video.synchronised_frames() + 36);
  expect_panels_clear(zoom, "zoom");
  for (int i = 0; i < 2; ++i) {
    const PixelRect cell = l.cell(i);
    Box all;
    for (const Rgba& c : {kProgrammedColour, method_colour(films[static_cast<std::size_t>(i)].method), kTrailColour}) {
      const Box b = find(zoom, l.width, c, cell);
      all.count += b.count;
      all.u0 = std::min(all.u0, b.u0);
      all.u1 = std::max(all.u1, b.u1);
      all.v0 = std::min(all.v0, b.v0);
      all.v1 = std::max(all.v1, b.v1);
    }
    EXPECT_GT(all.count, 200) << i;
    const int uc = cell.left + cell.width / 2, vc = cell.top + cell.height / 2;
    EXPECT_GT(find(zoom, l.width, kProgrammedColour, {uc - 6, vc - 6, 12, 12}).count, 0) << i << ": the corner is centred";
    const bool leaves = all.u0 <= cell.left + 1 || all.u1 >= cell.left + cell.width - 2 || all.v0 <= cell.top + 1 ||
                        all.v1 >= cell.top + cell.height - 2;
    EXPECT_TRUE(leaves) << i << ": the edges run out of the cell";
  }
}

}  // namespace
}  // namespace blendbench
