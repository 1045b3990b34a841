#include "blendbench/geometry/arc_construction.hpp"

#include "blendbench/core/format.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <sstream>
#include <vector>

namespace blendbench {
namespace {

constexpr double kTwoPi = 2 * std::numbers::pi;

ArcBuild failure(const std::string& message) { return {{Status::kInfeasible, message}, Arc{}}; }

using Vec2 = Eigen::Vector2d;

// Points of each arc at which a chain is compared with the spiral (see arcs_along_spiral).
constexpr int kSpiralSamplesPerArc = 64;

double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }
Vec2 left_of(const Vec2& t) { return {-t.y(), t.x()}; }

// The spiral's radius at angle phi.
double spiral_radius(const Spiral& s, double phi) { return s.r0 + (s.r1 - s.r0) * phi / s.sweep; }

// An arc in the spiral's plane (coordinates along u and v about its centre): its centre, its
// signed radius (> 0 turning counter-clockwise about w), its start and its sweep (> 0).
struct PlanarArc {
  Vec2 center;
  double rho = 0;
  Vec2 start;
  double sweep = 0;
};

// The circle through q tangent to the unit tangent t at p, as the arc from `from` to `to` (p and
// q in one order or the other) turning the way t turns; nullopt when q lies on the tangent line
// (no finite circle; not met between points of a spiral).
std::optional<PlanarArc> arc_tangent_at(const Vec2& p, const Vec2& t, const Vec2& q, const Vec2& from, const Vec2& to) {
  const Vec2 n = left_of(t);
  const Vec2 pq = q - p;
  const double denom = 2 * n.dot(pq);
  if (!(std::abs(denom) > 1e-12 * pq.norm())) return std::nullopt;
  PlanarArc a;
  a.rho = pq.squaredNorm() / denom;
  a.center = p + a.rho * n;
  a.start = from;
  const double turn = std::atan2(cross2(from - a.center, to - a.center), (from - a.center).dot(to - a.center));
  double sweep = a.rho > 0 ? turn : -turn;
  if (sweep <= 0) sweep += kTwoPi;
  a.sweep = sweep;
  return a;
}

// The arc from p, leaving along the unit tangent t, to q.
std::optional<PlanarArc> arc_leaving(const Vec2& p, const Vec2& t, const Vec2& q) { return arc_tangent_at(p, t, q, p, q); }

// The arc from q to p that arrives at p along the unit tangent t.
std::optional<PlanarArc> arc_arriving(const Vec2& q, const Vec2& p, const Vec2& t) { return arc_tangent_at(p, t, q, q, p); }

// The biarc from (p0, t0) to (p1, t1), unit tangents: the two tangent arcs through the joint
// at the middle of the control points p0 + d t0, p1 - d t1, d the root of
// |(p1 - d t1) - (p0 + d t0)| = 2d (equal distances; the standard symmetric biarc).
bool add_biarc(const Vec2& p0, const Vec2& t0, const Vec2& p1, const Vec2& t1, std::vector<PlanarArc>& out) {
  const Vec2 v = p1 - p0;
  const Vec2 t = t0 + t1;
  const double a = 2 * (1 - t0.dot(t1));
  const double vt = v.dot(t);
  // a d^2 + 2 (v.t) d - v.v = 0, the positive root written without cancellation
  const double denom = vt + std::sqrt(vt * vt + a * v.squaredNorm());
  if (!(denom > 0)) return false;
  const double d = v.squaredNorm() / denom;
  const Vec2 joint = 0.5 * ((p0 + d * t0) + (p1 - d * t1));
  const std::optional<PlanarArc> first = arc_leaving(p0, t0, joint);
  const std::optional<PlanarArc> second = arc_arriving(joint, p1, t1);
  if (!first || !second) return false;
  out.push_back(*first);
  out.push_back(*second);
  return true;
}

// Golden-section search for the minimum of f on [lo, hi] (f unimodal there); its value.
template <class F>
double golden_minimum(F f, double lo, double hi) {
  const double g = (std::sqrt(5.0) - 1) / 2;
  double a = hi - g * (hi - lo);
  double b = lo + g * (hi - lo);
  double fa = f(a);
  double fb = f(b);
  for (int i = 0; i < 60; ++i) {
    if (fa < fb) {
      hi = b;
      b = a;
      fb = fa;
      a = hi - g * (hi - lo);
      fa = f(a);
    } else {
      lo = a;
      a = b;
      fa = fb;
      b = lo + g * (hi - lo);
      fb = f(b);
    }
  }
  return std::min({fa, fb, f(lo), f(hi)});
}

// The distance from the points of `arcs` to the spiral, both ways (an upper bound on their
// Hausdorff distance, up to the sampling). First the cheap bound: each point of the chain
// against the spiral's point at the same angle about its centre (the chain's angle goes from 0
// to the sweep continuously, so every spiral point has a chain point at its angle, and the
// bound holds both ways). Where that exceeds `tolerance`, the nearest points themselves (a
// steep helix is far from the spiral at the same angle, yet close to it): each chain point's
// nearest spiral point near its angle, and each spiral point's nearest point on the arcs that
// reach its angle.
double chain_deviation(const std::vector<Arc>& arcs, const Spiral& s, double tolerance) {
  struct Sample {
    Vec3 q;
    double phi;
  };
  std::vector<Sample> samples;
  samples.reserve(arcs.size() * kSpiralSamplesPerArc);
  std::vector<double> arc_end_phi;  // the angle each arc ends at
  double phi = 0;
  double cheap = 0;
  for (const Arc& arc : arcs) {
    const double len = length(arc);
    for (int k = 1; k <= kSpiralSamplesPerArc; ++k) {
      const Vec3 q = point(arc, len * k / kSpiralSamplesPerArc);
      const Vec3 rel = q - s.center;
      double a = std::atan2(rel.dot(s.v), rel.dot(s.u));
      a += kTwoPi * std::round((phi - a) / kTwoPi);
      phi = a;
      samples.push_back({q, a});
      cheap = std::max(cheap, (q - spiral_point(s, std::clamp(a, 0.0, s.sweep))).norm());
    }
    arc_end_phi.push_back(phi);
  }
  if (cheap <= tolerance) return cheap;
  // nearest points: the nearest spiral point to a chain point lies within 2 cheap of the
  // same-angle one, so within 2 cheap / min |dp/dphi| in the angle (|dp/dphi| >= min radius)
  const double window = 2 * cheap / std::min(s.r0, s.r1) + 1e-12;
  double worst = 0;
  for (const Sample& p : samples) {
    const double lo = std::clamp(p.phi - window, 0.0, s.sweep);
    const double hi = std::clamp(p.phi + window, 0.0, s.sweep);
    worst = std::max(worst, golden_minimum([&](double a) { return (spiral_point(s, a) - p.q).norm(); }, lo, hi));
  }
  const int spiral_samples = static_cast<int>(samples.size());
  for (int k = 0; k <= spiral_samples; ++k) {
    const double a = s.sweep * k / spiral_samples;
    const Vec3 p = spiral_point(s, a);
    const auto hit = std::lower_bound(arc_end_phi.begin(), arc_end_phi.end(), a);
    const std::size_t at = std::min<std::size_t>(static_cast<std::size_t>(hit - arc_end_phi.begin()), arcs.size() - 1);
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t j = at == 0 ? 0 : at - 1; j <= std::min(at + 1, arcs.size() - 1); ++j) {
      const Arc& arc = arcs[j];
      nearest = std::min(nearest, golden_minimum([&](double t) { return (point(arc, t) - p).norm(); }, 0.0, length(arc)));
    }
    worst = std::max(worst, nearest);
  }
  return worst;
}

