#include "planner/corner.hpp"

namespace blendbench {

// Placeholder until the arc method lands: the blender turns this into an exact stop.
CornerFit fit_arc_corner(const CornerInput& corner) {
  CornerFit fit;
  fit.outcome = {Status::kInfeasible, "the arc method is not available in this build (" + corner.name + ")"};
  return fit;
}

}  // namespace blendbench
