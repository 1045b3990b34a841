#pragma once
// Path segments in 3D, all evaluated by arc length s in [0, length] (metres).
//
// Every segment answers position, unit tangent and curvature vector (kappa * N, 1/m) at s, and
// the maximum curvature (1/m) and maximum sharpness |d kappa / ds| (1/m^2) over an interval.
// Lines, arcs (and helices) and clothoids are exactly arc-length parameterised; a Bezier carries
// an arc-length table (Gauss-Legendre + Newton inversion) so it can be sampled uniformly in s.
// Queries clamp s into [0, length].

#include <variant>
#include <vector>

#include "blendbench/core/geometry.hpp"

namespace blendbench {

// A straight segment from p0 to p1; s = 0 at p0.
struct Line {
  Vec3 p0;
  Vec3 p1;
};

// A circular arc, or a helix when `rise` is non-zero:
//   p(phi) = center + radius (cos(phi) u + sin(phi) v) + rise * phi / sweep * w,  w = u x v,
// for phi in [0, sweep]. u and v are orthonormal, v is the direction of motion at the start,
// radius > 0 and sweep > 0 (a full circle is 2 pi; more turns are allowed).
struct Arc {
  Vec3 center;
  Vec3 u;
  Vec3 v;
  double radius = 0;
  double sweep = 0;
  double rise = 0;
};

// A Bezier curve of degree 1..6 by its control points, with an arc-length table built once at
// construction. The curve must be regular (no zero-speed point); construction asserts it.
class Bezier {
 public:
  explicit Bezier(std::vector<Vec3> control_points);

  [[nodiscard]] const std::vector<Vec3>& control_points() const { return ctrl_; }
  [[nodiscard]] int degree() const { return static_cast<int>(ctrl_.size()) - 1; }
  [[nodiscard]] double length() const { return knots_s_.back(); }

  // Curve parameter u in [0, 1] at arc length s (|error in s| below 1e-12 of the length).
  [[nodiscard]] double parameter_at(double s) const;
  // Position and the first three derivatives with respect to u.
  [[nodiscard]] Vec3 eval(double u) const;
  [[nodiscard]] Vec3 d1(double u) const;
  [[nodiscard]] Vec3 d2(double u) const;
  [[nodiscard]] Vec3 d3(double u) const;
  // Arc length from u = 0 to u.
  [[nodiscard]] double length_to(double u) const;

