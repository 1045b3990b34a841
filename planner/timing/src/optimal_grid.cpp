#include "optimal_grid.hpp"

#include <algorithm>
#include <cmath>

#include "blendbench/corner/blend.hpp"
#include "blendbench/timing/profile_margins.hpp"

namespace blendbench::timing_detail {
namespace {

// Equal parts of a Bezier piece that get a node each: its curvature peaks inside the piece, and
// a node holds the limits where it is (the sampled check covers the rest).
constexpr int kBezierCells = 16;
// Parts of a clothoid (curvature linear in s, so extreme at its ends): one node in the middle.
constexpr int kClothoidCells = 2;
// The longest node spacing in time (s): a long cruise needs no finer grid, but the speed along
// a feed-bound stretch still follows the path's curvature between nodes only through the
// sampled check.
constexpr double kMaxNodeTime = 0.05;
// Nodes per jerk phase: the profile's tangential acceleration is linear in s between nodes, and a
// jerk phase (A / J in time) spans this many cells.
constexpr double kNodesPerJerkPhase = 12;
// Where the profile is slow the phases it can use are shorter than A / J: a jerk-limited change
// of the speed by v (from a = 0 back to a = 0) takes 2 sqrt(v / J) when v < A^2 / J, so the jerk
// phase the grid spaces its nodes by is the shorter of A / J and this factor times sqrt(v / J)
// at the starting profile's speed v (a quarter of the time of doubling the speed). Measured
// against the same problem on a 4x finer grid (optimal_test, AFourTimesFinerGrid...): with A / J
// alone the grid lost 0.7-0.9 % near the default scenario's limited curvature steps (the profile
// brakes to 20-50 mm/s there under J = 50 m/s^3) and 12 % on a random path (seed 43100002: an arc
// of 3.7 mm under J = 2.7 m/s^3, A / J = 0.55 s, crossed at 10-20 mm/s in 0.3 s, got 4 cells);
// with 1 the worst was 0.50 % (arc_10mm), with 0.5 it is 0.23 %, and the default scenario's
// variants plan in 0.59 times the time in all (fewer refinement rounds; docs/timing.md).
constexpr double kSlowPhase = 0.5;
// A junction whose bound on v^2 is below this share of its pieces' own (feed, curvature) is the
// profile's slowest point there, with a = 0 (GridNode::pinned).
constexpr double kPinShare = 1e-4;
// The least time (in units of its spacing, of the starting profile) between a time mark and a
// mandatory one ...
constexpr double kMinTimeGap = 0.5;
// ... where its spacing counts as at least this share of its piece's at full speed: where the
// starting profile creeps (next to a junction's tiny speed bound) a gap of the spacing at its
// own speed left cells so short that the barrier method's first centring never reached its
// equalities on the CAM contour's clothoid_points (15,968 nodes, which then fell back to seed
// 004's plan, 17.38 s against 11.98); at 1/2 it converges there, and the grid agrees with the
// 4x finer one within 0.23 % (1/4: 0.66 % on seed 43100002; 1: 0.37 % on bezier_0.5mm).
constexpr double kLeastGapShare = 0.5;
// Every stretch between two rests gets at least this many cells: the first and last are the
// constant-jerk cells at the rests, and a cell between them carries the rest.
constexpr std::size_t kMinCells = 4;
// At a limited curvature step (cartesian): the largest weight a third difference of the sampled
// positions gives a step of the acceleration (3/4: the peak of the quadratic B-spline that the
// difference of a truncated quadratic makes), and the share of the jerk limit the step leaves to
// the path's own jerk there.
constexpr double kStepWeight = 0.75;
constexpr double kStepJerkShare = 0.1;
// The reach of a third difference across a curvature step, in servo periods either side of it
// (a stencil of four samples around the step spans at most two periods to each side), with a
// margin for the speed changing there.
constexpr double kStepWindow = 2.5;
// Mandatory nodes closer than this share of the path's length are one node (a piece shorter than
// that is crossed within the cell; the sampled check holds it).
constexpr double kMergeShare = 1e-9;
// The difference step of rotation_jet as a share of the piece (as rotation_bounds does,
// orientation.cpp: small against the quintic's scale, large against rounding).
constexpr double kRotationDifferenceShare = 1e-3;

// A node-to-be: where, and what makes it mandatory.
struct Mark {
  double s = 0;
  double t = 0;  // s, the starting profile's time there
  bool mandatory = false;
  bool rest = false;
  int joint = -1;  // index into prepared.joints at a junction
  double spacing = 0;       // s, a time mark's own spacing (piece_spacing at the starting profile's speed)
  double full_spacing = 0;  // s, and its piece's at full speed (a jerk phase of A / J)
};

NodeSide make_side(Grid& grid, const Path& path, const TimingOptions& options, std::size_t k, double local) {
  const PathPiece& piece = path.pieces()[k];
  const SegmentFrame f = frame(piece.segment, local);
  NodeSide side;
  side.piece = static_cast<std::uint32_t>(k);
  side.t = f.tangent;
  side.k = f.curvature;
  side.dk = f.curvature_derivative;
  side.acceleration = piece.limits.acceleration;
  side.deceleration = piece.limits.deceleration;
  side.jerk = piece.limits.jerk;
  if (piece.orientation) {
    const AngularLimits& lim = piece.orientation->limits;
    if (std::isfinite(lim.acceleration) || std::isfinite(lim.jerk)) {
      SideRotation r = rotation_jet(*piece.orientation, length(piece.segment), local);
      r.acceleration = lim.acceleration;
      r.jerk = lim.jerk;
      side.rotation = static_cast<int>(grid.rotations.size());
      grid.rotations.push_back(r);
    }
  }
  (void)options;
  return side;
}

// Lowers node.b_max to `b` (m^2/s^2) where that is lower, recording what bounds it.
void cap_node(GridNode& node, double b, NodeCap cap) {
  if (b < node.b_max) {
    node.b_max = b;
    node.cap = cap;
  }
}

// The caps a side puts on its node's speed: the feed (with hand-over zones), the path mode's
// eq. 25-26 terms (seed 004), the tool's angular velocity limit.
void side_caps(GridNode& node, const Path& path, const TimingOptions& options, const Prepared& prepared, std::size_t k,
               double local) {
  const PathPiece& piece = path.pieces()[k];
  const double feed = feed_at(path, prepared.zones, k, local);
  cap_node(node, feed * feed, NodeCap::kFeed);
  if (options.limits == LimitsMode::kPath) {
    const double kappa = curvature_vector(piece.segment, local).norm();
    const double c = sharpness(piece.segment, local);
    if (kappa > 0) cap_node(node, piece.limits.acceleration / kappa, NodeCap::kCurvature);
    const double eq26 = std::hypot(c, kappa * kappa);
    if (eq26 > 0) cap_node(node, std::pow(piece.limits.jerk / eq26, 2.0 / 3.0), NodeCap::kSharpness);
  }
  if (piece.orientation && std::isfinite(piece.orientation->limits.velocity)) {
    const double rate = angular_rate_at(*piece.orientation, local).norm();
    if (rate > 0) {
      const double v = piece.orientation->limits.velocity / rate;
      cap_node(node, v * v, NodeCap::kRotation);
    }
  }
}

// The node at a junction of `prepared.joints[j]`.
GridNode junction_node(Grid& grid, const Path& path, const TimingOptions& options, const Prepared& prepared, std::size_t j,
                       bool rest) {
  const Junction& jn = prepared.joints[j];
  const PathPiece& prev = path.pieces()[jn.prev];
  const PathPiece& next = path.pieces()[jn.next];
  GridNode node;
  node.s = path.offset(jn.next);
  node.rest = rest;
  node.b_max = kInf;
  const double len_prev = length(prev.segment);
  NodeSide left = make_side(grid, path, options, jn.prev, len_prev);
  NodeSide right = make_side(grid, path, options, jn.next, 0.0);
  side_caps(node, path, options, prepared, jn.prev, len_prev);
  side_caps(node, path, options, prepared, jn.next, 0.0);
  if (!rest) {
    const double sides = node.b_max;
    cap_node(node, jn.cap_kink * jn.cap_kink, NodeCap::kJunction);
    // a speed bound far below the pieces' own: the profile's slowest point, where it turns from
    // braking to speeding up (a = 0)
    node.pinned = node.b_max < kPinShare * sides;
    if (jn.dk > 0 && !next.curvature_step_allowed) {
      if (options.limits == LimitsMode::kPath) {
        // seed 004's tangential model: the step of the normal acceleration within j dt
        cap_node(node, std::min(prev.limits.jerk, next.limits.jerk) * options.dt / jn.dk, NodeCap::kJunction);
      } else {
        // a step of the acceleration by dk v^2 between two samples enters a third difference of
        // the positions with a weight of at most 3/4 (the largest value of the quadratic B-spline
        // the difference stencil makes of it); the rest of the stencil is the jerk's average
        const Vec3 step = kStepWeight * (left.k - right.k) / options.dt;
        left.step = step;
        right.step = step;
        // and the step alone may take at most (1 - kStepJerkShare) of the jerk limit, on the
        // vector and on each axis (else the optimum sits where the jerk budget vanishes, the
        // apex of its cone, where a barrier method crawls)
        const double jerk = std::min(prev.limits.jerk, next.limits.jerk);
        cap_node(node, (1 - kStepJerkShare) * jerk / step.norm(), NodeCap::kJunction);
        if (options.axis_limits) {
          for (int x = 0; x < 3; ++x) {
            if (std::abs(step(x)) > 0) {
              cap_node(node, (1 - kStepJerkShare) * options.axis_limits->jerk(x) / std::abs(step(x)), NodeCap::kJunction);
            }
          }
        }
      }
    }
  }
  node.left = static_cast<std::uint32_t>(grid.sides.size());
  grid.sides.push_back(left);
  node.right = static_cast<std::uint32_t>(grid.sides.size());
  grid.sides.push_back(right);
  return node;
}

// The two ends of the path (rests), on its first and last pieces of non-zero length.
GridNode end_node(Grid& grid, const Path& path, const TimingOptions& options, const Prepared& prepared, bool first) {
  const auto& pieces = path.pieces();
  std::size_t k = first ? 0 : pieces.size() - 1;
  while (length(pieces[k].segment) <= 0 && (first ? k + 1 < pieces.size() : k > 0)) first ? ++k : --k;
  GridNode node = interior_node(grid, path, options, prepared, k, first ? path.offset(k) : path.offset(k + 1));
  node.s = first ? 0.0 : path.length();
  node.rest = true;
  return node;
}

}  // namespace

SideRotation rotation_jet(const PieceOrientation& orientation, double length, double local) {
  SideRotation r;
  r.rate = angular_rate_at(orientation, local);
  if (std::holds_alternative<GeodesicOrientation>(orientation.law) || !(length > 0)) return r;
  const double h = kRotationDifferenceShare * length;
  const double c = std::clamp(local, h, length - h);
  const Vec3 lo = angular_rate_at(orientation, c - h);
  const Vec3 mid = angular_rate_at(orientation, c);
  const Vec3 hi = angular_rate_at(orientation, c + h);
  r.d1 = (hi - lo) / (2 * h);
  r.d2 = (hi - 2 * mid + lo) / (h * h);
  return r;
}

GridNode interior_node(Grid& grid, const Path& path, const TimingOptions& options, const Prepared& prepared,
                       std::size_t piece, double s) {
  GridNode node;
  node.s = s;
  node.b_max = kInf;
  const double local = std::clamp(s - path.offset(piece), 0.0, length(path.pieces()[piece].segment));
  node.left = node.right = static_cast<std::uint32_t>(grid.sides.size());
  grid.sides.push_back(make_side(grid, path, options, piece, local));
  side_caps(node, path, options, prepared, piece, local);
  return node;
}

void fill_middles(Grid& grid, const Path& path, const TimingOptions& options, const Prepared& prepared) {
  for (std::size_t i = 0; i + 1 < grid.nodes.size(); ++i) {
    GridNode& node = grid.nodes[i];
    if (node.middle != GridNode::kNoMiddle) continue;
    const double s = 0.5 * (node.s + grid.nodes[i + 1].s);
    const NodeSide& right = grid.sides[node.right];
    // the piece of the cell (every junction is a node, but for merged tiny pieces)
    std::size_t piece = right.piece;
    if (!(s >= path.offset(piece) && s <= path.offset(piece + 1))) piece = path.locate(s).piece;
    const GridNode middle = interior_node(grid, path, options, prepared, piece, s);
    node.middle = middle.right;
    node.middle_b_max = middle.b_max;
  }
}

double piece_spacing(const PathPiece& piece, const TimingOptions& options, double v) {
  const Limits& lim = piece.limits;
  // (v infinite: the full jerk phase; v = 0: the floor of half a period)
  const double full = std::min(lim.acceleration, lim.deceleration) / lim.jerk;
  const double phase = std::min(full, kSlowPhase * std::sqrt(std::max(v, 0.0) / lim.jerk));
  return std::clamp(phase / kNodesPerJerkPhase, 0.5 * options.dt, std::max(kMaxNodeTime, 0.5 * options.dt));
}

Grid build_grid(const Path& path, const TimingOptions& options, const Prepared& prepared, const std::vector<Span>& start,
                double tau, double stretch) {
  Grid grid;
  grid.mode = options.limits;
  grid.dt = options.dt;
  if (options.limits == LimitsMode::kCartesian) grid.axes = options.axis_limits;
  const auto& pieces = path.pieces();
  const double length_total = path.length();

  // the marks: mandatory ones first (junctions, zone ends, curved pieces' parts), then the
  // starting profile's instants every tau
  std::vector<Mark> marks;
  for (std::size_t j = 0; j < prepared.joints.size(); ++j) {
    const Junction& jn = prepared.joints[j];
    marks.push_back({path.offset(jn.next), 0.0, true, jn.cap == 0, static_cast<int>(j)});
  }
  for (const HandoverZone& z : prepared.zones) {
    for (const double local : {z.s0, z.s1}) {
      if (local > 0 && local < length(pieces[z.piece].segment)) marks.push_back({path.offset(z.piece) + local, 0.0, true, false, -1});
    }
  }
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const Segment& segment = pieces[k].segment;
    const int parts = std::holds_alternative<Bezier>(segment) ? kBezierCells
                      : std::holds_alternative<Clothoid>(segment) ? kClothoidCells
                                                                  : 1;
    const double len = length(segment);
    for (int i = 1; i < parts && len > 0; ++i) marks.push_back({path.offset(k) + len * i / parts, 0.0, true, false, -1});
  }
  // time marks: every piece_spacing of the piece at the starting profile's speed there (a share of
  // its jerk phase at that speed), each with its own spacing for the gap rule below
  {
    double t = 0;
    std::size_t piece = 0;
    for (const Span& sp : start) {
      const double end = sp.t0 + sp.curve.duration();
      for (t = std::max(t, sp.t0); t < end;) {
        const double s = sp.s0 + sp.curve.at(t - sp.t0).s;
        while (piece + 1 < pieces.size() && path.offset(piece + 1) <= s) ++piece;
        const double spacing = std::max(tau, stretch * piece_spacing(pieces[piece], options, sp.curve.at(t - sp.t0).v));
        const double full = std::max(tau, stretch * piece_spacing(pieces[piece], options, kInf));
        if (s > 0 && s < length_total) marks.push_back({s, t, false, false, -1, spacing, full});
        t += spacing;
      }
    }
  }
  std::sort(marks.begin(), marks.end(), [](const Mark& a, const Mark& b) {
    return a.s != b.s ? a.s < b.s : a.mandatory > b.mandatory;
  });
  // a time mark closer than kMinTimeGap times its spacing (in the starting profile's time, and
  // kLeastGapShare of its piece's at full speed at least) to a mandatory one is dropped: near a
  // rest the starting profile creeps, and the marks there would make cells of nanometres
  {
    std::size_t span = 0;
    for (Mark& m : marks) {
      if (!m.mandatory) continue;
      while (span + 1 < start.size() && start[span + 1].s0 <= m.s) ++span;
      const Span& sp = start[span];
      m.t = sp.t0 + sp.curve.time_at_distance(std::clamp(m.s - sp.s0, 0.0, sp.length()));
    }
    double before = 0;  // the time of the last mandatory mark (the start is a rest)
    std::vector<double> after(marks.size(), start.back().t0 + start.back().curve.duration());
    for (std::size_t i = marks.size(); i-- > 0;) {
      if (i + 1 < marks.size()) after[i] = marks[i + 1].mandatory ? marks[i + 1].t : after[i + 1];
    }
    std::size_t i = 0;
    std::erase_if(marks, [&](const Mark& m) {
      const double next = after[i++];
      if (m.mandatory) {
        before = m.t;
        return false;
      }
      const double gap = kMinTimeGap * std::max(m.spacing, kLeastGapShare * m.full_spacing);
      return m.t - before < gap || next - m.t < gap;
    });
  }
  // around a curvature step whose rule applies (cartesian), no node closer than the reach of a
  // third difference across it (kStepWindow periods at the starting profile's speed, an upper
  // bound of the optimum's there): the two cells next to it then hold the whole window
  std::vector<std::pair<double, double>> windows;
  if (options.limits == LimitsMode::kCartesian) {
    std::size_t span = 0;
    for (const Junction& jn : prepared.joints) {
      if (!(jn.dk > 0) || jn.cap == 0 || pieces[jn.next].curvature_step_allowed) continue;
      const double s = path.offset(jn.next);
      while (span + 1 < start.size() && start[span + 1].s0 <= s) ++span;
      const Span& sp = start[span];
      const double v = sp.velocity_at(std::clamp(s - sp.s0, 0.0, sp.length()));
      const double reach = kStepWindow * v * options.dt;
      windows.emplace_back(s - reach, s + reach);
    }
  }
  if (!windows.empty()) {
    std::size_t w = 0;
    std::erase_if(marks, [&](const Mark& m) {
      while (w < windows.size() && windows[w].second < m.s) ++w;
      return !m.mandatory && w < windows.size() && m.s > windows[w].first && m.s < windows[w].second;
    });
  }

