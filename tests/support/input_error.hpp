#pragma once
// The check every bad-input test makes: a call throws InputError, located where expected (file,
// line, column, field) and saying what is expected. One place for it, so every test of a
// refusal checks the same things the same way.

#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <utility>

#include "blendbench/core/input_error.hpp"

namespace blendbench::test {

// What the error must say; an unset member is not checked. `message` must occur in what() (the
// whole line, location included); "" checks nothing.
struct ExpectedError {
  std::optional<std::string> file = std::nullopt;
  std::optional<int> line = std::nullopt;
  std::optional<int> column = std::nullopt;
  std::optional<std::string> field = std::nullopt;
  std::string message = "";
};

// Runs `call`, which must throw InputError matching `expected`; a failure of the calling test
// otherwise (no exception, or another field, place or message). Returns the error for further
// checks (an empty error when none was thrown). `context` goes into every failure message.
template <class Call>
InputError expect_input_error(Call&& call, const ExpectedError& expected, const std::string& context = "") {
  try {
    std::forward<Call>(call)();
  } catch (const InputError& e) {
    const std::string what = e.what();
    if (expected.file) {
      EXPECT_EQ(e.file(), *expected.file) << context << "\n" << what;
    }
    if (expected.line) {
      EXPECT_EQ(e.line(), *expected.line) << context << "\n" << what;
    }
    if (expected.column) {
      EXPECT_EQ(e.column(), *expected.column) << context << "\n" << what;
    }
    if (expected.field) {
      EXPECT_EQ(e.field(), *expected.field) << context << "\n" << what;
    }
    EXPECT_NE(what.find(expected.message), std::string::npos)
        << context << "\nexpected '" << expected.message << "' in\n" << what;
    return e;
  }
  ADD_FAILURE() << "no InputError (expected '" << expected.message << "')" << (context.empty() ? "" : ": ") << context;
  return InputError("", 0, 0, "", "");
}

}  // namespace blendbench::test
