// The biclothoid curve itself (seed 004 def. 2, eq. 7-14): construction from a start posture and a
// turn, its end point with the derivatives Algorithm 1 needs, postures along it, and its
// clothoid segments in 3D.

#include "blendbench/corner/biclothoid.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Core>

#include "biclothoid_internal.hpp"
#include "blendbench/geometry/phase_series.hpp"
#include "blendbench/geometry/segment.hpp"

namespace blendbench {
using namespace biclothoid_detail;  // the helpers private to the biclothoid sources
namespace {

// clothoid_moments: largest phase excursion on a panel (rad).
constexpr double kMomentPanelPhase = 2.0;

// The first three moments of a clothoid's unit tangent about its start (derived here;
// clothoid_xy sums only the zeroth): with T(u) = exp(i theta(u)),
// theta(u) = theta0 + kappa0 u + c u^2 / 2,
//   M_k = int_0^len u^k T(u) du   (k = 0, 1, 2; M_0 is the displacement).
// On panels of half-width h about midpoints m as in clothoid_xy, but with the local phase
// below 2 rad (half as many panels; the terms below decay like 2^n / n!, so summing them loses
// at most a factor e^2 in rounding, about 1e-15 relative),
// T(m + h tau) = R sum_n e_n tau^n with R = exp(i theta(m)), e_0 = 1 and
// e_{n+1} = i (beta e_n + gamma e_{n-1}) / (n + 1), beta = kappa(m) h, gamma = c h^2. Since
// int_{-1}^{1} tau^j dtau is 2 / (j + 1) for even j and 0 for odd j, with
//   S_0 = sum_{n even} e_n / (n + 1),  S_1 = sum_{n odd} e_n / (n + 2),  S_2 = sum_{n even} e_n / (n + 3)
// and (m + h tau)^k expanded, a panel adds
//   M_0 += 2 h R S_0,   M_1 += 2 h R (m S_0 + h S_1),   M_2 += 2 h R (m^2 S_0 + 2 m h S_1 + h^2 S_2).
// The series stop as clothoid_xy's (two successive terms below 1e-18 of a sum near 1: from
// there on n + 1 > |beta| + |gamma| and the terms keep falling).
struct ClothoidMoments {
  Vec2 m0 = Vec2::Zero();  // m
  Vec2 m1 = Vec2::Zero();  // m^2
  Vec2 m2 = Vec2::Zero();  // m^3
  Vec2 t_end = Vec2::Zero();  // the unit tangent at len
};

// One panel's series in its own frame (beta, gamma as above): the even and odd parts of
// P(+-1), P(tau) = sum e_n tau^n, and S_0, S_1, S_2. T is double for one panel, or a 2-array for
// two side by side (series::BasicPhaseTaylor): the recurrence is a chain of dependent
// multiplications, so a fillet's two clothoids sum theirs together (panel_series_pair).
template <class T>
struct BasicPanelSeries {
  series::BasicPhaseTaylor<T> e;
  T er = series::filled<T>(1);  // sum of e_n, n even
  T ei = series::filled<T>(0);
  T or_ = series::filled<T>(0);  // n odd
  T oi = series::filled<T>(0);
  T s0r = series::filled<T>(1);
  T s0i = series::filled<T>(0);
  T s1r = series::filled<T>(0);
  T s1i = series::filled<T>(0);
  T s2r = series::filled<T>(series::kInverse[3]);
  T s2i = series::filled<T>(0);

  BasicPanelSeries(const T& beta, const T& gamma) : e{.b = beta, .g = gamma} {}

