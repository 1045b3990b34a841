// Planning cost and quality on CAM output: smooth curves emitted as tiny G1 lines.
//
// `BM_CamPath`, `BM_CamPlan`: a spline as 10^4 and 10^5 lines of 0.01-0.1 mm (the shape of
// LinuxCNC's trajectory-planner performance files), blended with biclothoid 0.05 mm (G64 P0.05),
// and the same smoothed by g2_fit within 0.02 mm first (`...Smoothed`). `path`: blend (with the
// corner fits and their reports, and the smoothing); `plan`: blend and time.
// Targets: 10^4 segments path <= 0.5 s and plan <= 1 s, 10^5 segments <= 10 s, linear; smoothed
// (issue 45): 10^4 lines path <= 1 s, plan <= 2 s; 10^5 lines <= 10 s and <= 20 s. `plan`
// under the optimal planner (issue #43): 10^4 <= 2 s, 10^5 <= 20 s. The second argument of
// BM_CamPlan is the velocity planner: 0 optimal, 1 seed004 (both in one run, for the ratio); 2000
// segments as well, for the cost exponent.
//
// `BM_Cardioid`, `BM_Wave` (issue 45's figures): a closed cardioid-like contour of 10^4 lines of
// 0.0164 mm and a 3D wave of 5000 lines of 0.02 mm, written to 0.1 um as G-code with four
// decimals is, at F6000 with 1000 mm/s^2 and 10000 mm/s^3; unsmoothed (biclothoid 0.05 mm) and
// smoothed by g2_fit at 0.02 mm, and by clothoid_points. Counters: the planned cycle time, the acceleration-only bound of
// the same path and of the unsmoothed program (Timing::bound_cycle_time), the largest measured
// distance of the smoothed curve to the lines, and the largest tangent turn and curvature jump
// at any junction of the path. Target: the smoothed cardioid planned within 1.3 times the
// unsmoothed program's bound.
// Run by hand: build/bench/bench_cam.

#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <random>

#include "blendbench/corner/blend.hpp"
#include "blendbench/timing/timing.hpp"
#include "support/cam_program.hpp"

