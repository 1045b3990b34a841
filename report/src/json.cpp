#include "blendbench/report/json.hpp"

#include <cmath>

namespace blendbench {

nlohmann::json finite_or_null(double value) { return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(); }

}  // namespace blendbench
