// The `arc` transition method (seed 001 line-to-line, seed 003 arc-to-arc): a circular arc tangent to
// both moves, placed by the corner distance d.
//
// Rules (derived here; seed 001 (controller manual, line-to-line) and seed 003 (controller manual,
// arc-to-arc) state them in words only):
// - line-line (seed 001): both lines are shortened by d and the fillet arc tangent to both joins them;
//   its radius is d / tan(theta / 2) for a tangent turn theta at the corner.
// - with an arc (seed 003): the move with the larger radius (a line counts as infinite radius; equal
//   radii: the incoming move, as seed 003 says for tangent arcs) is shortened by (arc length) d. At
//   that point T1 the transition circle is tangent to it, so its centre is O = T1 + rho n1 (n1 the
//   left normal at T1 in the corner plane, rho the signed radius, positive = counter-clockwise
//   about the plane normal). Tangency to the other move decides rho:
//     other is a circle (centre Q, signed radius r): two oriented circles touch with the same
//       direction of travel iff |O - Q| = |rho - r|. With w = T1 - Q this is
//       |w + rho n1|^2 = (rho - r)^2, linear in rho:  rho = (r^2 - |w|^2) / (2 (n1.w + r)),
//       and the tangency point is T2 = Q - r n2 with n2 = (O - Q) / (rho - r).
//     other is a line (through C, left normal ns): the centre's signed distance to the line is rho:
//       (T1 - C).ns + rho n1.ns = rho  ->  rho = (T1 - C).ns / (1 - n1.ns),  T2 = O - rho ns.
//   The other move is trimmed to T2. rho = 0 (T1 lies on the other curve) is seed 003's intersection
//   case (zero-length transition); 1/rho = 0 is its line-segment case. solve_planar evaluates
//   these in rearranged forms that keep their digits near tangency and for nearly equal circles.
// - a candidate is accepted when T2 lies on the part of the other move the blender allows
//   (`*_available`), the transition adds no loop (its signed turning equals that of the
//   programmed path it replaces, or it is a short arc, |turn| <= pi, that cuts a loop off where
//   the arcs cross twice) and makes no detour (at most 4 times the length it replaces).
// - when no circle exists for the requested d (tangency behind the corner, a loop, a detour, or a
//   circle so near the other move's circle that where it touches it is ill-conditioned), the
//   rule is applied with the roles swapped (the smaller-radius move shortened by d; fallback
//   "smaller_radius_shortened"; this keeps near-tangent corners blended with the full d); when
//   that fails too, or T2 lies beyond the available part, d is shrunk (bisection on the seed 003 rule)
//   and the note says so; when no d >= 1 um works, the corner is infeasible.
// - tangent corners (G1 already, only a curvature jump): the larger-radius move is shortened by
//   d and that piece becomes the transition (seed 003's rule for tangent arcs in opposite directions,
//   used for every tangent corner; it is also the limit of the general construction there).
// - a 180-degree corner between a line and an arc or two arcs on different circles: the moves
//   part at once (nothing overlaps as in seed 001's line reversal), so the general construction
//   applies; it gives a small U-turn arc, the limit of the near-180-degree transitions.
// - non-planar corners (line and arc, or two arcs, not in one plane; helices): no circle is
//   tangent to both in general. Both moves are shortened by d and joined by a G1 biarc (two
//   circular arcs in different planes, equal tangent lengths; fallback "biarc").
// A transition circle turning less than 1e-6 rad is emitted as a Clothoid with zero sharpness
// (the same circle, evaluated from its start instead of a centre a million lengths away).

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string_view>
#include <utility>

#include "blendbench/core/format.hpp"
#include "blendbench/corner/corner.hpp"

