#include "blendbench/geometry/segment.hpp"

#include "blendbench/core/golden.hpp"
#include "blendbench/geometry/phase_series.hpp"
#include "blendbench/core/overloaded.hpp"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>

namespace blendbench {
namespace {

// 10-point Gauss-Legendre nodes and weights on [-1, 1] (symmetric half).
constexpr std::array<double, 5> kGlNodes = {0.1488743389816312, 0.4333953941292472, 0.6794095682990244,
                                            0.8650633666889845, 0.9739065285171717};
constexpr std::array<double, 5> kGlWeights = {0.2955242247147529, 0.2692667193099963, 0.2190863625159820,
                                              0.1494513491505806, 0.0666713443086881};

// Integral of f over [a, b] by 10-point Gauss-Legendre.
template <class F>
double gauss_legendre(const F& f, double a, double b) {
  const double mid = 0.5 * (a + b);
  const double half = 0.5 * (b - a);
  double sum = 0;
  for (std::size_t i = 0; i < kGlNodes.size(); ++i) {
    const double dx = half * kGlNodes[i];
    sum += kGlWeights[i] * (f(mid - dx) + f(mid + dx));
  }
  return sum * half;
}

// clothoid_xy: largest phase excursion |kappa(m) t + c t^2 / 2| on a panel; with 1 the Taylor
// terms decay like 1/n! and summing them loses at most a factor e in rounding.
constexpr double kClothoidPanelPhase = 1.0;

double clamp_s(double s, double len) { return std::clamp(s, 0.0, len); }

// Helix helpers: b = rise per radian along w.
double arc_pitch(const Arc& arc) { return arc.rise / arc.sweep; }
// ds/dphi; of a planar arc its radius's magnitude, which is what hypot(r, +-0) returns, without
// the call (an arc's length, points and tangents take it several times per corner fit)
double arc_speed(const Arc& arc) {
  if (arc.rise == 0 && arc.sweep != 0) return std::abs(arc.radius);
  return std::hypot(arc.radius, arc_pitch(arc));
}

// Derivative control points (hodograph) of a Bezier curve.
std::vector<Vec3> hodograph(const std::vector<Vec3>& p) {
  std::vector<Vec3> d;
  const int n = static_cast<int>(p.size()) - 1;
  d.reserve(static_cast<std::size_t>(std::max(n, 0)));
  for (int i = 0; i < n; ++i) d.push_back(n * (p[static_cast<std::size_t>(i) + 1] - p[static_cast<std::size_t>(i)]));
  return d;
}

// de Casteljau evaluation (degree <= 6, so a fixed-size scratch array suffices).
Vec3 bernstein(const std::vector<Vec3>& p, double u) {
  if (p.empty()) return Vec3::Zero();
  std::array<Vec3, 7> q;
  const std::size_t n = p.size();
  std::copy(p.begin(), p.end(), q.begin());
  for (std::size_t level = 1; level < n; ++level) {
    for (std::size_t i = 0; i + level < n; ++i) q[i] = (1 - u) * q[i] + u * q[i + 1];
  }
  return q[0];
}

// gauss_legendre of the speed |d1(u)| of a Bezier with hodograph h (N points) over [a, b], its
// ten nodes evaluated together: de Casteljau on the stored points, component by component
// across the nodes (no copies of the points per node, loops of fixed length), with the very
// operations and order of bernstein, Eigen's norm ((x^2 + y^2) + z^2, then sqrt) and
// gauss_legendre's sum, so the table is the same bit for bit.
template <std::size_t N>
double panel_length_n(const std::vector<Vec3>& h, double a, double b) {
  constexpr std::size_t kNodes = 2 * kGlNodes.size();
  const double mid = 0.5 * (a + b);
  const double half = 0.5 * (b - a);
  std::array<double, kNodes> u;
  std::array<double, kNodes> v;  // 1 - u
  for (std::size_t i = 0; i < kGlNodes.size(); ++i) {
    const double dx = half * kGlNodes[i];
    u[2 * i] = mid - dx;
    u[2 * i + 1] = mid + dx;
  }
  for (std::size_t j = 0; j < kNodes; ++j) v[j] = 1 - u[j];
  std::array<std::array<double, kNodes>, 3> d;  // d1 at each node, by component
  for (std::size_t c = 0; c < 3; ++c) {
    std::array<std::array<double, kNodes>, N> q;
    for (std::size_t i = 0; i < N; ++i) q[i].fill(h[i][static_cast<Eigen::Index>(c)]);
    for (std::size_t level = 1; level < N; ++level) {
      for (std::size_t i = 0; i + level < N; ++i) {
        for (std::size_t j = 0; j < kNodes; ++j) q[i][j] = v[j] * q[i][j] + u[j] * q[i + 1][j];
      }
    }
    d[c] = q[0];
  }
  std::array<double, kNodes> speed;
  for (std::size_t j = 0; j < kNodes; ++j) speed[j] = std::sqrt(d[0][j] * d[0][j] + d[1][j] * d[1][j] + d[2][j] * d[2][j]);
  double sum = 0;
  for (std::size_t i = 0; i < kGlNodes.size(); ++i) sum += kGlWeights[i] * (speed[2 * i] + speed[2 * i + 1]);
  return sum * half;
}
double panel_length(const std::vector<Vec3>& h, double a, double b) {
  switch (h.size()) {
    case 1: return panel_length_n<1>(h, a, b);
    case 2: return panel_length_n<2>(h, a, b);
    case 3: return panel_length_n<3>(h, a, b);
    case 4: return panel_length_n<4>(h, a, b);
    case 5: return panel_length_n<5>(h, a, b);
    case 6: return panel_length_n<6>(h, a, b);
    default: return 0;  // no hodograph (one control point), or past the degree-6 limit asserted by Bezier
  }
}

// Golden-section maximisation of f on [a, b] after a scan of `samples` points.
template <class F>
double scan_max(const F& f, double a, double b, int samples) {
  if (b <= a) return f(a);
  double best = -1;
  double best_x = a;
  const double h = (b - a) / samples;
  for (int i = 0; i <= samples; ++i) {
    const double x = a + h * i;
    const double fx = f(x);
    if (fx > best) {
      best = fx;
      best_x = x;
    }
  }
  // refine around the best sample
  double lo = std::max(a, best_x - h);
  double hi = std::min(b, best_x + h);
  const auto refined = golden_minimum([&f](double x) { return -f(x); }, lo, hi, 1e-14 * (b - a), 60);
  return std::max(best, -refined.second);
}

}  // namespace

Segment to_segment(const Primitive& primitive) {
  return std::visit([](const auto& p) -> Segment { return p; }, primitive);
}

// ---- Line

double length(const Line& line) { return (line.p1 - line.p0).norm(); }

Vec3 point(const Line& line, double s) {
  const double len = length(line);
  if (len <= 0) return line.p0;
  return line.p0 + (line.p1 - line.p0) * (clamp_s(s, len) / len);
}

Vec3 tangent(const Line& line, double /*s*/) {
  const Vec3 d = line.p1 - line.p0;
  const double len = d.norm();
  return len > 0 ? Vec3(d / len) : Vec3::Zero();
}

Vec3 curvature_vector(const Line& /*line*/, double /*s*/) { return Vec3::Zero(); }

Line sub_segment(const Line& line, double s0, double s1) { return Line{point(line, s0), point(line, s1)}; }

// ---- Arc (and helix)

double length(const Arc& arc) { return arc.sweep * arc_speed(arc); }

// From the arc's start, not its centre. The blend of a nearly straight corner has a radius of
// hundreds of metres or more (a corner distance over tan(theta / 2)), and centre + radius
// (cos phi, sin phi) rounds every point by about eps times the radius, differently for each s:
// noise that the third differences of a sampled path read as jerk (at 351 m, 1e-6 of a
// 171 m/s^3 limit at 1 ms; at 10^7 m it would be nanometres of position). The start is rounded
// once, the same for every s, and the offset from it is of the size of the arc length; its
// 1 - cos phi is 2 sin^2(phi / 2), without the cancellation, from one sine and cosine of phi / 2.
Vec3 point(const Arc& arc, double s) {
  const double phi = clamp_s(s, length(arc)) / arc_speed(arc);
  const double sh = std::sin(0.5 * phi);
  const double ch = std::cos(0.5 * phi);
  const Vec3 start = arc.center + arc.radius * arc.u;
  return start + arc.radius * (2 * sh * ch * arc.v - 2 * sh * sh * arc.u) + arc_pitch(arc) * phi * arc.u.cross(arc.v);
}

namespace {
// An arc's angle phi at arc length s (clamped), g = ds/dphi.
double arc_angle(const Arc& arc, double s, double g) { return clamp_s(s, length(arc)) / g; }
// Its unit tangent and curvature vector at phi, from sin(phi) and cos(phi): d2p/dphi2 is radial,
// divided by (ds/dphi)^2.
Vec3 arc_tangent(const Arc& arc, double g, double sn, double cs) {
  const Vec3 d = arc.radius * (-sn * arc.u + cs * arc.v) + arc_pitch(arc) * arc.u.cross(arc.v);
  return d / g;
}
Vec3 arc_curvature(const Arc& arc, double g, double sn, double cs) {
  return -arc.radius * (cs * arc.u + sn * arc.v) / (g * g);
}
}  // namespace

Vec3 tangent(const Arc& arc, double s) {
  const double g = arc_speed(arc);
  const double phi = arc_angle(arc, s, g);
  return arc_tangent(arc, g, std::sin(phi), std::cos(phi));
}

Vec3 curvature_vector(const Arc& arc, double s) {
  const double g = arc_speed(arc);
  const double phi = arc_angle(arc, s, g);
  return arc_curvature(arc, g, std::sin(phi), std::cos(phi));
}

Arc sub_segment(const Arc& arc, double s0, double s1) {
  const double g = arc_speed(arc);
  const double len = length(arc);
  const double phi0 = clamp_s(s0, len) / g;
  const double phi1 = clamp_s(s1, len) / g;
  Arc out = arc;
  const Vec3 w = arc.u.cross(arc.v);
  out.u = std::cos(phi0) * arc.u + std::sin(phi0) * arc.v;
  out.v = -std::sin(phi0) * arc.u + std::cos(phi0) * arc.v;
  out.center = arc.center + arc_pitch(arc) * phi0 * w;
  out.sweep = phi1 - phi0;
  out.rise = arc_pitch(arc) * out.sweep;
  return out;
}

// ---- Bezier

Bezier::Bezier(std::vector<Vec3> control_points)
    : ctrl_(std::move(control_points)), h1_(hodograph(ctrl_)), h2_(hodograph(h1_)), h3_(hodograph(h2_)) {
  assert(ctrl_.size() >= 2 && ctrl_.size() <= 7);
  // table: breakpoints uniform in u; the speed of the fillets used here varies slowly enough
  // that 64 panels of 10-point Gauss-Legendre give lengths accurate to ~1e-15 relative.
  constexpr int kPanels = 64;
  knots_u_.resize(kPanels + 1);
  knots_s_.resize(kPanels + 1);
  knots_u_[0] = 0;
  knots_s_[0] = 0;
  for (int i = 1; i <= kPanels; ++i) {
    const auto k = static_cast<std::size_t>(i);
    knots_u_[k] = static_cast<double>(i) / kPanels;
    knots_s_[k] = knots_s_[k - 1] + panel_length(h1_, knots_u_[k - 1], knots_u_[k]);
  }
}

Vec3 Bezier::eval(double u) const { return bernstein(ctrl_, u); }
Vec3 Bezier::d1(double u) const { return bernstein(h1_, u); }
Vec3 Bezier::d2(double u) const { return bernstein(h2_, u); }
Vec3 Bezier::d3(double u) const { return bernstein(h3_, u); }

double Bezier::length_to(double u) const {
  u = std::clamp(u, 0.0, 1.0);
  const auto it = std::upper_bound(knots_u_.begin(), knots_u_.end(), u);
  const auto k = static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - knots_u_.begin() - 1, 0));
  if (k + 1 >= knots_u_.size()) return knots_s_.back();
  return knots_s_[k] + gauss_legendre([this](double x) { return d1(x).norm(); }, knots_u_[k], u);
}

