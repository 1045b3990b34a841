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

// Knot spacing: kSpacingPerTolerance tolerances (and at least two of the stream's mean line
// length), halved up to kMaxHalvings times when the fit cannot stay within the tolerance. A
// quintic span bends comfortably over a few tolerances' worth of deviation; 20 keeps the pieces
// few (the velocity planner cuts each into 16 intervals) and was the coarsest at which the
// cardioid and wave streams of bench_cam met 0.02 mm without halving.
constexpr double kSpacingPerTolerance = 20;
constexpr double kSpacingPerLine = 2;
constexpr int kMinSpans = 4;
constexpr int kMaxHalvings = 4;
// Weighted solves per parameter pass, and passes (the first on chord lengths, then each after
// the points' parameters move to their closest points).
constexpr int kIterations = 30;
constexpr int kPasses = 3;
// The share of the tolerance the reweighting aims the largest residual at, and the shares it
// tries next when the measured distance is still above the tolerance (the residual at the
// points' parameters is an upper bound of their distance; the lines between them and the chord
// sampling of the measurement take the rest).
constexpr std::array<double, 3> kTargets = {0.9, 0.75, 0.6};
// Reweighting: each weight is multiplied by (residual / target)^2 clamped to these factors, and
// kept between kWeightFloor and kWeightCeiling times the initial weight (the floor keeps the
// normal equations well conditioned where no point is active).
constexpr double kWeightStepDown = 0.25;
constexpr double kWeightStepUp = 100;
constexpr double kWeightFloor = 1e-6;
constexpr double kWeightCeiling = 1e12;
// The initial weight per unit parameter length of data (the spans are one unit long): small, so
// the first solve is smooth and the reweighting raises only the weights it must.
constexpr double kInitialWeight = 1e-3;
// A curve whose speed in its (normalised) parameter falls below this share of the nominal 1
// would turn about a cusp: refused.
constexpr double kMinSpeed = 0.05;
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

// One fit at one knot spacing, in normalised coordinates: positions relative to the first point
// divided by the spacing h, parameters in spans (knot i at i).
class Fit {
 public:
  Fit(const std::vector<Vec3>& x, const std::vector<double>& sigma, const CurveEnds& ends, int spans)
      : spans_(spans), nc_(spans + kDegree), x_(x), ends_(ends) {
    knots_.resize(nc_ + kOrder);
    for (int i = 0; i < nc_ + kOrder; ++i) knots_(i) = std::clamp(i - kDegree, 0, spans);
    const double total = sigma.back();
    u_.resize(x.size());
    for (std::size_t k = 0; k < x.size(); ++k) u_[k] = spans * sigma[k] / total;
    u_.back() = spans;
    build_forms();
    build_penalty();
    update_basis();
    // the weights: kInitialWeight per unit of parameter, shared by the data points
    w0_ = kInitialWeight * spans / static_cast<double>(x.size());
    w_.assign(x.size(), w0_);
  }

  // Reweighted solves towards residuals at most `target` (normalised), keeping the smoothest
  // solution whose residuals stay within `accept`; returns the solves made.
  int reweight(double target, double accept, int iterations) {
    int solves = 0;
    for (int it = 0; it < iterations; ++it) {
      solve();
      ++solves;
      double worst = 0;
      for (std::size_t k = 0; k < x_.size(); ++k) {
        const double r = (eval(k) - x_[k]).norm();
        worst = std::max(worst, r);
        const double ratio = r / target;
        const double step = std::clamp(ratio * ratio, kWeightStepDown, kWeightStepUp);
        w_[k] = std::clamp(w_[k] * step, w0_ * kWeightFloor, w0_ * kWeightCeiling);
      }
      worst_ = worst;
      if (feasible(accept)) keep_if_smoother();
    }
    return solves;
  }

