#include "planner/corner.hpp"

namespace blendbench {

// Placeholder until the biclothoid method lands: the blender turns this into an exact stop.
CornerFit fit_biclothoid_corner(const CornerInput& corner) {
  CornerFit fit;
  fit.outcome = {Status::kInfeasible, "the biclothoid method is not available in this build (" + corner.name + ")"};
  return fit;
}

}  // namespace blendbench
