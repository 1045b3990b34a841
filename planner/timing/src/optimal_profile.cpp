#include "optimal_profile.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "blendbench/corner/blend.hpp"
#include "blendbench/timing/cartesian.hpp"
#include "blendbench/timing/profile_margins.hpp"

namespace blendbench::timing_detail {
namespace {

const double kEpsilon = std::numeric_limits<double>::epsilon();
// Newton steps inverting a normal cell's time at a sample (quadratic convergence from the
// linear guess; bisection when a step leaves the bracket).
constexpr int kInversionSteps = 60;
// A kink: a tangent turning by more than this (rad) at a junction (path.hpp's kG1Angle).
constexpr double kKinkAngle = kG1Angle;
// A curvature step: |k_before - k_after| above this (1/m; intervals.cpp's rounding rule, here
// absolute: stencils across a smaller step are checked as any other).
constexpr double kStepRounding = 1e-9;

// Gauss-Legendre nodes and weights on [0, 1] for the time of a normal cell.
constexpr std::array<double, 8> kGaussNodes = {0.019855071751231856, 0.10166676129318664, 0.2372337950418355,
                                               0.40828267875217511, 0.59171732124782489, 0.7627662049581645,
                                               0.89833323870681336, 0.98014492824876811};
constexpr std::array<double, 8> kGaussWeights = {0.050614268145188129, 0.11119051722668724, 0.15685332293894364,
                                                 0.18134189168918100, 0.18134189168918100, 0.15685332293894364,
                                                 0.11119051722668724, 0.050614268145188129};

// The time from a normal cell's start to w (in [0, 1]); NaN where b is not positive on [0, w].
double time_to(const CellMotion& m, double w) {
  double total = 0;
  for (std::size_t q = 0; q < kGaussNodes.size(); ++q) {
    const double y = w * kGaussNodes[q];
    const double bb = m.shape.b(y, m.b0, m.a0, m.a1);
    if (!(bb > 0)) return std::numeric_limits<double>::quiet_NaN();
    total += kGaussWeights[q] * m.shape.stretch(y) / std::sqrt(bb);
  }
  return w * total;
}

// The w a normal cell reaches tau after its start (Newton on the increasing t(w), bisection as
// the safeguard).
double w_at(const CellMotion& m, double tau) {
  if (tau <= 0) return 0;
  if (tau >= m.duration) return 1;
  double lo = 0;
  double hi = 1;
  double w = tau / m.duration;
  for (int k = 0; k < kInversionSteps; ++k) {
    const double t = time_to(m, w);
    (t < tau ? lo : hi) = w;
    double next = w - (t - tau) * std::sqrt(std::max(m.shape.b(w, m.b0, m.a0, m.a1), 0.0)) / m.shape.stretch(w);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - w) <= 2 * kEpsilon) return next;
    w = next;
  }
  return w;
}

// The limits and frame of the pieces touching arc length s, for the analytic checks: the ratio
// of each quantity is the smallest over those pieces (a sample on a junction belongs to the
// phase of one of them).
struct Ratios {
  double velocity = 0, acceleration = 0, jerk = 0, rotation_velocity = 0, rotation_acceleration = 0,
         rotation_jerk = 0;
};

