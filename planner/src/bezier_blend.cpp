#include "planner/corner.hpp"

namespace blendbench {

// Placeholder until the bezier method lands: the blender turns this into an exact stop.
CornerFit fit_bezier_corner(const CornerInput& corner) {
  CornerFit fit;
  fit.outcome = {Status::kInfeasible, "the bezier method is not available in this build (" + corner.name + ")"};
  return fit;
}

}  // namespace blendbench
