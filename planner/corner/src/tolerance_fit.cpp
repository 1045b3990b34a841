// Equal tolerance (docs/methods.md, "Equal tolerance"): every method sized at each corner so
// that the corner's deviation, as the corner report gives it, equals one tolerance T.
//
// The unknown is the method's own parameter p (corner distance for arc, TP for bezier, the
// deviation asked of the clothoid and biclothoid fits), the equation dev(p) = T with dev the
// two-sided Hausdorff distance between the transition and the programmed stretch it replaces
// (corner_deviation, the value path_deviation_max_mm takes its maximum over).
//
// Closed forms (two lines, tangent turn theta; derived here):
//  - arc (seed 001): the fillet of corner distance d has radius r = d / tan(theta / 2); the
//    corner lies r / cos(theta / 2) from its centre, so the corner is r (1 / cos(theta / 2) - 1)
//    = d tan(theta / 4) from the arc, and no point of either line or of the arc is farther from
//    the other curve (the arc's midpoint is cos(theta / 2) of that from the lines):
//    dev = d tan(theta / 4). At a reversal (theta = pi) both lines are shortened by d and the
//    corner is d from the kept path: dev = d, the same formula.
//  - bezier (seed 000 eq. 8-9): the cubic P0, B, B, P3 with |P0 - B| = |P3 - B| = L has
//    C(u) - B = L (-a t_in + b t_out), a = (1 - u)^3, b = u^3, so with w = u (1 - u) and
//    c = cos(theta): |C - B|^2 / L^2 = (1 - 3w)^2 - 2 w^3 (1 + c), whose derivative in w,
//    -6 (1 - 3w) - 6 w^2 (1 + c), is negative on [0, 1/4]: the corner's nearest curve point is
//    the midpoint (w = 1/4), at L sin(theta / 2) / 4. The midpoint is cos(theta / 2) of that
//    from the lines, and (checked on a grid of turns, and by the tests' dense measure) no other
//    curve point is farther: dev = L sin(theta / 2) / 4.
//  - clothoid, biclothoid: the parameter is the deviation (seed 002 eq. 9, seed 004 section 7.1).
// Everywhere else (arcs, non-planar corners, the clothoid's curvature cap, short moves) dev(p)
// is measured and solved for.
//
// Monotone: dev grows with p for every method on every corner kind where p changes the
// transition (for two lines by the closed forms; elsewhere tested on random corners,
// tolerance_fit_test); where the method leaves the corner as it is (a tangent corner for the
// arc, collinear lines, one circle continued) dev is 0 for every p, and where p is shrunk to
// the moves (CornerFit::limited) dev stays at its value there. Where a method switches
// construction as p grows (the Bezier's cubic to its quartic, the arc's rule with the roles
// swapped) dev may jump; the search then ends at the jump, below T, and says so.
//
// The search: x = log p, y = log(dev / T), nearly linear (dev ~ p at a tangent jump, ~ p^2 at a
// curvature jump alone). From the closed form's p (exact for two lines; a model elsewhere),
// secant steps in (x, y) aimed kAim below T, a step of the model's slope before two points are
// known, at most a factor kMaxStep a step; once T is bracketed, regula falsi with the Illinois
// halving and bisection when a step leaves the bracket. It stops at the first p with
// T (1 - kSolveBand) <= dev <= T, at a limited fit within T, or when the bracket closes on a
// jump. Cost: one fit where a closed form holds (two lines) or the fit solves the deviation
// itself (biclothoid, clothoid); elsewhere a fit and a Hausdorff measure per step, two to four
// steps on most corners (bench_blend: BM_ToleranceProgram).

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "blendbench/core/format.hpp"
#include "blendbench/corner/corner.hpp"