// The circle through the spiral's end points centred on their bisector nearest its centre, as
// one arc with the spiral's full turns; nullopt when the end points coincide in the plane.
std::optional<Arc> bisector_circle(const Spiral& s) {
  const Vec3 w = s.u.cross(s.v);
  const Vec3 p0 = spiral_point(s, 0);
  const Vec3 p1 = spiral_point(s, s.sweep);
  Vec3 chord = p1 - p0;
  chord -= w * chord.dot(w);
  if (!(chord.norm() > 1e-12 * std::max(s.r0, s.r1))) return std::nullopt;
  const Vec3 dir = chord.normalized();
  const Vec3 mid = p0 + 0.5 * chord;
  const Vec3 center = s.center - dir * (s.center - mid).dot(dir);
  // the full turns the spiral makes beyond the first (its angle to the end point, mod 2 pi)
  const double base = std::fmod(s.sweep, kTwoPi);
  const int turns = static_cast<int>(std::lround((s.sweep - (base > 0 ? base : kTwoPi)) / kTwoPi));
  const ArcBuild built = arc_from_center(p0, p1, center, w, true, std::max(0, turns), 1e-9 * std::max(s.r0, s.r1));
  if (!built.outcome.ok()) return std::nullopt;
  return built.arc;
}

// The chain of `n` biarcs between points of the spiral at equal angles, rising at one slope;
// empty when a biarc does not exist.
std::vector<Arc> biarc_chain(const Spiral& s, int n) {
  const Vec3 w = s.u.cross(s.v);
  const double dr = (s.r1 - s.r0) / s.sweep;
  const auto knot = [&](int k, Vec2& p, Vec2& t) {
    const double phi = s.sweep * k / n;
    const double r = spiral_radius(s, phi);
    const Vec2 radial(std::cos(phi), std::sin(phi));
    p = r * radial;
    t = (dr * radial + r * left_of(radial)).normalized();
  };
  std::vector<PlanarArc> planar;
  planar.reserve(2 * static_cast<std::size_t>(n));
  Vec2 p0;
  Vec2 t0;
  knot(0, p0, t0);
  for (int k = 1; k <= n; ++k) {
    Vec2 p1;
    Vec2 t1;
    knot(k, p1, t1);
    if (!add_biarc(p0, t0, p1, t1, planar)) return {};
    p0 = p1;
    t0 = t1;
  }
  double total = 0;
  for (const PlanarArc& a : planar) total += std::abs(a.rho) * a.sweep;
  const double slope = s.rise / total;
  std::vector<Arc> arcs;
  arcs.reserve(planar.size());
  double height = 0;
  for (const PlanarArc& a : planar) {
    const double rise = slope * std::abs(a.rho) * a.sweep;
    const Vec3 w_arc = a.rho > 0 ? w : Vec3(-w);
    Arc arc;
    arc.center = s.center + a.center.x() * s.u + a.center.y() * s.v + height * w;
    const Vec3 start = s.center + a.start.x() * s.u + a.start.y() * s.v + height * w;
    arc.radius = std::abs(a.rho);
    arc.u = (start - arc.center) / arc.radius;
    arc.v = w_arc.cross(arc.u);
    arc.sweep = a.sweep;
    arc.rise = a.rho > 0 ? rise : -rise;
    arcs.push_back(arc);
    height += rise;
  }
  return arcs;
}

}  // namespace

