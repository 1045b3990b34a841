#pragma once
// Random programs that set tool orientations, shared by the orientation tests of the blender
// and of the velocity planner.

#include <numbers>
#include <string>

#include "blendbench/program/program.hpp"
#include "support/property.hpp"
#include "support/random_geometry.hpp"

namespace blendbench::test {

// A random program of 2 to 7 lines and arcs with random turns, every method, and a random
// orientation target on the first move and most others (turning by up to max_turn rad from
// the previous one).
inline Program random_program(std::mt19937_64& rng, double max_turn = 2.1) {
  const Method methods[] = {Method::kNone, Method::kArc, Method::kBezier, Method::kClothoid, Method::kBiclothoid};
  Program program;
  program.start_orientation = Quat(Eigen::AngleAxisd(std::numbers::pi, Vec3::UnitX()));
  Vec3 p = Vec3::Zero();
  Quat q = program.start_orientation;
  const int n = 2 + static_cast<int>(test::uniform(rng, 0, 6));
  for (int k = 0; k < n; ++k) {
    Move move;
    const Vec3 dir = random_unit(rng);
    const double len = test::log_uniform(rng, 0.02, 0.2);
    if (test::uniform(rng, 0, 1) < 0.25) {
      const Vec3 perp = random_perpendicular(rng, dir);
      const double r = test::uniform(rng, 0.5, 2) * len;
      move.geometry = Arc{p - r * perp, perp, dir, r, test::uniform(rng, 0.3, 2.5), 0.0};
    } else {
      move.geometry = Line{p, p + len * dir};
    }
    p = point(move.geometry, length(move.geometry));
    move.limits = {0.2, 2.0, 2.0, 20.0};
    move.transition.method = methods[static_cast<int>(test::uniform(rng, 0, 5))];
    move.transition.parameter = move.transition.method == Method::kNone ? 0.0 : test::log_uniform(rng, 1e-3, 0.01);
    if (k == 0 || test::uniform(rng, 0, 1) < 0.8) {
      q = Quat(Eigen::AngleAxisd(test::uniform(rng, 0, max_turn), random_unit(rng))) * q;
      move.orientation = q;
    }
    move.name = "move " + std::to_string(k + 1);
    program.moves.push_back(move);
  }
  return program;
}

}  // namespace blendbench::test
