#include "blendbench/render/render.hpp"

#include <GL/osmesa.h>

#include <algorithm>
#include <cassert>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "blendbench/sim/simulator.hpp"

namespace blendbench {
namespace {

// At most this many capsules per polyline (longer ones are subsampled), so that the scene keeps
// room for the model's own geoms.
constexpr int kMaxPolylineSegments = 400;
// Headlight floor: without a skybox the background is black, so the arm needs this much light.
constexpr float kMinHeadlightAmbient = 0.3f;
constexpr float kMinHeadlightDiffuse = 0.5f;
// Shadow map size when shadows are on (measured with llvmpipe: 4096 renders slower than 2048).
constexpr int kShadowSize = 2048;
// Polylines are simplified to this tolerance before drawing (m): far below what a frame shows.
constexpr double kDrawTolerance = 0.2e-3;
// Segments shorter than this are skipped (a connector needs a direction).
constexpr double kMinSegmentLength = 1e-9;  // m

constexpr float kPathRgba[4] = {0.15f, 0.45f, 1.0f, 1.0f};
constexpr float kPlannedRgba[4] = {1.0f, 0.55f, 0.1f, 1.0f};
constexpr float kTrailRgba[4] = {0.2f, 0.9f, 0.3f, 1.0f};
constexpr float kFloorRgba[4] = {0.35f, 0.37f, 0.4f, 1.0f};

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

// Douglas-Peucker simplification: the fewest points of `points` (end points kept) such that
// every dropped point lies within `tolerance` (m) of the simplified polyline. Software
// rendering pays per capsule, and a programmed path is mostly straight lines and arcs.
std::vector<Eigen::Vector3d> simplified(const std::vector<Eigen::Vector3d>& points, double tolerance) {
  if (points.size() < 3) return points;
  std::vector<bool> keep(points.size(), false);
  keep.front() = keep.back() = true;
  std::vector<std::pair<std::size_t, std::size_t>> spans = {{0, points.size() - 1}};
  while (!spans.empty()) {
    const auto [a, b] = spans.back();
    spans.pop_back();
    const Eigen::Vector3d d = points[b] - points[a];
    const double len2 = d.squaredNorm();
    double worst = 0;
    std::size_t worst_i = a;
    for (std::size_t i = a + 1; i < b; ++i) {
      const Eigen::Vector3d r = points[i] - points[a];
      const double t = len2 > 0 ? std::clamp(r.dot(d) / len2, 0.0, 1.0) : 0.0;
      const double dist = (r - t * d).norm();
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
  std::vector<Eigen::Vector3d> out;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (keep[i]) out.push_back(points[i]);
  }
  return out;
}

// Capsules along a polyline, subsampled to at most kMaxPolylineSegments (the end points kept).
void add_polyline(mjvScene& scn, const std::vector<Eigen::Vector3d>& points, const float rgba[4], double radius) {
  if (points.size() < 2) return;
  const std::size_t segments = points.size() - 1;
  const std::size_t stride = (segments + kMaxPolylineSegments - 1) / kMaxPolylineSegments;
  std::size_t a = 0;
  while (a < segments) {
    const std::size_t b = std::min(a + stride, segments);
    const Eigen::Vector3d& p = points[a];
    const Eigen::Vector3d& q = points[b];
    a = b;
    if ((q - p).norm() < kMinSegmentLength || !p.allFinite() || !q.allFinite()) continue;
    mjvGeom* g = new_decor(scn);
    if (g == nullptr) return;
    std::copy(rgba, rgba + 4, g->rgba);
    g->emission = 0.3f;
    mjv_makeConnector(g, mjGEOM_CAPSULE, radius, p.x(), p.y(), p.z(), q.x(), q.y(), q.z());
    ++scn.ngeom;
  }
}

}  // namespace

struct OffscreenRenderer::Impl {
  RenderOptions options;
  mjModel* model = nullptr;  // the renderer's copy
  mjData* data = nullptr;    // scratch copy of the state being drawn
  OSMesaContext gl = nullptr;
  std::vector<std::uint8_t> gl_buffer;  // OSMesa's default framebuffer (RGBA)
  mjvScene scene{};
  mjvCamera camera{};
  mjvOption option{};
  mjrContext context{};
  bool scene_made = false, context_made = false;
  std::vector<std::uint8_t> raw, rgb;  // bottom-up as read, top-down as returned
  std::vector<Eigen::Vector3d> trail;
  std::vector<Eigen::Vector3d> path;     // options.path_polyline, simplified once
  std::vector<Eigen::Vector3d> planned;  // options.planned_polyline, simplified once
  int tcp_site = -1;
  bool draw_floor = false;

