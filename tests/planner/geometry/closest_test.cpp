#include "blendbench/geometry/closest.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "support/property.hpp"
#include "support/random_geometry.hpp"

namespace blendbench {
namespace {

constexpr double kPi = std::numbers::pi;
// Tolerances relative to the size of the geometry (m):
constexpr double kExact = 1e-12;    // closed forms (lines, planar arcs): rounding only
constexpr double kRefined = 1e-10;  // scanned and golden-refined minima (closest.hpp), Bezier s
// A refined minimiser is only found to about sqrt(eps) of the size: the distance is flat there.
constexpr double kArgmin = 1e-6;
constexpr int kDenseSamples = 100000;

std::string where(std::uint64_t seed, int i) { return test::seed_text(seed) + " case " + std::to_string(i); }

// ---- brute-force reference

// The nearest of kDenseSamples + 1 samples of a curve at(t), t uniform on [0, t_max], and how
// far below it the true minimum can lie. With speed >= |dp/dt| and bend >= |d2p/dt2|, the
// true minimiser t* is within h/2 of a sample, so that sample is at most speed h/2 farther
// (first order); where the distance g stays positive, (g^2)'' = 2 (|p'|^2 - (q - p).p'') gives
// g'' <= (speed^2 + g bend) / g, so at most h^2/8 max g'' farther (second order: g'(t*) = 0
// inside, and an end minimiser is itself a sample).
struct Dense {
  double distance = std::numeric_limits<double>::infinity();  // of the nearest sample
  double slack = 0;  // the true minimum distance is at least distance - slack
};

template <class At>
Dense dense_closest(const At& at, double t_max, const Vec3& query, double speed, double bend) {
  Dense out;
  for (int i = 0; i <= kDenseSamples; ++i) {
    out.distance = std::min(out.distance, (at(t_max * i / kDenseSamples) - query).norm());
  }
  const double h = t_max / kDenseSamples;
  const double first = speed * h / 2;
  out.slack = first;
  if (out.distance > first) {
    const double g2 = (speed * speed + (out.distance + first) * bend) / (out.distance - first);
    out.slack = std::min(first, h * h / 8 * g2);
  }
  return out;
}

Dense dense_scan(const Line& line, const Vec3& q) {
  const Vec3 d = line.p1 - line.p0;
  return dense_closest([&](double t) -> Vec3 { return line.p0 + t * d; }, 1.0, q, d.norm(), 0.0);
}

// An arc or helix by its own formula in the angle phi: speed hypot(r, b), bend r (b = rise / sweep).
Dense dense_scan(const Arc& arc, const Vec3& q) {
  const Vec3 w = arc.u.cross(arc.v);
  const double b = arc.rise / arc.sweep;
  const auto at = [&](double phi) -> Vec3 {
    return arc.center + arc.radius * (std::cos(phi) * arc.u + std::sin(phi) * arc.v) + b * phi * w;
  };
  return dense_closest(at, arc.sweep, q, std::hypot(arc.radius, b), arc.radius);
}

// A Bezier in its own parameter u; its derivatives lie in the convex hulls of their control
// points, which bound speed and bend.
double bezier_speed_bound(const Bezier& bezier) {
  const auto& p = bezier.control_points();
  double speed = 0;
  for (std::size_t i = 0; i + 1 < p.size(); ++i) speed = std::max(speed, bezier.degree() * (p[i + 1] - p[i]).norm());
  return speed;
}

Dense dense_scan(const Bezier& bezier, const Vec3& q) {
  const auto& p = bezier.control_points();
  const double n = bezier.degree();
  double bend = 0;
  for (std::size_t i = 0; i + 2 < p.size(); ++i) bend = std::max(bend, n * (n - 1) * (p[i + 2] - 2 * p[i + 1] + p[i]).norm());
  return dense_closest([&](double u) { return bezier.eval(u); }, 1.0, q, bezier_speed_bound(bezier), bend);
}

// A clothoid by arc length: speed 1, bend the larger end curvature (curvature is linear in s).
Dense dense_scan(const Clothoid& clothoid, const Vec3& q) {
  const double bend = std::max(std::abs(clothoid.kappa0), std::abs(clothoid.kappa0 + clothoid.sharpness * clothoid.length));
  return dense_closest([&](double s) { return point(clothoid, s); }, clothoid.length, q, 1.0, bend);
}

Dense dense_scan(const Segment& segment, const Vec3& q) {
  return std::visit([&](const auto& seg) { return dense_scan(seg, q); }, segment);
}

// One answer checked for its own consistency (s in [0, length], the point on the segment at s,
// the distance that of the point) and against the dense scan (no sample nearer, none farther
// than the scan allows). `size` scales the tolerances (m).
void expect_closest(const Segment& seg, const Vec3& q, double size, const std::string& at) {
  const Closest c = closest_point(seg, q);
  const Dense ref = dense_scan(seg, q);
  ASSERT_TRUE(std::isfinite(c.s) && c.point.allFinite() && std::isfinite(c.distance)) << at;
  EXPECT_GE(c.s, 0.0) << at;
  EXPECT_LE(c.s, length(seg)) << at;
  EXPECT_LE((point(seg, c.s) - c.point).norm(), kRefined * size) << at << " the point is not at s";
  EXPECT_NEAR(c.distance, (q - c.point).norm(), kExact * size) << at;
  EXPECT_LE(c.distance, ref.distance + kRefined * size) << at << " a dense sample is nearer";
  EXPECT_GE(c.distance, ref.distance - ref.slack - kRefined * size) << at;
}

// A query near a segment: a point on it (or beyond an end) plus an offset from 1e-6 to 3 sizes
// in a random direction.
Vec3 query_near(std::mt19937_64& rng, const Segment& seg, double size) {
  const double len = length(seg);
  const double s = test::uniform(rng, -0.2 * len, 1.2 * len);
  const Vec3 base = s < 0 ? start_point(seg) + s * tangent(seg, 0)
                  : s > len ? end_point(seg) + (s - len) * tangent(seg, len)
                            : point(seg, s);
  return base + test::log_uniform(rng, 1e-6, 3) * size * test::random_unit(rng);
}

// ---- lines

TEST(ClosestPoint, InsideALineIsTheFootOfThePerpendicular) {
  const std::uint64_t seed = 1;
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(1000); ++i) {
    const Vec3 p0 = test::random_point(rng);
    const Vec3 dir = test::random_unit(rng);
    const double len = test::log_uniform(rng, 1e-3, 10);
    const Line line{p0, p0 + len * dir};
    const double t = test::uniform(rng, 0, 1);
    const Vec3 foot = line.p0 + t * (line.p1 - line.p0);
    const double offset = test::log_uniform(rng, 1e-6, 10);
    const Vec3 q = foot + offset * test::random_perpendicular(rng, dir);
    const Closest c = closest_point(Segment(line), q);
    const double size = p0.norm() + len + offset;
    EXPECT_NEAR(c.s, t * len, kExact * size) << where(seed, i);
    EXPECT_LE((c.point - foot).norm(), kExact * size) << where(seed, i);
    EXPECT_NEAR(c.distance, offset, kExact * size) << where(seed, i);
  }
}

TEST(ClosestPoint, BeyondEitherEndOfALineIsThatEndPoint) {
  const std::uint64_t seed = 2;
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(1000); ++i) {
    const Vec3 p0 = test::random_point(rng);
    const Vec3 dir = test::random_unit(rng);
    const double len = test::log_uniform(rng, 1e-3, 10);
    const Line line{p0, p0 + len * dir};
    const bool before = i % 2 == 0;
    const double t = before ? -test::log_uniform(rng, 1e-6, 3) : 1 + test::log_uniform(rng, 1e-6, 3);
    const Vec3 q = line.p0 + t * (line.p1 - line.p0) + test::uniform(rng, 0, 2) * len * test::random_perpendicular(rng, dir);
    const Vec3 end = before ? line.p0 : line.p1;
    const Closest c = closest_point(Segment(line), q);
    EXPECT_EQ(c.s, before ? 0.0 : length(line)) << where(seed, i);
    EXPECT_EQ(c.point, end) << where(seed, i);
    EXPECT_DOUBLE_EQ(c.distance, (q - end).norm()) << where(seed, i);
  }
}

