#pragma once
// The whole pipeline for one scenario (DESIGN: data flow): per variant, blend -> time -> IK ->
// simulate -> metrics, then results on disk (summary.json, per-variant trace.csv, path.csv,
// program.csv, corners.json, plots, video.mp4). Used by `blendbench run` and the end-to-end test.

#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "blendbench/io/scenario.hpp"

namespace blendbench {

struct RunRequest {
  std::filesystem::path out_dir;      // created if missing; files in it are replaced atomically
  bool video = true;                  // render video.mp4 per variant (needs BLENDBENCH_RENDER)
  bool plots = true;                  // run the matplotlib script after the summary is written
  std::vector<std::string> variants;  // names to run; empty = all
  std::optional<LimitsMode> limits;   // replaces the scenario's limits mode (`--limits`)
  std::optional<double> max_samples;  // replaces TimingOptions::max_samples (`--max-samples`)
  // receives one line of progress at a time (variant started, stage timings, warnings)
  std::function<void(const std::string&)> progress;
};

struct RunResult {
  nlohmann::json summary;  // what summary.json holds
  bool all_ok = true;      // every variant ran without divergence or planning failure
};

// Runs the scenario. Throws InputError for bad input found on the way (an unknown variant
// name, a target the robot cannot reach: the error names the move's file, line and field), and
// std::runtime_error when results cannot be written. A variant whose simulation diverges or
// whose plan fails is recorded with its status and message and the others still run.
RunResult run_scenario(const Scenario& scenario, const RunRequest& request);

// Whether this build can render videos.
bool video_supported();

}  // namespace blendbench