Vec3 spiral_point(const Spiral& spiral, double phi) {
  const double r = spiral_radius(spiral, phi);
  return spiral.center + r * (std::cos(phi) * spiral.u + std::sin(phi) * spiral.v) +
         spiral.rise * phi / spiral.sweep * spiral.u.cross(spiral.v);
}

Vec3 spiral_tangent(const Spiral& spiral, double phi) {
  const double r = spiral_radius(spiral, phi);
  const double dr = (spiral.r1 - spiral.r0) / spiral.sweep;
  const Vec3 radial = std::cos(phi) * spiral.u + std::sin(phi) * spiral.v;
  const Vec3 along = -std::sin(phi) * spiral.u + std::cos(phi) * spiral.v;
  return (dr * radial + r * along + spiral.rise / spiral.sweep * spiral.u.cross(spiral.v)).normalized();
}

SpiralArcs arcs_along_spiral(const Spiral& spiral, double tolerance, int max_arcs) {
  SpiralArcs out;
  const bool sane = std::isfinite(spiral.r0) && std::isfinite(spiral.r1) && std::isfinite(spiral.sweep) &&
                    std::isfinite(spiral.rise) && spiral.r0 > 0 && spiral.r1 > 0 && spiral.sweep > 0 && tolerance > 0 &&
                    spiral.center.allFinite() && spiral.u.allFinite() && spiral.v.allFinite();
  if (!sane) {
    out.outcome = {Status::kInfeasible, "a spiral needs positive radii, sweep and tolerance"};
    return out;
  }
  // one arc where the circle through both ends stays close (a rounded end point)
  double best = std::numeric_limits<double>::infinity();
  if (const std::optional<Arc> circle = bisector_circle(spiral)) {
    const std::vector<Arc> one = {*circle};
    // a planar circle whose centre moved by d from the spiral's: at every angle about the
    // spiral's centre its radius is within d of its own, which is within d of r0, which is
    // within |r1 - r0| of the spiral's, so 2 d + |r1 - r0| bounds the same-angle distance without
    // sampling (rounded end points, most arcs of CAM programs); with the spiral's centre inside
    // the circle its angle about that centre runs monotonically over the sweep, so the bound
    // holds both ways
    if (spiral.rise == 0) {
      const double shift = (circle->center - spiral.center).norm();
      const double bound = 2 * shift + std::abs(spiral.r1 - spiral.r0);
      if (bound <= tolerance && shift < 0.5 * circle->radius) {
        out.arcs = one;
        out.deviation = bound;
        return out;
      }
    }
    const double deviation = chain_deviation(one, spiral, tolerance);
    if (deviation <= tolerance) {
      out.arcs = one;
      out.deviation = deviation;
      return out;
    }
    best = deviation;
  }
  // biarcs, at least one per quarter turn, twice as many until close enough; the error of
  // biarcs falls about eightfold per doubling, so one that no longer halves has met the floor a
  // helix's single slope sets, and more arcs would not help
  double previous = std::numeric_limits<double>::infinity();
  for (int n = std::max(1, static_cast<int>(std::ceil(spiral.sweep / (0.5 * std::numbers::pi)))); 2 * n <= max_arcs; n *= 2) {
    std::vector<Arc> chain = biarc_chain(spiral, n);
    if (chain.empty()) continue;
    const double deviation = chain_deviation(chain, spiral, tolerance);
    best = std::min(best, deviation);
    if (deviation <= tolerance) {
      out.arcs = std::move(chain);
      out.deviation = deviation;
      return out;
    }
    if (deviation > 0.5 * previous) break;
    previous = deviation;
  }
  out.deviation = best;
  out.outcome = {Status::kInfeasible, "no chain of at most " + std::to_string(max_arcs) + " tangent arcs stays within " +
                                          format_mm(tolerance) + " of the spiral (closest: " + format_mm(best) +
                                          (spiral.rise != 0 ? "; tangent helical arcs rise at one slope, the spiral linearly in the angle)" : ")")};
  return out;
}

