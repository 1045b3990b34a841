#include "intervals.hpp"

#include <algorithm>
#include <cmath>
#include <array>

#include "blendbench/corner/blend.hpp"

// Junction rules, at a knot where the tangent turns by theta or the curvature vector jumps by
// dk (derived here; the sources only say a controller slows down there, seed 004 (Shahzadeh et al.) section 3):
//   - a direction change theta at speed v is a velocity step 2 v sin(theta/2) within one servo
//     period dt, i.e. an acceleration pulse 2 v sin(theta/2)/dt. Keeping that pulse within the
//     step the jerk limit allows in one period (j dt) and within the acceleration limit gives
//       v <= min(j dt^2, a dt) / (2 sin(theta/2));
//   - a curvature jump dk (e.g. line -> tangent arc) makes the normal acceleration dk v^2 appear
//     within one period; keeping that step within j dt gives v <= sqrt(j dt / dk);
//   - Buffered stops at a kink;
//   a and j are the lowest of the two pieces' limits.
// The buffer mode of the junction (the earlier piece's) chooses the junction velocity v_J from
// the two programmed velocities (junction_velocity, program.hpp). Where v_J is above a piece's
// programmed velocity, that piece gets a hand-over zone next to the junction (timing.hpp):
// its feed term is v_J over the distance a jerk-limited change between v_J and its own
// velocity needs, so the profile can cross the junction at v_J and reach the slower velocity
// at the end of the zone at the latest. v_J is first lowered to the kink and curvature-jump
// bounds above, so a zone never lets a piece run faster than the junction allows. The
// curvature and sharpness terms are never relaxed.
//
// Rotation (orientation.hpp). With rho(s) = dtheta/ds the tool's angular rate per unit path
// length, the angular velocity, acceleration and jerk are, by the chain rule as for the TCP
// (cartesian.hpp),
//   omega = rho v,   alpha = rho a_t + rho' v^2,   eta = rho j_t + 3 rho' v a_t + rho'' v^3,
// so with the piece's bounds |rho| <= R0, |rho'| <= R1, |rho''| <= R2 (rotation_bounds) and the
// tangential limits |a_t| <= A_t, |j_t| <= J_t of the S-curve, the conditions
//   (R1)  R0 v <= Omega,
//   (R2)  R0 A_t + R1 v^2 <= Alpha,
//   (R3)  R0 J_t + 3 R1 v A_t + R2 v^3 <= Eta
// at the largest speed on the piece hold the angular limits (Omega, Alpha, Eta: the piece's
// angular velocity, acceleration and jerk) everywhere on it. On a move piece (a slerp: R1 = R2 =
// 0) they are exact: A_t <= Alpha / R0, J_t <= Eta / R0, v <= Omega / R0. On a transition the
// tangential limits get kRotationShare of what the rotation allows and the speed is capped by
// the rest (rotation_budgets): a sound choice, not a tuned one. A junction where rho jumps (a
// kink left without transition, or the junction slow-down baseline) is bounded like a kink:
// the step v |d rho| of the angular velocity within one period within min(Alpha dt, Eta dt^2).

