#include "blendbench/program/g2_fit.hpp"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <unsupported/Eigen/Splines>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include "blendbench/core/format.hpp"
#include "blendbench/geometry/follow_distance.hpp"

// Eigen's B-spline basis (unsupported/Eigen/Splines: Piegl and Tiller's algorithms A2.1 and
// A2.3) gives the basis functions and their derivatives; Eigen has no penalised or constrained
// spline fit, and GSL's would break the planner's Eigen-only layering, so the fit is written
// here.

namespace blendbench {
namespace {

constexpr int kDegree = 5;
constexpr int kOrder = kDegree + 1;
using Basis = Eigen::Spline<double, 1, kDegree>;
using Knots = Basis::KnotVectorType;

// Knots (place_knots): a span ends where the lines' direction, seen over kDirectionWindow
// tolerances, has turned by kSpanTurn since its start, and lasts between kMinSpan and kMaxSpan
// tolerances. A quintic span follows a circle arc of a fifth of a radian to far below the
// tolerance, so the turn limit is the spline's resolution where the stream bends; the length
// limits keep the pieces few where it runs straight (the velocity planner cuts each into 16
// intervals) and fine enough at a sharp vertex. Where the fit cannot stay within the tolerance
// the spans there are halved (kMaxRefinements times at most).
constexpr double kSpanTurn = 0.2;  // rad
constexpr double kMinSpan = 2;
constexpr double kMaxSpan = 200;
constexpr double kDirectionWindow = 4;
constexpr int kMinSpans = 6;
constexpr int kMaxRefinements = 4;
// ADMM (Fit::admm): iterations per parameter pass, and passes (the first on chord lengths, then
// each after the points' parameters move to their closest points); over-relaxation (1.5-1.8 is
// the usual range); the balance of the residuals that changes rho, checked every kBalanceEvery
// iterations; and the residuals, as a share of the radius, at which it has converged.
constexpr int kIterations = 400;
constexpr int kPasses = 3;
constexpr double kRelaxation = 1.6;
constexpr double kBalance = 10;
constexpr int kBalanceEvery = 10;
constexpr double kConverged = 0.05;
// rho stays within this factor of its start; a pass without a solution inside the tolerance
// stops when the largest residual, still above kStallFar times the radius, fell by less than
// kStallShare over kStall iterations.
constexpr double kRhoRange = 1e6;
constexpr int kStall = 50;
constexpr double kStallShare = 0.05;
constexpr double kStallFar = 1.5;
// The radius ADMM keeps the residuals in, as a share of the tolerance, and the shares it tries
// next when the measured distance is still above the tolerance (the residual at the points'
// parameters bounds their distance from above; the lines between them and the chord sampling of
// the measurement take the rest).
constexpr std::array<double, 3> kTargets = {0.9, 0.8, 0.7};
// The largest residual a solution may keep, as a share of the tolerance.
constexpr double kAccept = 0.95;
// The normalisation: positions and parameters in units of this many tolerances.
constexpr double kUnit = 20;
// A curve whose speed in its parameter (nominally 1, the parameter being close to arc length)
// falls below this would turn about a cusp, and one whose curvature exceeds kMaxCurvature over
// the tolerance turns about a near-cusp: refused (the knots refined). A stream within the
// tolerance of a smooth curve needs no radius below half the tolerance (a hairpin in its tube).
constexpr double kMinSpeed = 0.05;
constexpr double kMaxCurvature = 10;
constexpr int kSpeedSamples = 8;
// The measurement's resolution (follow_distance.hpp) as a share of the tolerance, and its
// reach: how far along the lines a point's nearest part is looked for.
constexpr double kResolutionShare = 0.05;
constexpr double kReachPerTolerance = 4;
constexpr double kReachPerLine = 2;
// Newton steps per closest-point correction of a parameter.
constexpr int kNewtonSteps = 3;

// A control point as an affine form of the unknowns: constant + sum of coef * z[var].
struct Term {
  int var;
  Vec3 coef;
};
struct ControlForm {
  Vec3 constant = Vec3::Zero();
  std::vector<Term> terms;
};

// Where the lines of `points` (arc length `sigma` at each) are at arc length `at` (clamped).
Vec3 polyline_at(const std::vector<Vec3>& points, const std::vector<double>& sigma, double at) {
  at = std::clamp(at, 0.0, sigma.back());
  const auto it = std::upper_bound(sigma.begin(), sigma.end(), at);
  const std::size_t k = std::min(static_cast<std::size_t>(std::max<std::ptrdiff_t>(it - sigma.begin() - 1, 0)), sigma.size() - 2);
  const double len = sigma[k + 1] - sigma[k];
  return len > 0 ? Vec3(points[k] + (points[k + 1] - points[k]) * ((at - sigma[k]) / len)) : points[k];
}

// The breakpoints of the spline (m of arc length along the lines, from 0 to the total): each span
// ends where the direction of the lines, as the chord over a window of kDirectionWindow
// tolerances shows it (rounding noise of the points averages out over it), has turned by
// kSpanTurn since the span's start, and is kMinSpan to kMaxSpan tolerances long. A closed
// stream's first two spans equal its last two (the seam's constraints, Fit::build_forms).
std::vector<double> place_knots(const std::vector<Vec3>& points, const std::vector<double>& sigma, double tolerance, bool closed) {
  const double total = sigma.back();
  const double window = kDirectionWindow * tolerance;
  const double min_span = std::min(kMinSpan * tolerance, total / kMinSpans);
  const double max_span = std::max(kMaxSpan * tolerance, min_span);
  // the cumulative turning of the window's chord, sampled a quarter window apart
  const double step = 0.25 * window;
  const auto samples = static_cast<std::size_t>(std::ceil(total / step));
  std::vector<double> turning(samples + 1, 0.0);
  const auto direction = [&](double at) {
    return Vec3(polyline_at(points, sigma, at + 0.5 * window) - polyline_at(points, sigma, at - 0.5 * window));
  };
  Vec3 previous = direction(0.0);
  for (std::size_t j = 1; j <= samples; ++j) {
    const Vec3 d = direction(std::min(total, static_cast<double>(j) * step));
    const double turn = d.norm() > 0 && previous.norm() > 0 ? angle_between(previous, d) : 0.0;
    turning[j] = turning[j - 1] + turn;
    if (d.norm() > 0) previous = d;
  }
  const auto turning_at = [&](double at) {
    if (samples == 0) return 0.0;
    const double x = std::clamp(at / step, 0.0, static_cast<double>(samples));
    const auto j = std::min(static_cast<std::size_t>(x), samples - 1);
    return turning[j] + (turning[j + 1] - turning[j]) * (x - static_cast<double>(j));
  };
  std::vector<double> out{0.0};
  while (total - out.back() > min_span) {
    const double from = out.back();
    const double budget = turning_at(from) + kSpanTurn;
    // the farthest end within both limits, by bisection on the (non-decreasing) turning
    double lo = from + min_span;
    double hi = std::min(from + max_span, total);
    if (turning_at(hi) > budget) {
      for (int it = 0; it < 40; ++it) {
        const double mid = 0.5 * (lo + hi);
        (turning_at(mid) > budget ? hi : lo) = mid;
      }
      hi = lo;
    }
    out.push_back(total - hi < min_span ? total : hi);  // no sliver at the end
  }
  out.back() = total;
  // at least kMinSpans spans: split the longest
  while (out.size() < static_cast<std::size_t>(kMinSpans) + 1) {
    std::size_t widest = 0;
    for (std::size_t i = 1; i + 1 < out.size(); ++i) {
      if (out[i + 1] - out[i] > out[widest + 1] - out[widest]) widest = i;
    }
    out.insert(out.begin() + static_cast<std::ptrdiff_t>(widest) + 1, 0.5 * (out[widest] + out[widest + 1]));
  }
  if (closed) {
    // the first two spans and the last two alike, the narrower of each pair
    const std::size_t n = out.size() - 1;
    const double a = std::min(out[1] - out[0], out[n] - out[n - 1]);
    const double b = std::min(out[2] - out[1], out[n - 1] - out[n - 2]);
    std::vector<double> inner;
    for (std::size_t i = 2; i + 2 <= n; ++i) {
      if (out[i] > a + b + 0.5 * min_span && out[i] < total - a - b - 0.5 * min_span) inner.push_back(out[i]);
    }
    out = {0.0, a, a + b};
    out.insert(out.end(), inner.begin(), inner.end());
    for (const double x : {total - a - b, total - a, total}) out.push_back(x);
  }
  return out;
}

// One fit on given breakpoints, in normalised coordinates: positions relative to the first point,
// positions and parameters divided by the unit (kUnit tolerances).
//
// The problem: minimise E = integral |C'''(u)|^2 over the control points (affine in the unknowns
// z, build_forms) subject to |C(u_k) - x_k| <= radius at every data point. Convex (a quadratic
// objective, one ball per point), solved by ADMM (Boyd et al., "Distributed optimization and
// statistical learning via the alternating direction method of multipliers", 2011, sections 3.1
// and 3.4): with v_k = C(u_k) - x_k kept in the ball and scaled multipliers l_k,
//   z:   minimise E + rho / 2 sum |C(u_k) - x_k - v_k + l_k|^2   (a weighted least-squares
//        spline, the same matrix for every iteration at one rho: factored once),
//   v_k: the projection of a r_k + (1 - a) v_k + l_k onto the ball (r_k = C(u_k) - x_k, a the
//        over-relaxation),
//   l_k: += a r_k + (1 - a) v_k - v_k(new),
// rho doubled or halved when the primal and dual residuals drift apart by kBalance (3.4.1); the
// iterate kept is the smoothest whose residuals all lie within the acceptance.
class Fit {
 public:
  Fit(const std::vector<Vec3>& x, const std::vector<double>& u, const std::vector<double>& breaks, const CurveEnds& ends)
      : x_(x), u_(u), ends_(ends), v_(x.size(), Vec3::Zero()), l_(x.size(), Vec3::Zero()) {
    set_breaks(breaks);
    // rho: the weight that makes the data term per unit of parameter one, like the penalty's
    rho0_ = rho_ = breaks.back() / static_cast<double>(x.size());
  }

