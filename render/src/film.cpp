#include "blendbench/render/film.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>
#include <stdexcept>

#include "blendbench/core/units.hpp"
#include "blendbench/render/video.hpp"

namespace blendbench {
namespace {

constexpr double kUm = 1e-6;  // m; the overlays write the servo's errors in micrometres (docs/units.md)
constexpr const char* kUmText = " \u00b5m";  // render draws the micro sign (OffscreenRenderer::draw_text)
// Lines at a view 480 pixels tall (scaled with the view's height): drawn in this order, each
// narrower than the one before, so that where they coincide all three show.
constexpr double kReferenceHeight = 480;
constexpr double kProgrammedWidth = 8, kPlannedWidth = 5, kTrailWidth = 2;  // pixels
constexpr double kTcpRadius = 5;                                                 // pixels
// Small views keep lines this much of their reference width, to stay visible.
constexpr double kMinLineScale = 0.7;
// The TCP: a white disc (with render's dark rim), unlike any method's colour.
constexpr Rgba kTcpColour{1, 1, 1, 1};
// Polylines are simplified to this share of a pixel at the view's target.
constexpr double kSimplifyPixels = 0.25;
// The comparison: a held end after the last variant is done, the largest frame, the zoom's half
// height per contour error (so the error spans an eighth of the view) and at least, and how long
// before and after its transition a corner is shown.
constexpr double kHoldAfterDone = 0.5;  // s
constexpr int kMaxWidth = 1920, kMaxHeight = 1080;
constexpr double kZoomPerError = 4;
constexpr double kMinZoomHalf = 3e-3;  // m
constexpr double kZoomMargin = 0.25;   // s
constexpr Rgba kHeaderColour{0.12f, 0.13f, 0.15f, 1};
constexpr Rgba kDoneColour{0.05f, 0.45f, 0.25f, 0.85f};
constexpr Rgba kNotSettledColour{0.7f, 0.4f, 0.0f, 0.85f};
constexpr Rgba kFailedColour{0.45f, 0.1f, 0.1f, 1};
constexpr Rgba kWhite{1, 1, 1, 1};
constexpr int kPad = 6;  // pixels

// The legend of one variant: the three lines (the planned one in its method's colour), and the
// tool where one is drawn.
std::vector<LegendEntry> legend(const FilmSettings& s, const VariantFilm& film) {
  std::vector<LegendEntry> entries = {{kProgrammedColour, "programmed path"},
                                      {method_colour(film.method), film.method.empty() ? "planned path" : "planned path (" + film.method + ")"},
                                      {kTrailColour, "actual TCP trail"}};
  if (s.tool) {
    entries.push_back({kToolColour, "tool"});
    entries.push_back({kToolAxisColour, "tool z axis"});
  }
  return entries;
}

// The legend of a comparison: the programmed path, each method's colour once (in the order the
// variants come), the actual trail; `brief` with shorter words for a narrow header.
std::vector<LegendEntry> compare_legend(const FilmSettings& s, const std::vector<VariantFilm>& films, bool brief) {
  std::vector<LegendEntry> entries = {{kProgrammedColour, brief ? "programmed" : "programmed path"}};
  std::vector<std::string> methods;
  for (const VariantFilm& f : films) {
    if (std::find(methods.begin(), methods.end(), f.method) != methods.end()) continue;
    methods.push_back(f.method);
    entries.push_back({method_colour(f.method), f.method.empty() ? "planned" : f.method});
  }
  entries.push_back({kTrailColour, brief ? "actual" : "actual TCP trail"});
  if (s.tool) {
    entries.push_back({kToolColour, "tool"});
    entries.push_back({kToolAxisColour, brief ? "tool z" : "tool z axis"});
  }
  return entries;
}

std::string fixed(double value, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  return buffer;
}

std::string ordinal(int n) {
  const int tens = n % 100;
  const char* suffix = tens >= 11 && tens <= 13 ? "th" : n % 10 == 1 ? "st" : n % 10 == 2 ? "nd" : n % 10 == 3 ? "rd" : "th";
  return std::to_string(n) + suffix;
}

int poses(const VariantFilm& film, int nq) { return nq > 0 ? static_cast<int>(film.qpos.size()) / nq : 0; }

double end_time(const VariantFilm& film, int nq) {
  return film.pose_rate_hz > 0 ? std::max(0, poses(film, nq) - 1) / film.pose_rate_hz : 0.0;
}

// The trace sample of time t (clamped to the recording).
std::size_t sample_at(const VariantFilm& film, double t) {
  if (film.tcp.empty() || !(film.sample_period > 0)) return 0;
  const double i = std::round(std::max(0.0, t) / film.sample_period);
  return std::min(film.tcp.size() - 1, static_cast<std::size_t>(i));
}

double value_at(const std::vector<double>& values, std::size_t i) { return i < values.size() ? values[i] : 0.0; }

// The programmed and planned paths and the trail, simplified for one scale of view; the trail
// keeps the trace index of each point it keeps.
struct ViewLines {
  std::vector<Vec3> programmed, planned, trail;
  std::vector<std::size_t> trail_index;
};

std::vector<Vec3> simplified(const std::vector<Vec3>& points, double tolerance) {
  std::vector<Vec3> out;
  for (const std::size_t i : simplify(points, tolerance)) out.push_back(points[i]);
  return out;
}

ViewLines view_lines(const std::vector<Vec3>& programmed, const VariantFilm& film, double tolerance) {
  ViewLines lines;
  lines.programmed = simplified(programmed, tolerance);
  lines.planned = simplified(film.planned, tolerance);
  lines.trail_index = simplify(film.tcp, tolerance);
  for (const std::size_t i : lines.trail_index) lines.trail.push_back(film.tcp[i]);
  return lines;
}

// Half a pixel's world size at the camera's target (a view `height` pixels tall, looking at
// `target`).
double tolerance_for(const CameraPose& camera, const Vec3& target, int height) {
  const double depth = std::max(1e-3, (target - camera.eye).dot(camera.forward));
  return kSimplifyPixels * pixel_size(camera, depth, height);
}

Vec3 centre_of(const std::vector<Vec3>& points) {
  if (points.empty()) return Vec3::Zero();
  Vec3 lo = points.front(), hi = points.front();
  for (const Vec3& p : points) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return 0.5 * (lo + hi);
}

// The camera of the settings' mode before any TCP is known (kTcp: the part camera).
CameraPose static_camera(const FilmSettings& s, double aspect) {
  if (s.camera.mode == CameraSpec::Mode::kFixed) return look_at(s.camera.position, s.camera.look_at, s.camera.fovy_deg);
  return frame_part(s.programmed, s.base, aspect, s.camera.part);
}

// The camera of a view at an instant: the static one, or following the TCP.
CameraPose camera_at(const FilmSettings& s, const CameraPose& fixed_camera, const Vec3& tcp) {
  if (s.camera.mode != CameraSpec::Mode::kTcp) return fixed_camera;
  const ViewAngles view = default_view(s.programmed, s.base);
  return orbit_camera(tcp, s.camera.part.azimuth_deg.value_or(view.azimuth_deg),
                      s.camera.part.elevation_deg.value_or(view.elevation_deg), s.camera.distance, s.camera.fovy_deg);
}

// Draws one variant at time t into `rect`: the arm in its pose, the three lines, the TCP.
void draw_view(OffscreenRenderer& renderer, const PixelRect& rect, const CameraPose& camera, const ViewLines& lines,
               const VariantFilm& film, double t, int nq, SceneStyle style) {
  const int pose = std::clamp(static_cast<int>(std::lround(t * film.pose_rate_hz)), 0, poses(film, nq) - 1);
  renderer.pose(std::span<const double>(film.qpos.data() + static_cast<std::ptrdiff_t>(pose) * nq, static_cast<std::size_t>(nq)));
  const double scale = std::max(kMinLineScale, rect.height / kReferenceHeight);
  std::array<Polyline, 3> polylines{};
  polylines[0] = {lines.programmed, std::nullopt, kProgrammedColour, std::max(1.0, kProgrammedWidth * scale)};
  polylines[1] = {lines.planned, std::nullopt, method_colour(film.method), std::max(1.0, kPlannedWidth * scale)};
  std::array<Marker, 1> tcp{};
  std::size_t markers = 0;
  if (!film.tcp.empty()) {
    // the trail: the kept points before the current sample, then the current TCP
    const std::size_t k = sample_at(film, t);
    const auto before = static_cast<std::size_t>(
        std::lower_bound(lines.trail_index.begin(), lines.trail_index.end(), k) - lines.trail_index.begin());
    polylines[2] = {std::span<const Vec3>(lines.trail.data(), before), film.tcp[k], kTrailColour,
                    std::max(1.0, kTrailWidth * scale)};
    tcp[0] = {film.tcp[k], kTcpColour, std::max(2.0, kTcpRadius * scale)};
    markers = 1;
  }
  renderer.draw_scene(rect, camera, polylines, std::span<const Marker>(tcp.data(), markers), style);
}

// A label along the bottom of `rect`, centred.
void bottom_label(OffscreenRenderer& renderer, const PixelRect& rect, const std::string& text, const Rgba& colour) {
  const int w = std::min(rect.width - 2 * kPad, renderer.text_width(text) + 4 * kPad);
  const int h = renderer.text_height() + 2 * kPad;
  renderer.draw_label({rect.left + (rect.width - w) / 2, rect.top + rect.height - h - kPad, w, h}, text, colour, kWhite);
}

// Where the overlays go: the corner of a view whose box covers the least of the projected path
// (the programmed and planned lines), so the panel and the legend do not hide what the video is
// about. Each box is tested inflated by the programmed line's half width; where every corner
// covers some of the path (a path filling the whole view), the one covering the least length.
struct PixelSegment {
  double u0 = 0, v0 = 0, u1 = 0, v1 = 0;  // frame pixels
};

// The segments of `lines` in the frame's pixels, seen through `camera` in `rect` (a segment with
// an end behind the eye is left out).
std::vector<PixelSegment> projected(const CameraPose& camera, const PixelRect& rect, std::initializer_list<std::span<const Vec3>> lines) {
  std::vector<PixelSegment> out;
  for (const std::span<const Vec3> line : lines) {
    for (std::size_t i = 1; i < line.size(); ++i) {
      const Projection a = project(camera, line[i - 1], rect.width, rect.height);
      const Projection b = project(camera, line[i], rect.width, rect.height);
      if (!(a.depth > 0) || !(b.depth > 0)) continue;
      out.push_back({a.u + rect.left, a.v + rect.top, b.u + rect.left, b.v + rect.top});
    }
  }
  return out;
}

// The length (pixels) of the segments inside `box` grown by `margin` on every side: each segment
// clipped to the box (Liang and Barsky's parametric clipping).
double covered(const std::vector<PixelSegment>& segments, const PixelRect& box, double margin) {
  const double x0 = box.left - margin, x1 = box.left + box.width + margin;
  const double y0 = box.top - margin, y1 = box.top + box.height + margin;
  double length = 0;
  for (const PixelSegment& s : segments) {
    const double du = s.u1 - s.u0, dv = s.v1 - s.v0;
    double t0 = 0, t1 = 1;
    bool outside = false;
    for (const auto& [p, q] : {std::pair{-du, s.u0 - x0}, std::pair{du, x1 - s.u0}, std::pair{-dv, s.v0 - y0}, std::pair{dv, y1 - s.v0}}) {
      if (p == 0) {
        outside = outside || q < 0;
        continue;
      }
      const double t = q / p;
      if (p < 0) t0 = std::max(t0, t);
      else t1 = std::min(t1, t);
    }
    if (!outside && t1 > t0) length += (t1 - t0) * std::hypot(du, dv);
  }
  return length;
}

// The corner of `preference` (in that order) whose box covers the least path; `current` is kept
// while it covers none (so a moving camera does not make the box jump about).
template <class BoxOf>
Corner clearest_corner(std::initializer_list<Corner> preference, const BoxOf& box_of, const std::vector<PixelSegment>& path,
                       double margin, std::optional<Corner> current = std::nullopt) {
  if (current && covered(path, box_of(*current), margin) == 0) return *current;
  Corner best = *preference.begin();
  double least = std::numeric_limits<double>::infinity();
  for (const Corner c : preference) {
    const double length = covered(path, box_of(c), margin);
    if (length < least) {
      least = length;
      best = c;
    }
  }
  return best;
}

bool is_top(Corner c) { return c == Corner::kTopLeft || c == Corner::kTopRight; }
bool is_left(Corner c) { return c == Corner::kTopLeft || c == Corner::kBottomLeft; }

// Half the programmed line's width in a view, and a pixel: how far a box keeps from the path.
double line_margin(const PixelRect& rect) {
  return 0.5 * std::max(1.0, kProgrammedWidth * std::max(kMinLineScale, rect.height / kReferenceHeight)) + 1;
}

// What a variant says once its motion is over (empty while it runs).
std::string done_text(const VariantFilm& film, double t) {
  if (film.done_time && t >= *film.done_time) return "done at t = " + fixed(*film.done_time, 3) + " s";
  if (!film.done_time && t >= film.reference_end) return "not settled (motion ended at t = " + fixed(film.reference_end, 2) + " s)";
  return {};
}

}  // namespace

void record_run(VariantFilm& film, const Trace& trace, const Metrics& metrics, const std::vector<CornerTiming>& corners) {
  film.sample_period = trace.period;
  film.reference_end = trace.reference_end;
  film.tcp.clear();
  film.tcp.reserve(trace.samples.size());
  for (const TraceSample& s : trace.samples) film.tcp.push_back(s.tcp);
  film.speed = metrics.tcp_speed;
  film.tracking_error = metrics.tracking_error;
  film.contour_error = metrics.contour_error_programmed;
  film.done_time = metrics.cycle_time;
  film.corners = corners;
}

// ---------------------------------------------------------------------------------------------
// one variant

struct VariantVideo::Impl {
  Impl(const mjModel& m, const VariantFilm& f, const FilmSettings& s)
      : film(f), settings(s), nq(m.nq), renderer(m, s.width, s.height, s.quality, font_scale_for(s.height)) {
    if (poses(film, nq) == 0 || !(film.pose_rate_hz > 0))
      throw std::invalid_argument("variant " + film.name + " has no recorded poses to film");
    base_camera = static_camera(settings, static_cast<double>(s.width) / s.height);
    const Vec3 target = settings.camera.mode == CameraSpec::Mode::kFixed ? settings.camera.look_at
                        : settings.camera.mode == CameraSpec::Mode::kTcp
                            ? Vec3(base_camera.eye + settings.camera.distance * base_camera.forward)
                            : centre_of(settings.programmed);
    const CameraPose scale_camera = camera_at(settings, base_camera, target);
    lines = view_lines(settings.programmed, film, tolerance_for(scale_camera, target, s.height));
  }