TEST(ClosestPoint, OnAZeroLengthLineIsItsOnlyPoint) {
  const std::uint64_t seed = 3;
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(200); ++i) {
    const Vec3 p = test::random_point(rng);
    const Vec3 q = p + test::log_uniform(rng, 1e-9, 10) * test::random_unit(rng);
    const Closest c = closest_point(Segment(Line{p, p}), q);
    EXPECT_EQ(c.s, 0.0) << where(seed, i);
    EXPECT_EQ(c.point, p) << where(seed, i);
    EXPECT_DOUBLE_EQ(c.distance, (q - p).norm()) << where(seed, i);
  }
  const Closest on = closest_point(Segment(Line{Vec3(1, 2, 3), Vec3(1, 2, 3)}), Vec3(1, 2, 3));
  EXPECT_EQ(on.s, 0.0);
  EXPECT_EQ(on.distance, 0.0);
}

// ---- planar arcs

// A random arc in a random plane: centre in the unit cube, radius 1 mm .. 1 m.
Arc random_arc(std::mt19937_64& rng, double sweep) {
  const Vec3 center = test::random_point(rng);
  const Vec3 u = test::random_unit(rng);
  const Vec3 v = test::random_perpendicular(rng, u);
  return Arc{center, u, v, test::log_uniform(rng, 1e-3, 1), sweep, 0.0};
}

