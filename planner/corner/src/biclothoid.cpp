#include "blendbench/corner/biclothoid.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "blendbench/core/format.hpp"
#include "blendbench/corner/clothoid_blend.hpp"
#include "blendbench/core/input_error.hpp"
#include "blendbench/geometry/segment.hpp"
#include "blendbench/geometry/phase_series.hpp"

namespace blendbench {
namespace {

constexpr double kPi = std::numbers::pi;
// Tangent angle (rad) below which a corner is G1 (as in blend.cpp), and how close to pi a
// turn must be to count as a reversal.
constexpr double kTangentAngle = 1e-9;
constexpr double kReversalAngle = 1e-9;
// Largest out-of-plane angle (rad) of a line or arc normal for a corner to count as planar.
constexpr double kPlanarAngle = 1e-10;
// Shortest chord (start to end) of a fillet accepted, relative to a + b: near a reversal of
// 179.999 deg a fillet's chord is 8.7e-6 (a + b); where q1 and q2 cross just after the corner
// the equations also admit vanishing hairpins with start = end, which are no fillets.
constexpr double kMinChordRatio = 1e-6;
// How close to a point where the moves cross again a fillet may start or end (fraction of the
// distance from the corner).
constexpr double kCrossingMargin = 0.98;
// Algorithm 1 stops when the end misses q2 by less than this fraction of a + b (the blender's
// continuity needs 1e-9).
constexpr double kSolveTolerance = 1e-13;
// Algorithm 2 stops once tolerance (1 - kReached) <= deviation <= tolerance (log scale).
constexpr double kReached = 1e-4;
// The most of an arc a fillet replaces (rad of the arc's turn).
constexpr double kMaxArcTurn = 0.25 * std::numbers::pi;

double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }
Vec2 direction(double theta) { return {std::cos(theta), std::sin(theta)}; }

// sin(x) / x, exact to rounding near 0
double sinc(double x) {
  if (std::abs(x) < 1e-4) return 1.0 - x * x / 6.0;
  return std::sin(x) / x;
}

// Illinois false position for a root of f on [x0, x1] where f(x0) and f(x1) differ in sign.
// Stops when |f| <= f_tol, the bracket is narrower than x_tol, or after max_it evaluations.
// Returns the final bracket, each end with its function value, so a caller can choose the
// side it needs.
struct Bracket {
  double x0, f0, x1, f1;
};
template <class F>
Bracket illinois(const F& f, Bracket br, double x_tol, double f_tol, int max_it) {
  int side = 0;
  for (int it = 0; it < max_it; ++it) {
    if (std::abs(br.x1 - br.x0) <= x_tol) break;
    double x = (br.x0 * br.f1 - br.x1 * br.f0) / (br.f1 - br.f0);
    // keep the trial strictly inside, else bisect
    const double lo = std::min(br.x0, br.x1);
    const double hi = std::max(br.x0, br.x1);
    if (!(x > lo && x < hi)) x = 0.5 * (br.x0 + br.x1);
    const double fx = f(x);
    if (!std::isfinite(fx)) break;
    if ((fx > 0) == (br.f1 > 0)) {
      br.x1 = x;
      br.f1 = fx;
      if (side == 1) br.f0 *= 0.5;
      side = 1;
    } else {
      br.x0 = x;
      br.f0 = fx;
      if (side == -1) br.f1 *= 0.5;
      side = -1;
    }
    if (std::abs(fx) <= f_tol) break;
  }
  return br;
}

// The piece sigma in [lo, hi] of a shape, prepared for many distance queries: for a circle its
// centre and the radial directions of its ends, so that no angle is computed per query.
class Piece {
 public:
  Piece(const PlanarShape& q, double lo, double hi)
      : q_(q),
        lo_(lo),
        hi_(hi),
        start_(lo == 0 ? Vec2::Zero() : shape_point(q, lo)),
        end_(hi == 0 ? Vec2::Zero() : shape_point(q, hi)) {
    if (q.kappa != 0) {
      centre_ = Vec2(-std::sin(q.theta), std::cos(q.theta)) / q.kappa;
      radius_ = 1.0 / std::abs(q.kappa);
      // the radial directions at the ends, ordered counter-clockwise
      from_ = start_ - centre_;
      to_ = end_ - centre_;
      if (q.kappa < 0) std::swap(from_, to_);
      wide_ = std::abs(q.kappa) * (hi - lo) > kPi;
    } else {
      dir_ = direction(q.theta);
    }
  }

  // Distance from x to the piece; also the closest point, and how the distance bends: its
  // Hessian at x is bend (I - u u^T), u the unit vector from the closest point to x, with
  // bend = 0 near the inside of a line, 1 / |x - centre| outside a circle and -1 / |x - centre|
  // inside it, and 1 / distance near an end point.
  struct Distance {
    double distance;
    Vec2 point;
    double bend = 0;  // 1/m
  };
  [[nodiscard]] Distance distance(const Vec2& x) const {
    if (q_.kappa == 0) {
      const double along = x.dot(dir_);
      const Vec2 p = std::clamp(along, lo_, hi_) * dir_;
      const double d = (x - p).norm();
      return {d, p, along > lo_ && along < hi_ ? 0.0 : end_bend(d)};
    }
    const Vec2 r = x - centre_;
    // inside the sector between from_ and to_ (counter-clockwise)?
    const bool after_from = cross(from_, r) >= 0;
    const bool before_to = cross(r, to_) >= 0;
    if (wide_ ? (after_from || before_to) : (after_from && before_to)) {
      const double rn = r.norm();
      const Vec2 p = rn > 0 ? Vec2(centre_ + r * (radius_ / rn)) : start_;
      return {std::abs(rn - radius_), p, rn > 0 ? (rn > radius_ ? 1.0 : -1.0) / rn : 0.0};
    }
    const double da = (x - start_).norm();
    const double db = (x - end_).norm();
    return da <= db ? Distance{da, start_, end_bend(da)} : Distance{db, end_, end_bend(db)};
  }

  static double end_bend(double d) { return d > 0 ? 1 / d : 0.0; }

  // The arc length parameter of a point on the piece (its foot), within [lo, hi].
  [[nodiscard]] double sigma_of(const Vec2& p) const {
    if (q_.kappa == 0) return std::clamp(p.dot(dir_), lo_, hi_);
    const Vec2 c = centre_;
    return std::clamp(std::atan2(cross(-c, p - c), (-c).dot(p - c)) / q_.kappa, lo_, hi_);
  }

 private:
  PlanarShape q_;
  double lo_;
  double hi_;
  Vec2 start_;
  Vec2 end_;
  Vec2 dir_ = Vec2::Zero();
  Vec2 centre_ = Vec2::Zero();
  double radius_ = 0;
  Vec2 from_ = Vec2::Zero();
  Vec2 to_ = Vec2::Zero();
  bool wide_ = false;
};

// 1 / n for n = 0 .. 47 (entry 0 unused).
// clothoid_moments: largest phase excursion on a panel (rad).
constexpr double kMomentPanelPhase = 2.0;

// i v: v turned by +90 deg; and r v as complex numbers (r a unit vector: v turned by its angle).
Vec2 perp(const Vec2& v) { return {-v.y(), v.x()}; }
Vec2 rotate(const Vec2& r, const Vec2& v) { return {r.x() * v.x() - r.y() * v.y(), r.x() * v.y() + r.y() * v.x()}; }

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
};
ClothoidMoments clothoid_moments(double theta0, double kappa0, double c, double len) {
  ClothoidMoments out;
  if (!(len > 0)) return out;
  const double kappa_max = std::max(std::abs(kappa0), std::abs(kappa0 + c * len));
  const double phase = 0.5 * kappa_max * len + 0.125 * std::abs(c) * len * len;
  const int panels = std::max(1, static_cast<int>(std::ceil(phase / kMomentPanelPhase)));
  const double h = 0.5 * len / panels;
  double m0x = 0;
  double m0y = 0;
  double m1x = 0;
  double m1y = 0;
  double m2x = 0;
  double m2y = 0;
  for (int j = 0; j < panels; ++j) {
    const double m = h * (2 * j + 1);
    const double beta = (kappa0 + c * m) * h;
    const double gamma = c * h * h;
    // the Taylor coefficients e_n (n even) and e_{n-1} of the integrand
    series::PhaseTaylor e{.b = beta, .g = gamma};
    double s0r = 1;
    double s0i = 0;
    double s1r = 0;
    double s1i = 0;
    double s2r = series::kInverse[3];
    double s2i = 0;
    for (std::size_t n = 0; n + 5 < series::kInverse.size(); n += 2) {
      e.step_two(n);
      s0r += e.re * series::kInverse[n + 3];
      s0i += e.im * series::kInverse[n + 3];
      s1r += e.prev_re * series::kInverse[n + 3];
      s1i += e.prev_im * series::kInverse[n + 3];
      s2r += e.re * series::kInverse[n + 5];
      s2i += e.im * series::kInverse[n + 5];
      if (e.below(1e-18)) break;
    }
    // the panel's moments in its frame, turned by theta(m); in scalars, as an Eigen 2-vector
    // built from two scalars and read back as a pair stalls store forwarding
    const double theta = theta0 + (kappa0 + 0.5 * c * m) * m;
    const double cs = std::cos(theta);
    const double sn = std::sin(theta);
    const double w = 2 * h;
    const double p0r = w * s0r;
    const double p0i = w * s0i;
    const double p1r = w * (m * s0r + h * s1r);
    const double p1i = w * (m * s0i + h * s1i);
    const double p2r = w * (m * m * s0r + 2 * m * h * s1r + h * h * s2r);
    const double p2i = w * (m * m * s0i + 2 * m * h * s1i + h * h * s2i);
    m0x += cs * p0r - sn * p0i;
    m0y += sn * p0r + cs * p0i;
    m1x += cs * p1r - sn * p1i;
    m1y += sn * p1r + cs * p1i;
    m2x += cs * p2r - sn * p2i;
    m2y += sn * p2r + cs * p2i;
  }
  out.m0.x() = m0x;
  out.m0.y() = m0y;
  out.m1.x() = m1x;
  out.m1.y() = m1y;
  out.m2.x() = m2x;
  out.m2.y() = m2y;
  return out;
}

