#include "optimal_problem.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <system_error>
#include <thread>

#include <Eigen/Dense>

#include "blendbench/core/interrupt.hpp"
#include "cell_shape.hpp"

namespace blendbench::timing_detail {
namespace {

using Mat2 = Eigen::Matrix2d;
using Vec2 = Eigen::Vector2d;

// The barrier method (optimal_problem.hpp). The duality gap of a centred point is nu / t (nu the
// barrier's parameter: 1 per linear or quadratic constraint, 2 per cone); the first centring aims
// at kStartGapShare of the time, each next one at 1/kBarrierGrowth of the last, down to
// kGapShare of the time.
constexpr double kStartGapShare = 0.1;
// kGapShare/kBarrierGrowth measured (BM_CamPlan/2000 and the default scenario's variants, 7
// December 2026, before the grid's spacing at low speed changed both problems): against 1e-7
// and 8, these take 120 Newton steps instead of 211 on the CAM contour and 0.21 s instead of
// 1.31 s on arc_0.5mm, the planned times within 0.013 %: a
// smaller growth leaves each centring's start closer to its central point, so fewer of its
// steps are cut short by the one node nearest a constraint (the step length is global), and a
// gap of 1e-4 of the time (the most the time can lie above the subproblem's optimum) is well
// below the grid's own resolution (0.1 %); the last centrings down to 1e-5 gained 0.007 % for
// a fifth of the steps on the 10^4-line contour.
constexpr double kGapShare = 1e-4;
constexpr double kBarrierGrowth = 2;
// A centring ends when the Newton decrement lambda^2 / 2 is below this (the barrier function's
// own units: the time times t, plus logs). A point that close to the central one has a duality
// gap within some lambda of nu / t (nu in the thousands to millions here), and the next
// centring starts from it anyway. Measured on BM_CamPlan/10000 (7 December 2026): 1e-6 / 1e-3 /
// 0.1 / 1 took 124 / 118 / 106 / 102 Newton steps, the plans equal to 1e-8 of the time; on the
// default scenario's variants the planned times moved by less than 1e-6 of them.
constexpr double kNewtonTol = 0.1;
constexpr int kMaxNewtonPerCentring = 80;
constexpr int kMaxInfeasibleSteps = 40;
// Steps of iterative refinement of each KKT solve (the blocks' scales differ by the barrier's
// 1 / slack^2 near active constraints).
constexpr int kRefinements = 0;
// Backtracking line search: sufficient decrease and step shrink.
constexpr double kArmijo = 0.01;
constexpr double kBacktrack = 0.5;
constexpr double kStepGrowth = 2;
constexpr int kMaxBacktracks = 60;
// The linearisations stop when one gains less than this share of the time.
constexpr double kLinearisationTol = 1e-6;
// The start, once inside every constraint, has its b and a scaled by this factor (the same motion
// at sqrt(0.7) = 0.84 of its speed: every constraint then holds with a margin of at least
// 1 - kStartShrink of its limit). The starting profile (seed 004's) lies on its limits along much
// of the path, and from a point that close to the barrier's boundary the first centring's global
// step was cut to a few percent for most of its steps. Measured on the 10^4-line CAM contour
// (BM_CamPlan, 46,693 nodes; 7 December 2026): the first centring took 86 Newton steps from the
// start as scaled, 21 / 19 / 18 with b and a scaled by 0.9 / 0.7 / 0.5, 199 / 124 / 124 steps in
// all; the plans agree within 0.003 %.
constexpr double kStartShrink = 0.7;
// Scales gamma^2 of the starting profile (b and a alike) tried in turn until every constraint
// holds strictly.
constexpr std::array<double, 22> kStartScales = {1.0,  1 - 1e-9, 1 - 1e-7, 1 - 1e-5, 1 - 1e-4, 0.999, 0.995, 0.98,
                                                 0.95, 0.9,  0.8,  0.65, 0.5,  0.35, 0.2,  0.1,
                                                 0.03, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6};
// The cells' shapes follow the linearisation point for this many centrings, then stay: renewing
// them changes the equalities and the jerk rows, so the iterate must be moved back inside, which
// at a large t costs more Newton steps than the shapes still gain.
constexpr int kShapeStages = 3;
// Nodes of the starting profile slower than this share of its largest v^2 start with a = 0 (a
// junction's speed bound near zero, where the profile turns from braking to speeding up).
constexpr double kNearStopShare = 1e-6;
// Newton steps of Solver::restore onto the equalities.
constexpr int kRestoreRounds = 3;
// Rounds of mending the start where its acceleration carries b below zero inside a cell.
constexpr int kStartRepairs = 8;
// The equalities hold once their largest residual is below this share of the largest b.
constexpr double kEqualityTol = 1e-13;

const double kInfinity = std::numeric_limits<double>::infinity();

// One side of a node in the stretch's units (optimal_problem.cpp: scaled so that the
// starting profile's largest speed and acceleration are 1).
struct ScaledSide {
  Vec3 t, k, dk;
  double kk = 0;  // |k|^2
  double acc = 0, dec = 0, jerk = 0;
  Vec3 step = Vec3::Zero();
  double step_norm = 0;
  Vec3 axis_a = Vec3::Constant(kInfinity), axis_j = Vec3::Constant(kInfinity);
  bool rotates = false;
  Vec3 rho = Vec3::Zero(), rho1 = Vec3::Zero(), rho2 = Vec3::Zero();
  double alpha = kInfinity, eta = kInfinity;
};

struct ScaledNode {
  double b_max = kInfinity;
  bool pinned = false;  // a = 0 here (GridNode::pinned)
  std::uint32_t left = 0, right = 0;
  // the middle of the cell after the node: its side, cap, and (per linearisation) where it lies
  // in the cell's w and the rows of b and a there over (b0, a0, a1, b1)
  std::uint32_t middle = 0;
  double middle_b_max = kInfinity;
  Eigen::Vector4d middle_b = Eigen::Vector4d::Zero();
  Eigen::Vector4d middle_a = Eigen::Vector4d::Zero();
};

// Gradient and the block tridiagonal Hessian of the barrier function over the free nodes:
// diag[i] over (b_i, a_i), off[c] between node c (rows) and node c + 1 (columns).
struct Derivatives {
  std::vector<Vec2> grad;
  std::vector<Mat2> diag;
  std::vector<Mat2> off;
  void reset(std::size_t nodes) {
    grad.assign(nodes, Vec2::Zero());
    diag.assign(nodes, Mat2::Zero());
    off.assign(nodes, Mat2::Zero());
  }
};

// The tangent of g(b) = J b^(-1/2) - q b^(1/2) at b^: r0 + r1 b.
struct Tangent {
  double r0, r1;
};
Tangent tangent_at(double jerk, double q, double b_hat) {
  const double root = std::sqrt(b_hat);
  const double g0 = jerk / root - q * root;
  const double g1 = -0.5 * jerk / (b_hat * root) - 0.5 * q / root;
  return {g0 - g1 * b_hat, g1};
}

class LogSum;

// The stretch's problem.
class Stretch {
 public:
  // `parallel_cells`: from this many cells on, evaluate() runs in two halves on two threads
  // (the barrier function and its derivatives are three quarters of a Newton step's work; a
  // thread's start, some 50 us, is a few percent of one evaluation at 4096 cells).
  Stretch(const Grid& grid, std::size_t first, std::size_t last, double v_ref, double a_ref, std::size_t parallel_cells);

