#include "blendbench/program/smoothing.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <chrono>
#include <cmath>
#include <numbers>
#include <string>
#include <tuple>
#include <utility>

#include "blendbench/core/format.hpp"
#include "blendbench/core/interrupt.hpp"
#include "blendbench/geometry/follow_distance.hpp"
#include "blendbench/program/clothoid_points.hpp"
#include "blendbench/program/g2_fit.hpp"
#include "blendbench/program/program.hpp"

namespace blendbench {
namespace {

constexpr std::array<std::pair<SmoothingMethod, std::string_view>, 3> kNames = {{
    {SmoothingMethod::kNone, "none"},
    {SmoothingMethod::kClothoidPoints, "clothoid_points"},
    {SmoothingMethod::kG2Fit, "g2_fit"},
}};

// A closed stream ends within this share of its length of where it starts (the program's
// join tolerance, program.hpp validate), and at least kMinClosure (m).
constexpr double kRelativeClosure = 1e-9;
constexpr double kMinClosure = 1e-12;
// g2_fit's streams also break where the direction, each side taken over this many tolerances
// of the lines, turns by stream_turn or more: a cusp drawn with lines shorter than the tolerance
// turns little at each vertex, but no curve within the tolerance turns round it smoothly.
constexpr double kTurnWindow = 2;
// clothoid_points' distance is measured at this share of the stream's mean line length, with
// the reach of this many longest lines (follow_distance.hpp).
constexpr double kPointsResolutionShare = 0.05;
constexpr double kPointsReachLines = 2;

bool same_limits(const Limits& a, const Limits& b) {
  return a.velocity == b.velocity && a.acceleration == b.acceleration && a.deceleration == b.deceleration &&
         a.jerk == b.jerk;
}

std::string move_name(const Program& program, std::size_t k) {
  const Move& move = program.moves[k];
  return move.name.empty() ? "move " + std::to_string(k + 1) : move.name;
}

const Line* stream_line(const Move& move, double max_length) {
  const Line* line = std::get_if<Line>(&move.geometry);
  if (line == nullptr || move.orientation || !(length(*line) < max_length)) return nullptr;
  return line;
}

}  // namespace

std::string_view to_string(SmoothingMethod method) {
  for (const auto& [m, name] : kNames) {
    if (m == method) return name;
  }
  return "unknown";
}

std::optional<SmoothingMethod> smoothing_method_from_string(std::string_view name) {
  std::string key(name);
  std::transform(key.begin(), key.end(), key.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const auto& [m, n] : kNames) {
    if (n == key) return m;
  }
  return std::nullopt;
}

void validate(const Smoothing& smoothing) {
  for (const auto& [value, field, what] :
       {std::tuple{smoothing.tolerance, "smoothing.tolerance", "the smoothing tolerance"},
        std::tuple{smoothing.stream_length, "smoothing.stream_length", "the stream line length"}}) {
    if (!(value > 0) || !std::isfinite(value)) {
      fail_at(smoothing.where, field, std::string(what) + " must be positive, got " + format_mm(value));
    }
  }
  for (const auto& [value, field, what] :
       {std::tuple{smoothing.max_turn, "smoothing.max_turn_deg", "the largest turn of a clothoid pair"},
        std::tuple{smoothing.stream_turn, "smoothing.stream_turn_deg", "the stream vertex turn"}}) {
    if (!(value > 0 && value < std::numbers::pi)) {
      fail_at(smoothing.where, field, std::string(what) + " must be between 0 and 180 deg, got " + format_deg(value));
    }
  }
}

std::vector<StreamRun> find_streams(const Program& program, const Smoothing& smoothing) {
  std::vector<StreamRun> out;
  const auto& moves = program.moves;
  const std::size_t n = moves.size();
  // the point `distance` back from the end of line k (forward from its start when `ahead`)
  // along consecutive lines, or the farthest one reached where the lines end
  const auto along = [&](std::size_t k, double distance, bool ahead) {
    for (;;) {
      const Line& line = std::get<Line>(moves[k].geometry);
      const double len = length(line);
      if (distance <= len) return Vec3(ahead ? line.p0 + (line.p1 - line.p0) * (distance / len) : line.p1 + (line.p0 - line.p1) * (distance / len));
      distance -= len;
      const bool more = ahead ? k + 1 < n && std::holds_alternative<Line>(moves[k + 1].geometry)
                              : k > 0 && std::holds_alternative<Line>(moves[k - 1].geometry);
      if (!more) return ahead ? line.p1 : line.p0;
      k = ahead ? k + 1 : k - 1;
    }
  };
  const double window = smoothing.method == SmoothingMethod::kG2Fit ? kTurnWindow * smoothing.tolerance : 0.0;
  // whether the vertex between lines k and k + 1 (both stream lines) lies inside a stream: it
  // turns by less than stream_turn, from line to line and (g2_fit) over the window each side
  const auto linked = [&](std::size_t k) {
    const Line* a = stream_line(moves[k], smoothing.stream_length);
    const Line* b = stream_line(moves[k + 1], smoothing.stream_length);
    if (a == nullptr || b == nullptr || !same_limits(moves[k].limits, moves[k + 1].limits) ||
        moves[k].buffer != moves[k + 1].buffer || !(angle_between(a->p1 - a->p0, b->p1 - b->p0) < smoothing.stream_turn)) {
      return false;
    }
    if (!(window > 0)) return true;
    const Vec3 before = a->p1 - along(k, window, false);
    const Vec3 after = along(k + 1, window, true) - b->p0;
    return angle_between(before, after) < smoothing.stream_turn;
  };
  for (std::size_t k = 0; k < n;) {
    if (stream_line(moves[k], smoothing.stream_length) == nullptr) {
      ++k;
      continue;
    }
    std::size_t last = k;
    while (last + 1 < n && linked(last)) ++last;
    if (last + 1 - k >= kMinStreamLines) out.push_back({k, last, false});
    k = last + 1;
  }
  // closed: one stream of the whole program that ends where it starts, a stream vertex there too
  if (out.size() == 1 && out.front().first == 0 && out.front().last + 1 == n) {
    const Line& first = std::get<Line>(moves.front().geometry);
    const Line& last = std::get<Line>(moves.back().geometry);
    double total = 0;
    for (const Move& m : moves) total += length(m.geometry);
    const bool meets = (last.p1 - first.p0).norm() <= std::max(kRelativeClosure * total, kMinClosure);
    out.front().closed = meets && same_limits(moves.front().limits, moves.back().limits) &&
                         moves.front().buffer == moves.back().buffer &&
                         angle_between(last.p1 - last.p0, first.p1 - first.p0) < smoothing.stream_turn;
  }
  return out;
}

SmoothedProgram smooth_streams(const Program& program) {
  SmoothedProgram out;
  const Smoothing& spec = program.smoothing;
  SmoothingReport& report = out.report;
  report.method = spec.method;
  if (spec.method == SmoothingMethod::kNone) return out;
  report.tolerance = spec.method == SmoothingMethod::kG2Fit ? spec.tolerance : 0.0;
  report.max_turn = spec.method == SmoothingMethod::kClothoidPoints ? spec.max_turn : 0.0;
  const auto start = std::chrono::steady_clock::now();
  const std::size_t n = program.moves.size();
  for (const StreamRun& run : find_streams(program, spec)) {
    throw_if_stop_requested();
    const auto line = [&](std::size_t k) -> const Line& { return std::get<Line>(program.moves[k].geometry); };
    SmoothedRun smoothed;
    smoothed.run = run;
    smoothed.start_anchored = !run.closed && run.first > 0;
    smoothed.end_anchored = !run.closed && run.last + 1 < n;
    // the points: the run's vertices, from the middle of its first line and to the middle of its
    // last where a move joins it there
    std::vector<Vec3> points;
    points.reserve(run.last - run.first + 2);
    points.push_back(smoothed.start_anchored ? Vec3(0.5 * (line(run.first).p0 + line(run.first).p1)) : line(run.first).p0);
    for (std::size_t k = run.first; k < run.last; ++k) points.push_back(line(k).p1);
    points.push_back(smoothed.end_anchored ? Vec3(0.5 * (line(run.last).p0 + line(run.last).p1)) : line(run.last).p1);
    CurveEnds ends;
    ends.closed = run.closed;
    if (smoothed.start_anchored) ends.start_tangent = (line(run.first).p1 - line(run.first).p0).normalized();
    if (smoothed.end_anchored) ends.end_tangent = (line(run.last).p1 - line(run.last).p0).normalized();

    CurveFit fit;
    double distance = -1;
    if (spec.method == SmoothingMethod::kG2Fit) {
      G2FitStats stats;
      fit = g2_fit(points, ends, spec.tolerance, &stats);
      distance = stats.distance;
    } else {
      fit = clothoid_points(points, ends, spec.max_turn);
    }
    const std::string which = move_name(program, run.first) + " to " + move_name(program, run.last) + " (a stream of " +
                              std::to_string(run.last - run.first + 1) + " lines)";
    if (!fit.outcome.ok()) {
      report.notes.push_back(which + " kept as lines: " + std::string(to_string(spec.method)) + ": " + fit.outcome.message);
      continue;
    }
    if (spec.method == SmoothingMethod::kClothoidPoints) {
      double longest = 0;
      for (std::size_t k = 0; k + 1 < points.size(); ++k) longest = std::max(longest, (points[k + 1] - points[k]).norm());
      double total = 0;
      for (std::size_t k = 0; k + 1 < points.size(); ++k) total += (points[k + 1] - points[k]).norm();
      const double mean = total / static_cast<double>(points.size() - 1);
      distance = follow_distance(fit.pieces, fit.span_begin, fit.span_end, points, kPointsResolutionShare * mean,
                                 kPointsReachLines * longest)
                     .hausdorff();
    }
    smoothed.curve = std::move(fit.pieces);
    smoothed.piece_move.reserve(fit.piece_segment.size());
    for (const std::size_t segment : fit.piece_segment) smoothed.piece_move.push_back(run.first + segment);
    smoothed.distance = distance;
    smoothed.points = static_cast<int>(run.last - run.first + 2);
    ++report.runs;
    report.points += smoothed.points;
    report.pieces += static_cast<int>(smoothed.curve.size());
    report.points_added += fit.points_added;
    report.max_distance = std::max(report.max_distance, distance);
    out.runs.push_back(std::move(smoothed));
  }
  report.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace blendbench
