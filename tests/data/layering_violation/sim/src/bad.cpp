// Fixture for tests/layering.cmake: sim reading YAML (line 6), a job of io.
#include "blendbench/sim/simulator.hpp"

#include <mujoco/mujoco.h>

#include <yaml-cpp/yaml.h>
