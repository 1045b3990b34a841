#include "blendbench/timing/time_optimal.hpp"  // the method

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>

#include "intervals.hpp"

namespace blendbench::timing_detail {
namespace {

// Cells per piece of varying curvature at least, and per circular arc in cartesian mode (its MVC
// is exact on one cell, but the acceleration left to speed changes falls with the speed); at
// most this share of the path length per cell on either.
constexpr int kBoundCellsPerCurve = 32;
constexpr int kBoundCellsPerArc = 8;
constexpr double kBoundCellShare = 1.0 / 1024;
// Relative slack on the cell count of an interval: the planner cuts a piece of varying curvature
// into equal intervals (intervals.cpp), whose lengths, differences of arc lengths along the
// path, are a whole number of cells only up to rounding; without it ceil() made 3 cells of
// most of the 2 meant, 48 per clothoid instead of 32.
constexpr double kCellSlack = 1e-9;
// Relative margin for the rounding of the sums (the header).
constexpr double kRoundingMargin = 1e-12;
// Relative margin on a Bezier's scanned maximum sharpness (as for its caps).
constexpr double kBezierScanMargin = 4e-9;

// One cell of the grid: its length, its MVC (m^2/s^2), the smallest curvature on it and its
// piece, whose vector limits bound the speed changes on it. Kept to 32 bytes: on CAM output
// (10^5 tiny lines, each corner two clothoids of 32 cells or more) the grid has millions of
// cells, and writing them was most of the plan's time (first-touch page faults).
struct Cell {
  double length = 0;
  double mvc = 0;
  double kappa = 0;         // 1/m
  std::uint32_t piece = 0;  // a path of 2^32 pieces would need over a terabyte for its pieces
};

// The largest rates of y = v^2 speeding up (rise) and slowing down (fall) on a cell at y: 2 a_t
// with the acceleration the normal part kappa y leaves (cartesian mode) or the tangential
// limit itself (path mode).
struct Rates {
  const std::vector<PieceModel>& models;
  bool cartesian;
  [[nodiscard]] double rise(const Cell& c, double y) const {
    return 2 * available(models[c.piece].vector.acceleration, c, y);
  }
  [[nodiscard]] double fall(const Cell& c, double y) const {
    return 2 * available(models[c.piece].vector.deceleration, c, y);
  }
  [[nodiscard]] double available(double a, const Cell& c, double y) const {
    if (!cartesian) return a;
    const double n = c.kappa * y;  // the normal acceleration kappa v^2
    return n >= a ? 0.0 : a * std::sqrt(1 - (n / a) * (n / a));
  }
};

// One cell of an interval before its MVC: length (m) and the curvature at its ends (1/m;
// signed on a clothoid).
struct Span1 {
  double length, k0, k1;
};

// The cells of [s0, s1] (local arc lengths) of a piece, n of them: uniform in s, or on a Bezier
// uniform in its parameter (arc lengths from its table, no inversion per cell; u0 the parameter
// at s0, NaN when unknown, and on return the parameter at s1).
void cut(const Segment& segment, double s0, double s1, int n, double& u0, std::vector<Span1>& out) {
  out.clear();
  if (const auto* b = std::get_if<Bezier>(&segment)) {
    if (std::isnan(u0)) u0 = b->parameter_at(s0);
    const double u1 = b->parameter_at(s1);
    const auto kappa = [&](double u) {
      const Vec3 c1 = b->d1(u);
      return c1.cross(b->d2(u)).norm() / std::pow(c1.norm(), 3);
    };
    double x = s0;
    double k = kappa(u0);
    for (int i = 1; i <= n; ++i) {
      const double u = u0 + (u1 - u0) * i / n;
      const double x1 = i == n ? s1 : std::clamp(b->length_to(u), x, s1);
      const double k1 = kappa(u);
      out.push_back({x1 - x, k, k1});
      x = x1;
      k = k1;
    }
    u0 = u1;
    return;
  }
  const auto kappa = [&](double s) {
    if (const auto* c = std::get_if<Clothoid>(&segment)) return c->kappa0 + c->sharpness * s;
    return curvature_vector(segment, s).norm();
  };
  double k = kappa(s0);
  for (int i = 1; i <= n; ++i) {
    const double k1 = kappa(s0 + (s1 - s0) * i / n);
    out.push_back({(s1 - s0) / n, k, k1});
    k = k1;
  }
}

// The smallest curvature of a piece on a cell from its end values: exact on lines, arcs and
// clothoids (linear, signed); on a Bezier the smaller end value less c_max (the piece's maximum
// sharpness) times half the cell's length.
double min_curvature(const Segment& segment, const Span1& cell, double c_max) {
  if (std::holds_alternative<Clothoid>(segment)) {
    return cell.k0 * cell.k1 <= 0 ? 0.0 : std::min(std::abs(cell.k0), std::abs(cell.k1));
  }
  if (std::holds_alternative<Bezier>(segment)) return std::max(0.0, std::min(cell.k0, cell.k1) - c_max * 0.5 * cell.length);
  return std::min(cell.k0, cell.k1);
}

// Exact integral of dx / sqrt(min(m, a0 + rise x, b0 + fall (len - x))) over [0, len]: on each
// stretch where one of the three (linear) functions is the smallest, 2 dx / (sqrt(f_u) +
// sqrt(f_w)).
double cell_time(double len, double m, double a0, double rise, double b0, double fall) {
  const auto f = [&](int which, double x) {
    return which == 0 ? m : which == 1 ? a0 + rise * x : b0 + fall * (len - x);
  };
  std::array<double, 5> cuts{0.0, len, 0.0, len, 0.0};
  int n = 2;
  if (rise > 0) cuts[n++] = std::clamp((m - a0) / rise, 0.0, len);
  if (fall > 0) cuts[n++] = std::clamp(len - (m - b0) / fall, 0.0, len);
  if (rise + fall > 0) cuts[n++] = std::clamp((b0 + fall * len - a0) / (rise + fall), 0.0, len);
  for (int i = 1; i < n; ++i) {
    for (int k = i; k > 0 && cuts[k - 1] > cuts[k]; --k) std::swap(cuts[k - 1], cuts[k]);
  }
  double total = 0;
  for (int i = 0; i + 1 < n; ++i) {
    const double u = cuts[i];
    const double w = cuts[i + 1];
    if (!(w > u)) continue;
    const double mid = 0.5 * (u + w);
    int which = 0;
    for (int k = 1; k < 3; ++k) {
      if (f(k, mid) < f(which, mid)) which = k;
    }
    const double su = std::sqrt(std::max(0.0, f(which, u)));
    const double sw = std::sqrt(std::max(0.0, f(which, w)));
    if (!(su + sw > 0)) return kInf;
    total += 2 * (w - u) / (su + sw);
  }
  return total;
}

}  // namespace

double time_optimal_bound(const Path& path, const TimingOptions& options, const std::vector<PieceModel>& models,
                          const std::vector<Junction>& joints, const std::vector<Interval>& intervals) {
  if (intervals.empty()) return 0.0;
  const auto& pieces = path.pieces();
  const bool cartesian = options.limits == LimitsMode::kCartesian;
  // the bound at each junction: 0 at a stop, the acceleration part of the kink rule
  std::vector<double> at_start(pieces.size(), kInf);
  for (const Junction& jn : joints) {
    const Limits& lp = models[jn.prev].vector;
    const Limits& ln = models[jn.next].vector;
    const double a = std::min({lp.acceleration, lp.deceleration, ln.acceleration, ln.deceleration});
    double v = kInf;
    if (jn.cap == 0) {
      v = 0;
    } else if (jn.theta > 1e-9) {
      v = a * options.dt / (2 * std::sin(0.5 * jn.theta));
    }
    at_start[jn.next] = v * v;
  }
  // the grid: every interval, cut finer on curved pieces; counted first, so that the cells are
  // written once into memory of their exact size
  const double h_path = path.length() * kBoundCellShare;
  const auto cells_on = [&](const Interval& iv) {
    const Segment& segment = pieces[iv.piece].segment;
    // lines and (path mode) circular arcs: one cell, their constraints constant along them
    const bool arc = std::holds_alternative<Arc>(segment);
    const bool curved = !std::holds_alternative<Line>(segment) && (cartesian || !arc);
    if (!curved) return 1;
    const double h = std::min(length(segment) / (arc ? kBoundCellsPerArc : kBoundCellsPerCurve), h_path);
    return std::max(1, static_cast<int>(std::ceil(iv.length() / h * (1 - kCellSlack))));
  };
  std::size_t count = 0;
  for (const Interval& iv : intervals) count += static_cast<std::size_t>(cells_on(iv));
  std::vector<Cell> cells;
  cells.reserve(count);
  // y at the knots, first the junctions' bounds
  std::vector<double> y(count + 1, kInf);
  std::size_t last_piece = pieces.size();
  double c_max = 0;
  std::vector<Span1> parts;
  double u = 0;  // a Bezier's parameter at the end of the last interval
  for (const Interval& iv : intervals) {
    const PathPiece& piece = pieces[iv.piece];
    const Limits& lim = models[iv.piece].vector;
    const double len = length(piece.segment);
    if (iv.piece != last_piece && std::holds_alternative<Bezier>(piece.segment)) {
      c_max = max_sharpness(piece.segment, 0, len) * (1 + kBezierScanMargin);
    }
    if (iv.piece != last_piece) u = std::numeric_limits<double>::quiet_NaN();
    const int n = cells_on(iv);
    const double a_n = cartesian ? std::min(lim.acceleration, lim.deceleration) : lim.acceleration;
    const double local0 = iv.s0 - path.offset(iv.piece);
    cut(piece.segment, local0, local0 + iv.length(), n, u, parts);
    if (iv.piece != last_piece && !cells.empty()) y[cells.size()] = at_start[iv.piece];
    for (int i = 0; i < n; ++i) {
      const Span1& part = parts[static_cast<std::size_t>(i)];
      Cell c;
      c.length = part.length;
      c.kappa = min_curvature(piece.segment, part, c_max);
      // the angular velocity limit is a velocity limit too (R1, intervals.cpp)
      const double v_rot = models[iv.piece].rotation_speed;
      c.mvc = std::min({iv.terms.feed * iv.terms.feed, c.kappa > 0 ? a_n / c.kappa : kInf, v_rot * v_rot});
      c.piece = static_cast<std::uint32_t>(iv.piece);
      cells.push_back(c);
    }
    last_piece = iv.piece;
  }

  // y at the knots: under the knot bounds and both adjacent cells' MVC, then the passes
  const Rates rates{models, cartesian};
  const std::size_t n = cells.size();
  y[0] = 0;
  y[n] = 0;
  for (std::size_t k = 1; k < n; ++k) y[k] = std::min({y[k], cells[k - 1].mvc, cells[k].mvc});
  for (std::size_t k = 0; k < n; ++k) {
    y[k + 1] = std::min(y[k + 1], y[k] + cells[k].length * rates.rise(cells[k], y[k]));
  }
  for (std::size_t k = n; k-- > 0;) y[k] = std::min(y[k], y[k + 1] + cells[k].length * rates.fall(cells[k], y[k + 1]));

  // each cell's time under the envelope
  double total = 0;
  for (std::size_t k = 0; k < n; ++k) {
    const Cell& c = cells[k];
    total += cell_time(c.length, c.mvc, y[k], rates.rise(c, y[k]), y[k + 1], rates.fall(c, y[k + 1]));
  }
  return total * (1 - kRoundingMargin);
}

}  // namespace blendbench::timing_detail