// The point at angle phi (from u towards v), distance rho from the arc's axis and height z
// along u x v.
Vec3 at_polar(const Arc& arc, double phi, double rho, double z) {
  return arc.center + rho * (std::cos(phi) * arc.u + std::sin(phi) * arc.v) + z * arc.u.cross(arc.v);
}

TEST(ClosestPoint, InsideAnArcSweepIsTheRadialProjection) {
  const std::uint64_t seed = 4;
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(1000); ++i) {
    const Arc arc = random_arc(rng, test::uniform(rng, 0.01, 2 * kPi - 0.01));
    const double phi = test::uniform(rng, 0, arc.sweep);
    const double rho = test::log_uniform(rng, 0.01, 3) * arc.radius;
    const double z = test::uniform(rng, -2, 2) * arc.radius;
    const Vec3 q = at_polar(arc, phi, rho, z);
    const Closest c = closest_point(Segment(arc), q);
    const double size = arc.center.norm() + arc.radius + rho + std::abs(z);
    EXPECT_NEAR(c.s, arc.radius * phi, kExact * size) << where(seed, i);
    EXPECT_LE((c.point - at_polar(arc, phi, arc.radius, 0)).norm(), kExact * size) << where(seed, i);
    EXPECT_NEAR(c.distance, std::hypot(rho - arc.radius, z), kExact * size) << where(seed, i);
  }
}

TEST(ClosestPoint, OutsideAnArcSweepIsTheNearerEndPoint) {
  const std::uint64_t seed = 5;
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(1000); ++i) {
    const Arc arc = random_arc(rng, test::uniform(rng, 0.01, 2 * kPi - 0.01));
    const double phi = test::uniform(rng, arc.sweep, 2 * kPi);
    const double rho = test::log_uniform(rng, 0.01, 3) * arc.radius;
    const Vec3 q = at_polar(arc, phi, rho, test::uniform(rng, -2, 2) * arc.radius);
    const Vec3 start = at_polar(arc, 0, arc.radius, 0);
    const Vec3 end = at_polar(arc, arc.sweep, arc.radius, 0);
    const Closest c = closest_point(Segment(arc), q);
    const double size = arc.center.norm() + arc.radius + rho;
    EXPECT_NEAR(c.distance, std::min((q - start).norm(), (q - end).norm()), kExact * size) << where(seed, i);
    const bool at_start = c.s == 0 && (c.point - start).norm() <= kExact * size;
    const bool at_end = c.s == length(arc) && (c.point - end).norm() <= kExact * size;
    EXPECT_TRUE(at_start || at_end) << where(seed, i) << " s=" << c.s << " of " << length(arc);
  }
}

TEST(ClosestPoint, OnTheAxisOfAnArcEveryPointIsEquallyNear) {
  const std::uint64_t seed = 6;
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(500); ++i) {
    const Arc arc = random_arc(rng, test::uniform(rng, 0.01, 2 * kPi));
    const double z = i % 4 == 0 ? 0.0 : test::uniform(rng, -2, 2) * arc.radius;  // the centre itself too
    const Vec3 q = at_polar(arc, 0, 0, z);
    const Closest c = closest_point(Segment(arc), q);
    const double size = arc.center.norm() + arc.radius + std::abs(z);
    ASSERT_TRUE(std::isfinite(c.s)) << where(seed, i);
    EXPECT_GE(c.s, 0.0) << where(seed, i);
    EXPECT_LE(c.s, length(arc)) << where(seed, i);
    EXPECT_LE((point(arc, c.s) - c.point).norm(), kExact * size) << where(seed, i);
    EXPECT_NEAR(c.distance, std::hypot(arc.radius, z), kExact * size) << where(seed, i);
  }
}

TEST(ClosestPoint, OnAFullCircleIsTheRadialProjectionAtEveryAngle) {
  const std::uint64_t seed = 7;
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(1000); ++i) {
    const Arc arc = random_arc(rng, 2 * kPi);
    const double phi = test::uniform(rng, 0, 2 * kPi);
    const double rho = test::log_uniform(rng, 0.01, 3) * arc.radius;
    const double z = test::uniform(rng, -2, 2) * arc.radius;
    const Closest c = closest_point(Segment(arc), at_polar(arc, phi, rho, z));
    const double size = arc.center.norm() + arc.radius + rho + std::abs(z);
    // s is r phi, or 0 and 2 pi r alike where the circle closes
    EXPECT_LE((point(arc, c.s) - at_polar(arc, phi, arc.radius, 0)).norm(), kExact * size) << where(seed, i);
    EXPECT_LE((c.point - at_polar(arc, phi, arc.radius, 0)).norm(), kExact * size) << where(seed, i);
    EXPECT_NEAR(c.distance, std::hypot(rho - arc.radius, z), kExact * size) << where(seed, i);
  }
}

