// Speed of the videos. The target: the whole pipeline (a variant video's frames with paths,
// trail, TCP marker, panel and legend, encoded to H.264 through ffmpeg) runs at >= 70 % of the
// frames per second of a bare loop that only poses the arm, renders it and reads the pixels back,
// on the same model (models/ur5e_like.xml), camera, size and render quality. Compare
// BM_Pipeline with BM_BareRenderRead of the same size from one run of this binary.
//
// BM_BareRenderRead with shadows and 4 samples shows what MuJoCo's defaults would cost.

#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "blendbench/render/film.hpp"
#include "support/source_tree.hpp"
#include "blendbench/render/render.hpp"
#include "blendbench/render/video.hpp"
#include "blendbench/sim/simulator.hpp"

namespace blendbench {
namespace {

constexpr double kFps = 30;
constexpr double kSeconds = 4;  // the film's length; frames repeat from the start when used up

// A film of the default scenario's arm: the shoulder and elbow swing gently while the TCP runs
// round a 120 x 360 mm rectangle (the default part's size) once; every frame differs.
struct Bench {
  Bench() : sim(blendbench::test::source_path("models/ur5e_like.xml")) {
    const mjModel& m = sim.model();
    const int key = mj_name2id(&m, mjOBJ_KEY, "ready");
    const std::vector<double> ready(m.key_qpos + key * m.nq, m.key_qpos + (key + 1) * m.nq);
    const Vec3 c[5] = {{0.40, -0.18, 0.2}, {0.52, -0.18, 0.2}, {0.52, 0.18, 0.2}, {0.40, 0.18, 0.2}, {0.40, -0.18, 0.2}};
    for (int e = 0; e < 4; ++e) {
      for (int i = 0; i < 100; ++i) programmed.push_back(c[e] + (c[e + 1] - c[e]) * (i / 100.0));
    }
    programmed.push_back(c[4]);
    film.name = "arc_5mm";
    film.planned = programmed;
    film.pose_rate_hz = kFps;
    const int poses = static_cast<int>(kSeconds * kFps) + 1;
    for (int k = 0; k < poses; ++k) {
      std::vector<double> q = ready;
      q[0] += 0.3 * std::sin(k / kFps);
      q[1] += 0.1 * std::sin(2 * k / kFps);
      film.qpos.insert(film.qpos.end(), q.begin(), q.end());
    }
    film.sample_period = 2e-3;
    const int samples = static_cast<int>(kSeconds / film.sample_period) + 1;
    for (int i = 0; i < samples; ++i) {
      const auto at = static_cast<std::size_t>(static_cast<double>(i) / (samples - 1) * static_cast<double>(programmed.size() - 1));
      film.tcp.push_back(programmed[at]);
      film.speed.push_back(0.25);
      film.tracking_error.push_back(40e-6);
      film.contour_error.push_back(10e-6);
    }
    film.reference_end = kSeconds;
    film.done_time = kSeconds;
  }

  [[nodiscard]] FilmSettings settings(const benchmark::State& state) const {
    FilmSettings s;
    s.width = static_cast<int>(state.range(0));
    s.height = static_cast<int>(state.range(1));
    s.fps = kFps;
    s.quality.shadows = state.range(2) != 0;
    s.quality.samples = static_cast<int>(state.range(3));
    s.scenario = "bench";
    s.programmed = programmed;
    return s;
  }

  Simulator sim;
  std::vector<Vec3> programmed;
  VariantFilm film;
};

const Bench& bench() {
  static const Bench b;
  return b;
}

void count_frames(benchmark::State& state) {
  state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

// The bare loop: pose, render the model through the video's camera, read the pixels.
void BM_BareRenderRead(benchmark::State& state) {
  const Bench& b = bench();
  const FilmSettings s = b.settings(state);
  const mjModel& m = b.sim.model();
  OffscreenRenderer renderer(m, s.width, s.height, s.quality);
  const CameraPose camera = VariantVideo(m, b.film, s).camera(0);
  const int poses = static_cast<int>(b.film.qpos.size()) / m.nq;
  int k = 0;
  for (auto _ : state) {
    renderer.pose(std::span<const double>(b.film.qpos.data() + static_cast<std::ptrdiff_t>(k % poses) * m.nq,
                                          static_cast<std::size_t>(m.nq)));
    renderer.draw_scene({0, 0, s.width, s.height}, camera, {});
    benchmark::DoNotOptimize(renderer.read().data());
    ++k;
  }
  count_frames(state);
}

// The pipeline: the variant video's frames (lines, marker, panel, legend) into ffmpeg.
void BM_Pipeline(benchmark::State& state) {
  const Bench& b = bench();
  const FilmSettings s = b.settings(state);
  VariantVideo video(b.sim.model(), b.film, s);
  const auto path = std::filesystem::temp_directory_path() / ("blendbench-bench-" + std::to_string(s.width) + ".mp4");
  VideoWriter writer(path.string(), s.width, s.height, s.fps);
  int k = 0;
  for (auto _ : state) writer.write(video.frame(k++ % video.frames()));
  // the encoder's tail belongs to the pipeline's time
  writer.finish();
  std::filesystem::remove(path);
  count_frames(state);
}

// The pipeline's frames without the encoder: what drawing the lines and the text costs.
void BM_Frames(benchmark::State& state) {
  const Bench& b = bench();
  const FilmSettings s = b.settings(state);
  VariantVideo video(b.sim.model(), b.film, s);
  int k = 0;
  for (auto _ : state) benchmark::DoNotOptimize(video.frame(k++ % video.frames()).data());
  count_frames(state);
}

// Arguments: width, height, shadows, samples. On a shared machine the load drifts during a run:
// each size alternates bare loop and pipeline kRounds times, so the medians of one run compare
// like with like.
constexpr int kRounds = 3;
const bool kRegistered = [] {
  for (const auto& [w, h] : {std::pair{640, 480}, std::pair{1280, 720}}) {
    for (int round = 0; round < kRounds; ++round) {
      benchmark::RegisterBenchmark("BM_BareRenderRead", BM_BareRenderRead)->Args({w, h, 0, 0})->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2);
      benchmark::RegisterBenchmark("BM_Pipeline", BM_Pipeline)->Args({w, h, 0, 0})->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2);
      if (round == 0) benchmark::RegisterBenchmark("BM_Frames", BM_Frames)->Args({w, h, 0, 0})->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2);
    }
  }
  benchmark::RegisterBenchmark("BM_BareRenderRead", BM_BareRenderRead)->Args({640, 480, 1, 4})->Unit(benchmark::kMillisecond)->UseRealTime();
  return true;
}();

}  // namespace
}  // namespace blendbench

BENCHMARK_MAIN();
