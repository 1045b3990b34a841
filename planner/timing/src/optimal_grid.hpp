#pragma once
// Internal to the optimal velocity planner (optimal.cpp): the grid in s on which the profile is
// optimised, and what holds at each of its nodes. Not installed.
//
// Nodes: both ends of the path, every junction between pieces of non-zero length, the ends of
// the hand-over zones (where the feed term changes), kBezierCells equal parts of every Bezier
// (whose curvature peaks inside), and in between one node every piece_spacing of the starting
// profile's time (a share of the jerk phase at the speed there), so that a jerk phase spans
// several cells. A node at a stop is a rest:
// the path is cut there into stretches from rest to rest, each optimised on its own.
//
// Each node has a side for the cell before it and one for the cell after it: the geometry and
// the limits of the piece on that side (at a junction the two pieces differ; inside a piece both
// sides are one). Everything here is in SI units (m, s, rad).

#include <cstdint>
#include <vector>

#include "blendbench/program/path.hpp"
#include "blendbench/timing/timing.hpp"
#include "seed004.hpp"

namespace blendbench::timing_detail {

// The tool's angular rate along the path at one side of a node: rho = dtheta/ds and its first
// two derivatives in s (rad/m, rad/m^2, rad/m^3; orientation.hpp), and the angular acceleration
// and jerk limits there (rad/s^2, rad/s^3; infinite when not limited).
struct SideRotation {
  Vec3 rate = Vec3::Zero();
  Vec3 d1 = Vec3::Zero();
  Vec3 d2 = Vec3::Zero();
  double acceleration = 0;
  double jerk = 0;
};

// The geometry and limits of the piece on one side of a node.
struct NodeSide {
  std::uint32_t piece = 0;
  Vec3 t = Vec3::Zero();   // unit tangent
  Vec3 k = Vec3::Zero();   // curvature vector kappa N (1/m)
  Vec3 dk = Vec3::Zero();  // d^3p/ds^3 (1/m^2)
  // the piece's acceleration (speeding up), deceleration and jerk limits: on the TCP's vectors
  // (cartesian) or along the path (path mode)
  double acceleration = 0, deceleration = 0, jerk = 0;
  // cartesian, at a curvature step whose rule applies (curvature_steps: limit): the step of the
  // curvature vector divided by the servo period, (k_before - k_after) / dt (1/(m s)): the
  // normal acceleration steps by |step| v^2 dt within one period, which the node's jerk limit
  // must hold together with the jerk on either side (optimal_problem.cpp); zero elsewhere
  Vec3 step = Vec3::Zero();
  // factors (<= 1) on every acceleration and jerk limit held here (vector, axes, rotation):
  // tightened where the sampled motion between nodes exceeded a limit (optimal.cpp)
  double tighten_acceleration = 1;
  double tighten_jerk = 1;
  int rotation = -1;  // index into Grid::rotations; -1 where the tool does not rotate (or is not limited)
};

// What bounds a node's speed from above (Grid::b_max), for the pieces' reports.
enum class NodeCap : std::uint8_t { kNone, kFeed, kCurvature, kSharpness, kRotation, kJunction };

struct GridNode {
  double s = 0;        // m, global arc length
  bool rest = false;   // the path is at rest here (a stop, or an end)
  double b_max = 0;    // m^2/s^2: the bound on v^2 (feed, junction rules, path-mode and rotation caps)
  NodeCap cap = NodeCap::kNone;
  std::uint32_t left = 0;   // side index for the cell before (unused at the first node)
  std::uint32_t right = 0;  // side index for the cell after (unused at the last node)
  // The middle of the cell after this node (none after the last): its side and the bound on v^2
  // there (feed, path-mode and rotation caps; no junction rule), held there too so that the
  // profile cannot gain time by bulging above a cap between nodes (fill_middles).
  std::uint32_t middle = kNoMiddle;
  double middle_b_max = 0;
  // The cell after this node holds the third-difference window of a limited curvature step at
  // one of its ends: it is never split (build_grid).
  bool keep = false;
  // The tangential acceleration is held at 0 here: a junction's speed bound so far below the
  // pieces' own that the profile is slowest there (a kink's j dt^2 rule), where v^2 may be ten
  // decades below its neighbours' and a cell's b would dip below zero before reaching the node
  // (build_grid).
  bool pinned = false;
  static constexpr std::uint32_t kNoMiddle = 0xffffffffu;
};

struct Grid {
  std::vector<GridNode> nodes;
  std::vector<NodeSide> sides;
  std::vector<SideRotation> rotations;
  std::vector<std::size_t> rests;  // indices of the rest nodes, first 0 and last nodes.size() - 1
  LimitsMode mode = LimitsMode::kCartesian;
  std::optional<AxisLimits> axes;  // cartesian only
  double dt = 0;
};

// The node spacing in time (s) the grid aims at on a piece where the profile runs at speed v (m/s):
// a share of its jerk phase (min(acceleration, deceleration) / jerk, shorter at low speed:
// kSlowPhase sqrt(v / jerk)), at least half a servo period and at most kMaxNodeTime.
double piece_spacing(const PathPiece& piece, const TimingOptions& options, double v);

// Builds the grid of `path` (validated; `prepared` from prepare(), its joints and zones) with
// one node every piece_spacing times `stretch` (at least `tau`, s) of the profile `start` (seed
// 004's chained spans) between the mandatory nodes above. Every stretch between two rests gets at least
// kMinCells cells.
Grid build_grid(const Path& path, const TimingOptions& options, const Prepared& prepared, const std::vector<Span>& start,
                double tau, double stretch = 1);

// Splits the cells [nodes[i], nodes[i + 1]] for every i in `cells` (sorted, unique) at their
// middles, filling the new nodes' sides from the path; `values` (one per node, e.g. v^2 and
// a) are extended by f(i) for each new node after node i, in order.
template <class F>
void split_cells(Grid& grid, const Path& path, const TimingOptions& options, const Prepared& prepared,
                 const std::vector<std::size_t>& cells, F f);

// Fills every cell's middle (GridNode::middle, middle_b_max) from the path.
void fill_middles(Grid& grid, const Path& path, const TimingOptions& options, const Prepared& prepared);

// The node of `grid` at global arc length s inside piece `piece` (not at its junctions):
// sides, b_max and cap from the path (used by build_grid and split_cells).
GridNode interior_node(Grid& grid, const Path& path, const TimingOptions& options, const Prepared& prepared,
                       std::size_t piece, double s);

// The rotation jet at local arc length `local` of a piece with an orientation (see
// SideRotation): rho exact, rho' and rho'' by central differences (one-sided at the ends).
SideRotation rotation_jet(const PieceOrientation& orientation, double length, double local);

template <class F>
void split_cells(Grid& grid, const Path& path, const TimingOptions& options, const Prepared& prepared,
                 const std::vector<std::size_t>& cells, F f) {
  if (cells.empty()) return;
  std::vector<GridNode> nodes;
  nodes.reserve(grid.nodes.size() + cells.size());
  std::size_t next = 0;
  for (std::size_t i = 0; i < grid.nodes.size(); ++i) {
    nodes.push_back(grid.nodes[i]);
    if (next < cells.size() && cells[next] == i) {
      ++next;
      nodes.back().middle = GridNode::kNoMiddle;
      const double s = 0.5 * (grid.nodes[i].s + grid.nodes[i + 1].s);
      const std::size_t piece = path.locate(s).piece;
      nodes.push_back(interior_node(grid, path, options, prepared, piece, s));
      f(i);
    }
  }
  grid.nodes = std::move(nodes);
  grid.rests.clear();
  for (std::size_t i = 0; i < grid.nodes.size(); ++i) {
    if (grid.nodes[i].rest) grid.rests.push_back(i);
  }
  fill_middles(grid, path, options, prepared);
}

}  // namespace blendbench::timing_detail
