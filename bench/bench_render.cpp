// Speed of off-screen rendering: render + read back one 640x480 frame of the test arm (the read
// waits for llvmpipe: mjr_render returns before it draws), alone and with H.264 encoding through ffmpeg.

#include <benchmark/benchmark.h>

#include <filesystem>

#include "support/test_arm.hpp"
#include "blendbench/render/render.hpp"
#include "blendbench/sim/simulator.hpp"
#include "blendbench/render/video.hpp"

namespace blendbench {
namespace {

struct Scene {
  Scene() : sim(Simulator::from_xml_string(test::kTestArmXml)), d(mj_makeData(&sim.model())) {
    const JointVector q = test::test_arm_bent_pose();
    for (int i = 0; i < 6; ++i) d->qpos[i] = q[i];
    mj_forward(&sim.model(), d);
  }
  ~Scene() { mj_deleteData(d); }
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;
  // Moves the arm a little so frames differ.
  void advance() {
    d->qpos[0] += 0.002;
    mj_kinematics(&sim.model(), d);
  }
  Simulator sim;
  mjData* d;
};

RenderOptions options(benchmark::State& state) {
  RenderOptions o;
  o.width = static_cast<int>(state.range(0));
  o.height = static_cast<int>(state.range(1));
  o.shadows = state.range(2) != 0;
  o.samples = static_cast<int>(state.range(3));
  o.path_polyline = {Eigen::Vector3d(0.4, -0.3, 0.2), Eigen::Vector3d(0.4, 0.3, 0.2), Eigen::Vector3d(0.2, 0.3, 0.4)};
  return o;
}

void BM_RenderRead(benchmark::State& state) {
  Scene scene;
  OffscreenRenderer renderer(scene.sim.model(), options(state));
  for (auto _ : state) {
    scene.advance();
    benchmark::DoNotOptimize(renderer.render(*scene.d).data());
  }
  state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_RenderEncode(benchmark::State& state) {
  Scene scene;
  const RenderOptions o = options(state);
  OffscreenRenderer renderer(scene.sim.model(), o);
  const auto path = std::filesystem::temp_directory_path() / "blendbench-bench-video.mp4";
  VideoWriter writer(path.string(), o.width, o.height, 30);
  for (auto _ : state) {
    scene.advance();
    writer.write(renderer.render(*scene.d));
  }
  writer.finish();
  std::filesystem::remove(path);
  state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

// Arguments: width, height, shadows, samples.
BENCHMARK(BM_RenderRead)
    ->Args({640, 480, 0, 0})
    ->Args({640, 480, 1, 4})
    ->Args({1280, 720, 0, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();
BENCHMARK(BM_RenderEncode)->Args({640, 480, 0, 0})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace blendbench

BENCHMARK_MAIN();