double Bezier::parameter_at(double s) const {
  const double len = length();
  s = clamp_s(s, len);
  if (s <= 0) return 0;
  if (s >= len) return 1;
  // bracket in the table, then safeguarded Newton on length_to(u) = s
  const auto it = std::upper_bound(knots_s_.begin(), knots_s_.end(), s);
  const auto k = static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - knots_s_.begin() - 1, 0));
  double lo = knots_u_[k];
  double hi = knots_u_[std::min(k + 1, knots_u_.size() - 1)];
  double u = lo + (hi - lo) * (s - knots_s_[k]) / std::max(knots_s_[k + 1] - knots_s_[k], 1e-300);
  for (int it_n = 0; it_n < 50; ++it_n) {
    const double f = length_to(u) - s;
    if (std::abs(f) <= 1e-14 * len) break;
    if (f > 0) hi = u; else lo = u;
    double next = u - f / d1(u).norm();
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    u = next;
  }
  return u;
}

double length(const Bezier& bezier) { return bezier.length(); }
Vec3 point(const Bezier& bezier, double s) { return bezier.eval(bezier.parameter_at(s)); }
Vec3 tangent(const Bezier& bezier, double s) { return bezier.d1(bezier.parameter_at(s)).normalized(); }

Vec3 curvature_vector(const Bezier& bezier, double s) {
  const double u = bezier.parameter_at(s);
  const Vec3 c1 = bezier.d1(u);
  const Vec3 c2 = bezier.d2(u);
  const double g2 = c1.squaredNorm();
  // component of C'' normal to C', divided by |C'|^2
  return (c2 - c1 * (c1.dot(c2) / g2)) / g2;
}