  // Moves each point's parameter to its closest point on the current curve (Newton on
  // (C(u) - x) . C'(u) = 0 from the current parameter), keeping them ordered and the ends fixed.
  void correct_parameters() {
    for (std::size_t k = 1; k + 1 < x_.size(); ++k) {
      double u = u_[k];
      for (int step = 0; step < kNewtonSteps; ++step) {
        const auto d = derivatives(u, 2);
        const Vec3 r = d[0] - x_[k];
        const double f = r.dot(d[1]);
        const double df = d[1].squaredNorm() + r.dot(d[2]);
        if (!(df > 0)) break;
        u = std::clamp(u - f / df, 0.0, static_cast<double>(spans_));
      }
      u_[k] = u;
    }
    for (std::size_t k = 1; k < x_.size(); ++k) u_[k] = std::max(u_[k], u_[k - 1]);
    u_.back() = spans_;
    update_basis();
  }

  // Whether the kept solution exists, its largest residual, its control points.
  [[nodiscard]] bool has_solution() const { return !best_.empty(); }
  [[nodiscard]] const std::vector<Vec3>& control() const { return best_; }
  [[nodiscard]] double worst() const { return worst_; }
  [[nodiscard]] const std::vector<double>& parameters() const { return u_; }
  void use_best() {
    if (!best_.empty()) q_ = best_;
  }
  void forget_best() {
    best_.clear();
    best_energy_ = std::numeric_limits<double>::infinity();
  }

