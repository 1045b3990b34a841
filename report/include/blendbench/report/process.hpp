#pragma once
// Child processes without a shell: a program and its arguments as a vector, started with
// posix_spawn, so no file or scenario name can ever be read as a command.

#include <string>
#include <vector>

namespace blendbench {

struct ProcessResult {
  bool ok = false;      // started and exited with status 0
  std::string message;  // why not: "cannot start X: ...", "X exited with status N", "X killed by signal N"
};

// Runs argv[0] (looked up on PATH when it has no slash) with the arguments argv[1..] and waits
// for it. Standard input is /dev/null; standard output and error are the caller's.
ProcessResult run_process(const std::vector<std::string>& argv);

}  // namespace blendbench
