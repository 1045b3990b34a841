#include "blendbench/program/corner_placement.hpp"

namespace blendbench {

std::vector<CornerPlacement> corner_placements(const Path& path, const Program& program) {
  std::vector<CornerPlacement> out;
  for (const CornerReport& c : path.corners) {
    CornerPlacement p;
    p.index = c.index;
    const auto k = static_cast<std::size_t>(c.index);
    // the programmed corner: the end of move k, at the length of moves 0..k
    if (k < program.moves.size()) {
      const Primitive& g = program.moves[k].geometry;
      p.point = point(g, length(g));
      for (std::size_t i = 0; i <= k; ++i) p.s_programmed += length(program.moves[i].geometry);
    }
    // on the planned path: the transition's pieces, or the junction where move k + 1 starts
    bool found = false;
    for (std::size_t i = 0; i < path.pieces().size(); ++i) {
      const PathPiece& piece = path.pieces()[i];
      if (piece.corner == c.index) {
        if (!found) p.s_start = path.offset(i);
        p.s_end = path.offset(i + 1);
        found = true;
      }
    }
    if (!found) {
      p.s_start = p.s_end = path.length();
      for (std::size_t i = 0; i < path.pieces().size(); ++i) {
        if (path.pieces()[i].move > c.index) {
          p.s_start = p.s_end = path.offset(i);
          break;
        }
      }
    }
    out.push_back(p);
  }
  return out;
}

}  // namespace blendbench
