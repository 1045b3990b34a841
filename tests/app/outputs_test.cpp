// Outputs a user can trust, on the real program: a run stopped by SIGINT or SIGTERM in the middle
// of its simulation (exit code, its one-line message, no temporary file left, the previous run
// intact, finished variants kept), a second run into a folder in use, output options naming the
// same file, outputs that are not regular files, and a variant out of reach failing alone.

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "support/property.hpp"

namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The program started with an argument vector, its stdout and stderr on one pipe.
class Child {
 public:
  explicit Child(const std::vector<std::string>& args) {
    int fds[2];
    if (::pipe(fds) != 0) return;
    pid_ = ::fork();
    if (pid_ == 0) {
      ::dup2(fds[1], STDOUT_FILENO);
      ::dup2(fds[1], STDERR_FILENO);
      ::close(fds[0]);
      ::close(fds[1]);
      std::vector<std::string> all = {BLENDBENCH_BINARY};
      all.insert(all.end(), args.begin(), args.end());
      std::vector<char*> argv;
      for (std::string& a : all) argv.push_back(a.data());
      argv.push_back(nullptr);
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
    ::close(fds[1]);
    fd_ = fds[0];
  }
  ~Child() {
    if (pid_ > 0 && status_ < 0) {
      ::kill(pid_, SIGKILL);
      (void)wait();
    }
    if (fd_ >= 0) ::close(fd_);
  }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  // Reads output until a line starts with `prefix` (true) or the output ends (false).
  bool wait_for_line(const std::string& prefix) {
    for (;;) {
      const auto newline = pending_.find('\n');
      if (newline != std::string::npos) {
        const std::string line = pending_.substr(0, newline);
        output_ += pending_.substr(0, newline + 1);
        pending_.erase(0, newline + 1);
        if (line.rfind(prefix, 0) == 0) return true;
        continue;
      }
      char buffer[4096];
      const ssize_t n = ::read(fd_, buffer, sizeof buffer);
      if (n <= 0) return false;
      pending_.append(buffer, static_cast<std::size_t>(n));
    }
  }
  void signal(int sig) const { ::kill(pid_, sig); }
  // Reads the rest of the output and returns the exit code (-1 when killed by a signal).
  int wait() {
    char buffer[4096];
    ssize_t n = 0;
    while (fd_ >= 0 && (n = ::read(fd_, buffer, sizeof buffer)) > 0) pending_.append(buffer, static_cast<std::size_t>(n));
    output_ += pending_;
    pending_.clear();
    int status = 0;
    ::waitpid(pid_, &status, 0);
    status_ = status;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  [[nodiscard]] const std::string& output() const { return output_; }
  [[nodiscard]] pid_t pid() const { return pid_; }

 private:
  pid_t pid_ = -1;
  int fd_ = -1;
  int status_ = -1;
  std::string pending_, output_;
};

int run(const std::vector<std::string>& args, std::string* output = nullptr) {
  Child child(args);
  const int code = child.wait();
  if (output != nullptr) *output = child.output();
  return code;
}

// Every file below `dir` with its content, hidden ones included.
std::map<std::string, std::string> contents(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    out[fs::relative(e.path(), dir).string()] = e.is_regular_file() ? slurp(e.path()) : std::string("<dir>");
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
    std::string text = slurp(blendbench::test::source_path("tests/data/tiny.yaml"));
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

  Child rerun({"run", scenario_, "--out", out_.string(), "--no-plots"});
  ASSERT_TRUE(rerun.wait_for_line("  exact: inverse kinematics")) << rerun.output();
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

TEST_F(Outputs, SigtermDuringTheSecondVariantKeepsTheFirst) {
  Child first({"run", scenario_, "--out", out_.string(), "--no-plots"});
  ASSERT_TRUE(first.wait_for_line("[2/2] arc")) << first.output();
  ASSERT_TRUE(first.wait_for_line("  arc: inverse kinematics")) << first.output();
  first.signal(SIGTERM);
  EXPECT_EQ(first.wait(), 143) << first.output();
  EXPECT_NE(first.output().find("blendbench: interrupted by SIGTERM: kept 1 finished variant(s) (exact) in " +
                                out_.string() + "\n"),
            std::string::npos)
      << first.output();
  // the finished variant is complete, the interrupted one gone, and the summary says so
  const nlohmann::json summary = nlohmann::json::parse(slurp(out_ / "summary.json"));
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
  Child first({"run", scenario_, "--out", out_.string(), "--no-plots"});
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
  EXPECT_EQ(slurp(csv), "earlier") << "nothing is written on a refusal";
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
  EXPECT_EQ(slurp(dir_ / "target.txt"), "keep");
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
  EXPECT_EQ(slurp(dir_ / "real" / "summary.json"), "{}");
}

// The exact stop reaches a corner beyond the arm's reach; the biclothoid cuts it 40 mm inside:
// the run exits 1, the failure names the move, and the other variant's results are written.
TEST_F(Outputs, AVariantOutOfReachFailsAloneWithExitOne) {
  std::ofstream(dir_ / "reach.yaml") << R"(name: reach
units: mm
frame: {origin: [0, 0, 300], rpy_deg: [0, 0, 0]}
defaults: {velocity: 200, acceleration: 2000, jerk: 20000}
simulation: {settle_tolerance: 0.2, settle_time_s: 0.3}
program:
  start: [600, -150, 0]
  moves:
    - line: [910, 0, 0]
    - line: [600, 150, 0]
variants:
  - {name: exact, transition: {method: none}}
  - {name: biclothoid_40, transition: {method: biclothoid, parameter: 40}}
)";
  std::string output;
  const fs::path out = dir_ / "runs" / "reach";
  EXPECT_EQ(run({"run", (dir_ / "reach.yaml").string(), "--out", out.string(), "--no-video", "--no-plots"}, &output), 1)
      << output;
  EXPECT_NE(output.find("  exact: failed - " + (dir_ / "reach.yaml").string() + ":9:7: 'program.moves[0]': the path leaves "
                        "the robot's reach"),
            std::string::npos)
      << output;
  EXPECT_NE(output.find("  biclothoid_40: cycle "), std::string::npos) << output;
  const nlohmann::json summary = nlohmann::json::parse(slurp(out / "summary.json"));
  EXPECT_EQ(summary["variants"][0]["status"], "failed");
  EXPECT_EQ(summary["variants"][1]["status"], "ok");
  EXPECT_TRUE(fs::is_regular_file(out / "biclothoid_40" / "trace.csv"));
}

}  // namespace
