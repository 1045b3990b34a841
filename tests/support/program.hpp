#pragma once
// The blendbench program started from a test with an argument vector (no shell between), its
// standard output and error read from one pipe: line by line while it runs (to act on a
// progress line, e.g. send it a signal), or all at once.

#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <string>
#include <vector>

namespace blendbench::test {

class Child {
 public:
  // Starts `program` with `args` in the working directory `cwd` (empty: the test's own).
  Child(const std::string& program, const std::vector<std::string>& args, const std::filesystem::path& cwd = {}) {
    int fds[2];
    if (::pipe(fds) != 0) return;
    pid_ = ::fork();
    if (pid_ == 0) {
      ::dup2(fds[1], STDOUT_FILENO);
      ::dup2(fds[1], STDERR_FILENO);
      ::close(fds[0]);
      ::close(fds[1]);
      if (!cwd.empty() && ::chdir(cwd.c_str()) != 0) ::_exit(127);
      std::vector<std::string> all = {program};
      all.insert(all.end(), args.begin(), args.end());
      std::vector<char*> argv;
      for (std::string& a : all) argv.push_back(a.data());
      argv.push_back(nullptr);
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
    ::close(fds[1]);
    fd_ = fds[0];
  }
  ~Child() {
    if (pid_ > 0 && !reaped_) {
      ::kill(pid_, SIGKILL);
      (void)wait();
    }
    if (fd_ >= 0) ::close(fd_);
  }
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  // Reads output until a line starts with `prefix` (true) or the output ends (false).
  bool wait_for_line(const std::string& prefix) {
    for (;;) {
      const auto newline = pending_.find('\n');
      if (newline != std::string::npos) {
        const std::string line = pending_.substr(0, newline);
        output_ += pending_.substr(0, newline + 1);
        pending_.erase(0, newline + 1);
        if (line.rfind(prefix, 0) == 0) return true;
        continue;
      }
      if (!read_some()) return false;
    }
  }

  void signal(int sig) const { ::kill(pid_, sig); }

  // Reads the rest of the output and waits; returns the exit code, -1 when killed by a signal.
  int wait() {
    while (read_some()) {
    }
    output_ += pending_;
    pending_.clear();
    int status = 0;
    ::waitpid(pid_, &status, 0);
    reaped_ = true;
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  // Reads the rest of the output and waits at most `seconds`; past that the child is killed
  // (SIGKILL) and -2 is returned. Otherwise as wait().
  int wait_within(double seconds) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    for (;;) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      if (left.count() <= 0) {
        ::kill(pid_, SIGKILL);
        (void)wait();
        return -2;
      }
      pollfd p{fd_, POLLIN, 0};
      const int ready = fd_ < 0 ? 0 : ::poll(&p, 1, static_cast<int>(std::min<long long>(left.count(), 200)));
      if (fd_ < 0 || (ready > 0 && !read_some())) {
        // the output ended: the child exits (or closed its output); wait for it within the time left
        while (std::chrono::steady_clock::now() < deadline) {
          int status = 0;
          const pid_t done = ::waitpid(pid_, &status, WNOHANG);
          if (done == pid_) {
            reaped_ = true;
            output_ += pending_;
            pending_.clear();
            return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
          }
          ::usleep(10000);
        }
      }
    }
  }

  // Waits at most `seconds` for the child to end without reading its output (so a child that
  // writes more than the pipe holds stays blocked in that write); past that it is killed
  // (SIGKILL) and -2 is returned. Then reads what it printed; otherwise as wait().
  int wait_exit_within(double seconds) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
    int status = 0;
    while (::waitpid(pid_, &status, WNOHANG) == 0) {
      if (std::chrono::steady_clock::now() > deadline) {
        ::kill(pid_, SIGKILL);
        (void)wait();
        return -2;
      }
      ::usleep(20000);
    }
    reaped_ = true;
    while (read_some()) {
    }
    output_ += pending_;
    pending_.clear();
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  // What it printed so far (all of it after wait()).
  [[nodiscard]] const std::string& output() const { return output_; }
  [[nodiscard]] pid_t pid() const { return pid_; }

 private:
  bool read_some() {
    if (fd_ < 0) return false;
    char buffer[4096];
    const ssize_t n = ::read(fd_, buffer, sizeof buffer);
    if (n <= 0) return false;
    pending_.append(buffer, static_cast<std::size_t>(n));
    return true;
  }

  pid_t pid_ = -1;
  int fd_ = -1;
  bool reaped_ = false;
  std::string pending_, output_;
};

}  // namespace blendbench::test