  const VariantFilm& film;
  const FilmSettings& settings;
  int nq;
  OffscreenRenderer renderer;
  CameraPose base_camera;
  ViewLines lines;
  std::optional<Corner> panel_corner, legend_corner;  // the last frame's
  OverlayBoxes boxes;                                  // the last frame's
};

VariantVideo::VariantVideo(const mjModel& m, const VariantFilm& film, const FilmSettings& settings)
    : impl_(std::make_unique<Impl>(m, film, settings)) {}
VariantVideo::~VariantVideo() = default;

int VariantVideo::frames() const {
  return static_cast<int>(std::floor(end_time(impl_->film, impl_->nq) * impl_->settings.fps + 1e-9)) + 1;
}

CameraPose VariantVideo::camera(int k) const {
  const Impl& r = *impl_;
  const double t = k / r.settings.fps;
  return camera_at(r.settings, r.base_camera, r.film.tcp.empty() ? r.base_camera.eye : r.film.tcp[sample_at(r.film, t)]);
}

const std::vector<std::uint8_t>& VariantVideo::frame(int k) {
  Impl& r = *impl_;
  const double t = k / r.settings.fps;
  const PixelRect all{0, 0, r.settings.width, r.settings.height};
  draw_view(r.renderer, all, camera(k), r.lines, r.film, t, r.nq, {.tool = r.settings.tool});

  // the panel and the legend where they hide least of the path; once the motion is over, how it
  // ended, along the bottom beside the legend
  const std::size_t i = sample_at(r.film, t);
  const std::vector<TextRow> rows = {{"time", fixed(t, 2) + " s"},
                                     {"variant", r.film.name},
                                     {"path speed", fixed(value_at(r.film.speed, i) / kMm, 1) + " mm/s"},
                                     {"tracking error", fixed(value_at(r.film.tracking_error, i) / kUm, 1) + kUmText}};
  const std::vector<LegendEntry> entries = legend(r.settings, r.film);
  const std::vector<PixelSegment> path = projected(camera(k), all, {r.lines.programmed, r.lines.planned});
  const double margin = line_margin(all);
  const Corner panel = clearest_corner(
      {Corner::kTopLeft, Corner::kTopRight, Corner::kBottomRight, Corner::kBottomLeft},
      [&](Corner c) { return r.renderer.panel_box(all, c, rows); }, path, margin, r.panel_corner);
  const auto others = [&](std::initializer_list<Corner> order) {
    std::vector<Corner> out;
    for (const Corner c : order)
      if (c != panel) out.push_back(c);
    return out;
  };
  const std::vector<Corner> legend_order = others({Corner::kBottomLeft, Corner::kBottomRight, Corner::kTopRight, Corner::kTopLeft});
  const auto legend_box = [&](Corner c) { return r.renderer.legend_box(all, c, entries); };
  const Corner legend_corner =
      clearest_corner({legend_order[0], legend_order[1], legend_order[2]}, legend_box, path, margin,
                      r.legend_corner != panel ? r.legend_corner : std::nullopt);
  r.panel_corner = panel;
  r.legend_corner = legend_corner;
  r.boxes.panel = r.renderer.draw_panel(all, panel, rows);
  r.boxes.legend = r.renderer.draw_legend(all, legend_corner, entries);
  if (const std::string done = done_text(r.film, t); !done.empty()) {
    const PixelRect beside = is_top(legend_corner)   ? all
                             : is_left(legend_corner) ? PixelRect{all.width / 3, 0, all.width - all.width / 3, all.height}
                                                      : PixelRect{0, 0, all.width - all.width / 3, all.height};
    bottom_label(r.renderer, beside, done, r.film.done_time ? kDoneColour : kNotSettledColour);
  }
  return r.renderer.read();
}

const OverlayBoxes& VariantVideo::overlays() const { return impl_->boxes; }

// ---------------------------------------------------------------------------------------------
// the comparison

PixelRect CompareLayout::cell(int i) const {
  return {(i % columns) * cell_width, header + (i / columns) * cell_height, cell_width, cell_height};
}

CompareLayout compare_layout(int variants, int view_width, int view_height) {
  CompareLayout l;
  const int n = std::max(1, variants);
  l.columns = n <= 3 ? n : static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n))));
  l.rows = (n + l.columns - 1) / l.columns;
  // the header: two lines of the font the cells use, sized for the unscaled view first
  const auto header_for = [](int cell_height) {
    const int h = font_scale_for(cell_height) * 52 / 100;
    return h + h % 2;
  };
  const double scale = std::min({1.0, static_cast<double>(kMaxWidth) / (l.columns * view_width),
                                 static_cast<double>(kMaxHeight - header_for(view_height)) / (l.rows * view_height)});
  l.cell_width = std::max(2, static_cast<int>(view_width * scale) / 2 * 2);
  l.cell_height = std::max(2, static_cast<int>(view_height * scale) / 2 * 2);
  l.header = header_for(l.cell_height);
  l.width = l.columns * l.cell_width;
  l.height = l.header + l.rows * l.cell_height;
  return l;
}