  // New breakpoints (the same ends), keeping the points' parameters and the multipliers: a
  // refinement starts where the coarser fit left off.
  void set_breaks(const std::vector<double>& breaks) {
    breaks_ = breaks;
    spans_ = static_cast<int>(breaks_.size()) - 1;
    nc_ = spans_ + kDegree;
    knots_.resize(nc_ + kOrder);
    for (int i = 0; i < nc_ + kOrder; ++i) knots_(i) = breaks_[static_cast<std::size_t>(std::clamp(i - kDegree, 0, spans_))];
    build_forms();
    build_penalty();
    update_basis();
    factored_ = false;
    forget_best();
  }

  // ADMM iterations towards |C(u_k) - x_k| <= radius, keeping the smoothest iterate whose
  // residuals all stay within `accept`; stops once it has one and both residuals fall below
  // kConverged of the radius. Returns the iterations made.
  int admm(double radius, double accept, int iterations) {
    int made = 0;
    std::vector<Vec3> targets(x_.size());
    double stall_worst = std::numeric_limits<double>::infinity();
    for (int it = 0; it < iterations; ++it, ++made) {
      if (!factored_) factor();
      for (std::size_t k = 0; k < x_.size(); ++k) targets[k] = x_[k] + v_[k] - l_[k];
      solve(targets);
      double primal = 0;
      double dual = 0;
      double worst = 0;
      for (std::size_t k = 0; k < x_.size(); ++k) {
        const Vec3 r = eval(k) - x_[k];
        worst = std::max(worst, r.norm());
        const Vec3 relaxed = kRelaxation * r + (1 - kRelaxation) * v_[k];
        Vec3 v = relaxed + l_[k];
        const double norm = v.norm();
        if (norm > radius) v *= radius / norm;
        dual = std::max(dual, (v - v_[k]).norm());
        l_[k] += relaxed - v;
        v_[k] = v;
        primal = std::max(primal, (r - v).norm());
      }
      worst_ = worst;
      if (worst <= accept && q_finite()) keep_if_smoother();
      if (!best_.empty() && primal <= kConverged * radius && dual <= kConverged * radius) {
        ++made;
        break;
      }
      // residual balancing (3.4.1), both residuals as lengths: the primal one the largest gap
      // between a residual and its ball's point, the dual one (over rho) the largest change of v
      if (it % kBalanceEvery == kBalanceEvery - 1) {
        if (primal > kBalance * dual && rho_ < kRhoRange * rho0_) rescale(2);
        else if (dual > kBalance * primal && rho_ > rho0_ / kRhoRange) rescale(0.5);
      }
      // no point inside yet and the largest residual no longer falling: the spline cannot reach
      // the points there (refine the knots)
      if (best_.empty() && it % kStall == kStall - 1) {
        if (worst > kStallFar * radius && worst > (1 - kStallShare) * stall_worst) {
          ++made;
          break;
        }
        stall_worst = worst;
      }
    }
    return made;
  }