// A fillet prepared for the many evaluations of the deviation measure: on panels of each
// clothoid (local phase below 1 rad, as in clothoid_xy) the position and unit tangent are
// Taylor polynomials about the panel midpoint m,
//   T(m + t) = exp(i theta(m)) sum_n e_n t^n,   p(m + t) = p(m) + exp(i theta(m)) sum_n e_n t^(n+1) / (n+1),
// with e_n from clothoid_xy's recurrence (e_{n+1} = i (kappa(m) e_n + c e_{n-1}) / (n + 1)),
// so an evaluation costs two polynomials and no trigonometric function. Truncated where the
// terms fall below 1e-15 of the panel's size (the deviation needs about 1e-12 of itself).
class FilletTable {
 public:
  struct Point {
    Vec2 p;
    Vec2 t;  // unit tangent
    double kappa;
  };

  explicit FilletTable(const Biclothoid& curve) : curve_(curve) {
    add_clothoid(curve.start, curve.c, curve.s1, 0.0);
    add_clothoid(curve.mid, -curve.c, curve.s2, curve.s1);
  }

  [[nodiscard]] double length() const { return curve_.s1 + curve_.s2; }

  [[nodiscard]] Point at(double s) const {
    s = std::clamp(s, 0.0, length());
    const double kappa =
        s <= curve_.s1 ? curve_.start.kappa + curve_.c * s : curve_.mid.kappa - curve_.c * (s - curve_.s1);
    if (overflow_) {
      const Posture at = posture_at(curve_, s);
      return {at.p, direction(at.theta), kappa};
    }
    // the panel holding s (panels are ordered by their start)
    std::size_t k = 0;
    while (k + 1 < count_ && s > panels_[k + 1].start) ++k;
    const Panel& panel = panels_[k];
    const double t = s - panel.mid;
    // four interleaved Horner chains in t^4 (coefficients n = 4m + j), which shortens the
    // chain of dependent multiply-adds fourfold; (re, im) pairs as 2-vectors
    const double t2 = t * t;
    const double t4 = t2 * t2;
    std::array<Vec2, 4> tan_acc = {Vec2::Zero(), Vec2::Zero(), Vec2::Zero(), Vec2::Zero()};
    std::array<Vec2, 4> pos_acc = {Vec2::Zero(), Vec2::Zero(), Vec2::Zero(), Vec2::Zero()};
    for (int m = (panel.terms + 3) / 4 - 1; m >= 0; --m) {
      for (std::size_t j = 0; j < 4; ++j) {
        const auto u = static_cast<std::size_t>(4 * m) + j;
        tan_acc[j] = tan_acc[j] * t4 + panel.coef[u];
        pos_acc[j] = pos_acc[j] * t4 + panel.integral[u];
      }
    }
    const double t3 = t2 * t;
    const Vec2 tangent_sum = (tan_acc[0] + t * tan_acc[1]) + (t2 * tan_acc[2] + t3 * tan_acc[3]);
    const Vec2 point_sum = (pos_acc[0] + t * pos_acc[1]) + (t2 * pos_acc[2] + t3 * pos_acc[3]);
    return {panel.base + t * point_sum, tangent_sum, kappa};
  }

 private:
  static constexpr std::size_t kMaxPanels = 12;
  static constexpr std::size_t kMaxTerms = 32;  // a multiple of 4
  static_assert(kMaxTerms < series::kInverse.size());
  struct Panel {
    double start = 0;  // arc length where the panel begins
    double mid = 0;    // its midpoint
    Vec2 base = Vec2::Zero();  // position at mid
    int terms = 0;
    std::array<Vec2, kMaxTerms> coef;      // exp(i theta(mid)) e_n, as (re, im)
    std::array<Vec2, kMaxTerms> integral;  // coef / (n + 1)
  };

  void add_clothoid(const Posture& from, double c, double len, double offset) {
    if (!(len > 0)) return;
    const double kappa_max = std::max(std::abs(from.kappa), std::abs(from.kappa + c * len));
    const double phase = 0.5 * kappa_max * len + 0.125 * std::abs(c) * len * len;
    const auto pieces = static_cast<std::size_t>(std::max(1.0, std::ceil(phase)));
    if (count_ + pieces > kMaxPanels) {
      overflow_ = true;
      return;
    }
    const double h = 0.5 * len / static_cast<double>(pieces);
    Vec2 edge = from.p;  // position at the start of the next panel
    for (std::size_t j = 0; j < pieces; ++j) {
      Panel& panel = panels_[count_++];
      const double m = h * static_cast<double>(2 * j + 1);
      panel.start = offset + m - h;
      panel.mid = offset + m;
      const double kappa = from.kappa + c * m;
      const double theta = from.theta + (from.kappa + 0.5 * c * m) * m;
      const std::complex<double> rot(std::cos(theta), std::sin(theta));
      // Taylor coefficients e_n in t (not scaled by h) of exp(i (kappa t + c t^2 / 2)); the even
      // and odd parts of sum_n coef_n h^(n+1) / (n+1) give the positions at mid -+ h
      series::PhaseTaylor e{.b = kappa, .g = c};
      double h_pow = h;  // h^(n+1)
      double even_re = 0;
      double even_im = 0;
      double odd_re = 0;
      double odd_im = 0;
      std::size_t n = 0;
      // in scalars: an Eigen 2-vector built from two scalars goes through memory, and reading
      // it back as a pair cannot be forwarded from the two stores (a stall per coefficient)
      const auto store = [&](std::size_t u, double re, double im, double hp) {
        const double coef_re = rot.real() * re - rot.imag() * im;
        const double coef_im = rot.real() * im + rot.imag() * re;
        const double int_re = coef_re * series::kInverse[u + 1];
        const double int_im = coef_im * series::kInverse[u + 1];
        panel.coef[u].x() = coef_re;
        panel.coef[u].y() = coef_im;
        panel.integral[u].x() = int_re;
        panel.integral[u].y() = int_im;
        if (u % 2 == 0) {
          even_re += int_re * hp;
          even_im += int_im * hp;
        } else {
          odd_re += int_re * hp;
          odd_im += int_im * hp;
        }
      };
      while (n + 2 <= kMaxTerms) {
        store(n, e.re, e.im, h_pow);
        e.step_two(n);
        store(n + 1, e.prev_re, e.prev_im, h_pow * h);
        n += 2;
        h_pow *= h * h;
        // the next two terms are below 1e-15 of the panel's size
        const double tail = std::abs(e.re) + std::abs(e.im) + (std::abs(e.prev_re) + std::abs(e.prev_im)) / h;
        if (tail * h_pow < 1e-15 * h) break;
      }
      panel.terms = static_cast<int>(n);
      for (std::size_t u = n; u < kMaxTerms && u % 4 != 0; ++u) {
        panel.coef[u] = Vec2::Zero();
        panel.integral[u] = Vec2::Zero();
      }
      // base = edge - p_poly(-h) = edge - (odd - even) ... with p_poly(t) = t sum integral_n t^n
      const double br = even_re - odd_re;
      const double bi = even_im - odd_im;
      const double er = even_re + odd_re;
      const double ei = even_im + odd_im;
      panel.base = edge + Vec2(br, bi);
      edge = panel.base + Vec2(er, ei);
    }
  }

  Biclothoid curve_;
  std::array<Panel, kMaxPanels> panels_;
  std::size_t count_ = 0;
  bool overflow_ = false;
};