  [[nodiscard]] std::size_t cells() const { return h_.size(); }
  [[nodiscard]] double barrier_parameter() const { return nu_; }
  // Linearises the jerk limits at b and shapes every cell from it (cell_shape.hpp).
  void linearise(const std::vector<double>& b, const std::vector<double>& a, bool shapes = true) {
    for (std::size_t i = 1; i < cells(); ++i) b_lin_[i] = b[i];
    if (!shapes) return;
    for (std::size_t i = 1; i < cells(); ++i) {
      shape_b_[i] = b[i];
      a_lin_[i] = a[i];
    }
    for (std::size_t c = 1; c + 1 < cells(); ++c) {
      shape_[c] = CellShape(h_[c], std::sqrt(b[c]), std::sqrt(b[c + 1]), a[c]);
      const double w = shape_[c].at_position(0.5 * h_[c]);
      nodes_[c].middle_b = shape_[c].row_at(w);
      nodes_[c].middle_a = Eigen::Vector4d(0, 1 - w, w, 0);
    }
  }
  [[nodiscard]] const CellShape& shape(std::size_t c) const { return shape_[c]; }
  [[nodiscard]] bool pinned(std::size_t i) const { return nodes_[i].pinned; }
  [[nodiscard]] const std::vector<double>& linearised_at() const { return b_lin_; }
  // The point the cells' shapes come from (v^2 and a at the nodes).
  [[nodiscard]] const std::vector<double>& shaped_b() const { return shape_b_; }
  [[nodiscard]] const std::vector<double>& shaped_a() const { return a_lin_; }
  // The time of the profile (its objective), in the stretch's units; infinity outside its domain.
  [[nodiscard]] double time(const std::vector<double>& b, const std::vector<double>& a) const;
  // t * time + barrier; infinity outside the domain (b <= 0 at an inner node or inside a cell, a
  // constraint not strictly held).
  [[nodiscard]] double value(const std::vector<double>& b, const std::vector<double>& a, double t) const;
  // Value, gradient and Hessian of the same (the point inside the domain).
  double derivatives(const std::vector<double>& b, const std::vector<double>& a, double t, Derivatives& d) const;
  // The residuals of the equalities (E), one per cell.
  void residuals(const std::vector<double>& b, const std::vector<double>& a, std::vector<double>& r) const;
  // The coefficients of equality c on (b, a) of its left node c and right node c + 1.
  [[nodiscard]] Vec2 row_left(std::size_t c) const {
    if (c == 0) return Vec2::Zero();
    if (c + 1 == cells()) return Vec2(1.0, 1.5 * h_[c]);
    return Vec2(-1.0, -2 * h_[c] * (1 - shape_[c].mean()));
  }
  [[nodiscard]] Vec2 row_right(std::size_t c) const {
    if (c + 1 == cells()) return Vec2::Zero();
    if (c == 0) return Vec2(1.0, -1.5 * h_[0]);
    return Vec2(1.0, -2 * h_[c] * shape_[c].mean());
  }

 private:
  template <bool kDerivatives>
  double evaluate(const std::vector<double>& b, const std::vector<double>& a, double t, Derivatives* d) const;
  // The objective's cells [c0, c1) and the constraints' nodes [i0, i1) of evaluate: adds the
  // time times t to `total` and every barrier argument to `logs`; false outside the domain.
  template <bool kDerivatives>
  bool evaluate_part(const std::vector<double>& b, const std::vector<double>& a, double t, Derivatives* d,
                     std::size_t c0, std::size_t c1, std::size_t i0, std::size_t i1, double& total,
                     LogSum& logs) const;

