// Reading input files by the rules of input_file.hpp.

#include "blendbench/core/input_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>

#include "blendbench/core/format.hpp"
#include "blendbench/core/input_error.hpp"

namespace blendbench {
namespace {

// A file descriptor closed on every way out.
struct Descriptor {
  int fd = -1;
  ~Descriptor() {
    if (fd >= 0) ::close(fd);
  }
};

// What kind of file a stat mode names, for a refusal.
std::string kind_of(mode_t mode) {
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISLNK(mode)) return "a symbolic link";
  return "not a regular file";
}

std::string mib(std::uintmax_t bytes) { return format_value(static_cast<double>(bytes) / (1 << 20), 4) + " MiB"; }

// Checks what a stat saw: a regular file within the limit.
template <class Fail>
void check_kind_and_size(const struct stat& st, const std::string& what, std::uintmax_t max_bytes, const Fail& fail) {
  if (!S_ISREG(st.st_mode)) fail("the " + what + " is " + kind_of(st.st_mode) + ", not a regular file");
  if (static_cast<std::uintmax_t>(st.st_size) > max_bytes) {
    fail("the " + what + " is " + mib(static_cast<std::uintmax_t>(st.st_size)) + "; the limit is " + mib(max_bytes));
  }
}

// Reads the open descriptor whole after checking it is the file `seen` described.
template <class Fail>
std::string read_opened(int fd, const struct stat& seen, const std::string& what, std::uintmax_t max_bytes, const Fail& fail) {
  struct stat opened {};
  if (::fstat(fd, &opened) != 0) fail("cannot examine the " + what + ": " + std::strerror(errno));
  if (opened.st_dev != seen.st_dev || opened.st_ino != seen.st_ino) fail("the " + what + " changed while it was opened");
  check_kind_and_size(opened, what, max_bytes, fail);
  // at most max_bytes + 1: a file that grew past the limit since the stat is refused as well
  std::string text;
  text.reserve(static_cast<std::size_t>(std::min<std::uintmax_t>(static_cast<std::uintmax_t>(opened.st_size), max_bytes)));
  std::array<char, 1 << 16> buffer;
  while (true) {
    const ssize_t n = ::read(fd, buffer.data(), buffer.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) fail("cannot read the " + what + ": " + std::strerror(errno));
    if (n == 0) break;
    text.append(buffer.data(), static_cast<std::size_t>(n));
    if (text.size() > max_bytes) fail("the " + what + " is larger than the limit of " + mib(max_bytes));
  }
  return text;
}

constexpr int kReadFlags = O_RDONLY | O_CLOEXEC | O_NONBLOCK | O_NOCTTY;

}  // namespace

std::string read_input_file(const std::string& path, const std::string& what, std::uintmax_t max_bytes) {
  const auto fail = [&](const std::string& message) { throw InputError(path, 0, 0, "", message); };
  if (path.empty()) fail("no " + what + " named (an empty file name)");
  // the kind and size first, from the path: a FIFO or a device is never opened
  struct stat seen {};
  if (::stat(path.c_str(), &seen) != 0) fail("cannot open the " + what + ": " + std::strerror(errno));
  check_kind_and_size(seen, what, max_bytes, fail);
  Descriptor in{::open(path.c_str(), kReadFlags)};
  if (in.fd < 0) fail("cannot open the " + what + ": " + std::strerror(errno));
  return read_opened(in.fd, seen, what, max_bytes, fail);
}

std::optional<std::string> read_input_file_at(int dir_fd, const std::string& name, const std::string& shown,
                                              const std::string& what, std::uintmax_t max_bytes) {
  const auto fail = [&](const std::string& message) { throw InputError(shown, 0, 0, "", message); };
  if (name.empty() || name.find('/') != std::string::npos || name == "." || name == "..") {
    fail("not a file name inside its folder: '" + name + "'");
  }
  struct stat seen {};
  if (::fstatat(dir_fd, name.c_str(), &seen, AT_SYMLINK_NOFOLLOW) != 0) {
    if (errno == ENOENT) return std::nullopt;
    fail("cannot open the " + what + ": " + std::strerror(errno));
  }
  if (S_ISLNK(seen.st_mode)) fail("the " + what + " is a symbolic link: it is not read through (it may lead out of its folder)");
  check_kind_and_size(seen, what, max_bytes, fail);
  Descriptor in{::openat(dir_fd, name.c_str(), kReadFlags | O_NOFOLLOW)};
  if (in.fd < 0) fail("cannot open the " + what + ": " + std::strerror(errno));
  return read_opened(in.fd, seen, what, max_bytes, fail);
}

}  // namespace blendbench
