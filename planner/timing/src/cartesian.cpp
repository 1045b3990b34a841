#include "blendbench/timing/cartesian.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include "blendbench/core/overloaded.hpp"

namespace blendbench {
namespace {

const double kInf = std::numeric_limits<double>::infinity();
// Relative size below which a control point lies in the plane of a Bezier's control polygon.
constexpr double kPlanarTol = 1e-12;
// Newton steps on (C2) (convex and increasing in v, so from above it converges monotonically;
// a dozen suffice from the starting bound), and nudges down until (C1), (C2) hold exactly.
constexpr int kNewtonSteps = 60;
constexpr int kNudges = 64;
// The smallest share of each limit left to the normal parts (a few ulps; see
// cartesian_tangential_limits).
constexpr double kMinNormalShare = 16 * std::numeric_limits<double>::epsilon();

// The unit normal of the plane a curved segment lies in; nullopt when it is not planar.
std::optional<Vec3> plane_normal(const Segment& segment) {
  return std::visit(Overloaded{
                        [](const Line&) -> std::optional<Vec3> { return std::nullopt; },
                        [](const Arc& a) -> std::optional<Vec3> {
                          if (a.rise != 0) return std::nullopt;
                          return a.u.cross(a.v).normalized();
                        },
                        [](const Clothoid& c) -> std::optional<Vec3> { return c.e1.cross(c.e2).normalized(); },
                        [](const Bezier& b) -> std::optional<Vec3> {
                          // the plane of the control polygon, when every control point lies in it
                          const auto& p = b.control_points();
                          double size = 0;
                          for (const Vec3& q : p) size = std::max(size, (q - p[0]).norm());
                          Vec3 n = Vec3::Zero();
                          for (std::size_t i = 1; i < p.size(); ++i) {
                            for (std::size_t j = i + 1; j < p.size(); ++j) {
                              const Vec3 c = (p[i] - p[0]).cross(p[j] - p[0]);
                              if (c.norm() > n.norm()) n = c;
                            }
                          }
                          if (!(n.norm() > 0)) return std::nullopt;
                          n.normalize();
                          for (const Vec3& q : p) {
                            if (std::abs(n.dot(q - p[0])) > kPlanarTol * size) return std::nullopt;
                          }
                          return n;
                        },
                    },
                    segment);
}

// |P_S e_i| for the axes i, S the subspace the segment's motion lies in (see the header).
Vec3 axis_reach(const Segment& segment) {
  if (const auto* line = std::get_if<Line>(&segment)) {
    const Vec3 d = line->p1 - line->p0;
    return d.norm() > 0 ? Vec3(d.cwiseAbs() / d.norm()) : Vec3::Ones();
  }
  if (const auto n = plane_normal(segment)) {
    return Vec3((Vec3::Ones() - n->cwiseProduct(*n)).cwiseMax(0.0).cwiseSqrt());
  }
  return Vec3::Ones();
}

// v, or the first of v (1 - 2^i eps), i = 0, 1, ..., with ok (0 when none: ok(0) holds for the
// conditions here, whose left-hand sides grow with v): a root rounded above the conditions'
// boundary moves just below it.
template <class Ok>
double nudge_down(double v, Ok ok) {
  double step = std::numeric_limits<double>::epsilon();
  for (int i = 0; i < kNudges && v > 0 && !ok(v); ++i, step *= 2) v *= 1 - std::min(step, 1.0);
  return v > 0 && ok(v) ? v : 0.0;
}

}  // namespace

std::string_view to_string(LimitsMode mode) { return mode == LimitsMode::kPath ? "path" : "cartesian"; }

std::optional<LimitsMode> limits_mode_from_string(std::string_view name) {
  if (name == "path") return LimitsMode::kPath;
  if (name == "cartesian") return LimitsMode::kCartesian;
  return std::nullopt;
}

Limits effective_vector_limits(const Segment& segment, const Limits& limits, const std::optional<AxisLimits>& axes) {
  if (!axes) return limits;
  const Vec3 reach = axis_reach(segment);
  Limits out = limits;
  for (int i = 0; i < 3; ++i) {
    if (!(reach[i] > 0)) continue;
    const double a = axes->acceleration[i] / reach[i];
    out.acceleration = std::min(out.acceleration, a);
    out.deceleration = std::min(out.deceleration, a);
    out.jerk = std::min(out.jerk, axes->jerk[i] / reach[i]);
  }
  return out;
}

TangentialLimits cartesian_tangential_limits(double kappa, double g, const Limits& limits, double share) {
  assert(share > 0 && share < 1);
  TangentialLimits out{limits.acceleration, limits.deceleration, limits.jerk};
  if (!(kappa > 0) && !(g > 0)) return out;
  const double jerk = limits.jerk;
  // v0: the highest constant speed, kappa v^2 <= min(A+, A-) and v^3 sqrt(kappa^4 + g^2) <= J
  const double a_normal = std::min(limits.acceleration, limits.deceleration);
  const double v0 = std::min(kappa > 0 ? std::sqrt(a_normal / kappa) : kInf, std::cbrt(jerk / std::hypot(kappa * kappa, g)));
  const double vc = std::min(limits.velocity, share * v0);
  // (C1) at v_c, in ratios to the limits so tiny limits neither underflow nor overflow
  const double n_a = kappa * vc * vc;
  out.acceleration = limits.acceleration * std::sqrt(1 - std::pow(n_a / limits.acceleration, 2));
  out.deceleration = limits.deceleration * std::sqrt(1 - std::pow(n_a / limits.deceleration, 2));
  // (C2) at v_c: alpha = kappa^2 v_c^3 / J, beta = g v_c^3 / J, e / J the equal share
  const double alpha = kappa * kappa * vc * vc * vc / jerk;
  const double beta = g * vc * vc * vc / jerk;
  const double e = 0.5 * (std::sqrt(2 - (alpha - beta) * (alpha - beta)) - (alpha + beta));
  if (kappa > 0) {
    const double a_cap = e * jerk / (3 * kappa * vc);
    out.acceleration = std::min(out.acceleration, a_cap);
    out.deceleration = std::min(out.deceleration, a_cap);
  }
  const double coupling = 3 * kappa * vc * std::max(out.acceleration, out.deceleration) / jerk + beta;
  out.jerk = jerk * (std::sqrt(std::max(0.0, 1 - coupling * coupling)) - alpha);
  // leave the normal parts a budget the doubles resolve: where v_c is so slow that they need
  // less than a few ulps of the limits, the shares above round to the full limits
  out.acceleration = std::min(out.acceleration, limits.acceleration * (1 - kMinNormalShare));
  out.deceleration = std::min(out.deceleration, limits.deceleration * (1 - kMinNormalShare));
  out.jerk = std::min(out.jerk, jerk * (1 - kMinNormalShare));
  return out;
}

CartesianCap cartesian_speed_limit(double kappa, double g, const Limits& limits, const TangentialLimits& tangential) {
  CartesianCap cap{kInf, kInf};
  if (!(kappa > 0) && !(g > 0)) return cap;
  // (C1) on both sides: kappa v^2 <= sqrt(A^2 - A_t^2), as sqrt((A - A_t)(A + A_t)): the
  // difference is exact when A_t is close to A
  const auto room_of = [](double a, double a_t) { return std::sqrt(std::max(0.0, (a - a_t) * (a + a_t))); };
  const double room = std::min(room_of(limits.acceleration, tangential.acceleration),
                               room_of(limits.deceleration, tangential.deceleration));
  if (kappa > 0) cap.acceleration = nudge_down(std::sqrt(room / kappa), [&](double v) { return kappa * v * v <= room; });
  // (C2) in ratios to J, with the deficit d = 1 - J_t / J (J - J_t exact for J_t >= J / 2):
  // f(v) = (k2 v^3 - d)(2 - d + k2 v^3) + (m v + q v^3)^2 = (J_t/J + k2 v^3)^2 + (..)^2 - 1,
  // convex and increasing for v >= 0
  const double jerk = limits.jerk;
  const double d = (jerk - tangential.jerk) / jerk;
  const double k2 = kappa * kappa / jerk;
  const double m = 3 * kappa * std::max(tangential.acceleration, tangential.deceleration) / jerk;
  const double q = g / jerk;
  const auto f = [&](double v) {
    const double v3 = v * v * v;
    return (k2 * v3 - d) * (2 - d + k2 * v3) + (m * v + q * v3) * (m * v + q * v3);
  };
  // start above the root: where one term alone reaches 1
  double v = kInf;
  if (k2 > 0) v = std::min(v, std::cbrt(d / k2));
  if (q > 0) v = std::min(v, std::cbrt(1 / q));
  if (m > 0) v = std::min(v, 1 / m);
  for (int it = 0; it < kNewtonSteps; ++it) {
    const double v2 = v * v;
    const double v3 = v2 * v;
    const double df = 3 * k2 * v2 * (2 - d + k2 * v3) + 3 * k2 * v2 * (k2 * v3 - d) + 2 * (m * v + q * v3) * (m + 3 * q * v2);
    const double fv = f(v);
    if (!(fv > 0) || !(df > 0)) break;
    const double next = v - fv / df;
    if (!(next < v)) break;
    v = std::max(next, 0.0);
  }
  cap.jerk = nudge_down(v, [&](double x) { return f(x) <= 0; });
  return cap;
}

}  // namespace blendbench
