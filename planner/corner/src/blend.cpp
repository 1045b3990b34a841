#include "blendbench/corner/blend.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "blendbench/geometry/closest.hpp"
#include "blendbench/core/format.hpp"
#include "blendbench/corner/corner.hpp"
#include "blend_internal.hpp"

namespace blendbench {
namespace {

// The corner report's deviation is exact to this share of the corner's size (the longer of the
// transition and the path it replaces): hausdorff_within, closest.hpp.
constexpr double kDeviationTolerance = 1e-9;

std::string move_name(const Program& program, std::size_t k) {
  const Move& move = program.moves[k];
  return move.name.empty() ? "move " + std::to_string(k + 1) : move.name;
}

CornerFit fit_corner(const CornerInput& corner) {
  const double theta = angle_between(tangent(corner.in, length(corner.in)), tangent(corner.out, 0.0));
  // near reversals by one rule for every method (corner.hpp)
  if (corner.spec.method != Method::kNone) {
    if (auto fit = near_reversal_fit(corner, theta)) return *fit;
  }
  // equal tolerance: the method's parameter solved for the deviation (fit_corner_at_tolerance)
  if (corner.spec.tolerance > 0 && corner.spec.method != Method::kNone) return fit_corner_at_tolerance(corner);
  switch (corner.spec.method) {
    case Method::kNone: {
      // An exact stop stops where the tangent turns. Where it is continuous (a line tangent to
      // an arc, tangent arcs, collinear lines) there is no corner to stop at: the path runs
      // through, and the velocity planner holds the curvature step there to the jerk limit as
      // at any G1 junction (a glue bead round a rounded rectangle keeps moving). A move that
      // the previous transition used up whole leaves no tangent to compare: it stops there.
      CornerFit fit;
      if (theta > kG1Angle || !(length(corner.in) > 0) || !(length(corner.out) > 0)) {
        fit.stop = true;
        fit.corner_case = CornerCase::kExactStop;
      } else {
        const bool lines = std::holds_alternative<Line>(corner.in) && std::holds_alternative<Line>(corner.out);
        fit.corner_case = lines ? CornerCase::kCollinear : CornerCase::kTangent;
        fit.note = "exact stop: the tangent is continuous here, so the path does not stop";
      }
      return fit;
    }
    case Method::kArc: return fit_arc_corner(corner);
    case Method::kBezier: return fit_bezier_corner(corner);
    case Method::kClothoid: return fit_clothoid_corner(corner);
    case Method::kBiclothoid: return fit_biclothoid_corner(corner);
  }
  return {};
}

// Limits on a transition (seed 001): velocity from the transition parameter, or else the junction
// velocity of the buffer mode (PLCopen: the blend runs at the velocity the mode chooses, so a
// blended corner honours BlendingPrevious/Next/High as a kink would); acceleration,
// deceleration and jerk from the next move.
Limits transition_limits(const Move& in, const Move& out) {
  Limits lim = out.limits;
  lim.velocity = in.transition.velocity > 0 ? in.transition.velocity
                                            : junction_velocity(in.buffer, in.limits.velocity, out.limits.velocity);
  return lim;
}

}  // namespace

std::optional<CornerFit> near_reversal_fit(const CornerInput& corner, double theta) {
  if (!(theta >= std::numbers::pi - kNearReversalAngle) || theta >= std::numbers::pi - kReversalAngle) {
    return std::nullopt;
  }
  const std::string why = "the tangent turns by " + format_deg(theta) + ", within " + format_deg(kNearReversalAngle) +
                          " of a reversal";
  // as at a reversal: no transition, the kink stays
  CornerFit fit;
  fit.corner_case = CornerCase::kNearReversal;
  fit.note = why + ": no transition, the kink stays (as at a reversal)";
  fit.stop = corner.buffer == BufferMode::kBuffered;
  return fit;
}

std::string cusp_problem(const CornerInput& corner, const CornerFit& fit) {
  if (fit.transition.empty() || !(fit.parameter_used > 0)) return {};
  double scale = fit.parameter_used;
  for (const Primitive* p : {&corner.in, &corner.out}) {
    if (const auto* a = std::get_if<Arc>(p)) scale = std::min(scale, a->radius);
  }
  double kappa = 0;
  for (const Segment& seg : fit.transition) kappa = std::max(kappa, max_curvature(seg, 0, length(seg)));
  if (!(kappa * scale > 1 / kCuspShare)) return {};
  return "the transition would be a cusp: its smallest radius " + format_mm(1 / kappa) + " is below " +
         format_value(100 * kCuspShare) + " % of " + format_mm(scale) + " (the parameter or a programmed radius)";
}

double curvature_speed_limit(double kappa, double sharpness, double a_max, double j_max) {
  const double inf = std::numeric_limits<double>::infinity();
  const double v1 = kappa > 0 ? std::sqrt(a_max / kappa) : inf;                // eq. 25
  const double q = std::sqrt(sharpness * sharpness + std::pow(kappa, 4));
  const double v2 = q > 0 ? std::cbrt(j_max / q) : inf;                         // eq. 26
  return std::min(v1, v2);                                                      // eq. 27
}

namespace {

// The deviation of a transition (its total length `transition_length`) that trims `trim_in`
// from the end of `in` and `trim_out` from the start of `out` (measure_corner, corner_deviation).
double measured_deviation(const std::vector<Segment>& transition, double transition_length, double trim_in,
                          double trim_out, const Primitive& in, const Primitive& out) {
  const double len_in = length(in);
  const double len_out = length(out);
  if (transition.empty()) {
    // a zero-length transition still skips the trimmed programmed path (a reversal, an
    // intersection, the same circle backwards): it deviates by how far that part lies from the
    // path that is kept
    std::vector<Segment> skipped;
    std::vector<Segment> kept;
    if (trim_in > 0) {
      skipped.push_back(to_segment(sub_segment(in, len_in - trim_in, len_in)));
      if (trim_in < len_in) kept.push_back(to_segment(sub_segment(in, 0, len_in - trim_in)));
    }
    if (trim_out > 0) {
      skipped.push_back(to_segment(sub_segment(out, 0, trim_out)));
      if (trim_out < len_out) kept.push_back(to_segment(sub_segment(out, trim_out, len_out)));
    }
    if (skipped.empty() || kept.empty()) return 0;
    return directed_hausdorff_within(skipped, kept, kDeviationTolerance * (trim_in + trim_out));
  }
  // the programmed path replaced by the transition: the trimmed end of `in` and start of `out`
  std::vector<Segment> replaced;
  if (trim_in > 0) replaced.push_back(to_segment(sub_segment(in, len_in - trim_in, len_in)));
  if (trim_out > 0) replaced.push_back(to_segment(sub_segment(out, 0, trim_out)));
  if (replaced.empty()) {
    // a transition that replaces nothing (e.g. an inserted line on a collinear corner) deviates
    // by its distance to the programmed moves
    replaced.push_back(to_segment(in));
    replaced.push_back(to_segment(out));
  }
  // to kDeviationTolerance of the longer of the two curves
  double replaced_length = 0;
  for (const Segment& seg : replaced) replaced_length += length(seg);
  return hausdorff_within(transition, replaced, kDeviationTolerance * std::max(transition_length, replaced_length));
}

}  // namespace

void measure_corner(CornerReport& report, const std::vector<Segment>& transition, const Primitive& in,
                    const Primitive& out, double a_max, double j_max, double exact_deviation) {
  report.length = 0;
  report.kappa_max = 0;
  report.sharpness_max = 0;
  report.deviation = 0;
  report.feed_max = 0;
  if (transition.empty()) {
    // (a fit sets the exact deviation of a kink only where it solved a tolerance; the methods'
    // own line pair sets 0 where it has no length, as measured)
    report.deviation = exact_deviation >= 0 ? exact_deviation
                                            : measured_deviation(transition, 0, report.trim_in, report.trim_out, in, out);
    return;
  }
  for (const Segment& seg : transition) {
    const double len = length(seg);
    report.length += len;
    report.kappa_max = std::max(report.kappa_max, max_curvature(seg, 0, len));
    report.sharpness_max = std::max(report.sharpness_max, max_sharpness(seg, 0, len));
  }
  report.feed_max = curvature_speed_limit(report.kappa_max, report.sharpness_max, a_max, j_max);
  report.deviation = exact_deviation >= 0
                         ? exact_deviation
                         : measured_deviation(transition, report.length, report.trim_in, report.trim_out, in, out);
}

double corner_deviation(const CornerFit& fit, const Primitive& in, const Primitive& out) {
  if (fit.exact_deviation >= 0) return fit.exact_deviation;
  double transition_length = 0;
  for (const Segment& seg : fit.transition) transition_length += length(seg);
  return measured_deviation(fit.transition, transition_length, fit.trim_in, fit.trim_out, in, out);
}

namespace {

// The blender on a validated program, without merging. `program_corner` maps a corner of
// `program` to the corner of the program as written (merge_collinear's `last`; empty: the same),
// so that a refused corner's note names it as corners.json, the report and the plots do: C<index>.
Path blend_moves(const Program& program, const std::vector<std::size_t>& program_corner = {}) {
  const std::size_t n = program.moves.size();
  std::vector<double> lengths(n);
  for (std::size_t k = 0; k < n; ++k) lengths[k] = length(program.moves[k].geometry);

  // fit every corner; trims of move k: from its start (corner k-1) and its end (corner k)
  std::vector<double> trim_start(n, 0.0);
  std::vector<double> trim_end(n, 0.0);
  std::vector<CornerFit> fits;
  fits.reserve(n > 0 ? n - 1 : 0);
  const auto blended = [&](std::size_t corner) { return program.moves[corner].transition.method != Method::kNone; };
  for (std::size_t k = 0; k + 1 < n; ++k) {
    const Move& a = program.moves[k];
    const Move& b = program.moves[k + 1];
    CornerInput corner;
    corner.in = sub_segment(a.geometry, trim_start[k], lengths[k]);
    corner.out = b.geometry;
    const bool a_shared = k > 0 && blended(k - 1);
    const bool b_shared = k + 2 < n && blended(k + 1);
    corner.in_available = std::min(a_shared ? 0.5 * lengths[k] : lengths[k], lengths[k] - trim_start[k]);
    corner.out_available = b_shared ? 0.5 * lengths[k + 1] : lengths[k + 1];
    corner.spec = a.transition;
    corner.buffer = a.buffer;
    // (the number named first: GCC 12 warns -Wrestrict on "C" + a temporary, a false positive)
    const std::string number = std::to_string(program_corner.empty() ? k : program_corner[k]);
    corner.name = "C" + number + " (" + move_name(program, k) + " -> " + move_name(program, k + 1) + ")";
    corner.where = a.where;
    CornerFit fit = fit_corner(corner);
    if (fit.outcome.ok()) {
      if (const std::string cusp = cusp_problem(corner, fit); !cusp.empty()) fit.outcome = {Status::kInfeasible, cusp};
    }
    if (!fit.outcome.ok()) {
      // documented fallback: leave the corner as programmed and stop there
      CornerFit kink;
      kink.stop = true;
      kink.corner_case = fit.corner_case;
      kink.fallback = Fallback::kExactStop;
      kink.note = corner.name + ": " + fit.outcome.message;
      fit = kink;
    }
    trim_end[k] = fit.trim_in;
    trim_start[k + 1] = fit.trim_out;
    fits.push_back(std::move(fit));
  }

  Path path;
  std::size_t count = n;  // at most a piece per move and the transitions' pieces
  for (const CornerFit& fit : fits) count += fit.transition.size();
  path.reserve(count);
  bool stop_next = false;  // the next appended piece starts at rest
  // appends a piece, recording the tangent kink at its start; a kink left at a Buffered
  // junction forces a stop (seed 001 (controller manual, line-to-line), seed 003 (controller
  // manual, arc-to-arc): the path velocity goes to zero)
  // The tangents at a junction come from the programmed move for move pieces: a sliver left
  // between two fillets (nanometres long) has a chord direction good to only ~1e-7 rad, which
  // would read as a kink and force a spurious stop in Buffered mode.
  Vec3 end_tangent = Vec3::Zero();
  const auto append = [&](PathPiece piece, BufferMode junction_buffer, const Vec3& start_tangent,
                          const Vec3& piece_end_tangent) {
    if (!path.pieces().empty()) {
      piece.kink_angle = angle_between(end_tangent, start_tangent);
      if (piece.kink_angle > kG1Angle && junction_buffer == BufferMode::kBuffered) piece.stop_before = true;
    }
    piece.stop_before = piece.stop_before || stop_next;
    stop_next = false;
    end_tangent = piece_end_tangent;
    path.append(std::move(piece));
  };
  for (std::size_t k = 0; k < n; ++k) {
    const Move& move = program.moves[k];
    const double s0 = trim_start[k];
    const double s1 = lengths[k] - trim_end[k];
    if (s1 - s0 > 1e-12 * lengths[k]) {
      // the junction at its start belongs to the corner before it
      const bool allowed = k > 0 && program.moves[k - 1].transition.curvature_steps == CurvatureSteps::kAllow;
      append(PathPiece{to_segment(sub_segment(move.geometry, s0, s1)), static_cast<int>(k), -1, move.limits,
                       move.buffer, false, 0.0, allowed, move.where},
             k > 0 ? program.moves[k - 1].buffer : move.buffer, tangent(move.geometry, s0),
             tangent(move.geometry, s1));
    }
    if (k + 1 == n) break;

    const CornerFit& fit = fits[k];
    const Move& next = program.moves[k + 1];
    CornerReport report;
    report.index = static_cast<int>(k);
    report.method = move.transition.method;
    report.corner_case = fit.corner_case;
    report.fallback = fit.fallback;
    report.note = fit.note;
    report.parameter = fit.parameter_used;
    report.trim_in = fit.trim_in;
    report.trim_out = fit.trim_out;
    report.stop = fit.stop;
    report.curvature_steps = move.transition.curvature_steps;
    measure_corner(report, fit.transition, move.geometry, next.geometry, next.limits.acceleration, next.limits.jerk,
                   fit.exact_deviation);
    // equal tolerance: reached where the deviation lies in the band below it (corner.hpp)
    report.tolerance = move.transition.tolerance;
    report.tolerance_reached = report.tolerance > 0 && report.deviation <= report.tolerance &&
                               report.deviation >= report.tolerance * (1 - kToleranceBand);
    report.source = move.where;
    stop_next = stop_next || fit.stop;
    const Limits lim = transition_limits(move, next);
    // where the transition's limits were written: the next move's (acceleration, deceleration,
    // jerk, and the velocity unless the incoming move sets it)
    const SourceRef& source =
        move.transition.velocity > 0 || lim.velocity != next.limits.velocity ? move.where : next.where;
    for (const Segment& seg : fit.transition) {
      if (length(seg) <= 0) continue;
      append(PathPiece{seg, -1, static_cast<int>(k), lim, move.buffer, false, 0.0,
                       report.curvature_steps == CurvatureSteps::kAllow, source},
             move.buffer, tangent(seg, 0.0),
             tangent(seg, length(seg)));
    }
    path.corners.push_back(std::move(report));
  }
  return path;
}

// Whether vertices[i] (i in [1, size - 1)) lie within `tol` of the chord from the first to the
// last, each ahead of the one before along it.
bool on_chord(const std::vector<Vec3>& vertices, double tol) {
  const Vec3& a = vertices.front();
  const Vec3 d = vertices.back() - a;
  const double len = d.norm();
  if (!(len > 0)) return false;
  const Vec3 u = d / len;
  double along = 0;
  for (std::size_t i = 1; i + 1 < vertices.size(); ++i) {
    const Vec3 r = vertices[i] - a;
    const double x = r.dot(u);
    if (x <= along || x >= len || (r - x * u).norm() > tol) return false;
    along = x;
  }
  return true;
}

// Whether move b may join a run of lines that ends with move a (blend.hpp).
bool mergeable(const Move& a, const Move& b) {
  const auto same = [](const Limits& x, const Limits& y) {
    return x.velocity == y.velocity && x.acceleration == y.acceleration && x.deceleration == y.deceleration &&
           x.jerk == y.jerk;
  };
  return std::holds_alternative<Line>(a.geometry) && std::holds_alternative<Line>(b.geometry) &&
         a.transition.method != Method::kNone && a.transition.merge_tolerance > 0 && same(a.limits, b.limits) &&
         a.buffer == b.buffer && !a.orientation && !b.orientation;
}

}  // namespace

MergedProgram merge_collinear(const Program& program) {
  MergedProgram out;
  const auto& moves = program.moves;
  out.program.moves.reserve(moves.size());
  out.first.reserve(moves.size());
  out.last.reserve(moves.size());
  std::vector<Vec3> vertices;
  for (std::size_t k = 0; k < moves.size();) {
    // grow the run k..m greedily while its inner vertices stay on the chord
    std::size_t m = k;
    double tol = moves[k].transition.merge_tolerance;
    if (std::holds_alternative<Line>(moves[k].geometry)) {
      vertices = {std::get<Line>(moves[k].geometry).p0, std::get<Line>(moves[k].geometry).p1};
      while (m + 1 < moves.size() && m + 1 - k < static_cast<std::size_t>(kMaxMergeRun) && mergeable(moves[m], moves[m + 1])) {
        const double t = std::min(tol, moves[m].transition.merge_tolerance);
        vertices.push_back(std::get<Line>(moves[m + 1].geometry).p1);
        if (!on_chord(vertices, t)) break;
        tol = t;
        ++m;
      }
    }
    Move merged = moves[k];
    if (m > k) {
      merged.geometry = Line{vertices.front(), std::get<Line>(moves[m].geometry).p1};
      merged.transition = moves[m].transition;
      out.moves_merged += static_cast<int>(m - k);
      out.tolerance = std::max(out.tolerance, tol);
    }
    out.program.moves.push_back(std::move(merged));
    out.first.push_back(k);
    out.last.push_back(m);
    k = m + 1;
  }
  return out;
}

Path blend(const Program& program) {
  validate(program);
  Path path = program.smoothing.method != SmoothingMethod::kNone ? blend_smoothed(program) : blend_unoriented(program);
  if (oriented(program)) return orient_path(path, program);
  return path;
}

Path blend_unoriented(const Program& program) {
  // only a move with a merge tolerance (G64 Q) starts a run: without one the program blends as
  // it is, without the merged copy of every move (at 10^5 CAM lines, 35 MB written and dropped,
  // 9 % of blending them on fresh memory)
  const bool may_merge =
      std::any_of(program.moves.begin(), program.moves.end(), [](const Move& m) { return m.transition.merge_tolerance > 0; });
  const MergedProgram merged = may_merge ? merge_collinear(program) : MergedProgram{};
  if (merged.moves_merged == 0) return blend_moves(program);
  const Path blended = blend_moves(merged.program, merged.last);
  // the pieces and reports with the program's own move and corner indices
  Path path;
  path.reserve(blended.pieces().size());
  for (PathPiece piece : blended.pieces()) {
    if (piece.move >= 0) piece.move = static_cast<int>(merged.first[static_cast<std::size_t>(piece.move)]);
    if (piece.corner >= 0) piece.corner = static_cast<int>(merged.last[static_cast<std::size_t>(piece.corner)]);
    path.append(std::move(piece));
  }
  path.corners = blended.corners;
  for (CornerReport& r : path.corners) {
    r.index = static_cast<int>(merged.last[static_cast<std::size_t>(r.index)]);
    // the corner is at the end of the last merged move: its source is that move's
    r.source = program.moves[static_cast<std::size_t>(r.index)].where;
  }
  path.moves_merged = merged.moves_merged;
  path.merge_tolerance = merged.tolerance;
  return path;
}

}  // namespace blendbench
