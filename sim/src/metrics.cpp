#include "blendbench/sim/metrics.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include "blendbench/geometry/closest.hpp"
#include "blendbench/sim/signal.hpp"

namespace blendbench {
namespace {

// Distance from a point to a chain of segments: the exact or refined closest point
// (closest_point) on every segment whose bounding sphere can hold a closer point than the best
// so far, so a long path costs a few closest-point searches per query, not one per segment. The
// search starts at the segment nearest to the previous query (a trace moves along the path), so
// `best` is small from the first segment on: on a CAM program of thousands of tiny fillets a
// search from the chain's start computed hundreds of closest points per query (2 minutes of
// metrics for 2000 lines); the result is the same minimum.
class ChainDistance {
 public:
  explicit ChainDistance(std::vector<Segment> segments) {
    for (Segment& seg : segments) {
      // bounding sphere: the centre of the samples' box, and every point of the curve lies
      // within half a sample spacing (in arc length, hence in space) of a sample
      constexpr int kSamples = 32;
      const double len = length(seg);
      Vec3 lo = point(seg, 0), hi = lo;
      std::vector<Vec3> pts;
      for (int i = 0; i <= kSamples; ++i) {
        pts.push_back(point(seg, len * i / kSamples));
        lo = lo.cwiseMin(pts.back());
        hi = hi.cwiseMax(pts.back());
      }
      const Vec3 centre = 0.5 * (lo + hi);
      double radius = 0;
      for (const Vec3& p : pts) radius = std::max(radius, (p - centre).norm());
      items_.push_back({std::move(seg), centre, radius + 0.5 * len / kSamples});
    }
  }

  [[nodiscard]] double operator()(const Vec3& p) const {
    if (items_.empty()) return std::numeric_limits<double>::infinity();
    double best = closest_point(items_[hint_].segment, p).distance;
    std::size_t nearest = hint_;
    for (std::size_t i = 0; i < items_.size(); ++i) {
      const Item& item = items_[i];
      if (i == hint_ || (p - item.centre).norm() - item.radius >= best) continue;
      const double d = closest_point(item.segment, p).distance;
      if (d < best) {
        best = d;
        nearest = i;
      }
    }
    hint_ = nearest;
    return best;
  }

