#include "planner/timing.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "planner/blend.hpp"
#include "planner/scurve.hpp"
#include "../support/property.hpp"

namespace blendbench {
namespace {

constexpr double kRel = 1e-9;  // relative slack on every limit (issue 4)
constexpr double kEps = std::numeric_limits<double>::epsilon();
constexpr double kFeedShareTol = 1e-9;

// Limits that apply at path arc length s: those of every piece touching s (both at a junction).
struct LocalLimits {
  double v_lim = std::numeric_limits<double>::infinity();  // v_lim(s), 004 eq. 25-27
  double kappa = 0;                                         // largest curvature at s
  double a_normal = std::numeric_limits<double>::infinity();  // the bound on kappa v^2
  double acceleration = 0, deceleration = 0, jerk = 0, feed = 0;  // the largest of the pieces
};

LocalLimits limits_at(const Path& path, double s) {
  LocalLimits out;
  const auto& pieces = path.pieces();
  const double tol = 1e-12 * std::max(1.0, path.length());
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    if (s < path.offset(k) - tol || s > path.offset(k + 1) + tol) continue;
    const PathPiece& p = pieces[k];
    const double local = std::clamp(s - path.offset(k), 0.0, length(p.segment));
    const double kappa = curvature_vector(p.segment, local).norm();
    const double c = sharpness(p.segment, local);
    out.v_lim = std::min(out.v_lim, std::min(p.limits.velocity,
                                             curvature_speed_limit(kappa, c, p.limits.acceleration, p.limits.jerk)));
    if (kappa > out.kappa) {
      out.kappa = kappa;
      out.a_normal = p.limits.acceleration;
    }
    out.acceleration = std::max(out.acceleration, p.limits.acceleration);
    out.deceleration = std::max(out.deceleration, p.limits.deceleration);
    out.jerk = std::max(out.jerk, p.limits.jerk);
    out.feed = std::max(out.feed, p.limits.velocity);
  }
  return out;
}

// Margins of a sampled profile: the largest ratio value/limit seen (<= 1 + kRel required).
struct Margins {
  double v = 0, a = 0, j = 0, normal = 0;
};

// Checks a timing against the path: sampling grid, start and end at rest, monotone s, and on
// every sample v <= v_lim(s), kappa v^2 <= a, |a_t|, |j_t| within the limits; finite
// differences of s (stencil averages of v, a, j) within the largest limits of the pieces the
// stencil touches, up to the rounding noise of s; v = 0 at every stop (the samples on either
// side of a stop are within J dt^2 / 2 of rest: a jerk-limited arrival at rest).
Margins expect_valid(const Path& path, const Timing& timing, const std::string& where) {
  Margins m;
  const auto& x = timing.samples;
  EXPECT_TRUE(timing.outcome.ok()) << where << " " << timing.outcome.message;
  if (x.empty()) {
    ADD_FAILURE() << where << ": no samples";
    return m;
  }
  const double dt = timing.dt;
  EXPECT_EQ(x.size(), static_cast<std::size_t>(std::ceil(timing.cycle_time / dt)) + 1) << where;
  EXPECT_EQ(x.front().s, 0.0) << where;
  EXPECT_EQ(x.front().v, 0.0) << where;
  EXPECT_EQ(x.back().s, path.length()) << where;
  EXPECT_EQ(x.back().v, 0.0) << where;
  EXPECT_EQ(x.back().a, 0.0) << where;
  std::vector<LocalLimits> lim(x.size());
  for (std::size_t k = 0; k < x.size(); ++k) {
    lim[k] = limits_at(path, x[k].s);
    EXPECT_EQ(x[k].t, static_cast<double>(k) * dt) << where;
    if (k > 0) {
      EXPECT_GE(x[k].s, x[k - 1].s) << where << " k=" << k;
    }
    EXPECT_GE(x[k].v, 0.0) << where << " k=" << k;
    m.v = std::max(m.v, x[k].v / lim[k].v_lim);
    m.normal = std::max(m.normal, lim[k].kappa * x[k].v * x[k].v / lim[k].a_normal);
    m.a = std::max(m.a, x[k].a >= 0 ? x[k].a / lim[k].acceleration : -x[k].a / lim[k].deceleration);
    m.j = std::max(m.j, std::abs(x[k].j) / lim[k].jerk);
  }
  EXPECT_LE(m.v, 1 + kRel) << where;
  EXPECT_LE(m.normal, 1 + kRel) << where;
  EXPECT_LE(m.a, 1 + kRel) << where;
  EXPECT_LE(m.j, 1 + kRel) << where;

  // finite differences over stencils of 2, 3 and 4 samples
  const double noise = 4 * kEps * std::max(path.length(), 1e-300);
  const auto widest = [&](std::size_t k0, std::size_t k1) {
    LocalLimits w;
    for (std::size_t k = k0; k <= k1; ++k) {
      w.feed = std::max(w.feed, lim[k].feed);
      w.acceleration = std::max(w.acceleration, lim[k].acceleration);
      w.deceleration = std::max(w.deceleration, lim[k].deceleration);
      w.jerk = std::max(w.jerk, lim[k].jerk);
    }
    return w;
  };
  for (std::size_t k = 0; k + 1 < x.size(); ++k) {
    const double v = (x[k + 1].s - x[k].s) / dt;
    EXPECT_LE(v, widest(k, k + 1).feed * (1 + kRel) + 2 * noise / dt) << where << " k=" << k;
  }
  for (std::size_t k = 1; k + 1 < x.size(); ++k) {
    const double a = (x[k + 1].s - 2 * x[k].s + x[k - 1].s) / (dt * dt);
    const LocalLimits w = widest(k - 1, k + 1);
    EXPECT_LE(a, w.acceleration * (1 + kRel) + 4 * noise / (dt * dt)) << where << " k=" << k;
    EXPECT_GE(a, -w.deceleration * (1 + kRel) - 4 * noise / (dt * dt)) << where << " k=" << k;
  }
  for (std::size_t k = 1; k + 2 < x.size(); ++k) {
    const double j = (x[k + 2].s - 3 * x[k + 1].s + 3 * x[k].s - x[k - 1].s) / (dt * dt * dt);
    EXPECT_LE(std::abs(j), widest(k - 1, k + 2).jerk * (1 + kRel) + 8 * noise / (dt * dt * dt))
        << where << " k=" << k;
  }

  // at rest at every stop
  const auto& pieces = path.pieces();
  for (std::size_t p = 1; p < pieces.size(); ++p) {
    if (!pieces[p].stop_before) continue;
    const double s_stop = path.offset(p);
    const double jerk = std::max(pieces[p - 1].limits.jerk, pieces[p].limits.jerk);
    const auto after = std::lower_bound(x.begin(), x.end(), s_stop, [](const TimedSample& a, double s) { return a.s < s; });
    if (after == x.end()) continue;
    EXPECT_LE(after->v, 0.5 * jerk * dt * dt * (1 + kRel)) << where << " stop before piece " << p;
    if (after != x.begin()) {
      EXPECT_LE(std::prev(after)->v, 0.5 * jerk * dt * dt * (1 + kRel)) << where;
    }
  }
  return m;
}

Move line_move(const Vec3& a, const Vec3& b, const Limits& limits) {
  Move move;
  move.geometry = Line{a, b};
  move.limits = limits;
  return move;
}

TEST(Timing, SingleLineIsTheAnalyticScurve) {
  // dv = 0.5 >= a^2/j = 0.2: each ramp 0.5/2 + 2/20 = 0.35 s over 0.0875 m; 0.825 m cruised
  Program program;
  program.moves = {line_move({0, 0, 0}, {1, 0, 0}, {0.5, 2.0, 2.0, 20.0})};
  const Path path = blend(program);
  const Timing timing = plan_timing(path);
  ASSERT_TRUE(timing.outcome.ok());
  EXPECT_NEAR(timing.cycle_time, 0.35 + 1.65 + 0.35, 1e-12);
  EXPECT_EQ(timing.samples.size(), 2351u);
  ASSERT_EQ(timing.pieces.size(), 1u);
  EXPECT_EQ(timing.pieces[0].binding, "feed");
  EXPECT_DOUBLE_EQ(timing.pieces[0].v_peak, 0.5);
  EXPECT_NEAR(timing.feed_share, 1.65 / 2.35, kFeedShareTol);
  // mid-cruise sample
  EXPECT_NEAR(timing.samples[1000].v, 0.5, 1e-12);
  EXPECT_NEAR(timing.samples[1000].s, 0.0875 + 0.5 * (1.0 - 0.35), 1e-12);
  expect_valid(path, timing, "single line");
}

TEST(Timing, ExactStopSquareStopsAtEveryCorner) {
  const Limits lim{0.2, 1.0, 1.0, 10.0};
  Program program;
  program.moves = {line_move({0, 0, 0}, {0.1, 0, 0}, lim), line_move({0.1, 0, 0}, {0.1, 0.1, 0}, lim),
                   line_move({0.1, 0.1, 0}, {0, 0.1, 0}, lim)};
  const Path path = blend(program);
  const Timing timing = plan_timing(path);
  const double one = plan_scurve(0.1, 0, 0, {0.2, 1.0, 1.0, 10.0}).curve.duration();
  EXPECT_NEAR(timing.cycle_time, 3 * one, 1e-12);
  expect_valid(path, timing, "square");
}

TEST(Timing, ArcPieceIsCappedByItsCurvature) {
  // radius 0.01 m, a = 1: sqrt(a/kappa) = 0.1 m/s < feed 0.5; the arc alone, rest to rest
  Path path;
  PathPiece piece{Arc{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0.01, 3.0, 0.0}, 0, -1, {0.5, 1.0, 1.0, 1000.0}};
  path.append(piece);
  const Timing timing = plan_timing(path);
  ASSERT_EQ(timing.pieces.size(), 1u);
  EXPECT_EQ(timing.pieces[0].binding, "curvature");
  EXPECT_NEAR(timing.pieces[0].v_peak, 0.1, 1e-12);
  EXPECT_EQ(timing.feed_share, 0.0);
  expect_valid(path, timing, "arc");
}

TEST(Timing, NonPositiveServoPeriodIsAnInputError) {
  Program program;
  program.moves = {line_move({0, 0, 0}, {1, 0, 0}, {0.5, 2.0, 2.0, 20.0})};
  const Path path = blend(program);
  TimingOptions options;
  options.dt = 0;
  EXPECT_THROW((void)plan_timing(path, options), InputError);
}

TEST(Timing, EmptyPathIsOneSampleAtRest) {
  const Timing timing = plan_timing(Path{});
  ASSERT_EQ(timing.samples.size(), 1u);
  EXPECT_EQ(timing.cycle_time, 0.0);
}

// log-uniform in [lo, hi]
double log_uniform(std::mt19937_64& rng, double lo, double hi) {
  return std::exp(test::uniform(rng, std::log(lo), std::log(hi)));
}

TEST(Timing, PropertyExactStopProgramsHoldEveryLimit) {
  const int cases = test::property_cases(300);
  for (int i = 0; i < cases; ++i) {
    const auto seed = static_cast<std::uint64_t>(i);
    auto rng = test::make_rng(seed);
    Program program;
    Vec3 p = Vec3::Zero();
    const int n = 1 + static_cast<int>(test::uniform(rng, 0, 5));
    for (int k = 0; k < n; ++k) {
      const Vec3 dir = Vec3(test::uniform(rng, -1, 1), test::uniform(rng, -1, 1), test::uniform(rng, -1, 1)).normalized();
      // a feed that keeps each move within about two seconds (and the sample count small)
      const double len = log_uniform(rng, 1e-6, 0.5);
      const Vec3 q = p + dir * len;
      program.moves.push_back(line_move(p, q, {log_uniform(rng, std::max(1e-3, 0.5 * len), 2.0), log_uniform(rng, 0.1, 50.0),
                                               log_uniform(rng, 0.1, 50.0), log_uniform(rng, 1.0, 5000.0)}));
      p = q;
    }
    const Path path = blend(program);
    const Timing timing = plan_timing(path);
    expect_valid(path, timing, test::seed_text(seed));
    if (HasFailure()) return;
  }
}

}  // namespace
}  // namespace blendbench
