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

// Whether an existing directory may be replaced: empty, or a folder of this kind (holds `marker`).
bool replaceable(const fs::path& dir, const std::string& marker) {
  std::error_code ec;
  if (fs::symlink_status(dir / marker, ec).type() == fs::file_type::regular) return true;
  return fs::is_empty(dir, ec) && !ec;
}

// Checks `dir` as the destination: absent, or a replaceable directory. Returns whether it
// exists. Throws through `fail` (called with the reason) otherwise.
template <class Fail>
bool check_destination(const fs::path& dir, const std::string& marker, Fail fail) {
  std::error_code ec;
  const fs::file_status status = fs::symlink_status(dir, ec);
  if (status.type() == fs::file_type::not_found) return false;
  if (ec) fail("cannot be examined (" + ec.message() + ")");
  if (status.type() != fs::file_type::directory) {
    fail("exists and is " + kind_of(status.type()) + ", not a run folder: refusing to replace it");
  }
  if (!replaceable(dir, marker)) {
    fail("is a folder that is neither empty nor a run (no " + marker + "): refusing to replace what it holds");
  }
  return true;
}

// The names the machinery gives its files beside a folder `name`: `.name.lock`,
// `.name.staging-<digits>` and `.name.staging-old-<digits>`. `name` empty: any name.
bool staging_name_of(const std::string& entry, const std::string& name) {
  const std::string prefix = "." + name + ".staging-";
  std::string rest;
  if (!name.empty()) {
    if (entry.rfind(prefix, 0) != 0) return false;
    rest = entry.substr(prefix.size());
  } else {
    const std::size_t at = entry.rfind(".staging-");
    if (entry.empty() || entry[0] != '.' || at == std::string::npos || at == 0) return false;
    rest = entry.substr(at + 9);
  }
  if (rest.rfind("old-", 0) == 0) rest.erase(0, 4);
  return !rest.empty() && rest.size() <= 10 && rest.find_first_not_of("0123456789") == std::string::npos;
}

bool machinery_name(const std::string& entry) {
  if (staging_name_of(entry, "")) return true;
  return entry.size() > 6 && entry[0] == '.' && entry.compare(entry.size() - 5, 5, ".lock") == 0;
}

// Run folders of any kind (a run's summary, a reproduction's results): a folder inside one is
// deleted when the next run there is published.
constexpr const char* kRunMarkers[] = {"summary.json", "results.json"};

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

RunFolder::RunFolder(const fs::path& out, const std::string& marker, const std::string& flag) : marker_(marker), flag_(flag) {
  const auto refuse_out = [&](const std::string& why) { throw InputError("", 0, 0, flag_, out.string() + " " + why); };
  // the folder and its name; the lock file and the staging folder are its siblings
  fs::path target = fs::absolute(out).lexically_normal();
  if (!target.has_filename()) target = target.parent_path();
  const std::string name = target.filename().string();
  if (name.empty() || name == "." || name == "..") refuse_out("does not name a folder a run can be written to");
  if (machinery_name(name)) {
    refuse_out("has the name of a run's lock or staging folder (.NAME.lock, .NAME.staging-N): choose another name");
  }
  target_ = target;
  const fs::path parent = target_.parent_path();
  // refused before any file is created (and checked again under the lock)
  (void)check_destination(target_, marker_, refuse_out);
  std::error_code ec;
  // the folders above --out this run creates (deepest first), removed again when it commits nothing
  for (fs::path p = parent; !p.empty() && !fs::exists(fs::symlink_status(p, ec)); p = p.parent_path()) {
    created_.push_back(p);
    if (p == p.parent_path()) break;
  }
  fs::create_directories(parent, ec);
  if (ec) refuse_out("cannot be created: the folder " + parent.string() + ": " + ec.message());
  // the folder above, resolved once and held open: the staging folder, the lock and the renames
  // live in it, wherever a later change of the path may point
  parent_ = fs::canonical(parent, ec);
  if (ec) refuse_out("cannot be used: the folder " + parent.string() + ": " + ec.message());
  parent_fd_ = ::open(parent_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (parent_fd_ < 0) throw std::runtime_error(system_message("cannot open the folder " + parent_.string(), errno));

  // the lock: open, flock without waiting, then make sure the file is still the one at the path
  // (a run that just finished removes it)
  lock_name_ = hidden_sibling("", name, ".lock").string();
  lock_path_ = parent_ / lock_name_;
  for (int attempt = 0;; ++attempt) {
    const int fd = ::openat(parent_fd_, lock_name_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC | O_NOFOLLOW, 0644);
    if (fd < 0) {
      const int error = errno;
      release();
      throw std::runtime_error(system_message("cannot open the lock file " + lock_path_.string(), error));
    }
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int error = errno;
      char pid[32] = {};
      const ssize_t n = ::pread(fd, pid, sizeof pid - 1, 0);
      ::close(fd);
      release();
      if (error == EWOULDBLOCK) {
        const std::string holder = n > 0 ? std::string(pid, static_cast<std::size_t>(n)) : std::string();
        refuse_out("is in use by another run" + (holder.empty() ? std::string() : " (pid " + holder + ")") + " (lock " +
                   lock_path_.string() + "): wait for it or choose another " + flag_);
      }
      throw std::runtime_error(system_message("cannot lock " + lock_path_.string(), error));
    }
    struct stat held {};
    struct stat named {};
    if (::fstat(fd, &held) == 0 && ::fstatat(parent_fd_, lock_name_.c_str(), &named, AT_SYMLINK_NOFOLLOW) == 0 &&
        held.st_dev == named.st_dev && held.st_ino == named.st_ino) {
      lock_fd_ = fd;
      break;
    }
    ::close(fd);
    if (attempt > 100) {
      release();
      throw std::runtime_error("cannot take the lock " + lock_path_.string() + ": it keeps changing");
    }
  }
  lock_cleanup_ = register_cleanup(lock_path_);
  try {
    prepare(out, name);
  } catch (...) {
    release();
    throw;
  }
}