  // Moves each point's parameter to its closest point on the current curve (Newton on
  // (C(u) - x) . C'(u) = 0 from the current parameter), keeping them ordered and the ends fixed.
  void correct_parameters() {
    const double end = breaks_.back();
    for (std::size_t k = 1; k + 1 < x_.size(); ++k) {
      double u = u_[k];
      for (int step = 0; step < kNewtonSteps; ++step) {
        const auto d = derivatives(u, 2);
        const Vec3 r = d[0] - x_[k];
        const double f = r.dot(d[1]);
        const double df = d[1].squaredNorm() + r.dot(d[2]);
        if (!(df > 0)) break;
        u = std::clamp(u - f / df, 0.0, end);
      }
      u_[k] = u;
    }
    for (std::size_t k = 1; k < x_.size(); ++k) u_[k] = std::max(u_[k], u_[k - 1]);
    u_.back() = end;
    update_basis();
    factored_ = false;
  }

  [[nodiscard]] bool has_solution() const { return !best_.empty(); }
  [[nodiscard]] double worst() const { return worst_; }
  [[nodiscard]] const std::vector<double>& parameters() const { return u_; }
  [[nodiscard]] const std::vector<double>& breaks() const { return breaks_; }
  void use_best() {
    if (!best_.empty()) q_ = best_;
  }
  void forget_best() {
    best_.clear();
    best_energy_ = std::numeric_limits<double>::infinity();
  }