// Closest point on the fillet to x by Newton on h(s) = (V(s) - x) . T(s), h' = 1 + kappa (V - x) . N,
// started at `guess` and kept in [0, L]. Once the step is below 1e-6 L the distance follows from
// the local quadratic model, |V - x|^2 - h^2 / h', without another evaluation (its error,
// ~ kappa' step^3, stays below 1e-12 of the distance for the fillets here).
struct FilletClosest {
  double s;
  Vec2 point;
  double distance;
};
FilletClosest closest_on_fillet(const FilletTable& fillet, const Vec2& x, double guess) {
  const double len = fillet.length();
  double s = std::clamp(guess, 0.0, len);
  for (int it = 0; it < 30; ++it) {
    const FilletTable::Point at = fillet.at(s);
    const Vec2 d = at.p - x;
    const Vec2 n(-at.t.y(), at.t.x());
    const double h = d.dot(at.t);
    // a step from the local quadratic model; damped where the model is not convex
    const double hp = std::max(1.0 + at.kappa * d.dot(n), 0.25);
    const double next = std::clamp(s - h / hp, 0.0, len);
    const double step = next - s;
    if (std::abs(step) <= 1e-6 * len) {
      const double d2 = d.squaredNorm() - (std::abs(step) > 0 ? h * h / hp : 0.0);
      return {next, at.p + step * at.t, std::sqrt(std::max(d2, 0.0))};
    }
    s = next;
  }
  const FilletTable::Point at = fillet.at(s);
  return {s, at.p, (at.p - x).norm()};
}

// Maximum of a function on [x0, x1] given at both ends and, in the cases of section 7.1, with
// one interior maximum: `eval(x)` returns the value and its derivative. Evaluates the interior
// sample points `xs`, brackets the best point by the sign change of the derivative and refines
// by false position on the derivative. Returns the largest value seen.
struct ValueSlope {
  double value;
  double slope;
};
template <class F, std::size_t N>
double maximize(const F& eval, double x0, ValueSlope at0, double x1, ValueSlope at1, const std::array<double, N>& xs) {
  std::array<double, N + 2> x{};
  std::array<ValueSlope, N + 2> v{};
  x[0] = x0;
  v[0] = at0;
  for (std::size_t i = 0; i < N; ++i) {
    x[i + 1] = xs[i];
    v[i + 1] = eval(xs[i]);
  }
  x[N + 1] = x1;
  v[N + 1] = at1;
  std::size_t best = 0;
  for (std::size_t i = 1; i < N + 2; ++i) {
    if (v[i].value > v[best].value) best = i;
  }
  double top = v[best].value;
  // at a point with slope f' the maximum, within the interval of width w, is at most |f'| w
  // higher (and only f'^2 / (2 f'') near a sharp one): a slope below 1e-9 f / w is flat enough
  const double flat = 1e-9 * top / std::abs(x1 - x0);
  if (std::abs(v[best].slope) <= flat) return top;
  // the derivative changes sign from + to - on one side of the best point
  std::size_t lo = best;
  std::size_t hi = best;
  if (v[best].slope > 0 && best + 1 < N + 2) hi = best + 1;
  else if (v[best].slope < 0 && best > 0) lo = best - 1;
  if (lo == hi || !(v[lo].slope > 0) || !(v[hi].slope < 0)) return top;
  const auto slope = [&](double xi) {
    const ValueSlope vi = eval(xi);
    top = std::max(top, vi.value);
    return vi.slope;
  };
  illinois(slope, Bracket{x[lo], v[lo].slope, x[hi], v[hi].slope}, 1e-6 * std::abs(x1 - x0), flat, 30);
  return top;
}

// Where q1 (sigma in [-a_max, 0)) and q2 (sigma in (0, b_max]) meet again after the corner,
// as (-sigma1, sigma2), or nullopt. Both pass through the origin, so a line meets a circle of
// centre c once more at 2 (t . c) t, and two circles meet at the mirror image of the origin in
// their line of centres. At a tangent corner (no tangent jump) they touch at the origin and meet
// nowhere else; the formulas then give the origin up to rounding (a point 1e-33 m away once
// capped a tangent S-bend's fillet to nothing), so there is no crossing.
std::optional<std::pair<double, double>> crossing(const PlanarShape& q1, const PlanarShape& q2, double a_max,
                                                  double b_max) {
  const auto centre = [](const PlanarShape& q) -> Vec2 {
    return Vec2(-std::sin(q.theta), std::cos(q.theta)) / q.kappa;
  };
  if (q1.kappa == 0 && q2.kappa == 0) return std::nullopt;
  if (std::abs(std::remainder(q2.theta - q1.theta, 2 * kPi)) <= kTangentAngle) return std::nullopt;
  Vec2 x = Vec2::Zero();
  if (q1.kappa == 0 || q2.kappa == 0) {
    const PlanarShape& line = q1.kappa == 0 ? q1 : q2;
    const Vec2 t = direction(line.theta);
    x = 2 * t.dot(centre(q1.kappa == 0 ? q2 : q1)) * t;
  } else {
    const Vec2 c1 = centre(q1);
    const Vec2 d = centre(q2) - c1;
    if (!(d.squaredNorm() > 0)) return std::nullopt;
    x = 2 * (c1 - c1.dot(d) / d.squaredNorm() * d);
  }
  const auto sigma = [&](const PlanarShape& q) {
    if (q.kappa == 0) return x.dot(direction(q.theta));
    const Vec2 c = centre(q);
    return std::atan2(cross(-c, x - c), (-c).dot(x - c)) / q.kappa;
  };
  const double s1 = sigma(q1);
  const double s2 = sigma(q2);
  if (!(x.norm() > 0) || !(s1 < 0 && -s1 <= a_max) || !(s2 > 0 && s2 <= b_max)) return std::nullopt;
  return std::make_pair(-s1, s2);
}

// Derivation of eq. 11-13 in a form without the 0/0 of eq. 11 at kappa0 = kappa_e: with peak
// kappa_m, the tent profile gives kappa_m - kappa0 = c s1, kappa_m - kappa_e = c s2, and
// the turn is the area under it, 2 dtheta = (2 kappa_m^2 - kappa0^2 - kappa_e^2) / c with
// c = (2 kappa_m - kappa0 - kappa_e) / L. Eliminating c gives the quadratic
//   L kappa_m^2 - 2 dtheta kappa_m + dtheta (kappa0 + kappa_e) - L (kappa0^2 + kappa_e^2) / 2 = 0,
// kappa_m = (dtheta +- sqrt(SQ)) / L with 004's SQ = A^2 + B^2, A = dtheta - L kbar,
// B = L (kappa_e - kappa0) / 2, kbar = (kappa0 + kappa_e) / 2. The root with s1, s2 >= 0 is the
// one whose sign matches A: D = kappa_m - kbar = (A + sign(A) sqrt(SQ)) / L, c = 2 D / L,
// s1 = L (1 + B / (L D)) / 2. Eq. 11, which always takes -sqrt(SQ), is this root when A >= 0
// (the curvature peaks above both end values, as in 004's example); for A < 0 (a valley) eq. 11
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

// Turn of the programmed corner: the tangent jump delta in (-pi, pi].
double corner_turn(const CornerShapes& shapes) { return std::remainder(shapes.q2.theta - shapes.q1.theta, 2 * kPi); }

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

// Derivatives of a point of the curve and of its end (derived here; 004 solves Algorithm 1
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

struct PointSlopes {
  Vec2 d_length;  // d V(s) / d L at a fixed turn (without the end's T(L))
  Vec2 d_turn;    // d V(s) / d dtheta at a fixed length
};
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

// point_slopes at arc length s in [0, L]; `offset` receives V(s) - p0.
PointSlopes point_slopes_at(const Biclothoid& curve, double s, Vec2& offset) {
  s = std::clamp(s, 0.0, length(curve));
  const ClothoidMoments first =
      clothoid_moments(curve.start.theta, curve.start.kappa, curve.c, std::min(s, curve.s1));
  const ClothoidMoments second =
      s > curve.s1 ? clothoid_moments(curve.mid.theta, curve.mid.kappa, -curve.c, s - curve.s1) : ClothoidMoments{};
  offset = first.m0 + second.m0;
  return point_slopes(curve, first, second);
}

}  // namespace

