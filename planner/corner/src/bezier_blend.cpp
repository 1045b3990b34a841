// seed 000: a corner transition made of one Bezier curve, G2 at both junctions, sized by the
// transition parameter TP (distance from the corner to the transition points, Algorithm 1).
//
//   line-line      cubic, P1 = P2 = B                                      (seed 000 eq. 8-9)
//   line-circle    cubic when the line lies in the circle's plane          (seed 000 eq. 10-13)
//                  quartic with minimum bending energy otherwise           (seed 000 eq. 14-17)
//   circle-line    the mirror image of line-circle (the curve reversed)
//   circle-circle  quartic, P2 = B                                         (seed 000 eq. 18-24)
//
// Notation: P0 is the transition point on the incoming move, Pn the one on the outgoing move,
// B the corner, T the unit tangent in the direction of travel, K = kappa N the curvature vector.
// The end conditions used throughout follow from eq. 3-4 and the curvature vector of a
// Bezier, K = (C'' - (C''.t) t) / |C'|^2 with t = C'/|C'|:
//   at u = 0:  T0 = (P1 - P0)/|P1 - P0|,   K0 = (n-1)/n * perp(P2 - P1) / |P1 - P0|^2
//   at u = 1:  Tn = (Pn - Pn-1)/|...|,     Kn = (n-1)/n * perp(Pn-2 - Pn-1) / |Pn - Pn-1|^2
// where perp() removes the component along the end tangent. This is eq. 6-7 of seed 000 with the
// direction of the curvature kept, which G2 in 3D needs (the paper states magnitudes only).

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "blendbench/core/format.hpp"
#include "blendbench/corner/corner.hpp"