TEST(ClosestPoint, OnAPlanarArcOfSeveralTurnsIsAsNearAsItsCircle) {
  const std::uint64_t seed = 8;
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(300); ++i) {
    const Arc arc = random_arc(rng, test::uniform(rng, 2 * kPi + 0.01, 8 * kPi));
    const double phi = test::uniform(rng, 0, 2 * kPi);
    const double rho = test::log_uniform(rng, 0.01, 3) * arc.radius;
    const double z = test::uniform(rng, -2, 2) * arc.radius;
    const Vec3 q = at_polar(arc, phi, rho, z);
    const double size = arc.center.norm() + arc.radius + rho + std::abs(z);
    const Closest c = closest_point(Segment(arc), q);
    EXPECT_NEAR(c.distance, std::hypot(rho - arc.radius, z), kRefined * size) << where(seed, i);
    EXPECT_LE((c.point - at_polar(arc, phi, arc.radius, 0)).norm(), kArgmin * size) << where(seed, i);
    expect_closest(arc, q, size, where(seed, i));
  }
}

// ---- helices, Beziers, clothoids: against the dense scan

// Random segments of `kind`, 1 mm to 1 m across, each queried near it, against the dense scan.
void expect_closest_on_random(test::SegmentKind kind, std::uint64_t seed, int cases) {
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(cases); ++i) {
    const double size = test::log_uniform(rng, 1e-3, 1);
    const Segment seg = test::random_segment(rng, kind, test::random_point(rng), size);
    expect_closest(seg, query_near(rng, seg, size), size + start_point(seg).norm(), where(seed, i));
  }
}

TEST(ClosestPoint, OnAHelixMatchesADenseScan) { expect_closest_on_random(test::SegmentKind::kHelix, 9, 300); }

TEST(ClosestPoint, OnAHelixIsTheNearestTurn) {
  // a 10-turn helix and queries between two turns, nearer one of them: the scan sees ~13
  // samples a turn, so the nearest sample can sit on the farther turn
  const std::uint64_t seed = 10;
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(300); ++i) {
    const double r = test::log_uniform(rng, 1e-3, 1);
    const double pitch = test::uniform(rng, 0.05, 0.5) * r;  // rise per turn
    Arc helix = random_arc(rng, 20 * kPi);
    helix.radius = r;
    helix.rise = 10 * pitch;
    const double b = pitch / (2 * kPi);
    const int turn = 1 + static_cast<int>(test::uniform(rng, 0, 8));
    const double alpha = test::uniform(rng, 0, 2 * kPi);
    const double delta = test::uniform(rng, -0.4, 0.4) * pitch;  // above (below) the turn
    // on the helix's cylinder half of the time, else inside or outside it
    const bool on_cylinder = i % 2 == 0;
    const double rho = on_cylinder ? r : test::uniform(rng, 0.5, 1.5) * r;
    const Vec3 q = at_polar(helix, alpha, rho, b * (alpha + 2 * kPi * turn) + delta);
    const double size = helix.center.norm() + r + helix.rise;
    expect_closest(helix, q, size, where(seed, i));
    if (on_cylinder) {
      // on the cylinder the nearest point is on the same turn, less than half a turn away in
      // angle: d^2 = 2 r^2 (1 - cos psi) + (delta - b psi)^2 is smaller at psi = 0 than
      // anywhere with |psi| >= pi when |delta| <= 0.4 pitch and pitch <= r / 2
      const double phi = closest_point(Segment(helix), q).s / std::hypot(r, b);
      EXPECT_EQ(std::lround((phi - alpha) / (2 * kPi)), turn) << where(seed, i) << " phi=" << phi;
    }
  }
}

TEST(ClosestPoint, OnABezierTheArcLengthLeadsBackToThePoint) {
  // closest_point scans a Bezier in u and converts to s once: point(seg, s) must be the point
  expect_closest_on_random(test::SegmentKind::kBezier, 11, 300);
}

TEST(ClosestPoint, OnAClothoidMatchesADenseScan) { expect_closest_on_random(test::SegmentKind::kClothoid, 12, 150); }