WorstCorner worst_corner(const std::vector<VariantFilm>& films, const std::vector<CornerPlacement>& corners) {
  WorstCorner worst;
  for (const VariantFilm& film : films) {
    if (!(film.sample_period > 0)) continue;
    for (const CornerTiming& c : film.corners) {
      const double t0 = c.t_start - kCornerMargin, t1 = c.t_end + kCornerMargin;
      const std::size_t i0 = sample_at(film, t0), i1 = sample_at(film, t1);
      for (std::size_t i = i0; i <= i1 && i < film.contour_error.size(); ++i) {
        if (film.contour_error[i] <= worst.contour_error) continue;
        worst.contour_error = film.contour_error[i];
        worst.index = c.index;
      }
    }
  }
  for (const CornerPlacement& p : corners) {
    if (p.index == worst.index) worst.point = p.point;
  }
  if (worst.index >= 0 && std::none_of(corners.begin(), corners.end(), [&](const CornerPlacement& p) { return p.index == worst.index; }))
    worst.index = -1;
  return worst;
}

struct CompareVideo::Impl {
  Impl(const mjModel& m, const std::vector<VariantFilm>& f, const FilmSettings& s)
      : films(f),
        settings(s),
        nq(m.nq),
        layout(compare_layout(static_cast<int>(f.size()), s.width, s.height)),
        renderer(m, layout.width, layout.height, s.quality, font_scale_for(layout.cell_height)) {
    if (films.empty()) throw std::invalid_argument("a comparison needs at least one variant");
    panel_corners.resize(films.size());
    boxes.resize(films.size());
    const double aspect = static_cast<double>(layout.cell_width) / layout.cell_height;
    base_camera = static_camera(settings, aspect);
    const Vec3 target = settings.camera.mode == CameraSpec::Mode::kFixed ? settings.camera.look_at : centre_of(settings.programmed);
    const double tolerance = tolerance_for(camera_at(settings, base_camera, target), target, layout.cell_height);

    // the synchronised segment: until the last variant is done, and a little more
    double last = 0, longest = 0;
    for (const VariantFilm& film : films) {
      lines.push_back(view_lines(settings.programmed, film, tolerance));
      if (poses(film, nq) == 0) continue;
      longest = std::max(longest, end_time(film, nq));
      last = std::max(last, film.done_time.value_or(film.reference_end));
    }
    sync_frames = static_cast<int>(std::floor(std::min(longest, last + kHoldAfterDone) * s.fps + 1e-9)) + 1;
    for (std::size_t i = 0; i < films.size(); ++i) {
      int rank = 1;
      for (const VariantFilm& other : films) {
        if (films[i].done_time && other.done_time && *other.done_time < *films[i].done_time) ++rank;
      }
      ranks.push_back(rank);
    }

    // the zoom: the worst corner seen along the base camera's line of sight, translucent arm
    corner = worst_corner(films, settings.corners);
    if (corner.index < 0) return;
    const double half = std::max(kMinZoomHalf, kZoomPerError * corner.contour_error);
    double depth = (corner.point - base_camera.eye).dot(base_camera.forward);
    if (!(depth > 0)) depth = kMinPartDistance;
    zoom_camera = base_camera;
    zoom_camera.eye = corner.point - depth * base_camera.forward;
    zoom_camera.fovy_deg = 2 * std::atan(half / depth) / kDeg;
    const double zoom_tolerance = tolerance_for(zoom_camera, corner.point, layout.cell_height);
    for (const VariantFilm& film : films) {
      zoom_lines.push_back(view_lines(settings.programmed, film, zoom_tolerance));
      // each variant at its own passage through the corner (its transition's midpoint), and the
      // largest contour error there for the cell's panel
      std::optional<double> centre;
      double worst_here = 0;
      for (const CornerTiming& c : film.corners) {
        if (c.index != corner.index) continue;
        centre = 0.5 * (c.t_start + c.t_end);
        zoom_half_window = std::max(zoom_half_window, 0.5 * (c.t_end - c.t_start) + kZoomMargin);
        const std::size_t final_sample = sample_at(film, c.t_end + kCornerMargin);
        for (std::size_t i = sample_at(film, c.t_start - kCornerMargin); i <= final_sample && i < film.contour_error.size(); ++i)
          worst_here = std::max(worst_here, film.contour_error[i]);
      }
      passage.push_back(centre);
      corner_error.push_back(worst_here);
    }
    zoom_frames = static_cast<int>(std::floor(2 * zoom_half_window * s.fps * kSlowMotion + 1e-9)) + 1;
  }

