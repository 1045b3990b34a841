#include "blendbench/corner/clothoid_blend.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>

#include "blendbench/core/format.hpp"
#include "blendbench/corner/biclothoid.hpp"
#include "blendbench/corner/corner.hpp"
#include "blendbench/corner/corner_plane.hpp"
#include "blendbench/geometry/fresnel.hpp"

namespace blendbench {
namespace {

constexpr double kPi = std::numbers::pi;

// The pair of scale a: d = a S(u) / cos(alpha/2), T = a (C(u) + S(u) tan(alpha/2)).
ClothoidPair pair_of_scale(const ClothoidPairShape& shape, double scale) {
  ClothoidPair pair;
  pair.alpha = shape.alpha;
  pair.scale = scale;
  pair.u = shape.u;
  const double ch = shape.cos_half;
  const double sh = shape.sin_half;
  pair.half_length = scale * pair.u;
  pair.sharpness = kPi / (scale * scale);
  pair.kappa_peak = kPi * pair.u / scale;
  pair.deviation = scale * shape.s / ch;
  pair.tangent_length = scale * (shape.c * ch + shape.s * sh) / ch;
  return pair;
}

// The shape of turn alpha given its half angle's cosine and sine.
ClothoidPairShape pair_shape(double alpha, double cos_half, double sin_half) {
  ClothoidPairShape shape;
  shape.alpha = alpha;
  shape.u = std::sqrt(alpha / kPi);
  const FresnelCS f = fresnel(shape.u);
  shape.c = f.c;
  shape.s = f.s;
  shape.cos_half = cos_half;
  shape.sin_half = sin_half;
  return shape;
}

}  // namespace

ClothoidPairShape clothoid_pair_shape(double alpha) {
  return pair_shape(alpha, std::cos(0.5 * alpha), std::sin(0.5 * alpha));
}

ClothoidPairShape clothoid_pair_shape(double alpha, double cos_alpha, double sin_alpha) {
  // each half-angle formula on the side where 1 +- cos(alpha) does not cancel, the other half
  // from sin(alpha) = 2 sin(alpha / 2) cos(alpha / 2): both within a few ulp of their inputs, as
  // cos and sin of an alpha computed from the same cosine and sine are
  if (cos_alpha >= 0) {
    const double cos_half = std::sqrt(0.5 * (1 + cos_alpha));
    return pair_shape(alpha, cos_half, 0.5 * sin_alpha / cos_half);
  }
  const double sin_half = std::sqrt(0.5 * (1 - cos_alpha));
  return pair_shape(alpha, 0.5 * sin_alpha / sin_half, sin_half);
}

ClothoidPair clothoid_pair_for_deviation(const ClothoidPairShape& shape, double deviation) {
  return pair_of_scale(shape, deviation * shape.cos_half / shape.s);
}

ClothoidPair clothoid_pair_for_tangent_length(const ClothoidPairShape& shape, double tangent_length) {
  const double ch = shape.cos_half;
  return pair_of_scale(shape, tangent_length * ch / (shape.c * ch + shape.s * shape.sin_half));
}

ClothoidPair clothoid_pair_for_deviation(double alpha, double deviation) {
  return clothoid_pair_for_deviation(clothoid_pair_shape(alpha), deviation);
}

ClothoidPair clothoid_pair_for_tangent_length(double alpha, double tangent_length) {
  return clothoid_pair_for_tangent_length(clothoid_pair_shape(alpha), tangent_length);
}

std::vector<Segment> clothoid_pair_segments(const ClothoidPair& pair, const ClothoidPairShape& shape,
                                            const CornerPlane& plane) {
  // each clothoid's frame: e1 along its start tangent, e2 that turned by +90 deg (to_segments)
  const auto clothoid = [&](const Vec2& at, double cs, double sn, double kappa, double sharpness) {
    return Clothoid{to_space(plane, at), cs * plane.x + sn * plane.y, -sn * plane.x + cs * plane.y, kappa, sharpness,
                    pair.half_length};
  };
  const Vec2 start(-pair.tangent_length, 0.0);
  const Vec2 mid = start + Vec2(pair.scale * shape.c, pair.scale * shape.s);
  std::vector<Segment> out;
  if (!(pair.half_length > 0)) return out;
  out.reserve(2);
  out.emplace_back(clothoid(start, 1.0, 0.0, 0.0, pair.sharpness));
  // the second clothoid's heading as the first one's end angle kappa0 s + c s^2 / 2 (the
  // expression the Clothoid segment evaluates), not the equal alpha / 2: the two must give the
  // same curvature vector at the junction to the last bit (the velocity planner treats any
  // difference there, even 1e-14 1/m, as a curvature step)
  const double theta = (0.0 + 0.5 * pair.sharpness * pair.half_length) * pair.half_length;
  out.emplace_back(clothoid(mid, std::cos(theta), std::sin(theta), pair.sharpness * pair.half_length, -pair.sharpness));
  return out;
}

LinePair line_pair(const CornerInput& corner, const PlanarCorner& geometry, double start_distance) {
  LinePair line;
  const Vec2& turn = geometry.shapes.q2.t;  // (cos, sin) of the turn (line_corner)
  line.shape = clothoid_pair_shape(geometry.angle, turn.x(), turn.y());
  const bool by_start = start_distance > 0;
  line.pair = by_start ? clothoid_pair_for_tangent_length(line.shape, start_distance)
                       : clothoid_pair_for_deviation(line.shape, corner.spec.parameter);
  const double available = std::min(corner.in_available, corner.out_available);
  if (line.pair.tangent_length > available) {
    line.pair = clothoid_pair_for_tangent_length(line.shape, available);
    line.shrunk = true;
    line.shrink_note =
        pair_shrunk_note(by_start, by_start ? start_distance : corner.spec.parameter,
                         by_start ? line.pair.tangent_length : line.pair.deviation, corner);
  }
  return line;
}

void use_line_pair(const LinePair& line, const CornerPlane& plane, double parameter_used, CornerFit& fit) {
  fit.transition = clothoid_pair_segments(line.pair, line.shape, plane);
  fit.trim_in = line.pair.tangent_length;
  fit.trim_out = line.pair.tangent_length;
  fit.parameter_used = parameter_used;
  fit.exact_deviation = line.pair.deviation;
  fit.limited = line.shrunk;
}

ClothoidArcClothoid clothoid_arc_clothoid(double alpha, double kappa, double clothoid_length) {
  ClothoidArcClothoid cac;
  cac.alpha = alpha;
  cac.kappa = kappa;
  cac.clothoid_length = std::clamp(clothoid_length, 0.0, alpha / kappa);
  const double lc = cac.clothoid_length;
  // clothoid half: Makino's scale a = sqrt(pi Lc / kappa), u = Lc / a; turns phi = kappa Lc / 2
  double x = 0;
  double y = 0;
  if (lc > 0) {
    const double scale = std::sqrt(kPi * lc / kappa);
    const FresnelCS f = fresnel(lc / scale);
    x = scale * f.c;
    y = scale * f.s;
  }
  const double phi = 0.5 * kappa * lc;
  const double psi = std::max(0.5 * alpha - phi, 0.0);  // the arc's half turn
  const double radius = 1.0 / kappa;
  // arc from tangent angle phi to alpha/2
  x += radius * (std::sin(0.5 * alpha) - std::sin(phi));
  y += radius * (std::cos(phi) - std::cos(0.5 * alpha));
  const double ch = std::cos(0.5 * alpha);
  const double sh = std::sin(0.5 * alpha);
  cac.arc_length = 2 * psi * radius;
  cac.deviation = y / ch;
  cac.tangent_length = (x * ch + y * sh) / ch;
  return cac;
}

namespace {

// The segments of a clothoid-arc-clothoid in the corner plane (start at (-T, 0), heading +x,
// turning towards +y).
std::vector<Segment> cac_segments(const ClothoidArcClothoid& cac, const CornerPlane& plane) {
  const double lc = cac.clothoid_length;
  const double c = lc > 0 ? cac.kappa / lc : 0.0;
  const Posture start{Vec2(-cac.tangent_length, 0.0), 0.0, 0.0};
  // clothoid, arc and clothoid as one chain of postures
  const Biclothoid first = make_biclothoid(start, c, lc, 0.0);
  const Posture arc_start = first.mid;
  std::vector<Segment> out = to_segments(first, plane);
  const double psi2 = cac.arc_length * cac.kappa;  // the arc's turn
  if (cac.arc_length > 0) {
    const double radius = 1.0 / cac.kappa;
    const Vec2 normal(-std::sin(arc_start.theta), std::cos(arc_start.theta));
    const Vec3 center = to_space(plane, arc_start.p + radius * normal);
    const Vec3 from = to_space(plane, arc_start.p);
    const Vec3 u = (from - center).normalized();
    const Vec3 v = std::cos(arc_start.theta) * plane.x + std::sin(arc_start.theta) * plane.y;
    out.emplace_back(Arc{center, u, v, radius, psi2, 0.0});
  }
  const Vec2 chord = Vec2(std::cos(arc_start.theta + 0.5 * psi2), std::sin(arc_start.theta + 0.5 * psi2)) *
                     (2.0 / cac.kappa * std::sin(0.5 * psi2));
  const Posture last_start{arc_start.p + chord, cac.kappa, arc_start.theta + psi2};
  const std::vector<Segment> last = to_segments(make_biclothoid(last_start, -c, lc, 0.0), plane);
  out.insert(out.end(), last.begin(), last.end());
  return out;
}

// The clothoid length in [0, alpha / kappa] at which a monotone quantity of the
// clothoid-arc-clothoid reaches `target` (bisection with false position; both grow with it).
template <class F>
double cac_length_for(double alpha, double kappa, double target, const F& quantity) {
  double lo = 0;
  double hi = alpha / kappa;
  double f_lo = quantity(clothoid_arc_clothoid(alpha, kappa, lo)) - target;
  double f_hi = quantity(clothoid_arc_clothoid(alpha, kappa, hi)) - target;
  if (f_hi <= 0) return hi;
  if (f_lo >= 0) return lo;
  for (int it = 0; it < 200 && hi - lo > 1e-15 * (alpha / kappa); ++it) {
    // alternate false position and bisection: robust and fast on this smooth, monotone function
    double mid = (it % 2 == 0) ? (lo * f_hi - hi * f_lo) / (f_hi - f_lo) : 0.5 * (lo + hi);
    if (!(mid > lo && mid < hi)) mid = 0.5 * (lo + hi);
    const double f_mid = quantity(clothoid_arc_clothoid(alpha, kappa, mid)) - target;
    if (f_mid > 0) {
      hi = mid;
      f_hi = f_mid;
    } else {
      lo = mid;
      f_lo = f_mid;
    }
  }
  return lo;  // the side that keeps the quantity at or below the target
}

}  // namespace

CornerFit fit_clothoid_corner(const CornerInput& corner) {
  const PlanarCorner geometry = planar_corner(corner.in, corner.out);
  if (auto special = clothoid_special_case(corner, geometry)) return *special;

  // seed 002 (Makino) treats lines only: corners with arcs get a biclothoid fillet (seed 004), which is the
  // symmetric pair again where both moves are lines
  if (!geometry.lines) {
    CornerFit fit = fit_biclothoid_in_plane(corner, geometry);
    // a non-planar corner makes the biclothoid fall back to a Bezier in turn
    fit.fallback = fit.fallback == Fallback::kBezier ? Fallback::kBiclothoidBezier : Fallback::kBiclothoid;
    const double cap = corner.spec.kappa_max;
    if (fit.outcome.ok() && cap > 0) {
      double peak = 0;
      for (const Segment& seg : fit.transition) peak = std::max(peak, max_curvature(seg, 0, length(seg)));
      if (peak > cap * (1 + 1e-9)) {
        if (fit.corner_case == CornerCase::kRegular) fit.corner_case = CornerCase::kCurvatureCapUnmet;
        fit.note += std::string(fit.note.empty() ? "" : "; ") +
                    "the biclothoid fallback does not cap curvature: peak " + format_per_mm(peak) + " > kappa_max " +
                    format_per_mm(cap);
      }
    }
    return fit;
  }

  CornerFit fit;
  const double alpha = geometry.angle;
  const double tolerance = corner.spec.parameter;
  const double cap = corner.spec.kappa_max;
  const double available = std::min(corner.in_available, corner.out_available);
  const char* const short_move = corner.in_available <= corner.out_available ? "incoming" : "outgoing";

  // the pair at the tolerance, shrunk to the available tangent length
  LinePair line = line_pair(corner, geometry, 0.0);
  const ClothoidPair& pair = line.pair;
  // the pair as the transition, with its note (the fit itself is returned by the caller: a
  // copy of it out of the lambda cost an allocation per line-line fit)
  const auto use_pair = [&](Note note) {
    use_line_pair(line, geometry.plane, pair.deviation, fit);
    fit.note = std::move(note);
  };
  if (cap <= 0 || pair.kappa_peak <= cap) {
    use_pair(std::move(line.shrink_note));
    return fit;
  }

  // the pair is too sharp: with peak curvature fixed at the cap the deviation and the tangent
  // length grow with the clothoid length (clothoid_blend.hpp), from the plain arc of radius
  // 1 / cap (clothoid length 0) to the pair with that peak. A clothoid-arc-clothoid meets both
  // limits iff the plain arc does; then take the longest clothoids that keep both.
  const ClothoidArcClothoid arc_only = clothoid_arc_clothoid(alpha, cap, 0.0);
  if (arc_only.deviation > tolerance || arc_only.tangent_length > available) {
    fit.corner_case = CornerCase::kCurvatureCapUnmet;
    const std::string why = arc_only.deviation > tolerance
                                ? "an arc of that curvature deviates " + format_mm(arc_only.deviation) + " > " + format_mm(tolerance)
                                : "an arc of that curvature needs " + format_mm(arc_only.tangent_length) + " of the " +
                                      short_move + " move, which has " + format_mm(available);
    std::string note = "peak curvature " + format_per_mm(pair.kappa_peak) + " exceeds kappa_max " + format_per_mm(cap) + ": " + why +
                       "; the clothoid pair is kept";
    if (!line.shrink_note.empty()) note += "; " + line.shrink_note.text();
    use_pair(std::move(note));
    return fit;
  }
  const double lc = std::min(
      cac_length_for(alpha, cap, tolerance, [](const ClothoidArcClothoid& c) { return c.deviation; }),
      cac_length_for(alpha, cap, available, [](const ClothoidArcClothoid& c) { return c.tangent_length; }));
  const ClothoidArcClothoid cac = clothoid_arc_clothoid(alpha, cap, lc);
  fit.corner_case = CornerCase::kClothoidArcClothoid;
  fit.transition = cac_segments(cac, geometry.plane);
  fit.trim_in = cac.tangent_length;
  fit.trim_out = cac.tangent_length;
  fit.parameter_used = cac.deviation;
  if (cac.deviation < tolerance * (1 - 1e-9)) {
    fit.limited = true;
    fit.note = "deviation " + format_mm(cac.deviation) + " below the tolerance " + format_mm(tolerance) + ": the " + short_move +
               " move is short";
  }
  return fit;
}

}  // namespace blendbench