namespace {

double bezier_sharpness_at_u(const Bezier& bezier, double u) {
  const Vec3 c1 = bezier.d1(u);
  const Vec3 c2 = bezier.d2(u);
  const Vec3 c3 = bezier.d3(u);
  const Vec3 cross = c1.cross(c2);
  const double a = cross.norm();
  const double g = c1.norm();
  const double dg = c1.dot(c2) / g;
  const double da = a > 0 ? cross.dot(c1.cross(c3)) / a : c1.cross(c3).norm();
  const double dkappa_du = da / (g * g * g) - 3 * a * dg / (g * g * g * g);
  return std::abs(dkappa_du / g);
}

// d^3 p / ds^3 of a Bezier at parameter u, from its derivatives r1, r2, r3 in u: with
// sigma = |r1|, n = r2 sigma - r1 sigma', p_ss = n / sigma^3 and
// p_sss = n' / sigma^4 - 3 n sigma' / sigma^5, n' = r3 sigma - r1 sigma''.
Vec3 bezier_curvature_derivative_at_u(const Bezier& bezier, double u) {
  const Vec3 r1 = bezier.d1(u);
  const Vec3 r2 = bezier.d2(u);
  const Vec3 r3 = bezier.d3(u);
  const double sigma = r1.norm();
  const double sigma1 = r1.dot(r2) / sigma;
  const double sigma2 = (r2.squaredNorm() + r1.dot(r3) - sigma1 * sigma1) / sigma;
  const Vec3 n = r2 * sigma - r1 * sigma1;
  const Vec3 n1 = r3 * sigma - r1 * sigma2;
  const double s2 = sigma * sigma;
  return n1 / (s2 * s2) - 3.0 * sigma1 * n / (s2 * s2 * sigma);
}

// |d^3p/ds^3 + kappa^2 T| of a Bezier at u: the part normal to the tangent.
double bezier_spatial_sharpness_at_u(const Bezier& bezier, double u) {
  const Vec3 r1 = bezier.d1(u);
  const Vec3 r2 = bezier.d2(u);
  const double g2 = r1.squaredNorm();
  const Vec3 k = (r2 - r1 * (r1.dot(r2) / g2)) / g2;
  return (bezier_curvature_derivative_at_u(bezier, u) + k.squaredNorm() * r1 / std::sqrt(g2)).norm();
}

}  // namespace

