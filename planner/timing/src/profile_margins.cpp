#include "blendbench/timing/profile_margins.hpp"

#include <algorithm>
#include <cmath>

#include "blendbench/corner/blend.hpp"

namespace blendbench {
namespace {

// Relative rounding allowance of the finite-difference axis terms (positions of ~0.1 m to 1e-16,
// divided by dt^3 = 1e-9 s^3, against jerk limits of ~100 m/s^3).
constexpr double kAxisSlack = 1e-6;

}  // namespace

double feed_at(const Path& path, const std::vector<HandoverZone>& zones, std::size_t k, double local) {
  double feed = path.pieces()[k].limits.velocity;
  const auto first = std::lower_bound(zones.begin(), zones.end(), k,
                                      [](const HandoverZone& z, std::size_t piece) { return z.piece < piece; });
  for (auto z = first; z != zones.end() && z->piece == k; ++z) {
    if (z->s0 <= local && local <= z->s1) feed = std::max(feed, z->velocity);
  }
  return feed;
}

LocalLimits widest(const std::vector<LocalLimits>& lim, std::size_t k0, std::size_t k1) {
  LocalLimits w;
  for (std::size_t k = k0; k <= k1; ++k) {
    w.feed = std::max(w.feed, lim[k].feed);
    w.acceleration = std::max(w.acceleration, lim[k].acceleration);
    w.deceleration = std::max(w.deceleration, lim[k].deceleration);
    w.jerk = std::max(w.jerk, lim[k].jerk);
  }
  return w;
}

LocalLimits limits_between(const Path& path, double s0, double s1, const std::vector<HandoverZone>& zones) {
  LocalLimits w;
  w.feed = 0;
  w.acceleration = 0;
  w.deceleration = 0;
  w.jerk = 0;
  const auto& pieces = path.pieces();
  const std::size_t first = path.locate(s0).piece;
  const std::size_t last = path.locate(s1).piece;
  for (std::size_t k = first + 1; k < last; ++k) {
    const Limits& lim = pieces[k].limits;
    double feed = lim.velocity;
    for (const HandoverZone& z : zones) {
      if (z.piece == k) feed = std::max(feed, z.velocity);
    }
    w.feed = std::max(w.feed, feed);
    w.acceleration = std::max(w.acceleration, lim.acceleration);
    w.deceleration = std::max(w.deceleration, lim.deceleration);
    w.jerk = std::max(w.jerk, lim.jerk);
  }
  return w;
}

LocalLimits widest(const Path& path, const std::vector<TimedSample>& samples, const std::vector<LocalLimits>& lim,
                   std::size_t k0, std::size_t k1, const std::vector<HandoverZone>& zones) {
  LocalLimits w = widest(lim, k0, k1);
  const LocalLimits between = limits_between(path, samples[k0].s, samples[k1].s, zones);
  w.feed = std::max(w.feed, between.feed);
  w.acceleration = std::max(w.acceleration, between.acceleration);
  w.deceleration = std::max(w.deceleration, between.deceleration);
  w.jerk = std::max(w.jerk, between.jerk);
  return w;
}

LocalLimits limits_at(const Path& path, double s, const std::vector<HandoverZone>& zones) {
  LocalLimits out;
  const auto& pieces = path.pieces();
  path.for_pieces_at(s, [&](std::size_t k, double local) {
    const PathPiece& p = pieces[k];
    const double kappa = curvature_vector(p.segment, local).norm();
    const double c = sharpness(p.segment, local);
    const double feed = feed_at(path, zones, k, local);
    out.v_lim = std::min(out.v_lim, std::min(feed, curvature_speed_limit(kappa, c, p.limits.acceleration, p.limits.jerk)));
    if (kappa > out.kappa) {
      out.kappa = kappa;
      out.a_normal = p.limits.acceleration;
    }
    const double eq24 = std::hypot(c, kappa * kappa);
    if (eq24 / p.limits.jerk > out.eq24_factor / out.eq24_jerk) {
      out.eq24_factor = eq24;
      out.eq24_jerk = p.limits.jerk;
    }
    out.acceleration = std::max(out.acceleration, p.limits.acceleration);
    out.deceleration = std::max(out.deceleration, p.limits.deceleration);
    out.jerk = std::max(out.jerk, p.limits.jerk);
    out.feed = std::max(out.feed, feed);
  });
  return out;
}

ProfileMargins profile_margins(const Path& path, const Timing& timing, const std::vector<HandoverZone>& zones) {
  std::vector<LocalLimits> lim(timing.samples.size());
  for (std::size_t k = 0; k < lim.size(); ++k) lim[k] = limits_at(path, timing.samples[k].s, zones);
  return profile_margins(path, timing, lim);
}

ProfileMargins profile_margins(const Path& path, const Timing& timing, const std::vector<LocalLimits>& lim) {
  ProfileMargins m;
  const auto& x = timing.samples;
  const double dt = timing.dt;
  std::vector<Vec3> p(x.size());
  // path-level terms at every sample
  for (std::size_t k = 0; k < x.size(); ++k) {
    const TimedSample& q = x[k];
    p[k] = path.point(q.s);
    const LocalLimits& l = lim[k];
    m.velocity = std::max(m.velocity, q.v / l.v_lim);
    m.tangential_acceleration =
        std::max(m.tangential_acceleration, q.a >= 0 ? q.a / l.acceleration : -q.a / l.deceleration);
    m.tangential_jerk = std::max(m.tangential_jerk, std::abs(q.j) / l.jerk);
    m.normal_acceleration = std::max(m.normal_acceleration, l.kappa * q.v * q.v / l.a_normal);
    m.eq24_jerk = std::max(m.eq24_jerk, l.eq24_factor * q.v * q.v * q.v / l.eq24_jerk);
  }
  // axis terms: centred differences of the sampled positions
  for (std::size_t k = 1; k + 1 < x.size(); ++k) {
    const Vec3 a = (p[k + 1] - 2 * p[k] + p[k - 1]) / (dt * dt);
    m.axis_acceleration = std::max(m.axis_acceleration, a.cwiseAbs().maxCoeff() / widest(path, x, lim, k - 1, k + 1).acceleration);
  }
  for (std::size_t k = 1; k + 2 < x.size(); ++k) {
    const Vec3 j = (p[k + 2] - 3 * p[k + 1] + 3 * p[k] - p[k - 1]) / (dt * dt * dt);
    const double ratio = j.cwiseAbs().maxCoeff() / widest(path, x, lim, k - 1, k + 2).jerk;
    if (ratio > 1 + kAxisSlack) m.axis_jerk_over_time += dt;
    if (ratio > m.axis_jerk) {
      m.axis_jerk = ratio;
      m.axis_jerk_time = 0.5 * (x[k].t + x[k + 1].t);
      m.axis_jerk_s = 0.5 * (x[k].s + x[k + 1].s);
    }
  }
  return m;
}

}  // namespace blendbench