void RunFolder::check_not_nested(const fs::path& out) const {
  const auto refuse_out = [&](const std::string& why) { throw InputError("", 0, 0, flag_, out.string() + " " + why); };
  for (fs::path up = parent_; !up.empty() && up.has_filename(); up = up.parent_path()) {
    std::error_code ec;
    for (const char* marker : kRunMarkers) {
      if (fs::symlink_status(up / marker, ec).type() == fs::file_type::regular) {
        refuse_out("is inside the run folder " + up.string() + " (it holds " + marker +
                   "): the next run there would replace it, this one with it; choose a folder outside it");
      }
    }
    const std::string name = up.filename().string();
    if (staging_name_of(name, "")) refuse_out("is inside the staging folder " + up.string() + " of another run");
    // a run writing into a folder above: its lock is held
    const fs::path lock = up.parent_path() / hidden_sibling("", name, ".lock");
    const int fd = ::open(lock.c_str(), O_RDONLY | O_NOFOLLOW | O_CLOEXEC | O_NONBLOCK);
    if (fd >= 0) {
      const bool held = ::flock(fd, LOCK_SH | LOCK_NB) != 0 && errno == EWOULDBLOCK;
      ::close(fd);
      if (held) refuse_out("is inside " + up.string() + ", the output folder of a run that is running: choose a folder outside it");
    }
  }
}