  // Per span, whether it holds a point whose residual on the current curve exceeds `limit`.
  [[nodiscard]] std::vector<bool> spans_over(double limit) const {
    std::vector<bool> out(static_cast<std::size_t>(spans_), false);
    for (std::size_t k = 0; k < x_.size(); ++k) {
      if (!((eval(k) - x_[k]).norm() > limit)) continue;
      const auto it = std::upper_bound(breaks_.begin(), breaks_.end(), u_[k]);
      out[static_cast<std::size_t>(std::clamp<std::ptrdiff_t>(it - breaks_.begin() - 1, 0, spans_ - 1))] = true;
    }
    return out;
  }

  // Position and derivatives up to `order` (<= kDegree) of the current curve at u.
  [[nodiscard]] std::array<Vec3, kOrder> derivatives(double u, int order) const {
    const auto ders = Basis::BasisFunctionDerivatives(u, order, kDegree, knots_);
    const int first = static_cast<int>(Basis::Span(u, kDegree, knots_)) - kDegree;
    std::array<Vec3, kOrder> out;
    out.fill(Vec3::Zero());
    for (int d = 0; d <= order; ++d) {
      for (int a = 0; a < kOrder; ++a) out[static_cast<std::size_t>(d)] += ders(d, a) * q_[static_cast<std::size_t>(first + a)];
    }
    return out;
  }

  // The smallest speed |C'(u)| over kSpeedSamples points per span.
  [[nodiscard]] double min_speed() const {
    double out = std::numeric_limits<double>::infinity();
    for (std::size_t e = 0; e + 1 < breaks_.size(); ++e) {
      for (int j = 0; j <= kSpeedSamples; ++j) {
        const double u = breaks_[e] + (breaks_[e + 1] - breaks_[e]) * j / kSpeedSamples;
        out = std::min(out, derivatives(u, 1)[1].norm());
      }
    }
    return out;
  }

  [[nodiscard]] int spans() const { return spans_; }

