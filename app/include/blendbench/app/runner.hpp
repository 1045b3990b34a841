#pragma once
// The whole pipeline for one scenario (DESIGN: data flow): per variant, blend -> time -> IK ->
// simulate -> metrics, then results on disk (summary.json, per-variant trace.csv, path.csv,
// program.csv, corners.json, plots, video.mp4). Used by `blendbench run` and the end-to-end test.

#include <nlohmann/json.hpp>

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "blendbench/io/scenario.hpp"

namespace blendbench {

struct RunRequest {
  std::filesystem::path out_dir;      // created if missing; files in it are replaced atomically
  bool video = true;                  // render video.mp4 per variant (needs BLENDBENCH_RENDER)
  bool plots = true;                  // run the matplotlib script after the summary is written
  bool variant_files = true;          // per variant trace.csv, path.csv, program.csv, corners.json (a sweep keeps only summary.json)
  std::vector<std::string> variants;  // names to run; empty = all
  // receives one line of progress at a time (variant started, stage timings, warnings)
  std::function<void(const std::string&)> progress;
};

struct RunResult {
  nlohmann::json summary;  // what summary.json holds
  bool all_ok = true;      // every variant ran without divergence or planning failure (false when interrupted)
  int interrupted_by = 0;  // the signal that stopped the run (core/interrupt.hpp), 0 when none
};

// Runs the scenario. Throws InputError for bad input of the whole scenario (an unknown variant
// name, a start point the robot cannot reach, a variant's invalid transition: the error names
// the file, line and field), and std::runtime_error when summary.json cannot be written. A
// variant that cannot be planned, whose path leaves the robot's reach or limits, whose
// simulation diverges or whose files cannot be written is recorded with status "failed" and a
// message (naming the move where it applies) and the others still run. A stop request
// (SIGINT/SIGTERM) ends the variant in progress (its folder removed), marks it and the rest
// "interrupted", writes summary.json without plots and returns with interrupted_by set.
RunResult run_scenario(const Scenario& scenario, const RunRequest& request);

// Whether this build can render videos.
bool video_supported();

}  // namespace blendbench
