#include "blendbench/render/render.hpp"

#include <GL/osmesa.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>
#include <numbers>
#include <stdexcept>
#include <string_view>
#include <utility>

#include "blendbench/sim/simulator.hpp"

namespace blendbench {
namespace {

// Room in the scene beyond the model's own geoms (a floor, the tool).
constexpr int kMaxDecorations = 16;
// Headlight floor: without a skybox the background is black, so the arm needs this much light.
constexpr float kMinHeadlightAmbient = 0.3f;
constexpr float kMinHeadlightDiffuse = 0.5f;
// Shadow map size when shadows are on (measured: 4096 is slower than 2048).
constexpr int kShadowSize = 2048;
// Points closer to the eye than this are not drawn (m): the near plane is ~1 cm.
constexpr double kNearest = 1e-3;
// A line's aliased core is this much narrower than its antialiased full width (pixels).
constexpr double kCoreInset = 2;
// The TCP marker's disc: segments of its rim, and the rim's share of the radius.
constexpr int kDiscSegments = 24;
constexpr double kRimShare = 0.3;
// Text panels: padding inside a legend box and the length of a colour bar (in text heights).
constexpr int kPad = 5;  // pixels
constexpr double kBarLength = 1.8;
constexpr Rgba kPanelColour{0, 0, 0, 0.55f};
constexpr Rgba kPanelLabelColour{0.75f, 0.75f, 0.75f, 1};
constexpr float kFloorRgba[4] = {0.35f, 0.37f, 0.4f, 1.0f};

// A box of w x h pixels in a corner of `where`, kPad in from its edges.
PixelRect in_corner(const PixelRect& where, Corner corner, int w, int h) {
  const bool left = corner == Corner::kTopLeft || corner == Corner::kBottomLeft;
  const bool top = corner == Corner::kTopLeft || corner == Corner::kTopRight;
  return {left ? where.left + kPad : where.left + where.width - kPad - w, top ? where.top + kPad : where.top + where.height - kPad - h, w, h};
}

bool has_plane(const mjModel& m) {
  for (int g = 0; g < m.ngeom; ++g)
    if (m.geom_type[g] == mjGEOM_PLANE) return true;
  return false;
}

// The next free geom of the scene, initialised as a decoration; nullptr when the scene is full.
mjvGeom* new_decor(mjvScene& scn) {
  if (scn.ngeom >= scn.maxgeom) return nullptr;
  mjvGeom* g = scn.geoms + scn.ngeom;
  mjv_initGeom(g, mjGEOM_NONE, nullptr, nullptr, nullptr, nullptr);
  g->category = mjCAT_DECOR;
  g->objtype = mjOBJ_UNKNOWN;
  g->objid = -1;
  return g;
}

// Lines and discs over a rendered view, in its pixels (GL's window coordinates, origin at the
// view's bottom left; `project` measures rows from the top).
void draw_overlay(const mjrRect& view, const CameraPose& camera, std::span<const Polyline> lines, std::span<const Marker> markers) {
  glViewport(view.left, view.bottom, view.width, view.height);
  glScissor(view.left, view.bottom, view.width, view.height);
  glEnable(GL_SCISSOR_TEST);
  glMatrixMode(GL_PROJECTION);
  glLoadIdentity();
  glOrtho(0, view.width, 0, view.height, -1, 1);
  glMatrixMode(GL_MODELVIEW);
  glLoadIdentity();
  for (const GLenum cap : {GL_DEPTH_TEST, GL_LIGHTING, GL_TEXTURE_2D, GL_FOG, GL_CULL_FACE}) glDisable(cap);
  glEnable(GL_BLEND);
  glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
  glHint(GL_LINE_SMOOTH_HINT, GL_NICEST);
  const auto vertex = [&](const Vec3& p) {
    const Projection q = project(camera, p, view.width, view.height);
    if (!(q.depth > kNearest) || !std::isfinite(q.u) || !std::isfinite(q.v)) return false;
    glVertex2d(q.u, view.height - q.v);
    return true;
  };
  // a strip, broken where a point lies behind the eye
  const auto strip = [&](const Polyline& line) {
    glBegin(GL_LINE_STRIP);
    const auto add = [&](const Vec3& p) {
      if (!vertex(p)) {
        glEnd();
        glBegin(GL_LINE_STRIP);
      }
    };
    for (const Vec3& p : line.points) add(p);
    if (line.tip) add(*line.tip);
    glEnd();
  };
  for (const Polyline& line : lines) {
    glColor4f(line.colour.r, line.colour.g, line.colour.b, line.colour.a);
    // antialiased at full width (llvmpipe's smooth lines blend even their middle a little), then
    // an aliased core kCoreInset pixels narrower that carries the exact colour
    glEnable(GL_LINE_SMOOTH);
    glLineWidth(static_cast<GLfloat>(line.width_px));
    strip(line);
    glDisable(GL_LINE_SMOOTH);
    glLineWidth(static_cast<GLfloat>(std::max(1.0, line.width_px - kCoreInset)));
    strip(line);
  }
  for (const Marker& m : markers) {
    const Projection c = project(camera, m.position, view.width, view.height);
    if (!(c.depth > kNearest)) continue;
    // a dark disc, then the coloured one inside it: a rim that shows on any background
    for (const auto& [radius, rgba] : {std::pair{m.radius_px, Rgba{0.05f, 0.05f, 0.05f, 1}},
                                       std::pair{m.radius_px * (1 - kRimShare), m.colour}}) {
      glColor4f(rgba.r, rgba.g, rgba.b, rgba.a);
      glBegin(GL_TRIANGLE_FAN);
      glVertex2d(c.u, view.height - c.v);
      for (int i = 0; i <= kDiscSegments; ++i) {
        const double a = 2 * std::numbers::pi * i / kDiscSegments;
        glVertex2d(c.u + radius * std::cos(a), view.height - c.v + radius * std::sin(a));
      }
      glEnd();
    }
  }
  glDisable(GL_BLEND);
  glDisable(GL_SCISSOR_TEST);
  glLineWidth(1);
}

// The tool on the flange `site` of state `d` (render.hpp, SceneStyle::tool): a capsule from the
// flange to the TCP and a rod along the tool's z axis, as decorations.
void add_tool(mjvScene& scn, const mjData& d, int site, const Eigen::Isometry3d& tool) {
  Eigen::Isometry3d flange = Eigen::Isometry3d::Identity();
  flange.linear() = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(d.site_xmat + 9 * site);
  flange.translation() = Eigen::Map<const Vec3>(d.site_xpos + 3 * site);
  const Eigen::Isometry3d tcp = flange * tool;
  const auto connector = [&](int type, double width, const Vec3& a, const Vec3& b, const Rgba& colour) {
    mjvGeom* g = new_decor(scn);
    if (g == nullptr) return;
    mjv_makeConnector(g, type, width, a.x(), a.y(), a.z(), b.x(), b.y(), b.z());
    for (const auto& [i, c] : {std::pair{0, colour.r}, std::pair{1, colour.g}, std::pair{2, colour.b}, std::pair{3, colour.a}}) {
      g->rgba[i] = c;
    }
    ++scn.ngeom;
  };
  const Vec3 a = flange.translation();
  const Vec3 b = tcp.translation();
  if ((b - a).norm() > kMinToolLength) connector(mjGEOM_CAPSULE, kToolRadius, a, b, kToolColour);
  connector(mjGEOM_CAPSULE, kToolAxisRadius, b, b + kToolAxisLength * tcp.linear().col(2), kToolAxisColour);
}

// Removes the arm from the scene: every geom of a body other than the world.
void remove_arm(const mjModel& m, mjvScene& scn) {
  int kept = 0;
  for (int i = 0; i < scn.ngeom; ++i) {
    const mjvGeom& g = scn.geoms[i];
    if (g.objtype == mjOBJ_GEOM && g.objid >= 0 && m.geom_bodyid[g.objid] != 0) continue;
    scn.geoms[kept++] = g;
  }
  scn.ngeom = kept;
}

// Text as MuJoCo's fonts can draw it: runs of ASCII, and micro signs between them (render.hpp,
// draw_text). UTF-8 is decoded leniently: a character beyond ASCII other than the micro sign, or
// a malformed sequence, becomes "?".
struct TextPiece {
  std::string ascii;   // drawn as it is (empty for a micro sign)
  bool micro = false;  // a micro sign
};

std::vector<TextPiece> text_pieces(const std::string& text) {
  std::vector<TextPiece> pieces;
  const auto add = [&](char c) {
    if (pieces.empty() || pieces.back().micro) pieces.emplace_back();
    pieces.back().ascii += c;
  };
  for (std::size_t i = 0; i < text.size();) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c < 0x80) {
      add(static_cast<char>(c));
      ++i;
      continue;
    }
    // a multi-byte sequence: its lead byte says how long
    const std::size_t length = c >= 0xF0 ? 4 : c >= 0xE0 ? 3 : c >= 0xC0 ? 2 : 1;
    const std::string_view sequence(text.data() + i, std::min(length, text.size() - i));
    if (sequence == "\xC2\xB5" || sequence == "\xCE\xBC") {
      pieces.push_back({{}, true});
    } else {
      add('?');
    }
    i += sequence.size();
    // continuation bytes of a malformed sequence are skipped with it
    while (i < text.size() && (static_cast<unsigned char>(text[i]) & 0xC0) == 0x80) ++i;
  }
  return pieces;
}