  // merged: a mark within kMergeShare of the last kept one is dropped (a mandatory one only onto
  // a mandatory one, keeping a rest and the junction data)
  const double merge = kMergeShare * length_total;
  std::vector<Mark> kept;
  kept.reserve(marks.size() + 2);
  kept.push_back({0.0, 0.0, true, true, -1});
  for (const Mark& m : marks) {
    if (!(m.s > 0) || !(m.s < length_total)) continue;
    Mark& last = kept.back();
    if (m.s - last.s <= merge && (!m.mandatory || last.mandatory)) {
      if (m.rest && !last.rest) last = m;  // a rest wins
      continue;
    }
    if (m.s - last.s <= merge && m.mandatory && !last.mandatory) {
      last = m;  // a mandatory mark replaces a time mark
      continue;
    }
    kept.push_back(m);
  }
  // the end: drop marks within the merge distance of it
  while (kept.size() > 1 && length_total - kept.back().s <= merge && !kept.back().rest) kept.pop_back();
  const bool end_is_rest_junction = kept.size() > 1 && kept.back().rest && length_total - kept.back().s <= merge;
  if (!end_is_rest_junction) kept.push_back({length_total, 0.0, true, true, -1});

  // the nodes
  grid.nodes.reserve(kept.size());
  grid.sides.reserve(kept.size() + 2 * prepared.joints.size());
  for (std::size_t i = 0; i < kept.size(); ++i) {
    const Mark& m = kept[i];
    GridNode node;
    if (i == 0 || i + 1 == kept.size()) {
      node = end_node(grid, path, options, prepared, i == 0);
    } else if (m.joint >= 0) {
      node = junction_node(grid, path, options, prepared, static_cast<std::size_t>(m.joint), m.rest);
    } else {
      // inside a piece: the piece whose interior holds s
      Path::Location at = path.locate(m.s);
      std::size_t k = at.piece;
      while (k + 1 < pieces.size() && length(pieces[k].segment) <= 0) ++k;
      node = interior_node(grid, path, options, prepared, k, m.s);
    }
    node.rest = node.rest || m.rest;
    grid.nodes.push_back(node);
  }
  grid.nodes.back().s = length_total;
  for (std::size_t i = 0; i < grid.nodes.size(); ++i) {
    if (grid.nodes[i].rest) grid.rests.push_back(i);
  }
  // the two cells around a limited curvature step hold its third differences' window: kept
  // whole (the jerk is constant on a cell at the fixed point, cell_shape.hpp, so the step's rule
  // at the node holds over the window)
  for (std::size_t j = 1; j + 1 < grid.nodes.size(); ++j) {
    if (grid.nodes[j].rest || !(grid.sides[grid.nodes[j].right].step.squaredNorm() > 0)) continue;
    grid.nodes[j - 1].keep = true;
    grid.nodes[j].keep = true;
  }

  // at least kMinCells cells per stretch: halve the longest cells of the short ones
  for (int round = 0; round < 8; ++round) {
    std::vector<std::size_t> cells;
    for (std::size_t r = 0; r + 1 < grid.rests.size(); ++r) {
      const std::size_t a = grid.rests[r];
      const std::size_t b = grid.rests[r + 1];
      if (b - a >= kMinCells) continue;
      std::size_t longest = b;
      for (std::size_t i = a; i < b; ++i) {
        if (grid.nodes[i].keep) continue;
        if (longest == b || grid.nodes[i + 1].s - grid.nodes[i].s > grid.nodes[longest + 1].s - grid.nodes[longest].s) longest = i;
      }
      if (longest < b) cells.push_back(longest);
    }
    if (cells.empty()) break;
    split_cells(grid, path, options, prepared, cells, [](std::size_t) {});
  }
  fill_middles(grid, path, options, prepared);
  return grid;
}

}  // namespace blendbench::timing_detail
