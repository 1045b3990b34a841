#pragma once
// The blended path: a sequence of arc-length-parameterised pieces (trimmed moves and
// transition curves) plus a report per corner.

#include <algorithm>
#include <optional>
#include <string>
#include <vector>

#include "blendbench/core/note.hpp"
#include "blendbench/program/corner_case.hpp"
#include "blendbench/program/program.hpp"
#include "blendbench/geometry/segment.hpp"

namespace blendbench {

// What the blender did at one corner (between move `index` and move `index + 1`).
struct CornerReport {
  int index = 0;
  Method method = Method::kNone;
  CornerCase corner_case = CornerCase::kRegular;
  Fallback fallback = Fallback::kNone;
  Note note;                          // e.g. "parameter shrunk from 5 mm to 2.1 mm: move 3 is short" (note.hpp: made text when read)
  double parameter = 0;               // m: the transition parameter actually used (a biclothoid
                                      // sized by start distance: the start distance used)
  double length = 0;                  // m: transition length (0 for a kink or zero-length transition)
  double deviation = 0;               // m: Hausdorff distance (both directions) between the transition and the programmed path it replaces
  double kappa_max = 0;               // 1/m
  double sharpness_max = 0;           // 1/m^2
  double feed_max = 0;                // m/s: eq. 25-27 limit of the transition (0 when no transition)
  double trim_in = 0;                 // m removed from the end of the incoming move
  double trim_out = 0;                // m removed from the start of the outgoing move
  bool stop = false;                  // the path velocity must reach zero here
  CurvatureSteps curvature_steps = CurvatureSteps::kLimit;  // the transition's (program.hpp)
  double orientation_change = 0;      // rad: the tool's rotation from the transition's start to its end (0 without one)
  // Equal tolerance (Transition::tolerance, docs/methods.md): the tolerance asked for (m, 0 when
  // the corner is sized by its parameter) and whether the deviation reached it: within
  // [tolerance (1 - kToleranceBand), tolerance] (corner.hpp). False where the moves are too short
  // (the largest transition that fits), where the method cuts nothing (the note says why) and
  // without a tolerance.
  double tolerance = 0;
  bool tolerance_reached = false;
  // Where the move that ends at the corner was written (Move::where: file and line; a merged
  // run of lines: its last move).
  SourceRef source = {};
};

// One piece of the path.
// Angle (rad) below which two tangents count as continuous (G1) at a junction: the blender
// inserts no transition there and the velocity planner sees no kink.
inline constexpr double kG1Angle = 1e-9;

struct PathPiece {
  Segment segment;
  int move = -1;    // index of the programmed move this piece comes from, -1 for a transition
  int corner = -1;  // index of the corner a transition belongs to, -1 for a move piece
  Limits limits;    // limits that apply on this piece
  BufferMode buffer = BufferMode::kBlendingLow;
  // At the start of this piece: the path must be at rest (exact stop or Buffered kink), and
  // the tangent turns by `kink_angle` (rad, 0 where the path is G1).
  bool stop_before = false;
  double kink_angle = 0;
  // The curvature jump at the start of this piece may step (the corner it belongs to has
  // curvature_steps: allow); else the junction rule bounds it.
  bool curvature_step_allowed = false;
  // Where the move it comes from was written (a transition: the move its limits come from, the
  // outgoing one unless the incoming one sets its velocity), for errors.
  SourceRef where = {};
  // The tool orientation along the piece (orientation.hpp); none when the program sets no
  // orientation (the tool keeps the robot's fixed orientation).
  std::optional<PieceOrientation> orientation = {};
};

class Path {
 public:
  // Appends a piece; its start must coincide with the current end (asserted in debug builds).
  void append(PathPiece piece);
  // Room for `count` pieces in all, so that appending them moves none (a piece is some 400
  // bytes, and a CAM program has hundreds of thousands).
  void reserve(std::size_t count) {
    pieces_.reserve(count);
    offsets_.reserve(count + 1);
  }

  [[nodiscard]] const std::vector<PathPiece>& pieces() const { return pieces_; }
  [[nodiscard]] double length() const { return offsets_.empty() ? 0.0 : offsets_.back(); }
  // Arc length at the start of piece k (k <= pieces().size()).
  [[nodiscard]] double offset(std::size_t k) const { return offsets_[k]; }

  // Piece index and local arc length at path arc length s (clamped to [0, length]).
  struct Location {
    std::size_t piece;
    double s;
  };
  [[nodiscard]] Location locate(double s) const;

  // Calls f(k, local) for every piece k that touches arc length s (both neighbours at a
  // junction, within 1e-12 of the path's length, at least 1e-12 m), local clamped to the piece.
  template <typename F>
  void for_pieces_at(double s, F&& f) const {
    const double tol = 1e-12 * std::max(1.0, length());
    std::size_t first = locate(s).piece;
    std::size_t last = first;
    while (first > 0 && offsets_[first] >= s - tol) --first;
    while (last + 1 < pieces_.size() && offsets_[last + 1] <= s + tol) ++last;
    for (std::size_t k = first; k <= last; ++k) {
      if (s < offsets_[k] - tol || s > offsets_[k + 1] + tol) continue;
      f(k, std::clamp(s - offsets_[k], 0.0, blendbench::length(pieces_[k].segment)));
    }
  }

  [[nodiscard]] Vec3 point(double s) const;
  [[nodiscard]] Vec3 tangent(double s) const;
  [[nodiscard]] Vec3 curvature_vector(double s) const;
  // Whether the pieces carry an orientation (the program sets one); the orientation (unit
  // quaternion, base frame) and dtheta/ds (rad/m, base frame) at arc length s; identity and
  // zero on a path without orientation.
  [[nodiscard]] bool oriented() const { return !pieces_.empty() && pieces_.front().orientation.has_value(); }
  [[nodiscard]] Quat orientation(double s) const;
  [[nodiscard]] Vec3 angular_rate(double s) const;

  std::vector<CornerReport> corners;
  // Collinear lines merged before blending (Transition::merge_tolerance, G64 Q): how many moves
  // the merging removed and the largest tolerance it used (m). Move and corner indices in the
  // pieces and reports are the program's own, before merging (a merged line is its first move).
  int moves_merged = 0;
  double merge_tolerance = 0;
  // What smoothing did (Program::smoothing, smoothing.hpp): the streams replaced by curves,
  // whose pieces carry the move their start lies on; the stream's inner vertices have no corner
  // report.
  SmoothingReport smoothing;

 private:
  std::vector<PathPiece> pieces_;
  std::vector<double> offsets_{0.0};
};

}  // namespace blendbench