  // The header: a title line (the first of `titles` that fits) and the legend in one row.
  void draw_header(const std::vector<std::string>& titles) {
    const PixelRect strip{0, 0, layout.width, layout.header};
    renderer.fill(strip, kHeaderColour);
    std::string title = titles.back();
    for (const std::string& t : titles) {
      if (renderer.text_width(t) + 2 * kPad <= layout.width) {
        title = t;
        break;
      }
    }
    const int line = renderer.text_height();
    renderer.draw_text(kPad, kPad / 2, title, kWhite);
    int x = kPad;
    const int y = kPad / 2 + line + kPad / 2;
    // the legend in one row: in full words where they fit, else shorter
    const auto row_width = [&](const std::vector<LegendEntry>& entries) {
      int w = kPad;
      for (const LegendEntry& e : entries) w += 2 * line + 2 * kPad + renderer.text_width(e.text) + 2 * kPad;
      return w;
    };
    std::vector<LegendEntry> entries = compare_legend(settings, films, false);
    if (row_width(entries) > layout.width) entries = compare_legend(settings, films, true);
    for (const LegendEntry& e : entries) {
      const int bar = 2 * line, thickness = std::max(3, line / 4);
      renderer.fill({x, y + (line - thickness) / 2, bar, thickness}, e.colour);
      renderer.draw_text(x + bar + kPad, y, e.text, kWhite);
      x += bar + 2 * kPad + renderer.text_width(e.text) + 2 * kPad;
    }
  }

