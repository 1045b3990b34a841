#pragma once
// Point streams for the smoothing tests: the shapes CAM output takes (circles, smooth spatial
// curves, noisy samples, sharp turns, collinear runs, repeated points, reversals), as points in
// metres, and checks every smoothed curve must pass.

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "blendbench/geometry/closest.hpp"
#include "blendbench/geometry/segment.hpp"
#include "property.hpp"
#include "random_geometry.hpp"

namespace blendbench::test {

enum class StreamKind { kCircle, kSpline, kNoisy, kSharpTurn, kCollinear, kRepeated, kReversal };
inline constexpr std::array<StreamKind, 7> kStreamKinds = {StreamKind::kCircle,    StreamKind::kSpline,
                                                           StreamKind::kNoisy,     StreamKind::kSharpTurn,
                                                           StreamKind::kCollinear, StreamKind::kRepeated,
                                                           StreamKind::kReversal};

inline std::string stream_name(StreamKind kind) {
  switch (kind) {
    case StreamKind::kCircle: return "circle";
    case StreamKind::kSpline: return "spline";
    case StreamKind::kNoisy: return "noisy";
    case StreamKind::kSharpTurn: return "sharp turn";
    case StreamKind::kCollinear: return "collinear";
    case StreamKind::kRepeated: return "repeated points";
    case StreamKind::kReversal: return "reversal";
  }
  return "?";
}

// A smooth spatial curve through the origin: a sum of three sinusoids per axis with random
// amplitudes (up to `size`), frequencies (up to 3 / size) and phases, advancing along x.
struct SmoothCurve {
  std::array<Vec3, 3> amplitude, frequency, phase;
  Vec3 at(double t) const {
    Vec3 p(t, 0, 0);
    for (std::size_t i = 0; i < 3; ++i) {
      for (int c = 0; c < 3; ++c) {
        p[c] += amplitude[i][c] * (std::sin(frequency[i][c] * t + phase[i][c]) - std::sin(phase[i][c]));
      }
    }
    return p;
  }
};

inline SmoothCurve random_smooth_curve(std::mt19937_64& rng, double size) {
  SmoothCurve c;
  for (std::size_t i = 0; i < 3; ++i) {
    for (int k = 0; k < 3; ++k) {
      c.amplitude[i][k] = uniform(rng, -0.15, 0.15) * size;
      c.frequency[i][k] = uniform(rng, 0.5, 3) / size;
      c.phase[i][k] = uniform(rng, 0, 2 * std::numbers::pi);
    }
  }
  return c;
}

// `count` points of the curve at roughly equal steps of t (a step of `step` m, jittered by up to
// a third).
template <class Curve>
std::vector<Vec3> sample(std::mt19937_64& rng, const Curve& curve, int count, double step) {
  std::vector<Vec3> out;
  double t = 0;
  for (int k = 0; k < count; ++k) {
    out.push_back(curve(t));
    t += step * uniform(rng, 0.67, 1.33);
  }
  return out;
}

// A random stream of `kind`: about `count` points of lines `step` m long, placed and turned at
// random, with noise below `tolerance` / 3 where the kind is noisy. Circles are partial (at
// least a quarter turn) unless `closed` (the last point repeats the first).
inline std::vector<Vec3> random_stream(std::mt19937_64& rng, StreamKind kind, int count, double step, double tolerance,
                                       bool closed = false) {
  const Vec3 origin = random_point(rng, 0.2);
  const Vec3 n = random_unit(rng);
  const Vec3 e1 = random_perpendicular(rng, n);
  const Vec3 e2 = n.cross(e1);
  std::vector<Vec3> out;
  switch (kind) {
    case StreamKind::kCircle: {
      const double sweep = closed ? 2 * std::numbers::pi : uniform(rng, 0.5 * std::numbers::pi, 1.8 * std::numbers::pi);
      const double radius = step * count / sweep;
      const Vec3 first = origin + radius * e1;
      out.push_back(first);
      for (int k = 1; k < count; ++k) {
        const double a = sweep * k / count;
        out.push_back(origin + radius * (std::cos(a) * e1 + std::sin(a) * e2));
      }
      out.push_back(closed ? first : Vec3(origin + radius * (std::cos(sweep) * e1 + std::sin(sweep) * e2)));
      return out;
    }
    case StreamKind::kSpline:
    case StreamKind::kNoisy: {
      const SmoothCurve c = random_smooth_curve(rng, step * count / 3);
      const Mat3 frame = (Mat3() << e1, e2, n).finished();
      out = sample(rng, [&](double t) { return Vec3(origin + frame * c.at(t)); }, count, step);
      if (kind == StreamKind::kNoisy) {
        for (Vec3& p : out) p += random_unit(rng) * uniform(rng, 0, tolerance / 3);
      }
      return out;
    }
    case StreamKind::kSharpTurn: {
      // two straights meeting at a vertex turning by 10..30 deg
      const double turn = uniform(rng, 10, 30) * std::numbers::pi / 180;
      const Vec3 d2 = std::cos(turn) * e1 + std::sin(turn) * e2;
      for (int k = 0; k <= count / 2; ++k) out.push_back(origin + k * step * e1);
      const Vec3 corner = out.back();
      for (int k = 1; k <= count / 2; ++k) out.push_back(corner + k * step * d2);
      return out;
    }
    case StreamKind::kCollinear: {
      double s = 0;
      for (int k = 0; k <= count; ++k) {
        out.push_back(origin + s * e1);
        s += step * uniform(rng, 0.2, 1.8);
      }
      return out;
    }
    case StreamKind::kRepeated: {
      const SmoothCurve c = random_smooth_curve(rng, step * count / 3);
      const Mat3 frame = (Mat3() << e1, e2, n).finished();
      for (const Vec3& p : sample(rng, [&](double t) { return Vec3(origin + frame * c.at(t)); }, count, step)) {
        out.push_back(p);
        if (uniform(rng, 0, 1) < 0.2) out.push_back(p);  // the same point again
      }
      return out;
    }
    case StreamKind::kReversal: {
      // out along e1 and straight back, turning by 180 deg at one point
      for (int k = 0; k <= count / 2; ++k) out.push_back(origin + k * step * e1);
      for (int k = count / 2 - 1; k >= 0; --k) out.push_back(origin + k * step * e1 + 1e-3 * step * e2);
      return out;
    }
  }
  return out;
}

// The lines through `points` as segments (repeated points skipped).
inline std::vector<Segment> polyline_segments(const std::vector<Vec3>& points) {
  std::vector<Segment> out;
  for (std::size_t k = 0; k + 1 < points.size(); ++k) {
    if ((points[k + 1] - points[k]).norm() > 0) out.emplace_back(Line{points[k], points[k + 1]});
  }
  return out;
}

// Joints of a chain of pieces: the largest tangent turn (rad) and curvature-vector jump (1/m),
// over every junction (and, closed, from the last piece's end to the first's start).
struct JointJumps {
  double angle = 0;
  double curvature = 0;
  double gap = 0;  // m: the largest distance from a piece's end to the next one's start
};
inline JointJumps joint_jumps(const std::vector<Segment>& pieces, bool closed) {
  JointJumps out;
  const std::size_t n = pieces.size();
  for (std::size_t i = 0; i + (closed ? 0 : 1) < n; ++i) {
    const Segment& a = pieces[i];
    const Segment& b = pieces[(i + 1) % n];
    const double len = length(a);
    out.angle = std::max(out.angle, angle_between(tangent(a, len), tangent(b, 0.0)));
    out.curvature = std::max(out.curvature, (curvature_vector(a, len) - curvature_vector(b, 0.0)).norm());
    out.gap = std::max(out.gap, (end_point(a) - start_point(b)).norm());
  }
  return out;
}

}  // namespace blendbench::test
