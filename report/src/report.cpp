#include "blendbench/core/units.hpp"
#include "blendbench/report/report.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "blendbench/core/format.hpp"
#include "blendbench/core/input_error.hpp"
#include "blendbench/report/csv.hpp"
#include "blendbench/report/json.hpp"

namespace blendbench {
namespace {

// mm from m, for output

// Intervals a piece of length `len` is sampled in (a double: len / ds may exceed any integer).
double intervals(double len, double ds) { return std::max(1.0, std::ceil(len / ds - 1e-9)); }

// Refuses a sampling of `rows` rows beyond kMaxPathSamples, naming the length and spacing.
void check_rows(double rows, double length, double ds) {
  if (rows <= kMaxPathSamples) return;
  throw InputError("", 0, 0, "ds",
                   "sampling " + format_mm(length) + " every " + format_mm(ds) + " would write " + format_value(rows, 3) +
                       " rows; the limit is " + format_value(kMaxPathSamples) + " (a larger spacing)");
}

nlohmann::json mm(const Vec3& p) { return nlohmann::json::array({p.x() / kMm, p.y() / kMm, p.z() / kMm}); }

}  // namespace

double path_sample_count(const Path& path, double ds) {
  double rows = path.pieces().empty() ? 0 : 1;
  for (const PathPiece& piece : path.pieces()) rows += intervals(length(piece.segment), ds);
  return rows;
}

std::string path_csv(const Path& path, double ds) {
  CsvWriter out({"s", "x", "y", "z", "tx", "ty", "tz", "kappa"});
  if (path.pieces().empty()) return out.text();
  check_rows(path_sample_count(path, ds), path.length(), ds);
  for (std::size_t k = 0; k < path.pieces().size(); ++k) {
    const Segment& seg = path.pieces()[k].segment;
    const double len = length(seg);
    const int n = static_cast<int>(intervals(len, ds));
    // every piece contributes its start; the last piece also its end
    const int last = k + 1 == path.pieces().size() ? n : n - 1;
    for (int i = 0; i <= last; ++i) {
      const double s = len * i / n;
      const Vec3 p = point(seg, s);
      const Vec3 t = tangent(seg, s);
      const double kappa = curvature_vector(seg, s).norm();
      out.row({(path.offset(k) + s) / kMm, p.x() / kMm, p.y() / kMm, p.z() / kMm, t.x(), t.y(), t.z(), kappa * kMm});
    }
  }
  return out.text();
}

std::string program_csv(const Program& program, double ds) {
  CsvWriter out({"s", "x", "y", "z"});
  double rows = 1;
  double total = 0;
  for (const Move& move : program.moves) {
    rows += intervals(length(move.geometry), ds);
    total += length(move.geometry);
  }
  check_rows(rows, total, ds);
  double offset = 0;
  for (std::size_t k = 0; k < program.moves.size(); ++k) {
    const Primitive& g = program.moves[k].geometry;
    const double len = length(g);
    const int n = static_cast<int>(intervals(len, ds));
    const int last = k + 1 == program.moves.size() ? n : n - 1;
    for (int i = 0; i <= last; ++i) {
      const double s = len * i / n;
      const Vec3 p = point(g, s);
      out.row({(offset + s) / kMm, p.x() / kMm, p.y() / kMm, p.z() / kMm});
    }
    offset += len;
  }
  return out.text();
}

nlohmann::json corner_json(const CornerReport& c) {
  return {
        {"index", c.index},
        {"method", std::string(to_string(c.method))},
        {"case", std::string(to_string(c.corner_case))},
        {"fallback", std::string(to_string(c.fallback))},
        {"note", c.note.text()},
        {"parameter_mm", c.parameter / kMm},
        {"length_mm", c.length / kMm},
        {"deviation_mm", c.deviation / kMm},
        {"kappa_max_per_mm", c.kappa_max * kMm},
        {"sharpness_max_per_mm2", c.sharpness_max * kMm * kMm},
        {"feed_max_mm_per_min", finite_or_null(c.feed_max / kMm * 60.0)},
        {"trim_in_mm", c.trim_in / kMm},
        {"trim_out_mm", c.trim_out / kMm},
        {"stop", c.stop},
  };
}

std::string corner_name(int index, const SourceRef& source) {
  const std::string number = std::to_string(index);  // (named: GCC 12's -Wrestrict on "C" + a temporary)
  std::string name = "C" + number;
  if (source.line <= 0) return name;
  const std::string file = std::filesystem::path(source.file).filename().string();
  return name + (file.empty() ? " (line " + std::to_string(source.line) + ")" : " (" + file + ":" + std::to_string(source.line) + ")");
}

void add_corner_tolerance_and_source(nlohmann::json& corner, const CornerReport& c) {
  const bool toleranced = c.tolerance > 0;
  corner["tolerance_mm"] = toleranced ? nlohmann::json(c.tolerance / kMm) : nlohmann::json();
  corner["tolerance_reached"] = toleranced ? nlohmann::json(c.tolerance_reached) : nlohmann::json();
  corner["source_file"] = c.source.file.empty() ? nlohmann::json() : nlohmann::json(c.source.file);
  corner["source_line"] = c.source.line > 0 ? nlohmann::json(c.source.line) : nlohmann::json();
}

nlohmann::json corner_json(const CornerReport& c, const CornerPlacement& where) {
  nlohmann::json out = corner_json(c);
  add_corner_tolerance_and_source(out, c);
  out["point_mm"] = mm(where.point);
  out["s_programmed_mm"] = where.s_programmed / kMm;
  out["s_start_mm"] = where.s_start / kMm;
  out["s_end_mm"] = where.s_end / kMm;
  return out;
}

void add_orientation_change(nlohmann::json& corner, const CornerReport& report) {
  corner["orientation_change_deg"] = report.orientation_change / kDeg;
}

nlohmann::json corners_json(const Path& path) {
  nlohmann::json out = nlohmann::json::array();
  for (const CornerReport& c : path.corners) {
    out.push_back(corner_json(c));
    if (path.oriented()) add_orientation_change(out.back(), c);
  }
  return out;
}

nlohmann::json corners_json(const Path& path, const Program& program) {
  const std::vector<CornerPlacement> where = corner_placements(path, program);
  nlohmann::json out = nlohmann::json::array();
  for (std::size_t k = 0; k < path.corners.size(); ++k) {
    out.push_back(corner_json(path.corners[k], where[k]));
    if (path.oriented()) add_orientation_change(out.back(), path.corners[k]);
  }
  return out;
}


std::string timed_csv(const Path& path, const Timing& timing) {
  CsvWriter out({"t", "s", "x", "y", "z", "v", "a", "j", "kappa"});
  out.reserve(timing.samples.size());
  for (const TimedSample& sample : timing.samples) {
    const Vec3 p = path.point(sample.s);
    const double kappa = path.curvature_vector(sample.s).norm();
    out.row({sample.t, sample.s / kMm, p.x() / kMm, p.y() / kMm, p.z() / kMm, sample.v / kMm, sample.a / kMm,
             sample.j / kMm, kappa * kMm});
  }
  return out.text();
}

nlohmann::json pieces_json(const Path& path, const Timing& timing) {
  nlohmann::json pieces = nlohmann::json::array();
  for (const PieceTiming& p : timing.pieces) {
    const PathPiece& piece = path.pieces()[p.piece];
    pieces.push_back({{"index", p.piece},
                      {"move", piece.move},
                      {"corner", piece.corner},
                      {"length_mm", length(piece.segment) / kMm},
                      {"v_peak_mm_s", p.v_peak / kMm},
                      {"binding", std::string(binding_name(p.binding))}});
  }
  return pieces;
}

void add_corner_step(nlohmann::json& corner, const CornerReport& report, const Timing::CornerStep& step) {
  corner["curvature_steps"] = std::string(to_string(report.curvature_steps));
  corner["curvature_step_per_mm"] = step.dk * kMm;
  corner["curvature_step_velocity_mm_s"] = step.velocity / kMm;
  corner["curvature_step_jerk_mm_s3"] = step.jerk / kMm;
}

void add_plan_figures(nlohmann::json& out, LimitsMode limits, int moves_merged, double merge_tolerance,
                      double cycle_time, double bound_cycle_time) {
  out["limits"] = std::string(to_string(limits));
  out["moves_merged"] = moves_merged;
  out["merge_tolerance_mm"] = merge_tolerance / kMm;
  out["bound_cycle_time_s"] = bound_cycle_time;
  out["planned_to_bound_ratio"] = finite_or_null(bound_cycle_time > 0 ? cycle_time / bound_cycle_time : 1.0);
}

nlohmann::json smoothing_json(const SmoothingReport& report) {
  return {{"method", std::string(to_string(report.method))},
          {"tolerance_mm", report.tolerance / kMm},
          {"max_turn_deg", report.max_turn / kDeg},
          {"runs", report.runs},
          {"points", report.points},
          {"pieces", report.pieces},
          {"points_added", report.points_added},
          {"max_distance_mm", report.max_distance / kMm},
          {"fit_wall_time_s", report.wall_time},
          {"notes", report.notes}};
}

PlannerFigures planner_figures(const Timing& timing) {
  return {timing.algorithm, timing.iterations, timing.seed004_stretches, timing.planning_wall_time};
}

void add_planner_figures(nlohmann::json& out, const PlannerFigures& figures) {
  out["timing"] = std::string(algorithm_name(figures.algorithm));
  out["iterations"] = figures.iterations;
  out["seed004_stretches"] = figures.seed004_stretches;
  out["planning_wall_time_s"] = figures.wall_time;
}

nlohmann::json plan_summary_json(const Path& path, const Timing& timing, const Program& program) {
  nlohmann::json corners = corners_json(path, program);
  for (std::size_t k = 0; k < corners.size() && k < path.corners.size(); ++k) {
    add_corner_step(corners[k], path.corners[k], k < timing.corner_steps.size() ? timing.corner_steps[k] : Timing::CornerStep{});
  }
  nlohmann::json out = {{"cycle_time_s", timing.cycle_time},
                        {"path_length_mm", path.length() / kMm},
                        {"feed_share", timing.feed_share},
                        {"servo_period_s", timing.dt},
                        {"corners", corners},
                        {"pieces", pieces_json(path, timing)}};
  add_plan_figures(out, timing.limits, path.moves_merged, path.merge_tolerance, timing.cycle_time, timing.bound_cycle_time);
  out["smoothing"] = smoothing_json(path.smoothing);
  add_planner_figures(out, planner_figures(timing));
  return out;
}

}  // namespace blendbench