// Where the font's "u" ends below: drawn once in white on black at a known raster row, the rows
// from there to its lowest lit pixel (the font data is MuJoCo's own, so this is measured rather
// than assumed). The frame is cleared after.
int measure_u_bottom(const mjrContext& context, int width, int height) {
  const int w = std::min(width, std::max(1, 2 * context.charWidth[static_cast<unsigned char>('u')]));
  const int h = std::min(height, 3 * context.charHeight);
  const int origin = std::min(height - 1, context.charHeight);  // the raster row
  glViewport(0, 0, width, height);
  glClearColor(0, 0, 0, 1);
  glClear(GL_COLOR_BUFFER_BIT);
  mjr_text(mjFONT_NORMAL, "u", &context, 0, static_cast<float>(origin) / static_cast<float>(height), 1, 1, 1);
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4);
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadPixels(0, 0, w, h, GL_RGBA, GL_UNSIGNED_BYTE, pixels.data());
  glClear(GL_COLOR_BUFFER_BIT);
  for (int row = 0; row < h; ++row) {  // bottom-up
    for (int x = 0; x < w; ++x) {
      if (pixels[(static_cast<std::size_t>(row) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x)) * 4] > 128) return row - origin;
    }
  }
  return 0;  // no "u" drawn: the micro sign gets no descender
}

}  // namespace

