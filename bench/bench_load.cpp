// Loading time of a scenario (YAML) and of the same path as G-code, at 10^3, 10^4 and 10^5
// moves: reading the file, parsing, converting to SI and the planner's checks (validate), the
// same work for both formats, so the two should cost about the same and grow linearly.
// Run by hand: build/bench/bench_load.

#include <benchmark/benchmark.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "blendbench/io/program_io.hpp"
#include "blendbench/io/scenario.hpp"

namespace blendbench {
namespace {

namespace fs = std::filesystem;

// A welding-seam-like path of `n` moves in mm: a zig-zag of 10 mm lines, every tenth move a
// half circle of radius 5 mm (centre given), at 100 mm/s; in the scenario every tenth move also
// sets its own speed and transition.
struct Part {
  std::string yaml;
  std::string gcode;
};

Part make_part(int n) {
  Part part;
  part.yaml = "name: seam\nunits: mm\nframe: {origin: [300, 0, 200]}\n"
              "defaults: {velocity: 100, acceleration: 2000, jerk: 20000}\nprogram:\n  start: [0, 0, 0]\n  moves:\n";
  part.gcode = "G21 G90 G17 G64 P0.5\nG1 X0 Y0 F6000\n";
  double x = 0;
  double y = 0;
  for (int k = 0; k < n; ++k) {
    const std::string xs = std::to_string(x + 10);
    if (k % 10 == 9) {
      // a half circle of radius 5 mm about (x + 5, y), ending at (x + 10, y)
      const std::string cx = std::to_string(x + 5);
      part.yaml += "    - arc: {end: [" + xs + ", " + std::to_string(y) + ", 0], center: [" + cx + ", " + std::to_string(y) +
                   ", 0], direction: " + (k % 20 == 9 ? "ccw" : "cw") + "}\n      velocity: 80\n"
                   "      transition: {method: biclothoid, parameter: 0.5}\n";
      part.gcode += std::string(k % 20 == 9 ? "G3" : "G2") + " X" + xs + " Y" + std::to_string(y) + " I5 J0\n";
    } else {
      y = k % 2 == 0 ? 10 : 0;
      part.yaml += "    - line: [" + xs + ", " + std::to_string(y) + ", 0]\n";
      part.gcode += "G1 X" + xs + " Y" + std::to_string(y) + "\n";
    }
    x += 10;
  }
  part.yaml += "variants:\n  - {name: exact, transition: {method: none}}\n  - {name: bic, transition: {method: biclothoid, parameter: 0.5}}\n";
  part.gcode += "M2\n";
  return part;
}

// The part's files, written once per size into a folder of this process, removed at exit.
struct Files {
  std::string yaml;
  std::string gcode;
};

struct Folder {
  fs::path dir = fs::temp_directory_path() / ("blendbench_bench_load_" + std::to_string(::getpid()));
  Folder() { fs::create_directories(dir); }
  ~Folder() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

const Files& files(int n) {
  static const Folder folder;
  static std::map<int, Files> cache;
  auto it = cache.find(n);
  if (it != cache.end()) return it->second;
  const fs::path& dir = folder.dir;
  const Part part = make_part(n);
  Files f{(dir / ("seam_" + std::to_string(n) + ".yaml")).string(), (dir / ("seam_" + std::to_string(n) + ".ngc")).string()};
  std::ofstream(f.yaml) << part.yaml;
  std::ofstream(f.gcode) << part.gcode;
  return cache.emplace(n, f).first->second;
}

void BM_LoadScenarioYaml(benchmark::State& state) {
  const Files& f = files(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    const Scenario sc = load_scenario(f.yaml);
    benchmark::DoNotOptimize(sc.program.moves.data());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
  state.counters["bytes"] = static_cast<double>(fs::file_size(f.yaml));
}

void BM_LoadGcode(benchmark::State& state) {
  const Files& f = files(static_cast<int>(state.range(0)));
  GcodeOptions options;
  options.limits = {0.1, 2.0, 2.0, 20.0};
  for (auto _ : state) {
    const GcodeResult r = load_gcode_file(f.gcode, options);
    validate(r.program);
    benchmark::DoNotOptimize(r.program.moves.data());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
  state.counters["bytes"] = static_cast<double>(fs::file_size(f.gcode));
}

BENCHMARK(BM_LoadScenarioYaml)->RangeMultiplier(10)->Range(1000, 100000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LoadGcode)->RangeMultiplier(10)->Range(1000, 100000)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace blendbench

BENCHMARK_MAIN();