// ---- Clothoid

Eigen::Vector2d clothoid_xy(double kappa0, double sharpness, double s) {
  return clothoid_displacement(0.0, kappa0, sharpness, s);
}

Eigen::Vector2d clothoid_displacement(double theta0, double kappa0, double sharpness, double s) {
  if (!(s > 0)) return Eigen::Vector2d::Zero();
  // panels of half-width h around midpoints m, the local phase kappa(m) t + c t^2 / 2 (|t| <= h)
  // bounded by kClothoidPanelPhase
  const double kappa_max = std::max(std::abs(kappa0), std::abs(kappa0 + sharpness * s));
  const double phase = 0.5 * kappa_max * s + 0.125 * std::abs(sharpness) * s * s;
  const int panels = std::max(1, static_cast<int>(std::ceil(phase / kClothoidPanelPhase)));
  const double h = 0.5 * s / panels;
  double x = 0;
  double y = 0;
  for (int j = 0; j < panels; ++j) {
    const double m = h * (2 * j + 1);
    const double beta = (kappa0 + sharpness * m) * h;  // kappa(m) h
    const double gamma = sharpness * h * h;            // c h^2
    // int_{-1}^{1} exp(i (beta u + gamma u^2 / 2)) du = 2 sum_{n even} e_n / (n + 1), with the
    // Taylor coefficients e_n of the integrand (series::PhaseTaylor). Once two consecutive
    // coefficients are below 1e-18 (the sum is about 1) the rest are too, because
    // n + 1 > |beta| + |gamma| from then on.
    series::PhaseTaylor e{.b = beta, .g = gamma};
    double sum_re = 1;
    double sum_im = 0;
    for (std::size_t n = 0; n + 3 < series::kInverse.size(); n += 2) {
      e.step_two(n);
      sum_re += e.re * series::kInverse[n + 3];
      sum_im += e.im * series::kInverse[n + 3];
      if (e.below(1e-18)) break;
    }
    // rotate by the tangent angle at the midpoint
    const double theta = theta0 + (kappa0 + 0.5 * sharpness * m) * m;
    const double cs = std::cos(theta);
    const double sn = std::sin(theta);
    x += cs * sum_re - sn * sum_im;
    y += sn * sum_re + cs * sum_im;
  }
  return Eigen::Vector2d(2 * h * x, 2 * h * y);
}

