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

// The work of one variant is bounded before it is done. Its trace holds one sample per setpoint
// over the plan and the settle time after it, about kRunBytesPerSample of memory each (measured:
// the peak RSS of `blendbench run` grows by 2.1 kB per sample of settle time, trace.csv's text
// included), so a run holds at most kMaxRunSamples of them (1000 s at 500 Hz, about 1 GB):
// the settle time's share is refused at simulation.settle_time_s, the plan's by plan_timing at
// the move whose limit to raise. A video has at most kMaxVideoFrames frames (20 min at 30 fps),
// refused at video.fps. Both are InputError (exit 2) before the simulation starts.
inline constexpr double kRunBytesPerSample = 2.1e3;
inline constexpr double kMaxRunSamples = 5e5;
inline constexpr double kMaxVideoFrames = 36000;

struct RunRequest {
  std::filesystem::path out_dir;      // created if missing; files in it are replaced atomically
  bool video = true;                  // render video.mp4 per variant (needs BLENDBENCH_RENDER)
  bool compare = false;               // render compare.mp4: every variant side by side (needs BLENDBENCH_RENDER)
  bool plots = true;                  // run the matplotlib script after the summary is written
  bool variant_files = true;          // per variant trace.csv, path.csv, program.csv, corners.json (a sweep keeps only summary.json)
  std::vector<std::string> variants;  // names to run; empty = all
  std::optional<LimitsMode> limits;   // replaces the scenario's limits mode (`--limits`)
  std::optional<TimingOptions::Algorithm> timing;  // replaces the scenario's and variants' velocity planner (`--timing`)
  std::optional<double> max_samples;  // replaces kMaxRunSamples, plan and settle time (`--max-samples`)
  // receives one line of progress at a time (variant started, stage timings, warnings)
  std::function<void(const std::string&)> progress;
};

struct RunResult {
  RunSummary summary;  // what summary.json holds (to_json)
  bool all_ok = true;  // every variant's status is ok (clean tracking data); false when interrupted
  int interrupted_by = 0;  // the signal that stopped the run (core/interrupt.hpp), 0 when none
  std::optional<std::filesystem::path> report;  // report.html, when the plots were drawn
};

// Runs the scenario. Throws InputError for bad input of the whole scenario, found before any
// variant runs (an unknown variant name, a start point the robot cannot reach, robot.model not
// matching the MJCF file, a servo rate that does not divide the model's physics rate: the error
// names the file, line and field), and std::runtime_error when summary.json cannot be written. A
// variant whose simulation diverges, whose plan fails, whose data is not clean (saturated,
// outside the joint limits, not settled), whose path leaves the robot's reach or limits or whose
// files cannot be written ("failed", the message naming the move where it applies) is recorded
// with its status and message and the others still run. A stop request (SIGINT/SIGTERM) ends
// the variant in progress (its folder removed), marks it and the rest "interrupted", writes
// summary.json without plots and returns with interrupted_by set.
RunResult run_scenario(const Scenario& scenario, const RunRequest& request);

// Whether this build can render videos.
bool video_supported();

}  // namespace blendbench
