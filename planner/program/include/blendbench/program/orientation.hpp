#pragma once
// The tool's orientation along the blended path, as a function of the path's arc length s.
//
// Along a programmed move the orientation is the slerp from the move's start orientation (the
// previous target) to its target by the move's arc length: R(s) = exp((s / L) r) R_start, r the
// rotation vector of R_target R_start^T (the shorter way round), L the move's length. The rate
// rho = dtheta/ds = r / L (rad/m, base frame) is constant on the move, so position and
// orientation arrive together at every target, and the angular velocity is omega = rho v.
//
// Through a transition of length L_t that replaces the last `lead_in` of move k and the first
// `lead_out` of move k+1 (R_c the target at the corner), both moves' orientations are continued
// along the transition's own arc length x in [0, L_t], in rotation vectors about R_c:
//   a(x) = (x - lead_in) rho_in       (move k, extended past its trim point),
//   b(x) = (x - L_t + lead_out) rho_out (move k+1, extended back from its trim point),
// and blended with the quintic smooth step w(u) = 10u^3 - 15u^4 + 6u^5, u = x / L_t:
//   phi(x) = (1 - w) a(x) + w b(x),   R(x) = exp(phi(x)) R_c.
// phi(0) = a(0) and phi(L_t) = b(L_t), so the orientation joins both trimmed moves; w' and w''
// vanish at both ends, so phi' = rho_in, phi'' = 0 at x = 0 (rho_out, 0 at x = L_t). Where phi is
// parallel to phi' (at both ends), the space angular rate J_l(phi) phi' equals phi' and its
// derivative phi'' (J_l the left Jacobian of SO(3)), so dtheta/ds and d2theta/ds2 are continuous
// across both junctions: the angular velocity rho v and the angular acceleration
// rho a_t + rho' v^2 are continuous wherever v and a_t are (every method: the profile's a_t is
// continuous), which is what the seeds leave open and this model fixes.
//
// A corner with no transition of positive length (an exact stop, a kink, a zero-length
// transition) passes through the corner's target: the trimmed moves there slerp to it over what
// is left of them.
//
// The option `spline` (Program::orientation_interpolation) replaces both laws by one C2 curve
// along the whole blended path: R(s) = exp(phi(s)) R_0, R_0 the start orientation and phi a
// natural cubic spline in s through the targets' rotation vectors phi_k = log(R_k R_0^T), each
// taken as the representative (phi or (|phi| - 2 pi) phi / |phi|) nearest the previous one so
// the curve turns on past a half-turn. Knot k sits where the path passes target k: the middle of
// corner k's transition (the end of move k where the corner has none; the path's end for the
// last move). phi is C2 in s and exp is smooth, so dtheta/ds = J_l(phi) phi' and its derivative
// are continuous everywhere, also across transitions and between moves, at the price of the
// spline's overshoot between targets of unequal spacing (slerp has none). Targets more than
// kSplineMaxTurn from the start are refused: towards 2 pi the map exp compresses phi (|J_l|
// falls to 0.30 at 270 degrees and 0 at 360), so the spline in phi would no longer resemble the
// rotation it makes. The seeds are silent on orientation; this construction is derived here.

#include <Eigen/Geometry>
#include <limits>
#include <memory>
#include <numbers>
#include <utility>
#include <variant>
#include <vector>

#include "blendbench/core/geometry.hpp"

