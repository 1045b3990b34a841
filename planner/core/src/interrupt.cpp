#include "blendbench/core/interrupt.hpp"

#include <atomic>

namespace blendbench {
namespace {

// Written from a signal handler: must be lock-free to be async-signal-safe.
std::atomic<int> g_stop_signal{0};
static_assert(std::atomic<int>::is_always_lock_free);

}  // namespace

void request_stop(int signal) noexcept {
  int none = 0;
  g_stop_signal.compare_exchange_strong(none, signal);
}

int stop_signal() noexcept { return g_stop_signal.load(); }

void clear_stop_request() noexcept { g_stop_signal.store(0); }

void throw_if_stop_requested() {
  if (const int signal = stop_signal(); signal != 0) throw Interrupted{signal};
}

}  // namespace blendbench
