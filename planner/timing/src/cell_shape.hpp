#pragma once
// Internal to the optimal velocity planner: how the tangential acceleration runs between two
// nodes of the grid (a cell of length h). Not installed.
//
// A profile whose acceleration is linear in s cannot follow a jerk phase where the speed changes
// by a large factor within a cell: from rest, a = J t grows as s^(1/3), and a chord in s has up to
// 1.7 times the end slope, so the jerk limit at the cell's end holds the whole cell back. So the
// acceleration is made linear in w, the time of a reference motion through the cell normalised
// to [0, 1]: at the fixed point of the linearisations (the reference is the profile itself) the
// jerk is then constant on every cell, as in a time-optimal profile's phases. The reference is
// the motion of constant jerk j over a time T that starts at the linearisation profile's speed
// v0 and acceleration a0 at the cell's start and ends at its speed v1 after the cell's length h:
//   h = T (2 v0 + v1) / 3 + a0 T^2 / 6,   j = 2 (v1 - v0 - a0 T) / T^2
// (where that motion would stop inside the cell, the one of constant acceleration, j = 0 and
// T = 2h / (v0 + v1), is used). Along it, with v(w) = v0 + a0 T w + j T^2 w^2 / 2,
//   x(w) = T w (v0 + a0 T w / 2 + j T^2 w^2 / 6)          (arc length from the cell's start)
//   W(w) = int_0^x(w) w ds = T (v0 w^2 / 2 + a0 T w^3 / 3 + j T^2 w^4 / 8)
// and the profile on the cell, from the node values b0, a0', a1' (v^2 and a at its ends):
//   a(w) = a0' + (a1' - a0') w,   b(w) = b0 + 2 a0' x(w) + 2 (a1' - a0') W(w)    (b' = 2 a, exactly)
//   da/ds = (a1' - a0') / x'(w),   x'(w) = T v(w),   jerk = da/ds sqrt(b)
//   time = int_0^1 x'(w) / sqrt(b(w)) dw.
// b at the far node is b0 + 2 h ((1 - omega) a0' + omega a1') with omega = W(1) / h: the equality
// of the cell. Everything is linear in (b0, a0', a1') except the time, which is convex in them
// (1 / sqrt of a linear function, summed at Gauss-Legendre points in w with positive weights).
// The optimiser's time takes b(w) as (1 - w) times b carried forward from b0 plus w times b carried
// back from b1, the far node's value: the same where the equality holds, and positive near either
// node while it does not yet (after the shapes change, optimal_problem.cpp), where b0 or b1 is
// close to zero (a junction's speed bound).
// From rest (v0 = a0 = 0) the reference is s = c t^3, the exact start at the jerk limit.

#include <array>
#include <cmath>

#include "blendbench/core/geometry.hpp"

namespace blendbench::timing_detail {

class CellShape {
 public:
  // Gauss-Legendre points of the time integral on [0, 1].
  static constexpr int kPoints = 3;

  CellShape() = default;
  // A cell of length h (> 0) whose reference starts at speed v0 (>= 0) and acceleration a0 and
  // ends at speed v1 (> 0).
  CellShape(double h, double v0, double v1, double a0) : h_(h), v0_(v0) {
    const double p = (2 * v0 + v1) / 3;
    const double disc = p * p + (2.0 / 3.0) * a0 * h;
    bool ok = disc >= 0;
    if (ok) {
      t_ = 2 * h / (p + std::sqrt(disc));
      a0_ = a0;
      j_ = 2 * (v1 - v0 - a0 * t_) / (t_ * t_);
      // the speed stays positive inside (its minimum, where it has one inside)
      if (j_ > 0 && a0 < 0 && -a0 < j_ * t_) ok = v0 - a0 * a0 / (2 * j_) > 0;
      ok = ok && t_ > 0 && std::isfinite(j_);
    }
    if (!ok) {
      t_ = 2 * h / (v0 + v1);
      a0_ = (v1 - v0) / t_;
      j_ = 0;
    }
    for (int q = 0; q < kPoints; ++q) {
      const double w = kNodes[static_cast<std::size_t>(q)];
      // forward: b0 + 2 a0' (x - W) + 2 a1' W; back: b1 - 2 a0' ((h - x) - (W1 - W)) - 2 a1' (W1 - W)
      rows_[static_cast<std::size_t>(q)] = row_at(w);
      weights_[static_cast<std::size_t>(q)] = kWeights[static_cast<std::size_t>(q)] * stretch(w);
    }
    mean_ = integral(1.0) / h;
  }