ArcBuild arc_from_center(const Vec3& start, const Vec3& end, const Vec3& center, const Vec3& normal, bool ccw,
                         int turns, double radius_tolerance) {
  const double nn = normal.norm();
  if (!(nn > 0)) return failure("the arc's plane normal is zero");
  // axis w: motion is counter-clockwise about w
  const Vec3 w = (ccw ? 1.0 : -1.0) * normal / nn;
  // centre projected into the start's plane; in-plane offsets of start and end
  Vec3 c = center + w * (start - center).dot(w);
  double rise = (end - start).dot(w);
  const Vec3 end_in_plane = end - w * rise;
  const double r_start = (start - c).norm();
  if (std::abs(rise) <= kRiseRounding * r_start) rise = 0;
  const double r_end = (end_in_plane - c).norm();
  if (!(r_start > radius_tolerance)) return failure("the arc's start point lies on its centre");
  if (std::abs(r_start - r_end) > radius_tolerance) {
    return failure("the radius to the end (" + format_mm(r_end) + ") differs from the radius to the start (" +
                   format_mm(r_start) + ")");
  }
  // move the centre onto the chord's perpendicular bisector so both radii are equal; a chord
  // at rounding level (a full circle) has no usable direction and needs no correction
  const Vec3 chord = end_in_plane - start;
  if (chord.norm() > 1e-9 * r_start) {
    const Vec3 dir = chord.normalized();
    c -= dir * (c - (start + 0.5 * chord)).dot(dir);
  }
  const Vec3 rs = start - c;
  const Vec3 re = end_in_plane - c;
  const double r = rs.norm();
  Arc arc;
  arc.center = c;
  arc.radius = r;
  arc.u = rs / r;
  arc.v = w.cross(arc.u);
  // sweep: angle from start to end about w in (0, 2 pi], a full circle when they coincide
  double sweep = std::atan2(re.dot(arc.v), re.dot(arc.u));
  if (sweep <= 0) sweep += kTwoPi;
  if (sweep < 1e-12 && re.dot(arc.u) > 0) sweep = kTwoPi;
  arc.sweep = sweep + kTwoPi * turns;
  arc.rise = rise;
  return {{}, arc};
}

