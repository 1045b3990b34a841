// seed 004 Algorithm 2 (the largest fillet within a deviation tolerance) and the other way to size a
// fillet, by its start distance (Algorithm 1 alone, shrunk until it fits).

#include "blendbench/corner/biclothoid.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <memory_resource>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "biclothoid_internal.hpp"
#include "blendbench/core/format.hpp"
#include "blendbench/corner/clothoid_blend.hpp"

namespace blendbench {
using namespace biclothoid_detail;  // the helpers private to the biclothoid sources
namespace {

// How close to a point where the moves cross again a fillet may start or end (fraction of the
// distance from the corner).
constexpr double kCrossingMargin = 0.98;
// Algorithm 2 stops once tolerance (1 - kReached) <= deviation <= tolerance (log scale).
constexpr double kReached = 1e-4;
// The most of an arc a fillet replaces (rad of the arc's turn).
constexpr double kMaxArcTurn = 0.25 * std::numbers::pi;

// The start distance of a small fillet where a tangent jump delta and a curvature jump act
// together (biclothoid_mixed_shares), as a share F of the line-line pair's start a_angle,
// against rho = a_angle / a_curvature. Derived here (seed 004 is silent): for small fillets
// (small slopes and kappa a) only the jump in curvature counts (a common curvature adds the
// same parabola to the path and to the fillet), and scaling lengths by a_angle leaves one
// corner shape per rho and per sign of delta (kappa2 - kappa1), so F(rho, sign) is universal.
// It has no closed form here; the entries are Algorithm 2's own solutions (to its band, 5e-5)
// on corners of delta = 1e-3 rad from an arc of curvature 1/m to a line, at log10 rho = -2,
// -1.95, ..., 1; above that, to 3, solutions half the band inside the tolerance (secant steps
// to 1e-13) on corners whose arc turns by u1 = kappa_1 a_curvature = 0.01 over the fillet (at
// delta = 1e-3, u1 = 42 rho / A, A the pair's tangent length per unit tolerance, grows as
// 0.007 rho: the entries built so carried the arc's own curvature, u1 = 0.7 at rho = 100, and
// missed the small-fillet share by 0.2-0.3 %; Biclothoid.TheMixedTablesTailIsAlgorithm2sSolution
// recomputes them). The same solutions at delta = 0.1 rad differ by at most 0.3 %, on arc-arc
// corners of the same jump by 1e-5 (Biclothoid.TheMixedStartShareIsAlgorithm2sSmallFillet checks
// random ones against it). Below rho = 0.01 F is the first entry (the pair alone); above 1000
// rho F goes as 1 / rho to the curvature jump alone's limit (biclothoid_curvature_jump_start at
// u = 0: rho F = 1.00033-1.00061 at 1000, 1.00046 in the limit), the end share to kEndShare.
// Where the curvature jump turns the path the way the tangent jump does (sign +1), Algorithm
// 2's solutions change branch at log10 rho = 0.1045, from the shorter fillet (F = 0.388) to
// the longer (0.822); each side interpolates to its own solution there (kMixedJumpBelow,
// kMixedJumpAbove). The harmonic blend 1 / hypot(1 / a_angle, 1 / a_curvature) used before is up to 59 % too long below the change of branch and 22 % too short above it
// (within 5 % at sign -1): the first solve landed far enough out that 4.5 % of the random
// corners with an arc needed three or four solves.
// biclothoid_curvature_jump_start at u -> 0 (its fit's constant term, below): log(a / a_curvature)
// of the small fillet at a curvature jump alone, the limit the mixed shares tend to
constexpr double kCurvatureJumpAtZero = 4.633901e-4;
constexpr double kMixedLogRhoMin = -2.0;
constexpr double kMixedLogRhoStep = 0.05;
constexpr std::array<double, 101> kMixedShareOpposed = {  // sign -1
    0.99995, 0.99994, 0.99992, 0.99990, 0.99997, 0.99997, 0.99997, 0.99997, 0.99997, 0.99996, 0.99996, 0.99995,
    0.99994, 0.99992, 0.99989, 0.99985, 0.99978, 0.99967, 0.99950, 0.99923, 0.99881, 0.99815, 0.99715, 0.99561,
    0.99329, 0.98986, 0.98489, 0.97791, 0.96851, 0.95646, 0.94193, 0.92553, 0.90827, 0.89119, 0.87483, 0.85891,
    0.84231, 0.82344, 0.80088, 0.77379, 0.74147, 0.69878, 0.64974, 0.59859, 0.54779, 0.49881, 0.45247, 0.40919,
    0.36917, 0.33243, 0.29887, 0.26834, 0.24068, 0.21568, 0.19313, 0.17282, 0.15457, 0.13818, 0.12348, 0.11031,
    0.09851, 0.08795866, 0.07851631, 0.07007435, 0.06252978, 0.05578949, 0.0497695, 0.04439422, 0.03959566,
    0.03531278, 0.0314908, 0.02808064, 0.0250383, 0.02232444, 0.01990383, 0.01774496, 0.0158197, 0.01410287,
    0.01257201, 0.01120705, 0.009990061, 0.008905055, 0.007937751, 0.007075411, 0.006306667, 0.005621379, 0.0050105,
    0.004465963, 0.003980572, 0.003547909, 0.003162252, 0.002818499, 0.002512101, 0.002239, 0.00199558, 0.001778618,
    0.001585239, 0.00141288, 0.001259259, 0.001122338, 0.001000302};
constexpr std::array<double, 101> kMixedShareAligned = {  // sign +1
    0.99995, 0.99994, 0.99992, 0.99990, 0.99997, 0.99997, 0.99997, 0.99997, 0.99997, 0.99996, 0.99996, 0.99995,
    0.99994, 0.99992, 0.99989, 0.99985, 0.99978, 0.99967, 0.99949, 0.99921, 0.99878, 0.99810, 0.99704, 0.99539,
    0.99286, 0.98901, 0.98326, 0.97482, 0.96280, 0.94621, 0.92417, 0.89617, 0.86214, 0.82252, 0.77826, 0.73058,
    0.68084, 0.63037, 0.58033, 0.53167, 0.48481, 0.43757, 0.39182, 0.74179, 0.66154, 0.58916, 0.52423, 0.46620,
    0.41446, 0.36839, 0.32744, 0.29104, 0.25870, 0.22999, 0.20450, 0.18186, 0.16175, 0.14388, 0.12801, 0.11391,
    0.10137, 0.09022817, 0.08031904, 0.07150632, 0.06366723, 0.05669299, 0.05048718, 0.04496429, 0.04004849,
    0.03567247, 0.03177652, 0.02830759, 0.02521858, 0.02246764, 0.02001757, 0.01783531, 0.01589146, 0.01415988,
    0.01261729, 0.01124302, 0.01001863, 0.00892775, 0.007955779, 0.007089731, 0.006318042, 0.005630414, 0.005017677,
    0.004471664, 0.0039851, 0.003551506, 0.00316511, 0.002820769, 0.002513903, 0.002240432, 0.001996718, 0.001779522,
    0.001585957, 0.001413451, 0.001259712, 0.001122697, 0.001000588};
// b / a of the same solutions (the fillet's end on q2 as a share of its start on q1): 1 for
// the pair alone, kEndShare for the curvature jump alone
constexpr std::array<double, 101> kMixedEndOpposed = {  // sign -1
    1.00000, 1.00000, 1.00000, 1.00000, 1.00000, 1.00000, 1.00000, 1.00000, 1.00000, 1.00000, 1.00000, 1.00000,
    1.00000, 1.00000, 1.00000, 1.00000, 1.00000, 1.00000, 0.99999, 0.99999, 0.99997, 0.99994, 0.99989, 0.99978,
    0.99956, 0.99915, 0.99835, 0.99684, 0.99410, 0.98927, 0.98115, 0.96828, 0.94920, 0.92295, 0.88961, 0.85059,
    0.80830, 0.76552, 0.72461, 0.68710, 0.65385, 0.62618, 0.60303, 0.58329, 0.56625, 0.55141, 0.53840, 0.52696,
    0.51686, 0.50791, 0.49997, 0.49293, 0.48666, 0.48108, 0.47612, 0.47170, 0.46776, 0.46425, 0.46112, 0.45833,
    0.45584, 0.4536329, 0.4516565, 0.4498943, 0.4483233, 0.4469226, 0.4456737, 0.4445604, 0.4435678, 0.4426828,
    0.441894, 0.4411907, 0.4405638, 0.4400049, 0.4395067, 0.4390626, 0.4386668, 0.4383139, 0.4379994, 0.4377191,
    0.4374692, 0.4372464, 0.4370479, 0.436871, 0.4367133, 0.4365727, 0.4364474, 0.4363357, 0.4362362, 0.4361475,
    0.4360684, 0.435998, 0.4359351, 0.4358792, 0.4358293, 0.4357848, 0.4357452, 0.4357098, 0.4356784, 0.4356503,
    0.4356253};
constexpr std::array<double, 101> kMixedEndAligned = {  // sign +1
    1.00000, 1.00000, 1.00000, 1.00000, 1.00000, 1.00000, 1.00000, 1.00000, 1.00000, 1.00000, 1.00000, 1.00000,
    1.00000, 1.00000, 1.00000, 1.00000, 1.00000, 1.00000, 1.00001, 1.00001, 1.00003, 1.00006, 1.00011, 1.00022,
    1.00044, 1.00086, 1.00166, 1.00317, 1.00594, 1.01085, 1.01921, 1.03276, 1.05352, 1.08348, 1.12408, 1.17566,
    1.23717, 1.30630, 1.38005, 1.45538, 1.52939, 1.59698, 1.65829, 0.27765, 0.29695, 0.31349, 0.32780, 0.34024,
    0.35113, 0.36068, 0.36909, 0.37651, 0.38306, 0.38887, 0.39402, 0.39858, 0.40263, 0.40623, 0.40943, 0.41228,
    0.41481, 0.4170696, 0.4190745, 0.4208592, 0.4224482, 0.4238632, 0.4251233, 0.4262457, 0.4272454, 0.428136,
    0.4289294, 0.4296362, 0.430266, 0.4308271, 0.4313271, 0.4317726, 0.4321695, 0.4325233, 0.4328385, 0.4331194,
    0.4333698, 0.4335928, 0.4337917, 0.4339688, 0.4341267, 0.4342674, 0.4343928, 0.4345046, 0.4346042, 0.434693,
    0.4347721, 0.4348426, 0.4349054, 0.4349614, 0.4350113, 0.4350558, 0.4350955, 0.4351308, 0.4351623, 0.4351903,
    0.4352154};
constexpr double kMixedAlignedJump = 0.104494;  // log10 rho of the change of branch (sign +1)
// the solutions either side of it
constexpr BiclothoidMixedShares kMixedJumpBelow{0.38784, 1.66353};
constexpr BiclothoidMixedShares kMixedJumpAbove{0.82176, 0.25708};
// the largest end share biclothoid_mixed_shares returns (it interpolates between these)
constexpr double kMixedEndMax = [] {
  double top = std::max(kMixedJumpBelow.end, kMixedJumpAbove.end);
  for (const double e : kMixedEndOpposed) top = std::max(top, e);
  for (const double e : kMixedEndAligned) top = std::max(top, e);
  return top;
}();

// biclothoid_arc_sensitivity at |delta| = k pi / 32, k = 0..32. Derived here (seed 004 is
// silent): at a tangent jump the small-fillet model is the line-line pair, exact where the
// moves are lines; an arc of curvature kappa bends its move by kappa a over the stretch the
// fillet replaces, which at a large turn moves the fillet's start at first order in kappa a
// (at a small one both curves bend alike). The entries are d log a* / d (sgn(delta) kappa_i a)
// of the start a* whose deviation (section 7.1) is the tolerance, solved to 1e-13 in
// log(deviation / tol), by central differences at kappa_1 a = +-5e-4, kappa_2 = +-kappa_1 / 2
// (the four sign pairs cancel the curvature jump's part, even in the signs, which
// biclothoid_mixed_shares carries), tolerance 0.1 mm; the last node at pi - 1e-3
// (Biclothoid.TheArcSensitivityTableIsAlgorithm2sDerivative recomputes them so). At
// kappa_1 a = 2e-3 they agree to 1e-6 above delta = 0.7 rad and to 4e-5 at 0.2 rad, where the
// jump's part is no longer even at that size. Without them the start missed by up to 25 % at
// turns of two radians or more on arcs that the fillet follows for half a radian, and 0.8 % of
// the random corners with an arc needed a third solve (0.13 % with them; one-solve fits
// 42 % -> 58 %).
constexpr double kArcTurnStep = std::numbers::pi / 32;
constexpr std::array<double, 33> kArcSensitivityIn = {
    0.000000, -0.003257, -0.006573, -0.009919, -0.013333, -0.016840, -0.020467, -0.024240, -0.028191, -0.032352,
    -0.036758, -0.041449, -0.046470, -0.051872, -0.057712, -0.064056, -0.070981, -0.078576, -0.086944, -0.096208,
    -0.106514, -0.118037, -0.130986, -0.145617, -0.162245, -0.181255, -0.203133, -0.228490, -0.258107, -0.292992,
    -0.334470, -0.384304, -0.444200};
constexpr std::array<double, 33> kArcSensitivityOut = {
    0.000000, -0.006584, -0.013124, -0.019735, -0.026416, -0.033188, -0.040074, -0.047099, -0.054292, -0.061679,
    -0.069293, -0.077166, -0.085335, -0.093839, -0.102722, -0.112035, -0.121831, -0.132172, -0.143128, -0.154779,
    -0.167217, -0.180546, -0.194888, -0.210388, -0.227211, -0.245559, -0.265668, -0.287825, -0.312379, -0.339757,
    -0.370491, -0.405249, -0.444450};

// The natural logarithms of a mixed-share table's nodes (0: start aligned, 1: start opposed,
// 2: end aligned, 3: end opposed), taken on first use.
template <int kTable>
const std::array<double, 101>& log_nodes() {
  static const std::array<double, 101> logs = [] {
    const auto& f = kTable == 0 ? kMixedShareAligned
                    : kTable == 1 ? kMixedShareOpposed
                    : kTable == 2 ? kMixedEndAligned
                                  : kMixedEndOpposed;
    std::array<double, 101> out{};
    for (std::size_t k = 0; k < f.size(); ++k) out[k] = std::log(f[k]);
    return out;
  }();
  return logs;
}

}  // namespace

BiclothoidMixedShares biclothoid_mixed_shares(double rho, bool aligned) {
  const auto& start = aligned ? kMixedShareAligned : kMixedShareOpposed;
  const auto& end = aligned ? kMixedEndAligned : kMixedEndOpposed;
  const auto last = static_cast<std::ptrdiff_t>(start.size()) - 1;
  const double x = rho > 0 ? std::log10(rho) : kMixedLogRhoMin;
  if (x <= kMixedLogRhoMin) return {start.front(), end.front()};
  const double x_end = kMixedLogRhoMin + kMixedLogRhoStep * static_cast<double>(last);
  if (x >= x_end) {
    // towards the curvature jump alone as 1 / rho: rho F to its start's limit at u -> 0
    // (biclothoid_curvature_jump_start), the end share to kEndShare
    const double rho_end = std::pow(10.0, x_end);
    const double limit = std::exp(kCurvatureJumpAtZero);
    const double fade = rho_end / rho;
    return {(limit + (start.back() * rho_end - limit) * fade) / rho, kEndShare + (end.back() - kEndShare) * fade};
  }
  // linear in log share against log rho between the nodes either side of x; in the node
  // interval holding the change of branch, between the node on x's side and that side's
  // solution at the change
  const double u = (x - kMixedLogRhoMin) / kMixedLogRhoStep;
  const auto i = std::clamp(static_cast<std::ptrdiff_t>(u), std::ptrdiff_t{0}, last - 1);
  const auto node = [&](const std::array<double, 101>& f, std::ptrdiff_t k) { return f[static_cast<std::size_t>(k)]; };
  double x0 = kMixedLogRhoMin + kMixedLogRhoStep * static_cast<double>(i);
  double x1 = x0 + kMixedLogRhoStep;
  BiclothoidMixedShares lo{node(start, i), node(end, i)};
  BiclothoidMixedShares hi{node(start, i + 1), node(end, i + 1)};
  const bool at_jump = aligned && x0 < kMixedAlignedJump && kMixedAlignedJump < x1;
  if (at_jump) {
    if (x < kMixedAlignedJump) {
      x1 = kMixedAlignedJump;
      hi = kMixedJumpBelow;
    } else {
      x0 = kMixedAlignedJump;
      lo = kMixedJumpAbove;
    }
  }
  const double t = (x - x0) / (x1 - x0);
  const auto interpolate = [t](double log_f0, double log_f1) { return std::exp(log_f0 + t * (log_f1 - log_f0)); };
  // the nodes' logarithms, taken once (each fit interpolates once, and four logarithms were 2-3 %
  // of a fit with an arc); those of the solutions at the change of branch, rarely needed, here
  if (at_jump) {
    return {interpolate(std::log(lo.start), std::log(hi.start)), interpolate(std::log(lo.end), std::log(hi.end))};
  }
  const auto& log_start = aligned ? log_nodes<0>() : log_nodes<1>();
  const auto& log_end = aligned ? log_nodes<2>() : log_nodes<3>();
  const auto k0 = static_cast<std::size_t>(i);
  return {interpolate(log_start[k0], log_start[k0 + 1]), interpolate(log_end[k0], log_end[k0 + 1])};
}

BiclothoidArcSensitivity biclothoid_arc_sensitivity(double turn) {
  double u = std::abs(turn) / kArcTurnStep;
  if (!(u > 0)) return {0.0, 0.0};  // no turn (or not a number): nothing moves the start
  u = std::min(u, 32.0);
  const auto i = std::min(static_cast<std::size_t>(u), std::size_t{31});
  const double t = u - static_cast<double>(i);
  const auto lerp = [&](const std::array<double, 33>& f) { return f[i] + t * (f[i + 1] - f[i]); };
  return {lerp(kArcSensitivityIn), lerp(kArcSensitivityOut)};
}

// The start at a curvature jump alone, by scaling: with lengths in units of a_curvature the
// corner is fixed by u_i = kappa_i a_curvature (the tolerance is then |u2 - u1| / 42), so
// log(a / a_curvature) is one function of (u1, u2), even in them. Its quadratic, fitted here
// by least squares to Algorithm 2's solutions (secant steps on log(deviation / tol) to 1e-13,
// tol = 0.1 mm) on the grid u_i = 0.08 k, |u2| <= |u1| <= 0.8, u1 != u2 (220 corners):
// within 1.9e-5 of every one (the largest at u = (-0.8, -0.72)); quartic terms would take it
// to 6e-8. (seed 004 is silent: its 42, from table 1, is the u -> 0 limit to 0.1 %.)
double biclothoid_curvature_jump_start(double u1, double u2) {
  // outside the fitted range, its edge along the same direction
  constexpr double kRange = 0.8;
  if (!onto_range(kRange, u1, u2)) return 0.0;
  constexpr double kU1U1 = -4.836173e-3;
  constexpr double kU1U2 = -1.137315e-2;
  constexpr double kU2U2 = -8.226727e-4;
  const double value = kCurvatureJumpAtZero + u1 * (kU1U1 * u1 + kU1U2 * u2) + kU2U2 * u2 * u2;
  return std::isfinite(value) ? value : 0.0;
}

namespace {

// Where q1 (sigma in [-a_max, 0)) and q2 (sigma in (0, b_max]) meet again after the corner,
// as (-sigma1, sigma2), or nullopt. Both pass through the origin, so a line meets a circle of
// centre c once more at 2 (t . c) t, and two circles meet at the mirror image of the origin in
// their line of centres. At a tangent corner (no tangent jump) they touch at the origin and meet
// nowhere else; the formulas then give the origin up to rounding (a point 1e-33 m away once
// capped a tangent S-bend's fillet to nothing), so there is no crossing.
std::optional<std::pair<double, double>> crossing(const PlanarShape& q1, const PlanarShape& q2, double a_max,
                                                  double b_max) {
  const auto centre = [](const PlanarShape& q) -> Vec2 {
    return Vec2(perp(q.t) / q.kappa);
  };
  if (q1.kappa == 0 && q2.kappa == 0) return std::nullopt;
  if (std::abs(angle_turn(q1.theta, q2.theta)) <= kTangentAngle) return std::nullopt;
  Vec2 x = Vec2::Zero();
  if (q1.kappa == 0 || q2.kappa == 0) {
    const PlanarShape& line = q1.kappa == 0 ? q1 : q2;
    const Vec2 t = line.t;
    x = 2 * t.dot(centre(q1.kappa == 0 ? q2 : q1)) * t;
  } else {
    const Vec2 c1 = centre(q1);
    const Vec2 d = centre(q2) - c1;
    if (!(d.squaredNorm() > 0)) return std::nullopt;
    x = 2 * (c1 - c1.dot(d) / d.squaredNorm() * d);
  }
  const auto sigma = [&](const PlanarShape& q) {
    if (q.kappa == 0) return x.dot(q.t);
    const Vec2 c = centre(q);
    return std::atan2(cross(-c, x - c), (-c).dot(x - c)) / q.kappa;
  };
  // each condition before the next angle is computed (an arc's takes an atan2); the arc length
  // from the corner to x along either move is at least the chord |x|, so a chord longer than
  // either cap fails without them
  const double chord = x.norm();
  if (!(chord > 0) || chord > a_max || chord > b_max) return std::nullopt;
  const double s1 = sigma(q1);
  if (!(s1 < 0 && -s1 <= a_max)) return std::nullopt;
  const double s2 = sigma(q2);
  if (!(s2 > 0 && s2 <= b_max)) return std::nullopt;
  return std::make_pair(-s1, s2);
}

// The largest start distance a (on q1) and end distance b (on q2) a fillet may take: the move
// lengths a_max, b_max; at most an eighth of a turn of an arc is replaced, and only up to where
// the two moves cross again (near a reversal an arc can curl back across the other move).
struct Caps {
  double a;  // m
  double b;  // m
};
Caps fillet_caps(const CornerShapes& shapes, double a_max, double b_max) {
  double a_cap = shapes.q1.kappa != 0 ? std::min(a_max, kMaxArcTurn / std::abs(shapes.q1.kappa)) : a_max;
  double b_cap = shapes.q2.kappa != 0 ? std::min(b_max, kMaxArcTurn / std::abs(shapes.q2.kappa)) : b_max;
  if (const auto meet = crossing(shapes.q1, shapes.q2, a_cap, b_cap)) {
    a_cap = std::min(a_cap, kCrossingMargin * meet->first);
    b_cap = std::min(b_cap, kCrossingMargin * meet->second);
  }
  return {a_cap, b_cap};
}

}  // namespace

BiclothoidToleranceFit fit_biclothoid_with_tolerance(const CornerShapes& shapes, double tolerance, double a_max,
                                                     double b_max) {
  BiclothoidToleranceFit result;
  // section 6: fit from the more curved shape to the less curved one
  result.swapped = std::abs(shapes.q2.kappa) > std::abs(shapes.q1.kappa);
  const CornerShapes work = result.swapped ? reversed(shapes) : shapes;
  if (result.swapped) std::swap(a_max, b_max);
  const Caps caps = fillet_caps(work, a_max, b_max);
  const double a_cap = caps.a;
  const double b_cap = caps.b;
  const double delta = corner_turn(work);
  const bool tangent_jump = std::abs(delta) > 1e-9;
  // the line-line pair's shape at this turn, for the model below and the first solve's cold
  // guess (its Fresnel integrals once, not three times; its half angle's cosine and sine from
  // the tangents' dot and cross products, not a sincos)
  const ClothoidPairShape turn_shape =
      tangent_jump ? clothoid_pair_shape(std::abs(delta), work.q1.t.dot(work.q2.t), std::abs(cross(work.q1.t, work.q2.t)))
                   : ClothoidPairShape{};

  struct Trial {
    BiclothoidSolution fillet;
    double dlen_da = 0;  // sensitivities of Algorithm 1 (Solve)
    double db_da = 0;
    Vec2 end = Vec2::Zero();  // the fillet's end point (Solve)
    Deviation deviation;
    Witness witness;
    bool measured = false;
  };
  // the solves so far; the capacity is reserved once, so addresses stay stable, in a buffer on
  // the stack that is not cleared (an array of optionals would be cleared in full on every call,
  // 20 kB; a vector's allocation was 1 % of a fit with an arc)
  constexpr std::size_t kMaxTrials = 96;
  std::array<std::byte, kMaxTrials * sizeof(Trial) + alignof(Trial)> buffer;
  std::pmr::monotonic_buffer_resource arena(buffer.data(), buffer.size(), std::pmr::null_memory_resource());
  std::pmr::vector<Trial> store(&arena);
  store.reserve(kMaxTrials);
  // Algorithm 1 at start distance a, warm-started from the nearest earlier solve: its L and b
  // moved along their sensitivities in log-log coordinates, L (a) ~ L_n (a / a_n)^p with
  // p = (a_n / L_n) dL/da (exact for the line-line pair, where L and b are proportional to a)
  const auto solve = [&](double a) -> Trial* {
    // the nearest in log a: the smallest ratio max(a_n / a, a / a_n)
    const auto gap = [&](const Trial& t) { return std::max(t.fillet.a / a, a / t.fillet.a); };
    Trial* near = nullptr;
    for (Trial& t : store) {
      if (t.fillet.a == a) return &t;
      if (!near || gap(t) < gap(*near)) near = &t;
    }
    double guess_len = 0;
    double guess_b = 0;
    if (near) {
      const BiclothoidSolution& f = near->fillet;
      const double x = std::log(a / f.a);
      const double len = length(f.curve);
      double p_len = near->dlen_da * f.a / len;
      double p_b = near->db_da * f.a / f.b;
      if (!(std::abs(p_len) < 4)) p_len = 1;
      if (!(std::abs(p_b) < 4)) p_b = 1;
      guess_len = len * std::exp(p_len * x);
      guess_b = f.b * std::exp(p_b * x);
    }
    if (store.size() == kMaxTrials) return nullptr;
    ++result.solves;
    const auto sol = fit_at(work, a, guess_len, guess_b, Effort::kFull, tangent_jump ? &turn_shape : nullptr);
    if (!sol) return nullptr;
    store.push_back(Trial{sol->fillet, sol->dlen_da, sol->db_da, sol->end, {}, {}, false});
    return &store.back();
  };
  // Algorithm 1 from the other end: the fillet that ends exactly at the end bound (b = b_cap),
  // solved on the reversed corner with b_cap as its start distance, warm-started from trial
  // `from` along its sensitivities. Where the end bound is what stops the fillet growing, this
  // is the answer in one solve (b grows with a, so no larger a keeps b <= b_cap), where Newton
  // on log(b / b_cap) needs one or two more to reach the band. Its sensitivities follow by the
  // chain rule (dL/da = (dL/db) / (da/db), db/da = 1 / (da/db)).
  // (tried once per fit; not where the prediction starts at or past the start cap, which then
  // binds first)
  bool tried_end_bound = false;
  // the solve itself, guessed at start distance guess_a and length guess_len; `past_cap`, when
  // given, is set where it found a fillet on the guess's branch that starts past the start cap
  // (which then binds first)
  const auto solve_from_end = [&](double guess_a, double guess_len, Effort effort, bool* past_cap) -> Trial* {
    if (tried_end_bound || store.size() == kMaxTrials) return nullptr;
    tried_end_bound = true;
    const CornerShapes back = reversed(work);
    ++result.solves;
    const auto sol = fit_at(back, b_cap, guess_len, guess_a, effort);
    if (!sol || !(sol->db_da > 0)) return nullptr;
    // the same branch of solutions as the guess (Algorithm 1 has others, up to ten times
    // shorter or longer at the same b): within the factor 2 a Newton step on a may take
    if (!(sol->fillet.b > 0.5 * guess_a && sol->fillet.b < 2 * guess_a)) return nullptr;
    if (!(sol->fillet.b <= a_cap)) {
      if (past_cap) *past_cap = true;
      return nullptr;
    }
    BiclothoidSolution forward{reversed(sol->fillet.curve, sol->end), sol->fillet.b, b_cap};
    store.push_back(
        Trial{forward, sol->dlen_da / sol->db_da, 1 / sol->db_da, sol->fillet.curve.start.p, {}, {}, false});
    return &store.back();
  };
  const auto solve_at_end_bound = [&](const Trial& from) -> Trial* {
    const BiclothoidSolution& f = from.fillet;
    if (!(from.db_da > 0) || !std::isfinite(from.db_da)) return nullptr;
    const double da = (b_cap - f.b) / from.db_da;
    const double guess_a = f.a + da;
    const double guess_len = length(f.curve) + from.dlen_da * da;
    if (!(guess_a > 0 && guess_a < a_cap && guess_len > 0)) return nullptr;
    return solve_from_end(guess_a, guess_len, Effort::kGuessOnly, nullptr);
  };
  const auto measure = [&](Trial* t) {
    if (!t->measured) {
      const Measured m = measure_deviation(t->fillet, work, true);
      t->deviation = m.deviation;
      t->witness = m.witness;
      t->measured = true;
    }
    return t->deviation.max();
  };
  const auto fail = [&](const std::string& why) {
    result.outcome = {Status::kNotConverged, why};
    return result;
  };

  // dy/dx (x = log a, y below) at a measured trial, from the term that sets y: the end bound
  // through db/da, the deviation D through its witness (measure_deviation) and the motion of
  // the fillet point V(s) at a fixed s as a grows: the start slides back along q1
  // (-T0), the fillet turns with its start tangent (by -kappa1 per unit of a), and its length
  // and turn (delta + kappa1 a + kappa2 b) change along the solve's sensitivities
  const auto slope_at = [&](const Trial& t) {
    const BiclothoidSolution& f = t.fillet;
    const double dev = t.deviation.max();
    if (f.b / b_cap >= dev / tolerance) return f.a * t.db_da / f.b;
    const Witness& w = t.witness;
    Vec2 offset;
    const PointSlopes at = point_slopes_at(f.curve, w.s, offset);
    const Vec2 dv = -direction(f.curve.start.theta) - work.q1.kappa * perp(offset) + at.d_length * t.dlen_da +
                    at.d_turn * (work.q1.kappa + work.q2.kappa * t.db_da);
    double dd = w.u.dot(dv);
    if (w.crossing) dd = (w.slope1 * w.u2.dot(dv) - w.slope2 * dd) / (w.slope1 - w.slope2);
    return f.a * dd / dev;
  };

  // Algorithm 2 with the end bound folded in: the largest a with
  //   y(a) = max(log(dev / tol), log(b / b_cap)) <= 0,
  // both terms growing with a. Newton steps on y against x = log a with the slope above (with
  // the curvature of the two-term deviation law where the deviation sets y)
  // (deviation ~ a^p, p = 1 at a tangent jump, 2 at a curvature jump only, so y is nearly
  // linear in x), secant steps where the slope is not usable, bisection once bracketed steps
  // leave the bracket, stopping at -kReached <= y <= 0.
  // log a_cap, once it is needed (a fit whose first trial lands in the band never needs it)
  double x_cap_value = std::numeric_limits<double>::quiet_NaN();
  const auto x_cap = [&] {
    if (std::isnan(x_cap_value)) x_cap_value = std::log(a_cap);
    return x_cap_value;
  };
  // a first start distance from the small-fillet models: the line-line pair for the tangent
  // jump (deviation ~ a) and, from seed 004 table 1 (arc R10 -> line at 0.1 mm: a = 6.5 mm),
  // dev ~ |kappa jump| a^2 / 42 for the curvature jump; where both act, the share of the pair's
  // start that small fillets take (biclothoid_mixed_shares)
  const double kappa_jump = std::abs(work.q1.kappa - work.q2.kappa);
  const ClothoidPair pair = tangent_jump ? clothoid_pair_for_deviation(turn_shape, tolerance) : ClothoidPair{};
  const double a_angle = tangent_jump ? pair.tangent_length : std::numeric_limits<double>::infinity();
  const double a_curvature =
      kappa_jump > 0 ? std::sqrt(42.0 * tolerance / kappa_jump) : std::numeric_limits<double>::infinity();
  const bool mixed = std::isfinite(a_angle) && std::isfinite(a_curvature);
  const BiclothoidMixedShares shares =
      mixed ? biclothoid_mixed_shares(a_angle / a_curvature, delta * (work.q2.kappa - work.q1.kappa) > 0)
            : BiclothoidMixedShares{1.0, tangent_jump ? 1.0 : kEndShare};
  double a_model = mixed ? a_angle * shares.start : std::min(a_angle, a_curvature);
  // at a curvature jump alone, its start as the arcs' curvatures move it
  // (biclothoid_curvature_jump_start), aimed half the band inside the tolerance (the deviation
  // grows as a^2 there); at u of the start cap where that is shorter (there the start is the
  // cap, whatever the model, and u stays within the fit's range, |kappa1| a_cap <= pi / 4)
  if (!tangent_jump && std::isfinite(a_curvature)) {
    const double a = std::min(a_curvature, a_cap);
    a_model *= std::exp(biclothoid_curvature_jump_start(work.q1.kappa * a, work.q2.kappa * a) - 0.25 * kReached);
  }
  // at a tangent jump, the arcs' own curvatures at first order in kappa a
  // (biclothoid_arc_sensitivity), with a at most the start cap (kappa a <= pi / 4); where the
  // curvature jump acts too, also their second order as at the curvature jump alone, by the
  // share w of the deviation it makes at the model's start (dev = A a + B a^2, the pair's
  // A = tol / a_angle and the jump's B = tol / a_curvature^2: w = B a / (A + B a))
  if (tangent_jump) {
    const BiclothoidArcSensitivity g = biclothoid_arc_sensitivity(delta);
    const double a = std::min(a_model, a_cap);
    double log_shift = std::copysign(1.0, delta) * (g.in * work.q1.kappa + g.out * work.q2.kappa) * a;
    if (mixed) {
      const double w = a_model * a_angle / (a_curvature * a_curvature + a_model * a_angle);
      log_shift += w * (biclothoid_curvature_jump_start(work.q1.kappa * a, work.q2.kappa * a) - kCurvatureJumpAtZero);
    }
    a_model *= std::exp(log_shift);
  }
  // the end bound, as a start distance, where the model's fillet would end past it: b_cap where
  // there is a tangent jump (the line-line pair is symmetric, b = a), b_cap / kEndShare at a
  // curvature jump alone (kEndShare). (Where both act, b_cap / kEndShare, or b_cap over the
  // end share, started some corners on another branch of Algorithm 1's solutions.) Where the
  // model's fillet ends short of it (b = end share x a_model), the model is the start: b_cap,
  // up to 2.3 times shorter at a tangent jump that the curvature jump dominates, cost a solve
  // there and one more from the end bound.
  const bool ends_short = tangent_jump && a_model * shares.end <= b_cap;
  const double a_start =
      ends_short ? std::min(a_cap, a_model) : std::min({a_cap, tangent_jump ? b_cap : b_cap / kEndShare, a_model});
  const double p_guess = a_angle <= a_curvature ? 1.0 : 2.0;
  struct Point {
    double x;
    double y;
    Trial* trial;
  };
  const auto evaluate = [&](double x) -> Point {
    Trial* t = solve(std::min(std::exp(x), a_cap));
    if (!t) return {x, std::numeric_limits<double>::infinity(), nullptr};
    const double y = std::max(std::log(measure(t) / tolerance), std::log(t->fillet.b / b_cap));
    return {x, y, t};
  };
  // the first point. Where the model's fillet ends past the end bound before it reaches the
  // start cap, the fillet that ends at the end bound, solved from the other end with the
  // model's start distance there (b_cap over the end share) and length (the pair's length per
  // unit of tangent length, or a + b at a curvature jump alone) as its guess: where the
  // deviation is within the tolerance there, it is the answer in one solve (solving forward at
  // the model's a took a second, from the end, for it). Where that fillet starts past the
  // start cap (near a reversal, where both caps are where the moves cross again), at the cap;
  // else (or where that solve fails) at a_start; backing off (halving a) while Algorithm 1
  // fails.
  Point cur{0, std::numeric_limits<double>::infinity(), nullptr};
  double a_first = a_start;
  // (b_cap / end share, the solve's guess, can only lie short of the start cap and the model
  // where b_cap lies short of them times the largest end share: the test that skips the
  // shares at the end bound's size on most corners, where the moves are long)
  if (!ends_short && b_cap < (mixed ? kMixedEndMax : shares.end) * std::min(a_cap, a_model)) {
    // the end share at the end bound's size: the shares' rho for the tolerance at which the
    // line-line pair would end at b_cap (a fillet much smaller than the model's is nearer the
    // pair's shape, b = a)
    double end_share = shares.end;
    if (mixed) {
      const double tol_there = clothoid_pair_for_tangent_length(turn_shape, b_cap).deviation;
      const double rho_there = b_cap / std::sqrt(42.0 * tol_there / kappa_jump);
      const double there = biclothoid_mixed_shares(rho_there, delta * (work.q2.kappa - work.q1.kappa) > 0).end;
      if (there > 0) end_share = there;  // (not a number where the pair has no deviation)
    }
    const double guess_a = b_cap / end_share;
    if (guess_a < std::min(a_cap, a_model)) {
      const double per_length = tangent_jump ? pair.half_length / pair.tangent_length : 1.0;
      bool past_cap = false;
      if (Trial* t = solve_from_end(guess_a, per_length * (guess_a + b_cap), Effort::kGuessOnly, &past_cap)) {
        cur = Point{std::log(t->fillet.a), std::max(std::log(measure(t) / tolerance), 0.0), t};
      } else if (past_cap) {
        a_first = a_cap;
      }
    }
  }
  if (!cur.trial) cur = evaluate(std::log(a_first));
  for (int attempt = 0; attempt < 12 && !cur.trial; ++attempt) cur = evaluate(cur.x - std::log(2.0));
  if (!cur.trial) return fail("biclothoid (004 Algorithm 1) did not converge");
  Point prev{0, 0, nullptr};
  double lo = -std::numeric_limits<double>::infinity();  // y <= 0 here
  double hi = std::numeric_limits<double>::infinity();   // y > 0 (or no solution) here
  Trial* best = nullptr;  // the largest a with y <= 0 so far
  double best_y = 0;
  for (int it = 0; it < 60; ++it) {
    if (cur.y <= 0) {
      lo = std::max(lo, cur.x);
      if (!best || cur.trial->fillet.a >= best->fillet.a) {
        best = cur.trial;
        best_y = cur.y;
      }
      if (cur.y >= -kReached || cur.x >= x_cap() - 1e-12) break;
    } else {
      hi = std::min(hi, cur.x);
    }
    // the end bound sets y here and a solve from the other end lands on it exactly
    if (cur.trial && cur.trial->fillet.b / b_cap >= cur.trial->deviation.max() / tolerance) {
      if (Trial* t = solve_at_end_bound(*cur.trial)) {
        const double x = std::log(t->fillet.a);
        const double y = std::max(std::log(measure(t) / tolerance), 0.0);
        // used when it lies inside what is known, or is feasible where a trial rounded past
        // the end bound (b = b_cap (1 + 1e-16): the same a up to rounding); else the step below
        // goes on from cur
        if (x > lo && (x < hi || y <= 0)) {
          prev = cur;
          cur = Point{x, y, t};
          continue;
        }
      }
    }
    // next x: Newton towards the middle of the accepted band (a at most halved or doubled),
    // else a secant step, else the slope guess; bisection when a bracketed step leaves the
    // bracket
    double next;
    const double slope = cur.trial && std::isfinite(cur.y) ? slope_at(*cur.trial) : 0.0;
    if (slope > 0 && std::isfinite(slope)) {
      // Newton, corrected for the curvature of y where the deviation sets it: with the two
      // small-fillet laws dev = A a + B a^2 (the tangent jump's linear, the curvature jump's
      // quadratic), the log-log slope is p = 1 + w, w = B a / (A + B a) the quadratic share,
      // and y'' = dp/dx = w (1 - w) = (p - 1) (2 - p); the step solves
      // y + p dx + y'' dx^2 / 2 = -0.3 kReached (its root nearer 0, plain Newton when none).
      // Against the slope measured at the next trial of the random corners that took three
      // solves, this y'' has the right sign throughout and is within a factor 2 (above for
      // p < 1, below for p > 1.15); plain Newton's miss there, y'' dx^2 / 2, was what sent
      // them past the band.
      const double r = cur.y + 0.3 * kReached;
      double step = r / slope;
      if (cur.trial->fillet.b / b_cap < cur.trial->deviation.max() / tolerance) {
        const double curvature = (slope - 1) * (2 - slope);
        const double disc = slope * slope - 2 * curvature * r;
        if (disc > 0) step = 2 * r / (slope + std::sqrt(disc));
      }
      next = cur.x - std::clamp(step, -std::log(2.0), std::log(2.0));
    } else if (prev.trial && cur.trial && std::isfinite(prev.y) && cur.y != prev.y) {
      next = cur.x - (cur.y + 0.3 * kReached) * (cur.x - prev.x) / (cur.y - prev.y);
    } else if (std::isfinite(cur.y)) {
      next = cur.x - (cur.y + 0.3 * kReached) / p_guess;
    } else {
      next = cur.x - std::log(2.0);
    }
    if (std::isfinite(lo) && std::isfinite(hi)) {
      if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
      if (hi - lo < 1e-13) break;
    } else if (std::isfinite(hi) && !(next < hi)) {
      next = hi - std::log(2.0);
    } else if (std::isfinite(lo) && !(next > lo)) {
      next = lo + std::log(2.0);
    }
    next = std::min(next, x_cap());
    prev = cur;
    cur = evaluate(next);
  }
  if (!best) return fail("no biclothoid fillet met the tolerance (004 Algorithm 2)");
  // limited: the start cap or the end bound is what stops the fillet growing; otherwise the
  // deviation reached the tolerance band unless the iterations ran out
  const bool limited = best->fillet.a >= a_cap * (1 - 1e-12) ||
                       std::log(best->fillet.b / b_cap) >= std::log(measure(best) / tolerance) - 1e-12;
  result.limited = limited;
  result.converged = limited || best_y >= -kReached;
  measure(best);
  result.deviation = best->deviation;
  result.fillet = best->fillet;
  if (result.swapped) {
    result.fillet.curve = reversed(best->fillet.curve, best->end);
    result.fillet.a = best->fillet.b;
    result.fillet.b = best->fillet.a;
  }
  return result;
}

BiclothoidStartFit fit_biclothoid_from_start(const CornerShapes& shapes, double start_distance, double a_max,
                                             double b_max) {
  BiclothoidStartFit result;
  const Caps caps = fillet_caps(shapes, a_max, b_max);
  const double a_cap = caps.a;
  const double b_cap = caps.b;
  using Limit = BiclothoidStartFit::Limit;
  // why the first (largest) start distance that failed did not fit
  Limit first_failure = Limit::kNone;
  const auto fits = [&](double a) -> std::optional<BiclothoidSolution> {
    auto sol = fit_biclothoid_at(shapes, a);
    if (!sol || sol->b > b_cap) {
      if (first_failure == Limit::kNone) first_failure = sol ? Limit::kOutgoing : Limit::kNoSolution;
      return std::nullopt;
    }
    return sol;
  };
  double a = std::min(start_distance, a_cap);
  if (a < start_distance) first_failure = Limit::kIncoming;
  std::optional<BiclothoidSolution> best = fits(a);
  if (!best) {
    // halve until a fillet fits, then bisect in log a between that and the last that did not
    double hi = a;
    for (int i = 0; i < 60 && !best; ++i) {
      hi = a;
      a *= 0.5;
      best = fits(a);
    }
    if (!best) {
      result.outcome = {Status::kNotConverged, "no biclothoid fillet fits at start distance " +
                                                   format_mm(start_distance) + " or any shorter (004 Algorithm 1)"};
      return result;
    }
    double lo = a;
    while (hi / lo > 1 + 1e-9) {
      const double mid = std::sqrt(lo * hi);
      if (auto sol = fits(mid)) {
        lo = mid;
        best = sol;
      } else {
        hi = mid;
      }
    }
  }
  result.fillet = *best;
  result.limit = best->a < start_distance * (1 - 1e-12) ? first_failure : Limit::kNone;
  result.deviation = biclothoid_deviation(*best, shapes);
  return result;
}

}  // namespace blendbench
