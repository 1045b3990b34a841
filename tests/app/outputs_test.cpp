// Outputs a user can trust, on the real program: a run stopped by SIGINT or SIGTERM in the middle
// of its simulation (exit code, its one-line message, no temporary file left, the previous run
// intact, finished variants kept), a second run into a folder in use, output options naming the
// same file, outputs that are not regular files, and a variant out of reach failing alone.

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "support/files.hpp"
#include "support/program.hpp"
#include "support/property.hpp"

namespace {

namespace fs = std::filesystem;

using blendbench::test::Child;
using blendbench::test::read_file;

// Runs the program to its end; returns its exit code and, into `output`, what it printed.
int run(const std::vector<std::string>& args, std::string* output = nullptr) {
  Child child(blendbench::test::blendbench_binary(), args);
  const int code = child.wait();
  if (output != nullptr) *output = child.output();
  return code;
}

// Every file below `dir` with its content, hidden ones included.
std::map<std::string, std::string> contents(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    out[fs::relative(e.path(), dir).string()] = e.is_regular_file() ? read_file(e.path()) : std::string("<dir>");
  }
  return out;
}

// The temporary files a writer makes: write_file_atomic's and the video's.
std::vector<std::string> temporaries_below(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name.find(".tmp.") != std::string::npos || name.find(".partial-") != std::string::npos) out.push_back(e.path());
  }
  return out;
}

