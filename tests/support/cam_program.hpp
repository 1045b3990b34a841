#pragma once
// The CAM contour of bench_cam and the optimal planner's tests: a point stream of tiny lines.

#include <cmath>
#include <cstddef>
#include <random>

#include "blendbench/program/program.hpp"

namespace blendbench::test {

// `n` lines along x = 20 sin(t) + 5 sin(3.1 t + 0.3), y = 15 sin(0.7 t + 1) + 4 cos(2.3 t) mm
// with t = s / 20 mm, each 0.01..0.1 mm of s (a fixed seed); feed 2000 mm/min, 1000 mm/s^2,
// 10000 mm/s^3 (the G-code defaults' order); every corner a biclothoid of 0.05 mm tolerance.
inline Program cam_program(int n) {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> step(0.01e-3, 0.1e-3);
  const auto at = [](double s) {
    const double t = s / 0.02;
    return Vec3(0.020 * std::sin(t) + 0.005 * std::sin(3.1 * t + 0.3), 0.015 * std::sin(0.7 * t + 1.0) + 0.004 * std::cos(2.3 * t),
                0.0);
  };
  Program program;
  program.moves.reserve(static_cast<std::size_t>(n));
  double s = 0;
  Vec3 p = at(0);
  for (int k = 0; k < n; ++k) {
    s += step(rng);
    const Vec3 q = at(s);
    Move& move = program.moves.emplace_back();
    move.geometry = Line{p, q};
    move.limits = {2.0 / 60.0, 1.0, 1.0, 10.0};
    move.transition.method = Method::kBiclothoid;
    move.transition.parameter = 0.05e-3;
    p = q;
  }
  return program;
}

}  // namespace blendbench::test