 private:
  struct Item {
    Segment segment;
    Vec3 centre;
    double radius;
  };
  std::vector<Item> items_;
  mutable std::size_t hint_ = 0;  // the segment nearest to the last query
};

// Component c of a list of vectors.
std::vector<double> component(const std::vector<Vec3>& v, int c) {
  std::vector<double> out(v.size());
  for (std::size_t k = 0; k < v.size(); ++k) out[k] = v[k][c];
  return out;
}

// Peak and RMS of |x'''| by central third differences (x[k+2] - 2x[k+1] + 2x[k-1] - x[k-2]) /
// (2 dt^3) over samples k with t_k <= t_end; the magnitudes per sample go to `each` when given.
std::pair<double, double> jerk_peak_rms(const std::vector<Vec3>& x, const std::vector<double>& t, double t_end,
                                        double dt, std::vector<double>* each) {
  const std::size_t n = x.size();
  if (each != nullptr) each->assign(n, 0.0);
  double peak = 0, sum = 0;
  std::size_t count = 0;
  const double scale = 1 / (2 * dt * dt * dt);
  for (std::size_t k = 2; k + 2 < n; ++k) {
    const double j = ((x[k + 2] - 2 * x[k + 1] + 2 * x[k - 1] - x[k - 2]) * scale).norm();
    if (each != nullptr) (*each)[k] = j;
    if (t[k] > t_end) continue;
    peak = std::max(peak, j);
    sum += j * j;
    ++count;
  }
  return {peak, count > 0 ? std::sqrt(sum / static_cast<double>(count)) : 0.0};
}

// Residual vibration of the high-passed error in [t0, t1].
Vibration vibration_in(const std::vector<Vec3>& hp, const std::vector<double>& t, double t0, double t1, double fs,
                       double f_min) {
  Vibration v;
  v.t_start = t0;
  v.t_end = t1;
  std::array<std::vector<double>, 3> window;
  for (std::size_t k = 0; k < hp.size(); ++k) {
    if (t[k] < t0 - 1e-12 || t[k] > t1 + 1e-12) continue;
    for (int c = 0; c < 3; ++c) window[static_cast<std::size_t>(c)].push_back(hp[k][c]);
  }
  int axis = 0;
  for (int c = 0; c < 3; ++c) {
    const auto& w = window[static_cast<std::size_t>(c)];
    if (w.empty()) continue;
    const auto [lo, hi] = std::minmax_element(w.begin(), w.end());
    if (*hi - *lo > v.peak_to_peak) {
      v.peak_to_peak = *hi - *lo;
      axis = c;
    }
  }
  v.frequency = dominant_frequency(window[static_cast<std::size_t>(axis)], fs, f_min);
  return v;
}

}  // namespace

std::optional<ProcessMetrics> process_metrics(const std::vector<Vec3>& actual, const std::vector<double>& speed,
                                              const std::vector<double>& reference_s, const Path& path) {
  const std::size_t n = actual.size();
  if (n == 0 || speed.size() != n || reference_s.size() != n || path.pieces().empty()) return std::nullopt;
  // the window: from the end of the first move's last piece to the start of the last move's first
  const auto& pieces = path.pieces();
  int first_move = -1, last_move = -1;
  for (const PathPiece& p : pieces) {
    if (p.move < 0) continue;
    if (first_move < 0) first_move = p.move;
    last_move = p.move;
  }
  if (first_move < 0 || first_move == last_move) return std::nullopt;
  ProcessMetrics out;
  out.s_start = 0;
  out.s_end = path.length();
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    if (pieces[k].move == first_move) out.s_start = path.offset(k + 1);
  }
  for (std::size_t k = pieces.size(); k-- > 0;) {
    if (pieces[k].move == last_move) out.s_end = path.offset(k);
  }
  out.s_end = std::max(out.s_end, out.s_start);
  // the samples whose reference lies in the window; a window between two samples (an exact
  // stop's corner point passed between them) takes those two
  constexpr double kEps = 1e-12;  // m: rounding of the planned arc length
  std::size_t lo = n, hi = 0;
  for (std::size_t k = 0; k < n; ++k) {
    if (reference_s[k] >= out.s_start - kEps && reference_s[k] <= out.s_end + kEps) {
      lo = std::min(lo, k);
      hi = k;
    }
  }
  if (lo > hi) {
    std::size_t after = n - 1;
    for (std::size_t k = 0; k < n; ++k) {
      if (reference_s[k] > out.s_end) {
        after = k;
        break;
      }
    }
    lo = after > 0 ? after - 1 : 0;
    hi = after;
  }
  // the programmed speed of the piece the reference is on
  const auto programmed = [&](std::size_t k) { return pieces[path.locate(reference_s[k]).piece].limits.velocity; };
  double total = 0, below = 0;
  out.min_speed = speed[lo];
  for (std::size_t k = lo; k <= hi; ++k) {
    out.min_speed = std::min(out.min_speed, speed[k]);
    if (k == hi) break;
    const double step = (actual[k + 1] - actual[k]).norm();
    total += step;
    if (speed[k] < 0.9 * programmed(k)) below += step;
  }
  out.share_below_90pct_speed = total > 0 ? below / total : (speed[lo] < 0.9 * programmed(lo) ? 1.0 : 0.0);
  return out;
}

