#include "blendbench/program/orientation.hpp"

#include <algorithm>
#include <cmath>

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
