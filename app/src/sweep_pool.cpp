#include "sweep_pool.hpp"

#include <sched.h>
#include <signal.h>
#include <sys/prctl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <mutex>
#include <set>
#include <sstream>
#include <thread>

#include "blendbench/app/runner.hpp"
#include "blendbench/core/interrupt.hpp"
#include "blendbench/io/scenario.hpp"
#include "blendbench/report/output.hpp"
#include "blendbench/report/process.hpp"
#include "progress_bar.hpp"

namespace blendbench::sweep_detail {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

// The environment variable through which a point's child learns its sweep's pid.
constexpr const char* kParentVariable = "BLENDBENCH_SWEEP_PARENT";

// A JSON file of the sweep's folder; null when absent, discarded (null-like) when malformed.
nlohmann::json read_json_or_null(const OutputDir& dir, const std::string& name, const std::string& what) {
  const std::optional<std::string> text = dir.read(name, what);
  if (!text) return nullptr;
  return nlohmann::json::parse(*text, nullptr, false);
}

// The last line the child printed that says something: why a run stopped.
std::string last_line(const OutputDir& dir) {
  std::string text;
  try {
    text = dir.read("log.txt", "point's log").value_or("");
  } catch (const InputError& e) {
    return e.what();
  }
  std::string last;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    if (line.find_first_not_of(" \t\r") != std::string::npos) last = line;
  }
  return last;
}

// Runs one point in its folder and records how it ended in status.json.
PointOutcome run_one(const SweepPlan& plan, const SweepPoint& point, const OutputDir& dir, const std::string& self,
                     std::set<std::string>& known) {
  dir.write("point.json", nlohmann::json({{"base_dir", plan.base_dir}, {"variants", point.variants}}).dump(2) + "\n");
  if (dir.read("scenario.yaml", "point's scenario") != point.scenario_text) dir.write("scenario.yaml", point.scenario_text);
  // nothing of an earlier run may stand for this one
  dir.remove("status.json");
  dir.remove("summary.json");

  const auto start = Clock::now();
  ProcessOptions options;
  // the log: a new file in the point's folder, whatever was there (a link planted at its name is
  // replaced, not written through)
  options.output_fd = dir.create_fresh("log.txt");
  // the child ends with this process, however this one ends (run_point_folder)
  options.environment = {std::string(kParentVariable) + "=" + std::to_string(::getpid())};
  ProcessResult result;
  try {
    result = run_process({self, "sweep", "--run-point", dir.path().string()}, options);
  } catch (...) {
    ::close(options.output_fd);
    throw;
  }
  ::close(options.output_fd);
  PointOutcome outcome;
  outcome.wall_time_s = std::chrono::duration<double>(Clock::now() - start).count();
  const nlohmann::json summary = read_json_or_null(dir, "summary.json", "point's run summary");
  outcome.has_summary = summary.is_object();
  outcome.variants = variant_results(summary, named_metrics(plan.spec), &known);
  if (result.ok) {
    outcome.status = "ok";
  } else if (result.signal != 0) {
    outcome.status = "crashed";
    outcome.message = result.message;
  } else if (result.exit_status == 128 + SIGINT || result.exit_status == 128 + SIGTERM) {
    // stopped by Ctrl-C or SIGTERM (core/interrupt.hpp): run again on --resume
    outcome.status = "interrupted";
    outcome.message = result.message;
  } else if (result.exit_status == 1 && outcome.has_summary) {
    outcome.status = "failed";
    outcome.message = "a variant failed";
  } else {
    outcome.status = "error";
    const std::string line = last_line(dir);
    outcome.message = line.empty() ? result.message : line;
  }
  nlohmann::json status = {{"status", outcome.status},
                           {"exit_status", result.exit_status},
                           {"signal", result.signal},
                           {"wall_time_s", outcome.wall_time_s}};
  if (!outcome.message.empty()) status["message"] = outcome.message;
  dir.write("status.json", status.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
  return outcome;
}

// The progress bar of the points: drawn in place on a terminal, silent otherwise.
class Progress {
 public:
  Progress(std::size_t total, std::size_t resumed) : total_(total), resumed_(resumed) {}

  void draw(std::size_t ran, std::size_t not_ok, std::size_t running) const {
    const std::size_t done = ran + resumed_;
    bar_.draw(done, total_,
              std::to_string(done) + "/" + std::to_string(total_) + " points, " + std::to_string(running) + " running, " +
                  std::to_string(not_ok) + " not ok",
              ran);
  }

  // A line above the bar (a failed point).
  void say(const std::string& line) const { bar_.say(line); }

  void finish() const { bar_.finish(); }

 private:
  std::size_t total_;
  std::size_t resumed_;
  ProgressBar bar_;
};

}  // namespace

