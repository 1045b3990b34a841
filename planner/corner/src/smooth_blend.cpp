#include <algorithm>
#include <optional>
#include <utility>

#include "blend_internal.hpp"

namespace blendbench {
namespace {

// Appends the blend of moves `first`..`last` of `program` (inclusive), the first one's geometry
// replaced by `head` and the last one's by `tail` where given (a stream's half lines), with the
// program's move and corner indices.
void lay_moves(Path& path, const Program& program, std::size_t first, std::size_t last, const std::optional<Line>& head,
               const std::optional<Line>& tail) {
  Program part;
  part.moves.assign(program.moves.begin() + static_cast<std::ptrdiff_t>(first),
                    program.moves.begin() + static_cast<std::ptrdiff_t>(last) + 1);
  // a half line is not merged with its neighbour (G64 Q): the merged chord would turn away from
  // the stream's curve, a kink where the two meet
  if (head) {
    part.moves.front().geometry = *head;
    part.moves.front().transition.merge_tolerance = 0;
  }
  if (tail) {
    part.moves.back().geometry = *tail;
    if (part.moves.size() > 1) part.moves[part.moves.size() - 2].transition.merge_tolerance = 0;
  }
  const Path blended = blend_unoriented(part);
  const int offset = static_cast<int>(first);
  bool joined = path.pieces().empty();  // the junction with a stream's curve before the moves
  for (PathPiece piece : blended.pieces()) {
    if (piece.move >= 0) piece.move += offset;
    if (piece.corner >= 0) piece.corner += offset;
    if (!joined) {
      const Segment& before = path.pieces().back().segment;
      piece.kink_angle = angle_between(tangent(before, length(before)), tangent(piece.segment, 0.0));
      joined = true;
    }
    path.append(std::move(piece));
  }
  for (CornerReport report : blended.corners) {
    report.index += offset;
    path.corners.push_back(std::move(report));
  }
  path.moves_merged += blended.moves_merged;
  path.merge_tolerance = std::max(path.merge_tolerance, blended.merge_tolerance);
}

}  // namespace

Path blend_smoothed(const Program& program) {
  SmoothedProgram smoothed = smooth_streams(program);
  if (smoothed.runs.empty()) {
    Path path = blend_unoriented(program);
    path.smoothing = std::move(smoothed.report);
    return path;
  }
  const auto& moves = program.moves;
  const auto half = [&](std::size_t k, bool second) {
    const Line& line = std::get<Line>(moves[k].geometry);
    const Vec3 middle = 0.5 * (line.p0 + line.p1);
    return second ? Line{middle, line.p1} : Line{line.p0, middle};
  };
  Path path;
  std::size_t next = 0;        // the first move not laid yet
  std::optional<Line> carry;   // the second half of the last stream's last line, laid with the moves after it
  for (const SmoothedRun& run : smoothed.runs) {
    // the moves before the stream, and the first half of its first line
    const std::size_t first = carry ? next - 1 : next;
    if (run.start_anchored) {
      lay_moves(path, program, first, run.run.first, carry, half(run.run.first, false));
    } else if (run.run.first > first) {
      lay_moves(path, program, first, run.run.first - 1, carry, std::nullopt);
    }
    // the stream's curve, joining the half line tangentially at zero curvature
    const Move& lead = moves[run.run.first];
    for (std::size_t i = 0; i < run.curve.size(); ++i) {
      const Segment& segment = run.curve[i];
      const std::size_t k = run.piece_move[i];
      PathPiece piece{segment, static_cast<int>(k), -1, lead.limits, lead.buffer, false, 0.0, false, moves[k].where};
      if (i == 0 && !path.pieces().empty()) {
        const Segment& before = path.pieces().back().segment;
        piece.kink_angle = angle_between(tangent(before, length(before)), tangent(segment, 0.0));
      }
      path.append(std::move(piece));
    }
    carry = run.end_anchored ? std::optional<Line>(half(run.run.last, true)) : std::nullopt;
    next = run.run.last + 1;
  }
  // the moves after the last stream
  if (carry) {
    lay_moves(path, program, next - 1, moves.size() - 1, carry, std::nullopt);
  } else if (next < moves.size()) {
    lay_moves(path, program, next, moves.size() - 1, std::nullopt, std::nullopt);
  }
  path.smoothing = std::move(smoothed.report);
  return path;
}

}  // namespace blendbench