  // A cell's panel, in the corner of the cell that hides least of its path (the top ones
  // preferred: the bottom holds the "done" label).
  void draw_cell_panel(int i, const CameraPose& camera, const ViewLines& cell_lines, const std::vector<TextRow>& rows) {
    const PixelRect cell = layout.cell(i);
    const auto u = static_cast<std::size_t>(i);
    const Corner c = clearest_corner(
        {Corner::kTopLeft, Corner::kTopRight, Corner::kBottomRight, Corner::kBottomLeft},
        [&](Corner k) { return renderer.panel_box(cell, k, rows); }, projected(camera, cell, {cell_lines.programmed, cell_lines.planned}),
        line_margin(cell), panel_corners[u]);
    panel_corners[u] = c;
    boxes[u].panel = renderer.draw_panel(cell, c, rows);
  }

  // A cell without motion: the variant's name and why.
  void draw_failed(const PixelRect& cell, const VariantFilm& film) {
    renderer.fill(cell, kHeaderColour);
    renderer.draw_label({cell.left + kPad, cell.top + cell.height / 2 - renderer.text_height(), cell.width - 2 * kPad,
                         2 * renderer.text_height()},
                        film.name + ": " + film.failure, kFailedColour, kWhite);
  }

  const std::vector<std::uint8_t>& synchronised(int k) {
    const double t = k / settings.fps;
    draw_header({"scenario " + settings.scenario + "   t = " + fixed(t, 2) + " s   (every variant at the same time)",
                 settings.scenario + "   t = " + fixed(t, 2) + " s", "t = " + fixed(t, 2) + " s"});
    for (int i = 0; i < layout.columns * layout.rows; ++i) {
      const PixelRect cell = layout.cell(i);
      if (i >= static_cast<int>(films.size())) {
        renderer.fill(cell, kHeaderColour);
        continue;
      }
      const VariantFilm& film = films[static_cast<std::size_t>(i)];
      if (poses(film, nq) == 0) {
        draw_failed(cell, film);
        continue;
      }
      const std::size_t s = sample_at(film, t);
      const CameraPose camera = camera_at(settings, base_camera, film.tcp.empty() ? Vec3::Zero() : film.tcp[s]);
      draw_view(renderer, cell, camera, lines[static_cast<std::size_t>(i)], film, t, nq, {.tool = settings.tool});
      draw_cell_panel(i, camera, lines[static_cast<std::size_t>(i)],
                      {{"variant", film.name},
                       {"path speed", fixed(value_at(film.speed, s) / kMm, 1) + " mm/s"},
                       {"tracking error", fixed(value_at(film.tracking_error, s) / kUm, 1) + kUmText}});
      if (std::string done = done_text(film, t); !done.empty()) {
        if (film.done_time) done += " (" + ordinal(ranks[static_cast<std::size_t>(i)]) + ")";
        bottom_label(renderer, cell, done, film.done_time ? kDoneColour : kNotSettledColour);
      }
    }
    return renderer.read();
  }

