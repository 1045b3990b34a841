#include "blendbench/corner/blend.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "blendbench/geometry/closest.hpp"
#include "blendbench/corner/corner.hpp"

namespace blendbench {
namespace {

// Angle (rad) below which two tangents count as continuous (G1) at a junction.
constexpr double kG1Angle = 1e-9;

std::string move_name(const Program& program, std::size_t k) {
  const Move& move = program.moves[k];
  return move.name.empty() ? "move " + std::to_string(k + 1) : move.name;
}

CornerFit fit_corner(const CornerInput& corner) {
  switch (corner.spec.method) {
    case Method::kNone: {
      CornerFit fit;
      fit.stop = true;
      fit.corner_case = CornerCase::kExactStop;
      return fit;
    }
    case Method::kArc: return fit_arc_corner(corner);
    case Method::kBezier: return fit_bezier_corner(corner);
    case Method::kClothoid: return fit_clothoid_corner(corner);
    case Method::kBiclothoid: return fit_biclothoid_corner(corner);
  }
  return {};
}

// Limits on a transition (001): velocity from the transition parameter, or else the junction
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

double curvature_speed_limit(double kappa, double sharpness, double a_max, double j_max) {
  const double inf = std::numeric_limits<double>::infinity();
  const double v1 = kappa > 0 ? std::sqrt(a_max / kappa) : inf;                // eq. 25
  const double q = std::sqrt(sharpness * sharpness + std::pow(kappa, 4));
  const double v2 = q > 0 ? std::cbrt(j_max / q) : inf;                         // eq. 26
  return std::min(v1, v2);                                                      // eq. 27
}

void measure_corner(CornerReport& report, const std::vector<Segment>& transition, const Primitive& in,
                    const Primitive& out, double a_max, double j_max) {
  report.length = 0;
  report.kappa_max = 0;
  report.sharpness_max = 0;
  report.deviation = 0;
  report.feed_max = 0;
  const double len_in = length(in);
  const double len_out = length(out);
  if (transition.empty()) {
    // a zero-length transition still skips the trimmed programmed path (a reversal, an
    // intersection, the same circle backwards): it deviates by how far that part lies from the
    // path that is kept
    std::vector<Segment> skipped;
    std::vector<Segment> kept;
    if (report.trim_in > 0) {
      skipped.push_back(to_segment(sub_segment(in, len_in - report.trim_in, len_in)));
      if (report.trim_in < len_in) kept.push_back(to_segment(sub_segment(in, 0, len_in - report.trim_in)));
    }
    if (report.trim_out > 0) {
      skipped.push_back(to_segment(sub_segment(out, 0, report.trim_out)));
      if (report.trim_out < len_out) kept.push_back(to_segment(sub_segment(out, report.trim_out, len_out)));
    }
    if (!skipped.empty() && !kept.empty()) {
      report.deviation = directed_hausdorff(skipped, kept, (report.trim_in + report.trim_out) / 512.0);
    }
    return;
  }
  for (const Segment& seg : transition) {
    const double len = length(seg);
    report.length += len;
    report.kappa_max = std::max(report.kappa_max, max_curvature(seg, 0, len));
    report.sharpness_max = std::max(report.sharpness_max, max_sharpness(seg, 0, len));
  }
  // the programmed path replaced by the transition: the trimmed end of `in` and start of `out`
  std::vector<Segment> replaced;
  if (report.trim_in > 0) replaced.push_back(to_segment(sub_segment(in, len_in - report.trim_in, len_in)));
  if (report.trim_out > 0) replaced.push_back(to_segment(sub_segment(out, 0, report.trim_out)));
  if (replaced.empty()) {
    // a transition that replaces nothing (e.g. an inserted line on a collinear corner) deviates
    // by its distance to the programmed moves
    replaced.push_back(to_segment(in));
    replaced.push_back(to_segment(out));
  }
  // sample step from the longer of the two curves: a tiny transition (a near-180 degree fillet)
  // replacing long trims would otherwise take billions of samples
  double replaced_length = 0;
  for (const Segment& seg : replaced) replaced_length += length(seg);
  report.deviation = hausdorff(transition, replaced, std::max(report.length, replaced_length) / 512.0);
  report.feed_max = curvature_speed_limit(report.kappa_max, report.sharpness_max, a_max, j_max);
}

Path blend(const Program& program) {
  validate(program);
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
    corner.name = "corner " + std::to_string(k + 1) + " (" + move_name(program, k) + " -> " + move_name(program, k + 1) + ")";
    corner.where = a.where;
    CornerFit fit = fit_corner(corner);
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
  bool stop_next = false;  // the next appended piece starts at rest
  // appends a piece, recording the tangent kink at its start; a kink left at a Buffered
  // junction forces a stop (001, 003: the path velocity goes to zero)
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
      append(PathPiece{to_segment(sub_segment(move.geometry, s0, s1)), static_cast<int>(k), -1, move.limits,
                       move.buffer, false, 0.0},
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
    measure_corner(report, fit.transition, move.geometry, next.geometry, next.limits.acceleration, next.limits.jerk);
    stop_next = stop_next || fit.stop;
    const Limits lim = transition_limits(move, next);
    for (const Segment& seg : fit.transition) {
      if (length(seg) <= 0) continue;
      append(PathPiece{seg, -1, static_cast<int>(k), lim, move.buffer, false, 0.0}, move.buffer, tangent(seg, 0.0),
             tangent(seg, length(seg)));
    }
    path.corners.push_back(std::move(report));
  }
  return path;
}

}  // namespace blendbench
