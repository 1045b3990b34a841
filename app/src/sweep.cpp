// `blendbench sweep`: the modes of the command (local pool, one shard, Slurm array, collect, the
// child that runs one point) and the plan kept on disk between them.

#include "blendbench/app/sweep.hpp"

#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <ostream>
#include <sstream>

#include "blendbench/io/data_root.hpp"
#include "blendbench/report/output.hpp"
#include "blendbench/report/process.hpp"
#include "sweep_pool.hpp"

namespace blendbench {
namespace {

namespace fs = std::filesystem;
using sweep_detail::point_dir;

constexpr int kExitOk = 0;
constexpr int kExitNotOk = 1;
constexpr const char* kPlanFile = "sweep.plan.json";

nlohmann::json where_json(const SourceRef& where) { return {{"line", where.line}, {"column", where.column}}; }

// An object of the plan with the sweep file line and column it came from.
nlohmann::json located(const SourceRef& where, nlohmann::json object) {
  object.update(where_json(where));
  return object;
}

SourceRef where_from(const nlohmann::json& j, const std::string& file) {
  return {file, j.value("line", 0), j.value("column", 0)};
}

constexpr const char* kLockFile = ".blendbench-sweep.lock";

nlohmann::json read_plan(const OutputDir& dir) {
  const std::string file = (dir.path() / kPlanFile).string();
  const std::optional<std::string> text = dir.read(kPlanFile, "sweep plan");
  if (!text) {
    throw InputError(file, 0, 0, "--collect", "no sweep plan here: run `blendbench sweep FILE --out DIR` (or --slurm) first");
  }
  nlohmann::json j = nlohmann::json::parse(*text, nullptr, false);
  if (j.is_discarded()) throw InputError(file, 0, 0, "", "invalid JSON in the sweep plan");
  return j;
}

// The sweep's folder, opened (and created) as the folder a sweep writes into; a folder the system
// refuses is bad input of `flag`.
OutputDir open_sweep_dir(const fs::path& path, bool create, const std::string& flag) {
  try {
    return OutputDir(path, create);
  } catch (const std::runtime_error& e) {
    throw InputError("", 0, 0, flag, e.what());
  }
}

// The sweep's lock, held while the sweep writes into its folder: exclusive for a local sweep, the
// Slurm submission and --collect (which write the plan and the tables), shared for the shards of
// an array (which run their own points of one plan side by side). A second sweep into a folder in
// use is refused at once: two sweeps would mix their plans and points.
class SweepLock {
 public:
  SweepLock(const OutputDir& dir, bool shared, const std::string& flag) : fd_(dir.try_lock(kLockFile, shared)) {
    if (fd_ < 0) {
      const std::string holder = dir.lock_holder(kLockFile);
      throw InputError("", 0, 0, flag,
                       dir.path().string() + " is in use by another sweep" + (holder.empty() ? "" : " (pid " + holder + ")") +
                           ": wait for it or choose another folder");
    }
  }
  ~SweepLock() { ::close(fd_); }
  SweepLock(const SweepLock&) = delete;
  SweepLock& operator=(const SweepLock&) = delete;

