// The planning cost of orientation: blend and plan_timing of the same program with and without
// orientation targets (issue: six-DOF tool poses). Run by hand: build/bench/bench_orientation;
// compare the two lines of one run (the ratio is the cost).

#include <benchmark/benchmark.h>

#include <cmath>
#include <string>

#include "blendbench/corner/blend.hpp"
#include "blendbench/timing/timing.hpp"

namespace blendbench {
namespace {

// A zig-zag of `n` lines of 20 mm turning by 60 degrees, Bezier (or arc) transitions of 5 mm,
// 0.25 m/s;
// `oriented`: every move turns the tool by 10 degrees about an axis that alternates between
// the base z and a tilted one (so consecutive rates are not parallel), under 180 deg/s limits.
Program zigzag(int n, bool oriented, Method method) {
  Program program;
  program.start_orientation = Quat(Eigen::AngleAxisd(M_PI, Vec3::UnitX()));
  Quat q = program.start_orientation;
  Vec3 p = Vec3::Zero();
  for (int k = 0; k < n; ++k) {
    const double heading = (k % 2 == 0 ? 1 : -1) * M_PI / 6;
    const Vec3 next = p + 0.02 * Vec3(std::cos(heading), std::sin(heading), 0);
    // built in place (a copy of a Move drew a GCC 12 -Wmaybe-uninitialized false positive)
    Move& move = program.moves.emplace_back();
    move.geometry = Line{p, next};
    move.limits = {0.25, 2.5, 2.5, 50.0};
    move.transition = {method, 0.005};
    move.angular = {M_PI, 4 * M_PI, 40 * M_PI};
    if (oriented) {
      const Vec3 axis = k % 2 == 0 ? Vec3::UnitZ() : Vec3(0.3, 0, 1).normalized();
      q = Quat(Eigen::AngleAxisd(10 * M_PI / 180, axis)) * q;
      move.orientation = q;
    }
    p = next;
  }
  return program;
}

void BM_PlanOrientation(benchmark::State& state) {
  const Method method = state.range(2) == 0 ? Method::kBezier : Method::kArc;
  const Program program = zigzag(static_cast<int>(state.range(0)), state.range(1) != 0, method);
  for (auto _ : state) {
    const Path path = blend(program);
    const Timing timing = plan_timing(path);
    benchmark::DoNotOptimize(timing.cycle_time);
  }
  state.SetLabel(std::string(to_string(method)) + (state.range(1) != 0 ? ", with orientation" : ", without orientation"));
}
BENCHMARK(BM_PlanOrientation)
    ->Args({1000, 0, 0})
    ->Args({1000, 1, 0})
    ->Args({1000, 0, 1})
    ->Args({1000, 1, 1})
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace blendbench

BENCHMARK_MAIN();
