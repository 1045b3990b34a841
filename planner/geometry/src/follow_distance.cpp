#include "blendbench/geometry/follow_distance.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace blendbench {
namespace {

// Relative margin on a piece's scanned maximum curvature (segment.hpp: a Bezier's is exact to
// below 1e-9 relative).
constexpr double kCurvatureMargin = 1e-6;

double point_segment_distance(const Vec3& q, const Vec3& a, const Vec3& b) {
  const Vec3 d = b - a;
  const double l2 = d.squaredNorm();
  const double t = l2 > 0 ? std::clamp((q - a).dot(d) / l2, 0.0, 1.0) : 0.0;
  return (q - (a + t * d)).norm();
}

// The curve as a chord polygon: the points of piece i are points[first[i]] .. points[first[i + 1] - 1],
// each chord within `deviation` of the piece; share[j] is point j's place on its piece (arc
// length over length, or u of a Bezier, which the pieces here are parameterised close to).
struct ChordPolygon {
  std::vector<Vec3> points;
  std::vector<double> share;
  std::vector<std::size_t> first;
  double deviation = 0;
};

// Chords of at most `max_deviation` from each piece: a stretch of length l of a curve of curvature
// at most kappa lies within kappa l^2 / 8 of its chord.
ChordPolygon chord_polygon(const std::vector<Segment>& pieces, double max_deviation) {
  ChordPolygon out;
  out.first.reserve(pieces.size() + 1);
  for (const Segment& piece : pieces) {
    out.first.push_back(out.points.size());
    const double len = length(piece);
    const double kappa = max_curvature(piece, 0.0, len) * (1 + kCurvatureMargin);
    const double chord = kappa > 0 ? std::sqrt(8 * max_deviation / kappa) : std::numeric_limits<double>::infinity();
    double step = 0;
    int n = 1;
    if (const auto* bezier = std::get_if<Bezier>(&piece)) {
      // uniform in u: an arc of du is at most du times the largest speed, which the hodograph's
      // control points bound (degree times the longest leg of the control polygon)
      const auto& c = bezier->control_points();
      double leg = 0;
      for (std::size_t j = 0; j + 1 < c.size(); ++j) leg = std::max(leg, (c[j + 1] - c[j]).norm());
      const double speed = bezier->degree() * leg;
      n = std::max(1, static_cast<int>(std::ceil(speed / chord)));
      for (int j = 0; j <= n; ++j) out.points.push_back(bezier->eval(static_cast<double>(j) / n));
      step = speed / n;
    } else {
      n = std::max(1, static_cast<int>(std::ceil(len / chord)));
      for (int j = 0; j <= n; ++j) out.points.push_back(point(piece, len * j / n));
      step = len / n;
    }
    for (int j = 0; j <= n; ++j) out.share.push_back(static_cast<double>(j) / n);
    out.deviation = std::max(out.deviation, kappa * step * step / 8);
  }
  out.first.push_back(out.points.size());
  return out;
}

}  // namespace

FollowDistance follow_distance(const std::vector<Segment>& pieces, const std::vector<double>& span_begin,
                               const std::vector<double>& span_end, const std::vector<Vec3>& polyline, double resolution,
                               double reach) {
  assert(polyline.size() >= 2 && span_begin.size() == pieces.size() && span_end.size() == pieces.size());
  assert(resolution > 0);
  FollowDistance out;
  if (pieces.empty()) return out;
  // the polyline's arc length at each point
  std::vector<double> sigma(polyline.size(), 0.0);
  for (std::size_t k = 1; k < polyline.size(); ++k) sigma[k] = sigma[k - 1] + (polyline[k] - polyline[k - 1]).norm();
  const std::size_t segments = polyline.size() - 1;
  const ChordPolygon chords = chord_polygon(pieces, 0.5 * resolution);
  // each chord point's place along the polyline, from its piece's stretch (non-decreasing)
  std::vector<double> place(chords.points.size());
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    for (std::size_t c = chords.first[i]; c < chords.first[i + 1]; ++c) {
      place[c] = std::max(c > 0 ? place[c - 1] : 0.0, span_begin[i] + chords.share[c] * (span_end[i] - span_begin[i]));
    }
  }

  // curve -> polyline: points every `resolution` along each chord, each against the polyline's
  // segments within reach of its place (a window sliding forward)
  double to_polyline = 0;
  std::size_t k0 = 0;
  std::size_t k1 = 0;
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    for (std::size_t c = chords.first[i]; c + 1 < chords.first[i + 1]; ++c) {
      const Vec3& a = chords.points[c];
      const Vec3& b = chords.points[c + 1];
      const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / resolution)));
      for (int j = c == chords.first[i] ? 0 : 1; j <= n; ++j) {
        const double share = static_cast<double>(j) / n;
        const Vec3 q = a + (b - a) * share;
        const double at = place[c] + share * (place[c + 1] - place[c]);
        while (k0 + 1 < segments && sigma[k0 + 1] < at - reach) ++k0;
        k1 = std::max(k1, k0);
        while (k1 + 1 < segments && sigma[k1 + 1] <= at + reach) ++k1;
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t k = k0; k <= k1; ++k) best = std::min(best, point_segment_distance(q, polyline[k], polyline[k + 1]));
        to_polyline = std::max(to_polyline, best);
      }
    }
  }

  // polyline -> curve: points every `resolution` on each segment, each against the chords whose
  // places lie within reach of it (a window sliding forward; a piece's last point and the next
  // one's first coincide, so the chord between them is a point)
  double to_curve = 0;
  std::size_t c0 = 0;
  std::size_t c1 = 0;
  const std::size_t last = chords.points.size() - 1;
  for (std::size_t k = 0; k < segments; ++k) {
    const Vec3& a = polyline[k];
    const Vec3& b = polyline[k + 1];
    const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / resolution)));
    for (int j = k == 0 ? 0 : 1; j <= n; ++j) {
      const double share = static_cast<double>(j) / n;
      const Vec3 q = a + (b - a) * share;
      const double at = sigma[k] + share * (sigma[k + 1] - sigma[k]);
      while (c0 + 1 < last && place[c0 + 1] < at - reach) ++c0;
      c1 = std::max(c1, c0 + 1);
      while (c1 < last && place[c1] <= at + reach) ++c1;
      double best = std::numeric_limits<double>::infinity();
      for (std::size_t c = c0; c < c1; ++c) best = std::min(best, point_segment_distance(q, chords.points[c], chords.points[c + 1]));
      to_curve = std::max(to_curve, best);
    }
  }
  out.curve_to_polyline = to_polyline + 0.5 * resolution;
  out.polyline_to_curve = to_curve + 0.5 * resolution + chords.deviation;
  return out;
}

}  // namespace blendbench
