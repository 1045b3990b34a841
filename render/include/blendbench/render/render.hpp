#pragma once
// Headless rendering of a MuJoCo model with OSMesa (software GL, no display or GPU needed) into
// one frame of RGB pixels: the model posed from a qpos vector, seen through a CameraPose, with
// polylines (paths, trails) drawn into the 3D scene and 2D overlays (text panels, a legend,
// labels) drawn over it with MuJoCo's bitmap fonts. A frame may hold several views (a grid of
// variants): draw each into its rectangle, then read the frame once.

#include <mujoco/mujoco.h>

#include <Eigen/Geometry>

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "blendbench/render/camera.hpp"

namespace blendbench {

// A colour, components in [0, 1].
struct Rgba {
  float r = 0, g = 0, b = 0, a = 1;
};

// The video's colours, as report.html's 3D view draws the same lines: the programmed path thick
// and grey, the planned (blended) path in its method's colour (method_colour), the actual TCP thin
// and dark. None of them is a method's colour, so the legend stays unambiguous, and none occurs in
// the lit scene or its background (the grey is warm and the dark is purple, where the arm and floor
// are neutral greys, white and light blue and an empty background is black), so a line's pixels
// can be told from the scene's. Lines are drawn unlit, so their pixels carry exactly these colours.
inline constexpr Rgba kProgrammedColour{0.6f, 0.56f, 0.5f, 1};  // warm grey
inline constexpr Rgba kTrailColour{0.3f, 0.0f, 0.3f, 1};        // dark purple

// A method's colour (the method named as summary.json names it: none, arc, bezier, clothoid,
// biclothoid), the same as in the report and its plots: render/method_colours.json is the one
// table (compiled in by render/CMakeLists.txt, read by report/scripts/plotio.py); a method it
// does not list takes one of its "others", picked by the sum of the name's character codes.
Rgba method_colour(std::string_view method);

// The tool on the flange (SceneStyle::tool), drawn lit like the arm, so its pixels are shades of:
inline constexpr Rgba kToolColour{0.95f, 0.90f, 0.25f, 1};      // yellow: the tool's body, flange to TCP
inline constexpr Rgba kToolAxisColour{0.80f, 0.60f, 0.70f, 1};  // reddish purple: the tool's z axis at the TCP

// A polyline drawn over the scene as a line of constant width on screen (so a zoomed view shows
// millimetres as clearly as an overview shows the part), never hidden by the arm: the paths are
// what the video is about. Drawn in the order given, later lines over earlier ones.
struct Polyline {
  std::span<const Vec3> points;  // world frame, m (not owned)
  std::optional<Vec3> tip;       // an extra last point (a trail's current TCP)
  Rgba colour;
  double width_px = 2;
};

// A disc over the scene, `radius_px` pixels wide, with a dark rim: the TCP. (MuJoCo's own site
// would be a ball of fixed size, which a zoomed view blows up over what it should show.)
struct Marker {
  Vec3 position;  // world frame, m
  Rgba colour;
  double radius_px = 4;
};

// The tool's drawing (decorations of the scene, never geoms of the model: the tool adds no mass
// or inertia to the simulated arm): a capsule of radius kToolRadius from the flange to the TCP
// (when they are more than kMinToolLength apart) and a rod (a capsule of radius kToolAxisRadius)
// kToolAxisLength long from the TCP along the tool frame's z axis.
inline constexpr double kToolRadius = 0.012;      // m: a torch neck or a gripper's body
inline constexpr double kMinToolLength = 0.001;   // m
inline constexpr double kToolAxisLength = 0.05;   // m
inline constexpr double kToolAxisRadius = 0.006;   // m

// How the model itself is drawn: whole, or without the arm (every geom of a body other than the
// world), for a close-up of the path where the tool would only be in the way; and the tool.
struct SceneStyle {
  bool hide_arm = false;
  // The tool frame in the frame of the model's site "tcp" (the flange), m; drawn with the arm
  // (not with hide_arm, nor when the model has no site "tcp"). None: no tool is drawn.
  std::optional<Eigen::Isometry3d> tool = std::nullopt;
};

// A rectangle of the frame in pixels, measured from its top-left corner.
struct PixelRect {
  int left = 0, top = 0, width = 0, height = 0;
};

enum class Corner { kTopLeft, kTopRight, kBottomLeft, kBottomRight };

// One row of a text panel: a label (drawn grey) and its value (white).
struct TextRow {
  std::string label, value;
};

struct LegendEntry {
  Rgba colour;
  std::string text;
};

// Cost drivers of software rendering (measured: ~120 fps at 640x480 without either, ~25 fps with
// MuJoCo's defaults of shadows and 4 samples).
struct RenderQuality {
  bool shadows = false;
  int samples = 0;  // multisamples of the off-screen buffer, >= 0
};

// An OSMesa context plus MuJoCo's scene and render context for one model and one frame size. The
// renderer keeps its own copy of the model whose off-screen buffer is enlarged to the frame (so a
// model's small <visual><global offwidth offheight> is not an error) and whose headlight is
// raised to a minimum so the arm is clearly lit; when the model has no plane geom a grey floor is
// drawn at z = 0. Non-copyable; not thread-safe (it makes its context current on the calling
// thread, before every drawing call).
class OffscreenRenderer {
 public:
  // `font_scale` is one of MuJoCo's font scales (50, 100, 150, 200, 250, 300 percent; 100 is a
  // font 18 pixels high, 150 is 28). Throws std::invalid_argument for a non-positive size, negative samples or an
  // unknown font scale, std::runtime_error when OSMesa or MuJoCo's render context cannot be
  // created (e.g. a size beyond the GL limits).
  OffscreenRenderer(const mjModel& m, int width, int height, RenderQuality quality = {}, int font_scale = 100);
  ~OffscreenRenderer();
  OffscreenRenderer(const OffscreenRenderer&) = delete;
  OffscreenRenderer& operator=(const OffscreenRenderer&) = delete;

