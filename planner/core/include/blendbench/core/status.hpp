#pragma once
// The planner's one status convention for expected infeasibility (STYLE: errors chosen by who
// can act on them). Bad input is an InputError; programming errors are asserts.

#include <string>
#include <string_view>

namespace blendbench {

enum class Status {
  kOk,
  kInfeasible,   // the request cannot be met (corner too tight, tolerance unreachable, ...)
  kUnreachable,  // a pose lies outside the robot's workspace
  kJointLimit,   // a solution exists only outside the joint limits
  kSingular,     // the solution is not unique or not stable (wrist/shoulder/elbow singularity)
  kNotConverged  // an iterative solver ran out of iterations
};

std::string_view to_string(Status status);

// A status with a human-readable message. `ok()` is true only for Status::kOk.
struct Outcome {
  Status status = Status::kOk;
  std::string message;
  [[nodiscard]] bool ok() const { return status == Status::kOk; }
};

}  // namespace blendbench
