#include "blendbench/report/output.hpp"

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>

#include <cmath>
#include <fstream>

#include "blendbench/core/input_error.hpp"
#include "support/files.hpp"

namespace blendbench {
namespace {

namespace fs = std::filesystem;

using test::read_file;

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
  EXPECT_EQ(read_file(file), "first");
  write_file_atomic(file, "second, longer");
  EXPECT_EQ(read_file(file), "second, longer");
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
  EXPECT_EQ(read_file(file), "old");
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
  EXPECT_EQ(read_file(file), "old");
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

// A symbolic link, a FIFO or a device given as an output is never replaced by a regular file,
// and a symbolic link planted at the temporary name is not followed.
TEST_F(OutputTest, NonRegularTargetsAreRefusedAndKept) {
  fs::create_directories(dir_);
  const fs::path elsewhere = dir_ / "elsewhere.txt";
  std::ofstream(elsewhere) << "keep";
  fs::create_symlink(elsewhere, dir_ / "link.csv");
  ASSERT_EQ(::mkfifo((dir_ / "fifo.csv").c_str(), 0644), 0);
  for (const char* name : {"link.csv", "fifo.csv"}) {
    SCOPED_TRACE(name);
    try {
      write_file_atomic(dir_ / name, "x");
      ADD_FAILURE() << "expected a refusal";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("refusing to replace"), std::string::npos) << e.what();
    }
  }
  EXPECT_TRUE(fs::is_symlink(dir_ / "link.csv"));
  EXPECT_EQ(fs::symlink_status(dir_ / "fifo.csv").type(), fs::file_type::fifo);
  EXPECT_EQ(read_file(elsewhere), "keep");
  EXPECT_THROW(write_file_atomic("/dev/null", "x"), std::runtime_error);

  // a link at the temporary name (a stale one, or planted) is replaced, not written through
  const fs::path target = dir_ / "out.csv";
  fs::create_symlink(elsewhere, temporary_path_for(target));
  write_file_atomic(target, "new");
  EXPECT_EQ(read_file(target), "new");
  EXPECT_EQ(read_file(elsewhere), "keep");
  EXPECT_FALSE(fs::exists(fs::symlink_status(temporary_path_for(target))));
}

// Two outputs naming one file, however spelled, are refused before any work; distinct files
// and options not given pass.
TEST_F(OutputTest, OutputsNamingTheSameFileAreRefused) {
  fs::create_directories(dir_ / "sub");
  fs::create_directory_symlink(dir_ / "sub", dir_ / "alias");
  std::ofstream(dir_ / "sub" / "a.csv") << "x";
  ASSERT_EQ(::link((dir_ / "sub" / "a.csv").c_str(), (dir_ / "hard.csv").c_str()), 0);
  const fs::path a = dir_ / "sub" / "a.csv";
  const fs::path spellings[] = {dir_ / "sub" / "." / "a.csv", dir_ / "sub" / ".." / "sub" / "a.csv",
                                dir_ / "alias" / "a.csv", dir_ / "hard.csv"};
  for (const fs::path& other : spellings) {
    SCOPED_TRACE(other.string());
    try {
      check_output_files({{"--csv", a}, {"--summary", other}});
      ADD_FAILURE() << "expected a refusal";
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "--summary");
      EXPECT_NE(std::string(e.what()).find("names the same file as --csv"), std::string::npos) << e.what();
    }
  }
  // the same for files that do not exist yet
  EXPECT_THROW(check_output_files({{"--csv", dir_ / "new.csv"}, {"--summary", dir_ / "alias" / ".." / "new.csv"}}),
               InputError);
  EXPECT_NO_THROW(check_output_files({{"--csv", a}, {"--summary", dir_ / "sub" / "b.json"}, {"--report", ""}}));
}

TEST_F(OutputTest, NonRegularOutputsAreRefusedBeforeAnyWork) {
  fs::create_directories(dir_ / "folder");
  ASSERT_EQ(::mkfifo((dir_ / "fifo").c_str(), 0644), 0);
  fs::create_symlink(dir_ / "nowhere", dir_ / "dangling");
  const std::pair<fs::path, std::string> cases[] = {{dir_ / "folder", "a directory"},
                                                    {dir_ / "fifo", "a FIFO"},
                                                    {dir_ / "dangling", "a symbolic link"},
                                                    {"/dev/null", "a device"}};
  for (const auto& [path, kind] : cases) {
    SCOPED_TRACE(path.string());
    try {
      check_output_files({{"--csv", path}});
      ADD_FAILURE() << "expected a refusal";
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "--csv");
      EXPECT_NE(std::string(e.what()).find("exists and is " + kind + ", not a regular file"), std::string::npos)
          << e.what();
    }
  }
}