 private:
  // The control points as affine forms of the unknowns (the clamped ends: the first and last
  // control points are the curve's ends). With a and b the widths of the first two spans,
  // C'(0) = (p / a) (Q1 - Q0) and C''(0) = p (p - 1) / a ((Q2 - Q1) / (a + b) - (Q1 - Q0) / a);
  // the same mirrored at the end.
  void build_forms() {
    forms_.assign(static_cast<std::size_t>(nc_), ControlForm{});
    int vars = 0;
    const auto free_point = [&](ControlForm& f) {
      f.terms = {{vars, Vec3::UnitX()}, {vars + 1, Vec3::UnitY()}, {vars + 2, Vec3::UnitZ()}};
      vars += 3;
    };
    const std::size_t last = static_cast<std::size_t>(nc_) - 1;
    const Vec3 start = x_.front();
    const Vec3 end = x_.back();
    const double a = breaks_[1] - breaks_[0];
    const double b = breaks_[2] - breaks_[1];
    const double a_end = breaks_[breaks_.size() - 1] - breaks_[breaks_.size() - 2];
    for (std::size_t i = 0; i <= last; ++i) {
      ControlForm& f = forms_[i];
      if (i == 0) {
        f.constant = start;
      } else if (i == last) {
        f.constant = ends_.closed ? start : end;
      } else if (ends_.closed && i == last - 1) {
        // C'(0) = C'(U), the end spans alike (place_knots): Q_{m-1} = 2 Q_0 - Q_1
        f.constant = 2 * start - forms_[1].constant;
        for (const Term& t : forms_[1].terms) f.terms.push_back({t.var, -t.coef});
      } else if (ends_.closed && i == last - 2) {
        // C''(0) = C''(U): Q_{m-2} = Q_2 - c Q_1 + c Q_0, c = 2 + 2 (a + b) / a
        const double c = 2 + 2 * (a + b) / a;
        f.constant = forms_[2].constant - c * forms_[1].constant + c * start;
        for (const Term& t : forms_[2].terms) f.terms.push_back(t);
        for (const Term& t : forms_[1].terms) f.terms.push_back({t.var, -c * t.coef});
      } else if (!ends_.closed && ends_.start_tangent && i == 1) {
        // unit speed along the joining line
        f.constant = start + a / kDegree * *ends_.start_tangent;
      } else if (!ends_.closed && ends_.start_tangent && i == 2) {
        // zero curvature at the start: Q_2 on the tangent line, anywhere along it
        f.constant = start;
        f.terms = {{vars++, *ends_.start_tangent}};
      } else if (!ends_.closed && ends_.end_tangent && i == last - 1) {
        f.constant = end - a_end / kDegree * *ends_.end_tangent;
      } else if (!ends_.closed && ends_.end_tangent && i == last - 2) {
        f.constant = end;
        f.terms = {{vars++, -*ends_.end_tangent}};
      } else {
        free_point(f);
      }
    }
    vars_ = vars;
    q_.assign(static_cast<std::size_t>(nc_), Vec3::Zero());
  }

  // The penalty: integral of |C'''(u)|^2, a band of the control points' Gram matrix of third
  // derivatives; C''' of a quintic is quadratic, so 3-point Gauss-Legendre per span is exact.
  void build_penalty() {
    penalty_.assign(static_cast<std::size_t>(nc_), {});
    const double r = std::sqrt(0.6);
    const std::array<double, 3> nodes = {0.5 - 0.5 * r, 0.5, 0.5 + 0.5 * r};
    const std::array<double, 3> weights = {5.0 / 18, 8.0 / 18, 5.0 / 18};
    for (std::size_t e = 0; e + 1 < breaks_.size(); ++e) {
      const double width = breaks_[e + 1] - breaks_[e];
      for (std::size_t g = 0; g < nodes.size(); ++g) {
        const double u = breaks_[e] + width * nodes[g];
        const auto ders = Basis::BasisFunctionDerivatives(u, 3, kDegree, knots_);
        const int first = static_cast<int>(Basis::Span(u, kDegree, knots_)) - kDegree;
        for (int i = 0; i < kOrder; ++i) {
          for (int j = i; j < kOrder; ++j) {
            penalty_[static_cast<std::size_t>(first + i)][static_cast<std::size_t>(j - i)] +=
                width * weights[g] * ders(3, i) * ders(3, j);
          }
        }
      }
    }
  }

  void update_basis() {
    first_.resize(x_.size());
    basis_.resize(x_.size());
    for (std::size_t k = 0; k < x_.size(); ++k) {
      const auto values = Basis::BasisFunctions(u_[k], kDegree, knots_);
      first_[k] = static_cast<int>(Basis::Span(u_[k], kDegree, knots_)) - kDegree;
      for (int a = 0; a < kOrder; ++a) basis_[k][static_cast<std::size_t>(a)] = values(a);
    }
  }

  [[nodiscard]] Vec3 eval(std::size_t k) const {
    Vec3 p = Vec3::Zero();
    for (int a = 0; a < kOrder; ++a) p += basis_[k][static_cast<std::size_t>(a)] * q_[static_cast<std::size_t>(first_[k] + a)];
    return p;
  }