  [[nodiscard]] double length() const { return h_; }
  // omega = W(1) / h.
  [[nodiscard]] double mean() const { return mean_; }
  // The reference's speed at w, and dx/dw = T v(w).
  [[nodiscard]] double speed(double w) const { return v0_ + a0_ * t_ * w + 0.5 * j_ * t_ * t_ * w * w; }
  [[nodiscard]] double stretch(double w) const { return t_ * speed(w); }
  // dw/ds at the cell's start and end (1/m); infinite at a start from rest.
  [[nodiscard]] double slope_start() const { return 1 / stretch(0.0); }
  [[nodiscard]] double slope_end() const { return 1 / stretch(1.0); }
  [[nodiscard]] double position(double w) const {
    return t_ * w * (v0_ + a0_ * t_ * w / 2 + j_ * t_ * t_ * w * w / 6);
  }
  [[nodiscard]] double integral(double w) const {
    const double w2 = w * w;
    return t_ * w2 * (v0_ / 2 + a0_ * t_ * w / 3 + j_ * t_ * t_ * w2 / 8);
  }
  // The w at arc length x in [0, h] from the cell's start (Newton on the increasing x(w)).
  [[nodiscard]] double at_position(double x) const {
    double lo = 0;
    double hi = 1;
    double w = x / h_;
    for (int k = 0; k < 100; ++k) {
      const double f = position(w) - x;
      (f < 0 ? lo : hi) = w;
      const double d = stretch(w);
      double next = d > 0 ? w - f / d : 0.5 * (lo + hi);
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
      if (std::abs(next - w) <= 1e-16) return next;
      w = next;
    }
    return w;
  }
  // b at w from the node values.
  [[nodiscard]] double b(double w, double b0, double a0, double a1) const {
    return b0 + 2 * a0 * position(w) + 2 * (a1 - a0) * integral(w);
  }
  // b at w as row . (b0, a0, a1, b1), blended as for the time (above).
  [[nodiscard]] Eigen::Vector4d row_at(double w) const {
    const double x = position(w);
    const double big_w = integral(w);
    const double w1 = integral(1.0);
    return {1 - w, 2 * (1 - w) * (x - big_w) - 2 * w * ((h_ - x) - (w1 - big_w)), 2 * (1 - w) * big_w - 2 * w * (w1 - big_w),
            w};
  }
  // b at quadrature point q as row . (b0, a0, a1, b1) (the blend above), and the time's weight
  // there: time = sum_q weight(q) / sqrt(b_q).
  [[nodiscard]] const Eigen::Vector4d& b_row(int q) const { return rows_[static_cast<std::size_t>(q)]; }
  [[nodiscard]] double weight(int q) const { return weights_[static_cast<std::size_t>(q)]; }
  [[nodiscard]] double b_at(int q, double b0, double a0, double a1, double b1) const {
    const Eigen::Vector4d& r = b_row(q);
    return r(0) * b0 + r(1) * a0 + r(2) * a1 + r(3) * b1;
  }

 private:
  static constexpr std::array<double, 3> kNodes = {0.11270166537925831, 0.5, 0.88729833462074169};
  static constexpr std::array<double, 3> kWeights = {5.0 / 18, 8.0 / 18, 5.0 / 18};
  double h_ = 1;
  double v0_ = 1;  // the reference's start speed, acceleration and jerk, and its duration
  double a0_ = 0;
  double j_ = 0;
  double t_ = 1;
  double mean_ = 0.5;
  std::array<Eigen::Vector4d, kPoints> rows_{};
  std::array<double, kPoints> weights_{};
};

}  // namespace blendbench::timing_detail