namespace blendbench {

using Quat = Eigen::Quaterniond;

// Angular limits of one move on the tool's rotation (rad/s, rad/s^2, rad/s^3), all > 0;
// infinity = none.
struct AngularLimits {
  double velocity = std::numeric_limits<double>::infinity();
  double acceleration = std::numeric_limits<double>::infinity();
  double jerk = std::numeric_limits<double>::infinity();
};

// The rotation vector (axis times angle, angle in [0, pi]) of a unit quaternion, accurate near
// zero; the quaternion with w >= 0 is used, so the rotation goes the shorter way.
Vec3 rotation_log(const Quat& q);
// The unit quaternion of rotation vector r (exact near zero).
Quat rotation_exp(const Vec3& r);
// The rotation angle (rad, [0, pi]) from a to b.
double rotation_angle(const Quat& a, const Quat& b);

// Along a move piece: R(sigma) = exp(sigma rate) start, sigma the piece's local arc length (m).
struct GeodesicOrientation {
  Quat start = Quat::Identity();
  Vec3 rate = Vec3::Zero();  // rad/m, base frame
};

// Along a transition piece (see above): x = offset + sigma, R = exp(phi(x)) corner.
struct BlendOrientation {
  Quat corner = Quat::Identity();  // the target at the corner
  Vec3 rate_in = Vec3::Zero();     // rad/m: the incoming move's rate
  Vec3 rate_out = Vec3::Zero();    // rad/m: the outgoing move's rate
  double lead_in = 0;              // m: trimmed from the end of the incoming move
  double lead_out = 0;             // m: trimmed from the start of the outgoing move
  double length = 0;               // m: the whole transition (> 0)
  double offset = 0;               // m: where this piece starts within the transition
};

// The natural cubic spline phi(s) of the option `spline` (see above): phi(knot[k]) = value[k],
// phi'' = 0 at both ends, knots strictly increasing (m), values rad. With two knots it is the
// straight line (the slerp). Built in O(n) (a tridiagonal solve); evaluated by binary search.
class OrientationSpline {
 public:
  // Throws std::invalid_argument for fewer than two knots, knots not strictly increasing, or
  // sizes that differ.
  OrientationSpline(Quat reference, std::vector<double> knots, std::vector<Vec3> values);
  [[nodiscard]] const Quat& reference() const { return reference_; }
  [[nodiscard]] const std::vector<double>& knots() const { return knots_; }
  // phi and phi' at s (clamped to the knots' range).
  [[nodiscard]] std::pair<Vec3, Vec3> at(double s) const;

 private:
  Quat reference_;
  std::vector<double> knots_;
  std::vector<Vec3> values_;
  std::vector<Vec3> second_;  // phi'' at the knots
};

// The largest turn of a target from the start orientation under the option `spline` (rad).
inline constexpr double kSplineMaxTurn = 1.5 * std::numbers::pi;

// Along a piece under the option `spline`: R = exp(phi(offset + sigma)) reference, offset the
// piece's start on the whole path (m).
struct SplineOrientation {
  std::shared_ptr<const OrientationSpline> spline;
  double offset = 0;
};

// The orientation law of one path piece and the angular limits that hold on it.
struct PieceOrientation {
  std::variant<GeodesicOrientation, BlendOrientation, SplineOrientation> law;
  AngularLimits limits;
};

// The orientation at local arc length sigma (m) of the piece (a unit quaternion, base frame).
Quat orientation_at(const PieceOrientation& piece, double sigma);
// dtheta/ds at sigma: the angular velocity per unit path speed (rad/m, base frame).
Vec3 angular_rate_at(const PieceOrientation& piece, double sigma);

// Bounds on |rho|, |rho'|, |rho''| (rad/m, rad/m^2, rad/m^3; ' = d/ds) over local [s0, s1] of a
// piece: exact on a move piece (rho constant, rho' = rho'' = 0); on a transition or spline piece the
// largest values over kBoundSamples + 1 points of [s0, s1] (rho exact, rho' and rho'' by local
// differences of rho at each, one-sided at the ends), raised by kBoundMargin. The functions are smooth (a quintic
// weight and exp), so the sampled maxima miss the true ones by O(kBoundSamples^-2) of their
// size; the margin covers that many times over, and the property tests check the limits on the
// sampled profile.
struct RotationBounds {
  double rate = 0;
  double rate_d1 = 0;
  double rate_d2 = 0;
};
inline constexpr int kBoundSamples = 64;
inline constexpr double kBoundMargin = 1.05;
RotationBounds rotation_bounds(const PieceOrientation& piece, double length, double s0, double s1);

}  // namespace blendbench
