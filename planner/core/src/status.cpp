#include "blendbench/core/status.hpp"

namespace blendbench {

std::string_view to_string(Status status) {
  switch (status) {
    case Status::kOk: return "ok";
    case Status::kInfeasible: return "infeasible";
    case Status::kUnreachable: return "unreachable";
    case Status::kJointLimit: return "joint_limit";
    case Status::kSingular: return "singular";
    case Status::kNotConverged: return "not_converged";
  }
  return "unknown";
}

}  // namespace blendbench
