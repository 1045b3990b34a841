#include "blendbench/program/corner_case.hpp"

#include <ostream>
#include <utility>

namespace blendbench {

namespace {

constexpr std::pair<CornerCase, std::string_view> kCaseNames[] = {
    {CornerCase::kRegular, "regular"},
    {CornerCase::kExactStop, "exact_stop"},
    {CornerCase::kCollinear, "collinear"},
    {CornerCase::kReversal, "reversal"},
    {CornerCase::kNearReversal, "near_reversal"},
    {CornerCase::kZeroDistance, "zero_distance"},
    {CornerCase::kIntersection, "intersection"},
    {CornerCase::kTangent, "tangent"},
    {CornerCase::kTangentOpposite, "tangent_opposite"},
    {CornerCase::kLineSegment, "line_segment"},
    {CornerCase::kSameCircleSameDirection, "same_circle_same_direction"},
    {CornerCase::kSameCircleOppositeDirection, "same_circle_opposite_direction"},
    {CornerCase::kClothoidArcClothoid, "clothoid_arc_clothoid"},
    {CornerCase::kCurvatureCapUnmet, "curvature_cap_unmet"},
    {CornerCase::kNonPlanar, "non_planar"},
};

constexpr std::pair<Fallback, std::string_view> kFallbackNames[] = {
    {Fallback::kNone, ""},
    {Fallback::kExactStop, "exact_stop"},
    {Fallback::kBiarc, "biarc"},
    {Fallback::kSmallerRadiusShortened, "smaller_radius_shortened"},
    {Fallback::kQuartic, "quartic"},
    {Fallback::kBezier, "bezier"},
    {Fallback::kBiclothoid, "biclothoid"},
    {Fallback::kBiclothoidBezier, "biclothoid, bezier"},
};

}  // namespace

std::string_view to_string(CornerCase corner_case) {
  for (const auto& [value, name] : kCaseNames) {
    if (value == corner_case) return name;
  }
  return "unknown";
}

std::string_view to_string(Fallback fallback) {
  for (const auto& [value, name] : kFallbackNames) {
    if (value == fallback) return name;
  }
  return "unknown";
}

std::optional<CornerCase> corner_case_from_string(std::string_view name) {
  for (const auto& [value, text] : kCaseNames) {
    if (text == name) return value;
  }
  return std::nullopt;
}

std::ostream& operator<<(std::ostream& out, CornerCase corner_case) { return out << to_string(corner_case); }
std::ostream& operator<<(std::ostream& out, Fallback fallback) { return out << to_string(fallback); }

}  // namespace blendbench