namespace blendbench {
namespace {

// The search stops once T (1 - kSolveBand) <= dev <= T, the band the corner report calls
// reached (corner.hpp); it aims kAim below T (in log), well inside it.
constexpr double kSolveBand = kToleranceBand;
constexpr double kAim = 0.3 * kSolveBand;
// The closed forms aim this share below T: dev = T exactly to rounding, never above it.
constexpr double kClosedFormAim = 1e-12;
// A deviation below this share of T is none: the method cuts nothing at this corner.
constexpr double kNoCut = 1e-9;
// Fits tried per corner at most, and the largest step (a factor in p) before a bracket.
constexpr int kMaxEvaluations = 60;
const double kMaxStep = std::log(8.0);
// Halvings of p tried where no fit succeeds before any has (the method fails at this corner).
constexpr int kMaxBackOff = 8;
// The bracket is closed (a jump of dev in p) at this width in log p: the parameter to 1e-6.
constexpr double kBracketClosed = 1e-6;
// rad: tangents closer than this meet without a turn (the blender's G1 threshold).
constexpr double kStraight = 1e-9;
// Bezier at a curvature jump alone (a tangent corner between a line and an arc or two arcs),
// the model dev = |kappa jump| TP^2 / kBezierCurvatureJump for the first step (a fit on
// corners of this kind; the search corrects it, so only its order matters).
constexpr double kBezierCurvatureJump = 20.0;

using Fitter = CornerFit (*)(const CornerInput&);

Fitter fitter_of(Method method) {
  switch (method) {
    case Method::kArc: return fit_arc_corner;
    case Method::kBezier: return fit_bezier_corner;
    case Method::kClothoid: return fit_clothoid_corner;
    case Method::kBiclothoid: return fit_biclothoid_corner;
    case Method::kNone: break;
  }
  return nullptr;
}

const char* parameter_name(Method method) {
  switch (method) {
    case Method::kArc: return "corner distance";
    case Method::kBezier: return "TP";
    default: return "deviation";
  }
}

// The curvature (1/m) of a move at arc length s (0 on a line).
double curvature_at(const Primitive& move, double s) { return curvature_vector(move, s).norm(); }

// One fit of the search: at x = log p, its deviation and y = log(dev / T).
struct Trial {
  double x = 0;
  double y = std::numeric_limits<double>::infinity();
  double dev = 0;
  bool ok = false;
  CornerFit fit;
};

}  // namespace

CornerFit fit_corner_at_tolerance(const CornerInput& corner) {
  const double tol = corner.spec.tolerance;
  const Method method = corner.spec.method;
  const Fitter fit_at = fitter_of(method);
  CornerInput work = corner;
  work.spec.tolerance = 0;
  work.spec.start_distance = 0;

  // the corner's turn, and the closed form of two lines: dev = factor p
  const double len_in = length(corner.in);
  const Vec3 t_in = tangent(corner.in, len_in);
  const Vec3 t_out = tangent(corner.out, 0.0);
  const double theta = angle_between(t_in, t_out);
  const bool lines = std::holds_alternative<Line>(corner.in) && std::holds_alternative<Line>(corner.out);
  // (none where the lines continue each other: nothing to cut there, at any parameter)
  double factor = 0;  // dev per unit parameter for two lines (0: no closed form)
  if (lines && theta > kStraight) {
    if (method == Method::kArc) factor = std::tan(0.25 * theta);
    if (method == Method::kBezier && theta < std::numbers::pi - kReversalAngle) factor = 0.25 * std::sin(0.5 * theta);
  }

  // the first parameter: the closed form for two lines, and the models elsewhere (the line-line
  // forms at the corner's turn; the Bezier's curvature-jump model added where one acts)
  double p0 = tol;
  double slope = 1;  // d log dev / d log p the first step assumes
  if (method == Method::kArc && theta > kStraight) p0 = tol / std::tan(0.25 * theta);
  if (method == Method::kBezier) {
    const double jump = std::abs(curvature_at(corner.in, len_in) - curvature_at(corner.out, 0.0));
    const double linear = theta > kStraight ? 0.25 * std::sin(0.5 * std::min(theta, 0.5 * std::numbers::pi)) : 0.0;
    const double quadratic = jump / kBezierCurvatureJump;
    // the positive root of quadratic p^2 + linear p = tol
    if (quadratic > 0) {
      p0 = 2 * tol / (linear + std::sqrt(linear * linear + 4 * quadratic * tol));
      slope = linear * p0 >= quadratic * p0 * p0 ? 1.0 : 2.0;
    } else if (linear > 0) {
      p0 = tol / linear;
    }
  }
  if (factor > 0) p0 = tol * (1 - kClosedFormAim) / factor;
  // the clothoid's and biclothoid's parameter is the deviation: exact for two lines (seed 002 eq.
  // 9), solved by the fit with arcs (seed 004 Algorithm 2)
  if (method == Method::kClothoid || method == Method::kBiclothoid) p0 = tol * (1 - kClosedFormAim);

  const auto evaluate = [&](double x) {
    Trial t;
    t.x = x;
    work.spec.parameter = std::exp(x);
    t.fit = fit_at(work);
    // a cusp is refused as the blender refuses it (cusp_problem): the search backs off from it
    if (t.fit.outcome.ok()) {
      if (std::string cusp = cusp_problem(work, t.fit); !cusp.empty()) t.fit.outcome = {Status::kInfeasible, std::move(cusp)};
    }
    t.ok = t.fit.outcome.ok();
    if (!t.ok) return t;
    t.dev = factor > 0 ? factor * t.fit.parameter_used : corner_deviation(t.fit, corner.in, corner.out);
    t.y = t.dev > 0 ? std::log(t.dev / tol) : -std::numeric_limits<double>::infinity();
    return t;
  };
  const auto within = [&](const Trial& t) { return t.ok && t.dev <= tol; };
  const auto in_band = [&](const Trial& t) { return within(t) && t.dev >= tol * (1 - kSolveBand); };

  Trial best;  // the largest p with dev <= T so far
  bool have_best = false;
  Trial first_failure;  // the first fit that failed, for the outcome where none succeeds
  bool failed = false;
  Trial lo_point;  // bracket: y <= 0 at lo, y > 0 (or no fit) at hi
  Trial hi_point;
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  int lo_stuck = 0;  // Illinois: steps in a row that moved the same end of the bracket
  int hi_stuck = 0;
  Trial prev;
  bool have_prev = false;
  const double y_aim = std::log1p(-kAim);
  double x = std::log(p0);
  bool jump = false;
  int back_offs = 0;
  for (int it = 0; it < kMaxEvaluations; ++it) {
    Trial cur = evaluate(x);
    if (!cur.ok && !failed) {
      first_failure = cur;
      failed = true;
    }
    if (within(cur)) {
      if (!have_best || cur.x > best.x) {
        best = cur;
        have_best = true;
      }
      // the tolerance reached, the moves exhausted, or nothing to cut (no parameter deviates)
      if (in_band(cur) || cur.fit.limited || cur.dev <= kNoCut * tol) break;
      if (cur.x > lo) {
        lo = cur.x;
        lo_point = cur;
        ++lo_stuck;
        hi_stuck = 0;
      }
    } else if (cur.x < hi) {
      hi = cur.x;
      hi_point = cur;
      ++hi_stuck;
      lo_stuck = 0;
    }
    // the next x
    double next = 0;
    const bool bracket = std::isfinite(lo) && std::isfinite(hi);
    if (bracket) {
      if (hi - lo < kBracketClosed) {
        jump = true;
        break;
      }
      // regula falsi between the ends (a failed fit at hi counts as far above), halving the
      // stuck end's value (Illinois) so that the bracket closes from both sides
      double y_lo = lo_point.y - y_aim;
      double y_hi = hi_point.ok ? hi_point.y - y_aim : std::numeric_limits<double>::infinity();
      if (lo_stuck > 1) y_hi = std::ldexp(y_hi, 1 - lo_stuck);
      if (hi_stuck > 1) y_lo = std::ldexp(y_lo, 1 - hi_stuck);
      next = std::isfinite(y_hi) && std::isfinite(y_lo) && y_hi > y_lo ? lo - y_lo * (hi - lo) / (y_hi - y_lo)
                                                                       : 0.5 * (lo + hi);
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    } else if (!cur.ok) {
      // no fit here: back off, by at most kMaxBackOff halvings in all; not at two lines, where
      // every parameter gives the same shape (the closed forms), so a fit failing at one fails at all
      if (factor > 0 || ++back_offs > kMaxBackOff) break;
      next = cur.x - std::log(2.0);
    } else {
      double s = slope;
      if (have_prev && prev.ok && std::isfinite(prev.y) && std::isfinite(cur.y) && cur.x != prev.x) {
        const double secant = (cur.y - prev.y) / (cur.x - prev.x);
        // (a construction that changes branch can leave dev nearly flat in p: the step's clamp,
        // not the slope, bounds it there)
        if (secant > 1e-3 && secant < 100) s = secant;
      }
      const double step = std::isfinite(cur.y) ? (y_aim - cur.y) / s : kMaxStep;
      next = cur.x + std::clamp(step, -kMaxStep, kMaxStep);
    }
    prev = cur;
    have_prev = true;
    x = next;
  }

  if (!have_best) {
    // no fit within the tolerance at any parameter tried: the method's own failure, or none
    CornerFit out = failed ? first_failure.fit : CornerFit{};
    if (out.outcome.ok()) {
      out.outcome = {Status::kInfeasible, "no " + std::string(to_string(method)) + " transition within the tolerance " +
                                              format_mm(tol) + " was found"};
    }
    return out;
  }
  CornerFit fit = std::move(best.fit);
  const double dev = best.dev;
  // the deviation as it was measured at the solution, for the report
  fit.exact_deviation = dev;
  // nothing to cut: a corner the method leaves as it is at any parameter (G1 already, or a
  // reversal a curve cannot join); a fit shrunk to nothing, where the previous corner used a
  // move up, is limited instead
  const CornerCase c = fit.corner_case;
  const bool g1 = c == CornerCase::kCollinear || c == CornerCase::kTangent || c == CornerCase::kTangentOpposite ||
                  c == CornerCase::kSameCircleSameDirection;
  if (dev <= kNoCut * tol && (g1 || c == CornerCase::kReversal)) {
    // the corner as the method leaves it (no transition where one would only retrace the
    // programmed path, e.g. the arc's piece of a tangent move)
    if (method == Method::kArc && g1) {
      work.spec.parameter = 0;
      fit = fit_at(work);
    }
    const std::string why = "nothing to cut: the " + std::string(to_string(method)) + " method leaves this " +
                            std::string(to_string(fit.corner_case)) + " corner as programmed";
    fit.note = fit.note.empty() ? Note(why) : Note(why + "; " + fit.note.text());
    return fit;
  }
  if (in_band(best)) return fit;
  // below the tolerance: say why
  std::string why = "tolerance " + format_mm(tol) + " not reached (deviation " + format_mm(dev) + "): ";
  if (fit.limited) {
    why += "the largest transition that fits, " + std::string(parameter_name(method)) + " " + format_mm(fit.parameter_used);
  } else if (jump) {
    why += "the deviation jumps past the tolerance at " + std::string(parameter_name(method)) + " " +
           format_mm(std::exp(hi)) + (hi_point.ok ? "" : " (no transition fits above it: " + hi_point.fit.outcome.message + ")");
  } else if (dev <= kNoCut * tol) {
    why += "the " + std::string(to_string(method)) + " method cuts nothing at this " +
           std::string(to_string(fit.corner_case)) + " corner";
  } else {
    why += "the search stopped after " + std::to_string(kMaxEvaluations) + " fits";
  }
  fit.note = fit.note.empty() ? Note(why) : Note(why + "; " + fit.note.text());
  return fit;
}

}  // namespace blendbench