struct OffscreenRenderer::Impl {
  int width = 0, height = 0;
  mjModel* model = nullptr;  // the renderer's copy
  mjData* data = nullptr;    // the state being drawn
  OSMesaContext gl = nullptr;
  std::vector<std::uint8_t> gl_buffer;  // OSMesa's default framebuffer (RGBA)
  mjvScene scene{};
  mjvCamera camera{};
  mjvOption option{};
  mjrContext context{};
  bool scene_made = false, context_made = false;
  std::vector<std::uint8_t> raw, rgb;  // bottom-up as read, top-down as returned
  bool draw_floor = false;
  int tcp_site = -1;  // the flange (site "tcp"), where the tool is drawn; -1: none
  // Rows from the raster position mjr_text draws at up to the lowest row of the font's "u" (its
  // baseline): below it, the micro sign takes the descender of "p" (draw_text).
  int u_bottom = 0;

  bool try_make_current() {
    return OSMesaMakeCurrent(gl, gl_buffer.data(), GL_UNSIGNED_BYTE, width, height) != 0;
  }
  void make_current() {
    if (!try_make_current()) throw std::runtime_error("OSMesaMakeCurrent failed");
    mjr_setBuffer(mjFB_OFFSCREEN, &context);
  }
  // A frame rectangle in GL's window coordinates (origin at the bottom left).
  [[nodiscard]] mjrRect gl_rect(const PixelRect& r) const { return {r.left, height - r.top - r.height, r.width, r.height}; }