Ratios ratios_on(const Path& path, const TimingOptions& options, const std::vector<HandoverZone>& zones, std::size_t k,
                 double local, const TimedSample& x) {
  const PathPiece& piece = path.pieces()[k];
  const Limits& lim = piece.limits;
  Ratios r;
  const double feed = feed_at(path, zones, k, local);
  r.velocity = x.v / feed;
  const SegmentFrame f = frame(piece.segment, local);
  if (options.limits == LimitsMode::kCartesian) {
    const Vec3 acc = tcp_acceleration(x.v, x.a, f.tangent, f.curvature);
    const Vec3 jerk = tcp_jerk(x.v, x.a, x.j, f.tangent, f.curvature, f.curvature_derivative);
    const double a_lim = x.a > 0 ? lim.acceleration : x.a < 0 ? lim.deceleration : std::min(lim.acceleration, lim.deceleration);
    r.acceleration = acc.norm() / a_lim;
    r.jerk = jerk.norm() / lim.jerk;
    if (options.axis_limits) {
      r.acceleration = std::max(r.acceleration, acc.cwiseAbs().cwiseQuotient(options.axis_limits->acceleration).maxCoeff());
      r.jerk = std::max(r.jerk, jerk.cwiseAbs().cwiseQuotient(options.axis_limits->jerk).maxCoeff());
    }
  } else {
    const double kappa = f.curvature.norm();
    const double c = sharpness(piece.segment, local);
    r.velocity = std::max(r.velocity, x.v / curvature_speed_limit(kappa, c, lim.acceleration, lim.jerk));
    r.acceleration = std::max(x.a >= 0 ? x.a / lim.acceleration : -x.a / lim.deceleration, kappa * x.v * x.v / lim.acceleration);
    r.jerk = std::abs(x.j) / lim.jerk;
  }
  if (piece.orientation) {
    const SideRotation jet = rotation_jet(*piece.orientation, length(piece.segment), local);
    const AngularLimits& ang = piece.orientation->limits;
    r.rotation_velocity = (jet.rate * x.v).norm() / ang.velocity;
    r.rotation_acceleration = (jet.rate * x.a + jet.d1 * x.v * x.v).norm() / ang.acceleration;
    r.rotation_jerk = (jet.rate * x.j + 3 * jet.d1 * x.v * x.a + jet.d2 * x.v * x.v * x.v).norm() / ang.jerk;
  }
  return r;
}

}  // namespace

CellState cell_state(const CellMotion& cell, double tau) {
  tau = std::clamp(tau, 0.0, cell.duration);
  switch (cell.kind) {
    case CellMotion::Kind::kFromRest:
      return {cell.c * tau * tau * tau, 3 * cell.c * tau * tau, 6 * cell.c * tau, 6 * cell.c};
    case CellMotion::Kind::kToRest: {
      const double r = cell.duration - tau;
      return {cell.length - cell.c * r * r * r, 3 * cell.c * r * r, -6 * cell.c * r, 6 * cell.c};
    }
    case CellMotion::Kind::kNormal:
      break;
  }
  const double w = w_at(cell, tau);
  const double v = std::sqrt(std::max(cell.shape.b(w, cell.b0, cell.a0, cell.a1), 0.0));
  const double slope = (cell.a1 - cell.a0) / cell.shape.stretch(w);  // da/ds
  return {cell.shape.position(w), v, cell.a0 + (cell.a1 - cell.a0) * w, slope * v};
}

bool make_motion(const Grid& grid, std::size_t first, std::size_t last, const std::vector<double>& b,
                 const std::vector<double>& a, const std::vector<double>& b_lin, const std::vector<double>& a_lin,
                 std::vector<CellMotion>& cells) {
  cells.clear();
  cells.reserve(last - first);
  double t = 0;
  for (std::size_t i = first; i < last; ++i) {
    const GridNode& n0 = grid.nodes[i];
    const GridNode& n1 = grid.nodes[i + 1];
    CellMotion m;
    m.s0 = n0.s;
    m.length = n1.s - n0.s;
    m.t0 = t;
    if (n0.rest && n1.rest) {
      // two rests closer than the grid resolves (a zero-length stretch): no motion
      m.kind = CellMotion::Kind::kFromRest;
      m.duration = 0;
    } else if (n0.rest || n1.rest) {
      // s = c tau^3 over the cell: duration 3 h / sqrt(b) at its moving end
      const double bb = n0.rest ? b[i + 1] : b[i];
      m.kind = n0.rest ? CellMotion::Kind::kFromRest : CellMotion::Kind::kToRest;
      if (!(bb > 0)) return false;
      m.duration = 3 * m.length / std::sqrt(bb);
      m.c = m.length / (m.duration * m.duration * m.duration);
    } else {
      m.shape = CellShape(m.length, std::sqrt(b_lin[i]), std::sqrt(b_lin[i + 1]), a_lin[i]);
      m.b0 = b[i];
      m.a0 = a[i];
      m.a1 = a[i + 1];
      m.duration = time_to(m, 1.0);
      if (!(m.duration > 0) || !std::isfinite(m.duration)) return false;
    }
    t += m.duration;
    cells.push_back(m);
  }
  return true;
}

