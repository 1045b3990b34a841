// The blendbench program as a user meets it: exit codes, messages that name file, line and
// field, and the files a run writes (including a video that ffprobe accepts).

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "../support/property.hpp"

namespace {

namespace fs = std::filesystem;

struct Result {
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

// Runs a shell command, capturing its stdout and stderr.
Result run_shell(const std::string& command) {
  Result r;
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return r;
  std::array<char, 4096> buffer{};
  while (std::fgets(buffer.data(), buffer.size(), pipe) != nullptr) r.output += buffer.data();
  const int status = ::pclose(pipe);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

Result run(const std::string& args) { return run_shell(std::string(BLENDBENCH_BINARY) + " " + args); }

Result run_probe(const fs::path& video) {
  return run_shell("ffprobe -v error -select_streams v:0 -show_entries stream=codec_name,avg_frame_rate -of compact '" +
                   video.string() + "'");
}

class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("blendbench_cli_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Writes a scenario file from the tiny one with one text replacement.
  std::string scenario_with(const std::string& from, const std::string& to) {
    std::ifstream in(blendbench::test::source_path("tests/data/tiny.yaml"));
    std::stringstream s;
    s << in.rdbuf();
    std::string text = s.str();
    const auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    const fs::path file = dir_ / "bad.yaml";
    std::ofstream(file) << text;
    return file.string();
  }

  fs::path dir_;
};

TEST_F(Cli, BadScenarioExitsTwoNamingFileLineAndField) {
  struct Case {
    std::string from, to, expected;
  };
  const Case cases[] = {
      {"units: mm", "units: mm\nspeed: 3", "bad.yaml:4:1: 'speed': unknown key"},
      {"velocity: 200", "velocity: fast", "bad.yaml:5:22: 'defaults.velocity': expected a number"},
      {"jerk: 20000", "jerky: 20000", "bad.yaml:5:47: 'defaults.jerky': unknown key"},
      {"defaults: {velocity: 200, acceleration: 2000, jerk: 20000}", "defaults: {velocity: 200, acceleration: 2000}",
       "bad.yaml:5:11: 'defaults.jerk': missing required field"},
      {"line: [60, 60, 0]", "line: [60, 900, 0]", "bad.yaml:12:7: 'program.moves[1]'"},
  };
  for (const Case& c : cases) {
    const std::string file = scenario_with(c.from, c.to);
    const Result r = run("run " + file + " --no-video --no-plots --out " + (dir_ / "out").string());
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(c.expected), std::string::npos) << "expected '" << c.expected << "' in:\n" << r.output;
  }
}

TEST_F(Cli, MissingFilesAndFlagsAreBadInput) {
  EXPECT_EQ(run("run /nonexistent/scenario.yaml --no-video").exit_code, 2);
  EXPECT_EQ(run("frobnicate").exit_code, 2);
  const std::string tiny = blendbench::test::source_path("tests/data/tiny.yaml");
  Result r = run("path " + tiny + " --variant nope --csv " + (dir_ / "p.csv").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("variants: exact, arc"), std::string::npos) << r.output;
  r = run("path " + tiny + " --method spline --param 1 --csv " + (dir_ / "p.csv").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("'--method'"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "p.csv")) << "nothing is written on bad input";
}

TEST_F(Cli, BadGcodeNamesLineAndWord) {
  const fs::path file = dir_ / "part.ngc";
  std::ofstream(file) << "G21 G90\nG1 X10 F1000\nG41 D1\nG1 Y10\n";
  const Result r = run("plan " + file.string() + " --csv " + (dir_ / "t.csv").string() + " --summary " +
                       (dir_ / "s.json").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("part.ngc:3:1: 'G41'"), std::string::npos) << r.output;
}

TEST_F(Cli, RunWritesSummaryTracesPlotsAndAPlayableVideo) {
  const fs::path out = dir_ / "run";
  const Result r = run("run " + blendbench::test::source_path("tests/data/tiny.yaml") + " --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(out / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(in);
  ASSERT_EQ(summary["variants"].size(), 2u);
  for (const auto& v : summary["variants"]) {
    const fs::path vdir = out / v["name"].get<std::string>();
    for (const char* file : {"trace.csv", "path.csv", "program.csv", "corners.json", "path.png", "speed.png",
                             "tracking_error.png", "joints.png", "video.mp4"}) {
      EXPECT_GT(fs::exists(vdir / file) ? fs::file_size(vdir / file) : 0u, 100u) << vdir / file;
    }
    const Result probe = run_probe(vdir / "video.mp4");
    EXPECT_EQ(probe.exit_code, 0) << probe.output;
    EXPECT_NE(probe.output.find("codec_name=h264"), std::string::npos) << probe.output;
    EXPECT_NE(probe.output.find("avg_frame_rate=24/1"), std::string::npos) << probe.output;
  }
  for (const char* file : {"compare_speed.png", "compare_path.png", "compare_metrics.png"}) {
    EXPECT_TRUE(fs::exists(out / file)) << file;
  }
}

}  // namespace
