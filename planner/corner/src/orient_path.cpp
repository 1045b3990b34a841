// The tool orientation of every piece of a blended path (orientation.hpp states the model).

#include <algorithm>
#include <cmath>

#include "blendbench/corner/blend.hpp"

namespace blendbench {
namespace {

AngularLimits tighter(const AngularLimits& a, const AngularLimits& b) {
  return {std::min(a.velocity, b.velocity), std::min(a.acceleration, b.acceleration), std::min(a.jerk, b.jerk)};
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

}  // namespace

Path orient_path(const Path& blended, const Program& program) {
  const std::size_t n = program.moves.size();
  const std::vector<Quat> target = move_targets(program);
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
      piece.orientation = PieceOrientation{law, program.moves[k].angular};
    } else {
      const auto c = static_cast<std::size_t>(piece.corner);
      BlendOrientation law{target[c], rate[c], rate[c + 1], report[c]->trim_in, report[c]->trim_out, transition[c], done[c]};
      done[c] += len;
      piece.orientation = PieceOrientation{law, tighter(program.moves[c].angular, program.moves[c + 1].angular)};
    }
    out.append(std::move(piece));
  }
  out.corners = blended.corners;
  out.moves_merged = blended.moves_merged;
  out.merge_tolerance = blended.merge_tolerance;
  // the rotation each transition takes, from its first to its last point
  for (CornerReport& r : out.corners) {
    const auto c = static_cast<std::size_t>(r.index);
    if (!(transition[c] > 0)) continue;
    const PieceOrientation law{BlendOrientation{target[c], rate[c], rate[c + 1], r.trim_in, r.trim_out, transition[c], 0.0}, {}};
    r.orientation_change = rotation_angle(orientation_at(law, 0.0), orientation_at(law, transition[c]));
  }
  return out;
}

}  // namespace blendbench
