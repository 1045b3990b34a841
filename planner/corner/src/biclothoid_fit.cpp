// seed 004 Algorithm 1: the biclothoid that starts G2 on the incoming move at a given distance
// before the corner and ends G2 on the outgoing one (Newton on the closed-form derivatives of
// biclothoid_end), with its sensitivities to the start distance for Algorithm 2.

#include "blendbench/corner/biclothoid.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <utility>

#include <Eigen/LU>

#include "biclothoid_internal.hpp"
#include "blendbench/corner/clothoid_blend.hpp"

namespace blendbench {
using namespace biclothoid_detail;  // the helpers private to the biclothoid sources
namespace {

// Shortest chord (start to end) of a fillet accepted, relative to a + b: near a reversal of
// 179.999 deg a fillet's chord is 8.7e-6 (a + b); where q1 and q2 cross just after the corner
// the equations also admit vanishing hairpins with start = end, which are no fillets.
constexpr double kMinChordRatio = 1e-6;
// Algorithm 1 stops when the end misses q2 by less than this fraction of a + b (the blender's
// continuity needs 1e-9).
constexpr double kSolveTolerance = 1e-12;
// Algorithm 1's last Newton step is taken without evaluating the end there (biclothoid_end_moved)
// where the step's predicted miss, |f''| h^2 / 2 with f'' from the change of the slopes (the
// Jacobian) since the point before, is below this fraction of kSolveTolerance. Evaluated there
// anyway over 40,000 of the property tests' random corners (16,600 such steps, as many with an
// arc at the end as with a line), the end missed by at most 12 % of the tolerance; the moved
// curve's peak point was within 9e-15 and its end within 2.5e-13 of the fillet's a + b of the
// evaluated ones. Evaluations of the end per one-solve fit: 2.9 -> 2.4 with a line at the end,
// 3.2 -> 2.7 with an arc there (whose cold guess misses by 1e-3 to 1e-2, so its median solve still
// takes three).
constexpr double kPredictedShare = 0.125;
// Newton iterations of a solve from its guess alone (Effort::kGuessOnly): warm solves take 2.1-2.3
// evaluations on average over the property tests' random corners, so 8 is ample; a solve that
// needs more is on its way to another root or none
constexpr int kGuessOnlyIterations = 8;
// The least turn of a fillet whose guess is checked for a hairpin (rad; fit_at; below it the
// chord is not even computed): the hairpins among the property tests' random corners turn by
// 3.2-3.4 rad, where the symmetric pair is 2.3-2.8 chords long (1.33 at 2 rad).
constexpr double kHairpinTurn = 2.0;

}  // namespace

// By scaling, as biclothoid_curvature_jump_start (seed 004 is silent): with lengths in units of
// a the corner is fixed by u_i = kappa_i a, so log(L / a) and log(b / a) are functions of
// (u1, u2), even in them, whose u -> 0 limits are the small fillet's (kEndShare). Their
// quadratics, fitted here by least squares to Algorithm 1's solutions (Newton from that limit
// to 1e-12) on the grid u_i = (pi / 80) k, 0 < u1 <= pi / 4, |u2| <= pi / 4, u1 != u2 (800
// corners), with the constant terms held at the limits: within 2.9e-5 (L) and 4.9e-5 (b) of
// every one, the largest beside u1 = u2 at the grid's edge. With the limits alone as the guess,
// the end missed by 5e-3 of the fillet's size at the eighth-turn cap (|u1| = pi / 4, where 29 %
// of the property tests' random arc-arc fits end, 15 % of those with one arc), and Algorithm 1
// took three or four evaluations there; from this guess, two (its first Newton step lands within the
// predicted-step bound, kPredictedShare).
BiclothoidJumpFillet biclothoid_curvature_jump_fillet(double u1, double u2) {
  if (!onto_range(kPi / 4, u1, u2)) return {1 + kEndShare, kEndShare};
  constexpr double kLengthU1U1 = -9.3493732e-3;
  constexpr double kLengthU1U2 = 1.0435115e-2;
  constexpr double kLengthU2U2 = 3.2240993e-3;
  constexpr double kEndU1U1 = -4.7945311e-3;
  constexpr double kEndU1U2 = 1.4757704e-2;
  constexpr double kEndU2U2 = 4.2615296e-3;
  const double log_length = u1 * (kLengthU1U1 * u1 + kLengthU1U2 * u2) + kLengthU2U2 * u2 * u2;
  const double log_end = u1 * (kEndU1U1 * u1 + kEndU1U2 * u2) + kEndU2U2 * u2 * u2;
  return {(1 + kEndShare) * std::exp(log_length), kEndShare * std::exp(log_end)};
}

std::optional<Solve> biclothoid_detail::fit_at(const CornerShapes& shapes, double a, double guess_length,
                                              double guess_b, Effort effort, const ClothoidPairShape* turn_shape) {
  const bool full = effort == Effort::kFull;
  if (!(a > 0) || !std::isfinite(a)) return std::nullopt;
  const PlanarShape& q1 = shapes.q1;
  const PlanarShape& q2 = shapes.q2;
  const double delta = corner_turn(shapes);
  const ShapeAt on_q1 = shape_at(q1, q1.t, -a);
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
  // dominates, else the fillet of a curvature jump alone at the arcs' kappa_i a
  // (biclothoid_curvature_jump_fillet; its small-fillet limit, b = kEndShare a and L = a + b,
  // before: L = 1.5 a, b = a / 2, from seed 004 table 1's fillets, took 0.4 more evaluations per
  // cold solve over the property tests' random corners than that limit, which took 2.3 to 2.8
  // on the random tangent corners with two arcs where this guess takes 2.0).
  // Which dominates: the deviation of the pair grows like |delta| a / 6, that of a curvature
  // jump like |kappa1 - kappa2| a^2 / 42 (see fit_biclothoid_with_tolerance).
  if (!(guess_length > 0 && guess_b > 0)) {
    const double jump = std::abs(q1.kappa - q2.kappa);
    if (std::abs(delta) / 6 > jump * a / 42) {
      const ClothoidPair pair = turn_shape ? clothoid_pair_for_tangent_length(*turn_shape, a)
                                           : clothoid_pair_for_tangent_length(std::abs(delta), a);
      guess_length = 2 * pair.half_length;
      guess_b = a;
    } else {
      const BiclothoidJumpFillet fillet = biclothoid_curvature_jump_fillet(q1.kappa * a, q2.kappa * a);
      guess_length = fillet.length * a;
      guess_b = fillet.end * a;
    }
  }
  // a hairpin: near a reversal, where an arc curls its move back across the other one, the
  // fillet turns by more than the corner (by Theta = |delta + kappa1 a + kappa2 b|, up to pi / 2
  // more) between a start and an end far closer together than a and b. There the guess is
  // the length of the symmetric pair that turns by Theta between the guessed start and end
  // (biclothoid_hairpin_length): the pair at the corner's turn and tangent length a guessed up
  // to 36 times too long, and Newton, which at most halves L per step, took five or six more
  // evaluations per solve (near-reversal corners with an arc were the slowest fits, 11-15 us).
  if (const double turn = std::abs(base_turn + q2.kappa * guess_b); turn > kHairpinTurn) {
    const double chord = (shape_at(q2, q2.t, guess_b).p - start.p).norm();
    if (4 * chord < guess_length) {
      const double hairpin = biclothoid_hairpin_length(chord, turn);
      if (hairpin > 0) guess_length = std::min(guess_length, hairpin);
    }
  }

  if (q2.kappa == 0) {
    // q2 is a line: the end angle is fixed, so one equation in L: the end lies on the line,
    // f(L) = t2 x p(L) = 0 with f' = t2 x dp/dL. Newton from the guess (L at most halves or
    // doubles per step) converges to the root nearest the guess; once a sign change brackets
    // it, steps leaving the bracket bisect it. A bracket search if that fails.
    const Vec2 t2 = q2.t;
    const auto eval = [&](double len) { return biclothoid_end(start, on_q1.t, 0.0, base_turn, len); };
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
      return Solve{{e.curve, a, b}, dlen_da, t2.dot(e.d_length * dlen_da + dp_da), e.p};
    };
    double x = guess_length;
    auto e = eval(x);
    double prev_x = 0;
    double prev_f = 0;
    double prev_slope = 0;
    double lo = 0;  // a bracket [lo, hi] once hi > 0, f(lo) of sign lo_sign
    double hi = 0;
    bool lo_positive = false;
    for (int it = 0; it < (full ? 40 : kGuessOnlyIterations) && e; ++it) {
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
      const double slope = cross(t2, e->d_length);
      double next = x - f / slope;
      // the Newton step's end, f(next) ~ f'' (next - x)^2 / 2, from the slopes here and at the
      // point before: within the tolerance, the solution there without another evaluation
      if (prev_x > 0 && std::isfinite(next) && (hi <= 0 || (next > lo && next < hi))) {
        const double curvature = (slope - prev_slope) / (x - prev_x);
        if (0.5 * std::abs(curvature) * (next - x) * (next - x) <= kPredictedShare * f_tol) {
          if (const auto moved = biclothoid_end_moved(*e, next - x, 0.0)) {
            if (auto sol = finish(*moved)) return sol;
          }
        }
      }
      if (hi > 0) {
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        if (hi - lo <= 1e-15 * hi) break;
      } else {
        if (!std::isfinite(next)) next = 2 * x;
        next = std::clamp(next, 0.5 * x, 2 * x);
      }
      prev_x = x;
      prev_f = f;
      prev_slope = slope;
      x = next;
      e = eval(x);
    }
    if (!full) return std::nullopt;
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
  const Vec2 t2 = q2.t;
  const auto evaluate = [&](double len, double b) -> std::optional<Eval> {
    const auto e = biclothoid_end(start, on_q1.t, q2.kappa, base_turn + q2.kappa * b, len);
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
    return Solve{{ev.end.curve, a, b}, slope.x(), slope.y(), ev.end.p};
  };
  const auto solve_from = [&](double len, double b) -> std::optional<Solve> {
    auto cur = evaluate(len, b);
    // the point before and its Jacobian, once there is one
    bool has_prev = false;
    Vec2 prev_point = Vec2::Zero();
    Eigen::Matrix2d prev_jac = Eigen::Matrix2d::Zero();
    for (int it = 0; it < (full ? 25 : kGuessOnlyIterations) && cur; ++it) {
      const double scale = a + b;
      if (cur->r.norm() <= kSolveTolerance * scale) return accept(*cur, b);
      const double det = cur->jac.determinant();
      if (!(std::abs(det) > 0) || !std::isfinite(det)) return std::nullopt;
      const Vec2 step = -(cur->jac.inverse() * cur->r);
      double lambda = 1;
      if (std::abs(step.x()) > 0.5 * len) lambda = std::min(lambda, 0.5 * len / std::abs(step.x()));
      if (std::abs(step.y()) > 0.5 * b) lambda = std::min(lambda, 0.5 * b / std::abs(step.y()));
      // the full Newton step's miss, ~|r''| |step|^2 / 2, with |r''| bounded by the change of
      // the Jacobian since the point before (Frobenius norm): within the tolerance, the
      // solution there without another evaluation
      if (has_prev && lambda == 1) {
        const double curvature = (cur->jac - prev_jac).norm() / (Vec2(len, b) - prev_point).norm();
        if (0.5 * curvature * step.squaredNorm() <= kPredictedShare * kSolveTolerance * (a + b + step.y())) {
          if (const auto moved = biclothoid_end_moved(cur->end, step.x(), q2.kappa * step.y())) {
            if (auto sol = accept(Eval{*moved, Vec2::Zero(), cur->jac}, b + step.y())) return sol;
          }
        }
      }
      bool accepted = false;
      for (int half = 0; half < 12 && !accepted; ++half, lambda *= 0.5) {
        auto next = evaluate(len + lambda * step.x(), b + lambda * step.y());
        if (next && next->r.norm() < cur->r.norm()) {
          has_prev = true;
          prev_point = Vec2(len, b);
          prev_jac = cur->jac;
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
  if (!full) return std::nullopt;
  // other starts: a symmetric fillet, then unequal ones (tangent corners are not symmetric)
  for (const double ratio : {1.0, 0.5, 2.0}) {
    if (auto sol = solve_from(a * (1 + ratio), a * ratio)) return sol;
  }
  return std::nullopt;
}

// The pair's half has the displacement scale (C(u), S(u)) in its start's frame and the length
// scale u; the chord bisects the turn, so half the chord is scale (C(u) cos(turn / 2) +
// S(u) sin(turn / 2)) (derived here).
double biclothoid_hairpin_length(double chord, double turn) {
  if (!(turn > 0) || !(chord >= 0)) return 0.0;
  const ClothoidPairShape shape = clothoid_pair_shape(turn);
  const double half_chord = shape.c * shape.cos_half + shape.s * shape.sin_half;  // per unit scale
  return half_chord > 0 ? chord * shape.u / half_chord : 0.0;
}

std::optional<BiclothoidSolution> fit_biclothoid_at(const CornerShapes& shapes, double a, double guess_length,
                                                    double guess_b) {
  const auto sol = fit_at(shapes, a, guess_length, guess_b);
  if (!sol) return std::nullopt;
  return sol->fillet;
}

}  // namespace blendbench