std::optional<BiclothoidEnd> biclothoid_end(const Posture& start, double kappa_e, double dtheta, double length) {
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
  const ClothoidMoments first = clothoid_moments(start.theta, start.kappa, c, s1);
  curve.mid.p = start.p + first.m0;
  curve.mid.kappa = start.kappa + c * s1;
  curve.mid.theta = start.theta + (start.kappa + 0.5 * c * s1) * s1;
  const ClothoidMoments second = clothoid_moments(curve.mid.theta, curve.mid.kappa, -c, curve.s2);
  out.p = curve.mid.p + second.m0;
  out.tangent = direction(start.theta + dtheta);
  const PointSlopes slopes = point_slopes(curve, first, second);
  out.d_length = out.tangent + slopes.d_length;
  out.d_turn = slopes.d_turn;
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

Biclothoid reversed(const Biclothoid& curve) {
  const Posture e = end_posture(curve);
  return make_biclothoid(Posture{e.p, -e.kappa, e.theta + kPi}, -curve.c, curve.s2, curve.s1);
}

Vec2 shape_point(const PlanarShape& shape, double sigma) {
  const double half = 0.5 * shape.kappa * sigma;
  return sigma * sinc(half) * direction(shape.theta + half);
}

double shape_angle(const PlanarShape& shape, double sigma) { return shape.theta + shape.kappa * sigma; }

namespace {

// shape_point and the unit tangent there from one sine and cosine: with h = kappa sigma / 2
// and t0 the tangent at the corner, the chord is sigma sinc(h) along t0 turned by h, and the
// tangent is turned by 2 h.
struct ShapeAt {
  Vec2 p;
  Vec2 t;
};
ShapeAt shape_at(const PlanarShape& shape, const Vec2& t0, double sigma) {
  const double half = 0.5 * shape.kappa * sigma;
  const Vec2 turn(std::cos(half), std::sin(half));
  const Vec2 chord = rotate(turn, t0);
  return {sigma * (std::abs(half) < 1e-4 ? 1.0 - half * half / 6.0 : turn.y() / half) * chord, rotate(turn, chord)};
}

// A solution of Algorithm 1 and how it moves with the start distance a (implicit function
// theorem on its end conditions): warm starts for the next solve of Algorithm 2.
struct Solve {
  BiclothoidSolution fillet;
  double dlen_da = 0;  // d length / d a
  double db_da = 0;    // d b / d a
};

std::optional<Solve> fit_at(const CornerShapes& shapes, double a, double guess_length, double guess_b) {
  if (!(a > 0) || !std::isfinite(a)) return std::nullopt;
  const PlanarShape& q1 = shapes.q1;
  const PlanarShape& q2 = shapes.q2;
  const double delta = corner_turn(shapes);
  const ShapeAt on_q1 = shape_at(q1, direction(q1.theta), -a);
  const Posture start{on_q1.p, q1.kappa, shape_angle(q1, -a)};
  // the fillet turns as much as the path it replaces: kappa1 a + delta + kappa2 b
  const double base_turn = delta + q1.kappa * a;
  // how the end of a fillet of fixed length moves with a: the start slides back along q1
  // (d p0 / d a = -T0), the curve turns with its start tangent (by -kappa1 per unit of a) and
  // its turn grows by kappa1
  const Vec2 t0 = on_q1.t;
  const auto end_da = [&](const BiclothoidEnd& e) -> Vec2 {
    return -t0 - q1.kappa * perp(e.p - start.p) + q1.kappa * e.d_turn;
  };

  // a cold guess: the symmetric line-line fillet with tangent length a where the tangent jump
  // dominates (the limit of small fillets), else L = 1.5 a, b = a / 2 (004 table 1's fillets).
  // Which dominates: the deviation of the pair grows like |delta| a / 6, that of a curvature
  // jump like |kappa1 - kappa2| a^2 / 42 (see fit_biclothoid_with_tolerance).
  if (!(guess_length > 0 && guess_b > 0)) {
    const double jump = std::abs(q1.kappa - q2.kappa);
    if (std::abs(delta) / 6 > jump * a / 42) {
      const ClothoidPair pair = clothoid_pair_for_tangent_length(std::abs(delta), a);
      guess_length = 2 * pair.half_length;
      guess_b = a;
    } else {
      guess_length = 1.5 * a;
      guess_b = 0.5 * a;
    }
  }

  if (q2.kappa == 0) {
    // q2 is a line: the end angle is fixed, so one equation in L: the end lies on the line,
    // f(L) = t2 x p(L) = 0 with f' = t2 x dp/dL. Newton from the guess (L at most halves or
    // doubles per step) converges to the root nearest the guess; once a sign change brackets
    // it, steps leaving the bracket bisect it. A bracket search if that fails.
    const Vec2 t2 = direction(q2.theta);
    const auto eval = [&](double len) { return biclothoid_end(start, 0.0, base_turn, len); };
    const auto offset = [&](double len) { return cross(t2, eval(len)->p); };
    if (cross(t2, start.p) == 0) return std::nullopt;
    const double scale = a + guess_b;
    const double f_tol = kSolveTolerance * scale;
    // the end must lie after the corner (b > 0): a fillet can also cross the line just after
    // its start
    const auto finish = [&](const BiclothoidEnd& e) -> std::optional<Solve> {
      const double b = e.p.dot(t2);
      if (!(b > 0) || std::abs(cross(t2, e.p)) > 1e-11 * (a + b)) return std::nullopt;
      if (!((e.p - start.p).norm() > kMinChordRatio * (a + b))) return std::nullopt;
      // f(L(a), a) = 0 and b = t2 . p(L(a), a)
      const Vec2 dp_da = end_da(e);
      const double dlen_da = -cross(t2, dp_da) / cross(t2, e.d_length);
      return Solve{{e.curve, a, b}, dlen_da, t2.dot(e.d_length * dlen_da + dp_da)};
    };
    double x = guess_length;
    auto e = eval(x);
    double prev_x = 0;
    double prev_f = 0;
    double lo = 0;  // a bracket [lo, hi] once hi > 0, f(lo) of sign lo_sign
    double hi = 0;
    bool lo_positive = false;
    for (int it = 0; it < 40 && e; ++it) {
      const double f = cross(t2, e->p);
      if (std::abs(f) <= f_tol) {
        if (auto sol = finish(*e)) return sol;
        break;
      }
      if (hi > 0) {
        ((f > 0) == lo_positive ? lo : hi) = x;
      } else if (prev_x > 0 && (f > 0) != (prev_f > 0)) {
        lo = std::min(prev_x, x);
        hi = std::max(prev_x, x);
        lo_positive = ((lo == x ? f : prev_f) > 0);
      }
      double next = x - f / cross(t2, e->d_length);
      if (hi > 0) {
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        if (hi - lo <= 1e-15 * hi) break;
      } else {
        if (!std::isfinite(next)) next = 2 * x;
        next = std::clamp(next, 0.5 * x, 2 * x);
      }
      prev_x = x;
      prev_f = f;
      x = next;
      e = eval(x);
    }
    // fallback: scan L geometrically for sign changes, polish each bracket by false position
    // (Illinois) and keep the root with b > 0 nearest the guess
    std::optional<Solve> best;
    double scan_x = 0.02 * scale;
    double scan_f = offset(scan_x);
    for (int k = 1; k < 48; ++k) {
      const double x1 = scan_x * 1.25;
      const double f1 = offset(x1);
      if ((f1 > 0) != (scan_f > 0)) {
        const Bracket br = illinois(offset, Bracket{scan_x, scan_f, x1, f1}, 1e-15 * x1, f_tol, 100);
        const auto sol = finish(*eval(std::abs(br.f0) < std::abs(br.f1) ? br.x0 : br.x1));
        if (sol && (!best || std::abs(length(sol->fillet.curve) - guess_length) <
                                 std::abs(length(best->fillet.curve) - guess_length))) {
          best = sol;
        }
      }
      scan_x = x1;
      scan_f = f1;
    }
    return best;
  }

  // q2 is an arc: Newton on (L, b) for r(L, b) = p(L, turn(b)) - q2(b) = 0 with
  // turn(b) = base_turn + kappa2 b and the Jacobian [dp/dL, kappa2 dp/dturn - T2(b)]
  // (biclothoid_end); L and b at most halve or double per step, and the step halves while |r|
  // does not decrease
  struct Eval {
    BiclothoidEnd end;
    Vec2 r;
    Eigen::Matrix2d jac;
  };
  const Vec2 t2 = direction(q2.theta);
  const auto evaluate = [&](double len, double b) -> std::optional<Eval> {
    const auto e = biclothoid_end(start, q2.kappa, base_turn + q2.kappa * b, len);
    if (!e) return std::nullopt;
    const ShapeAt on_q2 = shape_at(q2, t2, b);
    Eval ev{*e, e->p - on_q2.p, Eigen::Matrix2d()};
    ev.jac.col(0) = e->d_length;
    ev.jac.col(1) = q2.kappa * e->d_turn - on_q2.t;
    return ev;
  };
  // a solution that shrinks to a point where q1 and q2 cross (near a reversal) is not a fillet
  const auto accept = [&](const Eval& ev, double b) -> std::optional<Solve> {
    if (!((ev.end.p - start.p).norm() > kMinChordRatio * (a + b))) return std::nullopt;
    // r(L(a), b(a), a) = 0: J d(L, b)/da = -dr/da
    const Vec2 slope = -(ev.jac.inverse() * end_da(ev.end));
    return Solve{{ev.end.curve, a, b}, slope.x(), slope.y()};
  };
  const auto solve_from = [&](double len, double b) -> std::optional<Solve> {
    auto cur = evaluate(len, b);
    for (int it = 0; it < 25 && cur; ++it) {
      const double scale = a + b;
      if (cur->r.norm() <= kSolveTolerance * scale) return accept(*cur, b);
      const double det = cur->jac.determinant();
      if (!(std::abs(det) > 0) || !std::isfinite(det)) return std::nullopt;
      const Vec2 step = -(cur->jac.inverse() * cur->r);
      double lambda = 1;
      if (std::abs(step.x()) > 0.5 * len) lambda = std::min(lambda, 0.5 * len / std::abs(step.x()));
      if (std::abs(step.y()) > 0.5 * b) lambda = std::min(lambda, 0.5 * b / std::abs(step.y()));
      bool accepted = false;
      for (int half = 0; half < 12 && !accepted; ++half, lambda *= 0.5) {
        auto next = evaluate(len + lambda * step.x(), b + lambda * step.y());
        if (next && next->r.norm() < cur->r.norm()) {
          len += lambda * step.x();
          b += lambda * step.y();
          cur = std::move(next);
          accepted = true;
        }
      }
      // no decrease along the Newton direction: converged to rounding, or stuck
      if (!accepted) return cur->r.norm() <= 1e-12 * scale ? accept(*cur, b) : std::nullopt;
    }
    return std::nullopt;
  };
  if (auto sol = solve_from(guess_length, guess_b)) return sol;
  // other starts: a symmetric fillet, then unequal ones (tangent corners are not symmetric)
  for (const double ratio : {1.0, 0.5, 2.0}) {
    if (auto sol = solve_from(a * (1 + ratio), a * ratio)) return sol;
  }
  return std::nullopt;
}

}  // namespace

std::optional<BiclothoidSolution> fit_biclothoid_at(const CornerShapes& shapes, double a, double guess_length,
                                                    double guess_b) {
  const auto sol = fit_at(shapes, a, guess_length, guess_b);
  if (!sol) return std::nullopt;
  return sol->fillet;
}

namespace {

// Where the larger directed distance D is attained, for its derivative with respect to the
// start distance a (fit_biclothoid_with_tolerance): the fillet point V(s) and the unit vector u
// from its partner (a point of U, or the foot of V(s) on U) to it. The partner is a critical
// point (the foot, or a smooth maximum over U) or fixed (the corner), so by the envelope
// theorem dD/da = u . dV(s)/da at a fixed s. At a crossing of a tangent jump, where V(s) is as
// far from both pieces (D = d1(s) = d2(s), slopes d1', d2'), s moves too:
//   dD/da = (d1' dd2/da - d2' dd1/da) / (d1' - d2'),   ddk/da = uk . dV(s)/da.
struct Witness {
  double s = 0;
  Vec2 u = Vec2::Zero();
  bool crossing = false;
  Vec2 u2 = Vec2::Zero();  // the crossing: u for the second piece, and both slopes
  double slope1 = 0;
  double slope2 = 0;
};
struct Measured {
  Deviation deviation;
  Witness witness;
};

Measured measure_deviation(const BiclothoidSolution& fillet, const CornerShapes& shapes) {
  const Biclothoid& curve = fillet.curve;
  const FilletTable table(curve);
  const double len = length(curve);
  const double a = fillet.a;
  const double b = fillet.b;
  const PlanarShape& q1 = shapes.q1;
  const PlanarShape& q2 = shapes.q2;
  Measured out;
  Deviation& dev = out.deviation;

  // fillet -> original: exact distances to the two pieces of U. The distance to U is the
  // smaller of the distances to q1[-a, 0] and q2[0, b]; its maximum is either a smooth maximum
  // of one of them or (at a tangent jump) where they are equal.
  const std::array<Piece, 2> pieces = {Piece(q1, -a, 0.0), Piece(q2, 0.0, b)};
  struct FilletSample {
    double s;
    Vec2 p;  // V(s)
    std::array<Piece::Distance, 2> d;
    std::array<double, 2> slope;   // d distance / ds to each piece
    std::array<double, 2> second;  // d^2 distance / ds^2
    [[nodiscard]] int active() const { return d[0].distance <= d[1].distance ? 0 : 1; }
    [[nodiscard]] double value() const { return d[static_cast<std::size_t>(active())].distance; }
  };
  // with u the unit vector from the foot to V(s): slope = u . T, and from the Hessian of the
  // distance (Piece::Distance) and dT/ds = kappa N, second = kappa u . N + bend (1 - slope^2)
  const auto sample = [&](double s) {
    const FilletTable::Point at = table.at(s);
    FilletSample f{s, at.p, {pieces[0].distance(at.p), pieces[1].distance(at.p)}, {}, {}};
    const Vec2& t = at.t;
    for (std::size_t k = 0; k < 2; ++k) {
      const Piece::Distance& d = f.d[k];
      if (d.distance > 0) {
        const Vec2 u = (at.p - d.point) / d.distance;
        f.slope[k] = t.dot(u);
        f.second[k] = at.kappa * cross(t, u) + d.bend * (1 - f.slope[k] * f.slope[k]);
      } else {
        f.slope[k] = k == 0 ? 1.0 : -1.0;
      }
    }
    return f;
  };
  FilletSample top{};
  const auto keep = [&](const FilletSample& f) {
    if (f.value() > top.value()) top = f;
  };
  // the maximum between two samples l < r: where both have the same nearest piece (or at a
  // curvature jump only, where the distance to U is C1), Newton on the slope; across a tangent
  // jump the distance has a kink where the nearest piece changes, found first
  const bool kink = std::abs(corner_turn(shapes)) > kTangentAngle;
  const auto refine = [&](const FilletSample& l, const FilletSample& r, const auto& self) -> void {
    const int kl = l.active();
    const int kr = r.active();
    if (kl == kr || !kink) {
      const double sl = l.slope[static_cast<std::size_t>(kl)];
      const double sr = r.slope[static_cast<std::size_t>(kr)];
      if (!(sl > 0 && sr < 0)) return;
      // from the higher end, kept inside the shrinking bracket (false position where a step
      // leaves it or the distance is not concave); a slope below 1e-9 f / L leaves the value
      // within 1e-9 of the maximum (see maximize)
      const double flat = 1e-9 * top.value() / len;
      Bracket br{l.s, sl, r.s, sr};
      FilletSample at = l.value() >= r.value() ? l : r;
      for (int it = 0; it < 30 && br.x1 - br.x0 > 1e-6 * len; ++it) {
        const auto k = static_cast<std::size_t>(at.active());
        double next = (br.x0 * br.f1 - br.x1 * br.f0) / (br.f1 - br.f0);
        if (at.second[k] < 0) {
          const double newton = at.s - at.slope[k] / at.second[k];
          if (newton > br.x0 && newton < br.x1) next = newton;
        }
        at = sample(next);
        keep(at);
        const double slope = at.slope[static_cast<std::size_t>(at.active())];
        if (std::abs(slope) <= flat) break;
        (slope > 0 ? br.x0 : br.x1) = next;
        (slope > 0 ? br.f0 : br.f1) = slope;
      }
      return;
    }
    // Newton on g = d1 - d2 (g' = slope1 - slope2), kept inside the shrinking bracket
    FilletSample cross_at = l;
    double lo = l.s;
    double hi = r.s;
    const double g_lo = l.d[0].distance - l.d[1].distance;
    double s = 0.5 * (lo + hi);
    for (int it = 0; it < 40; ++it) {
      cross_at = sample(s);
      keep(cross_at);
      const double g = cross_at.d[0].distance - cross_at.d[1].distance;
      if ((g > 0) == (g_lo > 0)) lo = s;
      else hi = s;
      const double dg = cross_at.slope[0] - cross_at.slope[1];
      double next = dg != 0 ? s - g / dg : 0.5 * (lo + hi);
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
      if (std::abs(next - s) <= 1e-10 * len || std::abs(g) <= 1e-13 * len) break;
      s = next;
    }
    // a smooth maximum of the piece active on either side of the crossing
    if (cross_at.slope[static_cast<std::size_t>(kl)] < 0 && cross_at.s > l.s) {
      FilletSample left = cross_at;
      left.d[static_cast<std::size_t>(kr)].distance = std::numeric_limits<double>::infinity();
      self(l, left, self);
    }
    if (cross_at.slope[static_cast<std::size_t>(kr)] > 0 && cross_at.s < r.s) {
      FilletSample right = cross_at;
      right.d[static_cast<std::size_t>(kl)].distance = std::numeric_limits<double>::infinity();
      self(right, r, self);
    }
  };
  {
    // the ends lie on U: distance 0, increasing inwards
    FilletSample start{0.0, curve.start.p, {Piece::Distance{0.0, curve.start.p}, Piece::Distance{1.0, Vec2::Zero()}},
                       {1.0, 1.0}, {0.0, 0.0}};
    FilletSample end{len, Vec2::Zero(), {Piece::Distance{1.0, Vec2::Zero()}, Piece::Distance{0.0, Vec2::Zero()}},
                     {-1.0, -1.0}, {0.0, 0.0}};
    std::array<FilletSample, 5> f = {start, sample(0.5 * curve.s1), sample(curve.s1), sample(curve.s1 + 0.5 * curve.s2),
                                     end};
    std::size_t best = 1;
    for (std::size_t i = 2; i < 4; ++i) {
      if (f[i].value() > f[best].value()) best = i;
    }
    top = f[best];
    if (f[best].slope[static_cast<std::size_t>(f[best].active())] > 0) refine(f[best], f[best + 1], refine);
    else refine(f[best - 1], f[best], refine);
  }
  dev.fillet_to_original = top.value();

  // original -> fillet: for a point of U its closest point on V (Newton); the maximum over U on
  // each side of the corner, where U has its kink, with the corner as a shared candidate. Seeds:
  // the foot on U of the fillet -> original maximum (a common normal of both curves, where a
  // smooth maximum of this direction lies too) and each side's midpoint as a guard.
  double guess = curve.s1;
  struct Farthest {
    double distance = -1;
    double s = 0;
    Vec2 u = Vec2::Zero();
  } farthest;
  const auto keep_farthest = [&](const Vec2& x, const FilletClosest& c) {
    if (!(c.distance > farthest.distance)) return;
    farthest = {c.distance, c.s, c.distance > 0 ? Vec2((c.point - x) / c.distance) : Vec2::Zero()};
  };
  const std::array<Vec2, 2> corner_tangent = {direction(q1.theta), direction(q2.theta)};
  const auto from_original = [&](double sigma, std::size_t side) {
    const ShapeAt x = shape_at(side == 0 ? q1 : q2, corner_tangent[side], sigma);
    const FilletClosest c = closest_on_fillet(table, x.p, guess);
    keep_farthest(x.p, c);
    guess = c.s;
    return ValueSlope{c.distance, c.distance > 0 ? x.t.dot(x.p - c.point) / c.distance : 0.0};
  };
  const FilletClosest corner = closest_on_fillet(table, Vec2::Zero(), curve.s1);
  keep_farthest(Vec2::Zero(), corner);
  const double g0 = corner.distance;
  const ValueSlope corner_in{g0, g0 > 0 ? corner_tangent[0].dot(-corner.point) / g0 : 0.0};
  const ValueSlope corner_out{g0, g0 > 0 ? corner_tangent[1].dot(-corner.point) / g0 : 0.0};
  const int foot_piece = top.active();
  const auto foot_index = static_cast<std::size_t>(foot_piece);
  const double foot = pieces[foot_index].sigma_of(top.d[foot_index].point);
  // the maximum over one side, from the far end (distance 0) to the corner, sampled at the
  // foot (when it lies on this side) and the midpoint; each evaluation starts Newton from the
  // previous closest point, the foot's from the fillet point it is the foot of
  const auto side_max = [&](std::size_t side, double lo, ValueSlope v_lo, double hi, ValueSlope v_hi,
                            double start_guess, bool has_foot) {
    const auto f = [&](double x) {
      if (has_foot && x == foot) guess = top.s;
      return from_original(x, side);
    };
    const double mid = 0.5 * (lo + hi);
    guess = start_guess;
    if (!has_foot || foot == mid) return maximize(f, lo, v_lo, hi, v_hi, std::array<double, 1>{mid});
    return maximize(f, lo, v_lo, hi, v_hi, std::array<double, 2>{std::min(foot, mid), std::max(foot, mid)});
  };
  const double side1 = side_max(0, -a, ValueSlope{0.0, 1.0}, 0.0, corner_in, 0.5 * corner.s,
                                foot_piece == 0 && foot > -a && foot < 0);
  const double side2 = side_max(1, 0.0, corner_out, b, ValueSlope{0.0, -1.0}, corner.s,
                                foot_piece == 1 && foot > 0 && foot < b);
  dev.original_to_fillet = std::max({g0, side1, side2});

  // the witness of the larger distance
  Witness& w = out.witness;
  if (dev.original_to_fillet >= dev.fillet_to_original) {
    w.s = farthest.s;
    w.u = farthest.u;
  } else {
    const auto k = static_cast<std::size_t>(top.active());
    const auto unit = [&](std::size_t j) {
      return top.d[j].distance > 0 ? Vec2((top.p - top.d[j].point) / top.d[j].distance) : Vec2::Zero();
    };
    w.s = top.s;
    w.u = unit(k);
    w.crossing = kink && std::abs(top.d[0].distance - top.d[1].distance) <= 1e-6 * top.value() &&
                 top.slope[0] != top.slope[1];
    if (w.crossing) {
      w.u = unit(0);
      w.u2 = unit(1);
      w.slope1 = top.slope[0];
      w.slope2 = top.slope[1];
    }
  }
  return out;
}

}  // namespace

Deviation biclothoid_deviation(const BiclothoidSolution& fillet, const CornerShapes& shapes) {
  return measure_deviation(fillet, shapes).deviation;
}

BiclothoidToleranceFit fit_biclothoid_with_tolerance(const CornerShapes& shapes, double tolerance, double a_max,
                                                     double b_max) {
  BiclothoidToleranceFit result;
  // section 6: fit from the more curved shape to the less curved one
  CornerShapes work = shapes;
  result.swapped = std::abs(shapes.q2.kappa) > std::abs(shapes.q1.kappa);
  if (result.swapped) {
    work.q1 = PlanarShape{shapes.q2.theta + kPi, -shapes.q2.kappa};
    work.q2 = PlanarShape{shapes.q1.theta + kPi, -shapes.q1.kappa};
    std::swap(a_max, b_max);
  }
  // at most an eighth of a turn of an arc is replaced, and only up to where the two moves cross
  // again (near a reversal an arc can curl back across the other move)
  double a_cap = work.q1.kappa != 0 ? std::min(a_max, kMaxArcTurn / std::abs(work.q1.kappa)) : a_max;
  double b_cap = work.q2.kappa != 0 ? std::min(b_max, kMaxArcTurn / std::abs(work.q2.kappa)) : b_max;
  if (const auto meet = crossing(work.q1, work.q2, a_cap, b_cap)) {
    a_cap = std::min(a_cap, kCrossingMargin * meet->first);
    b_cap = std::min(b_cap, kCrossingMargin * meet->second);
  }
  const bool tangent_jump = std::abs(corner_turn(work)) > 1e-9;

  struct Trial {
    BiclothoidSolution fillet;
    double dlen_da = 0;  // sensitivities of Algorithm 1 (Solve)
    double db_da = 0;
    Deviation deviation;
    Witness witness;
    bool measured = false;
  };
  // the solves so far; the capacity is reserved once, so addresses stay stable (an array of
  // optionals would be cleared in full on every call, 20 kB)
  constexpr std::size_t kMaxTrials = 96;
  std::vector<Trial> store;
  store.reserve(kMaxTrials);
  // Algorithm 1 at start distance a, warm-started from the nearest earlier solve: its L and b
  // moved along their sensitivities in log-log coordinates, L (a) ~ L_n (a / a_n)^p with
  // p = (a_n / L_n) dL/da (exact for the line-line pair, where L and b are proportional to a)
  const auto solve = [&](double a) -> Trial* {
    // the nearest in log a: the smallest ratio max(a_n / a, a / a_n)
    const auto gap = [&](const Trial& t) { return std::max(t.fillet.a / a, a / t.fillet.a); };
    Trial* near = nullptr;
    for (Trial& t : store) {
      if (t.fillet.a == a) return &t;
      if (!near || gap(t) < gap(*near)) near = &t;
    }
    double guess_len = 0;
    double guess_b = 0;
    if (near) {
      const BiclothoidSolution& f = near->fillet;
      const double x = std::log(a / f.a);
      const double len = length(f.curve);
      double p_len = near->dlen_da * f.a / len;
      double p_b = near->db_da * f.a / f.b;
      if (!(std::abs(p_len) < 4)) p_len = 1;
      if (!(std::abs(p_b) < 4)) p_b = 1;
      guess_len = len * std::exp(p_len * x);
      guess_b = f.b * std::exp(p_b * x);
    }
    if (store.size() == kMaxTrials) return nullptr;
    ++result.solves;
    const auto sol = fit_at(work, a, guess_len, guess_b);
    if (!sol) return nullptr;
    store.push_back(Trial{sol->fillet, sol->dlen_da, sol->db_da, {}, {}, false});
    return &store.back();
  };
  const auto measure = [&](Trial* t) {
    if (!t->measured) {
      const Measured m = measure_deviation(t->fillet, work);
      t->deviation = m.deviation;
      t->witness = m.witness;
      t->measured = true;
    }
    return t->deviation.max();
  };
  const auto fail = [&](const std::string& why) {
    result.outcome = {Status::kNotConverged, why};
    return result;
  };

  // dy/dx (x = log a, y below) at a measured trial, from the term that sets y: the end bound
  // through db/da, the deviation D through its witness (measure_deviation) and the motion of
  // the fillet point V(s) at a fixed s as a grows: the start slides back along q1
  // (-T0), the fillet turns with its start tangent (by -kappa1 per unit of a), and its length
  // and turn (delta + kappa1 a + kappa2 b) change along the solve's sensitivities
  const auto slope_at = [&](const Trial& t) {
    const BiclothoidSolution& f = t.fillet;
    const double dev = t.deviation.max();
    if (f.b / b_cap >= dev / tolerance) return f.a * t.db_da / f.b;
    const Witness& w = t.witness;
    Vec2 offset;
    const PointSlopes at = point_slopes_at(f.curve, w.s, offset);
    const Vec2 dv = -direction(f.curve.start.theta) - work.q1.kappa * perp(offset) + at.d_length * t.dlen_da +
                    at.d_turn * (work.q1.kappa + work.q2.kappa * t.db_da);
    double dd = w.u.dot(dv);
    if (w.crossing) dd = (w.slope1 * w.u2.dot(dv) - w.slope2 * dd) / (w.slope1 - w.slope2);
    return f.a * dd / dev;
  };

  // Algorithm 2 with the end bound folded in: the largest a with
  //   y(a) = max(log(dev / tol), log(b / b_cap)) <= 0,
  // both terms growing with a. Newton steps on y against x = log a with the slope above
  // (deviation ~ a^p, p = 1 at a tangent jump, 2 at a curvature jump only, so y is nearly
  // linear in x), secant steps where the slope is not usable, bisection once bracketed steps
  // leave the bracket, stopping at -kReached <= y <= 0.
  const double delta = corner_turn(work);
  const double x_cap = std::log(a_cap);
  // a first start distance from the two small-fillet models: the line-line pair for the
  // tangent jump (deviation ~ a) and, from 004 table 1 (arc R10 -> line at 0.1 mm: a = 6.5 mm),
  // dev ~ |kappa jump| a^2 / 42 for the curvature jump; where both act, the harmonic blend
  // 1 / a^2 = 1 / a_angle^2 + 1 / a_curvature^2 (an empirical fit: within about 1% of the
  // solution for 004 listing 1 point C and a 20 deg line-arc kink, against 6% for the smaller)
  const double kappa_jump = std::abs(work.q1.kappa - work.q2.kappa);
  const double a_angle = tangent_jump ? clothoid_pair_for_deviation(std::abs(delta), tolerance).tangent_length
                                      : std::numeric_limits<double>::infinity();
  const double a_curvature =
      kappa_jump > 0 ? std::sqrt(42.0 * tolerance / kappa_jump) : std::numeric_limits<double>::infinity();
  const double a_model = 1 / std::hypot(1 / a_angle, 1 / a_curvature);
  const double a_start = std::min({a_cap, b_cap, a_model});
  const double p_guess = a_angle <= a_curvature ? 1.0 : 2.0;
  struct Point {
    double x;
    double y;
    Trial* trial;
  };
  const auto evaluate = [&](double x) -> Point {
    Trial* t = solve(std::min(std::exp(x), a_cap));
    if (!t) return {x, std::numeric_limits<double>::infinity(), nullptr};
    const double y = std::max(std::log(measure(t) / tolerance), std::log(t->fillet.b / b_cap));
    return {x, y, t};
  };
  // the first point: back off (halving a) while Algorithm 1 fails
  Point cur = evaluate(std::log(a_start));
  for (int attempt = 0; attempt < 12 && !cur.trial; ++attempt) cur = evaluate(cur.x - std::log(2.0));
  if (!cur.trial) return fail("biclothoid (004 Algorithm 1) did not converge");
  Point prev{0, 0, nullptr};
  double lo = -std::numeric_limits<double>::infinity();  // y <= 0 here
  double hi = std::numeric_limits<double>::infinity();   // y > 0 (or no solution) here
  Trial* best = nullptr;  // the largest a with y <= 0 so far
  double best_y = 0;
  for (int it = 0; it < 60; ++it) {
    if (cur.y <= 0) {
      lo = std::max(lo, cur.x);
      if (!best || cur.trial->fillet.a >= best->fillet.a) {
        best = cur.trial;
        best_y = cur.y;
      }
      if (cur.y >= -kReached || cur.x >= x_cap - 1e-12) break;
    } else {
      hi = std::min(hi, cur.x);
    }
    // next x: Newton towards the middle of the accepted band (a at most halved or doubled),
    // else a secant step, else the slope guess; bisection when a bracketed step leaves the
    // bracket
    double next;
    const double slope = cur.trial && std::isfinite(cur.y) ? slope_at(*cur.trial) : 0.0;
    if (slope > 0 && std::isfinite(slope)) {
      next = cur.x - std::clamp((cur.y + 0.3 * kReached) / slope, -std::log(2.0), std::log(2.0));
    } else if (prev.trial && cur.trial && std::isfinite(prev.y) && cur.y != prev.y) {
      next = cur.x - (cur.y + 0.3 * kReached) * (cur.x - prev.x) / (cur.y - prev.y);
    } else if (std::isfinite(cur.y)) {
      next = cur.x - (cur.y + 0.3 * kReached) / p_guess;
    } else {
      next = cur.x - std::log(2.0);
    }
    if (std::isfinite(lo) && std::isfinite(hi)) {
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
      if (hi - lo < 1e-13) break;
    } else if (std::isfinite(hi) && !(next < hi)) {
      next = hi - std::log(2.0);
    } else if (std::isfinite(lo) && !(next > lo)) {
      next = lo + std::log(2.0);
    }
    next = std::min(next, x_cap);
    prev = cur;
    cur = evaluate(next);
  }
  if (!best) return fail("no biclothoid fillet met the tolerance (004 Algorithm 2)");
  // limited: the start cap or the end bound is what stops the fillet growing; otherwise the
  // deviation reached the tolerance band unless the iterations ran out
  const bool limited = best->fillet.a >= a_cap * (1 - 1e-12) ||
                       std::log(best->fillet.b / b_cap) >= std::log(measure(best) / tolerance) - 1e-12;
  result.limited = limited;
  result.converged = limited || best_y >= -kReached;
  measure(best);
  result.deviation = best->deviation;
  result.fillet = best->fillet;
  if (result.swapped) {
    result.fillet.curve = reversed(best->fillet.curve);
    result.fillet.a = best->fillet.b;
    result.fillet.b = best->fillet.a;
  }
  return result;
}

BiclothoidStartFit fit_biclothoid_from_start(const CornerShapes& shapes, double start_distance, double a_max,
                                             double b_max) {
  BiclothoidStartFit result;
  double a_cap = shapes.q1.kappa != 0 ? std::min(a_max, kMaxArcTurn / std::abs(shapes.q1.kappa)) : a_max;
  double b_cap = shapes.q2.kappa != 0 ? std::min(b_max, kMaxArcTurn / std::abs(shapes.q2.kappa)) : b_max;
  if (const auto meet = crossing(shapes.q1, shapes.q2, a_cap, b_cap)) {
    a_cap = std::min(a_cap, kCrossingMargin * meet->first);
    b_cap = std::min(b_cap, kCrossingMargin * meet->second);
  }
  using Limit = BiclothoidStartFit::Limit;
  // why the first (largest) start distance that failed did not fit
  Limit first_failure = Limit::kNone;
  const auto fits = [&](double a) -> std::optional<BiclothoidSolution> {
    auto sol = fit_biclothoid_at(shapes, a);
    if (!sol || sol->b > b_cap) {
      if (first_failure == Limit::kNone) first_failure = sol ? Limit::kOutgoing : Limit::kNoSolution;
      return std::nullopt;
    }
    return sol;
  };
  double a = std::min(start_distance, a_cap);
  if (a < start_distance) first_failure = Limit::kIncoming;
  std::optional<BiclothoidSolution> best = fits(a);
  if (!best) {
    // halve until a fillet fits, then bisect in log a between that and the last that did not
    double hi = a;
    for (int i = 0; i < 60 && !best; ++i) {
      hi = a;
      a *= 0.5;
      best = fits(a);
    }
    if (!best) {
      result.outcome = {Status::kNotConverged, "no biclothoid fillet fits at start distance " +
                                                   format_mm(start_distance) + " or any shorter (004 Algorithm 1)"};
      return result;
    }
    double lo = a;
    while (hi / lo > 1 + 1e-9) {
      const double mid = std::sqrt(lo * hi);
      if (auto sol = fits(mid)) {
        lo = mid;
        best = sol;
      } else {
        hi = mid;
      }
    }
  }
  result.fillet = *best;
  result.limit = best->a < start_distance * (1 - 1e-12) ? first_failure : Limit::kNone;
  result.deviation = biclothoid_deviation(*best, shapes);
  return result;
}

Vec3 to_space(const CornerPlane& plane, const Vec2& p) { return plane.origin + p.x() * plane.x + p.y() * plane.y; }

std::vector<Segment> to_segments(const Biclothoid& curve, const CornerPlane& plane) {
  std::vector<Segment> out;
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

PlanarCorner planar_corner(const Primitive& in, const Primitive& out) {
  PlanarCorner pc;
  const double len_in = length(in);
  const Vec3 corner = point(in, len_in);
  const Vec3 t1 = tangent(in, len_in);
  const Vec3 t2 = tangent(out, 0.0);
  pc.angle = angle_between(t1, t2);
  const Vec3 k1 = curvature_vector(in, len_in);
  const Vec3 k2 = curvature_vector(out, 0.0);
  pc.same_curvature = (k1 - k2).norm() <= 1e-9 * std::max({k1.norm(), k2.norm(), 1e-300});
  const Arc* arc1 = std::get_if<Arc>(&in);
  const Arc* arc2 = std::get_if<Arc>(&out);
  pc.lines = !arc1 && !arc2;
  if (arc1 && arc2) {
    pc.same_circle = (arc1->center - arc2->center).norm() <= 1e-9 * arc1->radius &&
                     std::abs(arc1->radius - arc2->radius) <= 1e-9 * arc1->radius && arc1->rise == 0 &&
                     arc2->rise == 0 &&
                     arc1->u.cross(arc1->v).cross(arc2->u.cross(arc2->v)).norm() <= kPlanarAngle;
  }

  // the plane normal: the arc's axis, or the lines' common normal oriented with the turn
  Vec3 normal;
  if (arc1) normal = arc1->u.cross(arc1->v).normalized();
  else if (arc2) normal = arc2->u.cross(arc2->v).normalized();
  else if (t1.cross(t2).norm() > 0) normal = t1.cross(t2).normalized();
  else normal = any_perpendicular(t1);

  // planar: no helix, every line in the plane, every arc axis along the normal
  pc.planar = true;
  for (const Primitive* prim : {&in, &out}) {
    if (const Arc* arc = std::get_if<Arc>(prim)) {
      if (arc->rise != 0 || arc->u.cross(arc->v).normalized().cross(normal).norm() > kPlanarAngle) pc.planar = false;
    } else {
      const Line& line = std::get<Line>(*prim);
      if (std::abs((line.p1 - line.p0).normalized().dot(normal)) > kPlanarAngle) pc.planar = false;
    }
  }

  pc.plane.origin = corner;
  pc.plane.x = (t1 - t1.dot(normal) * normal).normalized();
  pc.plane.y = normal.cross(pc.plane.x);
  const auto signed_curvature = [&](const Primitive& prim) {
    const Arc* arc = std::get_if<Arc>(&prim);
    if (!arc) return 0.0;
    return (arc->u.cross(arc->v).dot(normal) > 0 ? 1.0 : -1.0) / arc->radius;
  };
  pc.shapes.q1 = PlanarShape{0.0, signed_curvature(in)};
  pc.shapes.q2 = PlanarShape{std::atan2(t2.dot(pc.plane.y), t2.dot(pc.plane.x)), signed_curvature(out)};
  return pc;
}

std::optional<CornerFit> clothoid_special_case(const CornerInput& corner, const PlanarCorner& geometry) {
  CornerFit fit;
  fit.parameter_used = 0;
  // a reversal has no fillet: a kink that stops the path when Buffered (001, 003)
  if (geometry.angle >= kPi - kReversalAngle) {
    fit.case_name = geometry.same_circle ? "same_circle_opposite_direction" : "reversal";
    fit.stop = corner.buffer == BufferMode::kBuffered;
    fit.note = "the path reverses at the corner: no curvature-continuous transition exists, the corner stays a kink";
    return fit;
  }
  const bool tangent = geometry.angle <= kTangentAngle;
  // already G2: nothing to smooth
  if (tangent && geometry.same_curvature) {
    fit.case_name = geometry.same_circle ? "same_circle_same_direction" : "collinear";
    return fit;
  }
  // no length left on a move (consumed by the neighbouring corner): the corner stays as it is
  if (!(corner.in_available > 0) || !(corner.out_available > 0)) {
    fit.outcome = {Status::kInfeasible, corner.name + ": no length of the " +
                                            (corner.in_available > 0 ? "outgoing" : "incoming") +
                                            " move is left for a transition"};
    return fit;
  }
  if (corner.spec.parameter <= 0 && corner.spec.start_distance <= 0) {
    if (!tangent) {
      fail_at(corner.where, "transition.parameter",
              corner.name + ": a " + std::string(to_string(corner.spec.method)) +
                  " transition with maximum deviation 0 is impossible at a tangent discontinuity of " +
                  format_deg(geometry.angle) + "; give a positive deviation or use method none");
    }
    fit.case_name = "tangent";
    fit.note = "maximum deviation 0: the curvature jump is left as programmed";
    return fit;
  }
  return std::nullopt;
}

CornerFit fit_biclothoid_corner(const CornerInput& corner) {
  const PlanarCorner geometry = planar_corner(corner.in, corner.out);
  if (auto special = clothoid_special_case(corner, geometry)) return *special;
  const double tolerance = corner.spec.parameter;
  const double start_distance = corner.spec.start_distance;  // > 0: sized by it, not by tolerance
  CornerFit fit;
  fit.case_name = geometry.angle <= kTangentAngle ? "tangent" : "regular";

  // two lines: the symmetric fillet in closed form (004 section 7.1, 002 eq. 9), shrunk to
  // the shorter available length
  if (geometry.lines) {
    ClothoidPair pair = start_distance > 0 ? clothoid_pair_for_tangent_length(geometry.angle, start_distance)
                                           : clothoid_pair_for_deviation(geometry.angle, tolerance);
    const double available = std::min(corner.in_available, corner.out_available);
    if (pair.tangent_length > available) {
      const double asked = start_distance > 0 ? start_distance : tolerance;
      pair = clothoid_pair_for_tangent_length(geometry.angle, available);
      fit.note = std::string(start_distance > 0 ? "start distance" : "deviation") + " shrunk from " +
                 format_mm(asked) + " to " + format_mm(start_distance > 0 ? pair.tangent_length : pair.deviation) +
                 ": the " + (corner.in_available <= corner.out_available ? "incoming" : "outgoing") + " move is short";
    }
    const Posture start{Vec2(-pair.tangent_length, 0.0), 0.0, 0.0};
    fit.transition = to_segments(make_biclothoid(start, pair.sharpness, pair.half_length, pair.half_length),
                                 geometry.plane);
    fit.trim_in = pair.tangent_length;
    fit.trim_out = pair.tangent_length;
    fit.parameter_used = start_distance > 0 ? pair.tangent_length : pair.deviation;
    return fit;
  }

  // 004 has no 3D form: a non-planar corner goes to the Bezier method (000, quartic in 3D),
  // with its transition parameter set to the tolerance (a fillet that starts and ends within
  // that distance of the corner deviates less than it)
  if (!geometry.planar) {
    CornerFit bezier = fit_bezier_corner(corner);
    bezier.case_name = "non_planar";
    bezier.fallback = "bezier";
    if (!bezier.outcome.ok()) {
      bezier.outcome.message = "non-planar corner, Bezier fallback failed: " + bezier.outcome.message;
    }
    return bezier;
  }

  // 004 Algorithm 1 at the given start distance
  if (start_distance > 0) {
    const BiclothoidStartFit start_fit =
        fit_biclothoid_from_start(geometry.shapes, start_distance, corner.in_available, corner.out_available);
    if (!start_fit.outcome.ok()) {
      fit.outcome = start_fit.outcome;
      fit.outcome.message = corner.name + ": " + fit.outcome.message;
      return fit;
    }
    fit.transition = to_segments(start_fit.fillet.curve, geometry.plane);
    fit.trim_in = start_fit.fillet.a;
    fit.trim_out = start_fit.fillet.b;
    fit.parameter_used = start_fit.fillet.a;
    using Limit = BiclothoidStartFit::Limit;
    if (start_fit.limit != Limit::kNone) {
      const char* why = start_fit.limit == Limit::kIncoming
                            ? "limited by the incoming move (or an eighth of a turn of its arc)"
                        : start_fit.limit == Limit::kOutgoing
                            ? "the fillet must end within the outgoing move (or an eighth of a turn of its arc)"
                            : "004 Algorithm 1 found no fillet starting further out";
      fit.note = "start distance shrunk from " + format_mm(start_distance) + " to " + format_mm(start_fit.fillet.a) +
                 ": " + why;
    }
    return fit;
  }

  // 004 Algorithms 1 and 2 in the corner plane
  const BiclothoidToleranceFit tol_fit =
      fit_biclothoid_with_tolerance(geometry.shapes, tolerance, corner.in_available, corner.out_available);
  if (!tol_fit.outcome.ok()) {
    fit.outcome = tol_fit.outcome;
    fit.outcome.message = corner.name + ": " + fit.outcome.message;
    return fit;
  }
  fit.transition = to_segments(tol_fit.fillet.curve, geometry.plane);
  fit.trim_in = tol_fit.fillet.a;
  fit.trim_out = tol_fit.fillet.b;
  fit.parameter_used = tol_fit.deviation.max();
  if (tol_fit.limited) {
    fit.note = "deviation " + format_mm(fit.parameter_used) + " below the tolerance " + format_mm(tolerance) +
               ": the fillet is limited by the move lengths (or an eighth of a turn of an arc)";
  } else if (!tol_fit.converged) {
    fit.note = "deviation " + format_mm(fit.parameter_used) + " below the tolerance " + format_mm(tolerance) +
               ": the tolerance loop (004 Algorithm 2) stopped before reaching it";
  }
  return fit;
}

}  // namespace blendbench