namespace blendbench::timing_detail {
namespace {

// Sub-intervals per piece of varying curvature (step 1 of the method, timing.cpp).
constexpr int kSubdivisions = 16;
// Relative margin on the scanned maximum curvature and sharpness of a Bezier (segment.hpp
// gives them to a relative error below 1e-9).
constexpr double kBezierScanMargin = 4e-9;

// Design-speed shares of cartesian_tangential_limits (cartesian.hpp). A curved piece is planned
// for v_c = share x its highest constant speed, the rest of the acceleration and jerk budgets
// left to speed changes on it; the share is the candidate whose estimate of the piece's
// traversal is fastest (share_for_piece). A circular transition whose curvature steps are
// allowed runs at kConstantSpeedShare, as a controller runs a G1 blend at constant speed (it
// changes speed little on it). Any share in (0, 1) is sound; these are tuning values, not
// physics.
constexpr std::array<double, 6> kCurveSpeedShares = {0.5, 0.6, 0.7, 0.8, 0.9, 0.95};
constexpr double kConstantSpeedShare = 0.99;
// The share of each angular budget a transition leaves to the tangential terms ((R2), (R3) above).
constexpr double kRotationShare = 0.5;
// A jump of rho below this share of its size is rounding (the orientation model is C2 in s
// wherever a transition joins two moves).
constexpr double kRateJumpShare = 1e-9;
// Bisection steps on (R3): to the last bit of a double.
constexpr int kRotationBisections = 200;
// A curvature jump at most this share of the larger curvature at the junction, plus
// kCurvatureRounding (1/m), is rounding of the geometry (exact to ~1e-12 relative), not a step:
// a line meeting a clothoid that starts straight, or two pieces of one arc. 1e-9 1/m is a radius
// of 10^6 km; at 10 m/s its normal acceleration would step by 1e-7 m/s^2.
constexpr double kCurvatureStepShare = 1e-9;
constexpr double kCurvatureRounding = 1e-9;

// Maximum curvature and (spatial) sharpness over [s0, s1] of a piece, with the Bezier scan
// margin.
std::pair<double, double> max_terms(const Segment& segment, double s0, double s1, LimitsMode mode) {
  double kappa = max_curvature(segment, s0, s1);
  double c = mode == LimitsMode::kPath ? max_sharpness(segment, s0, s1) : max_spatial_sharpness(segment, s0, s1);
  if (std::holds_alternative<Bezier>(segment)) {
    kappa *= 1 + kBezierScanMargin;
    c *= 1 + kBezierScanMargin;
  }
  return {kappa, c};
}

CapTerms cap_terms(const PathPiece& piece, const PieceModel& model, double s0, double s1, double feed,
                   LimitsMode mode) {
  const auto [kappa, c] = max_terms(piece.segment, s0, s1, mode);
  CapTerms terms;
  terms.feed = feed;
  terms.rotation = model.rotation_cap;
  if (mode == LimitsMode::kCartesian) {
    const CartesianCap cap = cartesian_speed_limit(kappa, c, model.vector, model.tangential);
    terms.curvature = cap.acceleration;
    terms.sharpness = cap.jerk;
    return terms;
  }
  const double a = piece.limits.acceleration;
  terms.curvature = kappa > 0 ? std::sqrt(a / kappa) : kInf;
  // eq. 26 alone: the combined limit with no curvature term
  terms.sharpness = curvature_speed_limit(0.0, std::hypot(c, kappa * kappa), a, piece.limits.jerk);
  return terms;
}

bool varying_curvature(const Segment& segment) {
  if (std::holds_alternative<Bezier>(segment)) return true;
  if (const auto* c = std::get_if<Clothoid>(&segment)) return c->sharpness != 0;
  return false;
}

// The junction from piece `prev` to piece `next` (both of non-zero length; `stop` when a piece
// in between or `next` has stop_before), with its velocity bound: 0 at a stop, else the kink and
// curvature-jump rules above (infinity where the path is G2; the curvature-jump rule dropped
// where next.curvature_step_allowed). The buffer mode's junction velocity is not part of it:
// the neighbouring intervals' caps carry it.
Junction make_junction(const Path& path, std::size_t k_prev, std::size_t k_next, bool stop, const TimingOptions& options,
                       const std::vector<PieceModel>& models) {
  using Baseline = TimingOptions::Baseline;
  const PathPiece& prev = path.pieces()[k_prev];
  const PathPiece& next = path.pieces()[k_next];
  Junction out{k_prev, k_next, 0.0, 0.0, 0.0};
  out.theta = angle_between(tangent(prev.segment, length(prev.segment)), tangent(next.segment, 0.0));
  const Vec3 kappa_prev = curvature_vector(prev.segment, length(prev.segment));
  const Vec3 kappa_next = curvature_vector(next.segment, 0.0);
  out.dk = (kappa_prev - kappa_next).norm();
  if (out.dk <= kCurvatureStepShare * std::max(kappa_prev.norm(), kappa_next.norm()) + kCurvatureRounding) out.dk = 0;
  if (options.baseline == Baseline::kExactStop) return out;
  const bool kink = out.theta > kG1Angle;
  const bool buffered_kink = kink && prev.buffer == BufferMode::kBuffered;
  // the junction slow-down baseline keeps only the stops of Buffered kinks
  if (options.baseline == Baseline::kJunctionSlowdown) stop = buffered_kink;
  if (stop || buffered_kink) return out;
  const Limits& lp = models[k_prev].vector;
  const Limits& ln = models[k_next].vector;
  const double a = std::min({lp.acceleration, lp.deceleration, ln.acceleration, ln.deceleration});
  const double j = std::min(lp.jerk, ln.jerk);
  const double dt = options.dt;
  out.cap = kInf;
  if (kink) out.cap = std::min(j * dt * dt, a * dt) / (2.0 * std::sin(0.5 * out.theta));
  double step_cap = kInf;
  if (out.dk > 0 && !next.curvature_step_allowed) step_cap = std::sqrt(j * dt / out.dk);
  // a jump of the rotation rate: the angular velocity steps by v |d rho| in one period
  if (prev.orientation && next.orientation) {
    const Vec3 r0 = angular_rate_at(*prev.orientation, length(prev.segment));
    const Vec3 r1 = angular_rate_at(*next.orientation, 0.0);
    const double jump = (r1 - r0).norm();
    if (jump > kRateJumpShare * std::max(r0.norm(), r1.norm())) {
      const double alpha = std::min(prev.orientation->limits.acceleration, next.orientation->limits.acceleration);
      const double eta = std::min(prev.orientation->limits.jerk, next.orientation->limits.jerk);
      out.cap = std::min(out.cap, std::min(alpha * dt, eta * dt * dt) / jump);
    }
  }
  out.cap_kink = out.cap;
  out.cap = std::min(out.cap, step_cap);
  return out;
}

// The rotation budget of one piece ((R1)-(R3) above): its tangential limits lowered and its
// rotation cap.
void rotation_budget(const PathPiece& piece, PieceModel& m) {
  const double len = length(piece.segment);
  if (!piece.orientation || len <= 0) return;
  const RotationBounds b = rotation_bounds(*piece.orientation, len, 0.0, len);
  const AngularLimits& lim = piece.orientation->limits;
  TangentialLimits& t = m.tangential;
  const bool varying = b.rate_d1 > 0 || b.rate_d2 > 0;
  double cap = kInf;
  if (b.rate > 0) {
    cap = lim.velocity / b.rate;  // (R1)
    // for the time-optimal bound, which must not be slower than the truth: a transition's rate
    // without the sampling margin (its sampled maximum is at most the true one)
    const bool sampled = !std::holds_alternative<GeodesicOrientation>(piece.orientation->law);
    m.rotation_speed = sampled ? cap * kBoundMargin : cap;
    // (R2), (R3): the tangential terms' share
    const double share = varying ? kRotationShare : 1.0;
    t.acceleration = std::min(t.acceleration, share * lim.acceleration / b.rate);
    t.deceleration = std::min(t.deceleration, share * lim.acceleration / b.rate);
    t.jerk = std::min(t.jerk, share * lim.jerk / b.rate);
  }
  const double a_t = std::max(t.acceleration, t.deceleration);
  // (R2): R1 v^2 <= Alpha - R0 A_t
  if (b.rate_d1 > 0 && std::isfinite(lim.acceleration)) {
    cap = std::min(cap, std::sqrt(std::max(0.0, lim.acceleration - b.rate * a_t) / b.rate_d1));
  }
  // (R3): 3 R1 A_t v + R2 v^3 <= Eta - R0 J_t, increasing in v: bisection below each term's root
  if (varying && std::isfinite(lim.jerk)) {
    const double room = std::max(0.0, lim.jerk - b.rate * t.jerk);
    const auto f = [&](double v) { return 3 * b.rate_d1 * a_t * v + b.rate_d2 * v * v * v; };
    double hi = kInf;
    if (b.rate_d1 > 0 && a_t > 0) hi = std::min(hi, room / (3 * b.rate_d1 * a_t));
    if (b.rate_d2 > 0) hi = std::min(hi, std::cbrt(room / b.rate_d2));
    if (std::isfinite(hi)) {
      double lo = 0;
      for (int i = 0; i < kRotationBisections && hi - lo > 0; ++i) {
        const double mid = 0.5 * (lo + hi);
        if (mid <= lo || mid >= hi) break;
        (f(mid) <= room ? lo : hi) = mid;
      }
      cap = std::min(cap, lo);
    }
  }
  m.rotation_cap = cap;
}

// The design-speed share of a curved piece (length len, maximum curvature kappa and spatial
// sharpness g over it, vector limits `vector` with its feed) among the candidates: the one for
// which one S-curve over the whole piece, from v_in to v_out (its junction bounds) under
// the piece's tightest cap, is fastest. The estimate ignores that the caps are higher where the
// curvature is lower; the plan itself uses the chosen limits with every interval's own cap.
double share_for_piece(double len, double kappa, double g, const Limits& vector, double v_in, double v_out) {
  double best = kCurveSpeedShares.front();
  double best_time = kInf;
  for (const double share : kCurveSpeedShares) {
    const TangentialLimits t = cartesian_tangential_limits(kappa, g, vector, share);
    const CartesianCap c = cartesian_speed_limit(kappa, g, vector, t);
    const double cap = std::min({vector.velocity, c.acceleration, c.jerk});
    if (!(cap > 0) || !(t.acceleration > 0) || !(t.deceleration > 0) || !(t.jerk > 0)) continue;
    const double time = plan_scurve(len, std::min(v_in, cap), std::min(v_out, cap),
                                    {cap, t.acceleration, t.deceleration, t.jerk})
                            .curve.duration();
    if (time < best_time) {
      best_time = time;
      best = share;
    }
  }
  return best;
}

}  // namespace

std::vector<PieceModel> piece_models(const Path& path, const TimingOptions& options) {
  std::vector<PieceModel> models;
  models.reserve(path.pieces().size());
  for (const PathPiece& piece : path.pieces()) {
    PieceModel m;
    m.vector = piece.limits;
    if (options.limits == LimitsMode::kCartesian) {
      m.vector = effective_vector_limits(piece.segment, piece.limits, options.axis_limits);
    }
    m.tangential = {m.vector.acceleration, m.vector.deceleration, m.vector.jerk};
    models.push_back(m);
  }
  return models;
}

namespace {

// kCartesian: the tangential limits of every curved piece (share_budgets).
void cartesian_shares(const Path& path, const TimingOptions& options, const std::vector<Junction>& joints,
                      std::vector<PieceModel>& models) {
  if (options.limits != LimitsMode::kCartesian) return;
  const auto& pieces = path.pieces();
  // the junction bounds at both ends of every piece (0 at the ends of the path)
  std::vector<double> v_in(pieces.size(), 0.0);
  std::vector<double> v_out(pieces.size(), 0.0);
  for (const Junction& jn : joints) {
    v_out[jn.prev] = jn.cap;
    v_in[jn.next] = jn.cap;
  }
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const PathPiece& piece = pieces[k];
    const double len = length(piece.segment);
    if (len <= 0) continue;
    const auto [kappa, g] = max_terms(piece.segment, 0.0, len, options.limits);
    if (!(kappa > 0) && !(g > 0)) continue;
    PieceModel& m = models[k];
    // the arc of a corner whose curvature steps are allowed runs at (nearly) constant speed
    const bool constant_speed = std::holds_alternative<Arc>(piece.segment) && piece.corner >= 0 && piece.curvature_step_allowed;
    const double share = constant_speed ? kConstantSpeedShare : share_for_piece(len, kappa, g, m.vector, v_in[k], v_out[k]);
    m.tangential = cartesian_tangential_limits(kappa, g, m.vector, share);
  }
}

}  // namespace