// A SIGKILL leaves its temporary file behind; the next write of the same file removes the
// temporaries of processes that no longer run, and keeps those of a process that still does.
TEST_F(OutputTest, TemporariesOfKilledProcessesAreRemovedByTheNextWrite) {
  fs::create_directories(dir_);
  const pid_t dead = ::fork();
  if (dead == 0) ::_exit(0);
  ASSERT_GT(dead, 0);
  ASSERT_EQ(::waitpid(dead, nullptr, 0), dead);
  const fs::path target = dir_ / "path.csv";
  const fs::path stale = dir_ / ("path.csv.tmp." + std::to_string(dead));
  const fs::path living = dir_ / ("path.csv.tmp." + std::to_string(::getppid()));
  const fs::path other = dir_ / ("summary.json.tmp." + std::to_string(dead));
  for (const fs::path& p : {stale, living, other}) std::ofstream(p) << "half";
  write_file_atomic(target, "whole");
  EXPECT_EQ(read_file(target), "whole");
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(living));
  EXPECT_TRUE(fs::exists(other));  // another file's, until that file is written
}

// A managed folder reaches everything below it from its descriptor and never through a link.
TEST_F(OutputTest, AManagedFolderNeverWritesOrReadsThroughALink) {
  const OutputDir root(dir_ / "sweep", true);
  const fs::path outside = dir_ / "outside";
  fs::create_directories(outside);
  std::ofstream(outside / "victim.txt") << "keep";
  // a link in place of a sub-folder is refused, not followed
  fs::create_directory_symlink(outside, dir_ / "sweep" / "points");
  try {
    (void)root.sub("points");
    ADD_FAILURE() << "expected a refusal";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("points exists and is a symbolic link, not a folder"), std::string::npos) << e.what();
  }
  // a link (or a hard link) at a log's name is replaced by a new file
  const OutputDir point = root.sub("p");
  fs::create_symlink(outside / "victim.txt", dir_ / "sweep" / "p" / "log.txt");
  ASSERT_EQ(::link((outside / "victim.txt").c_str(), (dir_ / "sweep" / "p" / "hard.txt").c_str()), 0);
  for (const char* name : {"log.txt", "hard.txt"}) {
    const int fd = point.create_fresh(name);
    ASSERT_GE(fd, 0);
    ASSERT_EQ(::write(fd, "log", 3), 3);
    ::close(fd);
    EXPECT_EQ(read_file(dir_ / "sweep" / "p" / name), "log");
  }
  EXPECT_EQ(read_file(outside / "victim.txt"), "keep");
  // a write replaces a link at its name (rename, not write-through); reads refuse links
  point.write("status.json", "{}");
  EXPECT_EQ(point.read("status.json", "status"), std::optional<std::string>("{}"));
  EXPECT_EQ(point.read("absent.json", "status"), std::nullopt);
  fs::create_symlink(outside / "victim.txt", dir_ / "sweep" / "p" / "summary.json");
  EXPECT_THROW((void)point.read("summary.json", "summary"), InputError);
  EXPECT_THROW(point.write("../escape.txt", "x"), std::runtime_error);
  EXPECT_FALSE(fs::exists(dir_ / "sweep" / "escape.txt"));
  // the lock: exclusive excludes everything, shared admits shared
  const int held = root.try_lock(".lock", false);
  ASSERT_GE(held, 0);
  EXPECT_EQ(root.try_lock(".lock", true), -1);
  EXPECT_EQ(root.lock_holder(".lock"), std::to_string(::getpid()));
  ::close(held);
  const int shared = root.try_lock(".lock", true);
  const int shared2 = root.try_lock(".lock", true);
  EXPECT_GE(shared, 0);
  EXPECT_GE(shared2, 0);
  EXPECT_EQ(root.try_lock(".lock", false), -1);
  ::close(shared);
  ::close(shared2);
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