  ~Impl() {
    // GL resources go while their context is current
    if (gl != nullptr && context_made && try_make_current()) mjr_freeContext(&context);
    if (scene_made) mjv_freeScene(&scene);
    if (gl != nullptr) OSMesaDestroyContext(gl);
    if (data != nullptr) mj_deleteData(data);
    if (model != nullptr) mj_deleteModel(model);
  }
};

OffscreenRenderer::OffscreenRenderer(const mjModel& m, int width, int height, RenderQuality quality, int font_scale)
    : impl_(std::make_unique<Impl>()) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("render size must be positive");
  if (quality.samples < 0) throw std::invalid_argument("render samples must be >= 0");
  if (font_scale < 50 || font_scale > 300 || font_scale % 50 != 0)
    throw std::invalid_argument("font scale must be one of 50, 100, ..., 300, got " + std::to_string(font_scale));
  install_mujoco_handlers();
  Impl& r = *impl_;
  r.width = width;
  r.height = height;

  // the renderer's model: off-screen buffer of the requested size, quality, minimum headlight
  r.model = mj_copyModel(nullptr, &m);
  r.data = mj_makeData(r.model);
  mj_kinematics(r.model, r.data);
  mjVisual& vis = r.model->vis;
  vis.global.offwidth = std::max(vis.global.offwidth, width);
  vis.global.offheight = std::max(vis.global.offheight, height);
  vis.quality.offsamples = quality.samples;
  vis.quality.shadowsize = kShadowSize;
  vis.headlight.active = 1;
  for (int c = 0; c < 3; ++c) {
    vis.headlight.ambient[c] = std::max(vis.headlight.ambient[c], kMinHeadlightAmbient);
    vis.headlight.diffuse[c] = std::max(vis.headlight.diffuse[c], kMinHeadlightDiffuse);
  }
  r.draw_floor = !has_plane(*r.model);
  r.tcp_site = mj_name2id(r.model, mjOBJ_SITE, "tcp");

  // OSMesa context, current before MuJoCo makes its GL objects
  r.gl = OSMesaCreateContextExt(OSMESA_RGBA, 24, 8, 8, nullptr);
  if (r.gl == nullptr) throw std::runtime_error("OSMesaCreateContextExt failed");
  r.gl_buffer.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 4, 0);
  if (!r.try_make_current()) throw std::runtime_error("OSMesaMakeCurrent failed");
  GLint max_size = 0;
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size);
  if (width > max_size || height > max_size)
    throw std::runtime_error("render size " + std::to_string(width) + "x" + std::to_string(height) +
                             " exceeds this GL's largest off-screen buffer (" + std::to_string(max_size) + ")");

  // MuJoCo's scene, camera and render context
  mjv_defaultScene(&r.scene);
  mjv_makeScene(r.model, &r.scene, r.model->ngeom + r.model->nsite + 1000 + kMaxDecorations);
  r.scene_made = true;
  r.scene.flags[mjRND_SHADOW] = quality.shadows ? 1 : 0;
  r.scene.flags[mjRND_REFLECTION] = 0;
  mjv_defaultOption(&r.option);
  for (mjtByte& group : r.option.sitegroup) group = 0;  // markers are drawn at a size in pixels
  mjv_defaultFreeCamera(r.model, &r.camera);
  mjr_defaultContext(&r.context);
  r.context_made = true;  // mjr_freeContext also frees a partly made context
  try {
    mjr_makeContext(r.model, &r.context, font_scale);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error("cannot create MuJoCo's render context for " + std::to_string(width) + "x" +
                             std::to_string(height) + ": " + e.what());
  }
  mjr_setBuffer(mjFB_OFFSCREEN, &r.context);
  if (r.context.currentBuffer != mjFB_OFFSCREEN) throw std::runtime_error("MuJoCo has no off-screen buffer");
  if (r.context.offWidth < width || r.context.offHeight < height)
    throw std::runtime_error("off-screen buffer is " + std::to_string(r.context.offWidth) + "x" +
                             std::to_string(r.context.offHeight) + ", smaller than the requested " +
                             std::to_string(width) + "x" + std::to_string(height));
  const std::size_t bytes = static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3;
  r.raw.resize(bytes);
  r.rgb.resize(bytes);
  r.u_bottom = measure_u_bottom(r.context, width, height);
}

