// Blends and times two lines through the installed planner: 100 mm along x, then a 90 degree
// turn and 100 mm along y, with a biclothoid transition of at most 1 mm deviation at the corner
// (seed 004, Shahzadeh et al., Algorithms 1 and 2) and a jerk-limited velocity profile.
// Prints the path length, the corner's deviation and the cycle time; exit 1 when planning fails.
#include <cstdio>
#include <exception>

#include "blendbench/corner/blend.hpp"
#include "blendbench/timing/timing.hpp"

int main() {
  namespace bb = blendbench;
  const bb::Limits limits{0.25, 2.5, 2.5, 50.0};  // m/s, m/s^2, m/s^2, m/s^3
  bb::Transition fillet;
  fillet.method = bb::Method::kBiclothoid;
  fillet.parameter = 1e-3;  // m: the maximum deviation from the programmed corner

  bb::Program program;
  program.moves.push_back({bb::Line{{0, 0, 0}, {0.1, 0, 0}}, limits, bb::BufferMode::kBlendingLow, fillet, {}, "line 1"});
  program.moves.push_back({bb::Line{{0.1, 0, 0}, {0.1, 0.1, 0}}, limits, bb::BufferMode::kBlendingLow, {}, {}, "line 2"});

  try {
    const bb::Path path = bb::blend(program);
    const bb::Timing timing = bb::plan_timing(path);
    if (!timing.outcome.ok() || path.corners.size() != 1) {
      std::fprintf(stderr, "consumer: planning failed: %s\n", timing.outcome.message.c_str());
      return 1;
    }
    std::printf("path_length_mm %.4f\n", path.length() * 1e3);
    std::printf("tolerance_mm %.4f\n", fillet.parameter * 1e3);
    std::printf("corner_deviation_mm %.4f\n", path.corners[0].deviation * 1e3);
    std::printf("cycle_time_s %.4f\n", timing.cycle_time);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return 1;
  }
  return 0;
}
