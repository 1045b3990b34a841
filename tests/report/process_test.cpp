// Child processes from an argument vector: exit status, signals, output to a file, and names
// that a shell would have read as syntax passed through as plain arguments.

#include "blendbench/report/process.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

namespace blendbench {
namespace {

namespace fs = std::filesystem;

std::string read(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class Process : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("blendbench_process_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(Process, OutputGoesToTheFileStdoutAndStderr) {
  ProcessOptions options;
  options.output_file = (dir_ / "log.txt").string();
  const ProcessResult r = run_process(
      {"/usr/bin/python3", "-c", "import sys; print('out $(x); `y`'); sys.stdout.flush(); print('err', file=sys.stderr)"}, options);
  EXPECT_TRUE(r.ok) << r.message;
  EXPECT_EQ(r.exit_status, 0);
  EXPECT_EQ(r.signal, 0);
  EXPECT_EQ(read(options.output_file), "out $(x); `y`\nerr\n");
  // a second run replaces the file
  const ProcessResult again = run_process({"/usr/bin/python3", "-c", "print('two')"}, options);
  EXPECT_TRUE(again.ok);
  EXPECT_EQ(read(options.output_file), "two\n");
}

TEST_F(Process, ExitStatusAndSignalAreReported) {
  const ProcessResult two = run_process({"/usr/bin/python3", "-c", "raise SystemExit(2)"});
  EXPECT_FALSE(two.ok);
  EXPECT_EQ(two.exit_status, 2);
  EXPECT_EQ(two.signal, 0);
  EXPECT_NE(two.message.find("exited with status 2"), std::string::npos) << two.message;

  const ProcessResult killed = run_process({"/usr/bin/python3", "-c", "import os, signal; os.kill(os.getpid(), signal.SIGSEGV)"});
  EXPECT_FALSE(killed.ok);
  EXPECT_EQ(killed.exit_status, -1);
  EXPECT_EQ(killed.signal, 11);
  EXPECT_NE(killed.message.find("killed by signal 11"), std::string::npos) << killed.message;

  const ProcessResult missing = run_process({(dir_ / "no such program").string()});
  EXPECT_FALSE(missing.ok);
  EXPECT_EQ(missing.exit_status, -1);
  EXPECT_NE(missing.message.find("cannot start"), std::string::npos) << missing.message;
}

}  // namespace
}  // namespace blendbench