  bool try_make_current() {
    return OSMesaMakeCurrent(gl, gl_buffer.data(), GL_UNSIGNED_BYTE, options.width, options.height) != 0;
  }
  void make_current() {
    if (!try_make_current()) throw std::runtime_error("OSMesaMakeCurrent failed");
  }

  ~Impl() {
    // GL resources go while their context is current
    if (gl != nullptr && context_made && try_make_current()) mjr_freeContext(&context);
    if (scene_made) mjv_freeScene(&scene);
    if (gl != nullptr) OSMesaDestroyContext(gl);
    if (data != nullptr) mj_deleteData(data);
    if (model != nullptr) mj_deleteModel(model);
  }
};

OffscreenRenderer::OffscreenRenderer(const mjModel& m, RenderOptions options) : impl_(std::make_unique<Impl>()) {
  if (options.width <= 0 || options.height <= 0) throw std::invalid_argument("render size must be positive");
  if (options.samples < 0) throw std::invalid_argument("render samples must be >= 0");
  install_mujoco_handlers();
  Impl& r = *impl_;
  r.options = std::move(options);
  const RenderOptions& o = r.options;
  r.path = simplified(o.path_polyline, kDrawTolerance);
  r.planned = simplified(o.planned_polyline, kDrawTolerance);

  // the renderer's model: off-screen buffer of the requested size, quality, minimum headlight
  r.model = mj_copyModel(nullptr, &m);
  r.data = mj_makeData(r.model);
  mjVisual& vis = r.model->vis;
  vis.global.offwidth = std::max(vis.global.offwidth, o.width);
  vis.global.offheight = std::max(vis.global.offheight, o.height);
  vis.quality.offsamples = o.samples;
  vis.quality.shadowsize = kShadowSize;
  vis.headlight.active = 1;
  for (int c = 0; c < 3; ++c) {
    vis.headlight.ambient[c] = std::max(vis.headlight.ambient[c], kMinHeadlightAmbient);
    vis.headlight.diffuse[c] = std::max(vis.headlight.diffuse[c], kMinHeadlightDiffuse);
  }
  r.tcp_site = mj_name2id(r.model, mjOBJ_SITE, "tcp");
  r.draw_floor = !has_plane(*r.model);

  // OSMesa context, current before MuJoCo makes its GL objects (mjr_makeContext needs one)
  r.gl = OSMesaCreateContextExt(OSMESA_RGBA, 24, 8, 8, nullptr);
  if (r.gl == nullptr) throw std::runtime_error("OSMesaCreateContextExt failed");
  r.gl_buffer.assign(static_cast<std::size_t>(o.width) * static_cast<std::size_t>(o.height) * 4, 0);
  r.make_current();
  GLint max_size = 0;
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &max_size);
  if (o.width > max_size || o.height > max_size)
    throw std::runtime_error("render size " + std::to_string(o.width) + "x" + std::to_string(o.height) +
                             " exceeds this GL's largest off-screen buffer (" + std::to_string(max_size) + ")");