OffscreenRenderer::~OffscreenRenderer() = default;

int OffscreenRenderer::width() const { return impl_->width; }
int OffscreenRenderer::height() const { return impl_->height; }
const mjData& OffscreenRenderer::data() const { return *impl_->data; }

void OffscreenRenderer::pose(std::span<const double> qpos) {
  Impl& r = *impl_;
  assert(static_cast<int>(qpos.size()) == r.model->nq && "qpos of another model");
  std::copy(qpos.begin(), qpos.end(), r.data->qpos);
  mj_kinematics(r.model, r.data);
  mj_camlight(r.model, r.data);
}

void OffscreenRenderer::pose(const mjData& d) {
  pose(std::span<const double>(d.qpos, static_cast<std::size_t>(impl_->model->nq)));
}

void OffscreenRenderer::draw_scene(const PixelRect& where, const CameraPose& camera, std::span<const Polyline> lines,
                                   std::span<const Marker> markers, SceneStyle style) {
  Impl& r = *impl_;
  r.make_current();

  // the model's geoms (perhaps without the arm), then a floor where the model has none
  mjv_updateScene(r.model, r.data, &r.option, nullptr, &r.camera, mjCAT_ALL, &r.scene);
  if (style.hide_arm) remove_arm(*r.model, r.scene);
  if (r.draw_floor) {
    if (mjvGeom* g = new_decor(r.scene)) {
      const mjtNum size[3] = {2, 2, 0.1};
      const mjtNum pos[3] = {0, 0, 0};
      mjv_initGeom(g, mjGEOM_PLANE, size, pos, nullptr, kFloorRgba);
      g->category = mjCAT_DECOR;
      ++r.scene.ngeom;
    }
  }

  // the tool, with the arm
  if (style.tool && !style.hide_arm && r.tcp_site >= 0) add_tool(r.scene, *r.data, r.tcp_site, *style.tool);

  // our pinhole replaces MuJoCo's free camera: pose, then a symmetric frustum of the field of view
  const double tan_half = std::tan(0.5 * camera.fovy_deg * std::numbers::pi / 180);
  for (mjvGLCamera& c : r.scene.camera) {
    for (int i = 0; i < 3; ++i) {
      c.pos[i] = static_cast<float>(camera.eye[i]);
      c.forward[i] = static_cast<float>(camera.forward[i]);
      c.up[i] = static_cast<float>(camera.up[i]);
    }
    c.frustum_center = 0;
    c.frustum_top = static_cast<float>(static_cast<double>(c.frustum_near) * tan_half);
    c.frustum_bottom = -c.frustum_top;
  }
  mjr_render(r.gl_rect(where), &r.scene, &r.context);
  draw_overlay(r.gl_rect(where), camera, lines, markers);
}