  std::vector<double> h_;
  std::vector<CellShape> shape_;
  std::vector<ScaledNode> nodes_;
  std::vector<ScaledSide> sides_;
  std::vector<double> b_lin_;
  std::vector<double> shape_b_;
  std::vector<double> a_lin_;
  bool cartesian_ = true;
  bool axes_ = false;
  double nu_ = 0;
  std::size_t parallel_cells_ = 0;
};

Stretch::Stretch(const Grid& grid, std::size_t first, std::size_t last, double v_ref, double a_ref,
                 std::size_t parallel_cells)
    : parallel_cells_(std::max<std::size_t>(parallel_cells, 8)) {
  // units: speed v_ref, acceleration a_ref, so length L0 = v^2 / a, time T0 = v / a, jerk a / T0
  const double l0 = v_ref * v_ref / a_ref;
  const double t0 = v_ref / a_ref;
  const double j0 = a_ref / t0;
  const double dt = grid.dt / t0;
  cartesian_ = grid.mode == LimitsMode::kCartesian;
  axes_ = cartesian_ && grid.axes.has_value();
  const std::size_t n = last - first;
  h_.resize(n);
  shape_.resize(n);
  nodes_.resize(n + 1);
  b_lin_.assign(n + 1, 0.0);
  shape_b_.assign(n + 1, 0.0);
  a_lin_.assign(n + 1, 0.0);
  for (std::size_t c = 0; c < n; ++c) h_[c] = (grid.nodes[first + c + 1].s - grid.nodes[first + c].s) / l0;
  for (std::size_t i = 0; i <= n; ++i) {
    const GridNode& g = grid.nodes[first + i];
    ScaledNode& node = nodes_[i];
    node.b_max = g.b_max / (v_ref * v_ref);
    node.pinned = g.pinned && !g.rest;
    node.middle_b_max = g.middle_b_max / (v_ref * v_ref);
    for (int which = 0; which < 3; ++which) {
      if (which == 2 && (i == 0 || i + 1 >= n)) continue;  // no middle in a rest cell
      const std::uint32_t index = which == 0 ? g.left : which == 1 ? g.right : g.middle;
      if (which == 1 && g.right == g.left) {
        node.right = node.left;
        continue;
      }
      const NodeSide& in = grid.sides[index];
      ScaledSide out;
      out.t = in.t;
      out.k = in.k * l0;
      out.dk = in.dk * l0 * l0;
      out.kk = out.k.squaredNorm();
      out.acc = in.tighten_acceleration * in.acceleration / a_ref;
      out.dec = in.tighten_acceleration * in.deceleration / a_ref;
      out.jerk = in.tighten_jerk * in.jerk / j0;
      // (k_prev - k_next) / dt in the stretch's units
      out.step = in.step * grid.dt * l0 / dt;
      out.step_norm = out.step.norm();
      if (axes_) {
        out.axis_a = in.tighten_acceleration * grid.axes->acceleration / a_ref;
        out.axis_j = in.tighten_jerk * grid.axes->jerk / j0;
      }
      if (in.rotation >= 0) {
        const SideRotation& r = grid.rotations[static_cast<std::size_t>(in.rotation)];
        out.rotates = true;
        out.rho = r.rate * l0;
        out.rho1 = r.d1 * l0 * l0;
        out.rho2 = r.d2 * l0 * l0 * l0;
        out.alpha = in.tighten_acceleration * r.acceleration * t0 * t0;
        out.eta = in.tighten_jerk * r.jerk * t0 * t0 * t0;
      }
      (which == 0 ? node.left : which == 1 ? node.right : node.middle) = static_cast<std::uint32_t>(sides_.size());
      sides_.push_back(out);
    }
  }
  // the barrier's parameter: count the constraints as evaluate() makes them
  for (std::size_t c = 1; c + 1 < n; ++c) {
    if (std::isfinite(nodes_[c].middle_b_max)) nu_ += CellShape::kPoints;
    if (cartesian_) nu_ += sides_[nodes_[c].middle].acc == sides_[nodes_[c].middle].dec ? 1 : 2;
  }
  for (std::size_t i = 1; i < n; ++i) {
    const ScaledNode& node = nodes_[i];
    if (std::isfinite(node.b_max)) nu_ += 1;
    for (int which = 0; which < 2; ++which) {
      const ScaledSide& s = sides_[which == 0 ? node.left : node.right];
      const bool distinct = which == 0 || node.right != node.left;
      if (distinct) {
        nu_ += cartesian_ ? (s.acc == s.dec ? 1 : 2) : 2;
        if (axes_) nu_ += 6;
        if (s.rotates && std::isfinite(s.alpha)) nu_ += 2;
      }
      nu_ += cartesian_ ? 2 : 2;
      if (axes_) nu_ += 6;
      if (s.rotates && std::isfinite(s.eta)) nu_ += 2;
    }
  }
}

void Stretch::residuals(const std::vector<double>& b, const std::vector<double>& a, std::vector<double>& r) const {
  const std::size_t n = cells();
  r.resize(n);
  for (std::size_t c = 0; c < n; ++c) {
    if (c == 0) {
      r[c] = b[1] - 1.5 * h_[0] * a[1];
    } else if (c + 1 == n) {
      r[c] = b[c] + 1.5 * h_[c] * a[c];
    } else {
      const double omega = shape_[c].mean();
      r[c] = b[c + 1] - b[c] - 2 * h_[c] * ((1 - omega) * a[c] + omega * a[c + 1]);
    }
  }
}

double Stretch::time(const std::vector<double>& b, const std::vector<double>& a) const {
  const std::size_t n = cells();
  double total = 0;
  for (std::size_t c = 0; c < n; ++c) {
    const double h = h_[c];
    if (c == 0 || c + 1 == n) {
      const double bb = c == 0 ? b[1] : b[c];
      if (!(bb > 0)) return kInfinity;
      total += 3 * h / std::sqrt(bb);
      continue;
    }
    const CellShape& sh = shape_[c];
    if (!(b[c] > 0) || !(b[c + 1] > 0)) return kInfinity;
    for (int q = 0; q < CellShape::kPoints; ++q) {
      const double bq = sh.b_at(q, b[c], a[c], a[c + 1], b[c + 1]);
      if (!(bq > 0)) return kInfinity;
      total += sh.weight(q) / std::sqrt(bq);
    }
  }
  return total;
}

double Stretch::value(const std::vector<double>& b, const std::vector<double>& a, double t) const {
  return evaluate<false>(b, a, t, nullptr);
}

double Stretch::derivatives(const std::vector<double>& b, const std::vector<double>& a, double t, Derivatives& d) const {
  d.reset(cells() + 1);
  return evaluate<true>(b, a, t, &d);
}

// A sum of logarithms taken as one logarithm of their product, kept as mantissa and exponent
// (frexp), so that the many barrier terms cost one log each few dozen (the logs were a fifth of
// the planner's time) and no product under- or overflows.
class LogSum {
 public:
  void add(double x) {
    int e = 0;
    mantissa_ *= std::frexp(x, &e);
    exponent_ += e;
    if (++count_ == kChunk) flush();
  }
  [[nodiscard]] double value() {
    flush();
    return sum_ + static_cast<double>(exponent_) * std::numbers::ln2;
  }
  // Adds another sum's terms (without a logarithm of its own).
  void absorb(const LogSum& other) {
    add(other.mantissa_);
    exponent_ += other.exponent_;
    sum_ += other.sum_;
  }