void share_budgets(const Path& path, const TimingOptions& options, const std::vector<Junction>& joints,
                   std::vector<PieceModel>& models) {
  cartesian_shares(path, options, joints, models);
  // the rotation budgets after the cartesian shares, which they only lower further
  if (!path.oriented()) return;
  for (std::size_t k = 0; k < path.pieces().size(); ++k) rotation_budget(path.pieces()[k], models[k]);
}

std::vector<Junction> junctions(const Path& path, const TimingOptions& options, const std::vector<PieceModel>& models) {
  const auto& pieces = path.pieces();
  std::vector<Junction> out;
  std::size_t prev = pieces.size();
  bool stop = false;
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    stop = stop || pieces[k].stop_before;
    if (length(pieces[k].segment) <= 0) continue;
    if (prev < pieces.size()) out.push_back(make_junction(path, prev, k, stop, options, models));
    stop = false;
    prev = k;
  }
  return out;
}

namespace {

// The hand-over zones of one junction (see above and timing.hpp), appended to `zones`; the
// distances with the pieces' tangential limits.
void junction_zones(const Path& path, const Junction& junction, const std::vector<PieceModel>& models,
                    std::vector<HandoverZone>& zones) {
  const PathPiece& prev = path.pieces()[junction.prev];
  const PathPiece& next = path.pieces()[junction.next];
  const TangentialLimits& tp = models[junction.prev].tangential;
  const TangentialLimits& tn = models[junction.next].tangential;
  const double v_j = std::min(junction_velocity(prev.buffer, prev.limits.velocity, next.limits.velocity), junction.cap);
  // the slower next piece slows down from v_J after the junction
  if (v_j > next.limits.velocity) {
    const double d = velocity_change(v_j, next.limits.velocity, tn.deceleration, tn.jerk).distance;
    zones.push_back({junction.next, 0.0, std::min(d, length(next.segment)), v_j});
  }
  // the slower previous piece speeds up to v_J before the junction
  if (v_j > prev.limits.velocity) {
    const double d = velocity_change(prev.limits.velocity, v_j, tp.acceleration, tp.jerk).distance;
    const double len = length(prev.segment);
    zones.push_back({junction.prev, std::max(0.0, len - d), len, v_j});
  }
}

}  // namespace

