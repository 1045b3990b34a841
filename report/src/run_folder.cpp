#include "blendbench/report/run_folder.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
#include <map>
#include <mutex>
#include <stdexcept>
#include <system_error>
#include <thread>

#include "blendbench/core/input_error.hpp"
#include "blendbench/core/interrupt.hpp"
#include "blendbench/report/process.hpp"

namespace blendbench {
namespace fs = std::filesystem;
namespace {

constexpr const char* kField = "--out";

[[noreturn]] void refuse(const fs::path& out, const std::string& why) {
  throw InputError("", 0, 0, kField, out.string() + " " + why);
}

std::string system_message(const std::string& what, int error) {
  return what + ": " + std::strerror(error);
}

// What a non-directory is, for messages.
std::string kind_of(fs::file_type type) {
  switch (type) {
    case fs::file_type::regular: return "a file";
    case fs::file_type::symlink: return "a symbolic link";
    case fs::file_type::fifo: return "a FIFO";
    case fs::file_type::block:
    case fs::file_type::character: return "a device";
    case fs::file_type::socket: return "a socket";
    default: return "not a directory";
  }
}

// Whether an existing directory may be replaced by a run: empty, or a run (holds summary.json).
bool replaceable(const fs::path& dir) {
  std::error_code ec;
  if (fs::symlink_status(dir / "summary.json", ec).type() == fs::file_type::regular) return true;
  return fs::is_empty(dir, ec) && !ec;
}

// Checks `dir` as the destination of a run: absent, or a replaceable directory. Returns whether
// it exists. Throws through `fail` (called with the reason) otherwise.
template <class Fail>
bool check_destination(const fs::path& dir, Fail fail) {
  std::error_code ec;
  const fs::file_status status = fs::symlink_status(dir, ec);
  if (status.type() == fs::file_type::not_found) return false;
  if (ec) fail("cannot be examined (" + ec.message() + ")");
  if (status.type() != fs::file_type::directory) {
    fail("exists and is " + kind_of(status.type()) + ", not a run folder: refusing to replace it");
  }
  if (!replaceable(dir)) {
    fail("is a folder that is neither empty nor a run (no summary.json): refusing to replace what it holds");
  }
  return true;
}

// The hidden sibling `.<name><suffix>` of a folder named `name` in `parent` (built by appending:
// GCC 12 warns falsely, -Wrestrict, on "." + name).
fs::path hidden_sibling(const fs::path& parent, const std::string& name, const std::string& suffix) {
  std::string file = ".";
  file += name;
  file += suffix;
  return parent / file;
}

// renameat2 flags (linux/fs.h), spelled here to keep that header out.
constexpr unsigned kRenameNoReplace = 1U << 0;
constexpr unsigned kRenameExchange = 1U << 1;

// Whether renameat2 failed because the file system or kernel cannot do it (fall back).
bool unsupported(int error) { return error == EINVAL || error == ENOSYS || error == ENOTSUP || error == EOPNOTSUPP; }

// Process-wide registry of paths to remove on the way out. Never destroyed: the stop watchdog
// may use it while the program exits.
std::mutex& cleanup_mutex() {
  static auto* mutex = new std::mutex;
  return *mutex;
}
std::map<std::uint64_t, fs::path>& cleanup_paths() {
  static auto* paths = new std::map<std::uint64_t, fs::path>;
  return *paths;
}
std::uint64_t g_next_cleanup = 1;
std::terminate_handler g_previous_terminate = nullptr;

// The handler writes each stop signal's number here; the watchdog reads it.
int g_stop_pipe[2] = {-1, -1};

extern "C" void on_stop_signal(int signal) {
  const int saved = errno;
  request_stop(signal);
  const auto byte = static_cast<unsigned char>(signal);
  if (g_stop_pipe[1] >= 0) (void)!::write(g_stop_pipe[1], &byte, 1);
  errno = saved;
}

// Writes a line to standard error without locks or allocation beyond the string given.
void say(const std::string& line) {
  const std::string text = line + "\n";
  (void)!::write(STDERR_FILENO, text.data(), text.size());
}

// The second stage of a stop request. The first signal only records the request, so that the
// work unwinds at its next check and keeps what it finished (core/interrupt.hpp); the children
// are asked to stop at once. A call that blocks (a write to a full pipe nobody reads, an open
// that waits) never reaches that check, and SA_RESTART restarts it: kStopGrace after the
// request, or at a second signal, the children are killed, every registered temporary file and
// staging folder removed, and the program ends with 128 + the first signal.
void stop_watchdog() {
  unsigned char first = 0;
  while (::read(g_stop_pipe[0], &first, 1) != 1) {
    if (errno != EINTR) return;
  }
  signal_children(SIGTERM);
  const auto deadline = std::chrono::steady_clock::now() + kStopGrace;
  bool second = false;
  for (;;) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) break;
    pollfd p{g_stop_pipe[0], POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(left.count())) > 0) {
      unsigned char next = 0;
      if (::read(g_stop_pipe[0], &next, 1) == 1) {
        second = true;
        break;
      }
    }
  }
  signal_children(SIGKILL);
  remove_registered_paths();
  // the message last, and never waiting: standard error may be the full pipe the program blocks on
  ::fcntl(STDERR_FILENO, F_SETFL, ::fcntl(STDERR_FILENO, F_GETFL) | O_NONBLOCK);
  say(std::string("blendbench: ") + (second ? "a second stop signal" : "still running " +
                                                                            std::to_string(static_cast<int>(kStopGrace.count())) +
                                                                            " s after the stop signal") +
      ": ending now; temporary files removed");
  ::_exit(128 + first);
}