 private:
  static constexpr int kChunk = 32;  // mantissas in [0.5, 1): their product stays above 2^-32
  void flush() {
    if (count_ == 0) return;
    int e = 0;
    mantissa_ = std::frexp(mantissa_, &e);
    exponent_ += e;
    sum_ += std::log(mantissa_);
    mantissa_ = 1;
    count_ = 0;
  }
  double mantissa_ = 1;
  long exponent_ = 0;
  double sum_ = 0;
  int count_ = 0;
};

// Barrier terms on a few local variables z: value -log(...), and their gradient and Hessian in z.
template <int N>
struct Term {
  LogSum logs;  // the value is -logs.value()
  Eigen::Matrix<double, N, 1> grad = Eigen::Matrix<double, N, 1>::Zero();
  Eigen::Matrix<double, N, N> hess = Eigen::Matrix<double, N, N>::Zero();
};

// -log(c0 + g.z) (a linear constraint c0 + g.z > 0); false outside the domain.
template <int N, bool kDerivatives>
bool linear_term(double c0, const Eigen::Matrix<double, N, 1>& g, const Eigen::Matrix<double, N, 1>& z, Term<N>& out) {
  const double c = c0 + g.dot(z);
  if (!(c > 0)) return false;
  out.logs.add(c);
  if constexpr (kDerivatives) {
    out.grad -= g / c;
    out.hess += g * g.transpose() / (c * c);
  }
  return true;
}

// -log(t^2 - |u|^2) with u = M z + u0 and t = g.z + t0 (the second-order cone t > |u|); false
// outside the domain.
template <int N, bool kDerivatives>
bool cone_term(const Eigen::Matrix<double, 3, N>& m, const Vec3& u0, const Eigen::Matrix<double, N, 1>& g, double t0,
               const Eigen::Matrix<double, N, 1>& z, Term<N>& out) {
  const Vec3 u = m * z + u0;
  const double t = g.dot(z) + t0;
  if (!(t > 0)) return false;
  const double dd = t * t - u.squaredNorm();
  if (!(dd > 0)) return false;
  out.logs.add(dd);
  if constexpr (kDerivatives) {
    const Eigen::Matrix<double, N, 1> q = 2 * t * g - 2 * m.transpose() * u;
    out.grad -= q / dd;
    out.hess += (2.0 / dd) * (m.transpose() * m - g * g.transpose()) + q * q.transpose() / (dd * dd);
  }
  return true;
}

// Adds a term over z = (a_p, a_i, b_i) of node i and its neighbour p (p = i - 1 or i + 1; not
// added to p where p is a rest) into d.
void scatter_side(const Term<3>& term, std::size_t i, std::size_t p, std::size_t n, Derivatives& d) {
  d.grad[i](0) += term.grad(2);
  d.grad[i](1) += term.grad(1);
  d.diag[i](0, 0) += term.hess(2, 2);
  d.diag[i](0, 1) += term.hess(2, 1);
  d.diag[i](1, 0) += term.hess(1, 2);
  d.diag[i](1, 1) += term.hess(1, 1);
  if (p == 0 || p == n) return;
  d.grad[p](1) += term.grad(0);
  d.diag[p](1, 1) += term.hess(0, 0);
  if (p + 1 == i) {
    // off[p]: rows node p, columns node i
    d.off[p](1, 0) += term.hess(0, 2);
    d.off[p](1, 1) += term.hess(0, 1);
  } else {
    d.off[i](0, 1) += term.hess(2, 0);
    d.off[i](1, 1) += term.hess(1, 0);
  }
}

void scatter_node(const Term<2>& term, std::size_t i, Derivatives& d) {
  // z = (a_i, b_i)
  d.grad[i](0) += term.grad(1);
  d.grad[i](1) += term.grad(0);
  d.diag[i](0, 0) += term.hess(1, 1);
  d.diag[i](0, 1) += term.hess(1, 0);
  d.diag[i](1, 0) += term.hess(0, 1);
  d.diag[i](1, 1) += term.hess(0, 0);
}

template <bool kDerivatives>
double Stretch::evaluate(const std::vector<double>& b, const std::vector<double>& a, double t, Derivatives* d) const {
  const std::size_t n = cells();
  if (n < parallel_cells_) {
    double total = 0;
    LogSum logs;  // every barrier term's argument
    if (!evaluate_part<kDerivatives>(b, a, t, d, 0, n, 1, n, total, logs)) return kInfinity;
    return total - logs.value();
  }
  // two halves on two threads, then the cells and nodes between them: cells [0, m - 1) and
  // nodes [1, m - 1) write the derivatives of nodes <= m - 1 only, cells [m + 1, n) and nodes
  // [m + 2, n) those of nodes >= m + 1, and the rest (cells m - 1, m; nodes m - 1 .. m + 1)
  // follows them. The split depends on n alone, so the sums (and the plan) are the same to the
  // bit whether the second half runs on its own thread or not.
  const std::size_t m = n / 2;
  std::array<double, 3> total{0, 0, 0};
  std::array<LogSum, 3> logs;
  std::array<bool, 3> inside{false, false, false};
  const auto upper_half = [&] {
    inside[1] = evaluate_part<kDerivatives>(b, a, t, d, m + 1, n, m + 2, n, total[1], logs[1]);
  };
  {
    std::optional<std::jthread> upper;
    try {
      upper.emplace(upper_half);
    } catch (const std::system_error&) {
      upper_half();  // no thread to be had: the same sums on this one
    }
    inside[0] = evaluate_part<kDerivatives>(b, a, t, d, 0, m - 1, 1, m - 1, total[0], logs[0]);
  }
  inside[2] = inside[0] && inside[1] && evaluate_part<kDerivatives>(b, a, t, d, m - 1, m + 1, m - 1, m + 2, total[2], logs[2]);
  if (!inside[2]) return kInfinity;
  logs[0].absorb(logs[1]);
  logs[0].absorb(logs[2]);
  return total[0] + total[1] + total[2] - logs[0].value();
}

template <bool kDerivatives>
bool Stretch::evaluate_part(const std::vector<double>& b, const std::vector<double>& a, double t, Derivatives* d,
                            std::size_t c0, std::size_t c1, std::size_t i0, std::size_t i1, double& total,
                            LogSum& logs) const {
  const std::size_t n = cells();
  // the objective, cell by cell
  for (std::size_t c = c0; c < c1; ++c) {
    const double h = h_[c];
    if (c == 0 || c + 1 == n) {
      const std::size_t i = c == 0 ? 1 : c;
      const double bb = b[i];
      if (!(bb > 0)) return false;
      const double root = std::sqrt(bb);
      total += t * 3 * h / root;
      if constexpr (kDerivatives) {
        d->grad[i](0) += -t * 1.5 * h / (bb * root);
        d->diag[i](0, 0) += t * 2.25 * h / (bb * bb * root);
      }
      continue;
    }
    const CellShape& sh = shape_[c];
    if (!(b[c] > 0) || !(b[c + 1] > 0)) return false;
    for (int q = 0; q < CellShape::kPoints; ++q) {
      // the time at a quadrature point: weight / sqrt(b_q), b_q = m.(b_c, a_c, a_{c+1}, b_{c+1})
      const Eigen::Vector4d& m = sh.b_row(q);
      const double bq = m(0) * b[c] + m(1) * a[c] + m(2) * a[c + 1] + m(3) * b[c + 1];
      if (!(bq > 0)) return false;
      const double root = std::sqrt(bq);
      const double w = t * sh.weight(q);
      total += w / root;
      if constexpr (kDerivatives) {
        const double d1 = -0.5 * w / (bq * root);
        const double d2 = 0.75 * w / (bq * bq * root);
        // node c (b, a) = m(0), m(1); node c+1 (b, a) = m(3), m(2)
        const Vec2 left(m(0), m(1));
        const Vec2 right(m(3), m(2));
        d->grad[c] += d1 * left;
        d->grad[c + 1] += d1 * right;
        d->diag[c] += d2 * left * left.transpose();
        d->diag[c + 1] += d2 * right * right.transpose();
        d->off[c] += d2 * left * right.transpose();
      }
    }
    // the cell's middle: b under its cap, and (cartesian) the acceleration vector
    const ScaledNode& node = nodes_[c];
    const Eigen::Vector4d z(b[c], a[c], a[c + 1], b[c + 1]);
    Term<4> term;
    // the cap at the time's quadrature points (where a bulge of b above it would gain time)
    if (std::isfinite(node.middle_b_max)) {
      for (int q = 0; q < CellShape::kPoints; ++q) {
        if (!linear_term<4, kDerivatives>(node.middle_b_max, -sh.b_row(q), z, term)) return false;
      }
    }
    if (cartesian_) {
      const ScaledSide& sm = sides_[node.middle];
      const double am = node.middle_a.dot(z);
      const double bm = node.middle_b.dot(z);
      const auto quad = [&](double lim, double p, double dp) {
        const double dd = lim * lim - p * p - sm.kk * bm * bm;
        if (!(dd > 0)) return false;
        term.logs.add(dd);
        if constexpr (kDerivatives) {
          const Eigen::Vector4d grad = -2 * p * dp * node.middle_a - 2 * sm.kk * bm * node.middle_b;
          term.grad -= grad / dd;
          term.hess += (2 * dp * node.middle_a * node.middle_a.transpose() + 2 * sm.kk * node.middle_b * node.middle_b.transpose()) / dd +
                       grad * grad.transpose() / (dd * dd);
        }
        return true;
      };
      if (sm.acc == sm.dec) {
        if (!quad(sm.acc, am, 1.0)) return false;
      } else {
        if (!quad(sm.acc, std::max(am, 0.0), am > 0 ? 1.0 : 0.0)) return false;
        if (!quad(sm.dec, std::min(am, 0.0), am < 0 ? 1.0 : 0.0)) return false;
      }
    }
    logs.absorb(term.logs);
    if constexpr (kDerivatives) {
      // z = (b_c, a_c, a_{c+1}, b_{c+1}): node c (b, a) = z(0), z(1); node c+1 (b, a) = z(3), z(2)
      const std::array<int, 2> lft{0, 1};
      const std::array<int, 2> rgt{3, 2};
      for (std::size_t r = 0; r < 2; ++r) {
        d->grad[c](static_cast<int>(r)) += term.grad(lft[r]);
        d->grad[c + 1](static_cast<int>(r)) += term.grad(rgt[r]);
        for (std::size_t q = 0; q < 2; ++q) {
          d->diag[c](static_cast<int>(r), static_cast<int>(q)) += term.hess(lft[r], lft[q]);
          d->diag[c + 1](static_cast<int>(r), static_cast<int>(q)) += term.hess(rgt[r], rgt[q]);
          d->off[c](static_cast<int>(r), static_cast<int>(q)) += term.hess(lft[r], rgt[q]);
        }
      }
    }
  }

  // the constraints, node by node
  for (std::size_t i = i0; i < i1; ++i) {
    const ScaledNode& node = nodes_[i];
    const double bi = b[i];
    const double ai = a[i];
    // b <= b_max
    if (std::isfinite(node.b_max)) {
      const double c = node.b_max - bi;
      if (!(c > 0)) return false;
      logs.add(c);
      if constexpr (kDerivatives) {
        d->grad[i](0) += 1 / c;
        d->diag[i](0, 0) += 1 / (c * c);
      }
    }
    const Vec2 zn(ai, bi);
    for (int which = 0; which < 2; ++which) {
      const bool left = which == 0;
      const ScaledSide& s = sides_[left ? node.left : node.right];
      // the node's own terms (acceleration, axes, rotation), once per distinct side
      if (left || node.right != node.left) {
        Term<2> term;
        if (cartesian_) {
          const double base = s.kk * bi * bi;
          const auto quad = [&](double lim, double p, double dp) {
            const double dd = lim * lim - p * p - base;
            if (!(dd > 0)) return false;
            term.logs.add(dd);
            if constexpr (kDerivatives) {
              const Vec2 grad(-2 * p * dp, -2 * s.kk * bi);
              term.grad -= grad / dd;
              Mat2 h2 = Mat2::Zero();
              h2(0, 0) = 2 * dp;
              h2(1, 1) = 2 * s.kk;
              term.hess += h2 / dd + grad * grad.transpose() / (dd * dd);
            }
            return true;
          };
          if (s.acc == s.dec) {
            if (!quad(s.acc, ai, 1.0)) return false;
          } else {
            if (!quad(s.acc, std::max(ai, 0.0), ai > 0 ? 1.0 : 0.0)) return false;
            if (!quad(s.dec, std::min(ai, 0.0), ai < 0 ? 1.0 : 0.0)) return false;
          }
          if (axes_) {
            for (int x = 0; x < 3; ++x) {
              const Vec2 g(s.t(x), s.k(x));
              if (!linear_term<2, kDerivatives>(s.axis_a(x), -g, zn, term)) return false;
              if (!linear_term<2, kDerivatives>(s.axis_a(x), g, zn, term)) return false;
            }
          }
        } else {
          if (!linear_term<2, kDerivatives>(s.acc, Vec2(-1, 0), zn, term)) return false;
          if (!linear_term<2, kDerivatives>(s.dec, Vec2(1, 0), zn, term)) return false;
        }
        if (s.rotates && std::isfinite(s.alpha)) {
          Eigen::Matrix<double, 3, 2> m;
          m.col(0) = s.rho;
          m.col(1) = s.rho1;
          if (!cone_term<2, kDerivatives>(m, Vec3::Zero(), Vec2::Zero(), s.alpha, zn, term)) return false;
        }
        logs.absorb(term.logs);
        if constexpr (kDerivatives) scatter_node(term, i, *d);
      }
      // the jerk on this side's cell: a' = cp a_p + ci a_i, z = (a_p, a_i, b_i)
      const std::size_t p = left ? i - 1 : i + 1;
      double cp = 0;
      double ci = 0;
      if (left) {
        if (i == 1) {
          ci = 1 / (3 * h_[0]);
        } else {
          // da/ds at the cell's end: (a_i - a_{i-1}) times dw/ds there
          const double k = shape_[i - 1].slope_end();
          cp = -k;
          ci = k;
        }
      } else {
        if (i + 1 == n) {
          ci = -1 / (3 * h_[i]);
        } else {
          const double k = shape_[i].slope_start();
          cp = k;
          ci = -k;
        }
      }
      const Vec3 z(a[p], ai, bi);
      Term<3> term;
      const double b_hat = b_lin_[i];
      // with a limited curvature step at this node: J b^-1/2 - q b^1/2
      const auto jerk_tangent = [&](double jerk, double q) { return tangent_at(jerk, q, b_hat); };
      if (cartesian_) {
        Eigen::Matrix3d m;
        m.col(0) = cp * s.t;
        m.col(1) = ci * s.t + 3 * s.k;
        m.col(2) = s.dk;
        const Tangent tg = jerk_tangent(s.jerk, s.step_norm);
        if (!cone_term<3, kDerivatives>(m, Vec3::Zero(), Vec3(0, 0, tg.r1), tg.r0, z, term)) return false;
        if (axes_) {
          for (int x = 0; x < 3; ++x) {
            const Tangent ta = jerk_tangent(s.axis_j(x), std::abs(s.step(x)));
            const Vec3 row = m.row(x).transpose();
            if (!linear_term<3, kDerivatives>(ta.r0, Vec3(0, 0, ta.r1) - row, z, term)) return false;
            if (!linear_term<3, kDerivatives>(ta.r0, Vec3(0, 0, ta.r1) + row, z, term)) return false;
          }
        }
      } else {
        const Tangent tg = tangent_at(s.jerk, 0.0, b_hat);
        const Vec3 row(cp, ci, 0.0);
        if (!linear_term<3, kDerivatives>(tg.r0, Vec3(0, 0, tg.r1) - row, z, term)) return false;
        if (!linear_term<3, kDerivatives>(tg.r0, Vec3(0, 0, tg.r1) + row, z, term)) return false;
      }
      if (s.rotates && std::isfinite(s.eta)) {
        Eigen::Matrix3d m;
        m.col(0) = cp * s.rho;
        m.col(1) = ci * s.rho + 3 * s.rho1;
        m.col(2) = s.rho2;
        const Tangent tr = tangent_at(s.eta, 0.0, b_hat);
        if (!cone_term<3, kDerivatives>(m, Vec3::Zero(), Vec3(0, 0, tr.r1), tr.r0, z, term)) return false;
      }
      logs.absorb(term.logs);
      if constexpr (kDerivatives) scatter_side(term, i, p, n, *d);
    }
  }
  return true;
}

// The block tridiagonal KKT system of one Newton step (optimal_problem.hpp): block i (1 <= i <=
// n - 1) holds (nu_{i-1}, b_i, a_i), block n holds nu_{n-1} (padded with two unit rows).
class Kkt {
 public:
  // Factors the system of the Hessian d and the equalities of `p`, in the variables b_i / sb[i]
  // and a_i (b near a junction's near-zero speed bound is many decades below b elsewhere);
  // false when a pivot block is singular.
  bool factor(const Stretch& p, const Derivatives& d, const std::vector<double>& sb);
  // Solves for right-hand side r (block i: equality residual part, b part, a part) in place,
  // with kRefinements steps of iterative refinement against the unfactored system.
  void solve(std::vector<Vec3>& r) const;

