#pragma once
// Random corners between lines and arcs in random 3D planes, and an independent check of a
// fitted transition: position, tangent and curvature-vector continuity at every junction,
// trims within the available lengths, finite values, and the deviation from the replaced
// programmed path measured with test::Chain in both directions.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "chain_distance.hpp"
#include "blendbench/corner/corner.hpp"
#include "property.hpp"

namespace blendbench::test {

// An arc that starts at `start` heading along unit `heading`, turning left about unit
// `normal` (sign +1) or right (-1).
inline Arc arc_leaving(const Vec3& start, const Vec3& heading, const Vec3& normal, double sign, double radius,
                       double sweep) {
  const Vec3 centre = start + sign * radius * normal.cross(heading);
  return Arc{centre, (start - centre) / radius, heading, radius, sweep, 0.0};
}

// An arc that ends at `end` arriving along unit `heading`, turning left (+1) or right (-1).
inline Arc arc_arriving(const Vec3& end, const Vec3& heading, const Vec3& normal, double sign, double radius,
                        double sweep) {
  const Arc back = arc_leaving(end, -heading, normal, -sign, radius, sweep);
  const double len = length(back);
  return arc_leaving(point(back, len), -tangent(back, len), normal, sign, radius, sweep);
}

enum class CornerKind { kLineLine, kLineArc, kArcLine, kArcArc };

struct CornerCase {
  CornerInput input;
  CornerKind kind = CornerKind::kLineLine;
  double angle = 0;  // rad, the tangent jump
};

// A random corner: deflection 0.001..179.999 deg (half of them log-uniform, so tiny angles are
// common; a third of the corners with an arc are G1 instead), radii 0.1..1000 mm, move lengths
// 0.1..1000 mm (half of them blended at both ends), tolerance 1e-3..1 mm, a random plane.
inline CornerCase random_corner(std::mt19937_64& rng, CornerKind kind, Method method) {
  const auto log_uniform = [&](double lo, double hi) { return test::log_uniform(rng, lo, hi); };
  const auto coin = [&] { return uniform(rng, 0, 1) < 0.5; };
  CornerCase c;
  c.kind = kind;
  const Vec3 normal = Vec3(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1)).normalized();
  const double rot = uniform(rng, 0, 2 * std::numbers::pi);
  const Vec3 x = any_perpendicular(normal);
  const Vec3 t1 = std::cos(rot) * x + std::sin(rot) * normal.cross(x);
  const bool has_arc = kind != CornerKind::kLineLine;
  const bool g1 = has_arc && uniform(rng, 0, 1) < 1.0 / 3.0;
  c.angle = g1 ? 0.0 : (coin() ? log_uniform(1e-3, 179.999) : uniform(rng, 1e-3, 179.999)) * std::numbers::pi / 180;
  const double turn = coin() ? 1.0 : -1.0;
  const Vec3 t2 = std::cos(c.angle) * t1 + turn * std::sin(c.angle) * normal.cross(t1);
  const Vec3 corner(uniform(rng, -0.1, 0.1), uniform(rng, -0.1, 0.1), uniform(rng, -0.1, 0.1));
  const double r1 = log_uniform(1e-4, 1);
  const double r2 = log_uniform(1e-4, 1);
  const double sweep1 = uniform(rng, 0.05, 1.5 * std::numbers::pi);
  const double sweep2 = uniform(rng, 0.05, 1.5 * std::numbers::pi);
  const double len1 = log_uniform(1e-4, 1);
  const double len2 = log_uniform(1e-4, 1);
  const double side1 = coin() ? 1.0 : -1.0;
  const double side2 = coin() ? 1.0 : -1.0;
  if (kind == CornerKind::kLineLine || kind == CornerKind::kLineArc) {
    c.input.in = Line{corner - len1 * t1, corner};
  } else {
    c.input.in = arc_arriving(corner, t1, normal, side1, r1, sweep1);
  }
  if (kind == CornerKind::kLineLine || kind == CornerKind::kArcLine) {
    c.input.out = Line{corner, corner + len2 * t2};
  } else {
    c.input.out = arc_leaving(corner, t2, normal, side2, r2, sweep2);
  }
  c.input.in_available = coin() ? length(c.input.in) : 0.5 * length(c.input.in);
  c.input.out_available = coin() ? length(c.input.out) : 0.5 * length(c.input.out);
  c.input.spec.method = method;
  c.input.spec.parameter = log_uniform(1e-6, 1e-3);
  c.input.name = "random corner";
  return c;
}

struct FitCheck {
  double position = 0;   // largest gap at a junction / corner size
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
  check.trims_within = fit.trim_in <= in.in_available * (1 + 1e-12) && fit.trim_out <= in.out_available * (1 + 1e-12);
  if (fit.transition.empty()) return check;
  const auto junction = [&](const Segment& a, double sa, const Segment& b, double sb) {
    const Vec3 pa = point(a, sa);
    const Vec3 pb = point(b, sb);
    const Vec3 ka = curvature_vector(a, sa);
    const Vec3 kb = curvature_vector(b, sb);
    check.finite = check.finite && pa.allFinite() && pb.allFinite() && ka.allFinite() && kb.allFinite();
    check.position = std::max(check.position, (pa - pb).norm() / size);
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