std::vector<TimedSample> sample_motion(const std::vector<CellMotion>& cells, double path_length, double dt) {
  const double total = cells.empty() ? 0.0 : cells.back().t0 + cells.back().duration;
  const auto n = static_cast<std::size_t>(std::ceil(total / dt));
  std::vector<TimedSample> samples;
  samples.reserve(n + 1);
  std::size_t i = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) * dt;
    while (i + 1 < cells.size() && t >= cells[i + 1].t0) ++i;
    const CellMotion& m = cells[i];
    const CellState x = cell_state(m, t - m.t0);
    // clamped into the cell so rounding never breaks monotonicity
    samples.push_back({t, std::clamp(m.s0 + x.x, m.s0, m.s0 + m.length), x.v, x.a, x.j});
  }
  samples.push_back({static_cast<double>(n) * dt, path_length, 0.0, 0.0, 0.0});
  return samples;
}

namespace {

double gamma_for(double velocity, double acceleration, double jerk) {
  double gamma = 1;
  if (velocity > 1) gamma = std::min(gamma, 1 / velocity);
  if (acceleration > 1) gamma = std::min(gamma, 1 / std::sqrt(acceleration));
  if (jerk > 1) gamma = std::min(gamma, 1 / std::sqrt(jerk));
  return gamma;
}

}  // namespace

double ProfileCheck::scale() const { return gamma_for(velocity, acceleration, jerk); }

double ProfileCheck::scale(std::size_t k0, std::size_t k1) const {
  double v = 0, a = 0, j = 0;
  for (std::size_t k = k0; k <= k1 && k < velocity_ratio.size(); ++k) {
    v = std::max(v, velocity_ratio[k]);
    a = std::max(a, acceleration_any[k]);
    j = std::max(j, jerk_any[k]);
  }
  return gamma_for(v, a, j);
}

namespace {
// A first difference's ratio to the feed, on both samples of its period.
void note_velocity(ProfileCheck& out, std::size_t k, double ratio) {
  out.velocity = std::max(out.velocity, ratio);
  for (const std::size_t q : {k, k + 1}) {
    out.velocity_ratio[q] = std::max(out.velocity_ratio[q], ratio);
    out.worst[q] = std::max(out.worst[q], ratio);
  }
}
}  // namespace

