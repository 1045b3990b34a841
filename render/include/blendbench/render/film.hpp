#pragma once
// The videos of a run, rendered after the simulation from what it recorded: the arm's pose
// (qpos) at a fixed rate, and per setpoint the actual TCP, its speed and its errors. No frame is
// kept: each is drawn, read and handed to the encoder.
//
// What a frame shows: the arm; the programmed path (blue), the planned path (orange) and the
// actual TCP's trail so far (bluish green) as lines of constant width on screen, layered so that
// where they coincide all three show (blue outside, orange, green inside); the TCP as a red ball;
// the tool on the flange when the robot has one (yellow, its z axis reddish purple); a legend of
// the colours; a panel with the time, the variant, the TCP's path speed and
// its tracking error at that instant.
//
// - variant video: one variant, the whole run (to the end of the settle time).
// - comparison (compare video): every variant of the scenario in a grid, synchronised (each
//   cell shows its variant at the same time t; a variant that is done holds its last pose with
//   "done at t = ... s" and its rank), below a header with the scenario, t and the legend; then a
//   second segment in slow motion, zoomed on the worst corner (the corner with the largest
//   contour error against the programmed path, of any variant), each cell at its own passage
//   through that corner.

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "blendbench/program/corner_placement.hpp"
#include "blendbench/render/camera.hpp"
#include "blendbench/render/render.hpp"
#include "blendbench/sim/metrics.hpp"
#include "blendbench/sim/trace.hpp"

namespace blendbench {

// What one variant's videos need, recorded while it ran (world frame, SI units).
struct VariantFilm {
  std::string name;
  std::string method;          // as summary.json names it: the planned path's colour (method_colour)
  std::string failure;         // non-empty: the variant has no motion to show, and why
  std::vector<Vec3> planned;   // the planned (blended) path, densely sampled
  // the arm's pose from the simulation, pose k at t = k / pose_rate_hz from t = 0
  double pose_rate_hz = 0;
  std::vector<double> qpos;    // poses x the model's nq
  // per setpoint of the trace, sample i at t = i * sample_period
  double sample_period = 0;
  std::vector<Vec3> tcp;                // actual TCP, m
  std::vector<double> speed;            // actual TCP speed, m/s
  std::vector<double> tracking_error;   // m
  std::vector<double> contour_error;    // m, to the programmed path
  double reference_end = 0;             // s: when the reference (the planned motion) ended
  std::optional<double> done_time;      // s: the cycle time (settled); none: did not settle
  std::vector<CornerTiming> corners;    // when the reference passes each corner
};

// Copies what a film needs from a finished run's trace and metrics (per sample: actual TCP,
// speed, tracking and contour error; the reference's end, the cycle time; the corners' times).
void record_run(VariantFilm& film, const Trace& trace, const Metrics& metrics, const std::vector<CornerTiming>& corners);

// Where the camera stands (CameraPose states the angle convention).
//   kPart:  frame_part on the programmed path (the default);
//   kFixed: at `position`, looking at `look_at`;
//   kTcp:   following the actual TCP from `distance`, at azimuth / elevation (default: the part
//           camera's angles).
struct CameraSpec {
  enum class Mode { kPart, kFixed, kTcp };
  Mode mode = Mode::kPart;
  PartFraming part;                                  // kPart (its angles also serve kTcp)
  Vec3 position = Vec3(1.2, -0.8, 0.8);              // kFixed, m
  Vec3 look_at = Vec3(0.4, 0, 0.2);                  // kFixed, m
  double distance = 0.35;                            // kTcp, m
  double fovy_deg = 45;                              // kFixed, kTcp
};

// What every video of a run shares.
struct FilmSettings {
  int width = 640, height = 480;  // pixels of one view (a comparison cell is scaled to fit)
  double fps = 30;
  CameraSpec camera;
  RenderQuality quality;
  std::string scenario;               // named in the comparison's header
  std::vector<Vec3> programmed;       // the programmed path, densely sampled, m
  std::vector<CornerPlacement> corners;  // the programmed corners (points by corner index)
  // The corners' names by corner index, as corners.json, report.html and the plots name them:
  // "C<index>" and the program line, e.g. "C7 (bracket.ngc:110)"; a corner not named here is
  // "C<index>".
  std::map<int, std::string> corner_names;
  // The program frame in the base frame: the worst corner's point is shown in program coordinates.
  Eigen::Isometry3d program_frame = Eigen::Isometry3d::Identity();
  Vec3 base = Vec3::Zero();           // the robot base (the part camera looks away from it)
  // The tool frame in the flange frame (the model's site "tcp"), m: drawn on the arm
  // (SceneStyle::tool) and named in the legend; none: no tool.
  std::optional<Eigen::Isometry3d> tool;
};

// How far a render has come: frames drawn of the total.
using FilmProgress = std::function<void(int done, int total)>;

// Where a frame's overlays were drawn (frame pixels). Each overlay goes to the corner of its view
// that hides the least of the projected path (the programmed and planned lines): the panel
// preferring top left, top right, bottom right, bottom left; the legend, in a variant's video,
// bottom left, bottom right, top right, top left of the corners the panel left.
struct OverlayBoxes {
  PixelRect panel, legend;  // legend: empty in a comparison's cell (the header holds it)
};

// One variant's video, frame by frame (t = k / fps, k < frames()).
class VariantVideo {
 public:
  // Throws std::invalid_argument for a film without poses (a failed variant).
  VariantVideo(const mjModel& m, const VariantFilm& film, const FilmSettings& settings);
  ~VariantVideo();
  VariantVideo(const VariantVideo&) = delete;
  VariantVideo& operator=(const VariantVideo&) = delete;