 private:
  void substitute(std::vector<Vec3>& r) const;
  std::vector<Mat3> lower_;  // lower_[i]: block (i, i - 1)
  std::vector<Mat3> diag_;   // diag_[i]: block (i, i) before factoring
  std::vector<Mat3> inverse_;  // inverse of the Schur complement of block i
};

// The inverse of a symmetric 3x3 block after a symmetric diagonal scaling; false when singular.
bool scaled_inverse(const Mat3& s, Mat3& out) {
  Vec3 scale;
  for (int j = 0; j < 3; ++j) {
    const double v = std::abs(s(j, j));
    scale(j) = v > 0 ? 1 / std::sqrt(v) : 1.0;
  }
  const Mat3 scaled = scale.asDiagonal() * s * scale.asDiagonal();
  bool ok = false;
  Mat3 inv;
  scaled.computeInverseWithCheck(inv, ok, 0.0);
  if (!ok || !inv.allFinite()) return false;
  out = scale.asDiagonal() * inv * scale.asDiagonal();
  return true;
}

bool Kkt::factor(const Stretch& p, const Derivatives& d, const std::vector<double>& sb) {
  const std::size_t n = p.cells();
  // the Hessian block of nodes (i, j) in the scaled variables
  const auto scaled = [&](const Mat2& m, std::size_t i, std::size_t j) {
    Mat2 out = m;
    out.row(0) *= sb[i];
    out.col(0) *= sb[j];
    return out;
  };
  lower_.assign(n + 1, Mat3::Zero());
  diag_.assign(n + 1, Mat3::Zero());
  inverse_.assign(n + 1, Mat3::Zero());
  for (std::size_t i = 1; i <= n; ++i) {
    Mat3 block = Mat3::Zero();
    if (i < n) {
      const Vec2 row = p.row_right(i - 1);  // equality i-1 on node i
      block(0, 1) = block(1, 0) = row(0) * sb[i];
      block(0, 2) = block(2, 0) = p.pinned(i) ? 0.0 : row(1);
      block.block<2, 2>(1, 1) = scaled(d.diag[i], i, i);
      // a relative floor on the Hessian's diagonal against round-off
      block(1, 1) += 1e-14 * std::abs(block(1, 1));
      block(2, 2) += 1e-14 * std::abs(block(2, 2));
    } else {
      block(1, 1) = block(2, 2) = 1.0;
    }
    diag_[i] = block;
    if (i > 1) {
      Mat3& l = lower_[i];
      const Vec2 row = p.row_left(i - 1);  // equality i-1 on node i-1
      l(0, 1) = row(0) * sb[i - 1];
      l(0, 2) = p.pinned(i - 1) ? 0.0 : row(1);
      if (i < n) l.block<2, 2>(1, 1) = scaled(d.off[i - 1], i - 1, i).transpose();
      block -= l * inverse_[i - 1] * l.transpose();
    }
    if (!scaled_inverse(block, inverse_[i])) return false;
  }
  return true;
}

void Kkt::solve(std::vector<Vec3>& r) const {
  const std::size_t n = inverse_.size() - 1;
  const std::vector<Vec3> rhs = r;
  substitute(r);
  std::vector<Vec3> res(n + 1, Vec3::Zero());
  for (int k = 0; k < kRefinements; ++k) {
    for (std::size_t i = 1; i <= n; ++i) {
      Vec3 y = diag_[i] * r[i];
      if (i > 1) y += lower_[i] * r[i - 1];
      if (i < n) y += lower_[i + 1].transpose() * r[i + 1];
      res[i] = rhs[i] - y;
    }
    substitute(res);
    for (std::size_t i = 1; i <= n; ++i) r[i] += res[i];
  }
}

void Kkt::substitute(std::vector<Vec3>& r) const {
  const std::size_t n = inverse_.size() - 1;
  for (std::size_t i = 2; i <= n; ++i) r[i] -= lower_[i] * (inverse_[i - 1] * r[i - 1]);
  r[n] = inverse_[n] * r[n];
  for (std::size_t i = n - 1; i >= 1; --i) r[i] = inverse_[i] * (r[i] - lower_[i + 1].transpose() * r[i + 1]);
}

// The barrier method on one stretch (scaled units).
class Solver {
 public:
  Solver(Stretch& problem, std::vector<double>& b, std::vector<double>& a) : p_(problem), b_(b), a_(a) {
    const std::size_t n = p_.cells();
    nu_.assign(n, 0.0);
    rhs_.resize(n + 1);
    tb_.resize(n + 1);
    ta_.resize(n + 1);
  }
  // Centres the barrier function at t; returns false when the Newton iteration stalls.
  bool centre(double t);
  // Moves the iterate onto the equalities by the least change in the barrier function's metric
  // at t (a Newton system with no gradient: stiff where a constraint is close), with the step cut
  // to stay inside; true when they hold.
  bool restore(double t);
  [[nodiscard]] int newton_steps() const { return steps_; }
  [[nodiscard]] bool feasible() const { return feasible_; }

