#include "blendbench/program/orientation.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "blendbench/core/overloaded.hpp"

namespace blendbench {
namespace {

// Below this angle (rad) the series forms are used (their next terms are below 1e-17).
constexpr double kSmallAngle = 1e-4;
// The difference step of rotation_bounds, as a share of the interval: small against the
// functions' scale (a quintic over the transition), large against rounding (whose noise in a
// second difference is eps |rho| / h^2, far below |rho''| ~ |rho| / L^2 at this share).
constexpr double kDifferenceShare = 1e-3;

Mat3 hat(const Vec3& v) {
  Mat3 m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

// The left Jacobian of SO(3): d/dx exp(phi(x)) = hat(J_l(phi) phi') exp(phi(x)).
Mat3 left_jacobian(const Vec3& phi) {
  const double theta = phi.norm();
  double b = 0.5 - theta * theta / 24;  // (1 - cos theta) / theta^2
  double c = 1.0 / 6 - theta * theta / 120;  // (theta - sin theta) / theta^3
  if (theta >= kSmallAngle) {
    b = (1 - std::cos(theta)) / (theta * theta);
    c = (theta - std::sin(theta)) / (theta * theta * theta);
  }
  const Mat3 k = hat(phi);
  return Mat3::Identity() + b * k + c * k * k;
}

// The quintic smooth step and its first two derivatives in u.
struct Weight {
  double w, dw, ddw;
};
Weight smooth_step(double u) {
  u = std::clamp(u, 0.0, 1.0);
  const double u2 = u * u;
  return {u2 * u * (10 - 15 * u + 6 * u2), 30 * u2 * (1 - 2 * u + u2), 60 * u * (1 - 3 * u + 2 * u2)};
}

// phi(x) and phi'(x) of a transition (orientation.hpp).
std::pair<Vec3, Vec3> blend_phi(const BlendOrientation& b, double x) {
  const Weight w = smooth_step(x / b.length);
  const Vec3 in = (x - b.lead_in) * b.rate_in;
  const Vec3 out = (x - b.length + b.lead_out) * b.rate_out;
  const Vec3 phi = (1 - w.w) * in + w.w * out;
  const Vec3 dphi = (1 - w.w) * b.rate_in + w.w * b.rate_out + (w.dw / b.length) * (out - in);
  return {phi, dphi};
}

}  // namespace

// The natural cubic spline's second derivatives M_k from the tridiagonal system
//   h_{k-1} M_{k-1} + 2 (h_{k-1} + h_k) M_k + h_k M_{k+1} = 6 (d_k - d_{k-1}),  M_0 = M_{n-1} = 0,
// h_k = knot[k+1] - knot[k], d_k = (value[k+1] - value[k]) / h_k; diagonally dominant, so the
// Thomas algorithm (elimination without pivoting) is stable.
OrientationSpline::OrientationSpline(Quat reference, std::vector<double> knots, std::vector<Vec3> values)
    : reference_(reference.normalized()), knots_(std::move(knots)), values_(std::move(values)) {
  const std::size_t n = knots_.size();
  if (n < 2 || values_.size() != n) throw std::invalid_argument("orientation spline: needs two or more knots and a value at each");
  for (std::size_t k = 0; k + 1 < n; ++k) {
    if (!(knots_[k + 1] > knots_[k])) throw std::invalid_argument("orientation spline: knots must increase strictly");
  }
  second_.assign(n, Vec3::Zero());
  if (n == 2) return;
  const auto h = [&](std::size_t k) { return knots_[k + 1] - knots_[k]; };
  const auto d = [&](std::size_t k) { return Vec3((values_[k + 1] - values_[k]) / h(k)); };
  // forward elimination over the interior knots 1..n-2
  std::vector<double> diag(n, 0.0);
  std::vector<Vec3> rhs(n, Vec3::Zero());
  for (std::size_t k = 1; k + 1 < n; ++k) {
    diag[k] = 2 * (h(k - 1) + h(k));
    rhs[k] = 6 * (d(k) - d(k - 1));
    if (k > 1) {
      const double f = h(k - 1) / diag[k - 1];
      diag[k] -= f * h(k - 1);
      rhs[k] -= f * rhs[k - 1];
    }
  }
  for (std::size_t k = n - 2; k >= 1; --k) {
    second_[k] = (rhs[k] - h(k) * second_[k + 1]) / diag[k];
  }
}

std::pair<Vec3, Vec3> OrientationSpline::at(double s) const {
  s = std::clamp(s, knots_.front(), knots_.back());
  const auto upper = std::upper_bound(knots_.begin(), knots_.end(), s);
  const std::size_t k = std::min<std::size_t>(static_cast<std::size_t>(std::max<std::ptrdiff_t>(upper - knots_.begin(), 1)) - 1, knots_.size() - 2);
  const double h = knots_[k + 1] - knots_[k];
  const double a = (knots_[k + 1] - s) / h;  // 1 at knot k, 0 at knot k+1
  const double b = 1 - a;
  const Vec3& m0 = second_[k];
  const Vec3& m1 = second_[k + 1];
  const Vec3 phi = a * values_[k] + b * values_[k + 1] + (h * h / 6) * ((a * a * a - a) * m0 + (b * b * b - b) * m1);
  const Vec3 dphi = (values_[k + 1] - values_[k]) / h + (h / 6) * ((1 - 3 * a * a) * m0 + (3 * b * b - 1) * m1);
  return {phi, dphi};
}

Vec3 rotation_log(const Quat& q_in) {
  const Quat q = q_in.w() < 0 ? Quat(-q_in.w(), -q_in.x(), -q_in.y(), -q_in.z()) : q_in;
  const Vec3 v = q.vec();
  const double s = v.norm();
  if (s < kSmallAngle) return v * (2 / q.w()) * (1 - s * s / (3 * q.w() * q.w()));  // 2 atan(s/w)/s series
  return v * (2 * std::atan2(s, q.w()) / s);
}

Quat rotation_exp(const Vec3& r) {
  const double theta = r.norm();
  const double half = 0.5 * theta;
  const double k = theta < kSmallAngle ? 0.5 - theta * theta / 48 : std::sin(half) / theta;
  Quat q(std::cos(half), k * r.x(), k * r.y(), k * r.z());
  q.normalize();
  return q;
}

double rotation_angle(const Quat& a, const Quat& b) { return rotation_log(b * a.conjugate()).norm(); }

Quat orientation_at(const PieceOrientation& piece, double sigma) {
  return std::visit(Overloaded{
                        [&](const GeodesicOrientation& g) { return Quat((rotation_exp(sigma * g.rate) * g.start).normalized()); },
                        [&](const BlendOrientation& b) {
                          return Quat((rotation_exp(blend_phi(b, b.offset + sigma).first) * b.corner).normalized());
                        },
                        [&](const SplineOrientation& c) {
                          return Quat((rotation_exp(c.spline->at(c.offset + sigma).first) * c.spline->reference()).normalized());
                        },
                    },
                    piece.law);
}

Vec3 angular_rate_at(const PieceOrientation& piece, double sigma) {
  return std::visit(Overloaded{
                        [](const GeodesicOrientation& g) { return g.rate; },
                        [&](const BlendOrientation& b) {
                          const auto [phi, dphi] = blend_phi(b, b.offset + sigma);
                          return Vec3(left_jacobian(phi) * dphi);
                        },
                        [&](const SplineOrientation& c) {
                          const auto [phi, dphi] = c.spline->at(c.offset + sigma);
                          return Vec3(left_jacobian(phi) * dphi);
                        },
                    },
                    piece.law);
}

RotationBounds rotation_bounds(const PieceOrientation& piece, double length, double s0, double s1) {
  if (const auto* g = std::get_if<GeodesicOrientation>(&piece.law)) return {g->rate.norm(), 0.0, 0.0};
  s0 = std::clamp(s0, 0.0, length);
  s1 = std::clamp(s1, s0, length);
  RotationBounds out;
  // rho at kBoundSamples + 1 points of [s0, s1]; rho' and rho'' there by local differences of
  // step h (central inside, one-sided at the ends, so every stencil stays within [s0, s1])
  const double span = s1 - s0;
  const double h = kDifferenceShare * span;
  const auto rate = [&](double x) { return angular_rate_at(piece, x); };
  for (int i = 0; i <= kBoundSamples; ++i) {
    const double x = i == kBoundSamples ? s1 : s0 + span * i / kBoundSamples;
    const Vec3 r = rate(x);
    out.rate = std::max(out.rate, r.norm());
    if (!(h > 0)) continue;
    const double c = std::clamp(x, s0 + h, s1 - h);  // the stencil's centre
    const Vec3 lo = rate(c - h);
    const Vec3 mid = rate(c);
    const Vec3 hi = rate(c + h);
    const Vec3 d1 = i == 0 ? Vec3((-3 * lo + 4 * mid - hi) / (2 * h)) : i == kBoundSamples ? Vec3((lo - 4 * mid + 3 * hi) / (2 * h))
                                                                                      : Vec3((hi - lo) / (2 * h));
    out.rate_d1 = std::max(out.rate_d1, d1.norm());
    out.rate_d2 = std::max(out.rate_d2, ((hi - 2 * mid + lo) / (h * h)).norm());
  }
  out.rate *= kBoundMargin;
  out.rate_d1 *= kBoundMargin;
  out.rate_d2 *= kBoundMargin;
  return out;
}

}  // namespace blendbench