TEST(ClosestPoint, OnAZeroLengthClothoidIsItsOrigin) {
  // paths carry zero-length clothoids (a transition shrunk to nothing)
  const std::uint64_t seed = 14;
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(200); ++i) {
    const Vec3 origin = test::random_point(rng);
    const Vec3 e1 = test::random_unit(rng);
    const Clothoid c{origin, e1, test::random_perpendicular(rng, e1), test::uniform(rng, -5, 5), test::uniform(rng, -5, 5), 0.0};
    const Vec3 q = origin + test::log_uniform(rng, 1e-9, 10) * test::random_unit(rng);
    const Closest got = closest_point(Segment(c), q);
    EXPECT_EQ(got.s, 0.0) << where(seed, i);
    EXPECT_EQ(got.point, origin) << where(seed, i);
    EXPECT_DOUBLE_EQ(got.distance, (q - origin).norm()) << where(seed, i);
  }
}

TEST(ClosestPoint, OfAPrimitiveIsThatOfItsSegment) {
  const std::uint64_t seed = 13;
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(200); ++i) {
    const auto kind = i % 2 == 0 ? test::SegmentKind::kLine : test::SegmentKind::kArc;
    const Segment seg = test::random_segment(rng, kind, test::random_point(rng), 1.0);
    const Primitive primitive = kind == test::SegmentKind::kLine ? Primitive(std::get<Line>(seg)) : Primitive(std::get<Arc>(seg));
    const Vec3 q = query_near(rng, seg, 1.0);
    const Closest a = closest_point(primitive, q);
    const Closest b = closest_point(seg, q);
    EXPECT_EQ(a.s, b.s) << where(seed, i);
    EXPECT_EQ(a.point, b.point) << where(seed, i);
    EXPECT_EQ(a.distance, b.distance) << where(seed, i);
  }
}

// ---- Hausdorff distances

// A chain of 1..3 random segments of random kinds, about `size` across each.
std::vector<Segment> random_chain(std::mt19937_64& rng, double size) {
  std::vector<Segment> chain;
  Vec3 at = test::random_point(rng, size);
  const int n = 1 + static_cast<int>(test::uniform(rng, 0, 3));
  for (int k = 0; k < n; ++k) {
    const auto kind = test::kSegmentKinds[static_cast<std::size_t>(test::uniform(rng, 0, test::kSegmentKinds.size()))];
    chain.push_back(test::random_segment(rng, kind, at, size));
    at = end_point(chain.back());
  }
  return chain;
}

// The largest gap (m, along the curve) between the samples hausdorff takes of a segment: every
// `step` m and at least 64 samples (closest.hpp); a Bezier is sampled uniformly in u, so there
// its speed bound stands in for the mean speed.
double sampling_gap(const Segment& seg, double step) {
  const double len = length(seg);
  const Bezier* bezier = std::get_if<Bezier>(&seg);
  return (bezier != nullptr ? bezier_speed_bound(*bezier) : len) * std::min(1.0 / 64, step / len);
}

double sampling_gap(const std::vector<Segment>& set, double step) {
  double gap = 0;
  for (const Segment& seg : set) gap = std::max(gap, sampling_gap(seg, step));
  return gap;
}

// Samples of a set of segments, uniform in each one's own parameter (arc length, u for a
// Bezier), and the largest gap between neighbouring samples along the curve (m).
struct Samples {
  std::vector<Vec3> points;
  double gap = 0;
};

Samples sample_set(const std::vector<Segment>& set, int per_segment) {
  Samples out;
  for (const Segment& seg : set) {
    const Bezier* bezier = std::get_if<Bezier>(&seg);
    const double len = length(seg);
    for (int i = 0; i <= per_segment; ++i) {
      out.points.push_back(bezier != nullptr ? bezier->eval(static_cast<double>(i) / per_segment)
                                             : point(seg, len * i / per_segment));
    }
    out.gap = std::max(out.gap, (bezier != nullptr ? bezier_speed_bound(*bezier) : len) / per_segment);
  }
  return out;
}

// Directed Hausdorff distance between two sample sets by brute force. The distance to a set is
// 1-Lipschitz, so the true directed distance between the sampled curves lies in
// [result - to.gap / 2, result + from.gap / 2].
double brute_directed(const Samples& from, const Samples& to) {
  double worst = 0;
  for (const Vec3& a : from.points) {
    double best = std::numeric_limits<double>::infinity();
    for (const Vec3& b : to.points) best = std::min(best, (a - b).squaredNorm());
    worst = std::max(worst, best);
  }
  return std::sqrt(worst);
}

