#include "blendbench/report/output.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <utility>

#include "blendbench/core/input_error.hpp"
#include "blendbench/core/input_file.hpp"
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

// A file descriptor closed on every way out; moved, never copied.
struct Descriptor {
  int fd = -1;
  explicit Descriptor(int f) : fd(f) {}
  Descriptor(Descriptor&& other) noexcept : fd(std::exchange(other.fd, -1)) {}
  Descriptor(const Descriptor&) = delete;
  Descriptor& operator=(const Descriptor&) = delete;
  Descriptor& operator=(Descriptor&&) = delete;
  ~Descriptor() {
    if (fd >= 0) ::close(fd);
  }
};

// A name inside a folder: one component, never "." or "..".
void check_entry_name(const std::string& name, const std::filesystem::path& folder) {
  if (name.empty() || name == "." || name == ".." || name.find('/') != std::string::npos || name.find('\0') != std::string::npos) {
    throw std::runtime_error("'" + name + "' is not a name of a file inside " + folder.string());
  }
}

// Removes the temporaries of `name` in the folder (`name`.tmp.<pid>) whose process no longer
// runs: a SIGKILL leaves its temporary behind, and only the next write into the same place can
// clean it. A process that still runs (another writer of the same file) keeps its own.
void remove_stale_temporaries(int dir_fd, const std::string& name) {
  const int copy = ::dup(dir_fd);
  if (copy < 0) return;
  DIR* dir = ::fdopendir(copy);
  if (dir == nullptr) {
    ::close(copy);
    return;
  }
  ::rewinddir(dir);
  const std::string prefix = name + ".tmp.";
  const pid_t self = ::getpid();
  while (const dirent* entry = ::readdir(dir)) {
    const std::string_view entry_name(entry->d_name);
    if (entry_name.size() <= prefix.size() || entry_name.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string_view digits = entry_name.substr(prefix.size());
    if (digits.size() > 9 || digits.find_first_not_of("0123456789") != std::string_view::npos) continue;
    const auto pid = static_cast<pid_t>(std::stol(std::string(digits)));
    if (pid <= 0 || pid == self) continue;
    if (::kill(pid, 0) != 0 && errno == ESRCH) ::unlinkat(dir_fd, entry->d_name, 0);
  }
  ::closedir(dir);
}

// A file written to its temporary beside it and not yet renamed over its name.
struct Staged {
  int dir_fd = -1;  // not owned
  std::string name, tmp;
  std::filesystem::path shown, tmp_shown;
  std::uint64_t cleanup = 0;
};

// Writes `content` to a temporary beside `name` in the open folder: created exclusively and never
// through a symbolic link, written and synced. `shown` names the file in messages.
Staged stage_at(int dir_fd, const std::string& name, const std::filesystem::path& shown, std::string_view content) {
  // an existing target must be a regular file: a link, FIFO or device is never replaced
  struct stat existing {};
  if (::fstatat(dir_fd, name.c_str(), &existing, AT_SYMLINK_NOFOLLOW) == 0 && !S_ISREG(existing.st_mode)) {
    throw std::runtime_error("refusing to replace " + shown.string() + ": it is " + kind_of(existing.st_mode) +
                             ", not a regular file");
  }
  remove_stale_temporaries(dir_fd, name);
  // the temporary file: created exclusively (a stale one of a killed process with our pid is
  // removed first), never through a symbolic link
  Staged staged{dir_fd, name, temporary_path_for(name).string(), shown, temporary_path_for(shown), 0};
  constexpr int kCreate = O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC;
  int fd = ::openat(dir_fd, staged.tmp.c_str(), kCreate, 0666);
  if (fd < 0 && errno == EEXIST && ::unlinkat(dir_fd, staged.tmp.c_str(), 0) == 0) fd = ::openat(dir_fd, staged.tmp.c_str(), kCreate, 0666);
  if (fd < 0) throw std::runtime_error("cannot write " + staged.tmp_shown.string() + ": " + std::strerror(errno));
  staged.cleanup = register_cleanup(staged.tmp_shown);
  const bool written = write_all(fd, content) && ::fsync(fd) == 0;
  const int saved_errno = errno;
  const bool closed = ::close(fd) == 0;
  if (!written || !closed) {
    const int error = written ? errno : saved_errno;
    ::unlinkat(dir_fd, staged.tmp.c_str(), 0);
    unregister_cleanup(staged.cleanup);
    throw std::runtime_error("cannot write " + shown.string() + ": " + std::strerror(error));
  }
  return staged;
}

// Removes a staged temporary that will not be published.
void discard(const Staged& staged) noexcept {
  ::unlinkat(staged.dir_fd, staged.tmp.c_str(), 0);
  unregister_cleanup(staged.cleanup);
}

// Renames a staged temporary over its name.
void publish(const Staged& staged) {
  if (::renameat(staged.dir_fd, staged.tmp.c_str(), staged.dir_fd, staged.name.c_str()) != 0) {
    const int error = errno;
    discard(staged);
    throw std::runtime_error("cannot rename " + staged.tmp_shown.string() + " to " + staged.shown.string() + ": " +
                             std::strerror(error));
  }
  unregister_cleanup(staged.cleanup);
}

// Writes `content` to `name` in the open folder atomically: staged, then renamed.
void write_atomic_at(int dir_fd, const std::string& name, const std::filesystem::path& shown, std::string_view content) {
  publish(stage_at(dir_fd, name, shown, content));
}

// The folder of an output file, created when missing and opened (following the links of the path
// the user named).
Descriptor open_parent(const std::filesystem::path& path) {
  namespace fs = std::filesystem;
  const fs::path parent = path.has_parent_path() ? path.parent_path() : fs::path(".");
  std::error_code ec;
  fs::create_directories(parent, ec);
  if (ec) throw std::runtime_error("cannot create directory " + parent.string() + ": " + ec.message());
  Descriptor dir{::open(parent.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC)};
  if (dir.fd < 0) throw std::runtime_error("cannot open directory " + parent.string() + ": " + std::strerror(errno));
  return dir;
}

}  // namespace

