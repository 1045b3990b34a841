#pragma once
// Internal to the sweep: a point's folder and its files, and the pool that runs points as child
// processes (sweep.hpp describes the folder layout).

#include <cstddef>
#include <filesystem>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "blendbench/app/sweep_results.hpp"
#include "blendbench/io/sweep_spec.hpp"
#include "blendbench/report/output.hpp"

namespace blendbench::sweep_detail {

std::filesystem::path point_dir(const std::filesystem::path& out_dir, const SweepPoint& point);

// The point's folder DIR/points/<hash> in the sweep's folder (created when `create`, else nullopt
// when absent); every file of a sweep is reached through the sweep's OutputDir, never through a
// symbolic link planted in it (report/output.hpp).
std::optional<OutputDir> point_folder(const OutputDir& sweep_dir, const SweepPoint& point, bool create);

// How a point's run ended, from its status.json (and summary.json, keeping the metrics that are
// default metrics or in `named`; `known` receives every metric name of the ok variants); nullopt
// when it has not finished (no status.json, or one that is not a status).
std::optional<PointOutcome> read_outcome(const OutputDir& dir, const std::set<std::string>& named, std::set<std::string>* known);

struct PoolStats {
  std::size_t runs = 0;      // points asked for
  std::size_t ran = 0;       // run now
  std::size_t resumed = 0;   // skipped: finished before (--resume)
  std::size_t not_ok = 0;    // ran or resumed with a status other than ok
  double wall_s = 0;         // from start to the last run's end
};

// Runs plan.points[i] for every i in `runs`, `jobs` child processes at a time. With `resume`,
// a point whose folder holds its scenario and a status other than crashed is skipped. After the
// first point that ran ok, the metric names the sweep uses are checked against its summary
// (InputError, after the running points end). Draws a progress bar on stderr when it is a
// terminal and reports failed points there.
PoolStats run_pool(const SweepPlan& plan, const std::vector<std::size_t>& runs, const OutputDir& out_dir, int jobs,
                   bool resume);

// The child process: runs the point folder `dir` (scenario.yaml and point.json) headless and
// writes dir/summary.json. Returns 0 when every variant ran ok, else 1; throws InputError.
int run_point_folder(const std::filesystem::path& dir);

// The cores this process may run on (its CPU affinity), at least 1.
int available_cores();

}  // namespace blendbench::sweep_detail