TEST(Hausdorff, IsSymmetricAndTheLargerOfTheDirectedDistances) {
  const std::uint64_t seed = 20;
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(100); ++i) {
    const std::vector<Segment> a = random_chain(rng, 1.0);
    const std::vector<Segment> b = random_chain(rng, 1.0);
    const double step = test::log_uniform(rng, 0.005, 0.1);
    const double ab = directed_hausdorff(a, b, step);
    const double ba = directed_hausdorff(b, a, step);
    const double h = hausdorff(a, b, step);
    ASSERT_TRUE(std::isfinite(h) && std::isfinite(ab) && std::isfinite(ba)) << where(seed, i);
    EXPECT_EQ(h, hausdorff(b, a, step)) << where(seed, i);
    EXPECT_EQ(h, std::max(ab, ba)) << where(seed, i);
    EXPECT_GE(ab, 0.0) << where(seed, i);
    EXPECT_GE(ba, 0.0) << where(seed, i);
    EXPECT_LE(ab, h) << where(seed, i);
    EXPECT_LE(ba, h) << where(seed, i);
  }
}

TEST(Hausdorff, OfASetWithItselfIsZero) {
  const std::uint64_t seed = 21;
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(100); ++i) {
    const std::vector<Segment> a = random_chain(rng, 1.0);
    EXPECT_LE(hausdorff(a, a, test::log_uniform(rng, 0.005, 0.1)), kRefined * 3) << where(seed, i);
  }
}

TEST(Hausdorff, OfOneCurveSplitDifferentlyIsZero) {
  // the sets are unions: a chain of lines and arcs against the same chain cut at other places
  const std::uint64_t seed = 22;
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(200); ++i) {
    std::vector<Segment> whole;
    std::vector<Segment> cut;
    Vec3 at = test::random_point(rng);
    for (int k = 0; k < 3; ++k) {
      const auto kind = test::uniform(rng, 0, 1) < 0.5 ? test::SegmentKind::kLine : test::SegmentKind::kArc;
      const Segment seg = test::random_segment(rng, kind, at, 1.0);
      const Primitive primitive = kind == test::SegmentKind::kLine ? Primitive(std::get<Line>(seg)) : Primitive(std::get<Arc>(seg));
      const double len = length(seg);
      const double s = test::uniform(rng, 0.1, 0.9) * len;
      whole.push_back(seg);
      cut.push_back(to_segment(sub_segment(primitive, 0, s)));
      cut.push_back(to_segment(sub_segment(primitive, s, len)));
      at = end_point(seg);
    }
    EXPECT_LE(hausdorff(whole, cut, 0.01), kExact * 10) << where(seed, i);
  }
}

TEST(Hausdorff, WithAnEmptySetIsZero) {
  auto rng = test::make_rng(23);
  const std::vector<Segment> a = random_chain(rng, 1.0);
  const std::vector<Segment> none;
  EXPECT_EQ(hausdorff(a, none, 0.01), 0.0);
  EXPECT_EQ(hausdorff(none, a, 0.01), 0.0);
  EXPECT_EQ(hausdorff(none, none, 0.01), 0.0);
  EXPECT_EQ(directed_hausdorff(a, none, 0.01), 0.0);
  EXPECT_EQ(directed_hausdorff(none, a, 0.01), 0.0);
}

// A step of zero, a negative or NaN step, or one tiny against the length cannot overflow the
// sample count: the distance is still measured (at the 2^20 samples a segment cap).
TEST(Hausdorff, ADegenerateStepStillMeasuresTheDistance) {
  const double offset = 2e-3;
  const std::vector<Segment> a = {Line{Vec3(0, 0, 0), Vec3(1, 0, 0)}};
  const std::vector<Segment> b = {Line{Vec3(0, offset, 0), Vec3(1, offset, 0)}};
  for (const double step : {0.0, -1.0, std::numeric_limits<double>::quiet_NaN(), 1e-300}) {
    EXPECT_NEAR(hausdorff(a, b, step), offset, kExact) << "step " << step;
    EXPECT_NEAR(directed_hausdorff(a, b, step), offset, kExact) << "step " << step;
  }
}

TEST(Hausdorff, OfParallelLinesIsTheirOffset) {
  const std::uint64_t seed = 24;
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(300); ++i) {
    const Vec3 p = test::random_point(rng);
    const Vec3 dir = test::random_unit(rng);
    const double len = test::log_uniform(rng, 1e-3, 10);
    const double offset = test::log_uniform(rng, 1e-6, 10);
    const Vec3 shift = offset * test::random_perpendicular(rng, dir);
    const std::vector<Segment> a = {Line{p, p + len * dir}};
    const std::vector<Segment> b = {Line{p + shift, p + shift + len * dir}};
    const double size = p.norm() + len + offset;
    EXPECT_NEAR(hausdorff(a, b, len / 100), offset, kExact * size) << where(seed, i);
    EXPECT_NEAR(directed_hausdorff(a, b, len / 100), offset, kExact * size) << where(seed, i);
  }
}

