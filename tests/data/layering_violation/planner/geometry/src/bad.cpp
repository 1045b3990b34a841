// Fixture for tests/layering.cmake: geometry including timing, a higher layer (line 4).
#include "blendbench/geometry/segment.hpp"
#include "blendbench/core/geometry.hpp"
#include "blendbench/timing/timing.hpp"
