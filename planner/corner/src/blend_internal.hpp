#pragma once
// The blender's stages below blend() (blend.hpp), which validates the program, runs them and
// gives the pieces their orientation.

#include "blendbench/program/path.hpp"
#include "blendbench/program/program.hpp"

namespace blendbench {

// The blend of a valid program without smoothing or orientation: collinear lines merged (G64 Q),
// then every corner fitted (blend.cpp).
Path blend_unoriented(const Program& program);

// The blend of a valid program whose smoothing method is not none, without orientation: its
// streams replaced by their curves, the moves between them blended by blend_unoriented, the
// first and last half lines of each stream that meets a move kept as lines so the corner there
// is blended as any other (smooth_blend.cpp). Move and corner indices are the program's.
Path blend_smoothed(const Program& program);

}  // namespace blendbench