TEST(Hausdorff, OfALineAndALongerCollinearLineIsTheOverhang) {
  const std::uint64_t seed = 25;
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(300); ++i) {
    const Vec3 p = test::random_point(rng);
    const Vec3 dir = test::random_unit(rng);
    const double len = test::log_uniform(rng, 1e-3, 10);
    const double before = i % 3 == 0 ? 0.0 : test::uniform(rng, 0, 2) * len;
    const double after = i % 3 == 1 ? 0.0 : test::uniform(rng, 0, 2) * len;
    const std::vector<Segment> a = {Line{p, p + len * dir}};
    const std::vector<Segment> b = {Line{p - before * dir, p + (len + after) * dir}};
    const double size = p.norm() + len + before + after;
    const double step = len / 50;
    EXPECT_NEAR(hausdorff(a, b, step), std::max(before, after), kExact * size) << where(seed, i);
    EXPECT_NEAR(directed_hausdorff(b, a, step), std::max(before, after), kExact * size) << where(seed, i);
    EXPECT_LE(directed_hausdorff(a, b, step), kExact * size) << where(seed, i) << " a lies on b";
  }
}

TEST(Hausdorff, OfAnArcAndItsChordIsTheSagitta) {
  // both ways the farthest points are the middles: sagitta r (1 - cos(theta / 2)). Sampled
  // every `gap`, the arc's middle may be missed by r (1 - cos(gap / 2r)) <= gap^2 / 8r, the
  // chord's by sqrt(rho0^2 + (gap / 2)^2) - rho0 <= min(gap / 2, gap^2 / 8 rho0), rho0 = r cos(theta / 2)
  const std::uint64_t seed = 26;
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(500); ++i) {
    const Arc arc = random_arc(rng, test::uniform(rng, 0.01, kPi));
    const Line chord{at_polar(arc, 0, arc.radius, 0), at_polar(arc, arc.sweep, arc.radius, 0)};
    const double rho0 = arc.radius * std::cos(arc.sweep / 2);
    const double sagitta = arc.radius - rho0;
    const double step = test::log_uniform(rng, 1e-3, 1) * length(arc);
    const double gap_arc = sampling_gap(arc, step);
    const double gap_chord = sampling_gap(chord, step);
    const double miss_arc = gap_arc * gap_arc / (8 * arc.radius);
    const double miss_chord = std::min(gap_chord / 2, gap_chord * gap_chord / (8 * rho0));
    const double tol = kExact * (arc.center.norm() + arc.radius);
    const std::vector<Segment> a = {arc};
    const std::vector<Segment> b = {chord};
    const double from_arc = directed_hausdorff(a, b, step);
    const double from_chord = directed_hausdorff(b, a, step);
    EXPECT_LE(from_arc, sagitta + tol) << where(seed, i);
    EXPECT_GE(from_arc, sagitta - miss_arc - tol) << where(seed, i);
    EXPECT_LE(from_chord, sagitta + tol) << where(seed, i);
    EXPECT_GE(from_chord, sagitta - miss_chord - tol) << where(seed, i);
    EXPECT_GE(hausdorff(a, b, step), sagitta - std::min(miss_arc, miss_chord) - tol) << where(seed, i);
  }
}

TEST(Hausdorff, OfAParabolaAndItsChordIsHalfTheHeightOfItsMiddleControlPoint) {
  // the quadratic Bezier (-a, 0), (0, h), (a, 0) is the parabola y = h/2 (1 - x^2 / a^2): its
  // apex is h/2 from the chord and, for h <= sqrt(2) a, the nearest point of the curve to the
  // chord's middle (curvature radius a^2 / h >= h / 2). The curve's apex may be missed by
  // kappa gap^2 / 8 (kappa <= h / a^2), the chord's middle by gap / 2.
  const std::uint64_t seed = 27;
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(300); ++i) {
    const Vec3 m = test::random_point(rng);
    const Vec3 e1 = test::random_unit(rng);
    const Vec3 e2 = test::random_perpendicular(rng, e1);
    const double a = test::log_uniform(rng, 1e-3, 1);
    const double h = test::uniform(rng, 0.01, 1.4) * a;
    const std::vector<Segment> curve = {Bezier({m - a * e1, m + h * e2, m + a * e1})};
    const std::vector<Segment> chord = {Line{m - a * e1, m + a * e1}};
    const double step = test::log_uniform(rng, 1e-3, 0.1) * a;
    const double gap_curve = sampling_gap(curve, step);
    const double tol = kRefined * (m.norm() + a);
    const double from_curve = directed_hausdorff(curve, chord, step);
    const double from_chord = directed_hausdorff(chord, curve, step);
    EXPECT_LE(from_curve, h / 2 + tol) << where(seed, i);
    EXPECT_GE(from_curve, h / 2 - h / (a * a) * gap_curve * gap_curve / 8 - tol) << where(seed, i);
    EXPECT_LE(from_chord, h / 2 + tol) << where(seed, i);
    EXPECT_GE(from_chord, h / 2 - sampling_gap(chord, step) / 2 - tol) << where(seed, i);
  }
}

