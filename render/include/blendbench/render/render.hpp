#pragma once
// Headless rendering of a MuJoCo model with OSMesa (software GL, no display or GPU needed), with
// the programmed path, the planned (blended) path and the trail of the actual TCP drawn into the
// scene. One renderer per video; frames come out as RGB rows, top row first.

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace blendbench {

struct RenderOptions {
  int width = 640, height = 480;  // pixels, > 0
  // A named camera of the model; when it is absent (or empty) a free camera looks at the model's
  // centre from the front-right and above.
  std::string camera = "overview";
  std::vector<Eigen::Vector3d> path_polyline;     // programmed path, world frame, m (blue)
  std::vector<Eigen::Vector3d> planned_polyline;  // blended path, world frame, m (orange), optional
  bool draw_tcp_trail = true;                     // trail of the actual TCP (green), one point per frame
  // m, radius of the capsules drawing the polylines and the trail; without multisampling a line
  // thinner than a pixel may vanish (at 640x480 a workspace seen from 2 m has ~3 mm pixels)
  double line_radius = 0.004;
  // Cost drivers of software rendering (measured with Mesa llvmpipe on 2 vCPUs: ~120 fps at
  // 640x480 without either, ~25 fps with MuJoCo's defaults of shadows and 4 samples).
  bool shadows = false;
  int samples = 0;  // multisamples of the off-screen buffer
};

// An OSMesa context plus MuJoCo's scene and render context for one model. The renderer keeps its
// own copy of the model whose off-screen buffer is enlarged to the requested size (so a model's
// small <visual><global offwidth offheight> is not an error) and whose headlight is raised to a
// minimum so the arm is clearly lit; when the model has no plane geom a grey floor is drawn at
// z = 0. Non-copyable; not thread-safe (it makes its context current on the calling thread).
class OffscreenRenderer {
 public:
  // Throws std::invalid_argument for a non-positive size, std::runtime_error when OSMesa or
  // MuJoCo's render context cannot be created (e.g. a size beyond the GL limits).
  OffscreenRenderer(const mjModel& m, RenderOptions options);
  ~OffscreenRenderer();
  OffscreenRenderer(const OffscreenRenderer&) = delete;
  OffscreenRenderer& operator=(const OffscreenRenderer&) = delete;

  // Renders the state in d (which must belong to the model given to the constructor, with
  // current kinematics, e.g. from RunOptions::on_frame) and appends its TCP to the trail.
  // Returns width*height*3 bytes of RGB, rows top-down; valid until the next call.
  const std::vector<std::uint8_t>& render(const mjData& d);

  // Forgets the TCP trail (e.g. between two runs rendered with one renderer).
  void clear_trail();

  [[nodiscard]] int width() const;
  [[nodiscard]] int height() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace blendbench