namespace blendbench {
namespace {

// rad: tangents closer than this are continuous (the blender's G1 threshold).
constexpr double kTangentAngle = 1e-9;
// Tangents within kReversalAngle of opposite (corner.hpp) are a reversal; no Bezier joins them
// (the cubic of eq. 8-9 would stop at u = 1/2, and the curvature of any fillet grows like
// 1/angle^2; within kNearReversalAngle the blender already left the kink).
// m: a transition shorter than this is a zero-distance corner. Control points are stored in
// absolute coordinates, so below ~1 nm their rounding (1e-16 of ~1 m) would swamp curvature.
constexpr double kMinLength = 1e-9;
// rad: at most this much of a circle is replaced. Eq. 15, 22, 24 hold for 0 < theta < 2 pi but
// B - P4 shrinks again past a half-turn (the fillet cuts across the circle) and eq. 15
// degenerates (|P4 - P3| = 0) at a full turn; a half-turn keeps the fillet local.
constexpr double kMaxArcTurn = std::numbers::pi;
// |sin| of the angle between the line and the circle's plane below which they count as
// coplanar (seed 000 sec. 2.3: "if A, B, C, O are coplanar"). Tight, so that the cubic's curvature
// vector at P3 stays within ~1e-12 relative of the circle's; anything else takes the quartic.
constexpr double kCoplanar = 1e-12;
// Fraction of the transition length L below which an arm |P1 - P0| or |P3 - P2| of the coplanar
// cubic counts as too short: the end curvature (2/3) perp(...) / arm^2 becomes ill-conditioned
// (rounding of the absolute control points is amplified by (L / arm)^2, and the curvature
// rises from its end value to a sharp peak within a sliver of the curve). The quartic then
// takes over; its line arm is at least ~0.1 L by construction (see min_energy_arm).
constexpr double kMinCubicArm = 0.1;
// |sin| of the angle between the line and the circle's tangent at P3 below which eq. 13 has no
// usable solution (sin(alpha) -> 0: P2 at infinity).
constexpr double kParallel = 1e-10;
// Relative to the largest speed: a Bezier whose speed |C'(u)| dips below this has a cusp.
constexpr double kMinRelativeSpeed = 1e-9;
// Samples in u for the regularity check.
constexpr int kSpeedSamples = 256;
// A helix (Arc with rise) whose rise per radian is below this fraction of its radius is a circle.
constexpr double kFlatHelix = 1e-12;

// One side of the corner at its transition point: position, unit tangent in the direction of
// travel, curvature vector (1/m). `radius` is 0 on a line.
struct End {
  Vec3 p;
  Vec3 t;
  Vec3 k;
  double radius = 0;
  double turn = 0;  // rad: angle at the centre between the transition point and B (theta of eq. 15)
};

// The same end seen on the reversed path: tangent flips, curvature vector does not.
End reversed(const End& e) { return End{e.p, -e.t, e.k, e.radius, e.turn}; }

// seed 000 eq. 15 / 22 / 24, derived: with P2 = B and Pn-1 = Pn - l T, the end condition above
// gives K = (3/4) perp(B - Pn) / l^2. On a circle of radius r with B at angle theta from Pn,
// perp(B - Pn) points at the centre with length r (1 - cos theta), so K has the circle's
// direction and |K| = 1/r exactly when l^2 = (3/4) r^2 (1 - cos theta) = (3/2) r^2 sin^2(theta/2)
// (the form used here, exact to rounding for small theta). Eq. 15's middle member
// (3/4) r |P2 - P3| sin(alpha) is the same quantity: |P2 - P3| sin(alpha) = |perp(B - P4)|.
double quartic_arm(const End& e) { return std::sqrt(1.5) * e.radius * std::sin(0.5 * e.turn); }

// seed 000 eq. 16-17, derived (the printed closed form is garbled): a quartic with P0, P2, P3, P4
// fixed and P1 = P0 + l1 d (d the unit line direction). C'' = 12 sum_i D_i B_i,2(u) with
// D0 = P2 - 2P1 + P0, D1 = P3 - 2P2 + P1, D2 = P4 - 2P3 + P2, and the Gram matrix of the
// quadratic Bernstein basis is [6 3 1; 3 4 3; 1 3 6] / 30, so
//   eps(l1) = 144/30 * sum_ij G_ij D_i.D_j,  dD/dl1 = (-2d, d, 0),
//   d eps / d l1 = 0  <=>  -9 D0.d - 2 D1.d + D2.d = 0
//                  <=>  l1 = d.(4 P2 + 4 P3 - 7 P0 - P4) / 16.
// With P2 = P0 + TP d and P3 = P4 + l2 (a2, b2, c2) this is the paper's eq. 17:
// 16 l1 = 4 TP + 4 l2 d.(a2, b2, c2) + 3 d.(P4 - P0). eps is a convex quadratic in l1
// (coefficient 144/30 * 16 > 0), so this stationary point is the minimum.
// Range, for the line-circle quartic (P2 = B = P0 + L d, |P4 - B| <= L, l2 <= sqrt(3/8) L from
// eq. 15): 16 l1 = 4 L + 3 d.(P4 - P0) - 4 l2 d.T4 with 0 <= d.(P4 - P0) <= 2 L, so
// 0.097 L <= l1 <= 0.78 L: P1 always lies strictly between P0 and B.
double min_energy_arm(const Vec3& p0, const Vec3& d, const Vec3& p2, const Vec3& p3, const Vec3& p4) {
  return d.dot(4 * p2 + 4 * p3 - 7 * p0 - p4) / 16.0;
}

// The result of one case: control points, or why there are none.
struct Curve {
  std::vector<Vec3> points;
  Fallback fallback = Fallback::kNone;
  std::string fallback_why;  // why the fallback was needed, for the report's note
  bool non_planar = false;
};

// seed 000 eq. 10-13: the coplanar cubic from a line (start `a`, K = 0) to a circle (end `c`), or
// nullopt with the reason in `why`. P2 is where the line meets the circle's tangent at P3;
// P1 = P2 + sigma d. Eq. 13 re-derived from the end condition with n = 3:
//   K3 = (2/3) perp(P1 - P2) / |P3 - P2|^2 = N / r
//   => sigma (d.N) = (3/2) |P3 - P2|^2 / r,  i.e. |P1 - P2| = 3 |P3 - P2|^2 / (2 r sin(alpha))
// (alpha the angle at P2, sin(alpha) = |d.N| in the plane): the printed eq. 13 with its
// fraction restored. Existence: the tangent at P3 must meet the line ahead of P0 (t > 0) and
// behind P3 (l2 > 0), P1 must lie strictly between P0 and P2 (sigma < 0, l1 > 0: otherwise
// the hodograph turns back and the curvature at P3 points away from the centre), and P2 must
// lie within L of B, so that the whole control polygon, and by the convex hull property the
// curve, stays within L of the corner like every other case here. Both arms must also be at
// least kMinCubicArm L (conditioning). The paper asks only for a solution of eq. 10-13; these
// checks are what "the cubic exists" means here, and any failure takes the quartic.
std::optional<std::vector<Vec3>> coplanar_cubic(const End& a, const End& c, double l, std::string& why) {
  const Vec3& d = a.t;
  // P0 + t d = P3 - l2 T3, solved in the plane of d and T3
  const Vec3 dxt = d.cross(c.t);
  const double s2 = dxt.squaredNorm();
  if (s2 < kParallel * kParallel) {
    why = "the circle's tangent at P3 is parallel to the line (eq. 13: sin(alpha) = 0)";
    return std::nullopt;
  }
  const Vec3 w = c.p - a.p;
  const double t = w.cross(c.t).dot(dxt) / s2;
  const double l2 = d.cross(w).dot(dxt) / s2;
  if (!(t > 0) || !(l2 > 0)) {
    why = "the circle's tangent at P3 meets the line behind P0 or ahead of P3";
    return std::nullopt;
  }
  if (std::abs(t - l) > l) {
    why = "P2 would lie " + format_mm(std::abs(t - l)) + " from the corner, farther than the transition length";
    return std::nullopt;
  }
  const double kdot = d.dot(c.k);
  const double kappa2 = c.k.squaredNorm();
  // eq. 13: sigma (d.K) = (3/2) l2^2 kappa^2 (K = kappa N)
  const double sigma = kdot != 0 ? 1.5 * l2 * l2 * kappa2 / kdot : 0.0;
  const double l1 = t + sigma;
  if (!(sigma < 0) || !(l1 > 0)) {
    why = "P1 would not lie between P0 and P2 (the circle turns away from the corner, or TP is large for the radius)";
    return std::nullopt;
  }
  if (l1 < kMinCubicArm * l || l2 < kMinCubicArm * l) {
    why = "an arm of the cubic would be shorter than 0.1 L (ill-conditioned end curvature)";
    return std::nullopt;
  }
  const Vec3 p2 = a.p + t * d;
  return std::vector<Vec3>{a.p, a.p + l1 * d, p2, c.p};
}

// Line (start `a`) to circle (end `c`) through the corner b: the coplanar cubic when it exists,
// else the quartic of eq. 14-17.
Curve line_to_circle(const End& a, const Vec3& b, const End& c, double l) {
  Curve out;
  // the line is in the circle's plane when it has no component along the binormal T x N
  const Vec3 binormal = c.t.cross(c.k.normalized());
  const bool coplanar = std::abs(a.t.dot(binormal)) <= kCoplanar;
  out.non_planar = !coplanar;
  if (coplanar) {
    std::string why;
    if (auto cubic = coplanar_cubic(a, c, l, why)) {
      out.points = std::move(*cubic);
      return out;
    }
    out.fallback = Fallback::kQuartic;
    out.fallback_why = "quartic (000 eq. 14-17): the coplanar cubic of eq. 10-13 is not usable here: " + why;
  }
  // seed 000 eq. 14-17: P2 = B, P3 from eq. 15, P1 on the line by minimum bending energy
  const Vec3 p3 = c.p - quartic_arm(c) * c.t;
  const double l1 = min_energy_arm(a.p, a.t, b, p3, c.p);
  out.points = {a.p, a.p + l1 * a.t, b, p3, c.p};
  return out;
}

// seed 000 eq. 18-24: circle to circle, P2 = B, P1 and P3 from eq. 24 and eq. 22.
Curve circle_to_circle(const End& a, const Vec3& b, const End& c) {
  Curve out;
  const Vec3 n1 = a.t.cross(a.k).normalized();
  const Vec3 n2 = c.t.cross(c.k).normalized();
  out.non_planar = n1.cross(n2).norm() > kCoplanar;
  out.points = {a.p, a.p + quartic_arm(a) * a.t, b, c.p - quartic_arm(c) * c.t, c.p};
  return out;
}

// The curve is regular (no cusp): its speed |C'(u)| stays above kMinRelativeSpeed of its
// maximum on kSpeedSamples + 1 samples (|C'|^2 is a polynomial of degree up to 6; the
// near-cusps that matter are wide enough to be sampled).
//
// Most curves are regular with a wide margin, which their hodograph shows without sampling: C'
// is a Bezier whose control points h_i are the differences of the curve's (times the degree,
// which cancels here), so on a piece of it d . C'(u) >= min_i d . h_i for any unit d (a convex
// combination), while |C'(u)| <= max_i |h_i| everywhere. With d along the piece's end points and
// the hodograph split in halves (de Casteljau, at most three times) until every piece has
// min_i d . h_i > kProvenSpeed max_i |h_i|, the sampled minimum exceeds kProvenSpeed of the
// sampled maximum; kProvenSpeed is far above kMinRelativeSpeed, so the sampling's rounding
// (1e-15 of the speed) cannot change its verdict. Curves not proven so are sampled.
constexpr double kProvenSpeed = 1e-6;
bool speed_proven_regular(const std::vector<Vec3>& points) {
  using Polygon = std::array<Vec3, 6>;  // a hodograph of degree <= 5 (curves of degree <= 6)
  const std::size_t count = points.size() - 1;
  if (count < 1 || count > 6) return false;
  Polygon h;
  double top = 0;
  for (std::size_t i = 0; i < count; ++i) {
    h[i] = points[i + 1] - points[i];
    top = std::max(top, h[i].norm());
  }
  if (!(top > 0) || !std::isfinite(top)) return false;
  const auto proven = [&](const Polygon& piece, int depth, const auto& self) -> bool {
    const Vec3 sum = piece[0] + piece[count - 1];
    const double sum_norm = sum.norm();
    if (sum_norm > 0) {
      const Vec3 d = sum / sum_norm;
      double low = std::numeric_limits<double>::infinity();
      for (std::size_t i = 0; i < count; ++i) low = std::min(low, d.dot(piece[i]));
      if (low > kProvenSpeed * top) return true;
    }
    if (depth == 3) return false;
    // de Casteljau at u = 1/2: the left half's control points are the first of each level, the
    // right half's the last
    Polygon left;
    Polygon right;
    Polygon level = piece;
    for (std::size_t k = 0; k < count; ++k) {
      left[k] = level[0];
      right[count - 1 - k] = level[count - 1 - k];
      for (std::size_t i = 0; i + k + 1 < count; ++i) level[i] = 0.5 * (level[i] + level[i + 1]);
    }
    return self(left, depth + 1, self) && self(right, depth + 1, self);
  };
  return proven(h, 0, proven);
}

bool regular(const Bezier& curve, std::string& why) {
  if (speed_proven_regular(curve.control_points())) return true;
  double lo = std::numeric_limits<double>::infinity();
  double hi = 0;
  for (int k = 0; k <= kSpeedSamples; ++k) {
    const double speed = curve.d1(static_cast<double>(k) / kSpeedSamples).norm();
    lo = std::min(lo, speed);
    hi = std::max(hi, speed);
  }
  if (!(lo > kMinRelativeSpeed * hi)) {
    why = "the Bezier would have a cusp (minimum speed " + format_value(lo / hi) + " of the maximum)";
    return false;
  }
  return true;
}

bool is_line(const Primitive& p) { return std::holds_alternative<Line>(p); }

bool is_helix(const Primitive& p) {
  const Arc* arc = std::get_if<Arc>(&p);
  return arc != nullptr && std::abs(arc->rise) > kFlatHelix * arc->radius * arc->sweep;
}

double radius_of(const Primitive& p) {
  const Arc* arc = std::get_if<Arc>(&p);
  return arc != nullptr ? arc->radius : 0.0;
}

}  // namespace

CornerFit fit_bezier_corner(const CornerInput& corner) {
  CornerFit fit;
  const double tp = corner.spec.parameter;
  const double len_in = length(corner.in);
  const bool in_line = is_line(corner.in);
  const bool out_line = is_line(corner.out);
  const double r_in = radius_of(corner.in);
  const double r_out = radius_of(corner.out);

  // helices are outside seed 000 (lines and circles only): B is not in the osculating plane at P4
  if (is_helix(corner.in) || is_helix(corner.out)) {
    fit.corner_case = CornerCase::kNonPlanar;
    fit.outcome = {Status::kInfeasible, "the bezier method (000) joins lines and circles only, not helices"};
    return fit;
  }

  // seed 000 Algorithm 1 with the blender's availability: min(TP, in_available, out_available).
  // When both moves are blended at both ends the blender offers half of each, and this is
  // exactly Algorithm 1 (TP if both moves exceed 2 TP, else min(|AB|, |BC|)/2). A move blended
  // at this end only can give all of itself (no other corner competes for it), where the
  // paper would still halve it. Arcs give at most a half-turn (kMaxArcTurn). Length on an arc
  // is arc length, so the transition point is at arc length L from the corner.
  // (the reason is formatted only for a limit that shrinks TP: four notes built on every fit
  // were a large part of a Bezier fit's time)
  double l = tp;
  std::string why;
  const auto shrink = [&](double limit, const auto& reason) {
    if (limit < l) {
      l = std::max(limit, 0.0);
      why = reason();
    }
  };
  shrink(corner.in_available,
         [&] { return "the incoming move is short (" + format_mm(corner.in_available) + " available)"; });
  shrink(corner.out_available,
         [&] { return "the outgoing move is short (" + format_mm(corner.out_available) + " available)"; });
  if (!in_line) {
    shrink(kMaxArcTurn * r_in, [&] { return "the incoming arc (radius " + format_mm(r_in) + ") gives at most a half-turn"; });
  }
  if (!out_line) {
    shrink(kMaxArcTurn * r_out,
           [&] { return "the outgoing arc (radius " + format_mm(r_out) + ") gives at most a half-turn"; });
  }
  if (l < tp) fit.note = lengths_note("TP shrunk from ", tp, " to ", l, why);
  fit.parameter_used = l;

  // tangents and curvature vectors at the corner
  const Vec3 b_in = point(corner.in, len_in);
  const Vec3 b_out = point(corner.out, 0.0);
  const Vec3 t_in = tangent(corner.in, len_in);
  const Vec3 t_out = tangent(corner.out, 0.0);
  const double angle = angle_between(t_in, t_out);

  // reversal (180 degrees): no Bezier joins opposite tangents; the path must stop at the cusp
  // in every buffer mode (seed 001 stops in Buffered; a cusp cannot be passed at speed in any)
  if (angle >= std::numbers::pi - kReversalAngle) {
    fit.corner_case = CornerCase::kReversal;
    fit.stop = true;
    fit.parameter_used = 0;
    fit.note.clear();
    return fit;
  }
  // already G2: collinear lines, or the same circle continued in the same direction
  if (angle <= kTangentAngle) {
    if (in_line && out_line) {
      fit.corner_case = CornerCase::kCollinear;
      fit.parameter_used = 0;
      fit.note.clear();
      return fit;
    }
    const Vec3 k_in = curvature_vector(corner.in, len_in);
    const Vec3 k_out = curvature_vector(corner.out, 0.0);
    if (!in_line && !out_line && (k_in - k_out).norm() <= 1e-9 * k_in.norm()) {
      fit.corner_case = CornerCase::kSameCircleSameDirection;
      fit.parameter_used = 0;
      fit.note.clear();
      return fit;
    }
  }
  // (shrunk, where the corner is blended: not at the cases above, which TP does not change)
  fit.limited = l < tp;
  // zero distance (TP = 0, or nothing left of a move): a kink; the blender stops there in
  // Buffered mode (seed 001: a zero-length transition that only affects blending)
  if (l <= kMinLength) {
    fit.corner_case = CornerCase::kZeroDistance;
    fit.parameter_used = 0;
    return fit;
  }

  // the transition points (Algorithm 1) and the ends of the neighbouring moves there
  const double s_in = len_in - l;
  const End a{point(corner.in, s_in), tangent(corner.in, s_in), curvature_vector(corner.in, s_in), r_in,
              in_line ? 0.0 : l / r_in};
  const End c{point(corner.out, l), tangent(corner.out, l), curvature_vector(corner.out, l), r_out,
              out_line ? 0.0 : l / r_out};

  Curve curve;
  if (in_line && out_line) {
    // seed 000 eq. 8-9: P1 = P2 = B gives zero curvature at both ends
    curve.points = {a.p, b_out, b_out, c.p};
  } else if (in_line) {
    curve = line_to_circle(a, b_out, c, l);
  } else if (out_line) {
    // the mirror case: solve line -> circle on the reversed path and reverse the result
    curve = line_to_circle(reversed(c), b_in, reversed(a), l);
    std::reverse(curve.points.begin(), curve.points.end());
  } else {
    curve = circle_to_circle(a, b_out, c);
  }

  // never NaN: a non-finite or cusped curve is reported, not returned
  const bool finite = std::all_of(curve.points.begin(), curve.points.end(), [](const Vec3& q) { return q.allFinite(); });
  if (!finite) {
    fit.outcome = {Status::kInfeasible, "a control point of the Bezier is not finite"};
    return fit;
  }
  Bezier bezier(std::move(curve.points));
  std::string bad;
  if (!regular(bezier, bad)) {
    fit.outcome = {Status::kInfeasible, bad};
    return fit;
  }
  fit.corner_case = angle <= kTangentAngle ? CornerCase::kTangent : curve.non_planar ? CornerCase::kNonPlanar : CornerCase::kRegular;
  fit.fallback = curve.fallback;
  if (!curve.fallback_why.empty()) fit.note += (fit.note.empty() ? "" : "; ") + curve.fallback_why;
  fit.trim_in = l;
  fit.trim_out = l;
  fit.transition.emplace_back(std::move(bezier));
  return fit;
}

}  // namespace blendbench
