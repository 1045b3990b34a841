#pragma once
// Small JSON helpers shared by every writer of result files.

#include <nlohmann/json.hpp>

namespace blendbench {

// A JSON number, or null when the value is not finite (JSON has no infinity or NaN).
nlohmann::json finite_or_null(double value);

}  // namespace blendbench
