#pragma once
// An independent check of a fitted transition (on random corners, random_corner.hpp): position, tangent and curvature-vector continuity at every junction,
// trims within the available lengths, finite values, and the deviation from the replaced
// programmed path measured with test::Chain in both directions.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <variant>
#include <vector>

#include "chain_distance.hpp"
#include "random_corner.hpp"
#include "blendbench/corner/corner.hpp"
#include "property.hpp"

namespace blendbench::test {

struct FitCheck {
  double position = 0;   // largest gap at a junction / corner size (or coordinate scale, check_fit)
  double tangent = 0;    // rad, largest tangent kink at a junction
  double curvature = 0;  // largest curvature-vector jump / (largest curvature + 1 / size)
  double deviation = 0;  // m, max of both directed distances to the replaced path
  bool finite = true;
  bool trims_within = true;
};

inline FitCheck check_fit(const CornerInput& in, const CornerFit& fit) {
  FitCheck check;
  const double len_in = length(in.in);
  const double size = std::max({fit.trim_in, fit.trim_out, 1e-300});
  // gaps relative to the corner's size, or to 1e-6 of the moves' coordinates where that is
  // larger: a point of a move carries the rounding of the numbers it is computed from (1e-16 of
  // |p|, of |centre| + radius on an arc), which a fillet of 70-140 nm at 0.2-0.9 m from the
  // origin sees as a gap of 1.0-1.2e-9 of its size (seeds 8643 and 8769 of
  // BiclothoidStartDistance at 20000 cases; the planar fits close to 3e-22 m)
  const auto magnitude = [](const Primitive& move) {
    if (const Arc* arc = std::get_if<Arc>(&move)) return arc->center.norm() + arc->radius;
    const Line& line = std::get<Line>(move);
    return std::max(line.p0.norm(), line.p1.norm());
  };
  const double scale = std::max(size, 1e-6 * std::max(magnitude(in.in), magnitude(in.out)));
  check.trims_within = fit.trim_in <= in.in_available * (1 + 1e-12) && fit.trim_out <= in.out_available * (1 + 1e-12);
  if (fit.transition.empty()) return check;
  const auto junction = [&](const Segment& a, double sa, const Segment& b, double sb) {
    const Vec3 pa = point(a, sa);
    const Vec3 pb = point(b, sb);
    const Vec3 ka = curvature_vector(a, sa);
    const Vec3 kb = curvature_vector(b, sb);
    check.finite = check.finite && pa.allFinite() && pb.allFinite() && ka.allFinite() && kb.allFinite();
    check.position = std::max(check.position, (pa - pb).norm() / scale);
    check.tangent = std::max(check.tangent, angle_between(tangent(a, sa), tangent(b, sb)));
    check.curvature = std::max(check.curvature, (ka - kb).norm() / std::max({ka.norm(), kb.norm(), 1.0 / size}));
  };
  const Segment seg_in = to_segment(in.in);
  const Segment seg_out = to_segment(in.out);
  junction(seg_in, len_in - fit.trim_in, fit.transition.front(), 0.0);
  for (std::size_t k = 0; k + 1 < fit.transition.size(); ++k) {
    junction(fit.transition[k], length(fit.transition[k]), fit.transition[k + 1], 0.0);
  }
  junction(fit.transition.back(), length(fit.transition.back()), seg_out, fit.trim_out);
  std::vector<Segment> replaced;
  if (fit.trim_in > 0) replaced.push_back(to_segment(sub_segment(in.in, len_in - fit.trim_in, len_in)));
  if (fit.trim_out > 0) replaced.push_back(to_segment(sub_segment(in.out, 0.0, fit.trim_out)));
  const Chain transition(fit.transition);
  const Chain programmed(replaced);
  check.deviation = std::max(transition.directed_to(programmed), programmed.directed_to(transition));
  check.finite = check.finite && std::isfinite(check.deviation);
  return check;
}

// Junction tolerances of the curvature-continuous methods (clothoid, biclothoid): position
// relative to the corner size, tangent in rad, curvature vector relative to the larger
// curvature (or 1 / size).
inline constexpr double kG2Position = 1e-9;
inline constexpr double kG2Tangent = 1e-10;
inline constexpr double kG2Curvature = 1e-7;

// The checked fit is finite, within its trims and G2 at every junction; the failure says which.
inline ::testing::AssertionResult is_g2(const FitCheck& check) {
  if (!check.finite) return ::testing::AssertionFailure() << "a junction value is not finite";
  if (!check.trims_within) return ::testing::AssertionFailure() << "the trims exceed the available lengths";
  if (check.position > kG2Position) {
    return ::testing::AssertionFailure() << "position gap " << check.position << " > " << kG2Position;
  }
  if (check.tangent > kG2Tangent) {
    return ::testing::AssertionFailure() << "tangent kink " << check.tangent << " rad > " << kG2Tangent;
  }
  if (check.curvature > kG2Curvature) {
    return ::testing::AssertionFailure() << "curvature jump " << check.curvature << " > " << kG2Curvature;
  }
  return ::testing::AssertionSuccess();
}

// Largest curvature (1/m) and sharpness (1/m^2) over a fitted transition.
inline double peak_curvature(const CornerFit& fit) {
  double peak = 0;
  for (const Segment& seg : fit.transition) peak = std::max(peak, max_curvature(seg, 0, length(seg)));
  return peak;
}
inline double peak_sharpness(const CornerFit& fit) {
  double peak = 0;
  for (const Segment& seg : fit.transition) peak = std::max(peak, max_sharpness(seg, 0, length(seg)));
  return peak;
}

}  // namespace blendbench::test
