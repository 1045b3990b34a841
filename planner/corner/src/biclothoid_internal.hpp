#pragma once
// Private to planner/corner/src (not installed, not part of the corner library's API): the
// constants and helpers that the biclothoid sources share — the curve (biclothoid_curve.cpp),
// seed 004 Algorithm 1 (biclothoid_fit.cpp), the deviation (biclothoid_deviation.cpp), Algorithm 2
// and the start-distance fit (biclothoid_tolerance.cpp), the corner plane (corner_plane.cpp)
// and the corner method (biclothoid_corner.cpp).

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include "blendbench/corner/biclothoid.hpp"
#include "blendbench/corner/clothoid_blend.hpp"

namespace blendbench::biclothoid_detail {

inline constexpr double kPi = std::numbers::pi;
// Tangent angle (rad) below which a corner is G1 (as in blend.cpp).
inline constexpr double kTangentAngle = 1e-9;

inline double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }
inline Vec2 direction(double theta) { return {std::cos(theta), std::sin(theta)}; }

// i v: v turned by +90 deg; and r v as complex numbers (r a unit vector: v turned by its angle).
inline Vec2 perp(const Vec2& v) { return {-v.y(), v.x()}; }
inline Vec2 rotate(const Vec2& r, const Vec2& v) {
  return {r.x() * v.x() - r.y() * v.y(), r.x() * v.y() + r.y() * v.x()};
}

// b / a of a small fillet at a curvature jump alone (no tangent jump), derived here (seed 004 is
// silent): in the limit of small fillets the slopes are small and arc length is x, and only the
// jump matters (a common curvature adds the same parabola to the path and to the fillet), so
// take q1 of curvature k for x in [-a, 0] and q2 the line y = 0. The fillet's curvature is a tent
// k -> k + c s1 -> 0 of equal slopes c over s1 and s2 (s1 + s2 = a + b); it leaves q1 G2 at
// x = -a (y = k a^2 / 2, y' = -k a) and meets the line G2 at x = b, so its curvature's integral
// is k a (the slope returns to 0) and its first moment about x = b is k a (a + b) - k a^2 / 2
// (the height returns to 0). With k = a = 1 the tent's end gives c (s2 - s1) = 1, the integral
// then s1 = s2 + 1 - sqrt(2 s2^2 + 1), and the moment 2 s2^4 - 6 s2 + 3 = 0, whose root above 1
// is s2 = 1.2066504; so b / a = s1 + s2 - 1 = 2 s2 - sqrt(2 s2^2 + 1) = 0.4354205 (measured
// over the property tests' random tangent corners: 0.4343-0.4374, the spread from fillets that
// are not small; Biclothoid.ASmallFilletAtACurvatureJumpEndsAtTheDerivedShare).
inline constexpr double kEndShare = 0.4354205;

// The turn from angle `from` to angle `to`, std::remainder(to - from, 2 pi) in [-pi, pi], without
// the library call where |to - from| < 2 pi (a corner's angles lie in (-pi, pi]; a call was
// 1.5 % of a fit with an arc, made three to four times per fit). There the one multiple of
// 2 pi that remainder takes off is found by comparison, and the subtraction is exact (Sterbenz:
// |to - from| >= pi is within a factor 2 of 2 pi), as remainder's result is: the same to the
// bit, ties at +-pi included (remainder keeps them, rounding the quotient +-1/2 to even).
inline double angle_turn(double from, double to) {
  const double d = to - from;
  if (!(std::abs(d) < 2 * kPi)) return std::remainder(d, 2 * kPi);
  if (d > kPi) return d - 2 * kPi;
  if (d < -kPi) return d + 2 * kPi;
  return d;
}

// (u1, u2) moved along its ray onto the square |u_i| <= range where it lies outside it; false
// where it is not finite. The small-fillet fits in u_i = kappa_i a
// (biclothoid_curvature_jump_start, biclothoid_curvature_jump_fillet) hold on such a square and
// keep their edge's value beyond it (their quadratics would run off without bound).
inline bool onto_range(double range, double& u1, double& u2) {
  const double size = std::max(std::abs(u1), std::abs(u2));
  if (!std::isfinite(size)) return false;
  if (size > range) {
    u1 *= range / size;
    u2 *= range / size;
  }
  return true;
}

// Turn of the programmed corner: the tangent jump delta in (-pi, pi].
inline double corner_turn(const CornerShapes& shapes) { return angle_turn(shapes.q1.theta, shapes.q2.theta); }

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

// shape_point and the unit tangent there from one sine and cosine: with h = kappa sigma / 2
// and t0 the tangent at the corner, the chord is sigma sinc(h) along t0 turned by h, and the
// tangent is turned by 2 h.
struct ShapeAt {
  Vec2 p;
  Vec2 t;
};
inline ShapeAt shape_at(const PlanarShape& shape, const Vec2& t0, double sigma) {
  const double half = 0.5 * shape.kappa * sigma;
  const Vec2 turn(std::cos(half), std::sin(half));
  const Vec2 chord = rotate(turn, t0);
  return {sigma * (std::abs(half) < 1e-4 ? 1.0 - half * half / 6.0 : turn.y() / half) * chord, rotate(turn, chord)};
}

// How a point of the curve moves with its length and turn (biclothoid_curve.cpp, where the
// derivation stands): at arc length s in [0, L] (clamped), with `offset` receiving V(s) - p0.
struct PointSlopes {
  Vec2 d_length;  // d V(s) / d L at a fixed turn (without the end's T(L))
  Vec2 d_turn;    // d V(s) / d dtheta at a fixed length
};
PointSlopes point_slopes_at(const Biclothoid& curve, double s, Vec2& offset);

// A solution of Algorithm 1 and how it moves with the start distance a (implicit function
// theorem on its end conditions): warm starts for the next solve of Algorithm 2.
struct Solve {
  BiclothoidSolution fillet;
  double dlen_da = 0;  // d length / d a
  double db_da = 0;    // d b / d a
  Vec2 end = Vec2::Zero();  // the fillet's end point, from Algorithm 1's last evaluation
};
// seed 004 (Shahzadeh et al.) Algorithm 1 (biclothoid_fit.cpp): fit_biclothoid_at with the sensitivities.
// `Effort::kGuessOnly`: Newton from the guess alone, a few iterations, none of the other
// starts or the bracket scan (a solve that is only worth it if it is quick).
// `turn_shape`, when given, is clothoid_pair_shape(|delta|) of this corner's turn, for the cold
// guess's line-line pair (a caller that has it saves the Fresnel integrals).
enum class Effort { kFull, kGuessOnly };
std::optional<Solve> fit_at(const CornerShapes& shapes, double a, double guess_length, double guess_b,
                            Effort effort = Effort::kFull, const ClothoidPairShape* turn_shape = nullptr);

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
// seed 004 section 7.1 (biclothoid_deviation.cpp): biclothoid_deviation with its witness. With
// larger_only the larger distance (Deviation::max) and the witness are the same, but the
// original -> fillet distance, where it is the smaller, may be left short of its maximum
// (a side of U is not refined where the distance is 1-Lipschitz-bounded below what is known).
Measured measure_deviation(const BiclothoidSolution& fillet, const CornerShapes& shapes, bool larger_only);

}  // namespace blendbench::biclothoid_detail
