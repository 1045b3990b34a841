// Planning cost on CAM output: a smooth spline emitted as tiny G1 lines of 0.01-0.1 mm (the
// shape of LinuxCNC's trajectory-planner performance files), blended with biclothoid 0.05 mm
// (G64 P0.05). `path`: blend (the corner fits and their reports); `plan`: blend and time.
// Targets: 10^4 segments path <= 0.5 s and plan <= 1 s, 10^5 segments <= 10 s, linear; `plan`
// under the optimal planner (issue #43): 10^4 <= 2 s, 10^5 <= 20 s. The second argument of
// BM_CamPlan is the velocity planner: 0 optimal, 1 seed004 (both in one run, for the ratio); 2000
// segments as well, for the cost exponent.
// Run by hand: build/bench/bench_cam.

#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "blendbench/corner/blend.hpp"
#include "blendbench/timing/timing.hpp"

namespace blendbench {
namespace {

// `n` lines along x = 20 sin(t) + 5 sin(3.1 t + 0.3), y = 15 sin(0.7 t + 1) + 4 cos(2.3 t) mm
// with t = s / 20 mm, each 0.01..0.1 mm of s (a fixed seed); feed 2000 mm/min, 1000 mm/s^2,
// 10000 mm/s^3 (the G-code defaults' order); every corner a biclothoid of 0.05 mm tolerance.
Program cam_program(int n) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> step(0.01e-3, 0.1e-3);
  const auto at = [](double s) {
    const double t = s / 0.02;
    return Vec3(0.020 * std::sin(t) + 0.005 * std::sin(3.1 * t + 0.3), 0.015 * std::sin(0.7 * t + 1.0) + 0.004 * std::cos(2.3 * t),
                0.0);
  };
  Program program;
  program.moves.reserve(static_cast<std::size_t>(n));
  double s = 0;
  Vec3 p = at(0);
  for (int k = 0; k < n; ++k) {
    s += step(rng);
    const Vec3 q = at(s);
    Move& move = program.moves.emplace_back();
    move.geometry = Line{p, q};
    move.limits = {2.0 / 60.0, 1.0, 1.0, 10.0};
    move.transition.method = Method::kBiclothoid;
    move.transition.parameter = 0.05e-3;
    p = q;
  }
  return program;
}

void per_segment(benchmark::State& state) {
  state.counters["per_segment"] = benchmark::Counter(static_cast<double>(state.range(0)),
                                                     benchmark::Counter::kIsIterationInvariantRate |
                                                         benchmark::Counter::kInvert);
}

void BM_CamPath(benchmark::State& state) {
  const Program program = cam_program(static_cast<int>(state.range(0)));
  std::size_t pieces = 0;
  for (auto _ : state) {
    const Path path = blend(program);
    pieces = path.pieces().size();
    benchmark::DoNotOptimize(path.length());
  }
  per_segment(state);
  state.counters["pieces"] = static_cast<double>(pieces);
}

void BM_CamPlan(benchmark::State& state) {
  const Program program = cam_program(static_cast<int>(state.range(0)));
  std::size_t samples = 0;
  double ratio = 0;
  int newton_steps = 0;
  int iterations = 0;
  for (auto _ : state) {
    const Path path = blend(program);
    TimingOptions options;
    options.algorithm = state.range(1) == 0 ? TimingOptions::Algorithm::kOptimal : TimingOptions::Algorithm::kSeed004;
    const Timing timing = plan_timing(path, options);
    samples = timing.samples.size();
    ratio = timing.cycle_time / timing.bound_cycle_time;
    newton_steps = timing.newton_steps;
    iterations = timing.iterations;
    benchmark::DoNotOptimize(timing.cycle_time);
  }
  per_segment(state);
  state.counters["samples"] = static_cast<double>(samples);
  state.counters["planned_to_bound"] = ratio;
  state.counters["iterations"] = iterations;      // optimal: the convex subproblems solved
  state.counters["newton_steps"] = newton_steps;  // optimal: the barrier method's Newton steps
}

BENCHMARK(BM_CamPath)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CamPlan)->Args({2000, 0})->Args({2000, 1})->Args({10000, 0})->Args({10000, 1})->Args({100000, 0})->Args({100000, 1})->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace blendbench

BENCHMARK_MAIN();