void OffscreenRenderer::fill(const PixelRect& where, const Rgba& colour) {
  impl_->make_current();
  mjr_rectangle(impl_->gl_rect(where), colour.r, colour.g, colour.b, colour.a);
}

PixelRect OffscreenRenderer::panel_box(const PixelRect& where, Corner corner, const std::vector<TextRow>& rows) const {
  int labels = 0, values = 0;
  for (const TextRow& row : rows) {
    labels = std::max(labels, text_width(row.label));
    values = std::max(values, text_width(row.value));
  }
  PixelRect box;
  box.width = kPad + labels + 2 * kPad + values + kPad;
  box.height = kPad + static_cast<int>(rows.size()) * (text_height() + kPad);
  return in_corner(where, corner, box.width, box.height);
}

PixelRect OffscreenRenderer::draw_panel(const PixelRect& where, Corner corner, const std::vector<TextRow>& rows) {
  const PixelRect box = panel_box(where, corner, rows);
  fill(box, kPanelColour);
  int labels = 0;
  for (const TextRow& row : rows) labels = std::max(labels, text_width(row.label));
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const int y = box.top + kPad + static_cast<int>(i) * (text_height() + kPad);
    draw_text(box.left + kPad, y, rows[i].label, kPanelLabelColour);
    draw_text(box.left + 3 * kPad + labels, y, rows[i].value, {1, 1, 1, 1});
  }
  return box;
}

PixelRect OffscreenRenderer::legend_box(const PixelRect& where, Corner corner, const std::vector<LegendEntry>& entries) const {
  const int line = text_height();
  const int bar = static_cast<int>(kBarLength * line);
  int text = 0;
  for (const LegendEntry& e : entries) text = std::max(text, text_width(e.text));
  return in_corner(where, corner, kPad + bar + kPad + text + 2 * kPad, kPad + static_cast<int>(entries.size()) * (line + kPad));
}

PixelRect OffscreenRenderer::draw_legend(const PixelRect& where, Corner corner, const std::vector<LegendEntry>& entries) {
  const int line = text_height();
  const int bar = static_cast<int>(kBarLength * line);
  const PixelRect box = legend_box(where, corner, entries);
  fill(box, kPanelColour);
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const int y = box.top + kPad + static_cast<int>(i) * (line + kPad);
    // the bar as thick as the widest line drawn in the scene, centred on the text
    const int thickness = std::max(3, line / 4);
    fill({box.left + kPad, y + (line - thickness) / 2, bar, thickness}, entries[i].colour);
    draw_text(box.left + 2 * kPad + bar, y, entries[i].text, {1, 1, 1, 1});
  }
  return box;
}

void OffscreenRenderer::draw_label(const PixelRect& rect, const std::string& text, const Rgba& background,
                                   const Rgba& text_colour) {
  fill(rect, background);
  draw_text(rect.left + (rect.width - text_width(text)) / 2, rect.top + (rect.height - text_height()) / 2, text, text_colour);
}

void OffscreenRenderer::draw_text(int x, int y, const std::string& text, const Rgba& colour) {
  Impl& r = *impl_;
  r.make_current();
  // mjr_text places the baseline-left of the text at a position relative to the viewport
  glViewport(0, 0, r.width, r.height);
  const int descent = r.context.charHeight / 5;
  const double gl_y = r.height - y - r.context.charHeight + descent;
  const auto at = [&](const char* ascii, int left) {
    mjr_text(mjFONT_NORMAL, ascii, &r.context, static_cast<float>(left) / static_cast<float>(r.width),
             static_cast<float>(gl_y / r.height), colour.r, colour.g, colour.b);
  };
  int left = x;
  for (const TextPiece& piece : text_pieces(text)) {
    if (!piece.micro) {
      at(piece.ascii.c_str(), left);
      left += text_width(piece.ascii);
      continue;
    }
    // the micro sign: "u", and "p" clipped to below the baseline (its stem's descender)
    const int advance = r.context.charWidth[static_cast<unsigned char>('u')];
    at("u", left);
    glEnable(GL_SCISSOR_TEST);
    glScissor(left, 0, advance, static_cast<int>(std::floor(gl_y)) + r.u_bottom);
    at("p", left);
    glDisable(GL_SCISSOR_TEST);
    left += advance;
  }
}