namespace blendbench {
namespace {

using test::cam_program;  // support/cam_program.hpp

// A program of lines through `curve` at `n` + 1 points of equal arc length (from a table of 64
// samples per line), each coordinate rounded to 0.1 um; F6000, 1000 mm/s^2, 10000 mm/s^3,
// biclothoid 0.05 mm (G64 P0.05). `closed`: the last point is the first.
template <class Curve>
Program sampled_program(const Curve& curve, double t_end, int n, bool closed) {
  const int m = 64 * n;
  std::vector<Vec3> dense(static_cast<std::size_t>(m) + 1);
  std::vector<double> s(static_cast<std::size_t>(m) + 1, 0.0);
  for (int i = 0; i <= m; ++i) dense[static_cast<std::size_t>(i)] = curve(t_end * i / m);
  for (std::size_t i = 1; i < dense.size(); ++i) s[i] = s[i - 1] + (dense[i] - dense[i - 1]).norm();
  const auto rounded = [](Vec3 p) { return Vec3((p * 1e7).array().round() / 1e7); };
  std::vector<Vec3> points;
  std::size_t j = 0;
  for (int k = 0; k <= n; ++k) {
    const double target = s.back() * k / n;
    while (j + 1 < s.size() && s[j + 1] < target) ++j;
    const std::size_t next = std::min(j + 1, s.size() - 1);
    const double share = s[next] > s[j] ? (target - s[j]) / (s[next] - s[j]) : 0.0;
    points.push_back(rounded(dense[j] + share * (dense[next] - dense[j])));
  }
  if (closed && points.size() > 1) points.back() = points.front();
  Program program;
  for (std::size_t k = 0; k + 1 < points.size(); ++k) {
    Move& move = program.moves.emplace_back();
    move.geometry = Line{points[k], points[k + 1]};
    move.limits = {0.1, 1.0, 1.0, 10.0};
    move.transition.method = Method::kBiclothoid;
    move.transition.parameter = 0.05e-3;
  }
  return program;
}

// The cardioid-like contour: a dimpled limacon r = a (1.25 + cos t), 164 mm round, starting at
// its far point, n lines.
Program cardioid_program(int n) {
  // a = 164 mm / (the perimeter of r = 1.25 + cos t, 16.27 by a dense sum, then scaled exactly)
  const auto unit = [](double t) {
    const double r = 1.25 + std::cos(t);
    return Vec3(r * std::cos(t), r * std::sin(t), 0.0);
  };
  double perimeter = 0;
  for (int i = 0; i < 200000; ++i) perimeter += (unit(2 * std::numbers::pi * (i + 1) / 200000) - unit(2 * std::numbers::pi * i / 200000)).norm();
  const double a = 0.164 / perimeter;
  return sampled_program([&](double t) { return Vec3(a * (unit(t) - unit(0))); }, 2 * std::numbers::pi, n, true);
}

// The 3D wave: x = t, y = 4 sin(2 pi t / 25 mm), z = 2 sin(2 pi t / 40 mm) for t in [0, 80] mm
// (99.3 mm long), n lines.
Program wave_program(int n) {
  return sampled_program(
      [](double t) {
        return Vec3(t, 0.004 * std::sin(2 * std::numbers::pi * t / 0.025), 0.002 * std::sin(2 * std::numbers::pi * t / 0.040));
      },
      0.080, n, false);
}

Program smoothed(Program program, SmoothingMethod method = SmoothingMethod::kG2Fit) {
  program.smoothing.method = method;
  program.smoothing.tolerance = 0.02e-3;
  return program;
}

void per_segment(benchmark::State& state) {
  state.counters["per_segment"] = benchmark::Counter(static_cast<double>(state.range(0)),
                                                     benchmark::Counter::kIsIterationInvariantRate |
                                                         benchmark::Counter::kInvert);
}

void path_bench(benchmark::State& state, const Program& program) {
  std::size_t pieces = 0;
  for (auto _ : state) {
    const Path path = blend(program);
    pieces = path.pieces().size();
    benchmark::DoNotOptimize(path.length());
  }
  per_segment(state);
  state.counters["pieces"] = static_cast<double>(pieces);
}

void plan_bench(benchmark::State& state, const Program& program) {
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
    if (!timing.outcome.ok()) state.SkipWithError(timing.outcome.message.c_str());
  }
  per_segment(state);
  state.counters["samples"] = static_cast<double>(samples);
  state.counters["planned_to_bound"] = ratio;
  state.counters["iterations"] = iterations;      // optimal: the convex subproblems solved
  state.counters["newton_steps"] = newton_steps;  // optimal: the barrier method's Newton steps
}

void BM_CamPath(benchmark::State& state) { path_bench(state, cam_program(static_cast<int>(state.range(0)))); }
void BM_CamPlan(benchmark::State& state) { plan_bench(state, cam_program(static_cast<int>(state.range(0)))); }
void BM_CamPathSmoothed(benchmark::State& state) { path_bench(state, smoothed(cam_program(static_cast<int>(state.range(0))))); }
void BM_CamPlanSmoothed(benchmark::State& state) { plan_bench(state, smoothed(cam_program(static_cast<int>(state.range(0))))); }

// The figures of one program, unsmoothed and smoothed (range(1): 0 none, 1 g2_fit at 0.02 mm,
// 2 clothoid_points).
void figures(benchmark::State& state, const Program& lines) {
  const bool smooth = state.range(1) != 0;
  const Program program =
      smooth ? smoothed(lines, state.range(1) == 1 ? SmoothingMethod::kG2Fit : SmoothingMethod::kClothoidPoints) : lines;
  Timing timing;
  Path path;
  for (auto _ : state) {
    path = blend(program);
    timing = plan_timing(path);
    // (through a const copy: Debian's Google Benchmark 1.7.1 DoNotOptimize on a non-const double
    // member read back 0 after the loop under -O3)
    const double cycle = timing.cycle_time;
    benchmark::DoNotOptimize(cycle);
  }
  const double unsmoothed_bound = smooth ? plan_timing(blend(lines)).bound_cycle_time : timing.bound_cycle_time;
  double turn = 0;
  double jump = 0;
  for (std::size_t k = 1; k < path.pieces().size(); ++k) {
    const Segment& a = path.pieces()[k - 1].segment;
    const Segment& b = path.pieces()[k].segment;
    turn = std::max(turn, angle_between(tangent(a, length(a)), tangent(b, 0.0)));
    jump = std::max(jump, (curvature_vector(a, length(a)) - curvature_vector(b, 0.0)).norm());
  }
  if (!timing.outcome.ok()) state.SkipWithError(timing.outcome.message.c_str());
  state.counters["cycle_s"] = timing.cycle_time;
  state.counters["bound_s"] = timing.bound_cycle_time;
  state.counters["planned_to_bound"] = timing.cycle_time / timing.bound_cycle_time;
  state.counters["planned_to_unsmoothed_bound"] = timing.cycle_time / unsmoothed_bound;
  state.counters["pieces"] = static_cast<double>(path.pieces().size());
  state.counters["max_distance_mm"] = path.smoothing.max_distance * 1e3;
  state.counters["joint_turn_rad"] = turn;
  state.counters["curvature_jump_per_mm"] = jump * 1e-3;
}

void BM_Cardioid(benchmark::State& state) { figures(state, cardioid_program(static_cast<int>(state.range(0)))); }
void BM_Wave(benchmark::State& state) { figures(state, wave_program(static_cast<int>(state.range(0)))); }

BENCHMARK(BM_CamPath)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond);
// (the optimal planner evaluates long stretches on two threads: CPU time is the process's, and
// the wall time is what the targets are stated in)
BENCHMARK(BM_CamPlan)->Args({2000, 0})->Args({2000, 1})->Args({10000, 0})->Args({10000, 1})->Args({100000, 0})->Args({100000, 1})->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();
BENCHMARK(BM_CamPathSmoothed)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CamPlanSmoothed)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Cardioid)->Args({10000, 0})->Args({10000, 1})->Args({10000, 2})->Unit(benchmark::kMillisecond)->Iterations(1);
BENCHMARK(BM_Wave)->Args({5000, 0})->Args({5000, 1})->Args({5000, 2})->Unit(benchmark::kMillisecond)->Iterations(1);

}  // namespace
}  // namespace blendbench

BENCHMARK_MAIN();