  // The z-update's matrix at the current rho: the banded M = penalty + w sum N N^T (w = rho / 2)
  // reduced to the unknowns through the control points' forms, factored; and sum_j M_ij c_j,
  // the constant parts' share of the right-hand side.
  void factor() {
    const auto n = static_cast<std::size_t>(nc_);
    const double w = 0.5 * rho_;
    std::vector<std::array<double, kOrder>> band = penalty_;
    for (std::size_t k = 0; k < x_.size(); ++k) {
      const auto f = static_cast<std::size_t>(first_[k]);
      const auto& nk = basis_[k];
      for (std::size_t a = 0; a < kOrder; ++a) {
        for (std::size_t b = a; b < kOrder; ++b) band[f + a][b - a] += w * nk[a] * nk[b];
      }
    }
    offset_.assign(n, Vec3::Zero());
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(n * kOrder * 9 * 2);
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t d = 0; d < kOrder && i + d < n; ++d) {
        const double m = band[i][d];
        offset_[i] += m * forms_[i + d].constant;
        if (d > 0) offset_[i + d] += m * forms_[i].constant;
        for (const Term& s : forms_[i].terms) {
          for (const Term& t : forms_[i + d].terms) {
            const double c = m * s.coef.dot(t.coef);
            if (c == 0) continue;
            triplets.emplace_back(s.var, t.var, c);
            if (d > 0) triplets.emplace_back(t.var, s.var, c);
          }
        }
      }
    }
    Eigen::SparseMatrix<double> system(vars_, vars_);
    system.setFromTriplets(triplets.begin(), triplets.end());
    solver_.compute(system);
    factored_ = true;
  }

  // The z-update for `targets`: the control points minimising the penalty plus w sum |C(u_k) -
  // target_k|^2 (the factored matrix; the right-hand side sum w N target - sum M c).
  void solve(const std::vector<Vec3>& targets) {
    const auto n = static_cast<std::size_t>(nc_);
    const double w = 0.5 * rho_;
    std::vector<Vec3> g(n, Vec3::Zero());
    for (std::size_t k = 0; k < x_.size(); ++k) {
      const auto f = static_cast<std::size_t>(first_[k]);
      const Vec3 wt = w * targets[k];
      for (std::size_t a = 0; a < kOrder; ++a) g[f + a] += basis_[k][a] * wt;
    }
    Eigen::VectorXd r = Eigen::VectorXd::Zero(vars_);
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 gi = g[i] - offset_[i];
      for (const Term& s : forms_[i].terms) r[s.var] += s.coef.dot(gi);
    }
    const Eigen::VectorXd z = solver_.solve(r);
    for (std::size_t i = 0; i < n; ++i) {
      Vec3 p = forms_[i].constant;
      for (const Term& s : forms_[i].terms) p += z[s.var] * s.coef;
      q_[i] = p;
    }
  }

  // rho times `factor`; the scaled multipliers divided by it (Boyd et al. 3.4.1).
  void rescale(double factor) {
    rho_ *= factor;
    for (Vec3& l : l_) l /= factor;
    factored_ = false;
  }

  [[nodiscard]] bool q_finite() const {
    return std::all_of(q_.begin(), q_.end(), [](const Vec3& p) { return p.allFinite(); });
  }

  // The penalty of the current control points, sum over coordinates of q^T P q.
  [[nodiscard]] double energy() const {
    double out = 0;
    const auto n = q_.size();
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t d = 0; d < kOrder && i + d < n; ++d) {
        out += (d == 0 ? 1.0 : 2.0) * penalty_[i][d] * q_[i].dot(q_[i + d]);
      }
    }
    return out;
  }

  void keep_if_smoother() {
    const double e = energy();
    if (e <= best_energy_) {
      best_energy_ = e;
      best_ = q_;
    }
  }

  const std::vector<Vec3>& x_;
  std::vector<double> u_;
  CurveEnds ends_;
  std::vector<Vec3> v_;  // ADMM: each point's residual kept in the ball
  std::vector<Vec3> l_;  // ADMM: scaled multipliers
  double rho_ = 1;
  double rho0_ = 1;
  std::vector<double> breaks_;
  int spans_ = 0;
  int nc_ = 0;
  int vars_ = 0;
  Knots knots_;
  std::vector<int> first_;
  std::vector<std::array<double, kOrder>> basis_;
  std::vector<std::array<double, kOrder>> penalty_;
  std::vector<ControlForm> forms_;
  std::vector<Vec3> q_;
  std::vector<Vec3> offset_;
  double worst_ = std::numeric_limits<double>::infinity();
  std::vector<Vec3> best_;
  double best_energy_ = std::numeric_limits<double>::infinity();
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver_;
  bool factored_ = false;
};

// Binomial coefficient for n <= kDegree.
double binomial(int n, int k) {
  double out = 1;
  for (int i = 1; i <= k; ++i) out = out * (n - k + i) / i;
  return out;
}