double length(const Clothoid& clothoid) { return clothoid.length; }

Vec3 point(const Clothoid& c, double s) {
  const Eigen::Vector2d xy = clothoid_xy(c.kappa0, c.sharpness, clamp_s(s, c.length));
  return c.origin + xy.x() * c.e1 + xy.y() * c.e2;
}

Vec3 tangent(const Clothoid& c, double s) {
  s = clamp_s(s, c.length);
  const double theta = c.kappa0 * s + 0.5 * c.sharpness * s * s;
  return std::cos(theta) * c.e1 + std::sin(theta) * c.e2;
}

Vec3 curvature_vector(const Clothoid& c, double s) {
  s = clamp_s(s, c.length);
  const double theta = c.kappa0 * s + 0.5 * c.sharpness * s * s;
  const double kappa = c.kappa0 + c.sharpness * s;
  return kappa * (-std::sin(theta) * c.e1 + std::cos(theta) * c.e2);
}

// ---- Segment dispatch

double length(const Segment& segment) {
  return std::visit([](const auto& x) { return length(x); }, segment);
}
double length(const Primitive& primitive) {
  return std::visit([](const auto& x) { return length(x); }, primitive);
}
Vec3 point(const Segment& segment, double s) {
  return std::visit([s](const auto& x) { return point(x, s); }, segment);
}
Vec3 point(const Primitive& primitive, double s) {
  return std::visit([s](const auto& x) { return point(x, s); }, primitive);
}
Vec3 tangent(const Segment& segment, double s) {
  return std::visit([s](const auto& x) { return tangent(x, s); }, segment);
}
Vec3 tangent(const Primitive& primitive, double s) {
  return std::visit([s](const auto& x) { return tangent(x, s); }, primitive);
}
Vec3 curvature_vector(const Segment& segment, double s) {
  return std::visit([s](const auto& x) { return curvature_vector(x, s); }, segment);
}
Vec3 curvature_vector(const Primitive& primitive, double s) {
  return std::visit([s](const auto& x) { return curvature_vector(x, s); }, primitive);
}

TangentCurvature tangent_and_curvature(const Primitive& primitive, double s) {
  if (const Arc* arc = std::get_if<Arc>(&primitive)) {
    // tangent and curvature_vector from one sine and cosine
    const double g = arc_speed(*arc);
    const double phi = arc_angle(*arc, s, g);
    // at the arc's start (where a corner's outgoing arc is asked) the sine and cosine are exact
    // without the call
    const bool start = phi == 0;
    const double sn = start ? 0.0 : std::sin(phi);
    const double cs = start ? 1.0 : std::cos(phi);
    return {arc_tangent(*arc, g, sn, cs), arc_curvature(*arc, g, sn, cs)};
  }
  return {tangent(primitive, s), curvature_vector(primitive, s)};
}

Primitive sub_segment(const Primitive& primitive, double s0, double s1) {
  return std::visit([s0, s1](const auto& x) -> Primitive { return sub_segment(x, s0, s1); }, primitive);
}

Vec3 start_point(const Segment& segment) { return point(segment, 0.0); }
Vec3 end_point(const Segment& segment) { return point(segment, length(segment)); }

