// The runs behind the reproductions: a program planned and checked (plan_run), the figures
// and tables they feed, and the statistics of a run that the reports quote.

#include "blendbench/papers/reproduce.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "blendbench/corner/blend.hpp"
#include "blendbench/timing/scurve.hpp"
#include "papers_internal.hpp"

namespace blendbench {
using namespace papers_detail;  // the helpers private to the reproductions
namespace papers_detail {

Figure figure(std::string key, std::string label, double paper, double ours, double printed_step) {
  return Figure{std::move(key), std::move(label), paper, ours, printed_step};
}

Transition transition(Method method, double parameter) {
  Transition t;
  t.method = method;
  t.parameter = parameter;
  return t;
}

int fillet_count(const Path& path) {
  return static_cast<int>(std::count_if(path.corners.begin(), path.corners.end(),
                                        [](const CornerReport& c) { return c.length > 0; }));
}

double largest_deviation(const Path& path) {
  double d = 0;
  for (const CornerReport& c : path.corners) d = std::max(d, c.deviation);
  return d;
}

// The pieces of the path, as one curve for hausdorff().
std::vector<Segment> segments_of(const Path& path) {
  std::vector<Segment> out;
  for (const PathPiece& p : path.pieces()) out.push_back(p.segment);
  return out;
}

std::vector<Segment> segments_of(const Program& program) {
  std::vector<Segment> out;
  for (const Move& m : program.moves) out.push_back(to_segment(m.geometry));
  return out;
}

// The rest-to-rest time (s) of one S-curve over `distance` (m) with tangential limits only: what
// a planner that ignores corners and curvature achieves on a path of that length.
double tangential_only_time(double distance, const Limits& limits) {
  const ScurveResult r =
      plan_scurve(distance, 0.0, 0.0, ScurveLimits{limits.velocity, limits.acceleration, limits.deceleration, limits.jerk});
  return r.curve.duration();
}

FilletFeeds fillet_feeds(const Path& path) {
  FilletFeeds f;
  for (const CornerReport& c : path.corners) {
    if (c.length <= 0) continue;
    const Limits& lim = path.pieces().front().limits;
    ++f.count;
    const double v_acc = std::sqrt(lim.acceleration / c.kappa_max);
    if (c.feed_max < v_acc) ++f.jerk_bound;
    if (c.sharpness_max > c.kappa_max * c.kappa_max) ++f.sharpness_dominated;
    f.min_feed = std::min(f.min_feed, c.feed_max);
  }
  return f;
}

// Corners whose transition parameter the blender shrank because a move is short.
int shrunk(const Path& path) {
  return static_cast<int>(std::count_if(path.corners.begin(), path.corners.end(), [](const CornerReport& c) {
    return c.note.text().find("shrunk") != std::string::npos;
  }));
}

// Transition pieces of a run, and those whose peak velocity is bound by the programmed feed.
std::pair<int, int> fillet_pieces_at_feed(const PlannedRun& run) {
  int all = 0;
  int at_feed = 0;
  for (const PieceTiming& p : run.timing.pieces) {
    if (run.path.pieces()[p.piece].corner < 0) continue;
    ++all;
    if (p.binding == Binding::kFeed) ++at_feed;
  }
  return {at_feed, all};
}

std::string optimal_label(const std::string& label, const PlannedRun& run) {
  std::string out = label + ", optimal planner";
  // where the optimal planner kept seed 004's motion on a stretch between stops (its own was not
  // found there, or was not faster), the row says so
  if (run.optimal.seed004_stretches > 0) {
    out += " (seed 004's motion kept on " + std::to_string(run.optimal.seed004_stretches) + " stretch" +
           (run.optimal.seed004_stretches == 1 ? "" : "es") + " between stops)";
  }
  return out;
}

}  // namespace papers_detail

bool Figure::within_print_rounding() const {
  if (!(printed_step > 0) || !std::isfinite(paper)) return false;
  return std::abs(ours - paper) <= 0.5 * printed_step * (1 + 1e-9) + 1e-9 * std::abs(paper);
}

const Figure& FigureTable::at(std::string_view key) const {
  for (const Figure& f : rows) {
    if (f.key == key) return f;
  }
  throw std::out_of_range("no figure '" + std::string(key) + "' in table '" + title + "'");
}

PlannedRun plan_run(std::string name, std::string description, Program program, TimingOptions::Baseline baseline) {
  PlannedRun run;
  run.name = std::move(name);
  run.description = std::move(description);
  run.program = std::move(program);
  run.path = blend(run.program);
  TimingOptions options;
  options.dt = kServoPeriod;
  options.baseline = baseline;
  // the sources' own model: tangential limits and eq. 25-27 of seed 004 (the paper tables compare
  // with it), not the vectors on the TCP that runs default to
  options.limits = LimitsMode::kPath;
  // seed 004's planner for the comparison with the papers, the optimal one beside it: in kPath
  // both hold the same rules (eq. 25-27, kappa v^2, the kink and curvature-step junction bounds;
  // timing.hpp), so the optimal plan is the faster one unless it keeps seed 004's motion
  const auto plan = [&](TimingOptions::Algorithm algorithm) {
    options.algorithm = algorithm;
    Timing timing = plan_timing(run.path, options);
    if (!timing.outcome.ok()) {
      throw std::runtime_error("reproduction '" + run.name + "' (" + std::string(algorithm_name(algorithm)) +
                               " planner): planning failed: " + timing.outcome.message);
    }
    return timing;
  };
  const std::vector<HandoverZone> zones = handover_zones(run.path, options);
  run.timing = plan(TimingOptions::Algorithm::kSeed004);
  run.margins = profile_margins(run.path, run.timing, zones);
  run.optimal = plan(TimingOptions::Algorithm::kOptimal);
  run.optimal_margins = profile_margins(run.path, run.optimal, zones);
  run.fillets = fillet_count(run.path);
  return run;
}

}  // namespace blendbench
