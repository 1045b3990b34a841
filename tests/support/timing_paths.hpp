#pragma once
// Paths and probes shared by the velocity-planner tests: two kinked lines, a random path of
// every segment type, and the sampled velocity near an arc length.

#include <algorithm>
#include <cmath>
#include <random>
#include <utility>
#include <vector>

#include "blendbench/program/path.hpp"
#include "blendbench/timing/timing.hpp"
#include "support/property.hpp"

namespace blendbench::test {

// Two lines joined at `theta` (rad) in the x-y plane, no stop, the given buffer mode.
inline Path kinked_lines(double theta, const Limits& a, const Limits& b, BufferMode mode) {
  Path path;
  const Vec3 corner(0.2, 0, 0);
  path.append(PathPiece{Line{{0, 0, 0}, corner}, 0, -1, a, mode});
  PathPiece second{Line{corner, corner + 0.2 * Vec3(std::cos(theta), std::sin(theta), 0)}, 1, -1, b, mode};
  second.kink_angle = theta;
  path.append(second);
  return path;
}

// The velocity at arc length s, from the samples on either side (the smaller of the two, and
// the jerk-limited bound on how far either is from the knot velocity).
inline std::pair<double, double> velocities_around(const Timing& timing, double s) {
  const auto& x = timing.samples;
  const auto after = std::lower_bound(x.begin(), x.end(), s, [](const TimedSample& a, double v) { return a.s < v; });
  const auto before = after == x.begin() ? after : std::prev(after);
  return {std::min(before->v, after->v), std::max(before->v, after->v)};
}

// Largest sample velocity on global arc lengths [a, b].
inline double max_velocity_on(const Timing& timing, double a, double b) {
  double v = 0;
  for (const TimedSample& x : timing.samples) {
    if (x.s >= a && x.s <= b) v = std::max(v, x.v);
  }
  return v;
}

// A random path built piece by piece: lines, arcs, clothoids and cubic Beziers, each starting
// tangent to the previous end or at a random kink, with random limits, buffer modes and stops.
inline Path random_path(std::mt19937_64& rng) {
  const auto unit = [&rng] {
    return Vec3(test::uniform(rng, -1, 1), test::uniform(rng, -1, 1), test::uniform(rng, -1, 1) + 1e-3).normalized();
  };
  const auto random_limits = [&rng] {
    return Limits{test::log_uniform(rng, 0.02, 2.0), test::log_uniform(rng, 0.2, 50.0), test::log_uniform(rng, 0.2, 50.0),
                  test::log_uniform(rng, 2.0, 5000.0)};
  };
  const Limits shared = random_limits();
  const bool per_piece = test::uniform(rng, 0, 1) < 0.5;
  const BufferMode modes[] = {BufferMode::kAborting, BufferMode::kBuffered, BufferMode::kBlendingLow,
                              BufferMode::kBlendingPrevious, BufferMode::kBlendingNext, BufferMode::kBlendingHigh};
  Path path;
  Vec3 p = Vec3::Zero();
  Vec3 dir = unit();
  const int n = 1 + static_cast<int>(test::uniform(rng, 0, 10));
  for (int k = 0; k < n; ++k) {
    if (k > 0 && test::uniform(rng, 0, 1) < 0.35) dir = unit();
    const Vec3 perp = dir.cross(unit()).normalized();
    const double kind = test::uniform(rng, 0, 4);
    Segment seg = Line{p, p + dir * test::log_uniform(rng, 1e-4, 0.2)};
    if (kind >= 1 && kind < 2) {
      const double r = test::log_uniform(rng, 1e-3, 0.2);
      seg = Arc{p - r * perp, perp, dir, r, test::uniform(rng, 0.05, 3.0), 0.0};
    } else if (kind >= 2 && kind < 3) {
      const double len = test::log_uniform(rng, 1e-4, 0.05);
      seg = Clothoid{p, dir, perp, test::uniform(rng, -50, 50), test::uniform(rng, -1, 1) * 4e3, len};
    } else if (kind >= 3) {
      // legs within 70 degrees of dir: the hodograph never vanishes
      const double l = test::log_uniform(rng, 1e-4, 0.05);
      std::vector<Vec3> ctrl{p};
      for (int i = 0; i < 3; ++i) {
        const double ang = test::uniform(rng, -1.2, 1.2);
        ctrl.push_back(ctrl.back() + l * (std::cos(ang) * dir + std::sin(ang) * perp));
      }
      seg = Bezier(ctrl);
    }
    PathPiece piece{seg, k, -1, per_piece ? random_limits() : shared,
                    modes[static_cast<int>(test::uniform(rng, 0, 6)) % 6]};
    if (!path.pieces().empty()) {
      const Segment& prev = path.pieces().back().segment;
      piece.kink_angle = angle_between(tangent(prev, length(prev)), tangent(seg, 0.0));
      piece.stop_before = test::uniform(rng, 0, 1) < 0.1 ||
                          (piece.kink_angle > 1e-9 && path.pieces().back().buffer == BufferMode::kBuffered);
    }
    p = end_point(seg);
    dir = tangent(seg, length(seg));
    path.append(std::move(piece));
  }
  return path;
}

}  // namespace blendbench::test