std::filesystem::path temporary_path_for(const std::filesystem::path& path) {
  std::filesystem::path tmp = path;
  tmp += ".tmp." + std::to_string(::getpid());
  return tmp;
}

void write_file_atomic(const std::filesystem::path& path, std::string_view content) {
  const Descriptor dir = open_parent(path);
  write_atomic_at(dir.fd, path.filename().string(), path, content);
}

void write_files_atomic(const std::vector<std::pair<std::filesystem::path, std::string>>& files) {
  std::vector<Descriptor> dirs;
  dirs.reserve(files.size());
  std::vector<Staged> staged;
  try {
    for (const auto& [path, content] : files) {
      dirs.push_back(open_parent(path));
      staged.push_back(stage_at(dirs.back().fd, path.filename().string(), path, content));
    }
  } catch (...) {
    for (const Staged& s : staged) discard(s);
    throw;
  }
  // every file is whole on disk: now the renames, one after the other
  for (std::size_t i = 0; i < staged.size(); ++i) {
    try {
      publish(staged[i]);
    } catch (...) {
      for (std::size_t k = i + 1; k < staged.size(); ++k) discard(staged[k]);
      throw;
    }
  }
}

OutputFilesLock::OutputFilesLock(const std::vector<std::pair<std::string, std::filesystem::path>>& outputs) {
  for (const auto& [option, path] : outputs) {
    if (path.empty()) continue;
    // appended apart: "." + name draws GCC 12's -Wrestrict false positive
    std::string lock_name = ".";
    lock_name += path.filename().string();
    lock_name += ".lock";
    const std::filesystem::path lock = path.parent_path() / lock_name;
    std::error_code ec;
    std::filesystem::create_directories(path.has_parent_path() ? path.parent_path() : ".", ec);
    const int fd = ::open(lock.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd < 0) throw std::runtime_error("cannot open the lock file " + lock.string() + ": " + std::strerror(errno));
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int error = errno;
      ::close(fd);
      if (error == EWOULDBLOCK) {
        throw InputError("", 0, 0, option, path.string() + " is being written by another command (lock " + lock.string() +
                                               "): wait for it or choose another file");
      }
      throw std::runtime_error("cannot lock " + lock.string() + ": " + std::strerror(error));
    }
    held_.push_back({fd, lock, register_cleanup(lock)});
  }
}

OutputFilesLock::~OutputFilesLock() {
  for (const Held& h : held_) {
    // removed while held: a command that opened it before retries on a new file
    ::unlink(h.path.c_str());
    ::close(h.fd);
    unregister_cleanup(h.cleanup);
  }
}

OutputDir::OutputDir(const std::filesystem::path& path, bool create) : path_(path) {
  if (create) {
    std::error_code ec;
    std::filesystem::create_directories(path, ec);
    if (ec) throw std::runtime_error("cannot create the folder " + path.string() + ": " + ec.message());
  }
  const int fd = ::open(path.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) throw std::runtime_error("cannot open the folder " + path.string() + ": " + std::strerror(errno));
  fd_ = std::shared_ptr<const int>(new int(fd), [](const int* p) {
    ::close(*p);
    delete p;
  });
}