[[noreturn]] void on_terminate() {
  remove_registered_paths();
  if (g_previous_terminate != nullptr) g_previous_terminate();
  std::abort();
}

}  // namespace

RunFolder::RunFolder(const fs::path& out) {
  // the folder and its name; the lock file and the staging folder are its siblings
  fs::path target = fs::absolute(out).lexically_normal();
  if (!target.has_filename()) target = target.parent_path();
  const std::string name = target.filename().string();
  if (name.empty() || name == "." || name == "..") refuse(out, "does not name a folder a run can be written to");
  target_ = target;
  const fs::path parent = target_.parent_path();
  // refused before any file is created (and checked again under the lock)
  (void)check_destination(target_, [&](const std::string& why) { refuse(out, why); });
  std::error_code ec;
  // the folders above --out this run creates (deepest first), removed again when it commits nothing
  for (fs::path p = parent; !p.empty() && !fs::exists(fs::symlink_status(p, ec)); p = p.parent_path()) {
    created_.push_back(p);
    if (p == p.parent_path()) break;
  }
  fs::create_directories(parent, ec);
  if (ec) throw std::runtime_error("cannot create the folder " + parent.string() + ": " + ec.message());

  // the lock: open, flock without waiting, then make sure the file is still the one at the path
  // (a run that just finished removes it)
  lock_path_ = hidden_sibling(parent, name, ".lock");
  for (int attempt = 0;; ++attempt) {
    const int fd = ::open(lock_path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd < 0) throw std::runtime_error(system_message("cannot open the lock file " + lock_path_.string(), errno));
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int error = errno;
      char pid[32] = {};
      const ssize_t n = ::pread(fd, pid, sizeof pid - 1, 0);
      ::close(fd);
      if (error == EWOULDBLOCK) {
        const std::string holder = n > 0 ? std::string(pid, static_cast<std::size_t>(n)) : std::string();
        refuse(out, "is in use by another run" + (holder.empty() ? std::string() : " (pid " + holder + ")") +
                        " (lock " + lock_path_.string() + "): wait for it or choose another --out");
      }
      throw std::runtime_error(system_message("cannot lock " + lock_path_.string(), error));
    }
    struct stat held {};
    struct stat named {};
    if (::fstat(fd, &held) == 0 && ::lstat(lock_path_.c_str(), &named) == 0 && held.st_dev == named.st_dev &&
        held.st_ino == named.st_ino) {
      lock_fd_ = fd;
      break;
    }
    ::close(fd);
    if (attempt > 100) throw std::runtime_error("cannot take the lock " + lock_path_.string() + ": it keeps changing");
  }
  lock_cleanup_ = register_cleanup(lock_path_);
  try {
    prepare(out, parent, name);
  } catch (...) {
    release();
    throw;
  }
}

void RunFolder::prepare(const fs::path& out, const fs::path& parent, const std::string& name) {
  std::error_code ec;
  const std::string pid = std::to_string(::getpid());
  if (::ftruncate(lock_fd_, 0) != 0 || ::pwrite(lock_fd_, pid.data(), pid.size(), 0) < 0) {
    // the pid is only for the message of a second run; the lock holds without it
  }

  // the destination may be replaced as a whole; it holds a run when it has a summary
  std::error_code summary_ec;
  had_previous_ = check_destination(target_, [&](const std::string& why) { refuse(out, why); }) &&
                  fs::symlink_status(target_ / "summary.json", summary_ec).type() == fs::file_type::regular;

  // staging folders of killed runs: nobody else can own them while we hold the lock
  const std::string stale_prefix = hidden_sibling(parent, name, ".staging-").filename().string();
  for (const fs::directory_entry& entry : fs::directory_iterator(parent, ec)) {
    const std::string entry_name = entry.path().filename().string();
    if (entry_name.rfind(stale_prefix, 0) == 0) fs::remove_all(entry.path(), ec);
  }

  staging_ = parent / (stale_prefix + pid);
  if (!fs::create_directory(staging_, ec) || ec) {
    throw std::runtime_error("cannot create the staging folder " + staging_.string() +
                             (ec ? ": " + ec.message() : std::string(": it exists")));
  }
  staging_cleanup_ = register_cleanup(staging_);
}