std::vector<HandoverZone> all_zones(const Path& path, const std::vector<Junction>& joints,
                                    const std::vector<PieceModel>& models) {
  std::vector<HandoverZone> zones;
  for (const Junction& junction : joints) junction_zones(path, junction, models, zones);
  std::sort(zones.begin(), zones.end(),
            [](const HandoverZone& a, const HandoverZone& b) { return a.piece != b.piece ? a.piece < b.piece : a.s0 < b.s0; });
  return zones;
}

void build_intervals(const Path& path, const TimingOptions& options, const std::vector<PieceModel>& models,
                     const std::vector<Junction>& joints, const std::vector<HandoverZone>& zones,
                     std::vector<Interval>& intervals, std::vector<double>& knot_cap) {
  const auto& pieces = path.pieces();
  std::size_t next_joint = 0;
  std::size_t first_zone = 0;
  std::vector<double> cuts;
  // reserved once: on long programs growing these vectors (and faulting in their pages) cost
  // more than building the intervals
  std::size_t count = 2 * zones.size();
  for (const PathPiece& piece : pieces) count += varying_curvature(piece.segment) ? kSubdivisions : 1;
  intervals.reserve(intervals.size() + count);
  knot_cap.reserve(knot_cap.size() + count + 1);
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const PathPiece& piece = pieces[k];
    const double len = length(piece.segment);
    if (len <= 0) continue;
    double cap_in = 0.0;
    if (next_joint < joints.size() && joints[next_joint].next == k) cap_in = joints[next_joint++].cap;
    // cut points: sub-intervals of varying curvature, ends of hand-over zones
    const int m = varying_curvature(piece.segment) ? kSubdivisions : 1;
    while (first_zone < zones.size() && zones[first_zone].piece < k) ++first_zone;
    std::size_t end_zone = first_zone;
    while (end_zone < zones.size() && zones[end_zone].piece == k) ++end_zone;
    cuts.clear();
    for (int i = 0; i <= m; ++i) cuts.push_back(i == m ? len : len * i / m);
    for (std::size_t z = first_zone; z < end_zone; ++z) cuts.insert(cuts.end(), {zones[z].s0, zones[z].s1});
    std::sort(cuts.begin(), cuts.end());
    cuts.erase(std::unique(cuts.begin(), cuts.end()), cuts.end());
    const TangentialLimits& t = models[k].tangential;
    const ScurveLimits lim{0.0, t.acceleration, t.deceleration, t.jerk};
    for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
      const double a = cuts[i];
      const double b = cuts[i + 1];
      // the feed term: the programmed velocity, or the junction velocity in a hand-over zone
      double feed = piece.limits.velocity;
      for (std::size_t z = first_zone; z < end_zone; ++z) {
        if (zones[z].s0 <= a && b <= zones[z].s1) feed = std::max(feed, zones[z].velocity);
      }
      Interval iv;
      iv.s0 = i == 0 ? path.offset(k) : path.offset(k) + a;
      iv.s1 = i + 2 == cuts.size() ? path.offset(k + 1) : path.offset(k) + b;
      iv.piece = iv.piece_last = k;
      iv.terms = cap_terms(piece, models[k], a, b, feed, options.limits);
      iv.limits = lim;
      iv.limits.velocity = iv.terms.min();
      iv.flat = m == 1;
      intervals.push_back(iv);
      knot_cap.push_back(i == 0 ? cap_in : kInf);
    }
  }
  knot_cap.push_back(0.0);
}