// The Bezier control points of span e of the fitted curve (normalised), from its derivatives at
// the span's start: with D_k the k-th derivative times the span's width to the k,
// B_j = sum_{k <= j} C(j, k) / C(p, k) D_k / k!.
std::array<Vec3, kOrder> bezier_of_span(const Fit& fit, std::size_t e) {
  const std::vector<double>& breaks = fit.breaks();
  const double width = breaks[e + 1] - breaks[e];
  const auto d = fit.derivatives(breaks[e], kDegree);
  std::array<Vec3, kOrder> b;
  for (int j = 0; j <= kDegree; ++j) {
    Vec3 p = Vec3::Zero();
    double scale = 1;  // width^k / k!
    for (int k = 0; k <= j; ++k) {
      if (k > 0) scale *= width / k;
      p += binomial(j, k) / binomial(kDegree, k) * scale * d[static_cast<std::size_t>(k)];
    }
    b[static_cast<std::size_t>(j)] = p;
  }
  return b;
}

// The pieces of the fit's current curve in metres (`origin` plus `unit` times the normalised
// curve), joined exactly and leaving and meeting the joining lines exactly (control points on
// the tangent line: zero curvature).
std::vector<Segment> bezier_pieces(const Fit& fit, const std::vector<Vec3>& points, const CurveEnds& ends, double unit) {
  std::vector<Segment> out;
  const Vec3& origin = points.front();
  const auto spans = static_cast<std::size_t>(fit.spans());
  Vec3 previous_end = origin;
  for (std::size_t e = 0; e < spans; ++e) {
    const std::array<Vec3, kOrder> b = bezier_of_span(fit, e);
    std::vector<Vec3> control(kOrder);
    for (std::size_t j = 0; j < kOrder; ++j) control[j] = origin + unit * b[j];
    control[0] = previous_end;
    if (e == 0 && ends.start_tangent && !ends.closed) {
      const Vec3& t = *ends.start_tangent;
      for (std::size_t j = 1; j <= 2; ++j) control[j] = control[0] + (control[j] - control[0]).dot(t) * t;
    }
    if (e + 1 == spans) {
      control[kDegree] = ends.closed ? points.front() : points.back();
      if (ends.end_tangent && !ends.closed) {
        const Vec3& t = *ends.end_tangent;
        for (std::size_t j = kDegree - 2; j < kDegree; ++j) {
          control[j] = control[kDegree] + (control[j] - control[kDegree]).dot(t) * t;
        }
      }
    }
    previous_end = control[kDegree];
    out.emplace_back(Bezier(std::move(control)));
  }
  return out;
}

// `breaks` with every marked span cut in two; of a closed stream's first two or last two spans,
// all four (place_knots keeps them alike).
std::vector<double> refined(const std::vector<double>& breaks, std::vector<bool> marked, bool closed) {
  const std::size_t n = marked.size();
  if (closed && n >= 4 && (marked[0] || marked[1] || marked[n - 2] || marked[n - 1])) {
    marked[0] = marked[1] = marked[n - 2] = marked[n - 1] = true;
  }
  std::vector<double> out{breaks.front()};
  for (std::size_t e = 0; e < n; ++e) {
    if (marked[e]) out.push_back(0.5 * (breaks[e] + breaks[e + 1]));
    out.push_back(breaks[e + 1]);
  }
  return out;
}

}  // namespace

