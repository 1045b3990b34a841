#include "blendbench/core/interrupt.hpp"

#include <gtest/gtest.h>

#include <csignal>

namespace blendbench {
namespace {

TEST(Interrupt, TheFirstSignalWinsUntilCleared) {
  clear_stop_request();
  EXPECT_FALSE(stop_requested());
  EXPECT_NO_THROW(throw_if_stop_requested());
  request_stop(SIGTERM);
  request_stop(SIGINT);  // a later signal does not replace the first
  EXPECT_TRUE(stop_requested());
  EXPECT_EQ(stop_signal(), SIGTERM);
  try {
    throw_if_stop_requested();
    FAIL() << "expected Interrupted";
  } catch (const Interrupted& stop) {
    EXPECT_EQ(stop.signal, SIGTERM);
  }
  clear_stop_request();
  EXPECT_EQ(stop_signal(), 0);
  EXPECT_NO_THROW(throw_if_stop_requested());
}

// Interrupted is not a std::exception, so a handler that turns failures into a status lets it
// through to main.
TEST(Interrupt, PassesHandlersOfStdExceptions) {
  const auto run = [] {
    try {
      throw Interrupted{SIGINT};
    } catch (const std::exception&) {
      return false;
    }
  };
  EXPECT_THROW(run(), Interrupted);
}

}  // namespace
}  // namespace blendbench