  // Poses the renderer's copy of the model: `qpos` (the model's nq values) and forward
  // kinematics. Asserts the size.
  void pose(std::span<const double> qpos);
  // The state of `d` (which must belong to the model given to the constructor): its qpos.
  void pose(const mjData& d);
  // The renderer's posed state (positions of bodies, sites and cameras are current).
  [[nodiscard]] const mjData& data() const;

  // Draws the posed model (without its sites), seen through `camera`, into `where` (cleared
  // first), then `lines` and `markers` over it. Points behind the camera break a line.
  void draw_scene(const PixelRect& where, const CameraPose& camera, std::span<const Polyline> lines,
                  std::span<const Marker> markers = {}, SceneStyle style = {});
  // Fills `where` with a colour (blended by its alpha).
  void fill(const PixelRect& where, const Rgba& colour);
  // A two-column panel of rows (labels grey, values white) on a translucent dark box, in the
  // given corner of `where`. Returns the box drawn (panel_box).
  PixelRect draw_panel(const PixelRect& where, Corner corner, const std::vector<TextRow>& rows);
  // The box draw_panel would draw.
  [[nodiscard]] PixelRect panel_box(const PixelRect& where, Corner corner, const std::vector<TextRow>& rows) const;
  // A legend: one row per entry, a short bar of its colour and its text, on a translucent dark
  // box in the given corner of `where`. Returns the box drawn (legend_box).
  PixelRect draw_legend(const PixelRect& where, Corner corner, const std::vector<LegendEntry>& entries);
  // The box draw_legend would draw.
  [[nodiscard]] PixelRect legend_box(const PixelRect& where, Corner corner, const std::vector<LegendEntry>& entries) const;
  // A filled rectangle with the text centred in it.
  void draw_label(const PixelRect& rect, const std::string& text, const Rgba& background, const Rgba& text_colour);
  // Text (UTF-8) with its top-left corner at (x, y) pixels. MuJoCo's bitmap fonts hold printable
  // ASCII only: the micro sign (U+00B5, and the Greek mu U+03BC), which the overlays need for
  // "µm", is composed from the font's own strokes (its "u" with the descender of its "p"); any
  // other character beyond ASCII is drawn as "?".
  void draw_text(int x, int y, const std::string& text, const Rgba& colour);
  // Pixel width of `text` and the height of a line of text in this renderer's font.
  [[nodiscard]] int text_width(const std::string& text) const;
  [[nodiscard]] int text_height() const;

  // Reads the frame drawn so far: width*height*3 bytes of RGB, rows top-down; valid until the
  // next call (the buffer is reused: no allocation per frame).
  const std::vector<std::uint8_t>& read();

  [[nodiscard]] int width() const;
  [[nodiscard]] int height() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The font scale that keeps text readable in a view `height` pixels tall (100 up to 540, then
// 150 up to 900, then 200).
int font_scale_for(int height);

// Douglas-Peucker simplification: the indices (ascending, both ends kept) of the fewest points
// such that every dropped point lies within `tolerance` (m) of the simplified polyline.
std::vector<std::size_t> simplify(std::span<const Vec3> points, double tolerance);

// The named camera of the model at the state `d` (its current pose and field of view), or none
// when the model has no camera of that name.
std::optional<CameraPose> model_camera(const mjModel& m, const mjData& d, const std::string& name);

}  // namespace blendbench
