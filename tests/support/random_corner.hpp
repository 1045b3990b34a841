#pragma once
// Random corners between lines and arcs in random 3D planes, for the property tests of the
// corner methods and the distribution benchmark of their fits (bench_blend).

#include <cmath>
#include <numbers>
#include <random>

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

}  // namespace blendbench::test