  const std::vector<std::uint8_t>& zoomed(int j) {
    const double tau = -zoom_half_window + j / (settings.fps * kSlowMotion);
    // the corner as every output names it, at its point in program coordinates
    const Vec3 p = settings.program_frame.inverse() * corner.point / kMm;
    char where[96];
    std::snprintf(where, sizeof where, "(%.1f, %.1f, %.1f) mm", p.x(), p.y(), p.z());
    const std::string error = fixed(corner.contour_error / kMm, 3) + " mm";
    // (appended, not "C" + ...: GCC 12 warns -Wrestrict on that concatenation, a false positive)
    std::string number = "C";
    number += std::to_string(corner.index);
    const auto named = settings.corner_names.find(corner.index);
    const std::string name = named != settings.corner_names.end() ? named->second : number;
    draw_header({"worst corner " + name + " at " + std::string(where) + ": contour error up to " + error +
                     "   slow motion 1/" + std::to_string(kSlowMotion) + ", each variant at its own passage",
                 "worst corner " + name + ": up to " + error + ", slow motion 1/" + std::to_string(kSlowMotion),
                 "corner " + number + ", 1/" + std::to_string(kSlowMotion)});
    for (int i = 0; i < layout.columns * layout.rows; ++i) {
      const PixelRect cell = layout.cell(i);
      const auto u = static_cast<std::size_t>(i);
      if (u >= films.size()) {
        renderer.fill(cell, kHeaderColour);
        continue;
      }
      const VariantFilm& film = films[u];
      if (poses(film, nq) == 0 || !passage[u]) {
        draw_failed(cell, film);
        continue;
      }
      const double t = std::clamp(*passage[u] + tau, 0.0, end_time(film, nq));
      const std::size_t s = sample_at(film, t);
      draw_view(renderer, cell, zoom_camera, zoom_lines[u], film, t, nq, {.hide_arm = true});
      draw_cell_panel(i, zoom_camera, zoom_lines[u],
                      {{"variant", film.name},
                       {"time", fixed(t, 3) + " s"},
                       {"contour error", fixed(value_at(film.contour_error, s) / kMm, 3) + " mm"},
                       {"max at this corner", fixed(corner_error[u] / kMm, 3) + " mm"}});
    }
    return renderer.read();
  }

