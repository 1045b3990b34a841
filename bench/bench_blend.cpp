// Time one corner fit per corner type and method through the public fit_*_corner functions
// (seed 004 section 7.3 reports 5 us for line-line and 42 us for line-arc / arc-arc on a 2.4 GHz
// dual core). BM_ToleranceProgram blends a program of 10^4 random corners by parameter and at a
// tolerance (equal tolerance, issue 44). The targets, the tolerance loop of Algorithm 2 included, are on the
// distribution below: a median of 0.2 us for line-line and 2 us for line-arc and arc-arc, and a
// 99th percentile of 8 us.
// The corners are those of seed 004 listing 1 and table 2, in metres, and a spread of line-arc
// and arc-arc corners (radii 2-1000 mm, kinks 0-120 deg, turning the same or the opposite way).

#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <ctime>
#include <cmath>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <vector>

#include "blendbench/core/units.hpp"
#include "blendbench/geometry/arc_construction.hpp"
#include "blendbench/corner/biclothoid.hpp"
#include "blendbench/corner/blend.hpp"
#include "blendbench/corner/corner.hpp"
#include "blendbench/corner/corner_plane.hpp"
#include "blendbench/geometry/fresnel.hpp"
#include "blendbench/geometry/segment.hpp"
#include "support/random_corner.hpp"