void RunFolder::prepare(const fs::path& out, const std::string& name) {
  std::error_code ec;
  const std::string pid = std::to_string(::getpid());
  if (::ftruncate(lock_fd_, 0) != 0 || ::pwrite(lock_fd_, pid.data(), pid.size(), 0) < 0) {
    // the pid is only for the message of a second run; the lock holds without it
  }
  check_not_nested(out);

  // the destination may be replaced as a whole; it holds a run when it has the marker
  std::error_code marker_ec;
  had_previous_ = check_destination(target_, marker_, [&](const std::string& why) { throw InputError("", 0, 0, flag_, out.string() + " " + why); }) &&
                  fs::symlink_status(target_ / marker_, marker_ec).type() == fs::file_type::regular;

  // staging folders of killed runs (exactly .<name>.staging-<digits>): nobody else can own them
  // while we hold the lock
  for (const fs::directory_entry& entry : fs::directory_iterator(parent_, ec)) {
    if (staging_name_of(entry.path().filename().string(), name)) fs::remove_all(entry.path(), ec);
  }

  staging_name_ = hidden_sibling("", name, ".staging-" + pid).string();
  staging_ = parent_ / staging_name_;
  if (::mkdirat(parent_fd_, staging_name_.c_str(), 0777) != 0) {
    throw std::runtime_error(system_message("cannot create the staging folder " + staging_.string(), errno));
  }
  staging_cleanup_ = register_cleanup(staging_);
  staging_fd_ = ::openat(parent_fd_, staging_name_.c_str(), O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (staging_fd_ < 0) throw std::runtime_error(system_message("cannot open the staging folder " + staging_.string(), errno));
}

void RunFolder::release() noexcept {
  std::error_code ec;
  if (!committed_ && !kept_ && !staging_.empty()) fs::remove_all(staging_, ec);
  unregister_cleanup(staging_cleanup_);
  staging_cleanup_ = 0;
  if (staging_fd_ >= 0) {
    ::close(staging_fd_);
    staging_fd_ = -1;
  }
  if (lock_fd_ >= 0) {
    // removed while still held, so a run that opened it before is sent to retry on a new file
    ::unlinkat(parent_fd_, lock_name_.c_str(), 0);
    ::close(lock_fd_);
    lock_fd_ = -1;
  }
  unregister_cleanup(lock_cleanup_);
  lock_cleanup_ = 0;
  if (parent_fd_ >= 0) {
    ::close(parent_fd_);
    parent_fd_ = -1;
  }
  // a refused or failed first run leaves no empty results/runs/ behind (non-empty ones stay)
  if (!committed_) {
    for (const fs::path& p : created_) fs::remove(p, ec);
  }
  created_.clear();
}

RunFolder::~RunFolder() { release(); }

void RunFolder::check_before_publishing(const std::vector<std::string>& required) {
  std::string problem;
  // the folder above the target: still the one the run started in, reached without a link
  std::error_code ec;
  const fs::path now = fs::canonical(target_.parent_path(), ec);
  struct stat held {};
  struct stat named {};
  if (ec || now != parent_ || ::fstat(parent_fd_, &held) != 0 || ::stat(parent_.c_str(), &named) != 0 ||
      held.st_dev != named.st_dev || held.st_ino != named.st_ino) {
    problem = "the folder " + target_.parent_path().string() + " is no longer " + parent_.string() +
              " (moved, or replaced by a link) since the run started";
  }
  // the staging folder: still the one at its name, holding what the run wrote
  if (problem.empty() && (::fstat(staging_fd_, &held) != 0 ||
                          ::fstatat(parent_fd_, staging_name_.c_str(), &named, AT_SYMLINK_NOFOLLOW) != 0 ||
                          held.st_dev != named.st_dev || held.st_ino != named.st_ino)) {
    problem = "the staging folder " + staging_.string() + " was replaced while the run wrote it";
  }
  for (const std::string& entry : required) {
    if (!problem.empty()) break;
    struct stat st {};
    if (::fstatat(staging_fd_, entry.c_str(), &st, AT_SYMLINK_NOFOLLOW) != 0) {
      problem = "the run's " + entry + " is missing from " + staging_.string() + " (written elsewhere?)";
    }
  }
  if (problem.empty()) return;
  // nothing published; what the run wrote stays for the user to look at
  kept_ = true;
  unregister_cleanup(staging_cleanup_);
  staging_cleanup_ = 0;
  // where the staging folder is now, wherever it was moved (the descriptor follows it)
  std::error_code link_ec;
  const fs::path now_at = fs::read_symlink("/proc/self/fd/" + std::to_string(staging_fd_), link_ec);
  throw std::runtime_error("not published as " + target_.string() + ": " + problem + "; the run's files stay in " +
                           (link_ec ? staging_ : now_at).string() + " (files written after the change went where the old path then led)");
}

void RunFolder::commit_to(const fs::path& where_in, const std::vector<std::string>& required) {
  if (committed_) throw std::logic_error("RunFolder::commit_to: already committed");
  const fs::path where = fs::absolute(where_in).lexically_normal();
  if (where.parent_path() != target_.parent_path()) throw std::logic_error("RunFolder::commit_to: not a sibling of the target");
  check_before_publishing(required);
  const fs::path shown = parent_ / where.filename();
  const std::string where_name = where.filename().string();
  const bool exists = check_destination(shown, marker_, [&](const std::string& why) {
    throw std::runtime_error("cannot publish the run as " + where.string() + ": it " + why);
  });

  if (!exists) {
    // nothing to replace: one rename that refuses to overwrite what may have appeared since
    if (::renameat2(parent_fd_, staging_name_.c_str(), parent_fd_, where_name.c_str(), kRenameNoReplace) != 0) {
      const int error = errno;
      if (!unsupported(error) || ::renameat(parent_fd_, staging_name_.c_str(), parent_fd_, where_name.c_str()) != 0) {
        throw std::runtime_error(system_message("cannot rename " + staging_.string() + " to " + where.string(),
                                                unsupported(error) ? errno : error));
      }
    }
  } else if (::renameat2(parent_fd_, staging_name_.c_str(), parent_fd_, where_name.c_str(), kRenameExchange) == 0) {
    // swapped in one step: the previous run is now under the staging name
    std::error_code ec;
    fs::remove_all(staging_, ec);
  } else {
    // no atomic exchange on this file system: move the previous run aside, then rename
    const int error = errno;
    if (!unsupported(error)) {
      throw std::runtime_error(system_message("cannot swap " + staging_.string() + " and " + where.string(), error));
    }
    const std::string old = hidden_sibling("", where_name, ".staging-old-" + std::to_string(::getpid())).string();
    if (::renameat(parent_fd_, where_name.c_str(), parent_fd_, old.c_str()) != 0) {
      throw std::runtime_error(system_message("cannot move " + where.string() + " aside", errno));
    }
    if (::renameat(parent_fd_, staging_name_.c_str(), parent_fd_, where_name.c_str()) != 0) {
      const int saved = errno;
      (void)::renameat(parent_fd_, old.c_str(), parent_fd_, where_name.c_str());
      throw std::runtime_error(system_message("cannot rename " + staging_.string() + " to " + where.string(), saved));
    }
    std::error_code ec;
    fs::remove_all(parent_ / old, ec);
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