fs::path point_dir(const fs::path& out_dir, const SweepPoint& point) { return out_dir / "points" / point.hash; }

std::optional<OutputDir> point_folder(const OutputDir& sweep_dir, const SweepPoint& point, bool create) {
  if (create) return sweep_dir.sub("points").sub(point.hash);
  const std::optional<OutputDir> points = sweep_dir.find("points");
  return points ? points->find(point.hash) : std::nullopt;
}

std::optional<PointOutcome> read_outcome(const OutputDir& dir, const std::set<std::string>& named, std::set<std::string>* known) {
  const nlohmann::json status = read_json_or_null(dir, "status.json", "point's status");
  if (!status.is_object() || !status.contains("status") || !status["status"].is_string()) return std::nullopt;
  PointOutcome outcome;
  outcome.status = status["status"].get<std::string>();
  const auto text = [&](const char* key) {
    const auto it = status.find(key);
    return it != status.end() && it->is_string() ? it->get<std::string>() : std::string();
  };
  outcome.message = text("message");
  const auto wall = status.find("wall_time_s");
  outcome.wall_time_s = wall != status.end() && wall->is_number() ? wall->get<double>() : 0.0;
  const nlohmann::json summary = read_json_or_null(dir, "summary.json", "point's run summary");
  outcome.has_summary = summary.is_object();
  outcome.variants = variant_results(summary, named, known);
  return outcome;
}

int available_cores() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (::sched_getaffinity(0, sizeof set, &set) == 0) return std::max(1, CPU_COUNT(&set));
  return std::max(1U, std::thread::hardware_concurrency());
}

PoolStats run_pool(const SweepPlan& plan, const std::vector<std::size_t>& runs, const OutputDir& out_dir, int jobs,
                   bool resume) {
  PoolStats stats;
  stats.runs = runs.size();
  const auto start = Clock::now();

  // finished points are skipped on --resume: same scenario text, a status other than crashed
  std::vector<std::size_t> todo;
  for (const std::size_t i : runs) {
    const SweepPoint& point = plan.points[i];
    const std::optional<OutputDir> dir = resume ? point_folder(out_dir, point, false) : std::nullopt;
    if (dir) {
      const std::optional<PointOutcome> done = read_outcome(*dir, {}, nullptr);
      if (done && done->status != "crashed" && done->status != "interrupted" &&
          dir->read("scenario.yaml", "point's scenario") == point.scenario_text) {
        ++stats.resumed;
        stats.not_ok += done->status == "ok" ? 0 : 1;
        continue;
      }
    }
    todo.push_back(i);
  }

  const std::string self = fs::read_symlink("/proc/self/exe").string();
  const std::set<std::string> no_names;
  std::mutex mutex;
  std::condition_variable changed;
  std::atomic<std::size_t> next{0};
  std::atomic<bool> stop{false};
  std::size_t finished = 0;
  std::size_t running = 0;
  bool names_checked = plan.spec.named_metrics.empty();
  std::optional<InputError> names_error;
  std::exception_ptr failure;
  const Progress progress(runs.size(), stats.resumed);

  // each worker takes the next point, runs it as a child process and reports the outcome
  const auto worker = [&]() {
    for (;;) {
      if (stop || stop_requested()) return;
      const std::size_t k = next++;
      if (k >= todo.size()) return;
      const SweepPoint& point = plan.points[todo[k]];
      {
        const std::lock_guard<std::mutex> lock(mutex);
        ++running;
      }
      PointOutcome outcome;
      std::set<std::string> known;
      try {
        outcome = run_one(plan, point, *point_folder(out_dir, point, true), self, known);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(mutex);
        if (!failure) failure = std::current_exception();
        stop = true;
        --running;
        changed.notify_all();
        return;
      }
      const std::lock_guard<std::mutex> lock(mutex);
      --running;
      ++finished;
      if (outcome.status != "ok") {
        ++stats.not_ok;
        progress.say("point " + std::to_string(point.index) + " (" + point_values_text(plan.spec, point) + "): " +
                     outcome.status + (outcome.message.empty() ? "" : ": " + outcome.message) + " [" +
                     (point_dir(out_dir.path(), point) / "log.txt").string() + "]");
      }
      // the metric names of the sweep file, against the first summary that has ok variants
      if (!names_checked) {
        if (!known.empty()) {
          names_checked = true;
          try {
            check_metric_names(plan.spec, known);
          } catch (const InputError& e) {
            names_error = e;
            stop = true;
          }
        }
      }
      changed.notify_all();
    }
  };

  const int workers = std::max(1, std::min<int>(jobs, static_cast<int>(todo.size())));
  std::vector<std::thread> threads;
  for (int w = 0; w < workers && !todo.empty(); ++w) threads.emplace_back(worker);
  {
    std::unique_lock<std::mutex> lock(mutex);
    while (finished < todo.size() && !stop && !stop_requested()) {
      progress.draw(finished, stats.not_ok, running);
      changed.wait_for(lock, std::chrono::milliseconds(500));
    }
    progress.draw(finished, stats.not_ok, running);
  }
  for (std::thread& t : threads) t.join();
  progress.finish();
  // a stop request: no new point was started, the running ones ended
  throw_if_stop_requested();
  if (failure) std::rethrow_exception(failure);
  if (names_error) throw *names_error;
  stats.ran = finished;
  stats.wall_s = std::chrono::duration<double>(Clock::now() - start).count();
  return stats;
}

