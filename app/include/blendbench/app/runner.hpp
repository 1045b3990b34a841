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
#include "blendbench/app/smoothing_flags.hpp"
#include "blendbench/io/run_inputs.hpp"
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
  // where out_dir is published when the run ends (a staging folder renamed, report/run_folder.hpp),
  // for the paths the summary names; empty: out_dir itself
  std::filesystem::path published_dir;
  bool video = true;                  // render video.mp4 per variant (needs BLENDBENCH_RENDER)
  bool compare = false;               // render compare.mp4: every variant side by side (needs BLENDBENCH_RENDER)
  bool plots = true;                  // run the matplotlib script after the summary is written
  bool variant_files = true;          // per variant trace.csv, path.csv, program.csv, corners.json (a sweep keeps only summary.json)
  std::optional<double> max_samples;  // replaces kMaxRunSamples, plan and settle time (`--max-samples`)
  // `--smoothing` replaces every variant's method, `--smoothing-tolerance` the tolerance of
  // those that fit g2_fit (apply_smoothing_flags_to_variant)
  SmoothingFlags smoothing;
  // the constraints of the recommendation (`--max-contour-error`, `--max-vibration`; ranking.hpp)
  Constraints constraints;
  // what runs on perturbed arm models say about the order of two variants' cycle times (the
  // sensitivity runs): the ties are decided by it where it answers (ranking.hpp); empty: none
  OrderSpread spread;
  // `--sensitivity`: after the nominal runs, every variant that ran cleanly re-run on the
  // scenario's perturbed models (RunInputs::sensitivity), `jobs` simulations at a time (0: the
  // cores this process may use); summary.json gets `sensitivity`, and unless `spread` is given,
  // the ranking's ties follow its cycle-time conclusions (sensitivity.hpp, order_spread)
  bool sensitivity = false;
  int jobs = 0;
  // receives one line of progress at a time (variant started, stage timings, warnings)
  std::function<void(const std::string&)> progress;
};

struct RunResult {
  RunSummary summary;  // what summary.json holds (to_json)
  bool all_ok = true;  // every variant's status is ok (clean tracking data); false when interrupted
  int interrupted_by = 0;  // the signal that stopped the run (core/interrupt.hpp), 0 when none
  std::optional<std::filesystem::path> report;  // report.html, when the plots were drawn
};

// Runs the resolved scenario (io/run_inputs.hpp: `run`, `compare` and sweep points resolve once
// and hand the same inputs down). Throws InputError for bad input of the whole scenario, found
// before any variant runs (bad smoothing flags, a start point the robot cannot reach, robot.model not
// matching the MJCF file, a servo rate that does not divide the model's physics rate: the error
// names the file, line and field), and std::runtime_error when summary.json cannot be written. A
// variant whose simulation diverges, whose plan fails, whose data is not clean (saturated,
// outside the joint limits, not settled), whose path leaves the robot's reach or limits or whose
// files cannot be written ("failed", the message naming the move where it applies) is recorded
// with its status and message and the others still run. A stop request (SIGINT/SIGTERM) ends
// the variant in progress (its folder removed), marks it and the rest "interrupted", writes
// summary.json without plots and returns with interrupted_by set.
RunResult run_pipeline(const RunInputs& inputs, const RunRequest& request);

// run_pipeline(resolve_run(scenario), request): every variant of the scenario as written.
RunResult run_scenario(const Scenario& scenario, const RunRequest& request);

// Loads and checks the scenario's robot as run_scenario does before its first variant (the URDF,
// the MJCF and every file it names or the model built from the URDF, robot.model, the servo rate
// against the model's timestep, the start pose, the servo's tuning), without running anything:
// `validate` opens the files `run` opens. Throws InputError.
void check_robot(const Scenario& scenario);

// Whether this build can render videos.
bool video_supported();

}  // namespace blendbench