  // the terms n + 1 and n + 2
  void step(std::size_t n) noexcept {
    e.step_two(n);
    er += e.re;
    ei += e.im;
    or_ += e.prev_re;
    oi += e.prev_im;
    s0r += e.re * series::kInverse[n + 3];
    s0i += e.im * series::kInverse[n + 3];
    s1r += e.prev_re * series::kInverse[n + 3];
    s1i += e.prev_im * series::kInverse[n + 3];
    s2r += e.re * series::kInverse[n + 5];
    s2i += e.im * series::kInverse[n + 5];
  }
  static constexpr bool more(std::size_t n) { return n + 5 < series::kInverse.size(); }
  // the series stop once two successive terms are below 1e-18 (lane by lane)
  [[nodiscard]] T size() const noexcept { return e.size(); }
};
using PanelSeries = BasicPanelSeries<double>;

// the terms from n + 1 on, to the stop
void finish(PanelSeries& p, std::size_t n) noexcept {
  for (; PanelSeries::more(n); n += 2) {
    p.step(n);
    if (p.size() < 1e-18) return;
  }
}

// Two panels' series side by side, one in each lane of 2-arrays (a packed register each), in
// the registers one takes. A lane that stops leaves the other to go on alone: the same sums, to
// the last bit, as each panel on its own.
void panel_series_pair(PanelSeries& a, PanelSeries& b) noexcept {
  using Pair = Eigen::Array2d;
  BasicPanelSeries<Pair> both(Pair(a.e.b, b.e.b), Pair(a.e.g, b.e.g));
  // lane k back into its series
  const auto lane = [&](PanelSeries& out, Eigen::Index k) {
    out.e = series::lane(both.e, k);
    out.er = both.er[k];
    out.ei = both.ei[k];
    out.or_ = both.or_[k];
    out.oi = both.oi[k];
    out.s0r = both.s0r[k];
    out.s0i = both.s0i[k];
    out.s1r = both.s1r[k];
    out.s1i = both.s1i[k];
    out.s2r = both.s2r[k];
    out.s2i = both.s2i[k];
  };
  for (std::size_t n = 0; PanelSeries::more(n); n += 2) {
    both.step(n);
    const Pair size = both.size();
    const bool a_done = size[0] < 1e-18;
    const bool b_done = size[1] < 1e-18;
    if (a_done || b_done) {
      lane(a, 0);
      lane(b, 1);
      if (!a_done) finish(a, n + 2);
      if (!b_done) finish(b, n + 2);
      return;
    }
  }
  lane(a, 0);
  lane(b, 1);
}

// The moments of a clothoid, panel by panel (see clothoid_moments).
class MomentSum {
 public:
  MomentSum(const Vec2& t0, double kappa0, double c, double len) : kappa0_(kappa0), c_(c), tx_(t0.x()), ty_(t0.y()) {
    if (!(len > 0)) return;
    const double kappa_max = std::max(std::abs(kappa0), std::abs(kappa0 + c * len));
    const double phase = 0.5 * kappa_max * len + 0.125 * std::abs(c) * len * len;
    panels_ = std::max(1, static_cast<int>(std::ceil(phase / kMomentPanelPhase)));
    h_ = 0.5 * len / panels_;
  }
  [[nodiscard]] int panels() const { return panels_; }
  // panel j's series, not yet summed
  [[nodiscard]] PanelSeries series(int j) const { return {(kappa0_ + c_ * mid(j)) * h_, c_ * h_ * h_}; }
  // adds panel j (the next one) from its summed series
  void add(int j, const PanelSeries& p) {
    const double m = mid(j);
    const double h = h_;
    // the panel's moments in its frame, turned by theta(m); in scalars, as an Eigen 2-vector
    // built from two scalars and read back as a pair stalls store forwarding
    // R = T(m - h) / P(-1); T(m + h) = R P(1)
    const double pr = p.er - p.or_;
    const double pi = p.ei - p.oi;
    const double inv = 1 / (pr * pr + pi * pi);
    const double cs = (tx_ * pr + ty_ * pi) * inv;
    const double sn = (ty_ * pr - tx_ * pi) * inv;
    tx_ = cs * (p.er + p.or_) - sn * (p.ei + p.oi);
    ty_ = sn * (p.er + p.or_) + cs * (p.ei + p.oi);
    const double w = 2 * h;
    const double p0r = w * p.s0r;
    const double p0i = w * p.s0i;
    const double p1r = w * (m * p.s0r + h * p.s1r);
    const double p1i = w * (m * p.s0i + h * p.s1i);
    const double p2r = w * (m * m * p.s0r + 2 * m * h * p.s1r + h * h * p.s2r);
    const double p2i = w * (m * m * p.s0i + 2 * m * h * p.s1i + h * h * p.s2i);
    m0x_ += cs * p0r - sn * p0i;
    m0y_ += sn * p0r + cs * p0i;
    m1x_ += cs * p1r - sn * p1i;
    m1y_ += sn * p1r + cs * p1i;
    m2x_ += cs * p2r - sn * p2i;
    m2y_ += sn * p2r + cs * p2i;
  }
  // every panel, two at a time
  void add_all() {
    int j = 0;
    for (; j + 1 < panels_; j += 2) {
      PanelSeries a = series(j);
      PanelSeries b = series(j + 1);
      panel_series_pair(a, b);
      add(j, a);
      add(j + 1, b);
    }
    if (j < panels_) {
      PanelSeries a = series(j);
      finish(a, 0);
      add(j, a);
    }
  }
  [[nodiscard]] Vec2 tangent() const { return {tx_, ty_}; }
  // the second clothoid of a fillet starts with the first's end tangent
  void start_with(const Vec2& t0) {
    tx_ = t0.x();
    ty_ = t0.y();
  }
  [[nodiscard]] ClothoidMoments result() const {
    ClothoidMoments out;
    out.m0 = Vec2(m0x_, m0y_);
    out.m1 = Vec2(m1x_, m1y_);
    out.m2 = Vec2(m2x_, m2y_);
    out.t_end = Vec2(tx_, ty_);
    return out;
  }