  [[nodiscard]] int frames() const;
  // Frame k: width*height*3 bytes of RGB, rows top-down; valid until the next call.
  const std::vector<std::uint8_t>& frame(int k);
  // The camera of frame k.
  [[nodiscard]] CameraPose camera(int k) const;
  // The overlays of the last frame drawn.
  [[nodiscard]] const OverlayBoxes& overlays() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The comparison's geometry: a grid of columns x rows cells of cell_width x cell_height pixels
// (the view size scaled down, never up, so the whole fits 1920x1080), below a header strip.
struct CompareLayout {
  int columns = 1, rows = 1;
  int cell_width = 0, cell_height = 0;
  int header = 0;
  int width = 0, height = 0;  // the whole frame
  [[nodiscard]] PixelRect cell(int i) const;
};
// Columns: every variant in one row up to three, else ceil(sqrt(n)); header: two lines of text
// of the cells' font. `variants` >= 1.
CompareLayout compare_layout(int variants, int view_width, int view_height);

// The worst corner of a set of runs: the corner index whose contour error against the programmed
// path (any variant, from kCornerMargin before its transition to kCornerMargin after) is largest.
struct WorstCorner {
  int index = -1;            // corner index (CornerPlacement::index); -1: no corner
  Vec3 point = Vec3::Zero();
  double contour_error = 0;  // m
};
inline constexpr double kCornerMargin = 0.05;  // s
WorstCorner worst_corner(const std::vector<VariantFilm>& films, const std::vector<CornerPlacement>& corners);

// The comparison, frame by frame: the synchronised segment, then the slow-motion zoom.
class CompareVideo {
 public:
  // `films` in the scenario's order; at least one. Failed variants get a cell with their failure.
  CompareVideo(const mjModel& m, const std::vector<VariantFilm>& films, const FilmSettings& settings);
  ~CompareVideo();
  CompareVideo(const CompareVideo&) = delete;
  CompareVideo& operator=(const CompareVideo&) = delete;

  [[nodiscard]] const CompareLayout& layout() const;
  [[nodiscard]] int frames() const;          // both segments
  [[nodiscard]] int synchronised_frames() const;  // the first segment
  const std::vector<std::uint8_t>& frame(int k);
  [[nodiscard]] const WorstCorner& corner() const;
  // The overlays of cell `cell` (a variant's index) in the last frame drawn with it.
  [[nodiscard]] const OverlayBoxes& overlays(int cell) const;

  // The zoom runs kSlowMotion times slower than real time.
  static constexpr int kSlowMotion = 4;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Renders a video to `path` (VideoWriter: atomic), calling `progress` after every frame; returns
// the number of frames. Throws as VideoWriter and the videos' constructors do.
int write_variant_video(const mjModel& m, const VariantFilm& film, const FilmSettings& settings, const std::string& path,
                        const FilmProgress& progress = {});
int write_compare_video(const mjModel& m, const std::vector<VariantFilm>& films, const FilmSettings& settings,
                        const std::string& path, const FilmProgress& progress = {});

}  // namespace blendbench
