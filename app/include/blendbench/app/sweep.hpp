#pragma once
// `blendbench sweep`: runs every point of a sweep (sweep_spec.hpp) headless and collects one
// table (sweep_results.hpp), locally on a pool of child processes or as a Slurm job array.
//
// Files under the output folder DIR:
//   sweep.plan.json          the expanded sweep: axes, values, and per point its hash and variants
//   points/<hash>/           one run, named by the content hash of its expanded scenario, its
//                            variants and the base scenario's folder: scenario.yaml, point.json
//                            (what the run needs besides the scenario), log.txt (its output),
//                            summary.json (the run's), status.json (how it ended, how long it took)
//   shards/<I>-of-<K>.json   which points shard I ran and how they ended (Slurm, --shard)
//   sweep.csv, sweep.json, best.csv, pareto.png, report.html   the results (--collect)
//   sweep.sbatch, slurm/     the job array and its logs (--slurm)
//
// A point runs as a child process of this program (`blendbench sweep --run-point DIR/points/<hash>`),
// started with an argument vector (never a shell): a crash fails that point alone, and a point's
// metrics do not depend on --jobs.

#include <cstddef>
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "blendbench/app/sweep_results.hpp"
#include "blendbench/io/sweep_spec.hpp"

namespace blendbench {

// The command line of `blendbench sweep`.
struct SweepCommand {
  std::string file;          // the sweep file (not with --collect)
  std::string out_dir;       // default: results/runs/sweeps/<file's stem>
  int jobs = 0;              // parallel runs; 0: the cores this process may use
  bool resume = false;       // skip points whose run finished (by content hash)
  bool plots = true;         // draw pareto.png (and embed it in report.html)
  bool slurm = false;        // write DIR/sweep.sbatch and submit it
  int array_size = 0;        // Slurm array tasks; 0: one per point, at most kDefaultArraySize
  std::string partition;     // Slurm partition (default: the cluster's)
  std::string time;          // Slurm time limit per task ("30", "1:00:00", "1-0")
  bool dry_run = false;      // with --slurm: write the script, do not submit
  std::string shard;         // "I/K": run shard I (0-based) of K, as a Slurm task does
  std::string collect;       // DIR: merge the points' results into the tables
  std::string run_point;     // internal: run one point's folder (the child process)
  std::string timing;        // `--timing`: set on every point's scenario ("optimal", "seed004"); empty: the scenario's
};

constexpr int kDefaultArraySize = 100;

// Runs the command; prints progress to stderr and results to `out`. Returns the exit code: 0 when
// every row ran ok, 1 when a point or variant failed or results are missing. Throws InputError
// (exit 2) for a bad sweep file, a point the scenario loader refuses, an unknown metric name, or
// contradictory flags, and std::runtime_error when files cannot be written.
int sweep_command(const SweepCommand& command, std::ostream& out);

// The plan as stored in DIR/sweep.plan.json, and back (scenario texts are not stored: each
// point's is in its folder). Throws InputError naming `file` when the JSON is not a plan.
nlohmann::json plan_json(const SweepPlan& plan);
SweepPlan plan_from_json(const nlohmann::json& j, const std::string& file);

// The indices of the points that are runs of their own: the first point of every hash (two
// points that expand to the same scenario share one run).
std::vector<std::size_t> distinct_runs(const SweepPlan& plan);

// The Slurm job array script: task SLURM_ARRAY_TASK_ID of `tasks` runs
// `BINARY sweep SWEEP_FILE --shard ID/tasks --out OUT_DIR --jobs CPUS` (and --resume when asked).
// Paths must be absolute; throws InputError when one cannot be written into the script (a
// whitespace, quote, '%' or control character), or for a partition or time Slurm would not read.
struct SbatchOptions {
  std::string partition;
  std::string time;
  int cpus_per_task = 1;
  bool resume = false;
  std::string timing;  // passed on as --timing (empty: not)
};
std::string sbatch_script(const std::string& binary, const std::string& sweep_file, const std::filesystem::path& out_dir,
                          std::size_t tasks, const SbatchOptions& options);

}  // namespace blendbench
