#include "blendbench/io/data_root.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

namespace blendbench {
namespace {

namespace fs = std::filesystem;

// A fresh folder per test, removed afterwards; every layout below is built inside it.
class DataRoot : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("blendbench_data_root_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path folder(const std::string& relative) const {
    fs::create_directories(dir_ / relative);
    return dir_ / relative;
  }
  void write(const std::string& relative, const std::string& text) const {
    fs::create_directories((dir_ / relative).parent_path());
    std::ofstream(dir_ / relative) << text;
  }

  fs::path dir_;
};

// The message of the DataRootError that `f` throws; empty (and a test failure) when it throws none.
template <class F>
std::string error_of(F f) {
  try {
    f();
  } catch (const DataRootError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no DataRootError";
  return {};
}

TEST_F(DataRoot, EnvironmentVariableComesFirst) {
  const fs::path chosen = folder("chosen");
  // an installed layout beside the program is there too, and loses
  folder("prefix/share/blendbench");
  EXPECT_EQ(find_data_root(chosen.c_str(), dir_ / "prefix/bin/blendbench"), chosen);
}

TEST_F(DataRoot, EnvironmentVariableNamingNoFolderIsAnErrorNotSkipped) {
  folder("prefix/share/blendbench");
  const std::string missing = (dir_ / "missing").string();
  const std::string message = error_of([&] { find_data_root(missing.c_str(), dir_ / "prefix/bin/blendbench"); });
  EXPECT_NE(message.find("BLENDBENCH_DATA_DIR=" + missing), std::string::npos) << message;
  EXPECT_NE(message.find("not a folder"), std::string::npos) << message;
}

TEST_F(DataRoot, EmptyEnvironmentVariableCountsAsUnset) {
  const fs::path share = folder("prefix/share/blendbench");
  EXPECT_EQ(find_data_root("", dir_ / "prefix/bin/blendbench"), share);
}

TEST_F(DataRoot, InstalledProgramFindsShareBesideBin) {
  const fs::path share = folder("prefix/share/blendbench");
  // the build-tree file one folder up is there too, and loses to the installed layout
  write("prefix/blendbench-data-root", folder("elsewhere").string() + "\n");
  EXPECT_EQ(find_data_root(nullptr, dir_ / "prefix/bin/blendbench"), share);
}

TEST_F(DataRoot, BuildTreeFileBesideTheProgramOrOneFolderUp) {
  const fs::path source = folder("source");
  write("build/blendbench-data-root", source.string() + "  \r\n");
  EXPECT_EQ(find_data_root(nullptr, dir_ / "build/blendbench"), source);
  EXPECT_EQ(find_data_root(nullptr, dir_ / "build/tests/scenario_test"), source);
  // two folders up is not looked at
  const std::string message = error_of([&] { find_data_root(nullptr, dir_ / "build/tests/deeper/x_test"); });
  EXPECT_NE(message.find("cannot find"), std::string::npos) << message;
}

TEST_F(DataRoot, NothingFoundNamesEveryPlaceTried) {
  write("build/blendbench-data-root", (dir_ / "gone").string() + "\n");
  const std::string message = error_of([&] { find_data_root(nullptr, dir_ / "build/bin/blendbench"); });
  EXPECT_NE(message.find("BLENDBENCH_DATA_DIR (not set)"), std::string::npos) << message;
  EXPECT_NE(message.find((dir_ / "build/share/blendbench").string() + " (no such folder)"), std::string::npos) << message;
  EXPECT_NE(message.find((dir_ / "build/bin/blendbench-data-root").string() + " (no such file)"), std::string::npos)
      << message;
  EXPECT_NE(message.find((dir_ / "build/blendbench-data-root").string() + " (names '" + (dir_ / "gone").string() +
                         "', not a folder)"),
            std::string::npos)
      << message;
}

TEST_F(DataRoot, UnknownProgramLeavesOnlyTheEnvironmentVariable) {
  const std::string message = error_of([] { find_data_root(nullptr, fs::path()); });
  EXPECT_NE(message.find("running program's folder (unknown)"), std::string::npos) << message;
  EXPECT_NE(message.find("set BLENDBENCH_DATA_DIR"), std::string::npos) << message;
}

// This test program lives in the build tree, so without the variable it finds the source tree
// through build/blendbench-data-root, and the shipped model is there.
TEST(DataRootOfThisProcess, BuildTreeProgramFindsTheSourceTree) {
  std::optional<std::string> saved;
  if (const char* env = std::getenv(kDataDirVariable)) saved = env;
  ::unsetenv(kDataDirVariable);
  const fs::path root = data_root();
  EXPECT_TRUE(fs::is_regular_file(root / "tests/io/data_root_test.cpp")) << root;  // the source tree itself
  EXPECT_TRUE(fs::is_regular_file(data_file("models/ur5e_like.urdf")));
  if (saved) ::setenv(kDataDirVariable, saved->c_str(), 1);
}

}  // namespace
}  // namespace blendbench