 private:
  std::vector<Vec3> ctrl_;
  std::vector<Vec3> h1_, h2_, h3_;  // control points of the first three derivatives
  std::vector<double> knots_u_;  // table breakpoints in u, knots_u_[0] = 0, back() = 1
  std::vector<double> knots_s_;  // arc length at each breakpoint
};

// A planar clothoid in the plane through `origin` spanned by orthonormal e1, e2. With the
// tangent angle theta measured from e1 towards e2:
//   kappa(s) = kappa0 + sharpness * s,  theta(s) = kappa0 s + sharpness s^2 / 2,
//   p(s) = origin + X(s) e1 + Y(s) e2, X = int_0^s cos(theta), Y = int_0^s sin(theta).
// Curvature is signed (positive turns towards e2). length >= 0.
struct Clothoid {
  Vec3 origin;
  Vec3 e1;
  Vec3 e2;
  double kappa0 = 0;     // 1/m
  double sharpness = 0;  // 1/m^2
  double length = 0;     // m
};

using Segment = std::variant<Line, Arc, Bezier, Clothoid>;

// The programmed moves are lines and arcs only.
using Primitive = std::variant<Line, Arc>;
Segment to_segment(const Primitive& primitive);

// Per-type queries (overloads), and the same on a Segment via std::visit.
double length(const Line& line);
double length(const Arc& arc);
double length(const Bezier& bezier);
double length(const Clothoid& clothoid);
double length(const Segment& segment);
double length(const Primitive& primitive);

Vec3 point(const Line& line, double s);
Vec3 point(const Arc& arc, double s);
Vec3 point(const Bezier& bezier, double s);
Vec3 point(const Clothoid& clothoid, double s);
Vec3 point(const Segment& segment, double s);
Vec3 point(const Primitive& primitive, double s);

// Unit tangent in the direction of increasing s.
Vec3 tangent(const Line& line, double s);
Vec3 tangent(const Arc& arc, double s);
Vec3 tangent(const Bezier& bezier, double s);
Vec3 tangent(const Clothoid& clothoid, double s);
Vec3 tangent(const Segment& segment, double s);
Vec3 tangent(const Primitive& primitive, double s);

// d^2 p / ds^2 = kappa * N (1/m); zero on a line.
Vec3 curvature_vector(const Line& line, double s);
Vec3 curvature_vector(const Arc& arc, double s);
Vec3 curvature_vector(const Bezier& bezier, double s);
Vec3 curvature_vector(const Clothoid& clothoid, double s);
Vec3 curvature_vector(const Segment& segment, double s);
Vec3 curvature_vector(const Primitive& primitive, double s);

// tangent and curvature_vector at s together, the same vectors to the bit (an arc's from one
// sine and cosine of its angle instead of two).
struct TangentCurvature {
  Vec3 tangent;
  Vec3 curvature;
};
TangentCurvature tangent_and_curvature(const Primitive& primitive, double s);

// d^3 p / ds^3 = d(kappa N)/ds = -kappa^2 T + kappa' N + kappa tau B (1/m^2; kappa' = d kappa/ds,
// tau the torsion): with the path speed v, tangential acceleration a_t and jerk j_t, the TCP's
// jerk is j_t T + 3 v a_t (kappa N) + v^3 d^3p/ds^3. Zero on a line.
Vec3 curvature_derivative(const Segment& segment, double s);

// Position, unit tangent, curvature vector and its derivative d^3p/ds^3 at s in one
// evaluation (a Bezier inverts its arc length once, not once per quantity).
struct SegmentFrame {
  Vec3 point;
  Vec3 tangent;
  Vec3 curvature;             // kappa N
  Vec3 curvature_derivative;  // d^3p/ds^3
};
SegmentFrame frame(const Segment& segment, double s);

// |d kappa / ds| at s (1/m^2), kappa the unsigned curvature.
double sharpness(const Segment& segment, double s);

// Maximum unsigned curvature (1/m) and sharpness (1/m^2) over [s0, s1] (clamped to the
// segment). Exact for lines, arcs and clothoids; for a Bezier, a dense scan refined by golden
// section search (relative error below 1e-9 for the fillets used here).
double max_curvature(const Segment& segment, double s0, double s1);
double max_sharpness(const Segment& segment, double s0, double s1);
// Maximum over [s0, s1] of sqrt(kappa'^2 + (kappa tau)^2) (1/m^2), the part of d^3p/ds^3 normal
// to the tangent: equal to max_sharpness on planar segments, kappa tau on a helix. Same
// accuracy as max_sharpness.
double max_spatial_sharpness(const Segment& segment, double s0, double s1);

// The part of a line or arc between arc lengths s0 <= s1 (exact, same parameterisation).
Line sub_segment(const Line& line, double s0, double s1);
Arc sub_segment(const Arc& arc, double s0, double s1);
Primitive sub_segment(const Primitive& primitive, double s0, double s1);

// Start and end points.
Vec3 start_point(const Segment& segment);
Vec3 end_point(const Segment& segment);

// Clothoid coordinates X(s), Y(s) in the clothoid's own plane (see Clothoid), s >= 0 (0 for
// s <= 0). Computed panel by panel: on a panel of half-width h around m the integrand is
// exp(i theta(m)) exp(i (kappa(m) t + c t^2 / 2)), whose Taylor series in t follows from the
// recurrence (n+1) e_{n+1} = i kappa(m) e_n + i c e_{n-1} and integrates term by term; panels are
// short enough that the local phase stays within 1 rad, so no regime (small sharpness, large
// kappa0) cancels. Absolute error below 2e-15 s.
Eigen::Vector2d clothoid_xy(double kappa0, double sharpness, double s);

// The same integral with an initial tangent angle theta0 (rad): int_0^s (cos, sin)(theta0 +
// kappa0 t + sharpness t^2 / 2) dt, i.e. clothoid_xy rotated by theta0 without a separate
// rotation. Same accuracy.
Eigen::Vector2d clothoid_displacement(double theta0, double kappa0, double sharpness, double s);

}  // namespace blendbench
