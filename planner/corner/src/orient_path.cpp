// The tool orientation of every piece of a blended path (orientation.hpp states the model).

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>

#include "blendbench/core/input_error.hpp"
#include "blendbench/corner/blend.hpp"

namespace blendbench {
namespace {

AngularLimits tighter(const AngularLimits& a, const AngularLimits& b) {
  return {std::min(a.velocity, b.velocity), std::min(a.acceleration, b.acceleration), std::min(a.jerk, b.jerk)};
}

// The angular limits on a piece: its move's, or on a transition the tighter of its two moves'.
AngularLimits piece_limits(const Program& program, const PathPiece& piece) {
  if (piece.move >= 0) return program.moves[static_cast<std::size_t>(piece.move)].angular;
  const auto c = static_cast<std::size_t>(piece.corner);
  return tighter(program.moves[c].angular, program.moves[c + 1].angular);
}

// `out` (the oriented pieces) takes `blended`'s corner reports and merge record, and each
// report the rotation its transition takes from its first to its last point, by law_of(report),
// the orientation law over the transition from its start (transition[c]: its length).
template <class LawOf>
void finish(Path& out, const Path& blended, const std::vector<double>& transition, LawOf law_of) {
  out.corners = blended.corners;
  out.moves_merged = blended.moves_merged;
  out.merge_tolerance = blended.merge_tolerance;
  out.smoothing = blended.smoothing;
  for (CornerReport& r : out.corners) {
    const auto c = static_cast<std::size_t>(r.index);
    if (!(transition[c] > 0)) continue;
    const PieceOrientation law{law_of(r), {}};
    r.orientation_change = rotation_angle(orientation_at(law, 0.0), orientation_at(law, transition[c]));
  }
}

// The target at the end of every move (the previous one where a move sets none), each on the
// hemisphere of the one before, so that the slerp between them goes the shorter way.
std::vector<Quat> move_targets(const Program& program) {
  std::vector<Quat> out;
  out.reserve(program.moves.size());
  Quat current = program.start_orientation.normalized();
  for (const Move& move : program.moves) {
    if (move.orientation) {
      Quat q = move.orientation->normalized();
      if (q.dot(current) < 0) q.coeffs() *= -1;
      current = q;
    }
    out.push_back(current);
  }
  return out;
}

// The rotation vector of `q` about `reference` nearest `previous` among the representatives of
// that rotation that the spline's range can hold: phi = log(q reference^T) and phi +- 2 pi phi/|phi|
// (the same rotation, the other way round or a turn further). Consecutive targets differ by at
// most a half-turn (move_targets), so the nearest one continues the previous turn.
Vec3 unwrapped_log(const Quat& q, const Quat& reference, const Vec3& previous) {
  const Vec3 phi = rotation_log(q * reference.conjugate());
  const double angle = phi.norm();
  if (angle <= 0) return phi;
  Vec3 best = phi;
  for (const double turn : {-2 * std::numbers::pi, 2 * std::numbers::pi}) {
    const Vec3 other = phi * ((angle + turn) / angle);
    if ((other - previous).norm() < (best - previous).norm()) best = other;
  }
  return best;
}

// The option `spline` (orientation.hpp): one natural cubic spline of rotation vectors through
// the targets, knot k where the path passes target k, laid on every piece.
Path spline_path(const Path& blended, const Program& program, const std::vector<Quat>& target) {
  const std::size_t n = program.moves.size();
  // where each transition starts on the path and its length, and where the path passes each
  // corner without one: the start of the first piece past it (of a later move or transition;
  // the move before it may have been used up by the transition before)
  std::vector<double> transition_start(n, -1.0), transition(n, 0.0);
  double s = 0;
  for (const PathPiece& piece : blended.pieces()) {
    const double len = length(piece.segment);
    if (piece.corner >= 0) {
      const auto c = static_cast<std::size_t>(piece.corner);
      if (transition_start[c] < 0) transition_start[c] = s;
      transition[c] += len;
    }
    s += len;
  }
  const double total = s;
  std::vector<double> passed(n, total);
  {
    std::size_t k = 0;  // the next corner to place
    s = 0;
    for (const PathPiece& piece : blended.pieces()) {
      const auto after = static_cast<std::size_t>(piece.move >= 0 ? piece.move : piece.corner);
      for (; k < n && k < after; ++k) passed[k] = s;  // every corner before this piece's place
      s += length(piece.segment);
    }
  }
  // knots: the start, then each target where the path passes it; a target at the place of the
  // one before (a move a transition consumed) replaces it
  const Quat reference = program.start_orientation.normalized();
  std::vector<double> knots{0.0};
  std::vector<Vec3> values{Vec3::Zero()};
  const double tiny = 1e-12 * std::max(total, 1e-300);
  for (std::size_t k = 0; k < n; ++k) {
    const double at = k + 1 == n ? total : transition[k] > 0 ? transition_start[k] + 0.5 * transition[k] : passed[k];
    const Vec3 phi = unwrapped_log(target[k], reference, values.back());
    if (phi.norm() > kSplineMaxTurn) {
      fail_at(program.moves[k].where, "orientation",
              program.moves[k].name + ": the target turns the tool " + std::to_string(std::lround(phi.norm() * 180 / std::numbers::pi)) +
                  " deg from the start orientation along the path; orientation_interpolation: spline takes targets within " +
                  std::to_string(std::lround(kSplineMaxTurn * 180 / std::numbers::pi)) + " deg of it (slerp takes any)");
    }
    if (at - knots.back() > tiny) {
      knots.push_back(at);
      values.push_back(phi);
    } else if (knots.size() > 1) {
      values.back() = phi;  // at the start itself the start orientation holds
    }
  }
  if (knots.size() < 2) {  // a path of no length: hold the last target
    knots.push_back(1.0);
    values.push_back(values.back());
  }
  const auto spline = std::make_shared<const OrientationSpline>(reference, std::move(knots), std::move(values));

  Path out;
  s = 0;
  for (PathPiece piece : blended.pieces()) {
    const double len = length(piece.segment);
    piece.orientation = PieceOrientation{SplineOrientation{spline, s}, piece_limits(program, piece)};
    s += len;
    out.append(std::move(piece));
  }
  finish(out, blended, transition, [&](const CornerReport& r) {
    return SplineOrientation{spline, transition_start[static_cast<std::size_t>(r.index)]};
  });
  return out;
}

}  // namespace

Path orient_path(const Path& blended, const Program& program) {
  const std::size_t n = program.moves.size();
  const std::vector<Quat> target = move_targets(program);
  if (program.orientation_interpolation == OrientationInterpolation::kSpline) return spline_path(blended, program, target);
  const auto start_of = [&](std::size_t k) { return k == 0 ? program.start_orientation.normalized() : target[k - 1]; };
  // each move's rate by its programmed arc length
  std::vector<Vec3> rate(n);
  for (std::size_t k = 0; k < n; ++k) {
    rate[k] = rotation_log(target[k] * start_of(k).conjugate()) / length(program.moves[k].geometry);
  }
  // the corner reports by index, and the length of each corner's transition
  std::vector<const CornerReport*> report(n, nullptr);
  for (const CornerReport& r : blended.corners) report[static_cast<std::size_t>(r.index)] = &r;
  std::vector<double> transition(n, 0.0);
  for (const PathPiece& piece : blended.pieces()) {
    if (piece.corner >= 0) transition[static_cast<std::size_t>(piece.corner)] += length(piece.segment);
  }

  Path out;
  std::vector<double> done(n, 0.0);  // how much of each transition is laid already
  for (PathPiece piece : blended.pieces()) {
    const double len = length(piece.segment);
    if (piece.move >= 0) {
      const auto k = static_cast<std::size_t>(piece.move);
      // the programmed part [s0, s1] of the move the piece keeps
      const double s0 = k > 0 && report[k - 1] ? report[k - 1]->trim_out : 0.0;
      const double s1 = s0 + len;
      // at a corner without a transition the orientation passes through its target
      const bool cut_start = k > 0 && transition[k - 1] <= 0 && s0 > 0;
      const bool cut_end = k + 1 < n && transition[k] <= 0 && report[k] && report[k]->trim_in > 0;
      GeodesicOrientation law{rotation_exp(s0 * rate[k]) * start_of(k), rate[k]};
      if (cut_start || cut_end) {
        law.start = cut_start ? start_of(k) : law.start;
        const Quat end = cut_end ? target[k] : Quat(rotation_exp(s1 * rate[k]) * start_of(k));
        law.rate = len > 0 ? Vec3(rotation_log(end * law.start.conjugate()) / len) : Vec3::Zero();
      }
      piece.orientation = PieceOrientation{law, piece_limits(program, piece)};
    } else {
      const auto c = static_cast<std::size_t>(piece.corner);
      BlendOrientation law{target[c], rate[c], rate[c + 1], report[c]->trim_in, report[c]->trim_out, transition[c], done[c]};
      done[c] += len;
      piece.orientation = PieceOrientation{law, piece_limits(program, piece)};
    }
    out.append(std::move(piece));
  }
  finish(out, blended, transition, [&](const CornerReport& r) {
    const auto c = static_cast<std::size_t>(r.index);
    return BlendOrientation{target[c], rate[c], rate[c + 1], r.trim_in, r.trim_out, transition[c], 0.0};
  });
  return out;
}

}  // namespace blendbench
