// Planning time of plan_timing per path piece on long programs (10^4 and 10^5
// segments: the cost must be linear in size), under both velocity planners. Run by hand:
// build/bench/bench_timing.

#include <benchmark/benchmark.h>

#include <cmath>

#include "blendbench/timing/timing.hpp"

namespace blendbench {
namespace {

// A planar G2 meander like a smoothed CAM path: line 2 mm, clothoid 1 mm (curvature 0 -> 100/m),
// arc 0.5 rad of radius 10 mm, clothoid back to 0, alternating the turning side; every tenth
// line starts with a 5 degree kink. `n` pieces; a = 10 m/s^2, j = 1000 m/s^3, and the feed:
// 0.2 m/s is below every curve limit (the clothoids allow 0.215 m/s), 1 m/s is above them, so the
// cap varies along every clothoid and each of their spans is checked against its 16 caps.
Path meander(int n, double feed) {
  const Limits lim{feed, 10.0, 10.0, 1000.0};
  Path path;
  Vec3 p = Vec3::Zero();
  double heading = 0;
  double side = 1;
  const double kappa = 100.0;
  const double len_clothoid = 1e-3;
  for (int k = 0; k < n; ++k) {
    const Vec3 e1(std::cos(heading), std::sin(heading), 0);
    const Vec3 e2(-std::sin(heading), std::cos(heading), 0);
    Segment seg = Line{p, p};
    switch (k % 4) {
      case 0: {
        if (k % 40 == 0 && k > 0) heading += 5.0 * M_PI / 180.0;
        const Vec3 d(std::cos(heading), std::sin(heading), 0);
        seg = Line{p, p + 2e-3 * d};
        break;
      }
      case 1: {
        const double c = side * kappa / len_clothoid;
        seg = Clothoid{p, e1, e2, 0.0, c, len_clothoid};
        heading += 0.5 * c * len_clothoid * len_clothoid;
        break;
      }
      case 2: {
        const double r = 1.0 / kappa;
        const Vec3 n_in = side * e2;  // towards the centre
        seg = Arc{p + r * n_in, -n_in, e1, r, 0.5, 0.0};
        heading += side * 0.5;
        break;
      }
      default: {
        const double c = -side * kappa / len_clothoid;
        seg = Clothoid{p, e1, e2, side * kappa, c, len_clothoid};
        heading += side * kappa * len_clothoid + 0.5 * c * len_clothoid * len_clothoid;
        side = -side;
        break;
      }
    }
    p = end_point(seg);
    path.append(PathPiece{seg, k, -1, lim});
  }
  return path;
}

void plan_meander(benchmark::State& state, double feed) {
  const Path path = meander(static_cast<int>(state.range(0)), feed);
  std::size_t samples = 0;
  for (auto _ : state) {
    TimingOptions options;
    options.algorithm = state.range(1) == 0 ? TimingOptions::Algorithm::kOptimal : TimingOptions::Algorithm::kSeed004;
    const Timing timing = plan_timing(path, options);
    samples = timing.samples.size();
    benchmark::DoNotOptimize(timing.cycle_time);
  }
  state.counters["per_segment"] = benchmark::Counter(static_cast<double>(state.range(0)),
                                                     benchmark::Counter::kIsIterationInvariantRate |
                                                         benchmark::Counter::kInvert);
  state.counters["samples"] = static_cast<double>(samples);
}
void BM_PlanTiming(benchmark::State& state) { plan_meander(state, 0.2); }
void BM_PlanTimingCurveBound(benchmark::State& state) { plan_meander(state, 1.0); }
// the second argument: 0 the optimal planner, 1 seed 004's
BENCHMARK(BM_PlanTiming)->ArgsProduct({{10000, 100000}, {0, 1}})->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PlanTimingCurveBound)->ArgsProduct({{10000, 100000}, {0, 1}})->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace blendbench

BENCHMARK_MAIN();
