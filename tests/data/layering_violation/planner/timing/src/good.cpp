// Fixture for tests/layering.cmake: timing may include corner, geometry and core.
#include "blendbench/timing/timing.hpp"

#include <cmath>

#include "blendbench/corner/blend.hpp"
#include "blendbench/core/geometry.hpp"
