#pragma once
// Internal to the app: a progress bar on stderr for long jobs (sweeps, video renders), redrawn in
// place when stderr is a terminal and silent otherwise; a job ends with one summary line either
// way, so a log file gets exactly that line.

#include <chrono>
#include <cstddef>
#include <string>

namespace blendbench {

class ProgressBar {
 public:
  // Whether stderr is a terminal is decided once, here.
  ProgressBar();

  // Redraws the bar: `done` of `total`, a description, and the time left estimated from the
  // rate so far (measured from construction; `counted` of the done items count towards it,
  // e.g. not those resumed from an earlier run). Nothing when stderr is not a terminal.
  void draw(std::size_t done, std::size_t total, const std::string& what, std::size_t counted) const;
  void draw(std::size_t done, std::size_t total, const std::string& what) const { draw(done, total, what, done); }

  // A line above the bar (on a terminal the bar is cleared first and redrawn by the next draw).
  void say(const std::string& line) const;

  // Clears the bar; then prints `summary` as a line, when it is not empty.
  void finish(const std::string& summary = {}) const;

  [[nodiscard]] bool on_terminal() const { return tty_; }
  // Seconds since construction.
  [[nodiscard]] double elapsed() const;

 private:
  bool tty_;
  std::chrono::steady_clock::time_point start_;
};

// "1m05s", or "2h03m" from an hour on (rounded to the second; negative counts as 0).
std::string format_duration(double seconds);

}  // namespace blendbench