int OffscreenRenderer::text_width(const std::string& text) const {
  int w = 0;
  for (const TextPiece& piece : text_pieces(text)) {
    if (piece.micro) w += impl_->context.charWidth[static_cast<unsigned char>('u')];
    for (const char c : piece.ascii) {
      const auto i = static_cast<unsigned char>(c);
      if (i < 127) w += impl_->context.charWidth[i];
    }
  }
  return w;
}

int OffscreenRenderer::text_height() const { return impl_->context.charHeight; }

const std::vector<std::uint8_t>& OffscreenRenderer::read() {
  Impl& r = *impl_;
  r.make_current();
  // the read waits for llvmpipe to finish drawing; then flip to top-down rows
  mjr_readPixels(r.raw.data(), nullptr, {0, 0, r.width, r.height}, &r.context);
  const std::size_t row = static_cast<std::size_t>(r.width) * 3;
  const auto rows = static_cast<std::size_t>(r.height);
  for (std::size_t y = 0; y < rows; ++y) std::memcpy(r.rgb.data() + y * row, r.raw.data() + (rows - 1 - y) * row, row);
  return r.rgb;
}

int font_scale_for(int height) { return height <= 540 ? 100 : height <= 900 ? 150 : 200; }

std::vector<std::size_t> simplify(std::span<const Vec3> points, double tolerance) {
  if (points.size() < 3) {
    std::vector<std::size_t> all(points.size());
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
    return all;
  }
  std::vector<bool> keep(points.size(), false);
  keep.front() = keep.back() = true;
  // split each span at its farthest point until every dropped point is within the tolerance
  std::vector<std::pair<std::size_t, std::size_t>> spans = {{0, points.size() - 1}};
  while (!spans.empty()) {
    const auto [a, b] = spans.back();
    spans.pop_back();
    const Vec3 d = points[b] - points[a];
    const double len2 = d.squaredNorm();
    double worst = 0;
    std::size_t worst_i = a;
    for (std::size_t i = a + 1; i < b; ++i) {
      const Vec3 rel = points[i] - points[a];
      const double t = len2 > 0 ? std::clamp(rel.dot(d) / len2, 0.0, 1.0) : 0.0;
      const double dist = (rel - t * d).norm();
      if (dist > worst) {
        worst = dist;
        worst_i = i;
      }
    }
    if (worst > tolerance) {
      keep[worst_i] = true;
      spans.emplace_back(a, worst_i);
      spans.emplace_back(worst_i, b);
    }
  }
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (keep[i]) out.push_back(i);
  }
  return out;
}

std::optional<CameraPose> model_camera(const mjModel& m, const mjData& d, const std::string& name) {
  const int cam = mj_name2id(&m, mjOBJ_CAMERA, name.c_str());
  if (cam < 0) return std::nullopt;
  // a MuJoCo camera looks along its frame's -z with +y up; cam_xmat is row-major
  const mjtNum* x = d.cam_xmat + 9 * cam;
  CameraPose c;
  c.eye = Vec3(d.cam_xpos[3 * cam], d.cam_xpos[3 * cam + 1], d.cam_xpos[3 * cam + 2]);
  c.forward = -Vec3(x[2], x[5], x[8]);
  c.up = Vec3(x[1], x[4], x[7]);
  c.fovy_deg = m.cam_fovy[cam];
  return c;
}

}  // namespace blendbench
