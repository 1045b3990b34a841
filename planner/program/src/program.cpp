#include "blendbench/program/program.hpp"

#include "blendbench/core/format.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <sstream>
#include <utility>

namespace blendbench {
namespace {

std::string lower(std::string_view text) {
  std::string out(text);
  std::transform(out.begin(), out.end(), out.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

constexpr std::array<std::pair<BufferMode, std::string_view>, 6> kBufferNames = {{
    {BufferMode::kAborting, "Aborting"},
    {BufferMode::kBuffered, "Buffered"},
    {BufferMode::kBlendingLow, "BlendingLow"},
    {BufferMode::kBlendingPrevious, "BlendingPrevious"},
    {BufferMode::kBlendingNext, "BlendingNext"},
    {BufferMode::kBlendingHigh, "BlendingHigh"},
}};

constexpr std::array<std::pair<Method, std::string_view>, 5> kMethodNames = {{
    {Method::kNone, "none"},
    {Method::kArc, "arc"},
    {Method::kBezier, "bezier"},
    {Method::kClothoid, "clothoid"},
    {Method::kBiclothoid, "biclothoid"},
}};

std::string describe(const Move& move, std::size_t index) {
  return move.name.empty() ? "move " + std::to_string(index + 1) : move.name;
}

}  // namespace

std::string_view to_string(BufferMode mode) {
  for (const auto& [m, name] : kBufferNames) {
    if (m == mode) return name;
  }
  return "unknown";
}

std::string_view to_string(Method method) {
  for (const auto& [m, name] : kMethodNames) {
    if (m == method) return name;
  }
  return "unknown";
}

double junction_velocity(BufferMode mode, double v_prev, double v_next) {
  switch (mode) {
    case BufferMode::kBlendingPrevious: return v_prev;
    case BufferMode::kAborting:
    case BufferMode::kBlendingNext: return v_next;
    case BufferMode::kBlendingHigh: return std::max(v_prev, v_next);
    case BufferMode::kBuffered:
    case BufferMode::kBlendingLow: break;
  }
  return std::min(v_prev, v_next);
}

std::string_view to_string(CurvatureSteps steps) { return steps == CurvatureSteps::kAllow ? "allow" : "limit"; }

std::optional<CurvatureSteps> curvature_steps_from_string(std::string_view name) {
  if (name == "limit") return CurvatureSteps::kLimit;
  if (name == "allow") return CurvatureSteps::kAllow;
  return std::nullopt;
}

std::string_view to_string(OrientationInterpolation interpolation) {
  return interpolation == OrientationInterpolation::kSpline ? "spline" : "slerp";
}

std::optional<OrientationInterpolation> orientation_interpolation_from_string(std::string_view name) {
  if (name == "slerp") return OrientationInterpolation::kSlerp;
  if (name == "spline") return OrientationInterpolation::kSpline;
  return std::nullopt;
}

std::optional<BufferMode> buffer_mode_from_string(std::string_view name) {
  const std::string key = lower(name);
  for (const auto& [m, n] : kBufferNames) {
    if (lower(n) == key) return m;
  }
  return std::nullopt;
}

std::optional<Method> method_from_string(std::string_view name) {
  const std::string key = lower(name);
  for (const auto& [m, n] : kMethodNames) {
    if (n == key) return m;
  }
  return std::nullopt;
}

bool oriented(const Program& program) {
  return std::any_of(program.moves.begin(), program.moves.end(), [](const Move& m) { return m.orientation.has_value(); });
}

void validate(const Program& program) {
  if (program.moves.empty()) throw InputError("", 0, 0, "moves", "the program has no moves");
  if (program.moves.size() > kMaxMoves) {
    fail_at(program.moves[kMaxMoves].where, "moves",
            "the program has " + std::to_string(program.moves.size()) + " moves; the limit is " + std::to_string(kMaxMoves));
  }
  // size of the program, for relative tolerances; a non-finite length is reported below and must
  // not make the tolerance infinite (every other move would read as zero length)
  double size = 0;
  std::size_t longest = 0;
  for (std::size_t k = 0; k < program.moves.size(); ++k) {
    const double len = length(program.moves[k].geometry);
    if (std::isfinite(len) && len > size) {
      size = len;
      longest = k;
    }
  }
  // relative to the program's size: in double precision, points of a path that spans `size` are
  // only known to about 1e-16 of it, so joins and lengths are judged at 1e-9 of it (1 nm per m)
  constexpr double kRelativeJoin = 1e-9;
  constexpr double kMinSize = 1e-3;  // m: below a millimetre the tolerance stays 1e-12 m
  const double join_tol = kRelativeJoin * std::max(size, kMinSize);
  // why a length is below the tolerance: the move is a point (below a nanometre, less than any
  // machine resolves), or the tolerance is large because another move is huge
  constexpr double kPointLength = 1e-9;  // m
  const auto tolerance_cause = [&](double len) {
    if (len <= kPointLength) return std::string();
    return "; the join tolerance " + format_mm(join_tol) + " is 1e-9 of the longest move, " +
           describe(program.moves[longest], longest) + " of " + format_mm(size) +
           ": moves of such different sizes cannot be joined in double precision (check the units and coordinates of " +
           describe(program.moves[longest], longest) + ")";
  };

  for (std::size_t k = 0; k < program.moves.size(); ++k) {
    const Move& move = program.moves[k];
    const std::string who = describe(move, k);
    // an arc of zero or negative radius or sweep has a zero, negative or NaN length and NaN
    // points, so it is named first: the cause, not the symptom (a NaN or infinite radius or sweep
    // is a non-finite number, below)
    if (const Arc* arc = std::get_if<Arc>(&move.geometry)) {
      if (std::isfinite(arc->radius) && std::isfinite(arc->sweep) && !(arc->radius > 0 && arc->sweep > 0)) {
        fail_at(move.where, "geometry",
                who + " is a degenerate arc (radius " + format_mm(arc->radius) + ", sweep " + format_deg(arc->sweep) + ")");
      }
    }
    const double len = length(move.geometry);
    // the length alone misses an arc whose centre or axes are NaN but radius and sweep are not
    if (!std::isfinite(len) || !point(move.geometry, 0.0).allFinite() || !point(move.geometry, len).allFinite()) {
      fail_at(move.where, "geometry", who + " has a coordinate that is not a finite number (NaN or infinite)");
    }
    if (len <= join_tol) {
      const std::string cause = tolerance_cause(len);
      fail_at(move.where, "geometry",
              cause.empty() ? who + " has zero length (" + format_mm(len) + "); remove it or give it a distinct end point"
                            : who + " (" + format_mm(len) + ") is too short to be told from a point" + cause);
    }
    // joined to the previous move; checked after this move's own geometry, so that a non-finite
    // or degenerate start is named as such and not as an infinite or spurious gap
    if (k > 0) {
      const Move& previous = program.moves[k - 1];
      const Vec3 end = point(previous.geometry, length(previous.geometry));
      const double gap = (point(move.geometry, 0.0) - end).norm();
      if (gap > join_tol) {
        fail_at(move.where, "geometry",
                who + " does not start where " + describe(previous, k - 1) + " ends (gap " + format_mm(gap) + ")");
      }
    }
    const Limits& lim = move.limits;
    const std::array<std::pair<double, const char*>, 4> limits = {{{lim.velocity, "velocity"},
                                                                    {lim.acceleration, "acceleration"},
                                                                    {lim.deceleration, "deceleration"},
                                                                    {lim.jerk, "jerk"}}};
    for (const auto& [value, field] : limits) {
      if (!std::isfinite(value) || value <= 0) {
        fail_at(move.where, field, who + ": " + field + " must be positive and finite, got " + format_value(value));
      }
    }
    if (!std::isfinite(move.transition.parameter) || move.transition.parameter < 0) {
      fail_at(move.where, "transition.parameter", who + ": the transition parameter must be >= 0, got " + format_mm(move.transition.parameter));
    }
    if (!std::isfinite(move.transition.start_distance) || move.transition.start_distance < 0) {
      fail_at(move.where, "transition.start_distance", who + ": the start distance must be >= 0, got " + format_mm(move.transition.start_distance));
    }
    for (const auto& [value, field] : {std::pair{move.transition.parameter, "transition.parameter"},
                                       std::pair{move.transition.start_distance, "transition.start_distance"}}) {
      if (value > 0 && value < kMinTransitionSize) {
        fail_at(move.where, field,
                who + ": a transition is 0 (none) or at least " + format_mm(kMinTransitionSize) +
                    " (below that the rounding of the coordinates swamps the curve), got " + format_mm(value));
      }
    }
    if (move.transition.start_distance > 0 && move.transition.method != Method::kBiclothoid) {
      fail_at(move.where, "transition.start_distance",
              who + ": a start distance sizes only a biclothoid transition, not " +
                  std::string(to_string(move.transition.method)));
    }
    if (move.transition.start_distance > 0 && move.transition.parameter > 0) {
      fail_at(move.where, "transition.start_distance",
              who + ": give the biclothoid either a maximum deviation (parameter) or a start distance, not both");
    }
    // a tolerance replaces the parameter (and a biclothoid's start distance): both keys named
    if (!std::isfinite(move.transition.tolerance) || move.transition.tolerance < 0) {
      fail_at(move.where, "transition.tolerance",
              who + ": the tolerance must be > 0 and finite, got " + format_mm(move.transition.tolerance));
    }
    if (move.transition.tolerance > 0 && move.transition.parameter > 0) {
      fail_at(move.where, "transition.tolerance",
              who + ": give the transition either a tolerance (transition.tolerance) or a parameter (transition.parameter), not both");
    }
    if (move.transition.tolerance > 0 && move.transition.start_distance > 0) {
      fail_at(move.where, "transition.tolerance",
              who + ": give the biclothoid either a tolerance (transition.tolerance) or a start distance (transition.start_distance), not both");
    }
    if (!std::isfinite(move.transition.kappa_max) || move.transition.kappa_max < 0) {
      fail_at(move.where, "transition.kappa_max", who + ": the curvature cap must be >= 0, got " + format_per_mm(move.transition.kappa_max));
    }
    if (!std::isfinite(move.transition.merge_tolerance) || move.transition.merge_tolerance < 0) {
      fail_at(move.where, "transition.merge_tolerance",
              who + ": the merge tolerance must be >= 0, got " + format_mm(move.transition.merge_tolerance));
    }
    if (move.orientation && (!move.orientation->coeffs().allFinite() || std::abs(move.orientation->norm() - 1) > 1e-9)) {
      fail_at(move.where, "orientation", who + ": the orientation must be a unit quaternion, got norm " +
                                             format_value(move.orientation->norm()));
    }
    for (const auto& [value, field] : {std::pair{move.angular.velocity, "angular_velocity"},
                                       std::pair{move.angular.acceleration, "angular_acceleration"},
                                       std::pair{move.angular.jerk, "angular_jerk"}}) {
      if (std::isnan(value) || value <= 0) {
        fail_at(move.where, field, who + ": " + field + " must be positive, got " + format_value(value));
      }
    }
    if (!std::isfinite(move.transition.velocity) || move.transition.velocity < 0) {
      fail_at(move.where, "transition.velocity", who + ": the transition velocity must be >= 0, got " + format_mm_per_s(move.transition.velocity));
    }
  }
  validate(program.smoothing);
}

}  // namespace blendbench