std::vector<std::string> names_in(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

class Outputs : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("blendbench_outputs_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "runs");
    // the tiny scenario held for 15 s after its moves, with a small video: each variant spends
    // a few seconds in its simulation loop (rendering 380 frames), long enough to be signalled there
    // (the tests signal once the variant is planned: what follows is its IK and simulation)
    std::string text = read_file(blendbench::test::source_path("tests/data/tiny.yaml"));
    text.replace(text.find("settle_time_s: 0.3"), 18, "settle_time_s: 15");
    text.replace(text.find("width: 320, height: 240"), 23, "width: 96, height: 64");
    std::ofstream(dir_ / "long.yaml") << text;
    scenario_ = (dir_ / "long.yaml").string();
    out_ = dir_ / "runs" / "long";
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_, out_;
  std::string scenario_;
};

TEST_F(Outputs, SigintDuringAReRunKeepsThePreviousRunIntact) {
  std::string output;
  ASSERT_EQ(run({"run", scenario_, "--out", out_.string(), "--no-video", "--no-plots"}, &output), 0) << output;
  const auto before = contents(out_);

  Child rerun(blendbench::test::blendbench_binary(), {"run", scenario_, "--out", out_.string(), "--no-plots"});
  ASSERT_TRUE(rerun.wait_for_line("  exact: planned")) << rerun.output();
  rerun.signal(SIGINT);
  EXPECT_EQ(rerun.wait(), 130) << rerun.output();
  EXPECT_NE(rerun.output().find("blendbench: interrupted by SIGINT: nothing kept; " + out_.string() +
                                " still holds the previous run\n"),
            std::string::npos)
      << rerun.output();
  EXPECT_EQ(contents(out_), before) << "the previous run must be intact";
  EXPECT_EQ(names_in(dir_ / "runs"), std::vector<std::string>{"long"}) << "no lock, staging or partial folder left";
  EXPECT_EQ(temporaries_below(dir_), std::vector<std::string>{});
}

// SIGKILL cannot be handled: the killed re-run leaves its staging folder, but the previous run is
// intact, and the next run into the folder removes the leftover and replaces the run as a whole.
TEST_F(Outputs, SigkillDuringAReRunLeavesThePreviousRunAndTheNextRunCleansUp) {
  std::string output;
  ASSERT_EQ(run({"run", scenario_, "--out", out_.string(), "--no-video", "--no-plots"}, &output), 0) << output;
  const auto before = contents(out_);
  {
    Child rerun(blendbench::test::blendbench_binary(), {"run", scenario_, "--out", out_.string(), "--no-plots"});
    ASSERT_TRUE(rerun.wait_for_line("  exact: planned")) << rerun.output();
    rerun.signal(SIGKILL);
    EXPECT_EQ(rerun.wait(), -1);
  }
  EXPECT_EQ(contents(out_), before) << "the previous run must be intact";
  ASSERT_EQ(run({"run", scenario_, "--out", out_.string(), "--no-video", "--no-plots", "--variant", "arc"}, &output), 0)
      << output;
  EXPECT_EQ(names_in(dir_ / "runs"), std::vector<std::string>{"long"}) << "the killed run's staging folder is removed";
  EXPECT_EQ(names_in(out_), (std::vector<std::string>{"arc", "summary.json"})) << "no folder of the earlier run survives";
}

TEST_F(Outputs, SigtermDuringTheSecondVariantKeepsTheFirst) {
  Child first(blendbench::test::blendbench_binary(), {"run", scenario_, "--out", out_.string(), "--no-plots"});
  ASSERT_TRUE(first.wait_for_line("[2/2] arc")) << first.output();
  ASSERT_TRUE(first.wait_for_line("  arc: planned")) << first.output();
  first.signal(SIGTERM);
  EXPECT_EQ(first.wait(), 143) << first.output();
  EXPECT_NE(first.output().find("blendbench: interrupted by SIGTERM: kept 1 finished variant(s) (exact) in " +
                                out_.string() + "\n"),
            std::string::npos)
      << first.output();
  // the finished variant is complete, the interrupted one gone, and the summary says so
  const nlohmann::json summary = nlohmann::json::parse(read_file(out_ / "summary.json"));
  ASSERT_EQ(summary["variants"].size(), 2u);
  EXPECT_EQ(summary["variants"][0]["status"], "ok");
  EXPECT_EQ(summary["variants"][1]["status"], "interrupted");
  for (const char* file : {"trace.csv", "path.csv", "corners.json", "video.mp4"}) {
    EXPECT_TRUE(fs::is_regular_file(out_ / "exact" / file)) << file;
  }
  EXPECT_EQ(names_in(out_), (std::vector<std::string>{"exact", "summary.json"}));
  EXPECT_EQ(names_in(dir_ / "runs"), std::vector<std::string>{"long"});
  EXPECT_EQ(temporaries_below(dir_), std::vector<std::string>{});
}

TEST_F(Outputs, ASecondRunIntoAFolderInUseIsRefusedAtOnce) {
  Child first(blendbench::test::blendbench_binary(), {"run", scenario_, "--out", out_.string(), "--no-plots"});
  ASSERT_TRUE(first.wait_for_line("[1/2] exact")) << first.output();
  std::string output;
  EXPECT_EQ(run({"run", scenario_, "--out", (dir_ / "runs" / "." / "long").string(), "--no-video", "--no-plots"}, &output),
            2)
      << output;
  EXPECT_NE(output.find("'--out': " + (dir_ / "runs" / "." / "long").string() + " is in use by another run (pid " +
                        std::to_string(first.pid()) + ")"),
            std::string::npos)
      << output;
  first.signal(SIGTERM);
  EXPECT_EQ(first.wait(), 143) << first.output();
}

TEST_F(Outputs, TwoOutputOptionsNamingOneFileAreRefused) {
  const std::string tiny = blendbench::test::source_path("tests/data/tiny.yaml");
  fs::create_directories(dir_ / "sub");
  fs::create_directory_symlink(dir_ / "sub", dir_ / "alias");
  std::ofstream(dir_ / "sub" / "plan.csv") << "earlier";
  const std::string csv = (dir_ / "sub" / "plan.csv").string();
  for (const fs::path& summary : {dir_ / "sub" / "plan.csv", dir_ / "sub" / ".." / "sub" / "plan.csv", dir_ / "alias" / "plan.csv"}) {
    SCOPED_TRACE(summary.string());
    std::string output;
    EXPECT_EQ(run({"plan", tiny, "--csv", csv, "--summary", summary.string()}, &output), 2) << output;
    EXPECT_NE(output.find("'--summary': names the same file as --csv"), std::string::npos) << output;
  }
  std::string output;
  EXPECT_EQ(run({"path", tiny, "--csv", csv, "--report", (dir_ / "alias" / "plan.csv").string()}, &output), 2) << output;
  EXPECT_EQ(read_file(csv), "earlier") << "nothing is written on a refusal";
}

TEST_F(Outputs, OutputsThatAreNotRegularFilesAreRefusedAndKept) {
  const std::string tiny = blendbench::test::source_path("tests/data/tiny.yaml");
  ASSERT_EQ(::mkfifo((dir_ / "fifo").c_str(), 0644), 0);
  std::ofstream(dir_ / "target.txt") << "keep";
  fs::create_symlink(dir_ / "target.txt", dir_ / "link.csv");
  fs::create_directories(dir_ / "folder.csv");
  for (const char* name : {"fifo", "link.csv", "folder.csv"}) {
    SCOPED_TRACE(name);
    std::string output;
    EXPECT_EQ(run({"plan", tiny, "--csv", (dir_ / name).string(), "--summary", (dir_ / "s.json").string()}, &output), 2)
        << output;
    EXPECT_NE(output.find("'--csv': " + (dir_ / name).string() + " exists and is a"), std::string::npos) << output;
  }
  EXPECT_EQ(fs::symlink_status(dir_ / "fifo").type(), fs::file_type::fifo);
  EXPECT_TRUE(fs::is_symlink(dir_ / "link.csv"));
  EXPECT_EQ(read_file(dir_ / "target.txt"), "keep");
  EXPECT_FALSE(fs::exists(dir_ / "s.json"));

  // an --out that is a link to a run folder is not replaced by the run either
  fs::create_directories(dir_ / "real");
  std::ofstream(dir_ / "real" / "summary.json") << "{}";
  fs::create_directory_symlink(dir_ / "real", dir_ / "runs" / "linked");
  std::string output;
  EXPECT_EQ(run({"run", scenario_, "--out", (dir_ / "runs" / "linked").string(), "--no-video", "--no-plots"}, &output), 2)
      << output;
  EXPECT_NE(output.find("exists and is a symbolic link, not a run folder"), std::string::npos) << output;
  EXPECT_TRUE(fs::is_symlink(dir_ / "runs" / "linked"));
  EXPECT_EQ(read_file(dir_ / "real" / "summary.json"), "{}");
}

// tests/data/reach.yaml: the exact stop reaches a corner beyond the arm's reach, the biclothoid
// cuts it 40 mm inside. The run exits 1, the failure names the move, and the other variant's
// results are written.
TEST_F(Outputs, AVariantOutOfReachFailsAloneWithExitOne) {
  const std::string scenario = blendbench::test::source_path("tests/data/reach.yaml");
  std::string output;
  const fs::path out = dir_ / "runs" / "reach";
  EXPECT_EQ(run({"run", scenario, "--out", out.string(), "--no-video", "--no-plots"}, &output), 1) << output;
  EXPECT_NE(output.find("  exact: failed - " + scenario + ":12:7: 'program.moves[0]': the path leaves the robot's reach"),
            std::string::npos)
      << output;
  EXPECT_NE(output.find("  biclothoid_40: cycle "), std::string::npos) << output;
  const nlohmann::json summary = nlohmann::json::parse(read_file(out / "summary.json"));
  EXPECT_EQ(summary["variants"][0]["status"], "failed");
  EXPECT_EQ(summary["variants"][1]["status"], "ok");
  EXPECT_TRUE(fs::is_regular_file(out / "biclothoid_40" / "trace.csv"));
}

}  // namespace