  // Position and derivatives up to `order` (<= kDegree) of the kept (or current) curve at u.
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
    for (int e = 0; e < spans_; ++e) {
      for (int j = 0; j <= kSpeedSamples; ++j) {
        const double u = std::min(e + static_cast<double>(j) / kSpeedSamples, static_cast<double>(spans_));
        out = std::min(out, derivatives(u, 1)[1].norm());
      }
    }
    return out;
  }

  [[nodiscard]] int spans() const { return spans_; }

 private:
  // The control points as affine forms of the unknowns (the clamped ends: the first and last
  // control points are the curve's ends).
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
    const double alpha = 1.0 / kDegree;  // C'(0) = (p / h) (Q1 - Q0): unit speed along the tangent
    for (std::size_t i = 0; i <= last; ++i) {
      ControlForm& f = forms_[i];
      if (i == 0) {
        f.constant = start;
      } else if (i == last) {
        f.constant = ends_.closed ? start : end;
      } else if (ends_.closed && i == last - 1) {
        // C'(0) = C'(U): Q_{m-1} = 2 Q_0 - Q_1
        f.constant = 2 * start - forms_[1].constant;
        for (const Term& t : forms_[1].terms) f.terms.push_back({t.var, -t.coef});
      } else if (ends_.closed && i == last - 2) {
        // C''(0) = C''(U) on clamped uniform knots: Q_{m-2} = Q_2 - 6 Q_1 + 6 Q_0
        f.constant = forms_[2].constant - 6 * forms_[1].constant + 6 * start;
        for (const Term& t : forms_[2].terms) f.terms.push_back(t);
        for (const Term& t : forms_[1].terms) f.terms.push_back({t.var, -6 * t.coef});
      } else if (!ends_.closed && ends_.start_tangent && i == 1) {
        f.constant = start + alpha * *ends_.start_tangent;
      } else if (!ends_.closed && ends_.start_tangent && i == 2) {
        // zero curvature at the start: Q_2 on the tangent line, anywhere along it
        f.constant = start;
        f.terms = {{vars++, *ends_.start_tangent}};
      } else if (!ends_.closed && ends_.end_tangent && i == last - 1) {
        f.constant = end - alpha * *ends_.end_tangent;
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
    for (int e = 0; e < spans_; ++e) {
      for (std::size_t g = 0; g < nodes.size(); ++g) {
        const double u = e + nodes[g];
        const auto ders = Basis::BasisFunctionDerivatives(u, 3, kDegree, knots_);
        const int first = static_cast<int>(Basis::Span(u, kDegree, knots_)) - kDegree;
        for (int a = 0; a < kOrder; ++a) {
          for (int b = a; b < kOrder; ++b) {
            penalty_[static_cast<std::size_t>(first + a)][static_cast<std::size_t>(b - a)] += weights[g] * ders(3, a) * ders(3, b);
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

  // One weighted solve: the banded normal matrix M = sum w N N^T + penalty and right-hand sides
  // b = sum w N x, reduced to the unknowns through the control points' forms.
  void solve() {
    const auto n = static_cast<std::size_t>(nc_);
    std::vector<std::array<double, kOrder>> band = penalty_;
    std::vector<Vec3> rhs(n, Vec3::Zero());
    for (std::size_t k = 0; k < x_.size(); ++k) {
      const auto f = static_cast<std::size_t>(first_[k]);
      const auto& nk = basis_[k];
      for (std::size_t a = 0; a < kOrder; ++a) {
        const double wa = w_[k] * nk[a];
        rhs[f + a] += wa * x_[k];
        for (std::size_t b = a; b < kOrder; ++b) band[f + a][b - a] += wa * nk[b];
      }
    }
    // g_i = b_i - sum_j M_ij c_j
    std::vector<Vec3> g = rhs;
    for (std::size_t i = 0; i < n; ++i) {
      for (std::size_t d = 0; d < kOrder && i + d < n; ++d) {
        const double m = band[i][d];
        g[i] -= m * forms_[i + d].constant;
        if (d > 0) g[i + d] -= m * forms_[i].constant;
      }
    }
    std::vector<Eigen::Triplet<double>> triplets;
    triplets.reserve(n * kOrder * 9 * 2);
    Eigen::VectorXd r = Eigen::VectorXd::Zero(vars_);
    for (std::size_t i = 0; i < n; ++i) {
      for (const Term& s : forms_[i].terms) r[s.var] += s.coef.dot(g[i]);
      for (std::size_t d = 0; d < kOrder && i + d < n; ++d) {
        const double m = band[i][d];
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
    if (!analysed_) {
      solver_.analyzePattern(system);
      analysed_ = true;
    }
    solver_.factorize(system);
    const Eigen::VectorXd z = solver_.solve(r);
    for (std::size_t i = 0; i < n; ++i) {
      Vec3 p = forms_[i].constant;
      for (const Term& s : forms_[i].terms) p += z[s.var] * s.coef;
      q_[i] = p;
    }
  }

  [[nodiscard]] bool feasible(double target) const { return worst_ <= target * (1 + 1e-9) && q_finite(); }
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

  int spans_;
  int nc_;
  int vars_ = 0;
  Knots knots_;
  const std::vector<Vec3>& x_;
  CurveEnds ends_;
  std::vector<double> u_;
  std::vector<int> first_;
  std::vector<std::array<double, kOrder>> basis_;
  std::vector<std::array<double, kOrder>> penalty_;
  std::vector<ControlForm> forms_;
  std::vector<Vec3> q_;
  std::vector<double> w_;
  double w0_ = 0;
  double worst_ = std::numeric_limits<double>::infinity();
  std::vector<Vec3> best_;
  double best_energy_ = std::numeric_limits<double>::infinity();
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver_;
  bool analysed_ = false;
};

// Binomial coefficient for n <= kDegree.
double binomial(int n, int k) {
  double out = 1;
  for (int i = 1; i <= k; ++i) out = out * (n - k + i) / i;
  return out;
}

// The Bezier control points of span e of the fitted curve (normalised), from its derivatives at
// the span's start: with D_k the k-th derivative (the span is one unit long),
// B_j = sum_{k <= j} C(j, k) / C(p, k) D_k / k!.
std::array<Vec3, kOrder> bezier_of_span(const Fit& fit, int e) {
  const auto d = fit.derivatives(static_cast<double>(e), kDegree);
  std::array<Vec3, kOrder> b;
  for (int j = 0; j <= kDegree; ++j) {
    Vec3 p = Vec3::Zero();
    double factorial = 1;
    for (int k = 0; k <= j; ++k) {
      if (k > 0) factorial *= k;
      p += binomial(j, k) / binomial(kDegree, k) / factorial * d[static_cast<std::size_t>(k)];
    }
    b[static_cast<std::size_t>(j)] = p;
  }
  return b;
}

}  // namespace

CurveFit g2_fit(const std::vector<Vec3>& points, const CurveEnds& ends, double tolerance, G2FitStats* stats) {
  CurveFit fit;
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
  // data: the points, and points on the lines at most a tolerance apart, each with its arc length
  // and the segment it lies on
  std::vector<Vec3> data;
  std::vector<double> data_sigma;
  std::vector<std::size_t> data_segment;
  for (std::size_t k = 0; k + 1 < points.size(); ++k) {
    const double len = sigma[k + 1] - sigma[k];
    const int parts = std::max(1, static_cast<int>(std::ceil(len / tolerance)));
    for (int j = 0; j < parts; ++j) {
      const double share = static_cast<double>(j) / parts;
      data.push_back(points[k] + share * (points[k + 1] - points[k]));
      data_sigma.push_back(sigma[k] + share * len);
      data_segment.push_back(k);
    }
  }
  data.push_back(points.back());
  data_sigma.push_back(total);
  data_segment.push_back(points.size() - 2);
  if (ends.closed) data.back() = data.front();

  const double mean_line = total / static_cast<double>(points.size() - 1);
  double spacing = std::max(kSpacingPerTolerance * tolerance, kSpacingPerLine * mean_line);
  int spans = std::max(kMinSpans, static_cast<int>(std::ceil(total / spacing)));
  const Vec3 origin = points.front();
  std::string why = "no fit";
  int solves = 0;
  for (int halving = 0; halving <= kMaxHalvings; ++halving, spans *= 2) {
    const double h = total / spans;
    // normalised data: relative to the first point, in spans
    std::vector<Vec3> x(data.size());
    for (std::size_t k = 0; k < data.size(); ++k) x[k] = (data[k] - origin) / h;
    Fit problem(x, data_sigma, ends, spans);
    const double tol = tolerance / h;
    for (const double share : kTargets) {
      problem.forget_best();
      for (int pass = 0; pass < kPasses; ++pass) {
        if (pass > 0) {
          problem.use_best();
          problem.correct_parameters();
        }
        solves += problem.reweight(share * tol, tol, kIterations);
      }
      if (!problem.has_solution()) {
        why = "the residual stays at " + format_mm(problem.worst() * h) + " with knots " + format_mm(h) + " apart";
        break;
      }
      problem.use_best();
      if (!(problem.min_speed() > kMinSpeed)) {
        why = "the curve would stop (a cusp) with knots " + format_mm(h) + " apart";
        break;
      }
      // the pieces, joined exactly, and measured
      CurveFit out;
      Vec3 previous_end = points.front();
      for (int e = 0; e < spans; ++e) {
        const std::array<Vec3, kOrder> b = bezier_of_span(problem, e);
        std::vector<Vec3> control(kOrder);
        for (std::size_t j = 0; j < kOrder; ++j) control[j] = origin + h * b[j];
        control[0] = previous_end;
        // exact ends: the first and last points, along the joining lines at zero curvature
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
        out.pieces.emplace_back(Bezier(std::move(control)));
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
      for (int e = 0; e < spans; ++e) {
        out.span_begin.push_back(sigma_at(e));
        out.span_end.push_back(sigma_at(e + 1));
        const auto it = std::upper_bound(u.begin(), u.end(), static_cast<double>(e));
        const auto k = it == u.begin() ? 0 : static_cast<std::size_t>(it - u.begin()) - 1;
        out.piece_segment.push_back(std::min(data_segment[k], points.size() - 2));
      }
      out.span_end.back() = total;
      const FollowDistance measured = follow_distance(out.pieces, out.span_begin, out.span_end, points,
                                                      kResolutionShare * tolerance,
                                                      kReachPerTolerance * tolerance + kReachPerLine * longest);
      if (stats != nullptr) *stats = {spans, h, solves, measured.hausdorff()};
      if (measured.hausdorff() <= tolerance) return out;
      why = "measured " + format_mm(measured.hausdorff()) + " with knots " + format_mm(h) + " apart";
    }
  }
  return infeasible("no G2 fit within " + format_mm(tolerance) + " (" + why + ")");
}

}  // namespace blendbench
