#include "blendbench/sim/metrics.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include "blendbench/geometry/closest.hpp"

namespace blendbench {
namespace {

// Distance from `p` to the programmed path: the closest point over all moves (exact for lines
// and planar arcs). Linear in the number of moves, which is fine for programs of a few thousand.
double contour_distance(const Program& program, const Vec3& p) {
  double best = std::numeric_limits<double>::infinity();
  for (const Move& move : program.moves) best = std::min(best, closest_point(move.geometry, p).distance);
  return best;
}

}  // namespace

Metrics compute_metrics(const Trace& trace, const Program& program, const Path& path, const MetricsOptions& options) {
  assert(!trace.diverged);
  Metrics m;
  const std::size_t n = trace.samples.size();
  m.tracking_error.assign(n, 0.0);
  m.contour_error.assign(n, 0.0);

  // errors per sample
  double sum_sq = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const TraceSample& s = trace.samples[i];
    m.tracking_error[i] = (s.tcp - s.tcp_cmd).norm();
    m.contour_error[i] = contour_distance(program, s.tcp);
    m.tracking_error_max = std::max(m.tracking_error_max, m.tracking_error[i]);
    m.contour_error_max = std::max(m.contour_error_max, m.contour_error[i]);
    sum_sq += m.tracking_error[i] * m.tracking_error[i];
    m.joint_velocity_peak = m.joint_velocity_peak.cwiseMax(s.qd.cwiseAbs());
    m.torque_peak = m.torque_peak.cwiseMax(s.tau.cwiseAbs());
  }
  if (n > 0) m.tracking_error_rms = std::sqrt(sum_sq / static_cast<double>(n));

  // settling: the last sample outside the tolerance ends the cycle
  if (n > 0 && (trace.samples.back().tcp - options.end_point).norm() <= options.settle_tolerance) {
    std::size_t k = n - 1;
    while (k > 0 && (trace.samples[k - 1].tcp - options.end_point).norm() <= options.settle_tolerance) --k;
    m.cycle_time = trace.samples[k].t;
  }

  // derivatives by differences on the (uniform) servo grid
  if (n >= 4) {
    const double dt = trace.samples[1].t - trace.samples[0].t;
    for (std::size_t i = 1; i < n; ++i) {
      const JointVector qdd = (trace.samples[i].qd - trace.samples[i - 1].qd) / dt;
      m.joint_acceleration_peak = m.joint_acceleration_peak.cwiseMax(qdd.cwiseAbs());
    }
    const double dt3 = dt * dt * dt;
    for (std::size_t i = 3; i < n; ++i) {
      const auto& a = trace.samples[i];
      const auto& b = trace.samples[i - 1];
      const auto& c = trace.samples[i - 2];
      const auto& d = trace.samples[i - 3];
      const Vec3 jerk = (a.tcp_cmd - 3 * b.tcp_cmd + 3 * c.tcp_cmd - d.tcp_cmd) / dt3;
      m.cartesian_jerk_peak = std::max(m.cartesian_jerk_peak, jerk.norm());
      const JointVector qjerk = (a.q_cmd - 3 * b.q_cmd + 3 * c.q_cmd - d.q_cmd) / dt3;
      m.joint_jerk_peak = std::max(m.joint_jerk_peak, qjerk.cwiseAbs().maxCoeff());
    }
  }

  for (const CornerReport& c : path.corners) m.path_deviation_max = std::max(m.path_deviation_max, c.deviation);
  m.joint_velocity_limit_exceeded = (m.joint_velocity_peak.array() > options.velocity_limits.array()).any();
  m.torque_limit_reached =
      trace.torque_saturated || (m.torque_peak.array() >= options.torque_limits.array() * (1 - 1e-12)).any();
  return m;
}

}  // namespace blendbench
