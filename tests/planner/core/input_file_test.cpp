// The one way input files are opened (core/input_file.hpp): regular files only, never blocking,
// bounded, and inside a managed folder never through a symbolic link. (read_input_file by path is
// also exercised by tests/io/program_io_test.cpp: folders, FIFOs, /dev/zero, the size limit.)

#include "blendbench/core/input_file.hpp"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>

#include "support/input_error.hpp"
#include "support/scratch.hpp"

namespace blendbench {
namespace {

namespace fs = std::filesystem;

struct Folder {
  int fd = -1;
  explicit Folder(const fs::path& path) : fd(::open(path.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC)) {}
  ~Folder() { ::close(fd); }
};

TEST(InputFile, ByPathFollowsTheUsersLinksToARegularFile) {
  const test::ScratchDir dir("input_file");
  const std::string file = dir.write("a.yaml", "name: a\n");
  fs::create_symlink(file, dir / "link.yaml");
  EXPECT_EQ(read_input_file((dir / "link.yaml").string(), "scenario file"), "name: a\n");
  test::expect_input_error([&] { (void)read_input_file("", "scenario file"); }, {.message = "no scenario file named"});
}

TEST(InputFile, InAFolderItReadsRegularEntriesAndNeverThroughALink) {
  const test::ScratchDir dir("input_file_at");
  (void)dir.write("status.json", "{}");
  const test::ScratchDir outside("input_file_outside");
  const std::string secret = outside.write("secret", "do not read");
  fs::create_symlink(secret, dir / "summary.json");
  fs::create_directory(dir / "folder");
  ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0600), 0);
  const Folder folder(dir.path());
  ASSERT_GE(folder.fd, 0);
  EXPECT_EQ(read_input_file_at(folder.fd, "status.json", "DIR/status.json", "status file"), std::optional<std::string>("{}"));
  EXPECT_EQ(read_input_file_at(folder.fd, "absent.json", "DIR/absent.json", "status file"), std::nullopt);
  test::expect_input_error([&] { (void)read_input_file_at(folder.fd, "summary.json", "DIR/summary.json", "run summary"); },
                           {.file = "DIR/summary.json", .message = "the run summary is a symbolic link: it is not read through"});
  test::expect_input_error([&] { (void)read_input_file_at(folder.fd, "folder", "DIR/folder", "run summary"); },
                           {.message = "the run summary is a folder, not a regular file"});
  // a FIFO is refused at once: nothing waits for a writer
  const auto start = std::chrono::steady_clock::now();
  test::expect_input_error([&] { (void)read_input_file_at(folder.fd, "fifo", "DIR/fifo", "run summary"); },
                           {.message = "the run summary is a FIFO (named pipe), not a regular file"});
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(5));
  for (const char* name : {"../status.json", "a/b", "..", ""}) {
    test::expect_input_error([&] { (void)read_input_file_at(folder.fd, name, "DIR/x", "run summary"); },
                             {.message = "not a file name inside its folder"}, name);
  }
  test::expect_input_error([&] { (void)read_input_file_at(folder.fd, "status.json", "DIR/status.json", "status file", 1); },
                           {.message = "the limit is"});
}

}  // namespace
}  // namespace blendbench