Metrics compute_metrics(const Trace& trace, const Program& program, const Path& path, const MetricsOptions& options) {
  assert(!trace.diverged);
  Metrics m;
  const std::size_t n = trace.samples.size();
  const double t_end = trace.reference_end;
  m.tracking_error.assign(n, 0.0);
  m.orientation_error.assign(n, 0.0);
  m.contour_error_programmed.assign(n, 0.0);
  m.contour_error_planned.assign(n, 0.0);
  m.tcp_speed.assign(n, 0.0);
  if (n == 0) return m;
  const double dt = trace.period > 0 ? trace.period : (n > 1 ? trace.samples[1].t - trace.samples[0].t : 1.0);
  const double fs = 1 / dt;

  // errors per sample; tracking and following error over the motion
  std::vector<Segment> programmed;
  for (const Move& move : program.moves) programmed.push_back(to_segment(move.geometry));
  std::vector<Segment> planned;
  for (const PathPiece& piece : path.pieces()) planned.push_back(piece.segment);
  const ChainDistance to_programmed(std::move(programmed));
  const ChainDistance to_planned(std::move(planned));
  std::vector<double> t(n);
  std::vector<Vec3> actual(n), commanded(n), error(n);
  double sum_sq = 0;
  double orientation_sq = 0;
  JointVector following_sq = JointVector::Zero(), torque_sq = JointVector::Zero();
  std::size_t motion = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const TraceSample& s = trace.samples[k];
    t[k] = s.t;
    actual[k] = s.tcp;
    commanded[k] = s.tcp_cmd;
    error[k] = s.tcp - s.tcp_cmd;
    m.tracking_error[k] = error[k].norm();
    m.orientation_error[k] = rotation_angle(s.rotation, s.rotation_cmd);
    m.contour_error_programmed[k] = program.moves.empty() ? 0.0 : to_programmed(s.tcp);
    m.contour_error_planned[k] = path.pieces().empty() ? 0.0 : to_planned(s.tcp);
    m.contour_error_programmed_max = std::max(m.contour_error_programmed_max, m.contour_error_programmed[k]);
    m.contour_error_planned_max = std::max(m.contour_error_planned_max, m.contour_error_planned[k]);
    m.torque_peak = m.torque_peak.cwiseMax(s.tau.cwiseAbs());
    torque_sq += s.tau.cwiseAbs2();
    m.energy += (s.tau.cwiseProduct(s.qd_motor)).cwiseAbs() * dt;
    m.velocity_peak = m.velocity_peak.cwiseMax(s.qd.cwiseAbs());
    if (k > 0) m.acceleration_peak = m.acceleration_peak.cwiseMax(((s.qd - trace.samples[k - 1].qd) / dt).cwiseAbs());
    if (s.t > t_end + 1e-12) continue;
    ++motion;
    m.tracking_error_max = std::max(m.tracking_error_max, m.tracking_error[k]);
    sum_sq += m.tracking_error[k] * m.tracking_error[k];
    m.orientation_error_max = std::max(m.orientation_error_max, m.orientation_error[k]);
    orientation_sq += m.orientation_error[k] * m.orientation_error[k];
    // the tool's angular velocity by central differences of its orientation
    if (k > 0 && k + 1 < n) {
      const TraceSample& a = trace.samples[k - 1];
      const TraceSample& b = trace.samples[k + 1];
      m.angular_velocity_peak = std::max(m.angular_velocity_peak, rotation_angle(a.rotation, b.rotation) / (b.t - a.t));
      m.angular_velocity_commanded_peak =
          std::max(m.angular_velocity_commanded_peak, rotation_angle(a.rotation_cmd, b.rotation_cmd) / (b.t - a.t));
    }
    m.following_error_max = m.following_error_max.cwiseMax(s.following_error.cwiseAbs());
    following_sq += s.following_error.cwiseAbs2();
  }
  if (motion > 0) {
    m.tracking_error_rms = std::sqrt(sum_sq / static_cast<double>(motion));
    m.orientation_error_rms = std::sqrt(orientation_sq / static_cast<double>(motion));
    m.following_error_rms = (following_sq / static_cast<double>(motion)).cwiseSqrt();
  }
  m.torque_rms = (torque_sq / static_cast<double>(n)).cwiseSqrt();

  // actual TCP speed (central differences) and settling: the first sample after the reference
  // ended from which every sample of the settle window is within both tolerances
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t a = k > 0 ? k - 1 : k, b = k + 1 < n ? k + 1 : k;
    if (b > a) m.tcp_speed[k] = (actual[b] - actual[a]).norm() / (t[b] - t[a]);
  }
  std::size_t run_start = n;  // first sample of the current run of settled samples
  for (std::size_t k = 0; k < n; ++k) {
    const bool settled = t[k] >= t_end - 1e-12 && (actual[k] - options.end_point).norm() <= options.settle_tolerance &&
                         m.tcp_speed[k] <= options.settle_speed_tolerance;
    if (!settled) {
      run_start = n;
      continue;
    }
    if (run_start == n) run_start = k;
    if (t[k] - t[run_start] >= options.settle_window - 1e-9) {
      m.cycle_time = t[run_start];
      break;
    }
  }

  // jerk of the commanded TCP as it is, of the actual TCP low-passed
  std::vector<Vec3> smooth(n);
  {
    std::array<std::vector<double>, 3> c;
    for (int i = 0; i < 3; ++i) c[static_cast<std::size_t>(i)] = lowpass_zero_phase(component(actual, i), fs, options.jerk_lowpass);
    for (std::size_t k = 0; k < n; ++k) smooth[k] = Vec3(c[0][k], c[1][k], c[2][k]);
  }
  std::tie(m.jerk_actual_peak, m.jerk_actual_rms) = jerk_peak_rms(smooth, t, t_end, dt, &m.jerk_actual);
  std::tie(m.jerk_commanded_peak, m.jerk_commanded_rms) = jerk_peak_rms(commanded, t, t_end, dt, nullptr);

  // residual vibration: the high-passed error after the final stop and after each corner
  {
    std::array<std::vector<double>, 3> c;
    for (int i = 0; i < 3; ++i) c[static_cast<std::size_t>(i)] = highpass_zero_phase(component(error, i), fs, options.vibration_highpass);
    m.vibration.resize(n);
    for (std::size_t k = 0; k < n; ++k) m.vibration[k] = Vec3(c[0][k], c[1][k], c[2][k]);
  }
  const double t_last = t.back();
  m.vibration_final = vibration_in(m.vibration, t, t_end, std::min(t_end + options.vibration_window, t_last), fs,
                                   options.vibration_highpass);
  for (std::size_t c = 0; c < options.corners.size(); ++c) {
    double t1 = std::min({options.corners[c].t_end + options.vibration_window, t_end, t_last});
    if (c + 1 < options.corners.size()) t1 = std::min(t1, options.corners[c + 1].t_start);
    m.vibration_corners.push_back(vibration_in(m.vibration, t, options.corners[c].t_end,
                                               std::max(t1, options.corners[c].t_end), fs, options.vibration_highpass));
  }
  if (!options.reference_s.empty()) m.process = process_metrics(actual, m.tcp_speed, options.reference_s, path);
  return m;
}

