#include "blendbench/report/run_folder.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "blendbench/core/input_error.hpp"
#include "support/files.hpp"

namespace blendbench {
namespace {

namespace fs = std::filesystem;

using test::read_file;

// Every entry below `dir` (relative, sorted), hidden ones included.
std::vector<std::string> entries(const fs::path& dir) {
  std::vector<std::string> out;
  for (const auto& e : fs::recursive_directory_iterator(dir)) out.push_back(fs::relative(e.path(), dir).string());
  std::sort(out.begin(), out.end());
  return out;
}

class RunFolderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("blendbench_run_folder_test_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    out_ = dir_ / "run";
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A finished earlier run in out_: summary.json and a variant folder.
  void previous_run() const {
    fs::create_directories(out_ / "old_variant");
    std::ofstream(out_ / "summary.json") << "old";
    std::ofstream(out_ / "old_variant" / "trace.csv") << "old trace";
  }

  fs::path dir_, out_;
};

TEST_F(RunFolderTest, StagesBesideTheTargetAndPublishesOnCommit) {
  {
    RunFolder folder(out_);
    EXPECT_EQ(folder.target(), fs::absolute(out_));
    EXPECT_EQ(folder.staging().parent_path(), dir_);
    EXPECT_TRUE(fs::is_directory(folder.staging()));
    EXPECT_TRUE(fs::is_empty(folder.staging()));
    EXPECT_FALSE(folder.had_previous_run());
    EXPECT_TRUE(fs::exists(dir_ / ".run.lock"));
    EXPECT_FALSE(fs::exists(out_)) << "nothing is published before the commit";
    std::ofstream(folder.staging() / "summary.json") << "new";
    folder.commit();
    EXPECT_FALSE(fs::exists(folder.staging()));
  }
  EXPECT_EQ(read_file(out_ / "summary.json"), "new");
  // the lock is gone with the folder object, and nothing else is left beside the run
  EXPECT_EQ(entries(dir_), (std::vector<std::string>{"run", "run/summary.json"}));
}

TEST_F(RunFolderTest, ACommitReplacesThePreviousRunAsAWhole) {
  previous_run();
  {
    RunFolder folder(out_);
    EXPECT_TRUE(folder.had_previous_run());
    fs::create_directories(folder.staging() / "new_variant");
    std::ofstream(folder.staging() / "summary.json") << "new";
    folder.commit();
  }
  // no folder of the earlier run survives beside the new summary
  EXPECT_EQ(entries(dir_), (std::vector<std::string>{"run", "run/new_variant", "run/summary.json"}));
  EXPECT_EQ(read_file(out_ / "summary.json"), "new");
}

TEST_F(RunFolderTest, WithoutACommitThePreviousRunStaysIntact) {
  previous_run();
  {
    RunFolder folder(out_);
    std::ofstream(folder.staging() / "summary.json") << "half of a new run";
  }
  EXPECT_EQ(entries(dir_), (std::vector<std::string>{"run", "run/old_variant", "run/old_variant/trace.csv",
                                                     "run/summary.json"}));
  EXPECT_EQ(read_file(out_ / "summary.json"), "old");
}

// A first run refused or failed before its commit leaves no folder it created above --out
// (results/runs/ of a run in an empty working folder), but keeps one that holds something.
TEST_F(RunFolderTest, WithoutACommitTheFoldersItCreatedAreRemoved) {
  { RunFolder folder(dir_ / "results" / "runs" / "x"); }
  EXPECT_EQ(entries(dir_), std::vector<std::string>{});
  {
    RunFolder folder(dir_ / "results" / "runs" / "x");
    std::ofstream(dir_ / "results" / "note.txt") << "someone else's";
  }
  EXPECT_EQ(entries(dir_), (std::vector<std::string>{"results", "results/note.txt"}));
}

TEST_F(RunFolderTest, ASecondRunIntoTheSameFolderIsRefusedAtOnce) {
  RunFolder first(out_);
  try {
    RunFolder second(dir_ / "." / "run");  // another spelling of the same folder
    FAIL() << "expected the second run to be refused";
  } catch (const InputError& e) {
    EXPECT_EQ(e.field(), "--out");
    const std::string what = e.what();
    EXPECT_NE(what.find("is in use by another run (pid " + std::to_string(::getpid()) + ")"), std::string::npos) << what;
  }
  // the refused run took nothing away from the first
  EXPECT_TRUE(fs::is_directory(first.staging()));
  EXPECT_TRUE(fs::exists(dir_ / ".run.lock"));
}

TEST_F(RunFolderTest, TheLockIsFreeAgainAfterARun) {
  { RunFolder first(out_); }
  RunFolder second(out_);
  EXPECT_TRUE(fs::is_directory(second.staging()));
}

TEST_F(RunFolderTest, StagingFoldersOfKilledRunsAreRemoved) {
  fs::create_directories(dir_ / ".run.staging-999999" / "exact");
  fs::create_directories(dir_ / ".run.staging-old-999998");
  fs::create_directories(dir_ / ".other.staging-999999");  // another run's: not ours to remove
  RunFolder folder(out_);
  EXPECT_FALSE(fs::exists(dir_ / ".run.staging-999999"));
  EXPECT_FALSE(fs::exists(dir_ / ".run.staging-old-999998"));
  EXPECT_TRUE(fs::exists(dir_ / ".other.staging-999999"));
}

TEST_F(RunFolderTest, ATargetThatIsNotARunFolderIsRefusedAndKept) {
  const auto refused = [&](const fs::path& out, const std::string& expected) {
    try {
      RunFolder folder(out);
      ADD_FAILURE() << out << " was accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), "--out");
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
    // neither the lock nor a staging folder is left behind
    for (const auto& e : fs::directory_iterator(dir_)) {
      EXPECT_NE(e.path().filename().string().rfind(".", 0), 0u) << e.path();
    }
  };
  std::ofstream(dir_ / "file") << "data";
  refused(dir_ / "file", "exists and is a file");
  fs::create_directories(dir_ / "real_run");
  std::ofstream(dir_ / "real_run" / "summary.json") << "{}";
  fs::create_directory_symlink(dir_ / "real_run", dir_ / "link");
  refused(dir_ / "link", "exists and is a symbolic link");
  ASSERT_EQ(::mkfifo((dir_ / "fifo").c_str(), 0644), 0);
  refused(dir_ / "fifo", "exists and is a FIFO");
  fs::create_directories(dir_ / "documents");
  std::ofstream(dir_ / "documents" / "thesis.tex") << "precious";
  refused(dir_ / "documents", "neither empty nor a run");
  EXPECT_EQ(read_file(dir_ / "documents" / "thesis.tex"), "precious");
  EXPECT_EQ(read_file(dir_ / "file"), "data");
  refused("/", "does not name a folder");
}

TEST_F(RunFolderTest, AnEmptyFolderIsAcceptedAsTheTarget) {
  fs::create_directories(out_);
  RunFolder folder(out_);
  EXPECT_FALSE(folder.had_previous_run()) << "an empty folder holds no run";
  std::ofstream(folder.staging() / "summary.json") << "new";
  folder.commit();
  EXPECT_EQ(read_file(out_ / "summary.json"), "new");
}

TEST_F(RunFolderTest, CommitToASiblingKeepsThePreviousRun) {
  previous_run();
  const fs::path kept = dir_ / "run.interrupted";
  {
    RunFolder folder(out_);
    std::ofstream(folder.staging() / "summary.json") << "partial";
    folder.commit_to(kept);
  }
  EXPECT_EQ(read_file(out_ / "summary.json"), "old");
  EXPECT_EQ(read_file(kept / "summary.json"), "partial");
  // a second interrupted run replaces the first one's partial results as a whole
  {
    RunFolder folder(out_);
    fs::create_directories(folder.staging() / "v");
    std::ofstream(folder.staging() / "summary.json") << "partial 2";
    folder.commit_to(kept);
  }
  EXPECT_EQ(entries(kept), (std::vector<std::string>{"summary.json", "v"}));
}

TEST(CleanupRegistry, RemovesWhatIsRegisteredAndForgetsWhatWasReleased) {
  const fs::path dir = fs::temp_directory_path() / ("blendbench_cleanup_test_" + std::to_string(::getpid()));
  fs::create_directories(dir / "folder" / "inside");
  std::ofstream(dir / "kept") << "x";
  std::ofstream(dir / "temporary") << "x";
  register_cleanup(dir / "folder");
  const std::uint64_t released = register_cleanup(dir / "kept");
  register_cleanup(dir / "temporary");
  unregister_cleanup(released);
  remove_registered_paths();
  EXPECT_FALSE(fs::exists(dir / "folder"));
  EXPECT_FALSE(fs::exists(dir / "temporary"));
  EXPECT_TRUE(fs::exists(dir / "kept"));
  // emptied: a second call removes nothing more
  std::ofstream(dir / "temporary") << "again";
  remove_registered_paths();
  EXPECT_TRUE(fs::exists(dir / "temporary"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace blendbench
