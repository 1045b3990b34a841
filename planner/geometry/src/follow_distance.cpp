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
// each chord within `deviation` of the piece.
struct ChordPolygon {
  std::vector<Vec3> points;
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
    if (const auto* bezier = std::get_if<Bezier>(&piece)) {
      // uniform in u: an arc of du is at most du times the largest speed, which the hodograph's
      // control points bound (degree times the longest leg of the control polygon)
      const auto& c = bezier->control_points();
      double leg = 0;
      for (std::size_t j = 0; j + 1 < c.size(); ++j) leg = std::max(leg, (c[j + 1] - c[j]).norm());
      const double speed = bezier->degree() * leg;
      const int n = std::max(1, static_cast<int>(std::ceil(speed / chord)));
      for (int j = 0; j <= n; ++j) out.points.push_back(bezier->eval(static_cast<double>(j) / n));
      const double step = speed / n;
      out.deviation = std::max(out.deviation, kappa * step * step / 8);
      continue;
    }
    const int n = std::max(1, static_cast<int>(std::ceil(len / chord)));
    for (int j = 0; j <= n; ++j) out.points.push_back(point(piece, len * j / n));
    const double step = len / n;
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
  // the polyline's segments that meet [s0, s1] of its arc length
  const auto segment_range = [&](double s0, double s1) {
    const auto lo = std::upper_bound(sigma.begin(), sigma.end(), s0) - sigma.begin() - 1;
    const auto hi = std::lower_bound(sigma.begin(), sigma.end(), s1) - sigma.begin();
    return std::pair{static_cast<std::size_t>(std::clamp<std::ptrdiff_t>(lo, 0, static_cast<std::ptrdiff_t>(segments) - 1)),
                     static_cast<std::size_t>(std::clamp<std::ptrdiff_t>(hi, 1, static_cast<std::ptrdiff_t>(segments)) - 1)};
  };
  const ChordPolygon chords = chord_polygon(pieces, 0.5 * resolution);

  // curve -> polyline: chord points every `resolution`, each against the polyline near its piece
  double to_polyline = 0;
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    const auto [k0, k1] = segment_range(span_begin[i] - reach, span_end[i] + reach);
    for (std::size_t c = chords.first[i]; c + 1 < chords.first[i + 1]; ++c) {
      const Vec3& a = chords.points[c];
      const Vec3& b = chords.points[c + 1];
      const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / resolution)));
      for (int j = c == chords.first[i] ? 0 : 1; j <= n; ++j) {
        const Vec3 q = a + (b - a) * (static_cast<double>(j) / n);
        double best = std::numeric_limits<double>::infinity();
        for (std::size_t k = k0; k <= k1; ++k) best = std::min(best, point_segment_distance(q, polyline[k], polyline[k + 1]));
        to_polyline = std::max(to_polyline, best);
      }
    }
  }

  // polyline -> curve: points every `resolution` on each segment, each against the chords of
  // the pieces whose stretch lies within reach (spans non-decreasing: a window of pieces)
  double to_curve = 0;
  std::size_t i0 = 0;
  for (std::size_t k = 0; k < segments; ++k) {
    while (i0 + 1 < pieces.size() && span_end[i0] < sigma[k] - reach) ++i0;
    std::size_t i1 = i0;
    while (i1 + 1 < pieces.size() && span_begin[i1 + 1] <= sigma[k + 1] + reach) ++i1;
    const Vec3& a = polyline[k];
    const Vec3& b = polyline[k + 1];
    const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / resolution)));
    for (int j = k == 0 ? 0 : 1; j <= n; ++j) {
      const Vec3 q = a + (b - a) * (static_cast<double>(j) / n);
      double best = std::numeric_limits<double>::infinity();
      // consecutive points of the window (a piece's last and the next one's first coincide: that
      // chord is a point)
      for (std::size_t c = chords.first[i0]; c + 1 < chords.first[i1 + 1]; ++c) {
        best = std::min(best, point_segment_distance(q, chords.points[c], chords.points[c + 1]));
      }
      to_curve = std::max(to_curve, best);
    }
  }
  out.curve_to_polyline = to_polyline + 0.5 * resolution;
  out.polyline_to_curve = to_curve + 0.5 * resolution + chords.deviation;
  return out;
}

}  // namespace blendbench
