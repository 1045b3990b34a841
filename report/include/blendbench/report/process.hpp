#pragma once
// Child processes without a shell: a program and its arguments as a vector, started with
// posix_spawn, so no file or scenario name can ever be read as a command. Each child runs in a
// process group of its own and is registered while it runs, so that a stop request reaches it
// (and whatever it started) at once and none outlives this program (run_folder.hpp,
// install_stop_handlers).

#include <string>
#include <vector>

namespace blendbench {

struct ProcessResult {
  bool ok = false;       // started and exited with status 0
  int exit_status = -1;  // the status it exited with; -1 when it did not start or was killed
  int signal = 0;        // the signal that ended it; 0 when it exited
  std::string message;   // why not ok: "cannot start X: ...", "X exited with status N", "X killed by signal N"
};

struct ProcessOptions {
  // When set, the child's standard output and error go to this file (created or truncated);
  // otherwise they are the caller's.
  std::string output_file;
  // When >= 0 (and no output_file), the child's standard output and error go to this open
  // descriptor (OutputDir::create_fresh: a file that cannot lead out of its folder); the caller
  // keeps it and closes it.
  int output_fd = -1;
  // Variables added to the child's environment ("NAME=value").
  std::vector<std::string> environment;
};

// Runs argv[0] (looked up on PATH when it has no slash) with the arguments argv[1..] and waits
// for it. Standard input is /dev/null. Safe to call from several threads at once.
ProcessResult run_process(const std::vector<std::string>& argv, const ProcessOptions& options = {});

// Sends `signal` to the process group of every child run_process is running. Async-signal-safe
// only in the sense that it takes no lock a signal handler could hold: call it from a thread.
void signal_children(int signal) noexcept;

}  // namespace blendbench
