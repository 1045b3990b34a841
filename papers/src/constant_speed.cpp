#include "blendbench/papers/constant_speed.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace blendbench {

Timing constant_speed_timing(const Path& path, double speed, double ramp, double dt) {
  const double length = path.length();
  if (!(speed > 0) || !(ramp > 0) || !(dt > 0) || !(2 * ramp <= length)) {
    throw std::invalid_argument("constant_speed_timing: speed, ramp and dt must be positive and two ramps fit the path");
  }
  const double pi = std::numbers::pi;
  const double t_ramp = 2 * ramp / speed;  // s, each ramp
  const double t_total = 2 * t_ramp + (length - 2 * ramp) / speed;
  // the ramp up at time u from its start: s, v, a, j
  const auto up = [&](double u) {
    const double w = pi / t_ramp;
    return TimedSample{u, 0.5 * speed * (u - std::sin(w * u) / w), 0.5 * speed * (1 - std::cos(w * u)),
                       0.5 * speed * w * std::sin(w * u), 0.5 * speed * w * w * std::cos(w * u)};
  };
  Timing timing;
  timing.dt = dt;
  timing.cycle_time = t_total;
  const auto n = static_cast<long>(std::ceil(t_total / dt - 1e-9));
  for (long k = 0; k <= n; ++k) {
    const double t = static_cast<double>(k) * dt;
    TimedSample s{};
    if (t <= t_ramp) {
      s = up(t);
    } else if (t < t_total - t_ramp) {
      s = {t, ramp + speed * (t - t_ramp), speed, 0, 0};
    } else if (t < t_total) {
      // the ramp down mirrors the ramp up
      const TimedSample m = up(t_total - t);
      s = {t, length - m.s, m.v, -m.a, m.j};
    } else {
      s = {t, length, 0, 0, 0};
    }
    s.t = t;
    timing.samples.push_back(s);
  }
  timing.feed_share = (t_total - 2 * t_ramp) / t_total;
  return timing;
}

}  // namespace blendbench