void merge_intervals(const Path& path, std::vector<Interval>& intervals, std::vector<double>& knot_cap) {
  if (intervals.empty()) return;
  // compacted in place: intervals[0..kept] are the merged ones, knot_cap[i] their start caps
  std::size_t kept = 0;
  const double end_cap = knot_cap.back();
  for (std::size_t i = 1; i < intervals.size(); ++i) {
    Interval& last = intervals[kept];
    const Interval& iv = intervals[i];
    const Limits& a = path.pieces()[last.piece_last].limits;
    const Limits& b = path.pieces()[iv.piece].limits;
    const bool same = a.velocity == b.velocity && a.acceleration == b.acceleration &&
                      a.deceleration == b.deceleration && a.jerk == b.jerk && iv.terms.feed == last.terms.feed &&
                      iv.terms.curvature == last.terms.curvature && iv.terms.sharpness == last.terms.sharpness && iv.terms.rotation == last.terms.rotation &&
                      iv.limits.acceleration == last.limits.acceleration &&
                      iv.limits.deceleration == last.limits.deceleration && iv.limits.jerk == last.limits.jerk;
    if (same && knot_cap[i] == kInf) {
      last.s1 = iv.s1;
      last.piece_last = iv.piece_last;
      continue;
    }
    ++kept;
    intervals[kept] = iv;
    knot_cap[kept] = knot_cap[i];
  }
  intervals.resize(kept + 1);
  knot_cap.resize(kept + 2);
  knot_cap[kept + 1] = end_cap;
}

}  // namespace blendbench::timing_detail
