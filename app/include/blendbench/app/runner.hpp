#pragma once
// The whole pipeline for one scenario: per variant, blend -> time -> IK ->
// simulate -> metrics, then results on disk (summary.json, per-variant trace.csv, path.csv,
// program.csv, corners.json, plots, video.mp4, and report.html; compare.mp4 on request). Used by
// `blendbench run` and the end-to-end test. Videos are rendered after each variant's simulation
// from its recorded poses; each render draws a progress bar on stderr when it is a terminal and
// prints one summary line there.

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "blendbench/app/run_summary.hpp"
#include "blendbench/io/scenario.hpp"

namespace blendbench {

struct RunRequest {
  std::filesystem::path out_dir;      // created if missing; files in it are replaced atomically
  bool video = true;                  // render video.mp4 per variant (needs BLENDBENCH_RENDER)
  bool compare = false;               // render compare.mp4: every variant side by side (needs BLENDBENCH_RENDER)
  bool plots = true;                  // run the matplotlib script after the summary is written
  bool variant_files = true;          // per variant trace.csv, path.csv, program.csv, corners.json (a sweep keeps only summary.json)
  std::vector<std::string> variants;  // names to run; empty = all
  std::optional<LimitsMode> limits;   // replaces the scenario's limits mode (`--limits`)
  std::optional<double> max_samples;  // replaces TimingOptions::max_samples (`--max-samples`)
  // receives one line of progress at a time (variant started, stage timings, warnings)
  std::function<void(const std::string&)> progress;
};

struct RunResult {
  RunSummary summary;  // what summary.json holds (to_json)
  bool all_ok = true;  // every variant's status is ok (clean tracking data)
  std::optional<std::filesystem::path> report;  // report.html, when the plots were drawn
};

// Runs the scenario. Throws InputError for bad input found on the way (an unknown variant
// name, a target the robot cannot reach: the error names the move's file, line and field), and
// std::runtime_error when results cannot be written. A variant whose simulation diverges, whose
// plan fails or whose data is not clean (saturated, outside the joint limits, not settled) is
// recorded with its status and message and the others still run. Also InputError when
// robot.model does not match the MJCF file, or the servo rate does not divide the model's
// physics rate (located at the YAML key).
RunResult run_scenario(const Scenario& scenario, const RunRequest& request);

// Whether this build can render videos.
bool video_supported();

}  // namespace blendbench
