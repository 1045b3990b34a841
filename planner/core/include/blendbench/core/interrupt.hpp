#pragma once
// A stop request from outside the program (SIGINT, SIGTERM). The signal handler only records
// which signal arrived (request_stop); the long loops (the simulation's steps, the variants of a
// run, each output file) poll it and unwind by throwing Interrupted, so files are closed,
// temporary files removed and finished results kept on the way out. Nothing here installs a
// handler: the program does (report/run_folder.hpp, install_stop_handlers).

namespace blendbench {

// Thrown by throw_if_stop_requested. Deliberately not a std::exception, so that handlers that
// turn a std::exception into a failed result (a variant's, a file's) let it pass; main() catches
// it, prints one line and exits 128 + signal.
struct Interrupted {
  int signal = 0;  // the signal number that asked to stop (SIGINT 2, SIGTERM 15)
};

// Records a stop request; async-signal-safe (one lock-free atomic store). The first signal wins.
void request_stop(int signal) noexcept;

// The signal of the pending stop request, 0 when there is none.
[[nodiscard]] int stop_signal() noexcept;
[[nodiscard]] inline bool stop_requested() noexcept { return stop_signal() != 0; }

// Forgets a stop request (tests, and a program that handled it and goes on).
void clear_stop_request() noexcept;

// Throws Interrupted{stop_signal()} when a stop was requested; otherwise does nothing.
void throw_if_stop_requested();

}  // namespace blendbench