namespace blendbench {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2 * std::numbers::pi;

// rad: a corner whose tangent turns by less than this is G1 (collinear / tangent); reversals
// and near reversals by the shared thresholds (corner.hpp)
constexpr double kStraightAngle = 1e-10;
// rad: line and arc (or two arc planes) within this angle count as coplanar
constexpr double kPlanarAngle = 1e-10;
// relative to the radius: two arcs on the same circle
constexpr double kSameCircle = 1e-12;
// rad: a transition turning less than this is a straight line (seed 003 line-segment case)
constexpr double kLineTurn = 1e-12;
// rad: below this turn a transition circle is emitted as a zero-sharpness clothoid (the same
// circle, evaluated from its start point instead of a centre more than 1e6 lengths away)
constexpr double kArcMinTurn = 1e-6;
// relative to d: a transition radius below this is seed 003's zero-length intersection transition
constexpr double kIntersection = 1e-12;
// rad: transition turning equal to the replaced path's turning
constexpr double kTurnTol = 1e-6;
// a transition longer than this many times the path it replaces is a detour, not a transition
constexpr double kMaxDetour = 4.0;
// relative: a transition circle whose radius is within this fraction of the other circle's is
// refused. It runs within that fraction of the radius of the other circle all the way, so its
// point of tangency, where the two circles touch, is fixed by differences of that size between
// inputs of full size: at 6e-10 (a near-tangent corner, theta = 8e-5 rad, whose corner distance
// fell where the second intersection of the two circles makes T1 nearly tangent to the other
// circle) it lay 4.4 rad round the circle and the arc built on it missed T1 by 3e-9 of its
// length. The rule with the roles swapped (or a shorter d) then applies.
constexpr double kCoincidentCircle = 1e-6;
// m: the smallest corner distance the shrink search tries (1 um, far below robot resolution)
constexpr double kMinShrink = 1e-6;
constexpr int kBisections = 60;

// The corner as the fitting functions see it.
struct Corner {
  const Primitive* in = nullptr;
  const Primitive* out = nullptr;
  double len_in = 0;
  double len_out = 0;
  double avail_in = 0;
  double avail_out = 0;
  Vec3 c;       // corner point (end of in)
  Vec3 t_in;    // unit tangent of in at the corner
  Vec3 t_out;   // unit tangent of out at the corner
  double theta = 0;  // rad, unsigned turn of the tangent at the corner, [0, pi]
  bool buffered = false;
};

// A move near the corner as a curve of the corner plane: `t` is its unit tangent at the corner.
// A line: `p` is its end at the corner. A circle: `arc` is the move itself, `p` its centre,
// `rho` its signed radius (positive: counter-clockwise about the plane normal). `kappa` = 1 / rho,
// 0 on a line.
struct PlaneCurve {
  bool line = true;
  const Arc* arc = nullptr;
  Vec3 p;
  Vec3 t;
  double rho = 0;
  double kappa = 0;
};

struct Plane {
  Vec3 n;  // unit normal of the corner plane
  PlaneCurve in;
  PlaneCurve out;
  double delta = 0;  // rad, signed tangent turn at the corner about n, (-pi, pi]
};

enum class Verdict { kValid, kTooLong, kNoCircle };

struct Candidate {
  Verdict verdict = Verdict::kNoCircle;
  double trim_in = 0;
  double trim_out = 0;
  std::vector<Segment> transition;
  CornerCase corner_case = CornerCase::kRegular;
  bool kink = false;  // zero-length transition at a tangent discontinuity
  std::string why;    // why the candidate was rejected
};

// The component of `v` in the plane of unit normal `n`, normalised.
Vec3 in_plane(const Vec3& v, const Vec3& n) { return (v - n * n.dot(v)).normalized(); }

// Signed angle (rad) from a to b about the unit axis n, in (-pi, pi].
double signed_angle(const Vec3& a, const Vec3& b, const Vec3& n) { return std::atan2(n.dot(a.cross(b)), a.dot(b)); }

// A circular piece leaving p with unit tangent t, turning by `turn` >= 0 rad towards the unit
// normal m (perpendicular to t) over the length `len` (m), ending at `end`. A turn below
// kLineTurn is the straight line p -> end; below kArcMinTurn the circle is a Clothoid with zero
// sharpness (no far-away centre to lose digits); otherwise an Arc.
Segment circular_piece(const Vec3& p, const Vec3& t, const Vec3& m, double turn, double len, const Vec3& end) {
  if (turn <= kLineTurn) return Line{p, end};
  if (turn < kArcMinTurn) return Clothoid{p, t, m, turn / len, 0.0, len};
  const double radius = len / turn;
  return Arc{p + radius * m, -m, t, radius, turn, 0.0};
}

// Length of a circular piece of signed turn tau and curvature kappa with chord length `chord`:
// from the chord for small turns (stable as the radius grows without bound), else |tau|/|kappa|.
double piece_length(double tau, double kappa, double chord) {
  const double half = 0.5 * std::abs(tau);
  if (half < 0.25) return half < 1e-8 ? chord : chord * half / std::sin(half);
  return std::abs(tau) / std::abs(kappa);
}

// p - centre of a planar arc at arc length s, without the rounding of the absolute centre.
Vec3 radial(const Arc& arc, double s) {
  const double phi = s / arc.radius;
  return arc.radius * (std::cos(phi) * arc.u + std::sin(phi) * arc.v);
}

// point(arc, s_b) - point(arc, s_a) on a planar arc, from half angles (no cancellation when the
// two points are close on a large circle).
Vec3 arc_chord(const Arc& arc, double s_a, double s_b) {
  const double mid = 0.5 * (s_a + s_b) / arc.radius;
  const double half = 0.5 * (s_b - s_a) / arc.radius;
  return 2 * arc.radius * std::sin(half) * (-std::sin(mid) * arc.u + std::cos(mid) * arc.v);
}

// Arc length between the corner and a point on a circle move, given by its offset `rel` from
// the centre: from the point to the corner on the incoming move, from the corner to the point on
// the outgoing one; the occurrence nearest the corner, and a point a rounding error behind the
// corner counts as the corner.
double trim_on_arc(const Arc& arc, bool incoming, const Vec3& rel) {
  double phi = std::atan2(rel.dot(arc.v), rel.dot(arc.u));
  if (phi < 0) phi += kTwoPi;
  double psi = incoming ? std::fmod(arc.sweep - phi, kTwoPi) : phi;
  if (psi < 0) psi += kTwoPi;
  if (kTwoPi - psi <= 1e-14) psi = 0;
  return arc.radius * psi;
}

PlaneCurve plane_curve(const Primitive& move, const Vec3& n, const Vec3& c, const Vec3& t) {
  PlaneCurve pc;
  if (const Arc* arc = std::get_if<Arc>(&move)) {
    pc.line = false;
    pc.arc = arc;
    pc.p = arc->center;
    pc.rho = arc->u.cross(arc->v).dot(n) > 0 ? arc->radius : -arc->radius;
    pc.kappa = 1.0 / pc.rho;
  } else {
    pc.p = c;
  }
  pc.t = t;
  return pc;
}

// seed 003 with an arc in the corner plane: the move `fixed_in ? in : out` is shortened by d, the
// transition circle is tangent to it there (T1) and to the other move (T2), see the file
// comment. The formulas are rearranged so that their small terms are formed directly (the
// inputs of an ill-conditioned corner are themselves small differences). With n1 the left
// normal at T1, e1 = T1 - C, n_o the other circle's left normal at C (so C - centre_o =
// -rho_o n_o), w = T1 - centre_o = e1 - rho_o n_o and q = w + rho_o n1 = e1 + rho_o (n1 - n_o):
//   num = 2 (n1.w + rho_o) = 2 n1.q = 2 n1.e1 + rho_o |n1 - n_o|^2,   den = rho_o^2 - |w|^2 = 2 rho_o n_o.e1 - |e1|^2,
//   rho - rho_o = -|q|^2 / num,  O - centre_o = q + (rho - rho_o) n1,
//   n2 = (O - centre_o) / (rho - rho_o) ~ |q|^2 n1 - num q        (the transition curvature is num / den).
// For two circles with nearly coincident centres (Delta = centre_f - centre_o, exact in floating
// point, e = rho_o - rho_f, T1 = centre_f - rho_f n1) the same quantities read
//   num = 2 (n1.Delta + e),  den = e (rho_o + rho_f) + 2 rho_f n1.Delta - |Delta|^2,
//   n2 ~ -(num Delta + (e^2 - |Delta|^2) n1).
Candidate solve_planar(const Corner& k, const Plane& pl, bool fixed_in, double d) {
  Candidate cand;
  const Vec3& n = pl.n;
  const PlaneCurve& fc = fixed_in ? pl.in : pl.out;
  const PlaneCurve& oc = fixed_in ? pl.out : pl.in;
  const double avail_other = fixed_in ? k.avail_out : k.avail_in;

  // the fixed tangency point T1, its left normal n1, e1 = T1 - C and n1.e1 (on a circle the
  // chord from T1 to C bends towards the centre by rho (1 - cos(d / |rho|)))
  const double s1 = fixed_in ? k.len_in - d : d;
  Vec3 e1;
  Vec3 n1;
  double n1e1 = 0;
  if (fc.line) {
    e1 = (fixed_in ? -d : d) * fc.t;
    n1 = n.cross(fc.t).normalized();
  } else {
    e1 = fixed_in ? arc_chord(*fc.arc, k.len_in, s1) : arc_chord(*fc.arc, 0.0, s1);
    const Vec3 rel1 = radial(*fc.arc, s1);
    n1 = (fc.rho > 0 ? -rel1 : rel1).normalized();
    const double half = std::sin(0.5 * d / std::abs(fc.rho));
    n1e1 = -2 * fc.rho * half * half;
  }
  const Vec3 t1 = n1.cross(n);

  // the transition curvature kappa and T2 - T1 (chord); rel2 = T2 - reference of the other curve
  double kappa = 0;
  bool zero_length = false;
  Vec3 chord = Vec3::Zero();
  Vec3 rel2 = Vec3::Zero();
  Vec3 t2 = t1;
  if (!oc.line) {
    const Vec3 n_o = n.cross(oc.t).normalized();
    Vec3 w = e1 - oc.rho * n_o;
    Vec3 delta = fc.p - oc.p;
    delta -= n * n.dot(delta);
    double num = 0;
    double den = 0;
    Vec3 n2_dir;
    if (!fc.line && delta.norm() < w.norm()) {
      const double e = oc.rho - fc.rho;
      const double nd = n1.dot(delta);
      w = delta - fc.rho * n1;
      num = 2 * (nd + e);
      den = e * (oc.rho + fc.rho) + 2 * fc.rho * nd - delta.squaredNorm();
      n2_dir = -(num * delta + (e * e - delta.squaredNorm()) * n1);
    } else {
      // n1.(n1 - n_o) = |n1 - n_o|^2 / 2 for unit vectors: second order, so formed as a square
      const Vec3 q = e1 + oc.rho * (n1 - n_o);
      num = 2 * n1e1 + oc.rho * (n1 - n_o).squaredNorm();
      den = 2 * oc.rho * n_o.dot(e1) - e1.squaredNorm();
      n2_dir = q.squaredNorm() * n1 - num * q;
    }
    if (std::abs(den) <= kIntersection * d * std::abs(num)) {
      zero_length = true;
      rel2 = w;
    } else {
      const double g_norm = n2_dir.norm();
      if (!(g_norm > 0)) {
        cand.why = "the transition circle coincides with the other arc";
        return cand;
      }
      kappa = num / den;
      if (std::abs(kappa * oc.rho - 1) <= kCoincidentCircle) {
        cand.why = "the transition circle nearly coincides with the other arc (where it touches it is ill-conditioned)";
        return cand;
      }
      const Vec3 n2 = n2_dir / g_norm;
      rel2 = -oc.rho * n2;
      chord = rel2 - w;
      t2 = n2.cross(n);
    }
  } else {
    // the other move is a line through C with left normal ns
    const Vec3 ns = n.cross(oc.t).normalized();
    const double h = e1.dot(ns);
    const double cc = 0.5 * (n1 - ns).squaredNorm();  // 1 - n1.ns without cancellation
    if (std::abs(h) <= kIntersection * d * cc) {
      zero_length = true;
      rel2 = e1;
    } else if (cc <= 1e-300) {
      cand.why = "the transition would run parallel to the line";
      return cand;
    } else {
      kappa = cc / h;
      chord = (h / cc) * (n1 - ns);
      rel2 = e1 + chord;
      t2 = oc.t;
    }
  }

  // where T2 lies on the other move
  const bool other_in = !fixed_in;
  const double s2 = oc.line ? (other_in ? -rel2.dot(oc.t) : rel2.dot(oc.t)) : trim_on_arc(*oc.arc, other_in, rel2);
  const double tol = 1e-12 * (avail_other + d);
  if (!(s2 >= -tol)) {
    cand.why = "the tangency point lies before the corner";
    return cand;
  }
  if (s2 > avail_other + tol && !oc.line && s2 > kPi * std::abs(oc.rho)) {
    // more than half a turn ahead and off the move: the tangency is behind the corner
    cand.why = "the tangency point lies behind the corner";
    return cand;
  }
  if (s2 > avail_other + tol) {
    cand.verdict = Verdict::kTooLong;
    cand.why = "the tangency point lies beyond the available part of the other move";
    return cand;
  }
  const double s2c = std::clamp(s2, 0.0, avail_other);
  cand.trim_in = fixed_in ? d : s2c;
  cand.trim_out = fixed_in ? s2c : d;
  if (zero_length) {
    cand.verdict = Verdict::kValid;
    cand.corner_case = CornerCase::kIntersection;
    cand.kink = true;
    return cand;
  }

  // signed turning of the transition, start and end in the direction of travel
  const Vec3 ps = point(*k.in, k.len_in - cand.trim_in);
  const Vec3& ts = fixed_in ? t1 : t2;
  const Vec3& te = fixed_in ? t2 : t1;
  const Vec3 chord_se = fixed_in ? chord : Vec3(-chord);
  const double phi = signed_angle(ts, te, n);
  double tau = phi;
  if (std::abs(phi) < 0.5) {
    // near-straight: a forward chord means the short turn, a backward one a full loop
    if (chord_se.dot(ts) < 0) tau = phi + (kappa >= 0 ? kTwoPi : -kTwoPi);
  } else if (kappa > 0 && phi < 0) {
    tau = phi + kTwoPi;
  } else if (kappa < 0 && phi > 0) {
    tau = phi - kTwoPi;
  }
  const double len = piece_length(tau, kappa, chord_se.norm());
  if (!std::isfinite(len) || !std::isfinite(tau)) {
    cand.why = "the transition circle degenerates";
    return cand;
  }

  // no loop added: same turning as the replaced path, or a short arc cutting a loop off
  const double tau_prog = pl.in.kappa * cand.trim_in + pl.delta + pl.out.kappa * cand.trim_out;
  if (std::abs(tau - tau_prog) > kTurnTol && std::abs(tau) > kPi + kTurnTol) {
    cand.why = "the tangent circle would add a loop";
    return cand;
  }
  // no detour: a near-closed circle of huge radius is tangent to both but is no corner transition
  if (len > kMaxDetour * (cand.trim_in + cand.trim_out)) {
    cand.why = "the tangent circle would make a detour";
    return cand;
  }

  const Vec3 m = tau >= 0 ? n.cross(ts) : Vec3(-n.cross(ts));
  cand.transition.push_back(circular_piece(ps, ts, m.normalized(), std::abs(tau), len, ps + chord_se));
  cand.corner_case = std::abs(tau) <= kLineTurn ? CornerCase::kLineSegment : CornerCase::kRegular;
  cand.verdict = Verdict::kValid;
  return cand;
}

// The circular arc whose tangent lines at both ends meet at p + a t, at distance a > 0 from
// both ends: it leaves p with unit tangent t and ends with unit tangent t_end (turn below pi), at
// p + a t + a t_end. Built from the two tangents so both are exact; a turn of phi has radius
// a / tan(phi / 2).
Segment tangent_arc(const Vec3& p, const Vec3& t, const Vec3& t_end, double a) {
  const double phi = angle_between(t, t_end);
  const Vec3 end = p + a * t + a * t_end;
  if (phi <= kLineTurn) return Line{p, end};
  const Vec3 m = (t_end - t_end.dot(t) * t).normalized();
  const double half = 0.5 * phi;
  const double len = half < 1e-8 ? 2 * a : 2 * a * half * std::cos(half) / std::sin(half);
  return circular_piece(p, t, m, phi, len, end);
}

CornerFit kink_fit(const Corner& k, CornerCase corner_case, double trim_in, double trim_out) {
  CornerFit fit;
  fit.corner_case = corner_case;
  fit.trim_in = trim_in;
  fit.trim_out = trim_out;
  fit.parameter_used = std::max(trim_in, trim_out);
  fit.stop = k.buffered;
  return fit;
}

// "corner distance shrunk from <requested> to <used>: <why>", formatted when the report is read
// (the one note whose reason is made at run time, a rejected candidate's, is built at once from
// the same words)
constexpr char kShrunkFrom[] = "corner distance shrunk from ";
Note shrink_note(double requested, double used, Note::Literal why) {
  return Note::lengths(kShrunkFrom, requested, " to ", used, why);
}

// seed 001: two lines.
CornerFit fit_line_line(const Corner& k, double d_req) {
  const double d = std::min({d_req, k.avail_in, k.avail_out});
  const Note note = d < d_req ? shrink_note(d_req, d, "a move is short") : Note();
  const Vec3 p1 = point(*k.in, k.len_in - d);
  const Vec3 p2 = point(*k.out, d);
  CornerFit fit;
  fit.trim_in = d;
  fit.trim_out = d;
  fit.parameter_used = d;
  fit.note = note;

  // 0 degrees (seed 001 fig. 7-4): path unchanged, a linear transition move of length 2d
  if (k.theta <= kStraightAngle) {
    fit.corner_case = CornerCase::kCollinear;
    if (d > 0) fit.transition.push_back(Line{p1, p2});
    return fit;
  }
  // 180 degrees (seed 001 fig. 7-3): both shortened by d, meeting at the same point; the kink stays
  if (k.theta >= kPi - kReversalAngle) {
    CornerFit kink = kink_fit(k, CornerCase::kReversal, d, d);
    kink.note = note;
    return kink;
  }
  // zero distance (seed 001 fig. 7-5): nothing inserted, only blending is affected
  if (d <= 0) {
    CornerFit kink = kink_fit(k, CornerCase::kZeroDistance, 0, 0);
    kink.note = note;
    return kink;
  }
  // n degrees (seed 001 fig. 7-2): the fillet of radius d / tan(theta / 2), turning by theta
  const Vec3 b = k.t_in.cross(k.t_out);
  const double s = b.norm();
  const double c = k.t_in.dot(k.t_out);
  const Vec3 m = b.cross(k.t_in).normalized();
  const double radius = c >= 0 ? d * (1 + c) / s : d * s / (1 - c);
  fit.transition.push_back(circular_piece(p1, k.t_in, m, k.theta, radius * k.theta, p2));
  return fit;
}

// Non-planar corners: both moves shortened by d and joined by a biarc with equal tangent
// lengths a: Q0 = T1 + a t1, Q1 = T2 - a t2, |Q1 - Q0| = 2a, the junction the midpoint of Q0 Q1.
// With v = T2 - T1 the condition is 2 (t1.t2 - 1) a^2 - 2 v.(t1 + t2) a + |v|^2 = 0, whose
// positive root exists whenever t1 != t2 (the product of the roots is negative).
CornerFit fit_biarc(const Corner& k, double d_req) {
  const double d = std::min({d_req, k.avail_in, k.avail_out});
  CornerFit fit;
  fit.corner_case = CornerCase::kNonPlanar;
  fit.fallback = Fallback::kBiarc;
  fit.trim_in = d;
  fit.trim_out = d;
  fit.parameter_used = d;
  fit.note = "non-planar corner: both moves shortened by " + format_mm(d) + " and joined by two circular arcs";
  if (d < d_req) fit.note += "; " + shrink_note(d_req, d, "a move is short").text();
  const Vec3 p1 = point(*k.in, k.len_in - d);
  const Vec3 t1 = tangent(*k.in, k.len_in - d);
  const Vec3 p2 = point(*k.out, d);
  const Vec3 t2 = tangent(*k.out, d);
  const Vec3 v = p2 - p1;
  const double qa = -(t1 - t2).squaredNorm();  // 2 (t1.t2 - 1) without cancellation
  const double qb = -2 * v.dot(t1 + t2);
  const double qc = v.squaredNorm();
  const double disc = std::sqrt(std::max(qb * qb - 4 * qa * qc, 0.0));
  const double a = qb < 0 ? 2 * qc / (disc - qb) : (qa < 0 ? (qb + disc) / (-2 * qa) : -1.0);
  if (!(std::isfinite(a) && a > 0 && qc > 0)) {
    fit.outcome = {Status::kInfeasible, "no biarc joins the non-planar corner"};
    return fit;
  }
  // the junction tangent is the direction of Q0 -> Q1; both arcs use it, so G1 is exact there
  const Vec3 q0 = p1 + a * t1;
  const Vec3 q1 = p2 - a * t2;
  const Vec3 tj = (q1 - q0).normalized();
  const Segment first = tangent_arc(p1, t1, tj, a);
  const Segment second = tangent_arc(q0 + a * tj, tj, t2, a);
  fit.transition = {first, second};
  return fit;
}

// Arcs on one circle (seed 003): same direction -> a transition arc of length 2d on the circle;
// opposite direction -> both shortened by d, zero-distance transition.
CornerFit fit_same_circle(const Corner& k, const Arc& a_in, bool same_direction, double d_req) {
  const double d = std::min({d_req, k.avail_in, k.avail_out});
  const Note note = d < d_req ? shrink_note(d_req, d, "a move is short") : Note();
  if (!same_direction) {
    CornerFit fit = kink_fit(k, CornerCase::kSameCircleOppositeDirection, d, d);
    fit.note = note;
    return fit;
  }
  CornerFit fit;
  fit.corner_case = CornerCase::kSameCircleSameDirection;
  fit.trim_in = d;
  fit.trim_out = d;
  fit.parameter_used = d;
  fit.note = note;
  if (d > 0) {
    Arc piece = sub_segment(a_in, k.len_in - d, k.len_in);
    piece.sweep = 2 * d / piece.radius;
    fit.transition.push_back(piece);
  }
  return fit;
}

// Tangent corners: the larger-radius move shortened by d and that piece is the transition.
CornerFit fit_tangent(const Corner& k, bool larger_in, bool opposite, double d_req) {
  const double avail = larger_in ? k.avail_in : k.avail_out;
  const double d = std::min(d_req, avail);
  CornerFit fit;
  fit.corner_case = opposite ? CornerCase::kTangentOpposite : CornerCase::kTangent;
  fit.parameter_used = d;
  if (d < d_req) fit.note = shrink_note(d_req, d, "the larger-radius move is short");
  if (d <= 0) return fit;
  if (larger_in) {
    fit.trim_in = d;
    fit.transition.push_back(to_segment(sub_segment(*k.in, k.len_in - d, k.len_in)));
  } else {
    fit.trim_out = d;
    fit.transition.push_back(to_segment(sub_segment(*k.out, 0, d)));
  }
  return fit;
}

CornerFit from_candidate(const Corner& k, const Candidate& cand, double d) {
  CornerFit fit;
  fit.trim_in = cand.trim_in;
  fit.trim_out = cand.trim_out;
  fit.transition = cand.transition;
  fit.corner_case = cand.corner_case;
  fit.parameter_used = d;
  fit.stop = cand.kink && k.buffered;
  return fit;
}

// seed 003 (and line-arc) in one plane: the general construction, then the fallbacks.
CornerFit fit_planar(const Corner& k, const Plane& pl, bool larger_in, double d_req) {
  const double avail_larger = larger_in ? k.avail_in : k.avail_out;
  const double d = std::min(d_req, avail_larger);
  const bool reversal = k.theta >= kPi - kReversalAngle;
  const auto finish = [&](CornerFit fit) {
    if (reversal && !fit.transition.empty()) {
      fit.corner_case = CornerCase::kReversal;
      const std::string u_turn = "the moves part at the reversal: a U-turn arc joins them";
      fit.note = fit.note.empty() ? u_turn : u_turn + "; " + fit.note.text();
    }
    return fit;
  };

  const Candidate cand = solve_planar(k, pl, larger_in, d);
  if (cand.verdict == Verdict::kValid) {
    CornerFit fit = from_candidate(k, cand, d);
    if (d < d_req) fit.note = shrink_note(d_req, d, "the larger-radius move is short");
    return finish(std::move(fit));
  }
  // no circle for this d: the rule with the roles swapped
  if (cand.verdict == Verdict::kNoCircle) {
    const double d_swap = std::min(d_req, larger_in ? k.avail_out : k.avail_in);
    if (d_swap > 0) {
      const Candidate swapped = solve_planar(k, pl, !larger_in, d_swap);
      if (swapped.verdict == Verdict::kValid) {
        CornerFit fit = from_candidate(k, swapped, d_swap);
        fit.fallback = Fallback::kSmallerRadiusShortened;
        fit.note = "no transition arc with the larger-radius move shortened by " + format_mm(d) + " (" + cand.why +
                   "); the smaller-radius move is shortened instead";
        if (d_swap < d_req) fit.note += "; " + shrink_note(d_req, d_swap, "the smaller-radius move is short").text();
        return finish(std::move(fit));
      }
    }
  }
  // shrink d: find a valid corner distance below, then bisect towards the boundary
  const double d_min = std::min(kMinShrink, 0.5 * d);
  double lo = 0;
  double hi = d;
  for (double trial = 0.5 * d; trial >= d_min; trial *= 0.5) {
    if (solve_planar(k, pl, larger_in, trial).verdict == Verdict::kValid) {
      lo = trial;
      break;
    }
    hi = trial;
  }
  if (lo <= 0) {
    CornerFit fit;
    fit.outcome = {Status::kInfeasible, "no circular transition tangent to both moves (" + cand.why + ")"};
    return fit;
  }
  for (int it = 0; it < kBisections && hi - lo > 1e-12 * hi; ++it) {
    const double mid = 0.5 * (lo + hi);
    if (solve_planar(k, pl, larger_in, mid).verdict == Verdict::kValid) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  CornerFit fit = from_candidate(k, solve_planar(k, pl, larger_in, lo), lo);
  fit.note = lengths_note(kShrunkFrom, d_req, " to ", lo, cand.why);
  return finish(std::move(fit));
}

// The corner plane of a corner with at least one arc: false when the moves do not lie in one
// plane (or an arc is a helix).
bool corner_plane(const Corner& k, Plane& pl) {
  const Arc* a_in = std::get_if<Arc>(k.in);
  const Arc* a_out = std::get_if<Arc>(k.out);
  if ((a_in != nullptr && a_in->rise != 0) || (a_out != nullptr && a_out->rise != 0)) return false;
  const Vec3 w_in = a_in != nullptr ? a_in->u.cross(a_in->v).normalized() : Vec3::Zero();
  const Vec3 w_out = a_out != nullptr ? a_out->u.cross(a_out->v).normalized() : Vec3::Zero();
  if (a_in != nullptr && a_out != nullptr) {
    if (w_in.cross(w_out).norm() > kPlanarAngle) return false;
    pl.n = a_in->radius >= a_out->radius ? w_in : w_out;
  } else if (a_in != nullptr) {
    if (std::abs(w_in.dot(k.t_out)) > kPlanarAngle) return false;
    pl.n = w_in;
  } else {
    if (std::abs(w_out.dot(k.t_in)) > kPlanarAngle) return false;
    pl.n = w_out;
  }
  pl.in = plane_curve(*k.in, pl.n, k.c, in_plane(k.t_in, pl.n));
  pl.out = plane_curve(*k.out, pl.n, k.c, in_plane(k.t_out, pl.n));
  pl.delta = signed_angle(k.t_in, k.t_out, pl.n);
  return true;
}

// The arc fit of `corner` (fit_arc_corner, which marks it limited).
CornerFit fit_arc(const CornerInput& corner) {
  Corner k;
  k.in = &corner.in;
  k.out = &corner.out;
  k.len_in = length(corner.in);
  k.len_out = length(corner.out);
  k.avail_in = std::clamp(corner.in_available, 0.0, k.len_in);
  k.avail_out = std::clamp(corner.out_available, 0.0, k.len_out);
  k.c = point(corner.in, k.len_in);
  k.t_in = tangent(corner.in, k.len_in);
  k.t_out = tangent(corner.out, 0.0);
  k.theta = angle_between(k.t_in, k.t_out);
  k.buffered = corner.buffer == BufferMode::kBuffered;
  const double d_req = corner.spec.parameter;
  if (!std::isfinite(d_req) || d_req < 0) {
    CornerFit fit;
    fit.outcome = {Status::kInfeasible, "the corner distance must be finite and >= 0"};
    return fit;
  }

  const Arc* a_in = std::get_if<Arc>(&corner.in);
  const Arc* a_out = std::get_if<Arc>(&corner.out);
  if (a_in == nullptr && a_out == nullptr) return fit_line_line(k, d_req);

  // which move counts as the larger radius (seed 003; a line is infinite, ties go to the incoming)
  const bool larger_in = a_in == nullptr || (a_out != nullptr && a_in->radius >= a_out->radius * (1 - 1e-12));
  Plane pl;
  const bool planar = corner_plane(k, pl);

  // same circle (seed 003): same or opposite direction
  if (planar && a_in != nullptr && a_out != nullptr) {
    const double r = std::max(a_in->radius, a_out->radius);
    if ((a_in->center - a_out->center).norm() <= kSameCircle * r &&
        std::abs(a_in->radius - a_out->radius) <= kSameCircle * r) {
      const bool same_direction = a_in->u.cross(a_in->v).dot(a_out->u.cross(a_out->v)) > 0;
      return fit_same_circle(k, *a_in, same_direction, d_req);
    }
  }
  // tangent corners: G1 already
  if (k.theta <= kStraightAngle) {
    const bool opposite = planar && a_in != nullptr && a_out != nullptr && pl.in.rho * pl.out.rho < 0;
    return fit_tangent(k, larger_in, opposite, d_req);
  }
  // zero distance (seed 003): nothing inserted, only blending is affected
  const double avail_larger = larger_in ? k.avail_in : k.avail_out;
  if (std::min(d_req, avail_larger) <= 0) {
    CornerFit fit = kink_fit(k, CornerCase::kZeroDistance, 0, 0);
    if (d_req > 0) fit.note = shrink_note(d_req, 0, "the larger-radius move has no length left");
    return fit;
  }
  if (!planar) return fit_biarc(k, d_req);
  return fit_planar(k, pl, larger_in, d_req);
}

}  // namespace

CornerFit fit_arc_corner(const CornerInput& corner) {
  CornerFit fit = fit_arc(corner);
  // every branch reports the corner distance it used: shrunk (to a short move, or where no
  // circle exists for a larger one) when it is below the one asked for
  fit.limited = fit.outcome.ok() && fit.parameter_used < corner.spec.parameter;
  return fit;
}

}  // namespace blendbench
