#include "progress_bar.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace blendbench {
namespace {

constexpr int kBarWidth = 30;  // characters
// A cleared line: wide enough for the longest bar drawn.
constexpr int kLineWidth = 120;

}  // namespace

ProgressBar::ProgressBar() : tty_(::isatty(STDERR_FILENO) == 1), start_(std::chrono::steady_clock::now()) {}

double ProgressBar::elapsed() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

void ProgressBar::draw(std::size_t done, std::size_t total, const std::string& what, std::size_t counted) const {
  if (!tty_) return;
  const int filled = total == 0 ? kBarWidth : static_cast<int>(kBarWidth * std::min(done, total) / total);
  const std::size_t left = total > done ? total - done : 0;
  const std::string eta =
      counted == 0 ? "--" : format_duration(elapsed() / static_cast<double>(counted) * static_cast<double>(left));
  std::fprintf(stderr, "\r[%s%s] %s, ETA %s   ", std::string(static_cast<std::size_t>(filled), '#').c_str(),
               std::string(static_cast<std::size_t>(kBarWidth - filled), '.').c_str(), what.c_str(), eta.c_str());
  std::fflush(stderr);
}

void ProgressBar::say(const std::string& line) const {
  if (tty_) std::fprintf(stderr, "\r%*s\r", kLineWidth, "");
  std::fprintf(stderr, "%s\n", line.c_str());
}

void ProgressBar::finish(const std::string& summary) const {
  if (tty_) std::fprintf(stderr, "\r%*s\r", kLineWidth, "");
  if (!summary.empty()) std::fprintf(stderr, "%s\n", summary.c_str());
  std::fflush(stderr);
}

std::string format_duration(double seconds) {
  const long s = std::lround(std::max(0.0, seconds));
  char buffer[32];
  if (s >= 3600) {
    std::snprintf(buffer, sizeof buffer, "%ldh%02ldm", s / 3600, (s / 60) % 60);
  } else {
    std::snprintf(buffer, sizeof buffer, "%ldm%02lds", s / 60, s % 60);
  }
  return buffer;
}

}  // namespace blendbench