ArcBuild arc_from_radius(const Vec3& start, const Vec3& end, double radius, const Vec3& normal, bool ccw,
                         double radius_tolerance) {
  const double nn = normal.norm();
  if (!(nn > 0)) return failure("the arc's plane normal is zero");
  if (!(std::abs(radius) > 0)) return failure("the arc radius is zero");
  const Vec3 w = (ccw ? 1.0 : -1.0) * normal / nn;
  const double rise = (end - start).dot(w);
  const Vec3 chord = end - w * rise - start;
  const double d = chord.norm();
  const double r = std::abs(radius);
  if (!(d > 0)) return failure("an arc given by its radius needs an end point distinct from its start");
  if (d > 2 * r + radius_tolerance) {
    return failure("the radius " + format_mm(r) + " is too small for the chord " + format_mm(d));
  }
  // centre on the perpendicular bisector of the chord, on the left of the motion (ccw about w)
  // for the short arc and on the right for the long one
  const double h = std::sqrt(std::max(0.0, r * r - 0.25 * d * d));
  const Vec3 left = w.cross(chord / d);
  const Vec3 mid = start + 0.5 * chord;
  const Vec3 center = mid + (radius > 0 ? h : -h) * left;
  // the radii agree by construction; allow for rounding
  return arc_from_center(start, end, center, w, true, 0, std::max(radius_tolerance, 1e-12 * r));
}

ArcBuild arc_through(const Vec3& start, const Vec3& via, const Vec3& end) {
  const Vec3 a = via - start;
  const Vec3 b = end - start;
  const Vec3 n = a.cross(b);
  const double scale = std::max({a.norm(), b.norm(), 1e-300});
  if (!(n.norm() > 1e-12 * scale * scale)) {
    return failure("the start, via and end points of the arc are collinear or coincide");
  }
  // circumcentre of the triangle (start, via, end)
  const Vec3 center = start + (b.squaredNorm() * n.cross(a) + a.squaredNorm() * b.cross(n)) / (2 * n.squaredNorm());
  // n = a x b orients the travel start -> via -> end counter-clockwise about n
  return arc_from_center(start, end, center, n, true, 0, 1e-9 * scale);
}

}  // namespace blendbench