ProfileCheck check_samples(const Path& path, const TimingOptions& options, const Prepared& prepared,
                           const std::vector<TimedSample>& x) {
  ProfileCheck out;
  const std::size_t n = x.size();
  out.worst.assign(n, 0.0);
  out.velocity_ratio.assign(n, 0.0);
  out.acceleration_any.assign(n, 0.0);
  out.jerk_any.assign(n, 0.0);
  out.acceleration_ratio.assign(n, 0.0);
  out.jerk_ratio.assign(n, 0.0);
  out.rotation_ratio.assign(n, 0.0);
  const auto& pieces = path.pieces();
  const std::vector<HandoverZone>& zones = prepared.zones;
  const bool cartesian = options.limits == LimitsMode::kCartesian;

  // the analytic ratios at every sample
  std::vector<Vec3> p(n);
  std::vector<LocalLimits> lim(n);
  for (std::size_t k = 0; k < n; ++k) {
    const TimedSample& q = x[k];
    p[k] = path.point(q.s);
    lim[k] = limits_at(path, q.s, zones);
    Ratios best;
    bool first = true;
    path.for_pieces_at(q.s, [&](std::size_t piece, double local) {
      const Ratios r = ratios_on(path, options, zones, piece, local, q);
      if (first) {
        best = r;
        first = false;
        return;
      }
      best.velocity = std::min(best.velocity, r.velocity);
      best.acceleration = std::min(best.acceleration, r.acceleration);
      best.jerk = std::min(best.jerk, r.jerk);
      best.rotation_velocity = std::min(best.rotation_velocity, r.rotation_velocity);
      best.rotation_acceleration = std::min(best.rotation_acceleration, r.rotation_acceleration);
      best.rotation_jerk = std::min(best.rotation_jerk, r.rotation_jerk);
    });
    out.velocity = std::max({out.velocity, best.velocity, best.rotation_velocity});
    out.acceleration = std::max({out.acceleration, best.acceleration, best.rotation_acceleration});
    out.jerk = std::max({out.jerk, best.jerk, best.rotation_jerk});
    out.acceleration_ratio[k] = best.acceleration;
    out.jerk_ratio[k] = best.jerk;
    out.velocity_ratio[k] = std::max(best.velocity, best.rotation_velocity);
    out.acceleration_any[k] = std::max(best.acceleration, best.rotation_acceleration);
    out.jerk_any[k] = std::max(best.jerk, best.rotation_jerk);
    out.rotation_ratio[k] = std::max({best.rotation_velocity, best.rotation_acceleration, best.rotation_jerk});
    out.worst[k] = std::max({best.velocity, best.acceleration, best.jerk, out.rotation_ratio[k]});
  }
  if (n < 4) return out;

  // the finite differences, with the noise of the sampled positions (as the tests allow it)
  const double dt = x.front().t == 0 && n > 1 ? x[1].t - x[0].t : options.dt;
  if (cartesian) {
    // junctions whose stencils are skipped: kinks (velocity steps) for both, and curvature steps
    // that are allowed (reported) for the third differences
    std::vector<std::pair<double, bool>> steps;  // s, and whether only the jerk stencils skip it
    for (std::size_t i = 1; i < pieces.size(); ++i) {
      const Segment& sa = pieces[i - 1].segment;
      const Segment& sb = pieces[i].segment;
      if (length(sb) <= 0) continue;
      const bool kink = angle_between(tangent(sa, length(sa)), tangent(sb, 0.0)) > kKinkAngle;
      const bool allowed = pieces[i].curvature_step_allowed &&
                           (curvature_vector(sa, length(sa)) - curvature_vector(sb, 0.0)).norm() > kStepRounding;
      if (kink || allowed) steps.emplace_back(path.offset(i), !kink);
    }
    const auto crosses = [&](std::size_t k0, std::size_t k1, bool jerk) {
      const auto it = std::lower_bound(steps.begin(), steps.end(), std::pair{x[k0].s, false},
                                       [](const auto& a, const auto& b) { return a.first < b.first; });
      for (auto s = it; s != steps.end() && s->first <= x[k1].s; ++s) {
        if (jerk || !s->second) return true;
      }
      return false;
    };
    double size = 0;
    for (const Vec3& q : p) size = std::max(size, q.cwiseAbs().maxCoeff());
    const double noise = 8 * kEpsilon * (size + path.length());
    const Vec3 axis_a = options.axis_limits ? options.axis_limits->acceleration : Vec3::Constant(kInf);
    const Vec3 axis_j = options.axis_limits ? options.axis_limits->jerk : Vec3::Constant(kInf);
    // the mean speed over each period (a chord: never more than the arc's mean speed)
    for (std::size_t k = 0; k + 1 < n; ++k) {
      const double ratio = ((p[k + 1] - p[k]).norm() / dt - 2 * noise / dt) / widest(path, x, lim, k, k + 1, zones).feed;
      note_velocity(out, k, ratio);
    }
    for (std::size_t k = 1; k + 1 < n; ++k) {
      if (crosses(k - 1, k + 1, false)) continue;
      const Vec3 acc = (p[k + 1] - 2 * p[k] + p[k - 1]) / (dt * dt);
      const LocalLimits w = widest(path, x, lim, k - 1, k + 1, zones);
      const double slack = 4 * noise / (dt * dt);
      const double ratio = std::max((acc.norm() - slack) / std::max(w.acceleration, w.deceleration),
                                    (acc.cwiseAbs() - Vec3::Constant(slack)).cwiseQuotient(axis_a).maxCoeff());
      out.acceleration = std::max(out.acceleration, ratio);
      out.worst[k] = std::max(out.worst[k], ratio);
      for (std::size_t q = k - 1; q <= k + 1; ++q) out.acceleration_any[q] = std::max(out.acceleration_any[q], ratio);
    }
    for (std::size_t k = 1; k + 2 < n; ++k) {
      if (crosses(k - 1, k + 2, true)) continue;
      const Vec3 jerk = (p[k + 2] - 3 * p[k + 1] + 3 * p[k] - p[k - 1]) / (dt * dt * dt);
      const double slack = 8 * noise / (dt * dt * dt);
      const double ratio = std::max((jerk.norm() - slack) / widest(path, x, lim, k - 1, k + 2, zones).jerk,
                                    (jerk.cwiseAbs() - Vec3::Constant(slack)).cwiseQuotient(axis_j).maxCoeff());
      out.jerk = std::max(out.jerk, ratio);
      out.worst[k] = std::max(out.worst[k], ratio);
      out.worst[k + 1] = std::max(out.worst[k + 1], ratio);
      for (std::size_t q = k - 1; q <= k + 2; ++q) out.jerk_any[q] = std::max(out.jerk_any[q], ratio);
    }
    return out;
  }
  // path mode: differences of s
  double v_top = 0;
  for (const PathPiece& piece : pieces) v_top = std::max(v_top, piece.limits.velocity);
  for (const HandoverZone& z : zones) v_top = std::max(v_top, z.velocity);
  const double total = x.back().t;
  const double noise = 4 * kEpsilon * std::max(path.length() + v_top * total, 1e-300);
  // the mean speed over each period: between two samples below the feed the motion can bulge
  // above it (seen by 2 ppm on a random path, the tests' first differences)
  for (std::size_t k = 0; k + 1 < n; ++k) {
    const double ratio = ((x[k + 1].s - x[k].s) / dt - 2 * noise / dt) / widest(path, x, lim, k, k + 1, zones).feed;
    note_velocity(out, k, ratio);
  }
  for (std::size_t k = 1; k + 1 < n; ++k) {
    const double acc = (x[k + 1].s - 2 * x[k].s + x[k - 1].s) / (dt * dt);
    const LocalLimits w = widest(path, x, lim, k - 1, k + 1, zones);
    const double slack = 4 * noise / (dt * dt);
    const double ratio = acc >= 0 ? (acc - slack) / w.acceleration : (-acc - slack) / w.deceleration;
    out.acceleration = std::max(out.acceleration, ratio);
    out.worst[k] = std::max(out.worst[k], ratio);
    for (std::size_t q = k - 1; q <= k + 1; ++q) out.acceleration_any[q] = std::max(out.acceleration_any[q], ratio);
  }
  for (std::size_t k = 1; k + 2 < n; ++k) {
    const double jerk = (x[k + 2].s - 3 * x[k + 1].s + 3 * x[k].s - x[k - 1].s) / (dt * dt * dt);
    const double ratio = (std::abs(jerk) - 8 * noise / (dt * dt * dt)) / widest(path, x, lim, k - 1, k + 2, zones).jerk;
    out.jerk = std::max(out.jerk, ratio);
    out.worst[k] = std::max(out.worst[k], ratio);
    for (std::size_t q = k - 1; q <= k + 2; ++q) out.jerk_any[q] = std::max(out.jerk_any[q], ratio);
  }
  return out;
}

}  // namespace blendbench::timing_detail