Vec3 curvature_derivative(const Segment& segment, double s) {
  return std::visit(
      Overloaded{
          [](const Line&) -> Vec3 { return Vec3::Zero(); },
          [s](const Arc& a) -> Vec3 {
            // kappa N = -(r / g^2) radial(phi), phi = s / g: its derivative is -(r / g^3) d radial/dphi
            const double g = arc_speed(a);
            const double phi = clamp_s(s, length(a)) / g;
            return -a.radius / (g * g * g) * (-std::sin(phi) * a.u + std::cos(phi) * a.v);
          },
          [s](const Bezier& b) -> Vec3 { return bezier_curvature_derivative_at_u(b, b.parameter_at(s)); },
          [s](const Clothoid& c) -> Vec3 {
            // kappa n with n = (-sin, cos)(theta): (kappa n)' = c n - kappa^2 T
            const double x = clamp_s(s, c.length);
            const double theta = c.kappa0 * x + 0.5 * c.sharpness * x * x;
            const double kappa = c.kappa0 + c.sharpness * x;
            const Vec3 t = std::cos(theta) * c.e1 + std::sin(theta) * c.e2;
            const Vec3 n = -std::sin(theta) * c.e1 + std::cos(theta) * c.e2;
            return c.sharpness * n - kappa * kappa * t;
          },
      },
      segment);
}

SegmentFrame frame(const Segment& segment, double s) {
  if (const auto* b = std::get_if<Bezier>(&segment)) {
    const double u = b->parameter_at(s);
    const Vec3 c1 = b->d1(u);
    const Vec3 c2 = b->d2(u);
    const double g2 = c1.squaredNorm();
    return {b->eval(u), c1 / std::sqrt(g2), (c2 - c1 * (c1.dot(c2) / g2)) / g2, bezier_curvature_derivative_at_u(*b, u)};
  }
  return {point(segment, s), tangent(segment, s), curvature_vector(segment, s), curvature_derivative(segment, s)};
}

double sharpness(const Segment& segment, double s) {
  return std::visit(Overloaded{
                        [](const Line&) { return 0.0; },
                        [](const Arc&) { return 0.0; },
                        [s](const Bezier& b) { return bezier_sharpness_at_u(b, b.parameter_at(s)); },
                        [](const Clothoid& c) { return std::abs(c.sharpness); },
                    },
                    segment);
}

double max_curvature(const Segment& segment, double s0, double s1) {
  const double len = length(segment);
  s0 = clamp_s(s0, len);
  s1 = clamp_s(s1, len);
  if (s1 < s0) std::swap(s0, s1);
  return std::visit(
      Overloaded{
          [](const Line&) { return 0.0; },
          [](const Arc& a) { return a.radius / (a.radius * a.radius + arc_pitch(a) * arc_pitch(a)); },
          [s0, s1](const Bezier& b) {
            const double u0 = b.parameter_at(s0);
            const double u1 = b.parameter_at(s1);
            return scan_max(
                [&b](double u) {
                  const Vec3 c1 = b.d1(u);
                  return c1.cross(b.d2(u)).norm() / std::pow(c1.norm(), 3);
                },
                u0, u1, 64);
          },
          [s0, s1](const Clothoid& c) {
            return std::max(std::abs(c.kappa0 + c.sharpness * s0), std::abs(c.kappa0 + c.sharpness * s1));
          },
      },
      segment);
}

double max_sharpness(const Segment& segment, double s0, double s1) {
  const double len = length(segment);
  s0 = clamp_s(s0, len);
  s1 = clamp_s(s1, len);
  if (s1 < s0) std::swap(s0, s1);
  return std::visit(Overloaded{
                        [](const Line&) { return 0.0; },
                        [](const Arc&) { return 0.0; },
                        [s0, s1](const Bezier& b) {
                          return scan_max([&b](double u) { return bezier_sharpness_at_u(b, u); },
                                          b.parameter_at(s0), b.parameter_at(s1), 64);
                        },
                        [](const Clothoid& c) { return std::abs(c.sharpness); },
                    },
                    segment);
}

double max_spatial_sharpness(const Segment& segment, double s0, double s1) {
  const double len = length(segment);
  s0 = clamp_s(s0, len);
  s1 = clamp_s(s1, len);
  if (s1 < s0) std::swap(s0, s1);
  return std::visit(Overloaded{
                        [](const Line&) { return 0.0; },
                        [](const Arc& a) {
                          // kappa tau = r |b| / g^4 (b the rise per radian, g = ds/dphi)
                          const double g = arc_speed(a);
                          return a.radius * std::abs(arc_pitch(a)) / (g * g * g * g);
                        },
                        [s0, s1](const Bezier& b) {
                          return scan_max([&b](double u) { return bezier_spatial_sharpness_at_u(b, u); },
                                          b.parameter_at(s0), b.parameter_at(s1), 64);
                        },
                        [](const Clothoid& c) { return std::abs(c.sharpness); },
                    },
                    segment);
}

}  // namespace blendbench