TEST(Hausdorff, OfCoaxialHelicesIsTheirRadialGap) {
  // helices of radii r1 and r2 with one axis, pitch and phase: the point of one at angle phi
  // is nearest the other's point at phi (d^2 = dr^2 + 2 r1 r2 (1 - cos psi) + b^2 psi^2 at
  // psi away), so every point is |r1 - r2| from the other set; a wrong turn is farther
  const std::uint64_t seed = 28;
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(100); ++i) {
    const double turns = test::uniform(rng, 1, 10);
    Arc inner = random_arc(rng, 2 * kPi * turns);
    inner.rise = test::uniform(rng, 0.05, 0.5) * inner.radius * turns * (i % 2 == 0 ? 1 : -1);
    Arc outer = inner;
    outer.radius *= 1 + test::uniform(rng, 0.01, 0.5);
    const std::vector<Segment> a = {inner};
    const std::vector<Segment> b = {outer};
    const double step = length(inner) / 200;
    const double size = inner.center.norm() + outer.radius + std::abs(inner.rise);
    EXPECT_NEAR(directed_hausdorff(a, b, step), outer.radius - inner.radius, kRefined * size) << where(seed, i);
    EXPECT_NEAR(directed_hausdorff(b, a, step), outer.radius - inner.radius, kRefined * size) << where(seed, i);
  }
}

TEST(Hausdorff, OfAHelixAndItsAxisIsTheRadius) {
  const std::uint64_t seed = 29;
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(100); ++i) {
    const double turns = test::uniform(rng, 0.2, 10);
    Arc helix = random_arc(rng, 2 * kPi * turns);
    helix.rise = test::uniform(rng, 0.05, 2) * helix.radius * turns * (i % 2 == 0 ? 1 : -1);
    const std::vector<Segment> a = {helix};
    const std::vector<Segment> axis = {Line{helix.center, helix.center + helix.rise * helix.u.cross(helix.v)}};
    const double step = length(helix) / 500;
    const double size = helix.center.norm() + helix.radius + std::abs(helix.rise);
    EXPECT_NEAR(directed_hausdorff(a, axis, step), helix.radius, kRefined * size) << where(seed, i);
    EXPECT_NEAR(directed_hausdorff(axis, a, step), helix.radius, kRefined * size) << where(seed, i);
  }
}

TEST(Hausdorff, OfRandomCurvesLiesInTheBruteForceBracket) {
  // a Bezier and a clothoid against a helix and a line, both ways; brute force brackets the
  // true value (brute_directed), and hausdorff may lie below it by half its own sampling gap
  const std::uint64_t seed = 30;
  auto rng = test::make_rng(seed);
  for (int i = 0; i < test::property_cases(40); ++i) {
    const Vec3 start = test::random_point(rng, 0.3);
    std::vector<Segment> a = {test::random_segment(rng, test::SegmentKind::kBezier, start, 1.0)};
    a.push_back(test::random_segment(rng, test::SegmentKind::kClothoid, end_point(a.back()), 1.0));
    std::vector<Segment> b = {test::random_segment(rng, test::SegmentKind::kHelix, test::random_point(rng, 0.3), 1.0)};
    b.push_back(test::random_segment(rng, test::SegmentKind::kLine, end_point(b.back()), 1.0));
    const double step = 1e-3;
    const Samples sa = sample_set(a, 2000);
    const Samples sb = sample_set(b, 2000);
    for (const bool forward : {true, false}) {
      const auto& from = forward ? a : b;
      const auto& to = forward ? b : a;
      const Samples& s_from = forward ? sa : sb;
      const Samples& s_to = forward ? sb : sa;
      const double brute = brute_directed(s_from, s_to);
      const double d = directed_hausdorff(from, to, step);
      EXPECT_LE(d, brute + s_from.gap / 2 + kRefined) << where(seed, i) << " forward=" << forward;
      EXPECT_GE(d, brute - s_to.gap / 2 - sampling_gap(from, step) / 2 - kRefined) << where(seed, i) << " forward=" << forward;
    }
  }
}

}  // namespace
}  // namespace blendbench