std::optional<OutputDir> OutputDir::find(const std::string& name) const {
  check_entry_name(name, path_);
  const int fd = ::openat(*fd_, name.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) {
    if (errno == ENOENT) return std::nullopt;
    const int error = errno;
    struct stat st {};
    if (::fstatat(*fd_, name.c_str(), &st, AT_SYMLINK_NOFOLLOW) == 0 && !S_ISDIR(st.st_mode)) {
      throw std::runtime_error((path_ / name).string() + " exists and is " + kind_of(st.st_mode) +
                               ", not a folder: refusing to write or read through it");
    }
    throw std::runtime_error("cannot open the folder " + (path_ / name).string() + ": " + std::strerror(error));
  }
  return OutputDir(std::shared_ptr<const int>(new int(fd),
                                              [](const int* p) {
                                                ::close(*p);
                                                delete p;
                                              }),
                   path_ / name);
}

OutputDir OutputDir::sub(const std::string& name) const {
  check_entry_name(name, path_);
  if (::mkdirat(*fd_, name.c_str(), 0777) != 0 && errno != EEXIST) {
    throw std::runtime_error("cannot create the folder " + (path_ / name).string() + ": " + std::strerror(errno));
  }
  std::optional<OutputDir> found = find(name);
  if (!found) throw std::runtime_error("the folder " + (path_ / name).string() + " vanished as it was created");
  return *found;
}

void OutputDir::write(const std::string& name, std::string_view content) const {
  check_entry_name(name, path_);
  write_atomic_at(*fd_, name, path_ / name, content);
}

std::optional<std::string> OutputDir::read(const std::string& name, const std::string& what) const {
  return read_input_file_at(*fd_, name, (path_ / name).string(), what);
}

int OutputDir::create_fresh(const std::string& name) const {
  check_entry_name(name, path_);
  const std::string shown = (path_ / name).string();
  if (::unlinkat(*fd_, name.c_str(), 0) != 0 && errno != ENOENT) {
    throw std::runtime_error("cannot replace " + shown + ": " + std::strerror(errno));
  }
  const int fd = ::openat(*fd_, name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
  if (fd < 0) throw std::runtime_error("cannot create " + shown + ": " + std::strerror(errno));
  return fd;
}

int OutputDir::try_lock(const std::string& name, bool shared) const {
  check_entry_name(name, path_);
  const int fd = ::openat(*fd_, name.c_str(), O_RDWR | O_CREAT | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (fd < 0) throw std::runtime_error("cannot open the lock file " + (path_ / name).string() + ": " + std::strerror(errno));
  if (::flock(fd, (shared ? LOCK_SH : LOCK_EX) | LOCK_NB) != 0) {
    const int error = errno;
    ::close(fd);
    if (error == EWOULDBLOCK) return -1;
    throw std::runtime_error("cannot lock " + (path_ / name).string() + ": " + std::strerror(error));
  }
  if (!shared) {
    // the pid is only for the message of a second process; the lock holds without it
    const std::string pid = std::to_string(::getpid());
    if (::ftruncate(fd, 0) != 0 || ::pwrite(fd, pid.data(), pid.size(), 0) < 0) {
    }
  }
  return fd;
}

std::string OutputDir::lock_holder(const std::string& name) const {
  try {
    std::string pid = read_input_file_at(*fd_, name, (path_ / name).string(), "lock file", 32).value_or("");
    return pid.find_first_not_of("0123456789") == std::string::npos ? pid : std::string();
  } catch (const InputError&) {
    return {};
  }
}

void OutputDir::remove(const std::string& name) const {
  check_entry_name(name, path_);
  if (::unlinkat(*fd_, name.c_str(), 0) != 0 && errno != ENOENT) {
    throw std::runtime_error("cannot remove " + (path_ / name).string() + ": " + std::strerror(errno));
  }
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
    // a folder that exists must be one the file can be written in (a loop of links, a file)
    for (fs::path up = absolute.parent_path(); !up.empty(); up = up.parent_path()) {
      std::error_code status_ec;
      const fs::file_status status = fs::status(up, status_ec);
      if (status.type() == fs::file_type::not_found) {
        if (up == up.parent_path()) break;
        continue;
      }
      if (status_ec) throw InputError("", 0, 0, option, path.string() + ": cannot use the folder " + up.string() + ": " + status_ec.message());
      if (status.type() != fs::file_type::directory) {
        throw InputError("", 0, 0, option, path.string() + ": " + up.string() + " is not a folder");
      }
      break;
    }
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
