#pragma once
// The limits a velocity plan holds: along the path (mode `path`, the tangential model of seed
// seed 004, Shahzadeh et al., eq. 25-27) or as vectors on the TCP (mode `cartesian`), and the
// conditions on the path speed that make the vector limits hold.
//
// Derivation (cartesian). The TCP moves along p(s) (arc length s) at path speed v, with
// tangential acceleration a_t = dv/dt and jerk j_t = da_t/dt. With the Frenet frame T, N, B,
// p'' = kappa N and p''' = d(kappa N)/ds = -kappa^2 T + kappa' N + kappa tau B (' = d/ds, tau the
// torsion), the chain rule gives
//   velocity      v T
//   acceleration  a = a_t T + kappa v^2 N
//   jerk          j = j_t T + 3 v a_t kappa N + v^3 p'''
//                   = (j_t - kappa^2 v^3) T + (3 kappa v a_t + kappa' v^3) N + kappa tau v^3 B.
// T, N, B are orthonormal, so |a|^2 = a_t^2 + (kappa v^2)^2 and, with g = sqrt(kappa'^2 +
// (kappa tau)^2) (max_spatial_sharpness, segment.hpp),
//   |j|^2 <= (|j_t| + kappa^2 v^3)^2 + (3 kappa v |a_t| + g v^3)^2
// (the triangle inequality on the T component and on the N-B part). Each term grows with kappa,
// g, v, |a_t| and |j_t|. Hence on a stretch where |a_t| <= A_t and |j_t| <= J_t (the S-curve's
// tangential limits), kappa <= kappa_max and g <= g_max, the two conditions
//   (C1)  A_t^2 + (kappa_max v^2)^2 <= A^2     (A: the acceleration limit while speeding up,
//                                              the deceleration limit while slowing down)
//   (C2)  (J_t + kappa_max^2 v^3)^2 + (3 kappa_max v A_t + g_max v^3)^2 <= J^2
// at the largest speed v on the stretch give |a| <= A and |j| <= J everywhere on it, also while
// the speed changes on a curve (the 3 kappa v a_t and kappa' v^3 terms). A straight line has
// kappa = g = 0: (C1), (C2) reduce to |a_t| <= A, |j_t| <= J.
//
// The planner shares each budget between the tangential and the normal parts: on a curved
// piece it fixes the tangential limits once (cartesian_tangential_limits), and caps the speed
// on every interval of the piece by (C1) and (C2) with the interval's kappa_max and g_max
// (cartesian_speed_limit). Any choice of the tangential limits is sound; the one made here is
// stated at cartesian_tangential_limits.
//
// Per-axis limits (a CNC machine's axis_limits): on a piece whose motion lies in a subspace S
// (a line: its direction; a planar curve: its plane; otherwise all of space) the acceleration
// and jerk vectors lie in S (on a line both are along T; on a planar curve T and N span the
// plane and tau = 0), so their component on axis e_i is at most |x| |P_S e_i|. Lowering the
// vector limits to min_i (axis limit_i / |P_S e_i|) (effective_vector_limits) therefore holds
// every axis limit too; exact on lines, conservative on curves.

#include <optional>
#include <string_view>

#include "blendbench/core/geometry.hpp"
#include "blendbench/geometry/segment.hpp"
#include "blendbench/program/program.hpp"

namespace blendbench {

// Which limits a plan holds (TimingOptions::limits):
//   kPath: seed 004's model: |a_t| <= a, |j_t| <= j, kappa v^2 <= a and v <= cbrt(j / sqrt(c^2 +
//          kappa^4)) (eq. 25-27), kept for the paper reproductions;
//   kCartesian: |v| <= feed, |a| <= a (a_t >= 0) or deceleration (a_t <= 0) and |j| <= j as
//          vectors on the TCP, by (C1) and (C2) above.
enum class LimitsMode { kPath, kCartesian };

// "path", "cartesian", and back (nullopt when unknown).
std::string_view to_string(LimitsMode mode);
std::optional<LimitsMode> limits_mode_from_string(std::string_view name);

// Per-axis limits on the TCP's acceleration and jerk along the x, y, z axes of the frame the
// path is planned in (the robot base frame), m/s^2 and m/s^3, all > 0.
struct AxisLimits {
  Vec3 acceleration = Vec3::Zero();
  Vec3 jerk = Vec3::Zero();
};

// The vector limits on one piece: `limits` with acceleration, deceleration and jerk lowered so
// that every axis limit holds as well (see above); `limits` itself without axis limits.
Limits effective_vector_limits(const Segment& segment, const Limits& limits, const std::optional<AxisLimits>& axes);

// The S-curve's tangential limits on a curved piece (m/s^2, m/s^3, all > 0).
struct TangentialLimits {
  double acceleration = 0;
  double deceleration = 0;
  double jerk = 0;
};

// The tangential limits on a piece with maximum curvature kappa (1/m) and spatial sharpness g
// (1/m^2), vector limits `limits` (acceleration, deceleration, jerk; velocity = the feed),
// chosen at a design speed v_c = min(feed, share * v0), v0 the highest constant speed (C1),
// (C2) allow (a_t = j_t = 0), share in (0, 1): at v_c,
//   A_t(+/-) = sqrt(A(+/-)^2 - (kappa v_c^2)^2), lowered to e / (3 kappa v_c),
//   J_t = sqrt(J^2 - (3 kappa v_c A_t + g v_c^3)^2) - kappa^2 v_c^3,
// where e solves (e + kappa^2 v_c^3)^2 + (e + g v_c^3)^2 = J^2: what the constant-speed jerk
// leaves of J is shared equally between the tangential jerk and the jerk 3 kappa v a_t of
// changing speed on the curve. So (C1) and (C2) hold at v_c, and the interval caps of the piece
// are at least v_c where its curvature is highest. A line (kappa = g = 0) keeps the full limits.
TangentialLimits cartesian_tangential_limits(double kappa, double g, const Limits& limits, double share);

// The cap terms of (C1) and (C2) (m/s; infinity on a line): the highest speed with (C1) on
// both sides (speeding up and slowing down) and the highest with (C2), for curvature kappa and
// spatial sharpness g under vector limits `limits` and tangential limits `tangential`. The
// returned speeds satisfy the conditions in floating point.
struct CartesianCap {
  double acceleration;  // (C1)
  double jerk;          // (C2)
};
CartesianCap cartesian_speed_limit(double kappa, double g, const Limits& limits, const TangentialLimits& tangential);

// The TCP's acceleration and jerk vectors (m/s^2, m/s^3) at path speed v, tangential
// acceleration a_t and jerk j_t where the path has unit tangent t, curvature vector k = kappa N
// and its derivative dk = d^3p/ds^3 (the formulas above).
inline Vec3 tcp_acceleration(double v, double a_t, const Vec3& t, const Vec3& k) { return a_t * t + v * v * k; }
inline Vec3 tcp_jerk(double v, double a_t, double j_t, const Vec3& t, const Vec3& k, const Vec3& dk) {
  return j_t * t + 3.0 * v * a_t * k + v * v * v * dk;
}

}  // namespace blendbench