 private:
  bool newton_step(double t, bool& done);
  Stretch& p_;
  std::vector<double>& b_;
  std::vector<double>& a_;
  std::vector<double> nu_;
  Derivatives d_;
  // the derivatives at the iterate, made by the line search of the last step at `next_t_` (the
  // trial point is evaluated with them: most trials are taken, and the next step needs them
  // there; the value alone and then the derivatives took a tenth more CPU on BM_CamPlan/10000,
  // 7.2 against 6.6 s); valid until the problem or t changes (centre, restore)
  Derivatives next_;
  bool have_next_ = false;
  double next_t_ = 0;
  double next_phi_ = 0;
  Kkt kkt_;
  std::vector<Vec3> rhs_;
  std::vector<double> tb_, ta_, res_, scale_;
  bool feasible_ = false;
  int steps_ = 0;
  double last_alpha_ = 1;  // the last accepted step length
};

bool Solver::newton_step(double t, bool& done) {
  const std::size_t n = p_.cells();
  double phi = 0;
  if (have_next_ && next_t_ == t) {
    std::swap(d_, next_);
    phi = next_phi_;
  } else {
    phi = p_.derivatives(b_, a_, t, d_);
  }
  have_next_ = false;
  if (!std::isfinite(phi)) return false;
  p_.residuals(b_, a_, res_);
  double b_top = 0;
  for (std::size_t i = 1; i < n; ++i) b_top = std::max(b_top, b_[i]);
  double res_top = 0;
  for (const double r : res_) res_top = std::max(res_top, std::abs(r));
  feasible_ = res_top <= kEqualityTol * b_top;
  // right-hand side: -(grad + E^T nu), -(E x)
  for (std::size_t i = 1; i <= n; ++i) {
    Vec3& r = rhs_[i];
    r.setZero();
    r(0) = feasible_ ? 0.0 : -res_[i - 1];
    if (i < n) {
      Vec2 g = d_.grad[i];
      g += p_.row_right(i - 1) * nu_[i - 1];
      g += p_.row_left(i) * nu_[i];
      r(1) = -g(0);
      r(2) = -g(1);
    }
  }
  // a pinned node's acceleration stays: its row and column become the identity, its step 0
  for (std::size_t i = 1; i < n; ++i) {
    if (!p_.pinned(i)) continue;
    d_.grad[i](1) = 0;
    d_.diag[i](0, 1) = d_.diag[i](1, 0) = 0;
    d_.diag[i](1, 1) = 1;
    d_.off[i - 1].col(1).setZero();
    d_.off[i].row(1).setZero();
    rhs_[i](2) = 0;
  }
  // solved in b_i / b_i (every scaled b is 1 here) and a_i
  scale_.assign(n + 1, 1.0);
  for (std::size_t i = 1; i < n; ++i) {
    scale_[i] = b_[i];
    rhs_[i](1) *= b_[i];
  }
  if (!kkt_.factor(p_, d_, scale_)) return false;
  kkt_.solve(rhs_);
  for (std::size_t i = 1; i < n; ++i) rhs_[i](1) *= b_[i];
  // the decrement and the directional derivative of the barrier function
  double slope = 0;
  for (std::size_t i = 1; i < n; ++i) slope += d_.grad[i](0) * rhs_[i](1) + d_.grad[i](1) * rhs_[i](2);
  ++steps_;
  if (feasible_ && -slope / 2 <= kNewtonTol) {
    done = true;
    return true;
  }
  // line search: inside the domain, and with sufficient decrease once the equalities hold
  // (from twice the last step's length, not 1: far from the central point the steps stay cut
  // to a few percent for many steps running, and each halving costs an evaluation)
  double alpha = std::min(1.0, kStepGrowth * last_alpha_);
  for (int k = 0; k < kMaxBacktracks; ++k, alpha *= kBacktrack) {
    for (std::size_t i = 1; i < n; ++i) {
      tb_[i] = b_[i] + alpha * rhs_[i](1);
      ta_[i] = a_[i] + alpha * rhs_[i](2);
    }
    tb_[0] = ta_[0] = tb_[n] = ta_[n] = 0;
    const double trial = p_.derivatives(tb_, ta_, t, next_);
    if (!std::isfinite(trial)) continue;
    if (feasible_ && trial > phi + kArmijo * alpha * slope) continue;
    b_.swap(tb_);
    a_.swap(ta_);
    last_alpha_ = alpha;
    have_next_ = true;
    next_t_ = t;
    next_phi_ = trial;
    for (std::size_t c = 0; c < n; ++c) nu_[c] += alpha * rhs_[c + 1](0);
    // a step too small to change the value ends the centring
    if (feasible_ && std::abs(trial - phi) <= 1e-15 * std::abs(phi)) done = true;
    return true;
  }
  return false;
}

bool Solver::restore(double t) {
  const std::size_t n = p_.cells();
  have_next_ = false;
  for (int round = 0; round < kRestoreRounds; ++round) {
    p_.residuals(b_, a_, res_);
    double b_top = 0;
    for (std::size_t i = 1; i < n; ++i) b_top = std::max(b_top, b_[i]);
    double res_top = 0;
    for (const double r : res_) res_top = std::max(res_top, std::abs(r));
    if (res_top <= kEqualityTol * b_top) return feasible_ = true;
    if (!std::isfinite(p_.derivatives(b_, a_, t, d_))) return false;
    for (std::size_t i = 1; i <= n; ++i) rhs_[i] = Vec3(-res_[i - 1], 0.0, 0.0);
    for (std::size_t i = 1; i < n; ++i) {
      if (!p_.pinned(i)) continue;
      d_.diag[i](0, 1) = d_.diag[i](1, 0) = 0;
      d_.diag[i](1, 1) = 1;
      d_.off[i - 1].col(1).setZero();
      d_.off[i].row(1).setZero();
    }
    scale_.assign(n + 1, 1.0);
    for (std::size_t i = 1; i < n; ++i) scale_[i] = b_[i];
    if (!kkt_.factor(p_, d_, scale_)) return false;
    kkt_.solve(rhs_);
    for (std::size_t i = 1; i < n; ++i) rhs_[i](1) *= b_[i];
    double alpha = 1;
    bool moved = false;
    for (int k = 0; k < kMaxBacktracks && !moved; ++k, alpha *= kBacktrack) {
      for (std::size_t i = 1; i < n; ++i) {
        tb_[i] = b_[i] + alpha * rhs_[i](1);
        ta_[i] = a_[i] + alpha * rhs_[i](2);
      }
      tb_[0] = ta_[0] = tb_[n] = ta_[n] = 0;
      if (!std::isfinite(p_.value(tb_, ta_, t))) continue;
      b_.swap(tb_);
      a_.swap(ta_);
      moved = true;
    }
    if (!moved) return false;
  }
  return false;
}

bool Solver::centre(double t) {
  have_next_ = false;  // (the linearisation may have changed since)
  for (int k = 0; k < kMaxNewtonPerCentring + kMaxInfeasibleSteps; ++k) {
    bool done = false;
    if (!newton_step(t, done)) return false;
    if (done) return true;
  }
  return feasible_;
}

}  // namespace

StretchResult solve_stretch(const Grid& grid, std::size_t first, std::size_t last, const std::vector<double>& b0,
                            const std::vector<double>& a0, int max_linearisations, std::size_t parallel_cells) {
  const std::size_t n = last - first;
  StretchResult out;
  // units: the starting profile's largest speed and acceleration
  double v_ref = 0;
  double a_ref = 0;
  for (std::size_t i = 0; i <= n; ++i) {
    v_ref = std::max(v_ref, std::sqrt(std::max(b0[i], 0.0)));
    a_ref = std::max(a_ref, std::abs(a0[i]));
  }
  if (!(v_ref > 0) || !(a_ref > 0)) {
    out.b = b0;
    out.a = a0;
    return out;
  }
  Stretch problem(grid, first, last, v_ref, a_ref, parallel_cells);
  std::vector<double> b(n + 1, 0.0);
  std::vector<double> a(n + 1, 0.0);
  std::vector<double> lin(n + 1, 0.0);
  std::vector<double> lin_a(n + 1, 0.0);
  for (std::size_t i = 1; i < n; ++i) {
    lin[i] = b0[i] / (v_ref * v_ref);
    lin_a[i] = a0[i] / a_ref;
  }
  problem.linearise(lin, lin_a);
  // the largest scale of a point that holds every constraint strictly (b and a alike: the same
  // motion run slower; the cells' shapes do not change with it)
  std::vector<double> tb(n + 1, 0.0);
  std::vector<double> ta(n + 1, 0.0);
  // (relinearise: at each scale tried, the linearisation moves there too, as for the start,
  // whose own speed may sit on a bound the linearisation takes as given elsewhere)
  // (pb, pa) scaled by `scale` where that holds every constraint strictly; true then
  const auto try_scale = [&](std::vector<double>& pb, std::vector<double>& pa, double scale, bool relinearise) {
    for (std::size_t i = 1; i < n; ++i) {
      tb[i] = scale * pb[i];
      ta[i] = scale * pa[i];
    }
    if (relinearise) problem.linearise(tb, ta);
    if (!std::isfinite(problem.value(tb, ta, 1.0))) return false;
    pb.swap(tb);
    pa.swap(ta);
    return true;
  };
  const auto scale_inside = [&](std::vector<double>& pb, std::vector<double>& pa, bool relinearise = false) {
    return std::any_of(kStartScales.begin(), kStartScales.end(),
                       [&](double scale) { return try_scale(pb, pa, scale, relinearise); });
  };
  for (std::size_t i = 1; i < n; ++i) {
    b[i] = b0[i] / (v_ref * v_ref);
    a[i] = a0[i] / a_ref;
  }
  for (std::size_t i = 2; i + 1 < n; ++i) {
    if (problem.pinned(i) || (b[i] < kNearStopShare && b[i] <= b[i - 1] && b[i] <= b[i + 1])) a[i] = 0;
  }
  // where the start's acceleration carries b below zero inside a cell (no scale mends a sign:
  // next to a junction's near-zero speed bound), it starts at a = 0 at that cell's ends
  std::vector<char> held(n + 1, 0);
  for (int round = 0; round < kStartRepairs; ++round) {
    problem.linearise(b, a);
    bool repaired = false;
    for (std::size_t c = 1; c + 1 < n; ++c) {
      const CellShape& sh = problem.shape(c);
      for (int q = 0; q < CellShape::kPoints; ++q) {
        if (sh.b_at(q, b[c], a[c], a[c + 1], b[c + 1]) > 0) continue;
        a[c] = a[c + 1] = 0;
        held[c] = held[c + 1] = 1;
        repaired = true;
        break;
      }
    }
    if (!repaired) break;
  }
  const bool inside = scale_inside(b, a, true);
  // (every constraint is homogeneous in (b, a) or has a bound that loosens as b falls, so the
  // slower start is inside as well; kept only if it is)
  if (inside) try_scale(b, a, kStartShrink, false);
  const auto to_si = [&] {
    out.b.assign(n + 1, 0.0);
    out.a.assign(n + 1, 0.0);
    out.b_lin.assign(n + 1, 0.0);
    out.a_lin.assign(n + 1, 0.0);
    for (std::size_t i = 1; i < n; ++i) {
      out.b[i] = b[i] * v_ref * v_ref;
      out.a[i] = a[i] * a_ref;
      out.b_lin[i] = problem.shaped_b()[i] * v_ref * v_ref;
      out.a_lin[i] = problem.shaped_a()[i] * a_ref;
    }
  };
  if (!inside) {
    out.failure = "start";
    to_si();
    return out;
  }

  Solver solver(problem, b, a);
  const double nu = problem.barrier_parameter();
  double t = nu / (kStartGapShare * problem.time(b, a));
  // path following with the linearisation renewed at every centring: t grows until the gap is
  // small, then stays while the renewed linearisations still gain time
  bool ok = true;
  double previous = kInfinity;
  std::vector<double> kept_b;
  std::vector<double> kept_a;
  std::vector<double> last_b;
  std::vector<double> last_a;
  bool shapes_frozen = false;
  for (int stage = 0; ok; ++stage) {
    throw_if_stop_requested();
    if (stage > 0) {
      // renew the linearisation (and the cells' shapes) at the iterate; where the new shapes
      // leave it outside a constraint, run it slower until it is inside, and where nothing
      // helps keep the old linearisation and stop
      const bool shapes = stage < kShapeStages && solver.feasible() && !shapes_frozen;
      if (shapes) {
        kept_b = problem.shaped_b();
        kept_a = problem.shaped_a();
        last_b = b;
        last_a = a;
      }
      problem.linearise(b, a, shapes);
      // the new shapes change the equalities and the jerk rows: back inside, then onto them;
      // where that fails, back to the last shapes and the iterate that held them, which stay
      if (shapes && !(scale_inside(b, a) && solver.restore(t))) {
        b.swap(last_b);
        a.swap(last_a);
        problem.linearise(kept_b, kept_a);
        problem.linearise(b, a, false);
        solver.restore(t);
        shapes_frozen = true;
      }
    }
    ++out.linearisations;
    ok = solver.centre(t);
    const double time = problem.time(b, a);
    if (!ok) {
      // no more progress: the iterate is strictly feasible, and a plan where the equalities hold
      out.stalled = true;
      out.converged = solver.feasible();
      break;
    }
    if (nu / t > kGapShare * time) {
      t *= kBarrierGrowth;
      continue;
    }
    if (previous - time <= kLinearisationTol * time || out.linearisations >= max_linearisations) {
      out.converged = solver.feasible();
      break;
    }
    previous = time;
  }
  // a stalled step leaves a strictly feasible iterate; the equalities must hold, though
  if (!solver.feasible()) {
    out.converged = false;
    out.failure = "equalities";
  }
  out.newton_steps = solver.newton_steps();
  to_si();
  return out;
}

}  // namespace blendbench::timing_detail