void RunFolder::release() noexcept {
  std::error_code ec;
  if (!committed_ && !staging_.empty()) fs::remove_all(staging_, ec);
  unregister_cleanup(staging_cleanup_);
  staging_cleanup_ = 0;
  if (lock_fd_ >= 0) {
    // removed while still held, so a run that opened it before is sent to retry on a new file
    ::unlink(lock_path_.c_str());
    ::close(lock_fd_);
    lock_fd_ = -1;
  }
  unregister_cleanup(lock_cleanup_);
  lock_cleanup_ = 0;
  // a refused or failed first run leaves no empty results/runs/ behind (non-empty ones stay)
  if (!committed_) {
    for (const fs::path& p : created_) fs::remove(p, ec);
  }
  created_.clear();
}

RunFolder::~RunFolder() { release(); }

void RunFolder::commit_to(const fs::path& where_in) {
  if (committed_) throw std::logic_error("RunFolder::commit_to: already committed");
  const fs::path where = fs::absolute(where_in).lexically_normal();
  const bool exists = check_destination(where, [&](const std::string& why) {
    throw std::runtime_error("cannot publish the run as " + where.string() + ": it " + why);
  });

  if (!exists) {
    // nothing to replace: one rename that refuses to overwrite what may have appeared since
    if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, where.c_str(), kRenameNoReplace) != 0) {
      const int error = errno;
      if (!unsupported(error) || ::rename(staging_.c_str(), where.c_str()) != 0) {
        throw std::runtime_error(system_message("cannot rename " + staging_.string() + " to " + where.string(),
                                                unsupported(error) ? errno : error));
      }
    }
  } else if (::renameat2(AT_FDCWD, staging_.c_str(), AT_FDCWD, where.c_str(), kRenameExchange) == 0) {
    // swapped in one step: the previous run is now under the staging name
    std::error_code ec;
    fs::remove_all(staging_, ec);
  } else {
    // no atomic exchange on this file system: move the previous run aside, then rename
    const int error = errno;
    if (!unsupported(error)) {
      throw std::runtime_error(system_message("cannot swap " + staging_.string() + " and " + where.string(), error));
    }
    const fs::path old =
        hidden_sibling(where.parent_path(), where.filename().string(), ".staging-old-" + std::to_string(::getpid()));
    if (::rename(where.c_str(), old.c_str()) != 0) {
      throw std::runtime_error(system_message("cannot move " + where.string() + " aside", errno));
    }
    if (::rename(staging_.c_str(), where.c_str()) != 0) {
      const int saved = errno;
      (void)::rename(old.c_str(), where.c_str());
      throw std::runtime_error(system_message("cannot rename " + staging_.string() + " to " + where.string(), saved));
    }
    std::error_code ec;
    fs::remove_all(old, ec);
  }
  committed_ = true;
  unregister_cleanup(staging_cleanup_);
  staging_cleanup_ = 0;
}

void install_stop_handlers() {
  // the watchdog first, so that no signal can come before it listens
  if (::pipe2(g_stop_pipe, O_CLOEXEC) == 0) {
    std::thread(stop_watchdog).detach();
  }
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  // restart interrupted system calls (writes go on): the watchdog ends what stays blocked
  action.sa_flags = SA_RESTART;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
  // a reader that went away (`blendbench ... | head`) is a stop request too: the work unwinds and
  // leaves no temporary file, where the default action would end it on the spot
  sigaction(SIGPIPE, &action, nullptr);
  // past a file-size limit (ulimit -f) a write fails with EFBIG and says so, instead of SIGXFSZ
  // ending the program with its temporary files
  std::signal(SIGXFSZ, SIG_IGN);
  g_previous_terminate = std::set_terminate(on_terminate);
}

std::uint64_t register_cleanup(const fs::path& path) {
  const std::lock_guard<std::mutex> lock(cleanup_mutex());
  const std::uint64_t handle = g_next_cleanup++;
  cleanup_paths().emplace(handle, path);
  return handle;
}

void unregister_cleanup(std::uint64_t handle) noexcept {
  if (handle == 0) return;
  const std::lock_guard<std::mutex> lock(cleanup_mutex());
  cleanup_paths().erase(handle);
}

void remove_registered_paths() noexcept {
  const std::lock_guard<std::mutex> lock(cleanup_mutex());
  for (const auto& [handle, path] : cleanup_paths()) {
    try {
      std::error_code ec;
      fs::remove_all(path, ec);
    } catch (...) {
      // out of memory on the way out: remove what can be removed
    }
  }
  cleanup_paths().clear();
}

}  // namespace blendbench