 private:
  int fd_;
};

// "I/K" with 0 <= I < K.
std::pair<std::size_t, std::size_t> parse_shard(const std::string& text) {
  const std::size_t slash = text.find('/');
  const auto digits = [](const std::string& s) {
    return !s.empty() && s.size() <= 9 && s.find_first_not_of("0123456789") == std::string::npos;
  };
  const std::string i = slash == std::string::npos ? "" : text.substr(0, slash);
  const std::string k = slash == std::string::npos ? "" : text.substr(slash + 1);
  if (!digits(i) || !digits(k) || std::stoul(k) == 0 || std::stoul(i) >= std::stoul(k)) {
    throw InputError("", 0, 0, "--shard", "expected I/K with 0 <= I < K (shard I of K, from 0), got '" + text + "'");
  }
  return {std::stoul(i), std::stoul(k)};
}

// Validates one point; a refused point's scenario is written to its folder so the loader's message
// names a file that exists.
void validate_in(const SweepPlan& plan, const SweepPoint& point, const OutputDir& dir) {
  const fs::path file = point_dir(dir.path(), point) / "scenario.yaml";
  try {
    validate_point(plan, point, file.string());
  } catch (const InputError&) {
    sweep_detail::point_folder(dir, point, true)->write("scenario.yaml", point.scenario_text);
    throw;
  }
}

// Validates the points `indices` (the first of each hash is enough).
void validate_points(const SweepPlan& plan, const std::vector<std::size_t>& indices, const OutputDir& dir) {
  for (const std::size_t i : indices) validate_in(plan, plan.points[i], dir);
}

// The plan as text: strings that are not UTF-8 (a name in the base scenario) replaced, never a
// library's error.
std::string plan_text(const SweepPlan& plan) {
  return plan_json(plan).dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

// The plan file, rewritten only when it changes.
void write_plan(const OutputDir& dir, const SweepPlan& plan) {
  const std::string text = plan_text(plan);
  if (dir.read(kPlanFile, "sweep plan") != text) dir.write(kPlanFile, text);
}

// Whether two plans expand to the same points (the sweep file's name may be written differently).
bool same_plan(nlohmann::json a, nlohmann::json b) {
  a.erase("sweep_file");
  b.erase("sweep_file");
  return a == b;
}

std::string jobs_text(int jobs) { return "--jobs " + std::to_string(jobs); }

// The tables from the points' results: sweep.csv, sweep.json, best.csv, pareto.png, report.html.
int collect(const OutputDir& dir, bool plots, std::ostream& out) {
  const fs::path& out_dir = dir.path();
  const SweepPlan plan = plan_from_json(read_plan(dir), (out_dir / kPlanFile).string());
  // one outcome per point; a point that shares its run with an earlier one copies it
  std::vector<PointOutcome> outcomes;
  outcomes.reserve(plan.points.size());
  std::map<std::string, std::size_t> first_of_hash;
  std::vector<std::size_t> missing;
  const std::set<std::string> named = named_metrics(plan.spec);
  std::set<std::string> known;
  for (const SweepPoint& p : plan.points) {
    if (const auto seen = first_of_hash.find(p.hash); seen != first_of_hash.end()) {
      outcomes.push_back(outcomes[seen->second]);
      continue;
    }
    first_of_hash.emplace(p.hash, p.index);
    const std::optional<OutputDir> folder = sweep_detail::point_folder(dir, p, false);
    std::optional<PointOutcome> outcome = folder ? sweep_detail::read_outcome(*folder, named, &known) : std::nullopt;
    if (!outcome) missing.push_back(p.index);
    outcomes.push_back(outcome ? std::move(*outcome) : PointOutcome());
  }
  if (!missing.empty()) {
    std::string list;
    for (std::size_t k = 0; k < missing.size() && k < 10; ++k) list += (k == 0 ? "" : ", ") + std::to_string(missing[k]);
    if (missing.size() > 10) list += ", ...";
    out << "sweep: " << missing.size() << " of " << plan.points.size() << " points have no result yet (points " << list
        << "); run their shards again, or `blendbench sweep FILE --out DIR --resume`" << std::endl;
    return kExitNotOk;
  }
  const SweepTable table = build_table(plan, std::move(outcomes), known);

  dir.write("sweep.csv", sweep_csv(plan, table));
  dir.write("sweep.json", sweep_json(plan, table).dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n");
  dir.write("best.csv", best_csv(plan, table));
  std::string png;
  if (plots) {
    // the script writes pareto.png by name: whatever stands there (a link) is removed first, so
    // it writes a new file in the folder
    dir.remove("pareto.png");
    // an argument vector, no shell: the output folder is data, whatever characters it holds
    const ProcessResult plotted =
        run_process({"/usr/bin/python3", data_file("report/scripts/plot_sweep.py"), out_dir.string()});
    if (plotted.ok) {
      png = dir.read("pareto.png", "Pareto plot").value_or("");
    } else {
      std::cerr << "sweep: warning: the plot script failed (" << plotted.message << ")" << std::endl;
    }
  }
  dir.write("report.html", report_html(plan, table, png));

  out << best_text(plan, table);
  std::size_t not_ok = 0;
  for (const SweepRow& row : table.rows) not_ok += row.status == "ok" ? 0 : 1;
  out << "sweep: " << table.rows.size() << " rows (" << not_ok << " not ok) -> " << (out_dir / "sweep.csv").string() << ", "
      << (out_dir / "best.csv").string() << (png.empty() ? "" : ", " + (out_dir / "pareto.png").string()) << ", "
      << (out_dir / "report.html").string() << std::endl;
  return not_ok == 0 ? kExitOk : kExitNotOk;
}

// The summary line of a pool: how many ran, how fast.
void report_pool(const std::string& what, const sweep_detail::PoolStats& stats, int jobs, std::ostream& out) {
  out << "sweep: " << what << stats.runs << " runs: " << stats.ran << " ran, " << stats.resumed << " resumed, " << stats.not_ok
      << " not ok; " << format_fixed(stats.wall_s, 1) << " s";
  if (stats.ran > 0 && stats.wall_s > 0) {
    out << ", " << format_fixed(static_cast<double>(stats.ran) / stats.wall_s, 2) << " points/s at " << jobs_text(jobs);
  }
  out << std::endl;
}

// Where sbatch is on PATH, or empty.
std::string find_on_path(const std::string& program) {
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path == nullptr ? "" : path);
  for (std::string dir; std::getline(dirs, dir, ':');) {
    const fs::path candidate = fs::path(dir.empty() ? "." : dir) / program;
    if (::access(candidate.c_str(), X_OK) == 0) return candidate.string();
  }
  return {};
}

int run_slurm(const SweepCommand& command, const SweepPlan& plan, const OutputDir& dir, std::ostream& out) {
  const fs::path& out_dir = dir.path();
  const std::vector<std::size_t> runs = distinct_runs(plan);
  validate_points(plan, runs, dir);
  write_plan(dir, plan);
  if (command.array_size < 0) throw InputError("", 0, 0, "--array-size", "must be at least 1");
  const std::size_t wanted = command.array_size > 0 ? static_cast<std::size_t>(command.array_size) : kDefaultArraySize;
  const std::size_t tasks = std::min(wanted, runs.size());
  SbatchOptions options;
  options.partition = command.partition;
  options.time = command.time;
  options.cpus_per_task = command.jobs > 0 ? command.jobs : 1;
  options.resume = command.resume;
  options.timing = command.timing;
  const std::string binary = fs::read_symlink("/proc/self/exe").string();
  const fs::path script = out_dir / "sweep.sbatch";
  dir.write("sweep.sbatch", sbatch_script(binary, fs::absolute(command.file).lexically_normal().string(), out_dir, tasks, options));
  const OutputDir slurm = dir.sub("slurm");
  out << "sweep: " << plan.points.size() << " points (" << runs.size() << " runs) in " << tasks << " array tasks -> "
      << script.string() << std::endl;

  const std::string sbatch = command.dry_run ? std::string() : find_on_path("sbatch");
  if (sbatch.empty()) {
    out << (command.dry_run ? "sweep: --dry-run: not submitted" : "sweep: sbatch not found on PATH: not submitted")
        << "; submit with `sbatch " << script.string() << "`, then `blendbench sweep --collect " << out_dir.string() << "`"
        << std::endl;
    return kExitOk;
  }
  ProcessOptions submit;
  submit.output_fd = slurm.create_fresh("submit.log");
  const ProcessResult result = run_process({sbatch, "--parsable", script.string()}, submit);
  ::close(submit.output_fd);
  const std::string reply = slurm.read("submit.log", "sbatch's reply").value_or("");
  if (!result.ok) {
    out << "sweep: sbatch failed (" << result.message << "): " << reply << std::endl;
    return kExitNotOk;
  }
  // --parsable prints "JOBID" or "JOBID;CLUSTER"
  const std::string job = reply.substr(0, reply.find_first_of(";\n"));
  slurm.write("job_id", job + "\n");
  out << "sweep: submitted Slurm job array " << job << " (" << tasks << " tasks); when it has ended: blendbench sweep --collect "
      << out_dir.string() << std::endl;
  return kExitOk;
}

int run_shard(const SweepCommand& command, const SweepPlan& plan, const OutputDir& dir, int jobs, std::ostream& out) {
  const auto [index, count] = parse_shard(command.shard);
  // every task of the array must expand the same sweep the plan holds
  const fs::path plan_file = dir.path() / kPlanFile;
  if (dir.read(kPlanFile, "sweep plan")) {
    if (!same_plan(read_plan(dir), nlohmann::json::parse(plan_text(plan)))) {
      throw InputError(command.file, 0, 0, "--shard",
                       "the sweep no longer expands to the points of " + plan_file.string() +
                           " (the sweep file or its scenario changed since the array was written): write it again with --slurm");
    }
  } else {
    write_plan(dir, plan);
  }
  const std::vector<std::size_t> all = distinct_runs(plan);
  std::vector<std::size_t> mine;
  for (std::size_t j = index; j < all.size(); j += count) mine.push_back(all[j]);
  validate_points(plan, mine, dir);
  const sweep_detail::PoolStats stats = sweep_detail::run_pool(plan, mine, dir, jobs, command.resume);

  nlohmann::json points = nlohmann::json::array();
  for (const std::size_t i : mine) points.push_back(i);
  dir.sub("shards").write(std::to_string(index) + "-of-" + std::to_string(count) + ".json",
                          nlohmann::json({{"shard", index},
                                    {"of", count},
                                    {"points", points},
                                    {"ran", stats.ran},
                                    {"resumed", stats.resumed},
                                    {"not_ok", stats.not_ok},
                                    {"wall_time_s", stats.wall_s}})
                            .dump(2) +
                        "\n");
  report_pool("shard " + std::to_string(index) + "/" + std::to_string(count) + ": ", stats, jobs, out);
  return stats.not_ok == 0 ? kExitOk : kExitNotOk;
}

void check_flags(const SweepCommand& c) {
  const bool slurm_only = c.dry_run || c.array_size != 0 || !c.partition.empty() || !c.time.empty();
  if (!c.collect.empty()) {
    if (!c.file.empty()) throw InputError("", 0, 0, "--collect", "takes the output folder only, not a sweep file");
    if (c.slurm || slurm_only || !c.shard.empty() || c.resume || !c.out_dir.empty()) {
      throw InputError("", 0, 0, "--collect", "merges a finished sweep: no --out, --resume, --shard or Slurm flags");
    }
    return;
  }
  if (c.file.empty()) throw InputError("", 0, 0, "FILE", "a sweep file is required (or --collect DIR)");
  if (slurm_only && !c.slurm) throw InputError("", 0, 0, "--slurm", "--dry-run, --array-size, --partition and --time need --slurm");
  if (c.slurm && !c.shard.empty()) throw InputError("", 0, 0, "--shard", "a shard is what a Slurm task runs: not with --slurm");
  if (c.jobs < 0) throw InputError("", 0, 0, "--jobs", "must be at least 1 (0: every core)");
}

}  // namespace

std::vector<std::size_t> distinct_runs(const SweepPlan& plan) {
  std::vector<std::size_t> out;
  std::map<std::string, std::size_t> seen;
  for (const SweepPoint& p : plan.points) {
    if (seen.emplace(p.hash, p.index).second) out.push_back(p.index);
  }
  return out;
}

nlohmann::json plan_json(const SweepPlan& plan) {
  const SweepSpec& spec = plan.spec;
  nlohmann::json variants = nlohmann::json::array();
  for (std::size_t i = 0; i < spec.variants.size(); ++i) variants.push_back(located(spec.variants_where[i], {{"name", spec.variants[i]}}));
  nlohmann::json axes = nlohmann::json::array();
  for (const SweepAxis& a : spec.axes) {
    axes.push_back(located(a.where, {{"path", a.path}, {"values", a.values}, {"labels", a.labels}}));
  }
  nlohmann::json constraints = nlohmann::json::array();
  for (const Constraint& c : spec.constraints) constraints.push_back(located(c.where, {{"text", c.text}}));
  nlohmann::json names = nlohmann::json::array();
  for (const MetricName& m : spec.named_metrics) names.push_back(located(m.where, {{"name", m.name}, {"field", m.field}}));
  nlohmann::json points = nlohmann::json::array();
  for (const SweepPoint& p : plan.points) points.push_back({{"choice", p.choice}, {"variants", p.variants}, {"hash", p.hash}});
  return {{"blendbench_sweep_plan", 1},
          {"sweep_file", spec.file},
          {"scenario", spec.scenario},
          {"description", spec.description},
          {"base_dir", plan.base_dir},
          {"variants", variants},
          {"axes", axes},
          {"axes_where", where_json(spec.axes_where)},
          {"metrics", spec.metrics},
          {"constraints", constraints},
          {"pareto", {{"x", spec.pareto_x}, {"y", spec.pareto_y}}},
          {"named_metrics", names},
          {"points", points}};
}

SweepPlan plan_from_json(const nlohmann::json& j, const std::string& file) {
  if (!j.is_object() || j.value("blendbench_sweep_plan", 0) != 1) throw InputError(file, 0, 0, "", "not a sweep plan (version 1)");
  try {
    SweepPlan plan;
    SweepSpec& spec = plan.spec;
    spec.file = j.at("sweep_file").get<std::string>();
    spec.scenario = j.at("scenario").get<std::string>();
    spec.description = j.at("description").get<std::string>();
    plan.base_dir = j.at("base_dir").get<std::string>();
    for (const nlohmann::json& v : j.at("variants")) {
      spec.variants.push_back(v.at("name").get<std::string>());
      spec.variants_where.push_back(where_from(v, spec.file));
    }
    for (const nlohmann::json& a : j.at("axes")) {
      SweepAxis axis;
      axis.path = a.at("path").get<std::string>();
      axis.where = where_from(a, spec.file);
      axis.steps = parse_key_path(axis.path, axis.where, "axes." + axis.path);
      axis.values = a.at("values").get<std::vector<std::string>>();
      axis.labels = a.at("labels").get<std::vector<std::string>>();
      spec.axes.push_back(std::move(axis));
    }
    spec.axes_where = where_from(j.at("axes_where"), spec.file);
    spec.metrics = j.at("metrics").get<std::vector<std::string>>();
    for (const nlohmann::json& c : j.at("constraints")) {
      spec.constraints.push_back(parse_constraint(c.at("text").get<std::string>(), where_from(c, spec.file), "constraints"));
    }
    spec.pareto_x = j.at("pareto").at("x").get<std::string>();
    spec.pareto_y = j.at("pareto").at("y").get<std::string>();
    for (const nlohmann::json& m : j.at("named_metrics")) {
      spec.named_metrics.push_back({m.at("name").get<std::string>(), m.at("field").get<std::string>(), where_from(m, spec.file)});
    }
    std::size_t index = 0;
    for (const nlohmann::json& p : j.at("points")) {
      SweepPoint point;
      point.index = index++;
      point.choice = p.at("choice").get<std::vector<std::size_t>>();
      point.variants = p.at("variants").get<std::vector<std::string>>();
      point.hash = p.at("hash").get<std::string>();
      // the hash names the point's folder: exactly what content_hash writes (16 hex digits), so a
      // plan cannot send a read or a run outside DIR/points/ ("../../secret/x")
      if (point.hash.size() != 16 || point.hash.find_first_not_of("0123456789abcdef") != std::string::npos) {
        throw InputError(file, 0, 0, "points[" + std::to_string(point.index) + "].hash",
                         "a point's hash must be 16 hexadecimal digits, got '" + printable(point.hash) + "'");
      }
      if (point.choice.size() != spec.axes.size()) throw InputError(file, 0, 0, "points", "a point's values do not match the axes");
      for (std::size_t a = 0; a < spec.axes.size(); ++a) {
        if (point.choice[a] >= spec.axes[a].labels.size()) throw InputError(file, 0, 0, "points", "a point's value is out of range");
      }
      plan.points.push_back(std::move(point));
    }
    return plan;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(file, 0, 0, "", std::string("not a sweep plan: ") + e.what());
  }
}

int sweep_command(const SweepCommand& command, std::ostream& out) {
  if (!command.run_point.empty()) return sweep_detail::run_point_folder(command.run_point);
  check_flags(command);
  if (!command.collect.empty()) {
    const OutputDir dir = open_sweep_dir(fs::absolute(command.collect).lexically_normal(), false, "--collect");
    const SweepLock lock(dir, false, "--collect");
    return collect(dir, command.plots, out);
  }

  SweepSpec spec = load_sweep(command.file);
  spec.timing = command.timing;
  const fs::path out_dir = fs::absolute(command.out_dir.empty() ? "results/runs/sweeps/" + fs::path(command.file).stem().string()
                                                                : command.out_dir)
                               .lexically_normal();
  const OutputDir dir = open_sweep_dir(out_dir, true, "--out");
  // shards of one array share the folder; anything else has it alone
  const SweepLock lock(dir, !command.shard.empty(), "--out");
  // the first point is validated as soon as it exists: an axis that makes no valid scenario is
  // refused before the whole product is expanded
  const SweepPlan plan =
      expand_sweep(spec, [&](const SweepPlan& first, const SweepPoint& point) { validate_in(first, point, dir); });
  const int jobs = command.jobs > 0 ? command.jobs : sweep_detail::available_cores();
  if (command.slurm) return run_slurm(command, plan, dir, out);
  if (!command.shard.empty()) return run_shard(command, plan, dir, jobs, out);

  // locally: every point on a pool, then the tables
  const std::vector<std::size_t> runs = distinct_runs(plan);
  validate_points(plan, runs, dir);
  write_plan(dir, plan);
  out << "sweep: " << command.file << ": " << plan.points.size() << " points (" << runs.size() << " runs) -> "
      << out_dir.string() << " at " << jobs_text(jobs) << std::endl;
  const sweep_detail::PoolStats stats = sweep_detail::run_pool(plan, runs, dir, jobs, command.resume);
  report_pool("", stats, jobs, out);
  return collect(dir, command.plots, out);
}

}  // namespace blendbench
