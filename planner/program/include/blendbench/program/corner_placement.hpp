#pragma once
// Where each corner of a blended path lies: the programmed corner point, its arc length along
// the programmed path, and the span of its transition on the planned path. Reports, plots and
// the metrics of a run (when the reference passes a corner) use it.

#include <vector>

#include "blendbench/program/path.hpp"
#include "blendbench/program/program.hpp"

namespace blendbench {

// One corner (m): the programmed corner point (the end of move `index`), its arc length along
// the programmed path, and the span of its transition on the planned path (for a corner without
// a transition piece, an exact stop or a kink, start = end = the junction).
struct CornerPlacement {
  int index = 0;
  Vec3 point = Vec3::Zero();
  double s_programmed = 0;
  double s_start = 0, s_end = 0;
};

// The placement of every corner of `path`, in the order of path.corners; `program` is the
// program `path` was blended from.
std::vector<CornerPlacement> corner_placements(const Path& path, const Program& program);

}  // namespace blendbench