  const std::vector<VariantFilm>& films;
  const FilmSettings& settings;
  int nq;
  CompareLayout layout;
  OffscreenRenderer renderer;
  CameraPose base_camera, zoom_camera;
  std::vector<ViewLines> lines, zoom_lines;
  std::vector<int> ranks;
  int sync_frames = 0, zoom_frames = 0;
  WorstCorner corner;
  std::vector<std::optional<double>> passage;  // per film: when it passes the worst corner
  std::vector<double> corner_error;            // per film: its largest contour error there
  std::vector<std::optional<Corner>> panel_corners;  // per cell: where its panel was last
  std::vector<OverlayBoxes> boxes;                   // per cell: the last frame's
  double zoom_half_window = 0;                 // s
};

CompareVideo::CompareVideo(const mjModel& m, const std::vector<VariantFilm>& films, const FilmSettings& settings)
    : impl_(std::make_unique<Impl>(m, films, settings)) {}
CompareVideo::~CompareVideo() = default;

const CompareLayout& CompareVideo::layout() const { return impl_->layout; }
int CompareVideo::frames() const { return impl_->sync_frames + impl_->zoom_frames; }
int CompareVideo::synchronised_frames() const { return impl_->sync_frames; }
const WorstCorner& CompareVideo::corner() const { return impl_->corner; }
const OverlayBoxes& CompareVideo::overlays(int cell) const { return impl_->boxes.at(static_cast<std::size_t>(cell)); }

const std::vector<std::uint8_t>& CompareVideo::frame(int k) {
  return k < impl_->sync_frames ? impl_->synchronised(k) : impl_->zoomed(k - impl_->sync_frames);
}

// ---------------------------------------------------------------------------------------------
// to files

namespace {

template <class Video>
int write_video(Video& video, int width, int height, double fps, const std::string& path, const FilmProgress& progress) {
  VideoWriter writer(path, width, height, fps);
  const int total = video.frames();
  for (int k = 0; k < total; ++k) {
    writer.write(video.frame(k));
    if (progress) progress(k + 1, total);
  }
  writer.finish();
  return total;
}

}  // namespace

int write_variant_video(const mjModel& m, const VariantFilm& film, const FilmSettings& settings, const std::string& path,
                        const FilmProgress& progress) {
  VariantVideo video(m, film, settings);
  return write_video(video, settings.width, settings.height, settings.fps, path, progress);
}

int write_compare_video(const mjModel& m, const std::vector<VariantFilm>& films, const FilmSettings& settings,
                        const std::string& path, const FilmProgress& progress) {
  CompareVideo video(m, films, settings);
  return write_video(video, video.layout().width, video.layout().height, settings.fps, path, progress);
}

}  // namespace blendbench
