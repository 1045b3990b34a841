#include "blendbench/report/output.hpp"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>

#include <csignal>

#include <cmath>
#include <fstream>
#include <sstream>

namespace blendbench {
namespace {

namespace fs = std::filesystem;

std::string slurp(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class OutputTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("blendbench_output_test_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
  }
  void TearDown() override {
    ::chmod(dir_.c_str(), 0755);
    fs::remove_all(dir_);
  }
  fs::path dir_;
};

TEST_F(OutputTest, WritesAndReplacesAtomically) {
  const fs::path file = dir_ / "sub" / "summary.json";
  write_file_atomic(file, "first");
  EXPECT_EQ(slurp(file), "first");
  write_file_atomic(file, "second, longer");
  EXPECT_EQ(slurp(file), "second, longer");
  // no temporary file is left behind
  int entries = 0;
  for (const auto& e : fs::directory_iterator(file.parent_path())) entries += e.is_regular_file() ? 1 : 0;
  EXPECT_EQ(entries, 1);
}

TEST_F(OutputTest, FailureKeepsTheOldFileAndSaysWhere) {
  if (::geteuid() == 0) GTEST_SKIP() << "root ignores directory permissions";
  const fs::path file = dir_ / "summary.json";
  write_file_atomic(file, "old");
  ::chmod(dir_.c_str(), 0555);
  try {
    write_file_atomic(file, "new");
    FAIL() << "expected a failure in a read-only directory";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(dir_.string()), std::string::npos) << e.what();
  }
  ::chmod(dir_.c_str(), 0755);
  EXPECT_EQ(slurp(file), "old");
}

TEST_F(OutputTest, AWriteCutShortKeepsTheOldFileAndLeavesNoTemporary) {
  // a file-size limit stops the write part-way (as a full disk would); it binds root too
  const fs::path file = dir_ / "trace.csv";
  write_file_atomic(file, "old");
  rlimit saved{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &saved), 0);
  const auto old_handler = std::signal(SIGXFSZ, SIG_IGN);
  rlimit limited = saved;
  limited.rlim_cur = 4096;
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &limited), 0);
  std::string error;
  try {
    write_file_atomic(file, std::string(1 << 20, 'x'));
  } catch (const std::runtime_error& e) {
    error = e.what();
  }
  ::setrlimit(RLIMIT_FSIZE, &saved);
  std::signal(SIGXFSZ, old_handler);
  EXPECT_NE(error.find(file.string()), std::string::npos) << "expected a failure naming the file, got '" << error << "'";
  EXPECT_EQ(slurp(file), "old");
  int entries = 0;
  for (const auto& e : fs::directory_iterator(dir_)) entries += e.is_regular_file() ? 1 : 0;
  EXPECT_EQ(entries, 1) << "the temporary file must be removed";
}

TEST_F(OutputTest, FailsWhenTheTargetIsADirectory) {
  const fs::path file = dir_ / "taken";
  fs::create_directories(file / "inside");
  EXPECT_THROW(write_file_atomic(file, "x"), std::runtime_error);
  EXPECT_TRUE(fs::is_directory(file));
  int entries = 0;
  for (const auto& e : fs::directory_iterator(dir_)) entries += e.is_regular_file() ? 1 : 0;
  EXPECT_EQ(entries, 0) << "the temporary file must be removed";
}

TEST(FormatValue, TenDigitsShortestFormAndNonFinite) {
  EXPECT_EQ(format_value(0.125, 10), "0.125");
  EXPECT_EQ(format_value(1.0 / 3.0, 4), "0.3333");
  EXPECT_EQ(format_value(std::nan(""), 10), "nan");
}

TEST(FormatFixed, DecimalsAfterThePointAndNonFinite) {
  EXPECT_EQ(format_fixed(3.14159, 2), "3.14");
  EXPECT_EQ(format_fixed(2.5, 0), "2");  // round half to even, as printf does
  EXPECT_EQ(format_fixed(1234.5, 1), "1234.5");
  EXPECT_EQ(format_fixed(std::nan(""), 2), "nan");
  EXPECT_EQ(format_fixed(-std::numeric_limits<double>::infinity(), 2), "-inf");
}

}  // namespace
}  // namespace blendbench
