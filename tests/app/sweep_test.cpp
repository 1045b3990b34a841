// `blendbench sweep` as a user meets it, on the tiny scenario: results independent of --jobs,
// --resume skipping finished points, shards merged by --collect into the local table, a point
// that fails alone, bad values and names refused with exit 2, and the Slurm script.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "blendbench/report/process.hpp"
#include "support/property.hpp"

namespace blendbench {
namespace {

namespace fs = std::filesystem;

struct Result {
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

std::string read(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

class Sweep : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string name = ::testing::UnitTest::GetInstance()->current_test_info()->name();
    dir_ = fs::temp_directory_path() / ("blendbench_sweep_" + std::to_string(::getpid()) + "_" + name);
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Runs the program with an argument vector; output captured through a file.
  Result run(const std::vector<std::string>& args) {
    std::vector<std::string> argv = {blendbench::test::blendbench_binary()};
    argv.insert(argv.end(), args.begin(), args.end());
    ProcessOptions options;
    options.output_file = (dir_ / "output.txt").string();
    const ProcessResult p = run_process(argv, options);
    return {p.exit_status, read(options.output_file)};
  }

  // A sweep file over tests/data/tiny.yaml with the given body.
  std::string sweep_file(const std::string& body, const std::string& name = "sweep.yaml") {
    const fs::path file = dir_ / name;
    std::ofstream(file) << "scenario: " << test::source_path("tests/data/tiny.yaml") << "\n" << body;
    return file.string();
  }

  // 2 x 2 points of both variants (exact, arc)
  std::string small_sweep() {
    return sweep_file(R"(axes:
  variants[1].transition.parameter: [2, 5]
  defaults.velocity: [150, 200]
constraints: ["metrics.contour_error_programmed_max_mm <= 1.0"]
)");
  }

  fs::path dir_;
};

std::map<std::string, fs::file_time_type> summary_times(const fs::path& out) {
  std::map<std::string, fs::file_time_type> times;
  for (const auto& e : fs::directory_iterator(out / "points")) {
    times[e.path().filename().string()] = fs::last_write_time(e.path() / "summary.json");
  }
  return times;
}

TEST_F(Sweep, ResultsDoNotDependOnJobs) {
  const std::string file = small_sweep();
  const Result one = run({"sweep", file, "--out", (dir_ / "j1").string(), "--jobs", "1", "--no-plots"});
  ASSERT_EQ(one.exit_code, 0) << one.output;
  const Result two = run({"sweep", file, "--out", (dir_ / "j2").string(), "--jobs", "2", "--no-plots"});
  ASSERT_EQ(two.exit_code, 0) << two.output;
  const std::string csv = read(dir_ / "j1" / "sweep.csv");
  EXPECT_EQ(csv, read(dir_ / "j2" / "sweep.csv"));
  EXPECT_EQ(read(dir_ / "j1" / "sweep.json"), read(dir_ / "j2" / "sweep.json"));
  EXPECT_EQ(read(dir_ / "j1" / "best.csv"), read(dir_ / "j2" / "best.csv"));

  // a row per point and variant; the axes and metrics as columns, no clock readings among them
  std::istringstream lines(csv);
  std::string header;
  std::getline(lines, header);
  EXPECT_EQ(header.rfind("point,variant,method,variants[1].transition.parameter,defaults.velocity,status,", 0), 0U) << header;
  EXPECT_TRUE(has(header, ",metrics.cycle_time_s,")) << header;
  EXPECT_TRUE(has(header, ",metrics.contour_error_programmed_max_mm,")) << header;
  EXPECT_FALSE(has(header, "wall_time")) << header;
  int rows = 0;
  for (std::string line; std::getline(lines, line);) ++rows;
  EXPECT_EQ(rows, 8);
  EXPECT_TRUE(has(one.output, "4 ran, 0 resumed")) << one.output;
  EXPECT_TRUE(has(one.output, "best setting per method")) << one.output;
}

TEST_F(Sweep, ResumeSkipsFinishedPoints) {
  const std::string file = small_sweep();
  const std::string out = (dir_ / "out").string();
  const Result first = run({"sweep", file, "--out", out, "--jobs", "2", "--no-plots"});
  ASSERT_EQ(first.exit_code, 0) << first.output;
  const std::string csv = read(dir_ / "out" / "sweep.csv");
  const auto times = summary_times(dir_ / "out");
  ASSERT_EQ(times.size(), 4U);

  const Result again = run({"sweep", file, "--out", out, "--resume", "--no-plots"});
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_TRUE(has(again.output, "4 runs: 0 ran, 4 resumed")) << again.output;
  EXPECT_EQ(summary_times(dir_ / "out"), times);
  EXPECT_EQ(read(dir_ / "out" / "sweep.csv"), csv);

  // a point without its status has not finished: it runs again, the others do not
  const std::string redo = times.begin()->first;
  fs::remove(dir_ / "out" / "points" / redo / "status.json");
  const Result third = run({"sweep", file, "--out", out, "--resume", "--no-plots"});
  ASSERT_EQ(third.exit_code, 0) << third.output;
  EXPECT_TRUE(has(third.output, "4 runs: 1 ran, 3 resumed")) << third.output;
  const auto after = summary_times(dir_ / "out");
  for (const auto& [hash, time] : times) {
    if (hash != redo) {
      EXPECT_EQ(after.at(hash), time) << hash;
    }
  }
  EXPECT_EQ(read(dir_ / "out" / "sweep.csv"), csv);

  // without --resume every point runs
  const Result fresh = run({"sweep", file, "--out", out, "--no-plots"});
  EXPECT_TRUE(has(fresh.output, "4 runs: 4 ran, 0 resumed")) << fresh.output;
}

TEST_F(Sweep, ShardsCollectToTheLocalTable) {
  const std::string file = small_sweep();
  const Result local = run({"sweep", file, "--out", (dir_ / "local").string(), "--jobs", "2", "--no-plots"});
  ASSERT_EQ(local.exit_code, 0) << local.output;
  const std::string shards = (dir_ / "shards").string();
  for (const std::string shard : {"0/3", "2/3"}) {
    const Result r = run({"sweep", file, "--shard", shard, "--out", shards, "--jobs", "1"});
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  // shard 1 has not run: nothing is merged
  const Result early = run({"sweep", "--collect", shards, "--no-plots"});
  EXPECT_EQ(early.exit_code, 1) << early.output;
  EXPECT_TRUE(has(early.output, "1 of 4 points have no result yet (points 1)")) << early.output;
  EXPECT_FALSE(fs::exists(dir_ / "shards" / "sweep.csv"));

  const Result last = run({"sweep", file, "--shard", "1/3", "--out", shards});
  ASSERT_EQ(last.exit_code, 0) << last.output;
  EXPECT_TRUE(has(last.output, "shard 1/3: 1 runs: 1 ran")) << last.output;
  const Result merged = run({"sweep", "--collect", shards, "--no-plots"});
  ASSERT_EQ(merged.exit_code, 0) << merged.output;
  EXPECT_EQ(read(dir_ / "shards" / "sweep.csv"), read(dir_ / "local" / "sweep.csv"));
  EXPECT_EQ(read(dir_ / "shards" / "best.csv"), read(dir_ / "local" / "best.csv"));

  // a shard run again rewrites only its own points, to the same table
  const Result rerun = run({"sweep", file, "--shard", "1/3", "--out", shards});
  ASSERT_EQ(rerun.exit_code, 0) << rerun.output;
  ASSERT_EQ(run({"sweep", "--collect", shards, "--no-plots"}).exit_code, 0);
  EXPECT_EQ(read(dir_ / "shards" / "sweep.csv"), read(dir_ / "local" / "sweep.csv"));

  // a shard of a sweep file that changed since the plan was written is refused
  const std::string changed = sweep_file("axes:\n  defaults.velocity: [120]\n", "sweep.yaml");
  const Result stale = run({"sweep", changed, "--shard", "0/3", "--out", shards});
  EXPECT_EQ(stale.exit_code, 2) << stale.output;
  EXPECT_TRUE(has(stale.output, "no longer expands")) << stale.output;
}

// A field of a report list (the corner reports) is no default column, but a sweep may name it.
TEST_F(Sweep, AReportFieldCanBeNamed) {
  const std::string file = sweep_file(R"(axes:
  defaults.velocity: [200]
metrics: [metrics.cycle_time_s]
constraints: ["plan.corners[0].deviation_mm <= 0.001"]
pareto: {x: metrics.cycle_time_s, y: "plan.corners[0].deviation_mm"}
)");
  const Result r = run({"sweep", file, "--out", (dir_ / "out").string(), "--no-plots"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string csv = read(dir_ / "out" / "sweep.csv");
  EXPECT_EQ(csv.substr(0, csv.find('\n')),
            "point,variant,method,defaults.velocity,status,meets_constraints,on_pareto_front,metrics.cycle_time_s,"
            "plan.corners[0].deviation_mm");
  // the exact stop passes through the corner; the 5 mm arc blend does not
  const nlohmann::json sweep = nlohmann::json::parse(read(dir_ / "out" / "sweep.json"));
  EXPECT_EQ(sweep["rows"][0]["variant"], "exact");
  EXPECT_EQ(sweep["rows"][0]["meets_constraints"], true);
  EXPECT_EQ(sweep["rows"][1]["meets_constraints"], false);
  EXPECT_GT(sweep["rows"][1]["metrics"][1].get<double>(), 1.0);
}

// A point the robot cannot reach stops with an error in its own child: it is recorded with its
// status and message, the other points still give their rows, and the exit code is 1.
TEST_F(Sweep, APointThatFailsFailsAlone) {
  const std::string file = sweep_file("axes:\n  frame.origin: [[400, -50, 250], [5000, 0, 250]]\n");
  const Result r = run({"sweep", file, "--out", (dir_ / "out").string(), "--no-plots"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(has(r.output, "point 1 (frame.origin=[5000, 0, 250]): error:")) << r.output;
  const nlohmann::json sweep = nlohmann::json::parse(read(dir_ / "out" / "sweep.json"));
  ASSERT_EQ(sweep["rows"].size(), 4U);
  for (int i = 0; i < 2; ++i) EXPECT_EQ(sweep["rows"][i]["status"], "ok");
  for (int i = 2; i < 4; ++i) {
    EXPECT_EQ(sweep["rows"][i]["status"], "error");
    EXPECT_TRUE(has(sweep["rows"][i]["message"].get<std::string>(), "cannot be reached")) << sweep["rows"][i];
  }
}

TEST_F(Sweep, BadInputExitsTwoNamingTheSweepFile) {
  struct Case {
    std::string body;
    std::string expected;
  };
  const Case cases[] = {
      {"axes:\n  defaults.velocity: [200, -3]\n", "sweep.yaml:3:3: 'axes.defaults.velocity': point 1 of 2 (defaults.velocity=-3)"},
      {"axes:\n  program.moves[2].line: [[0, 0, 0]]\n", "sweep.yaml:3:3: 'axes.program.moves[2].line': point 0 of 1"},
      {"axes:\n  defaults.velocity: [200]\nconstraints: [\"nope_mm <= 1\"]\n",
       "sweep.yaml:4:15: 'constraints[0]': no metric 'nope_mm' in the runs' summaries (metrics: "},
  };
  for (const Case& c : cases) {
    const Result r = run({"sweep", sweep_file(c.body), "--out", (dir_ / "out").string(), "--no-plots"});
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_TRUE(has(r.output, c.expected)) << "expected '" << c.expected << "' in:\n" << r.output;
  }
  const Result flags = run({"sweep", small_sweep(), "--dry-run"});
  EXPECT_EQ(flags.exit_code, 2) << flags.output;
  EXPECT_TRUE(has(flags.output, "need --slurm")) << flags.output;
  const Result shard = run({"sweep", small_sweep(), "--shard", "3/3"});
  EXPECT_EQ(shard.exit_code, 2) << shard.output;
}

TEST_F(Sweep, SlurmDryRunWritesTheJobArray) {
  const std::string out = (dir_ / "out").string();
  const Result r = run({"sweep", small_sweep(), "--out", out, "--slurm", "--array-size", "2", "--partition", "debug",
                        "--time", "0:10:00", "--jobs", "2", "--dry-run"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string script = read(dir_ / "out" / "sweep.sbatch");
  EXPECT_TRUE(has(script, "#SBATCH --array=0-1\n")) << script;
  EXPECT_TRUE(has(script, "#SBATCH --partition=debug\n")) << script;
  EXPECT_TRUE(has(script, "#SBATCH --time=0:10:00\n")) << script;
  EXPECT_TRUE(has(script, "#SBATCH --cpus-per-task=2\n")) << script;
  EXPECT_TRUE(has(script, "#SBATCH --output=" + out + "/slurm/%A_%a.out\n")) << script;
  EXPECT_TRUE(has(script, " sweep '" + (dir_ / "sweep.yaml").string() + "' --shard \"${SLURM_ARRAY_TASK_ID}/2\" --out '" +
                              out + "'")) << script;
  EXPECT_TRUE(fs::exists(dir_ / "out" / "sweep.plan.json"));
  EXPECT_FALSE(fs::exists(dir_ / "out" / "slurm" / "job_id"));
  EXPECT_FALSE(fs::exists(dir_ / "out" / "points")) << "a dry run runs nothing";

  const Result bad = run({"sweep", small_sweep(), "--out", out, "--slurm", "--time", "1h; rm -rf /", "--dry-run"});
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
}

// The shipped example expands and every point passes the loader (without running it).
TEST_F(Sweep, ExampleSweepIsValid) {
  const Result r = run({"sweep", test::source_path("scenarios/sweeps/corners.yaml"), "--out", (dir_ / "out").string(),
                        "--slurm", "--dry-run"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(has(r.output, "20 points (20 runs)")) << r.output;
}

}  // namespace
}  // namespace blendbench