CurveFit g2_fit(const std::vector<Vec3>& points, const CurveEnds& ends, double tolerance, G2FitStats* stats) {
  const auto infeasible = [](std::string why) {
    CurveFit out;
    out.outcome = {Status::kInfeasible, std::move(why)};
    return out;
  };
  if (points.size() < 2) return infeasible("fewer than two points");
  // the polyline's arc length at each point
  std::vector<double> sigma(points.size(), 0.0);
  double longest = 0;
  for (std::size_t k = 1; k < points.size(); ++k) {
    const double len = (points[k] - points[k - 1]).norm();
    sigma[k] = sigma[k - 1] + len;
    longest = std::max(longest, len);
  }
  const double total = sigma.back();
  if (!(total > 0)) return infeasible("the points do not move");
  // the data, normalised: the points and points on the lines at most a tolerance apart, relative
  // to the first point in units of kUnit tolerances, each with its arc length (the first
  // parameter) and the segment it lies on
  const double unit = kUnit * tolerance;
  const Vec3& origin = points.front();
  std::vector<Vec3> x;
  std::vector<double> data_sigma;
  std::vector<std::size_t> data_segment;
  for (std::size_t k = 0; k + 1 < points.size(); ++k) {
    const double len = sigma[k + 1] - sigma[k];
    const int parts = std::max(1, static_cast<int>(std::ceil(len / tolerance)));
    for (int j = 0; j < parts; ++j) {
      const double share = static_cast<double>(j) / parts;
      x.push_back((points[k] + share * (points[k + 1] - points[k]) - origin) / unit);
      data_sigma.push_back(sigma[k] + share * len);
      data_segment.push_back(k);
    }
  }
  x.push_back(ends.closed ? Vec3::Zero() : Vec3((points.back() - origin) / unit));
  data_sigma.push_back(total);
  data_segment.push_back(points.size() - 2);
  std::vector<double> u0(data_sigma.size());
  for (std::size_t k = 0; k < u0.size(); ++k) u0[k] = data_sigma[k] / unit;

  std::vector<double> breaks = place_knots(points, sigma, tolerance, ends.closed);
  for (double& b : breaks) b /= unit;
  const double tol = tolerance / unit;
  std::string why = "no fit";
  int solves = 0;
  Fit problem(x, u0, breaks, ends);
  for (int refinement = 0; refinement <= kMaxRefinements; ++refinement) {
    std::vector<bool> failing;
    for (const double share : kTargets) {
      problem.forget_best();
      for (int pass = 0; pass < kPasses; ++pass) {
        if (pass > 0) {
          if (!problem.has_solution()) break;
          problem.use_best();
          problem.correct_parameters();
        }
        solves += problem.admm(share * tol, kAccept * tol, kIterations);
      }
      if (!problem.has_solution()) {
        why = "the residual stays at " + format_mm(problem.worst() * unit);
        failing = problem.spans_over(kAccept * tol);
        break;
      }
      problem.use_best();
      if (!(problem.min_speed() > kMinSpeed)) {
        why = "the curve would stop (a cusp)";
        break;
      }
      CurveFit out;
      out.pieces = bezier_pieces(problem, points, ends, unit);
      // a radius far below the tolerance is a cusp in all but name
      if (std::any_of(out.pieces.begin(), out.pieces.end(), [&](const Segment& piece) {
            return max_curvature(piece, 0.0, length(piece)) * tolerance > kMaxCurvature;
          })) {
        why = "the curve would turn about a near-cusp";
        break;
      }
      // each piece's stretch of the polyline, by the points' parameters (u to sigma, piecewise linear)
      const std::vector<double>& u = problem.parameters();
      const auto sigma_at = [&](double at) {
        const auto it = std::upper_bound(u.begin(), u.end(), at);
        if (it == u.begin()) return data_sigma.front();
        if (it == u.end()) return data_sigma.back();
        const auto k = static_cast<std::size_t>(it - u.begin());
        const double du = u[k] - u[k - 1];
        return du > 0 ? data_sigma[k - 1] + (data_sigma[k] - data_sigma[k - 1]) * (at - u[k - 1]) / du : data_sigma[k];
      };
      const std::vector<double>& b = problem.breaks();
      for (std::size_t e = 0; e + 1 < b.size(); ++e) {
        out.span_begin.push_back(sigma_at(b[e]));
        out.span_end.push_back(sigma_at(b[e + 1]));
        const auto it = std::upper_bound(u.begin(), u.end(), b[e]);
        const auto k = it == u.begin() ? 0 : static_cast<std::size_t>(it - u.begin()) - 1;
        out.piece_segment.push_back(std::min(data_segment[k], points.size() - 2));
      }
      out.span_end.back() = total;
      const FollowDistance measured = follow_distance(out.pieces, out.span_begin, out.span_end, points,
                                                      kResolutionShare * tolerance,
                                                      kReachPerTolerance * tolerance + kReachPerLine * longest);
      if (stats != nullptr) *stats = {problem.spans(), total / problem.spans(), solves, measured.hausdorff()};
      if (measured.hausdorff() <= tolerance) return out;
      why = "measured " + format_mm(measured.hausdorff());
    }
    // refine where the fit failed, or everywhere when it cannot say where
    if (std::none_of(failing.begin(), failing.end(), [](bool f) { return f; })) failing.assign(breaks.size() - 1, true);
    breaks = refined(breaks, failing, ends.closed);
    problem.set_breaks(breaks);
    why += " on " + std::to_string(breaks.size() - 1) + " spans";
  }
  return infeasible("no G2 fit within " + format_mm(tolerance) + " (" + why + ")");
}

}  // namespace blendbench
