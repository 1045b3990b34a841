#pragma once
// Random geometry for seeded property tests: directions, and segments of every kind that start
// at a given point (so they chain into paths). Sizes in metres.

#include <array>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "blendbench/geometry/segment.hpp"
#include "property.hpp"

namespace blendbench::test {

// A point uniform in the cube [-extent, extent]^3.
inline Vec3 random_point(std::mt19937_64& rng, double extent = 1) {
  return Vec3(uniform(rng, -extent, extent), uniform(rng, -extent, extent), uniform(rng, -extent, extent));
}

// A unit vector uniform on the sphere.
inline Vec3 random_unit(std::mt19937_64& rng) {
  for (;;) {
    const Vec3 v(uniform(rng, -1, 1), uniform(rng, -1, 1), uniform(rng, -1, 1));
    if (v.norm() > 0.1 && v.norm() <= 1) return v.normalized();
  }
}

// A unit vector perpendicular to the unit vector n, uniform on that circle.
inline Vec3 random_perpendicular(std::mt19937_64& rng, const Vec3& n) {
  const Vec3 e1 = any_perpendicular(n);
  const double a = uniform(rng, 0, 2 * std::numbers::pi);
  return std::cos(a) * e1 + std::sin(a) * n.cross(e1);
}

enum class SegmentKind { kLine, kArc, kHelix, kBezier, kClothoid };
inline constexpr std::array<SegmentKind, 5> kSegmentKinds = {SegmentKind::kLine, SegmentKind::kArc, SegmentKind::kHelix,
                                                             SegmentKind::kBezier, SegmentKind::kClothoid};

// A random segment of `kind` that starts at `start`, about `size` across, in a random plane:
// lines 0.1..1 size long; arcs of radius 0.1..1 size sweeping 0.05..2 pi, helices the same
// with up to 2 turns and a rise of up to +-size; Beziers of degree 2..5 whose control polygon
// advances along one direction (every hodograph control point has a positive component along
// it, so the curve is regular); clothoids 0.2..1 size long turning by up to ~4 rad.
inline Segment random_segment(std::mt19937_64& rng, SegmentKind kind, const Vec3& start, double size) {
  const Vec3 n = random_unit(rng);
  const Vec3 e1 = random_perpendicular(rng, n);
  const Vec3 e2 = n.cross(e1);
  switch (kind) {
    case SegmentKind::kLine:
      return Line{start, start + uniform(rng, 0.1, 1) * size * e1};
    case SegmentKind::kArc:
    case SegmentKind::kHelix: {
      const bool helix = kind == SegmentKind::kHelix;
      const double radius = uniform(rng, 0.1, 1) * size;
      const double sweep = uniform(rng, 0.05, helix ? 4 * std::numbers::pi : 2 * std::numbers::pi);
      const double rise = helix ? uniform(rng, -1, 1) * size : 0.0;
      return Arc{start - radius * e1, e1, e2, radius, sweep, rise};
    }
    case SegmentKind::kBezier: {
      const int degree = 2 + static_cast<int>(uniform(rng, 0, 4));
      std::vector<Vec3> ctrl{start};
      for (int i = 0; i < degree; ++i) {
        const Vec3 lateral = uniform(rng, -1, 1) * e2 + uniform(rng, -0.5, 0.5) * n;
        ctrl.push_back(ctrl.back() + size / degree * (uniform(rng, 0.2, 1) * e1 + lateral));
      }
      return Bezier(ctrl);
    }
    case SegmentKind::kClothoid: {
      const double len = uniform(rng, 0.2, 1) * size;
      const double kappa0 = uniform(rng, -2, 2) / len;
      const double sharpness = uniform(rng, -4, 4) / (len * len);
      return Clothoid{start, e1, e2, kappa0, sharpness, len};
    }
  }
  return Line{start, start};
}

}  // namespace blendbench::test