namespace blendbench {
namespace {


Arc xy_arc(const Vec3& start, const Vec3& end, const Vec3& centre, bool clockwise) {
  const ArcBuild built = arc_from_center(start, end, centre, Vec3::UnitZ(), !clockwise);
  if (!built.outcome.ok()) throw std::invalid_argument("xy_arc: " + built.outcome.message);
  return built.arc;
}

CornerInput corner(const Primitive& in, const Primitive& out, Method method, double tolerance, double kappa_max = 0) {
  CornerInput c;
  c.in = in;
  c.out = out;
  c.in_available = 0.5 * length(in);
  c.out_available = 0.5 * length(out);
  c.spec.method = method;
  c.spec.parameter = tolerance;
  c.spec.kappa_max = kappa_max;
  c.name = "bench";
  return c;
}

// seed 004 (Shahzadeh et al.) table 2: two lines with 150 deg between them (a 30 deg deflection)
CornerInput line_line(Method method, double kappa_max = 0) {
  const double alpha = 30 * std::numbers::pi / 180;
  const Vec3 t2(std::cos(alpha), std::sin(alpha), 0);
  return corner(Line{Vec3(-0.01, 0, 0), Vec3(0, 0, 0)}, Line{Vec3(0, 0, 0), 0.01 * t2}, method, 0.1 * kMm, kappa_max);
}

// a line into an R10 arc with a 20 deg kink (tangent discontinuity)
CornerInput line_arc(Method method) {
  const double alpha = -20 * std::numbers::pi / 180;
  const Vec3 t2(std::cos(alpha), std::sin(alpha), 0);
  const Vec3 centre = 10 * kMm * Vec3(-t2.y(), t2.x(), 0);  // turning left
  return corner(Line{Vec3(-0.03, 0, 0), Vec3(0, 0, 0)}, xy_arc(Vec3(0, 0, 0), centre * 2, centre, false), method,
                0.1 * kMm);
}

// seed 004 listing 1 point B: line tangent into the R10 arc (curvature jump only)
CornerInput line_arc_tangent(Method method) {
  return corner(Line{Vec3(-10, 10, 0) * kMm, Vec3(-10, 50, 0) * kMm},
                xy_arc(Vec3(-10, 50, 0) * kMm, Vec3(0, 60, 0) * kMm, Vec3(0, 50, 0) * kMm, true), method, 0.1 * kMm);
}

// seed 004 listing 1 point C: arc R10 into arc R30.01 with a 1.48 deg kink
CornerInput arc_arc(Method method) {
  const double offset = std::sqrt(30.01 * 30.01 - 30.0 * 30.0);
  return corner(xy_arc(Vec3(-10, 50, 0) * kMm, Vec3(0, 60, 0) * kMm, Vec3(0, 50, 0) * kMm, true),
                xy_arc(Vec3(0, 60, 0) * kMm, Vec3(0, 0, 0), Vec3(-offset, 30, 0) * kMm, true), method, 0.1 * kMm);
}

// An arc of radius r (m) turning left (ccw) or right, that ends at the origin heading along
// +x (arrive) or starts there heading at `heading` rad (leave), sweeping `sweep` rad.
Arc arc_arriving(double r, bool ccw, double sweep) {
  const Vec3 centre(0, ccw ? r : -r, 0);
  const double phi = ccw ? -std::numbers::pi / 2 - sweep : std::numbers::pi / 2 + sweep;
  const Vec3 start = centre + r * Vec3(std::cos(phi), std::sin(phi), 0);
  return xy_arc(start, Vec3(0, 0, 0), centre, !ccw);
}
Arc arc_leaving(double r, bool ccw, double heading, double sweep) {
  const Vec3 normal = (ccw ? 1.0 : -1.0) * Vec3(-std::sin(heading), std::cos(heading), 0);
  const Vec3 centre = r * normal;
  const Vec3 radial = -normal;  // centre -> origin
  const double turn = ccw ? sweep : -sweep;
  const Vec3 end = centre + r * Vec3(std::cos(turn) * radial.x() - std::sin(turn) * radial.y(),
                                     std::sin(turn) * radial.x() + std::cos(turn) * radial.y(), 0);
  return xy_arc(Vec3(0, 0, 0), end, centre, !ccw);
}

// arc R r1 (turning left) into arc R r2 after a kink of `kink_deg` to the left, the second arc
// turning left too (same) or right; each arc a quarter turn, tolerance 0.1 mm
CornerInput arc_arc_spread(double r1_mm, double r2_mm, double kink_deg, bool same) {
  const double kink = kink_deg * std::numbers::pi / 180;
  return corner(arc_arriving(r1_mm * kMm, true, std::numbers::pi / 2),
                arc_leaving(r2_mm * kMm, same, kink, std::numbers::pi / 2), Method::kBiclothoid, 0.1 * kMm);
}

// a 50 mm line into arc R r (turning left) after a kink of `kink_deg` to the right
CornerInput line_arc_spread(double r_mm, double kink_deg) {
  const double kink = -kink_deg * std::numbers::pi / 180;
  return corner(Line{Vec3(-0.05, 0, 0), Vec3(0, 0, 0)}, arc_leaving(r_mm * kMm, true, kink, std::numbers::pi / 2),
                Method::kBiclothoid, 0.1 * kMm);
}

void run(benchmark::State& state, const CornerInput& input, CornerFit (*fit)(const CornerInput&)) {
  for (auto _ : state) {
    CornerFit result = fit(input);
    benchmark::DoNotOptimize(result);
  }
}

void BM_BiclothoidLineLine(benchmark::State& s) { run(s, line_line(Method::kBiclothoid), fit_biclothoid_corner); }
void BM_BiclothoidLineArc(benchmark::State& s) { run(s, line_arc(Method::kBiclothoid), fit_biclothoid_corner); }
void BM_BiclothoidLineArcTangent(benchmark::State& s) {
  run(s, line_arc_tangent(Method::kBiclothoid), fit_biclothoid_corner);
}
void BM_BiclothoidArcArc(benchmark::State& s) { run(s, arc_arc(Method::kBiclothoid), fit_biclothoid_corner); }
// sized by a 3 mm start distance instead of the 0.1 mm tolerance: Algorithm 1 once, plus the
// deviation measured for the report
CornerInput by_start_distance(CornerInput c) {
  c.spec.parameter = 0;
  c.spec.start_distance = 3 * kMm;
  return c;
}
void BM_BiclothoidLineArcStartDistance(benchmark::State& s) {
  run(s, by_start_distance(line_arc(Method::kBiclothoid)), fit_biclothoid_corner);
}
void BM_BiclothoidArcArcStartDistance(benchmark::State& s) {
  run(s, by_start_distance(arc_arc(Method::kBiclothoid)), fit_biclothoid_corner);
}
void BM_BiclothoidCorner(benchmark::State& s, const CornerInput& input) { run(s, input, fit_biclothoid_corner); }
BENCHMARK_CAPTURE(BM_BiclothoidCorner, LineArc_R2_kink90, line_arc_spread(2, 90));
BENCHMARK_CAPTURE(BM_BiclothoidCorner, LineArc_R1000_kink2, line_arc_spread(1000, 2));
BENCHMARK_CAPTURE(BM_BiclothoidCorner, ArcArc_R10_R20_kink30, arc_arc_spread(10, 20, 30, true));
BENCHMARK_CAPTURE(BM_BiclothoidCorner, ArcArc_R10_R10_inflection, arc_arc_spread(10, 10, 0, false));
BENCHMARK_CAPTURE(BM_BiclothoidCorner, ArcArc_R20_R50_tangent, arc_arc_spread(20, 50, 0, true));
BENCHMARK_CAPTURE(BM_BiclothoidCorner, ArcArc_R20_R20_kink90_opposite, arc_arc_spread(20, 20, 90, false));
BENCHMARK_CAPTURE(BM_BiclothoidCorner, ArcArc_R100_R1000_kink5, arc_arc_spread(100, 1000, 5, true));
BENCHMARK_CAPTURE(BM_BiclothoidCorner, ArcArc_R2_R3_kink120, arc_arc_spread(2, 3, 120, true));

void BM_ClothoidLineLine(benchmark::State& s) { run(s, line_line(Method::kClothoid), fit_clothoid_corner); }
void BM_ClothoidLineLineCapped(benchmark::State& s) {
  // a curvature cap below the pair's 0.47 1/mm: clothoid-arc-clothoid
  run(s, line_line(Method::kClothoid, 400.0), fit_clothoid_corner);
}
void BM_ClothoidLineArc(benchmark::State& s) { run(s, line_arc(Method::kClothoid), fit_clothoid_corner); }
void BM_ClothoidArcArc(benchmark::State& s) { run(s, arc_arc(Method::kClothoid), fit_clothoid_corner); }

void BM_Fresnel(benchmark::State& state) {
  double x = 0.3;
  for (auto _ : state) {
    benchmark::DoNotOptimize(fresnel(x));
    x = x < 3.0 ? x + 0.01 : 0.3;
  }
}

void BM_ClothoidXy(benchmark::State& state) {
  // the second clothoid of listing 1's fillet S1S2: kappa 0.124 -> 0 1/mm over 7.76 mm
  double s = 7.76e-3;
  for (auto _ : state) {
    benchmark::DoNotOptimize(clothoid_xy(124.0, -1.6e4, s));
    s = s < 7.8e-3 ? s + 1e-7 : 7.76e-3;
  }
}

// The distribution over random corners: those of the property tests (test::random_corner,
// seeds 1000 + i, the kind i % 4, as Biclothoid.RandomCornersAreG2AndWithinTolerance; the
// random parameter is the corner distance for arc and TP for bezier), for every method; each fit
// timed on its own with the steady clock and its fastest of the benchmark's repetitions kept
// (the clock's own ~20 ns included). Counters: median, p90, p99, largest (us) and the share of
// corners over 8 us. `kind` empty: all 8000 corners of the four kinds, in the order the property
// test makes them (a program's corners come mixed, so each fit starts with the caches and branch
// history of another kind's fit; the 99th percentile is over all of them).
void distribution(benchmark::State& state, std::optional<test::CornerKind> kind, Method method,
                  CornerFit (*fit)(const CornerInput&)) {
  constexpr int kCorners = 2000;
  std::vector<CornerInput> corners;
  for (int i = 0; i < kCorners * 4; ++i) {
    const auto kind_i = static_cast<test::CornerKind>(i % 4);
    if (kind && kind_i != *kind) continue;
    auto rng = test::make_rng(1000 + static_cast<std::uint64_t>(i));
    corners.push_back(test::random_corner(rng, kind_i, method).input);
  }
  std::vector<double> best(corners.size(), 1e30);
  using Clock = std::chrono::steady_clock;
  for (auto _ : state) {
    for (std::size_t k = 0; k < corners.size(); ++k) {
      const auto t0 = Clock::now();
      CornerFit result = fit(corners[k]);
      const auto t1 = Clock::now();
      benchmark::DoNotOptimize(result);
      best[k] = std::min(best[k], std::chrono::duration<double, std::micro>(t1 - t0).count());
    }
  }
  std::vector<double> sorted = best;
  std::sort(sorted.begin(), sorted.end());
  const auto at = [&](double q) { return sorted[static_cast<std::size_t>(q * static_cast<double>(sorted.size() - 1))]; };
  state.counters["p50_us"] = at(0.5);
  state.counters["p90_us"] = at(0.9);
  state.counters["p99_us"] = at(0.99);
  state.counters["max_us"] = sorted.back();
  state.counters["over_8us"] = static_cast<double>(std::count_if(sorted.begin(), sorted.end(), [](double t) { return t > 8; })) /
                               static_cast<double>(sorted.size());
}
// With the distribution, the solves of seed 004's Algorithm 1 that Algorithm 2 takes on the
// planar corners with an arc (fit_biclothoid_with_tolerance), untimed: their mean and the share
// of fits that need three or more.
void BM_BiclothoidRandom(benchmark::State& s, std::optional<test::CornerKind> kind) {
  distribution(s, kind, Method::kBiclothoid, fit_biclothoid_corner);
  if (kind == test::CornerKind::kLineLine) return;
  int fits = 0;
  int solves = 0;
  int over_two = 0;
  for (int i = 0; i < 8000; ++i) {
    const auto kind_i = static_cast<test::CornerKind>(i % 4);
    if (kind ? kind_i != *kind : kind_i == test::CornerKind::kLineLine) continue;
    auto rng = test::make_rng(1000 + static_cast<std::uint64_t>(i));
    const CornerInput c = test::random_corner(rng, kind_i, Method::kBiclothoid).input;
    const PlanarCorner geometry = planar_corner(c.in, c.out);
    if (!geometry.planar || (!(geometry.angle > 1e-9) && geometry.same_curvature)) continue;  // no Algorithm 2
    const BiclothoidToleranceFit fit =
        fit_biclothoid_with_tolerance(geometry.shapes, c.spec.parameter, c.in_available, c.out_available);
    ++fits;
    solves += fit.solves;
    over_two += fit.solves > 2 ? 1 : 0;
  }
  s.counters["solves_mean"] = static_cast<double>(solves) / std::max(fits, 1);
  s.counters["over_2_solves"] = static_cast<double>(over_two) / std::max(fits, 1);
}
// What a one-solve fit is made of: over the random corners of one kind whose tolerance fit
// (Algorithm 2) took a single solve of Algorithm 1 (the median fit's case), each part timed on its
// own, the fastest of the benchmark's repetitions kept per corner, and its median reported (us):
// the whole corner (fit_biclothoid_corner: plane, fit, output), the corner plane
// (planar_corner), the tolerance fit (fit_biclothoid_with_tolerance), Algorithm 1 alone from its
// cold guess at the start distance the fit found (fit_biclothoid_at, in the fit's orientation:
// from the more curved move), and the deviation of the fitted fillet both ways
// (biclothoid_deviation; inside the fit the measure stops refining the smaller direction, so it
// costs somewhat less there). The two big parts are each needed once by any fit that is checked
// against its tolerance.
void BM_BiclothoidParts(benchmark::State& state, test::CornerKind kind) {
  struct Part {
    CornerInput input;
    PlanarCorner geometry;
    CornerShapes work;  // the fit's orientation
    double a = 0;       // its start distance there
    BiclothoidSolution fillet;
  };
  std::vector<Part> parts;
  for (int i = 0; i < 8000; ++i) {
    if (static_cast<test::CornerKind>(i % 4) != kind) continue;
    auto rng = test::make_rng(1000 + static_cast<std::uint64_t>(i));
    Part p;
    p.input = test::random_corner(rng, kind, Method::kBiclothoid).input;
    p.geometry = planar_corner(p.input.in, p.input.out);
    if (!p.geometry.planar) continue;
    const BiclothoidToleranceFit fit = fit_biclothoid_with_tolerance(p.geometry.shapes, p.input.spec.parameter,
                                                                     p.input.in_available, p.input.out_available);
    if (fit.solves != 1 || !fit.outcome.ok()) continue;
    p.work = fit.swapped ? reversed(p.geometry.shapes) : p.geometry.shapes;
    p.a = fit.swapped ? fit.fillet.b : fit.fillet.a;
    p.fillet = fit.fillet;
    parts.push_back(p);
  }
  constexpr std::size_t kParts = 5;
  std::vector<std::array<double, kParts>> best(parts.size());
  for (auto& b : best) b.fill(1e30);
  using Clock = std::chrono::steady_clock;
  // as in `distribution`: the result is released after the clock stops
  const auto time = [](double& slot, const auto& f) {
    const auto t0 = Clock::now();
    auto result = f();
    const auto t1 = Clock::now();
    benchmark::DoNotOptimize(result);
    slot = std::min(slot, std::chrono::duration<double, std::micro>(t1 - t0).count());
  };
  for (auto _ : state) {
    for (std::size_t k = 0; k < parts.size(); ++k) {
      const Part& p = parts[k];
      time(best[k][0], [&] { return fit_biclothoid_corner(p.input); });
      time(best[k][1], [&] { return planar_corner(p.input.in, p.input.out); });
      time(best[k][2], [&] {
        return fit_biclothoid_with_tolerance(p.geometry.shapes, p.input.spec.parameter, p.input.in_available,
                                             p.input.out_available);
      });
      time(best[k][3], [&] { return fit_biclothoid_at(p.work, p.a); });
      time(best[k][4], [&] { return biclothoid_deviation(p.fillet, p.geometry.shapes); });
    }
  }
  const std::array<const char*, kParts> names = {"corner_p50_us", "plane_p50_us", "tolerance_fit_p50_us",
                                                 "algorithm1_p50_us", "deviation_p50_us"};
  for (std::size_t j = 0; j < kParts; ++j) {
    std::vector<double> column;
    column.reserve(best.size());
    for (const auto& b : best) column.push_back(b[j]);
    std::nth_element(column.begin(), column.begin() + static_cast<std::ptrdiff_t>(column.size() / 2), column.end());
    state.counters[names[j]] = column.empty() ? 0.0 : column[column.size() / 2];
  }
  state.counters["corners"] = static_cast<double>(parts.size());
}
void BM_ClothoidRandom(benchmark::State& s, test::CornerKind kind) {
  distribution(s, kind, Method::kClothoid, fit_clothoid_corner);
}
void BM_ArcRandom(benchmark::State& s, test::CornerKind kind) { distribution(s, kind, Method::kArc, fit_arc_corner); }
void BM_BezierRandom(benchmark::State& s, test::CornerKind kind) {
  distribution(s, kind, Method::kBezier, fit_bezier_corner);
}
// Equal tolerance (issue 44): a program of 10^4 random corners blended whole (blend(), every
// corner fitted and measured as a run does), each method sized by its plain parameter and by a
// tolerance, for the cost per corner of solving the parameter. The program: lines of 1-20 mm
// (60 %) and arcs of radius 2-50 mm turning 0.2-2 rad, in a plane; a quarter of the junctions
// tangent, the others turning by 5-150 degrees in that plane; a fifth of the arcs in a plane
// tilted by 0.2-1.2 rad about their start tangent (a non-planar corner at their start), which
// the path then goes on in. The same program for every case (seed 44).
Program random_program(std::size_t moves) {
  auto rng = test::make_rng(44);
  const auto uniform = [&](double lo, double hi) { return test::uniform(rng, lo, hi); };
  Program program;
  program.moves.reserve(moves);
  Vec3 p = Vec3::Zero();
  Vec3 t = Vec3::UnitX();
  Vec3 n = Vec3::UnitZ();  // the plane the path goes on in
  for (std::size_t k = 0; k < moves; ++k) {
    if (k > 0 && uniform(0, 1) >= 0.25) {
      const double turn = uniform(5, 150) * std::numbers::pi / 180 * (uniform(0, 1) < 0.5 ? 1 : -1);
      t = (Eigen::AngleAxisd(turn, n) * t).normalized();
    }
    Move move;
    move.limits = {0.1, 2.0, 2.0, 50.0};
    if (uniform(0, 1) < 0.6) {
      move.geometry = Line{p, p + test::log_uniform(rng, 1e-3, 20e-3) * t};
    } else {
      if (uniform(0, 1) < 0.2) n = (Eigen::AngleAxisd(uniform(0.2, 1.2), t) * n).normalized();
      move.geometry = test::arc_leaving(p, t, n, uniform(0, 1) < 0.5 ? 1.0 : -1.0, test::log_uniform(rng, 2e-3, 50e-3),
                                        uniform(0.2, 2.0));
    }
    const double len = length(move.geometry);
    p = point(move.geometry, len);
    t = tangent(move.geometry, len);
    t = (t - t.dot(n) * n).normalized();  // (rounding)
    program.moves.push_back(std::move(move));
  }
  return program;
}

// Blends the random program with every move's transition `method` sized by `parameter` (m) or,
// where `tolerance` > 0, by that tolerance (m); counters: processor us per corner (the fastest
// blend of the iterations), and with a tolerance the share of corners that reached it.
void BM_ToleranceProgram(benchmark::State& state, Method method, double parameter, double tolerance) {
  constexpr std::size_t kMoves = 10001;
  Program program = random_program(kMoves);
  for (Move& move : program.moves) {
    move.transition.method = method;
    move.transition.parameter = tolerance > 0 ? 0.0 : parameter;
    move.transition.tolerance = tolerance;
  }
  std::size_t reached = 0;
  // s, the least processor time of a blend over the iterations: the machine is shared, and wall
  // time there counts other processes' work (it ran at twice the processor time when measured)
  double fastest = 1e30;
  for (auto _ : state) {
    const std::clock_t t0 = std::clock();
    Path path = blend(program);
    fastest = std::min(fastest, static_cast<double>(std::clock() - t0) / CLOCKS_PER_SEC);
    reached = static_cast<std::size_t>(std::count_if(path.corners.begin(), path.corners.end(),
                                                     [](const CornerReport& r) { return r.tolerance_reached; }));
    benchmark::DoNotOptimize(path);
  }
  state.counters["us_per_corner"] = fastest * 1e6 / static_cast<double>(kMoves - 1);
  state.counters["reached_share"] = static_cast<double>(reached) / static_cast<double>(kMoves - 1);
}
// plain parameters of the same order as the tolerance's solutions (0.1 mm): arc and TP 0.5 mm
BENCHMARK_CAPTURE(BM_ToleranceProgram, ArcParameter, Method::kArc, 0.5e-3, 0.0)->Unit(benchmark::kMillisecond)->Iterations(5);
BENCHMARK_CAPTURE(BM_ToleranceProgram, ArcTolerance, Method::kArc, 0.0, 0.1e-3)->Unit(benchmark::kMillisecond)->Iterations(5);
BENCHMARK_CAPTURE(BM_ToleranceProgram, BezierParameter, Method::kBezier, 0.5e-3, 0.0)->Unit(benchmark::kMillisecond)->Iterations(5);
BENCHMARK_CAPTURE(BM_ToleranceProgram, BezierTolerance, Method::kBezier, 0.0, 0.1e-3)->Unit(benchmark::kMillisecond)->Iterations(5);
BENCHMARK_CAPTURE(BM_ToleranceProgram, ClothoidParameter, Method::kClothoid, 0.1e-3, 0.0)->Unit(benchmark::kMillisecond)->Iterations(5);
BENCHMARK_CAPTURE(BM_ToleranceProgram, ClothoidTolerance, Method::kClothoid, 0.0, 0.1e-3)->Unit(benchmark::kMillisecond)->Iterations(5);
BENCHMARK_CAPTURE(BM_ToleranceProgram, BiclothoidParameter, Method::kBiclothoid, 0.1e-3, 0.0)->Unit(benchmark::kMillisecond)->Iterations(5);
BENCHMARK_CAPTURE(BM_ToleranceProgram, BiclothoidTolerance, Method::kBiclothoid, 0.0, 0.1e-3)->Unit(benchmark::kMillisecond)->Iterations(5);

BENCHMARK_CAPTURE(BM_BiclothoidRandom, LineLine, test::CornerKind::kLineLine)->Iterations(5);
BENCHMARK_CAPTURE(BM_BiclothoidRandom, LineArc, test::CornerKind::kLineArc)->Iterations(5);
BENCHMARK_CAPTURE(BM_BiclothoidRandom, ArcLine, test::CornerKind::kArcLine)->Iterations(5);
BENCHMARK_CAPTURE(BM_BiclothoidRandom, ArcArc, test::CornerKind::kArcArc)->Iterations(5);
BENCHMARK_CAPTURE(BM_BiclothoidRandom, All, std::nullopt)->Iterations(5);
BENCHMARK_CAPTURE(BM_BiclothoidParts, LineArc, test::CornerKind::kLineArc)->Iterations(5);
BENCHMARK_CAPTURE(BM_BiclothoidParts, ArcLine, test::CornerKind::kArcLine)->Iterations(5);
BENCHMARK_CAPTURE(BM_BiclothoidParts, ArcArc, test::CornerKind::kArcArc)->Iterations(5);
BENCHMARK_CAPTURE(BM_ClothoidRandom, LineLine, test::CornerKind::kLineLine)->Iterations(5);
BENCHMARK_CAPTURE(BM_ClothoidRandom, LineArc, test::CornerKind::kLineArc)->Iterations(5);
BENCHMARK_CAPTURE(BM_ClothoidRandom, ArcLine, test::CornerKind::kArcLine)->Iterations(5);
BENCHMARK_CAPTURE(BM_ClothoidRandom, ArcArc, test::CornerKind::kArcArc)->Iterations(5);
BENCHMARK_CAPTURE(BM_ArcRandom, LineLine, test::CornerKind::kLineLine)->Iterations(5);
BENCHMARK_CAPTURE(BM_ArcRandom, LineArc, test::CornerKind::kLineArc)->Iterations(5);
BENCHMARK_CAPTURE(BM_ArcRandom, ArcLine, test::CornerKind::kArcLine)->Iterations(5);
BENCHMARK_CAPTURE(BM_ArcRandom, ArcArc, test::CornerKind::kArcArc)->Iterations(5);
BENCHMARK_CAPTURE(BM_BezierRandom, LineLine, test::CornerKind::kLineLine)->Iterations(5);
BENCHMARK_CAPTURE(BM_BezierRandom, LineArc, test::CornerKind::kLineArc)->Iterations(5);
BENCHMARK_CAPTURE(BM_BezierRandom, ArcLine, test::CornerKind::kArcLine)->Iterations(5);
BENCHMARK_CAPTURE(BM_BezierRandom, ArcArc, test::CornerKind::kArcArc)->Iterations(5);

BENCHMARK(BM_BiclothoidLineLine);
BENCHMARK(BM_BiclothoidLineArc);
BENCHMARK(BM_BiclothoidLineArcTangent);
BENCHMARK(BM_BiclothoidArcArc);
BENCHMARK(BM_BiclothoidLineArcStartDistance);
BENCHMARK(BM_BiclothoidArcArcStartDistance);
BENCHMARK(BM_ClothoidLineLine);
BENCHMARK(BM_ClothoidLineLineCapped);
BENCHMARK(BM_ClothoidLineArc);
BENCHMARK(BM_ClothoidArcArc);
BENCHMARK(BM_Fresnel);
BENCHMARK(BM_ClothoidXy);

}  // namespace
}  // namespace blendbench

BENCHMARK_MAIN();