 private:
  [[nodiscard]] double mid(int j) const { return h_ * (2 * j + 1); }
  double kappa0_;
  double c_;
  int panels_ = 0;
  double h_ = 0;
  double tx_;  // the unit tangent at the start of the next panel
  double ty_;
  double m0x_ = 0;
  double m0y_ = 0;
  double m1x_ = 0;
  double m1y_ = 0;
  double m2x_ = 0;
  double m2y_ = 0;
};

ClothoidMoments clothoid_moments(const Vec2& t0, double kappa0, double c, double len) {
  MomentSum sum(t0, kappa0, c, len);
  sum.add_all();
  return sum.result();
}

// Both clothoids of a fillet (kappa0 -> peak over s1 at slope c, back at -c over s2): as
// clothoid_moments on each, the second from the first's end tangent; where each is one panel
// (a fillet that turns by up to about pi), the two series side by side.
struct FilletMoments {
  ClothoidMoments first;
  ClothoidMoments second;
};
FilletMoments fillet_moments(const Vec2& t0, double kappa0, double c, double s1, double s2) {
  MomentSum first(t0, kappa0, c, s1);
  MomentSum second(Vec2::Zero(), kappa0 + c * s1, -c, s2);
  if (first.panels() == 1 && second.panels() == 1) {
    PanelSeries a = first.series(0);
    PanelSeries b = second.series(0);
    panel_series_pair(a, b);
    first.add(0, a);
    second.start_with(first.tangent());
    second.add(0, b);
  } else {
    first.add_all();
    second.start_with(first.tangent());
    second.add_all();
  }
  return {first.result(), second.result()};
}

// Derivation of eq. 11-13 in a form without the 0/0 of eq. 11 at kappa0 = kappa_e: with peak
// kappa_m, the tent profile gives kappa_m - kappa0 = c s1, kappa_m - kappa_e = c s2, and
// the turn is the area under it, 2 dtheta = (2 kappa_m^2 - kappa0^2 - kappa_e^2) / c with
// c = (2 kappa_m - kappa0 - kappa_e) / L. Eliminating c gives the quadratic
//   L kappa_m^2 - 2 dtheta kappa_m + dtheta (kappa0 + kappa_e) - L (kappa0^2 + kappa_e^2) / 2 = 0,
// kappa_m = (dtheta +- sqrt(SQ)) / L with SQ (seed 004, Shahzadeh et al.) = A^2 + B^2, A = dtheta - L kbar,
// B = L (kappa_e - kappa0) / 2, kbar = (kappa0 + kappa_e) / 2. The root with s1, s2 >= 0 is the
// one whose sign matches A: D = kappa_m - kbar = (A + sign(A) sqrt(SQ)) / L, c = 2 D / L,
// s1 = L (1 + B / (L D)) / 2. Eq. 11, which always takes -sqrt(SQ), is this root when A >= 0
// (the curvature peaks above both end values, as in seed 004's example); for A < 0 (a valley) eq. 11
// gives s1 outside [0, L] and the valid root has +sqrt(SQ).
struct TurnProfile {
  double c;   // 1/m^2
  double s1;  // m, in [0, L]
};
TurnProfile turn_profile(double kappa0, double kappa_e, double dtheta, double length) {
  const double kbar = 0.5 * (kappa0 + kappa_e);
  const double half_jump = 0.5 * (kappa_e - kappa0);
  const double a = dtheta - length * kbar;
  const double b = length * half_jump;
  const double root = std::sqrt(a * a + b * b);  // both terms are turns (rad): no overflow
  if (root == 0) return {0.0, 0.5 * length};
  const double d = (a >= 0 ? a + root : a - root) / length;
  return {2 * d / length, std::clamp(0.5 * length * (1 + half_jump / d), 0.0, length)};
}

}  // namespace

Biclothoid make_biclothoid(const Posture& start, double c, double s1, double s2) {
  Biclothoid curve;
  curve.start = start;
  curve.c = c;
  curve.s1 = s1;
  curve.s2 = s2;
  curve.mid.p = start.p + clothoid_displacement(start.theta, start.kappa, c, s1);
  curve.mid.kappa = start.kappa + c * s1;
  curve.mid.theta = start.theta + (start.kappa + 0.5 * c * s1) * s1;
  return curve;
}

std::optional<Biclothoid> biclothoid_from_turn(const Posture& start, double kappa_e, double dtheta, double length) {
  if (!(length > 0) || !std::isfinite(length)) return std::nullopt;
  const TurnProfile profile = turn_profile(start.kappa, kappa_e, dtheta, length);
  return make_biclothoid(start, profile.c, profile.s1, length - profile.s1);
}

// Derivatives of a point of the curve and of its end (derived here; seed 004 solves Algorithm 1
// without them). With c and s1 the tangent angle is
//   theta(s) = theta0 + kappa0 s + c s^2 / 2 - c (s - s1)_+^2
// (curvature kappa0 + c s up to s1, then falling with slope c). The length L and the turn
// dtheta fix c and s1 through the end curvature and the turn,
//   kappa0 + c (2 s1 - L) = kappa_e,   kappa0 L + c (2 s1 L - s1^2 - L^2 / 2) = dtheta.
// Differentiating both and eliminating w = c ds1 (regular as c -> 0, where s1 is not) leaves
//   dc = (d dtheta - kappa_m dL) / Q,   Q = (s1 - L/2)^2 + L^2/4 > 0,   w = (c dL - (2 s1 - L) dc) / 2,
// kappa_m = kappa0 + c s1 the peak. A point V(s) = p0 + int_0^s T(u) du, T = exp(i theta), at a
// fixed s moves by
//   dV(s) = i int_0^s (d theta(u)) T(u) du,   d theta(u) = (u^2/2 - (u - s1)_+^2) dc + 2 (u - s1)_+ w,
// which in the tangent moments A_k of the first clothoid (about the start, up to min(s, s1))
// and B_k of the second (about the peak, u = s1 + v, up to s - s1; zero when s <= s1) is
//   dV(s) = i [dc (A_2 / 2 + s1^2 B_0 / 2 + s1 B_1 - B_2 / 2) + 2 w B_1];
// the end p = V(L) moves by T(L) dL more, as L is its arc length.
namespace {

PointSlopes point_slopes(const Biclothoid& curve, const ClothoidMoments& first, const ClothoidMoments& second) {
  const double c = curve.c;
  const double s1 = curve.s1;
  const double len = curve.s1 + curve.s2;
  const Vec2 phi = 0.5 * first.m2 + 0.5 * s1 * s1 * second.m0 + s1 * second.m1 - 0.5 * second.m2;
  const double q = (s1 - 0.5 * len) * (s1 - 0.5 * len) + 0.25 * len * len;
  const auto moved = [&](double dc, double w) { return perp(dc * phi + 2 * w * second.m1); };
  const double dc_length = -curve.mid.kappa / q;
  const double dc_turn = 1 / q;
  return {moved(dc_length, 0.5 * (c - (2 * s1 - len) * dc_length)), moved(dc_turn, -0.5 * (2 * s1 - len) * dc_turn)};
}

}  // namespace

// point_slopes at arc length s in [0, L]; `offset` receives V(s) - p0.
PointSlopes biclothoid_detail::point_slopes_at(const Biclothoid& curve, double s, Vec2& offset) {
  s = std::clamp(s, 0.0, length(curve));
  const ClothoidMoments first =
      clothoid_moments(direction(curve.start.theta), curve.start.kappa, curve.c, std::min(s, curve.s1));
  const ClothoidMoments second =
      s > curve.s1 ? clothoid_moments(first.t_end, curve.mid.kappa, -curve.c, s - curve.s1) : ClothoidMoments{};
  offset = first.m0 + second.m0;
  return point_slopes(curve, first, second);
}

std::optional<BiclothoidEnd> biclothoid_end(const Posture& start, double kappa_e, double dtheta, double length) {
  return biclothoid_end(start, direction(start.theta), kappa_e, dtheta, length);
}

std::optional<BiclothoidEnd> biclothoid_end(const Posture& start, const Vec2& start_tangent, double kappa_e,
                                            double dtheta, double length) {
  if (!(length > 0) || !std::isfinite(length)) return std::nullopt;
  const TurnProfile profile = turn_profile(start.kappa, kappa_e, dtheta, length);
  const double c = profile.c;
  const double s1 = profile.s1;
  BiclothoidEnd out;
  Biclothoid& curve = out.curve;
  curve.start = start;
  curve.c = c;
  curve.s1 = s1;
  curve.s2 = length - s1;
  const FilletMoments moments = fillet_moments(start_tangent, start.kappa, c, s1, curve.s2);
  const ClothoidMoments& first = moments.first;
  const ClothoidMoments& second = moments.second;
  curve.mid.p = start.p + first.m0;
  curve.mid.kappa = start.kappa + c * s1;
  curve.mid.theta = start.theta + (start.kappa + 0.5 * c * s1) * s1;
  out.p = curve.mid.p + second.m0;
  out.tangent = second.t_end;
  const PointSlopes slopes = point_slopes(curve, first, second);
  out.d_length = out.tangent + slopes.d_length;
  out.d_turn = slopes.d_turn;
  out.kappa_e = kappa_e;
  out.turn = dtheta;
  out.peak_tangent = first.t_end;
  out.peak_moment = first.m2;
  return out;
}

// The peak point of the moved curve (derived here). With theta(u) = theta0 + kappa0 u + c u^2 / 2
// on the first clothoid, the new peak V'(s1 + ds1) under c -> c + dc is
//   V(s1) + int_0^s1 (T' - T) du + int_s1^(s1 + ds1) T' du,   T'(u) = T(u) exp(i dc u^2 / 2),
// and to second order in dc, third in ds1 (the peak slides along the old clothoid, whose
// tangent turns by kappa_m ds1 + c ds1^2 / 2), with A_2 = int_0^s1 u^2 T du, T = T(s1),
// kappa_m = kappa0 + c s1,
//   V' = V(s1) + i dc A_2 / 2 + T ds1 + i (dc s1^2 / 2 + kappa_m ds1 / 2 + c ds1^2 / 6) T ds1
//        - kappa_m^2 ds1^3 / 6 T;
// the terms left out are ~dc^2 s1^5 / 8, kappa^3 ds1^4 / 24 and dc s1 ds1^2 / 2, all below
// 2e-13 of the length within the bounds below (1e-13 from dc at 1e-6 / L^2).
std::optional<BiclothoidEnd> biclothoid_end_moved(const BiclothoidEnd& from, double length_step, double turn_step) {
  constexpr double kPeakStep = 1e-5;   // |ds1| / L
  constexpr double kShapeStep = 1e-6;  // |dc| L^2
  const Biclothoid& old = from.curve;
  const double len = length(old) + length_step;
  if (!(len > 0) || !std::isfinite(len)) return std::nullopt;
  const double turn = from.turn + turn_step;
  const TurnProfile profile = turn_profile(old.start.kappa, from.kappa_e, turn, len);
  const double dc = profile.c - old.c;
  const double ds1 = profile.s1 - old.s1;
  if (!(std::abs(ds1) <= kPeakStep * len) || !(std::abs(dc) * len * len <= kShapeStep)) return std::nullopt;
  BiclothoidEnd out = from;
  Biclothoid& curve = out.curve;
  const Posture& start = old.start;
  curve.c = profile.c;
  curve.s1 = profile.s1;
  curve.s2 = len - profile.s1;
  curve.mid.kappa = start.kappa + curve.c * curve.s1;
  curve.mid.theta = start.theta + (start.kappa + 0.5 * curve.c * curve.s1) * curve.s1;
  const Vec2& t = from.peak_tangent;
  const double s1 = old.s1;
  const double km = old.mid.kappa;
  curve.mid.p = old.mid.p + perp(0.5 * dc * from.peak_moment) +
                ds1 * ((1 - km * km * ds1 * ds1 / 6) * t +
                       (0.5 * dc * s1 * s1 + 0.5 * km * ds1 + old.c * ds1 * ds1 / 6) * perp(t));
  out.p = from.p + length_step * from.d_length + turn_step * from.d_turn;
  // the end tangent turned by turn_step (to second order: turn steps here are ~1e-7 rad)
  out.tangent = (1 - 0.5 * turn_step * turn_step) * from.tangent + turn_step * perp(from.tangent);
  out.turn = turn;
  return out;
}

double length(const Biclothoid& curve) { return curve.s1 + curve.s2; }

Posture posture_at(const Biclothoid& curve, double s) {
  s = std::clamp(s, 0.0, length(curve));
  if (s <= curve.s1) {
    const Posture& p0 = curve.start;
    return {p0.p + clothoid_displacement(p0.theta, p0.kappa, curve.c, s), p0.kappa + curve.c * s,
            p0.theta + (p0.kappa + 0.5 * curve.c * s) * s};
  }
  const double t = s - curve.s1;
  const Posture& pm = curve.mid;
  return {pm.p + clothoid_displacement(pm.theta, pm.kappa, -curve.c, t), pm.kappa - curve.c * t,
          pm.theta + (pm.kappa - 0.5 * curve.c * t) * t};
}

Posture end_posture(const Biclothoid& curve) { return posture_at(curve, length(curve)); }

Biclothoid reversed(const Biclothoid& curve) { return reversed(curve, end_posture(curve).p); }

Biclothoid reversed(const Biclothoid& curve, const Vec2& end) {
  // the two clothoids still meet at the curvature extremum: the reversed curve's mid is the
  // same point, so only the end is needed; its curvature and angle as make_biclothoid gives
  // them (the first clothoid's end, to the last bit)
  const double t = curve.s2;
  const Posture& pm = curve.mid;
  const Posture e{end, pm.kappa - curve.c * t, pm.theta + (pm.kappa - 0.5 * curve.c * t) * t};
  Biclothoid back;
  back.start = Posture{e.p, -e.kappa, e.theta + kPi};
  back.c = -curve.c;
  back.s1 = curve.s2;
  back.s2 = curve.s1;
  back.mid.p = curve.mid.p;
  back.mid.kappa = back.start.kappa + back.c * back.s1;
  back.mid.theta = back.start.theta + (back.start.kappa + 0.5 * back.c * back.s1) * back.s1;
  return back;
}

std::vector<Segment> to_segments(const Biclothoid& curve, const CornerPlane& plane) {
  std::vector<Segment> out;
  out.reserve(2);  // one allocation, not a second one and a move for the second piece
  const auto piece = [&](const Posture& at, double c, double len) {
    if (!(len > 0)) return;
    const double cs = std::cos(at.theta);
    const double sn = std::sin(at.theta);
    out.emplace_back(Clothoid{to_space(plane, at.p), cs * plane.x + sn * plane.y, -sn * plane.x + cs * plane.y,
                              at.kappa, c, len});
  };
  piece(curve.start, curve.c, curve.s1);
  piece(curve.mid, -curve.c, curve.s2);
  return out;
}

}  // namespace blendbench