  // MuJoCo's scene, camera and render context
  mjv_defaultScene(&r.scene);
  mjv_makeScene(r.model, &r.scene, r.model->ngeom + r.model->nsite + 1000 + 3 * kMaxPolylineSegments + 1);
  r.scene_made = true;
  r.scene.flags[mjRND_SHADOW] = o.shadows ? 1 : 0;
  r.scene.flags[mjRND_REFLECTION] = 0;
  mjv_defaultOption(&r.option);
  mjv_defaultCamera(&r.camera);
  const int camera_id = o.camera.empty() ? -1 : mj_name2id(r.model, mjOBJ_CAMERA, o.camera.c_str());
  if (camera_id >= 0) {
    r.camera.type = mjCAMERA_FIXED;
    r.camera.fixedcamid = camera_id;
  } else {
    mjv_defaultFreeCamera(r.model, &r.camera);
    r.camera.azimuth = 135;
    r.camera.elevation = -25;
  }
  mjr_defaultContext(&r.context);
  r.context_made = true;  // mjr_freeContext also frees a partly made context
  try {
    mjr_makeContext(r.model, &r.context, mjFONTSCALE_100);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error("cannot create MuJoCo's render context for " + std::to_string(o.width) + "x" +
                             std::to_string(o.height) + ": " + e.what());
  }
  mjr_setBuffer(mjFB_OFFSCREEN, &r.context);
  if (r.context.currentBuffer != mjFB_OFFSCREEN) throw std::runtime_error("MuJoCo has no off-screen buffer");
  if (r.context.offWidth < o.width || r.context.offHeight < o.height)
    throw std::runtime_error("off-screen buffer is " + std::to_string(r.context.offWidth) + "x" +
                             std::to_string(r.context.offHeight) + ", smaller than the requested " +
                             std::to_string(o.width) + "x" + std::to_string(o.height));
  const std::size_t bytes = static_cast<std::size_t>(o.width) * static_cast<std::size_t>(o.height) * 3;
  r.raw.resize(bytes);
  r.rgb.resize(bytes);
}

OffscreenRenderer::~OffscreenRenderer() = default;

int OffscreenRenderer::width() const { return impl_->options.width; }
int OffscreenRenderer::height() const { return impl_->options.height; }

void OffscreenRenderer::clear_trail() { impl_->trail.clear(); }

const std::vector<std::uint8_t>& OffscreenRenderer::render(const mjData& d) {
  Impl& r = *impl_;
  const RenderOptions& o = r.options;
  assert(d.nbuffer == r.data->nbuffer && "mjData of another model");
  r.make_current();
  mjr_setBuffer(mjFB_OFFSCREEN, &r.context);

  // the state on the renderer's own data (mjv_updateScene takes it non-const)
  mj_copyData(r.data, r.model, &d);
  if (o.draw_tcp_trail && r.tcp_site >= 0) r.trail.emplace_back(r.data->site_xpos + 3 * r.tcp_site);

  // the model's geoms, then floor, paths and trail as decorations
  mjv_updateScene(r.model, r.data, &r.option, nullptr, &r.camera, mjCAT_ALL, &r.scene);
  if (r.draw_floor) {
    if (mjvGeom* g = new_decor(r.scene)) {
      const mjtNum size[3] = {2, 2, 0.1};
      const mjtNum pos[3] = {0, 0, 0};
      mjv_initGeom(g, mjGEOM_PLANE, size, pos, nullptr, kFloorRgba);
      g->category = mjCAT_DECOR;
      ++r.scene.ngeom;
    }
  }
  add_polyline(r.scene, r.path, kPathRgba, o.line_radius);
  add_polyline(r.scene, r.planned, kPlannedRgba, o.line_radius);
  if (o.draw_tcp_trail) add_polyline(r.scene, simplified(r.trail, kDrawTolerance), kTrailRgba, o.line_radius);

  // draw and read back (the read waits for llvmpipe), then flip to top-down rows
  const mjrRect viewport{0, 0, o.width, o.height};
  mjr_render(viewport, &r.scene, &r.context);
  mjr_readPixels(r.raw.data(), nullptr, viewport, &r.context);
  const std::size_t row = static_cast<std::size_t>(o.width) * 3;
  const auto rows = static_cast<std::size_t>(o.height);
  for (std::size_t y = 0; y < rows; ++y)
    std::memcpy(r.rgb.data() + y * row, r.raw.data() + (rows - 1 - y) * row, row);
  return r.rgb;
}

}  // namespace blendbench