Health check_health(const Trace& trace, const JointTrajectory& reference, const JointLimits& limits) {
  Health h;
  const std::size_t n = trace.samples.size();
  h.saturated_ticks = trace.saturated_ticks;
  // a share of the servo ticks the drive ran (saturation is counted per servo tick; dividing by
  // the setpoint samples, four times fewer by default, gave shares up to 400 %)
  for (std::size_t i = 0; i < 6; ++i) {
    h.saturated = h.saturated || trace.saturated_ticks[i] > 0;
    if (trace.servo_ticks > 0) {
      h.saturated_share[static_cast<Eigen::Index>(i)] =
          static_cast<double>(trace.saturated_ticks[i]) / static_cast<double>(trace.servo_ticks);
    }
  }
  // the first sample exceeding a limit (a relative allowance for rounding)
  const auto check = [](LimitCheck& out, double t, const JointVector& value, const JointVector& limit) {
    if (out.exceeded) return;
    for (int i = 0; i < 6; ++i) {
      if (std::abs(value[i]) > limit[i] * (1 + 1e-9)) {
        out = {true, t, i, std::abs(value[i]), limit[i]};
        return;
      }
    }
  };
  for (std::size_t k = 0; k < reference.q.size(); ++k) {
    const double t = static_cast<double>(k) * reference.dt;
    if (k < reference.qd.size()) check(h.reference_velocity, t, reference.qd[k], limits.velocity);
    if (k < reference.qdd.size()) check(h.reference_acceleration, t, reference.qdd[k], limits.acceleration);
  }
  for (std::size_t k = 0; k < n; ++k) {
    const TraceSample& s = trace.samples[k];
    check(h.actual_velocity, s.t, s.qd, limits.velocity);
    if (k > 0) {
      const double dt = s.t - trace.samples[k - 1].t;
      check(h.actual_acceleration, s.t, (s.qd - trace.samples[k - 1].qd) / dt, limits.acceleration);
    }
  }
  return h;
}

}  // namespace blendbench
