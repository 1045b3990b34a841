#pragma once
// Internal to the velocity planner (timing.cpp): the optimal planner of TimingOptions::kOptimal.
// Not installed.

#include "blendbench/program/path.hpp"
#include "blendbench/timing/timing.hpp"

namespace blendbench::timing_detail {

// The minimum-time plan of a validated path (optimal.cpp describes the method); plan_timing's
// contract (timing.hpp).
Timing plan_optimal(const Path& path, const TimingOptions& options);

// seed 004's plan of a validated path (timing.cpp); plan_timing's contract.
Timing plan_seed004(const Path& path, const TimingOptions& options);

}  // namespace blendbench::timing_detail