int run_point_folder(const fs::path& dir) {
  // a point runs only while the sweep that started it does: SIGTERM when it ends, SIGKILL
  // included (the request is checked at every step, and the watchdog ends what blocks); a sweep
  // that ended before the request was made is seen by the parent's pid
  if (const char* parent = std::getenv(kParentVariable); parent != nullptr) {
    ::prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (std::to_string(::getppid()) != parent) throw Interrupted{SIGTERM};
  }
  // the point's folder and the points/ folder above it are real folders: the run writes its
  // summary there and must not be sent elsewhere by a link planted in the sweep's folder
  for (const fs::path& folder : {dir, dir.parent_path()}) {
    std::error_code ec;
    if (!folder.empty() && fs::symlink_status(folder, ec).type() == fs::file_type::symlink) {
      throw InputError(folder.string(), 0, 0, "--run-point", "is a symbolic link: a point's folder must be a folder of the sweep");
    }
  }
  const OutputDir folder = [&] {
    try {
      return OutputDir(dir, false);
    } catch (const std::runtime_error& e) {
      throw InputError(dir.string(), 0, 0, "--run-point", e.what());
    }
  }();
  const std::optional<std::string> text = folder.read("scenario.yaml", "point's scenario");
  if (!text) throw InputError((dir / "scenario.yaml").string(), 0, 0, "--run-point", "no scenario.yaml in the point folder");
  const nlohmann::json point = read_json_or_null(folder, "point.json", "point file");
  if (!point.is_object() || !point["base_dir"].is_string() || !point["variants"].is_array()) {
    throw InputError((dir / "point.json").string(), 0, 0, "--run-point", "not a sweep point's point.json");
  }
  for (const nlohmann::json& v : point["variants"]) {
    if (!v.is_string()) throw InputError((dir / "point.json").string(), 0, 0, "--run-point", "not a sweep point's point.json");
  }
  const Scenario scenario = parse_scenario(*text, (dir / "scenario.yaml").string(), point["base_dir"].get<std::string>());
  RunRequest request;
  request.out_dir = dir;
  request.video = false;
  request.plots = false;
  request.variant_files = false;
  request.progress = [](const std::string& line) { std::cout << line << '\n'; };
  // resolved once, as a plain run of the same values is
  RunSelection selection;
  selection.variants = point["variants"].get<std::vector<std::string>>();
  const RunResult result = run_pipeline(resolve_run(scenario, selection), request);
  std::cout.flush();
  if (result.interrupted_by != 0) throw Interrupted{result.interrupted_by};
  return result.all_ok ? 0 : 1;
}

}  // namespace blendbench::sweep_detail
