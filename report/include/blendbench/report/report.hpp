#pragma once
// Text forms of planner results for files: the sampled path as CSV and the corner reports as
// JSON, in the units of the command-line contract (mm, 1/mm, mm/min).

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "blendbench/program/corner_placement.hpp"
#include "blendbench/program/path.hpp"
#include "blendbench/timing/timing.hpp"
#include "blendbench/program/program.hpp"

namespace blendbench {

// The most rows of a sampled path or program (path_csv, program_csv): 10^7, about 1 GB of CSV.
inline constexpr double kMaxPathSamples = 1e7;

// The rows path_csv writes for spacing `ds` (m > 0), as a double: it may exceed any integer.
double path_sample_count(const Path& path, double ds);

// The path sampled uniformly in s every `ds` m at most (both ends included), with the header
// `s,x,y,z,tx,ty,tz,kappa` in mm, unit tangent and 1/mm. Pieces are sampled separately so every
// junction appears exactly once. Throws InputError (field "ds") when that would be more than
// kMaxPathSamples rows, before any is written.
std::string path_csv(const Path& path, double ds);

// The programmed moves sampled every `ds` m at most, header `s,x,y,z` (mm); the same limit.
std::string program_csv(const Program& program, double ds);

// One corner report as JSON: index, method, case, fallback, note, parameter_mm, length_mm,
// deviation_mm, kappa_max_per_mm, sharpness_max_per_mm2, feed_max_mm_per_min, trim_in_mm,
// trim_out_mm, stop; with a placement also point_mm ([x, y, z]), s_programmed_mm, s_start_mm
// and s_end_mm, and the fields of add_corner_tolerance_and_source.
nlohmann::json corner_json(const CornerReport& corner);
nlohmann::json corner_json(const CornerReport& corner, const CornerPlacement& where);

// A corner's name in every output (report.html, the plots, the videos; plot_run.py writes the same):
// "C<index>" (corners.json's index: the corner at the end of move `index`) and, when known, the
// file name and line it comes from (CornerReport::source), e.g. "C7 (bracket.ngc:110)".
std::string corner_name(int index, const SourceRef& source);

// Adds to a corner's JSON the equal-tolerance fields and where the corner was written
// (CornerReport): tolerance_mm and tolerance_reached (true/false; null where the corner is sized
// by its parameter), source_file and source_line (the file and line of the move that ends at the
// corner: the G-code line, or the YAML line of the move; null when unknown). (Not in the paper
// reproductions' corner lists, which keep their committed form.)
void add_corner_tolerance_and_source(nlohmann::json& corner, const CornerReport& report);

// Every corner of `path` as corner_json, without and with the placement (`program` is the
// program `path` was blended from).
// Adds "orientation_change_deg" (the rotation the corner's transition takes, orientation.hpp)
// to a corner's JSON; the corners_json functions add it on paths that carry orientation, so
// the reports of programs without one stay as they were.
void add_orientation_change(nlohmann::json& corner, const CornerReport& report);
nlohmann::json corners_json(const Path& path);
nlohmann::json corners_json(const Path& path, const Program& program);

// The timed pieces: index, move, corner, length_mm, v_peak_mm_s and the binding constraint.
nlohmann::json pieces_json(const Path& path, const Timing& timing);

// The timed profile, one row per sample: `t,s,x,y,z,v,a,j,kappa` in s, mm, mm/s, mm/s^2 and
// mm/s^3 (tangential), 1/mm.
std::string timed_csv(const Path& path, const Timing& timing);

// What the timing says about one corner (report), added to its corner_json: the transition's
// curvature_steps ("limit" or "allow") and the largest curvature step the corner leaves,
// curvature_step_per_mm, the planned speed there curvature_step_velocity_mm_s and the jerk the
// step implies at the servo period curvature_step_jerk_mm_s3 = |dK| v^2 / dt (0 where none).
void add_corner_step(nlohmann::json& corner, const CornerReport& report, const Timing::CornerStep& step);

// The plan's figures beyond its cycle time, added to `out`: limits ("path" or "cartesian"),
// moves_merged and merge_tolerance_mm (collinear lines merged before blending, G64 Q:
// Path::moves_merged), bound_cycle_time_s (the time-optimal bound of the same path under the
// same limits without jerk) and planned_to_bound_ratio (cycle time over bound, 1 for an empty
// path).
void add_plan_figures(nlohmann::json& out, LimitsMode limits, int moves_merged, double merge_tolerance,
                      double cycle_time, double bound_cycle_time);

// What smoothing did (the summary's plan.smoothing, Path::smoothing): method, tolerance_mm
// (g2_fit's, else 0), max_turn_deg (clothoid_points', else 0), runs (streams smoothed), points
// (their programmed points), pieces (the curves' pieces), points_added (clothoid_points),
// max_distance_mm (the largest measured Hausdorff distance between a curve and its stream, both
// ways, an upper bound), fit_wall_time_s (the cost of finding and fitting the streams) and
// notes (streams kept as lines, and why).
nlohmann::json smoothing_json(const SmoothingReport& report);

// Which velocity planner made a plan and what it took (Timing's figures).
struct PlannerFigures {
  TimingOptions::Algorithm algorithm = TimingOptions::Algorithm::kOptimal;
  int iterations = 0;         // Timing::iterations
  int seed004_stretches = 0;  // Timing::seed004_stretches
  double wall_time = 0;       // s, Timing::planning_wall_time
};
PlannerFigures planner_figures(const Timing& timing);

// Adds them to `out`: timing ("optimal" or "seed004"), iterations, seed004_stretches and
// planning_wall_time_s (the velocity planner's own wall clock).
void add_planner_figures(nlohmann::json& out, const PlannerFigures& figures);

// The plan summary of the command-line contract: cycle_time_s, path_length_mm, feed_share,
// servo_period_s, the figures of add_plan_figures and add_planner_figures, corners
// (corners_json with placements and add_corner_step), pieces (pieces_json) and smoothing (smoothing_json).
nlohmann::json plan_summary_json(const Path& path, const Timing& timing, const Program& program);

}  // namespace blendbench
