#include "blendbench/report/process.hpp"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <mutex>
#include <set>

extern char** environ;

namespace blendbench {
namespace {

// The children running now, by pid (each the leader of its own process group). Never destroyed:
// the stop watchdog may read it while the program exits.
std::mutex& children_mutex() {
  static auto* mutex = new std::mutex;
  return *mutex;
}
std::set<pid_t>& children() {
  static auto* set = new std::set<pid_t>;
  return *set;
}

}  // namespace

void signal_children(int signal) noexcept {
  const std::lock_guard<std::mutex> lock(children_mutex());
  for (const pid_t pid : children()) ::kill(-pid, signal);
}

ProcessResult run_process(const std::vector<std::string>& argv, const ProcessOptions& options) {
  ProcessResult result;
  if (argv.empty()) {
    result.message = "no program to run";
    return result;
  }
  std::vector<std::string> args = argv;
  std::vector<char*> pointers;
  for (std::string& a : args) pointers.push_back(a.data());
  pointers.push_back(nullptr);

  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  if (!options.output_file.empty()) {
    // opened in the child only: the caller holds no descriptor that other children could inherit
    posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, options.output_file.c_str(),
                                     O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&actions, STDOUT_FILENO, STDERR_FILENO);
  } else if (options.output_fd >= 0) {
    // dup2 clears close-on-exec on the copies; the caller's descriptor stays close-on-exec
    posix_spawn_file_actions_adddup2(&actions, options.output_fd, STDOUT_FILENO);
    posix_spawn_file_actions_adddup2(&actions, options.output_fd, STDERR_FILENO);
  }
  // a process group of its own: a stop request is forwarded to it as a whole, and a terminal's
  // Ctrl-C reaches this program, which decides
  posix_spawnattr_t attributes;
  posix_spawnattr_init(&attributes);
  posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETPGROUP);
  posix_spawnattr_setpgroup(&attributes, 0);
  std::vector<std::string> variables = options.environment;
  std::vector<char*> environment;
  for (std::string& v : variables) environment.push_back(v.data());
  for (char** e = environ; *e != nullptr; ++e) environment.push_back(*e);
  environment.push_back(nullptr);
  pid_t pid = -1;
  int rc = 0;
  {
    // registered before a stop request could miss it (the lock also orders it against the watchdog)
    const std::lock_guard<std::mutex> lock(children_mutex());
    rc = posix_spawnp(&pid, pointers[0], &actions, &attributes, pointers.data(), environment.data());
    if (rc == 0) children().insert(pid);
  }
  posix_spawnattr_destroy(&attributes);
  posix_spawn_file_actions_destroy(&actions);
  if (rc != 0) {
    result.message = "cannot start " + argv[0] + ": " + std::strerror(rc);
    return result;
  }
  // wait for it to end without reaping it, forget it, then reap it: its pid cannot be reused
  // while it is still registered (a stop request signals the registered groups)
  siginfo_t info{};
  while (::waitid(P_PID, static_cast<id_t>(pid), &info, WEXITED | WNOWAIT) < 0 && errno == EINTR) {
  }
  {
    const std::lock_guard<std::mutex> lock(children_mutex());
    children().erase(pid);
  }
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) {
      result.message = "cannot wait for " + argv[0] + ": " + std::strerror(errno);
      return result;
    }
  }
  if (WIFEXITED(status)) result.exit_status = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) result.signal = WTERMSIG(status);
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
    result.ok = true;
  } else if (WIFEXITED(status)) {
    result.message = argv[0] + " exited with status " + std::to_string(WEXITSTATUS(status));
  } else if (WIFSIGNALED(status)) {
    result.message = argv[0] + " killed by signal " + std::to_string(WTERMSIG(status));
  } else {
    result.message = argv[0] + " ended abnormally";
  }
  return result;
}

}  // namespace blendbench
