#include "blendbench/report/output.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "blendbench/core/input_error.hpp"
#include "blendbench/report/run_folder.hpp"

namespace blendbench {
namespace {

// What an existing non-regular file is, for messages.
std::string kind_of(mode_t mode) {
  if (S_ISLNK(mode)) return "a symbolic link";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISCHR(mode) || S_ISBLK(mode)) return "a device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

// Writes all of `content` to fd, retrying short writes and EINTR; false with errno set on error.
bool write_all(int fd, std::string_view content) {
  while (!content.empty()) {
    const ssize_t n = ::write(fd, content.data(), content.size());
    if (n < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    content.remove_prefix(static_cast<std::size_t>(n));
  }
  return true;
}

}  // namespace

std::filesystem::path temporary_path_for(const std::filesystem::path& path) {
  std::filesystem::path tmp = path;
  tmp += ".tmp." + std::to_string(::getpid());
  return tmp;
}

void write_file_atomic(const std::filesystem::path& path, std::string_view content) {
  namespace fs = std::filesystem;
  if (path.has_parent_path()) {
    std::error_code ec;
    fs::create_directories(path.parent_path(), ec);
    if (ec) throw std::runtime_error("cannot create directory " + path.parent_path().string() + ": " + ec.message());
  }
  // an existing target must be a regular file: a link, FIFO or device is never replaced
  struct stat existing {};
  if (::lstat(path.c_str(), &existing) == 0 && !S_ISREG(existing.st_mode)) {
    throw std::runtime_error("refusing to replace " + path.string() + ": it is " + kind_of(existing.st_mode) +
                             ", not a regular file");
  }

  // the temporary file: created exclusively (a stale one of a killed process with our pid is
  // removed first), never through a symbolic link
  const fs::path tmp = temporary_path_for(path);
  int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
  if (fd < 0 && errno == EEXIST && ::unlink(tmp.c_str()) == 0) {
    fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
  }
  if (fd < 0) throw std::runtime_error("cannot write " + tmp.string() + ": " + std::strerror(errno));
  const std::uint64_t cleanup = register_cleanup(tmp);
  const auto fail = [&](const std::string& what, int error) {
    ::unlink(tmp.c_str());
    unregister_cleanup(cleanup);
    throw std::runtime_error(what + ": " + std::strerror(error));
  };

  const bool written = write_all(fd, content) && ::fsync(fd) == 0;
  const int saved_errno = errno;
  const bool closed = ::close(fd) == 0;
  if (!written || !closed) fail("cannot write " + path.string(), written ? errno : saved_errno);
  if (::rename(tmp.c_str(), path.c_str()) != 0) fail("cannot rename " + tmp.string() + " to " + path.string(), errno);
  unregister_cleanup(cleanup);
}

void check_output_files(const std::vector<std::pair<std::string, std::filesystem::path>>& outputs) {
  namespace fs = std::filesystem;
  struct Seen {
    std::string option;
    fs::path canonical;  // the folder resolved, the name as given
    dev_t dev = 0;
    ino_t ino = 0;
    bool exists = false;
  };
  std::vector<Seen> seen;
  for (const auto& [option, path] : outputs) {
    if (path.empty()) continue;
    Seen out{option, {}, 0, 0, false};
    struct stat st {};
    if (::lstat(path.c_str(), &st) == 0) {
      if (!S_ISREG(st.st_mode)) {
        throw InputError("", 0, 0, option,
                         path.string() + " exists and is " + kind_of(st.st_mode) + ", not a regular file: refusing to replace it");
      }
      out.exists = true;
      out.dev = st.st_dev;
      out.ino = st.st_ino;
    }
    // the folder as the system resolves it (symbolic links, "..", relative spelling)
    const fs::path absolute = fs::absolute(path).lexically_normal();
    std::error_code ec;
    const fs::path folder = fs::weakly_canonical(absolute.parent_path(), ec);
    out.canonical = (ec ? absolute.parent_path() : folder) / absolute.filename();
    for (const Seen& other : seen) {
      if (other.canonical == out.canonical || (out.exists && other.exists && other.dev == out.dev && other.ino == out.ino)) {
        throw InputError("", 0, 0, option,
                         "names the same file as " + other.option + " (" + path.string() + "): give each output its own file");
      }
    }
    seen.push_back(std::move(out));
  }
}

std::string format_fixed(double value, int decimals) {
  if (!std::isfinite(value)) return format_value(value, 10);
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  return buffer;
}

}  // namespace blendbench
