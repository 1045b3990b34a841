#pragma once
// Text forms of planner results for files: the sampled path as CSV and the corner reports as
// JSON, in the units of the command-line contract (mm, 1/mm, mm/min).

#include <nlohmann/json.hpp>
#include <string>

#include "blendbench/program/path.hpp"
#include "blendbench/timing/timing.hpp"
#include "blendbench/program/program.hpp"

namespace blendbench {

// The path sampled uniformly in s every `ds` m at most (both ends included), with the header
// `s,x,y,z,tx,ty,tz,kappa` in mm, unit tangent and 1/mm. Pieces are sampled separately so every
// junction appears exactly once.
std::string path_csv(const Path& path, double ds);

// The programmed moves sampled every `ds` m at most, header `s,x,y,z` (mm).
std::string program_csv(const Program& program, double ds);

// One JSON object per corner: index, method, case, fallback, note, parameter_mm, length_mm,
// deviation_mm, kappa_max_per_mm, sharpness_max_per_mm2, feed_max_mm_per_min, trim_in_mm,
// trim_out_mm, stop.
nlohmann::json corners_json(const Path& path);

// The timed profile, one row per sample: `t,s,x,y,z,v,a,j,kappa` in s, mm, mm/s, mm/s^2 and
// mm/s^3 (tangential), 1/mm.
std::string timed_csv(const Path& path, const Timing& timing);

// The plan summary of the command-line contract: cycle_time_s, path_length_mm, feed_share,
// servo_period_s, limits ("path" or "cartesian"), moves_merged and merge_tolerance_mm (collinear
// lines merged before blending, G64 Q: Path::moves_merged), bound_cycle_time_s (the time-optimal bound of
// the same path under the same limits without jerk) and planned_to_bound_ratio (cycle time over
// bound, 1 for an empty path), corners (as corners_json, plus the transition's curvature_steps,
// "limit" or "allow", and the largest curvature step the corner leaves: curvature_step_per_mm, the planned speed there curvature_step_velocity_mm_s
// and the jerk the step implies at the servo period curvature_step_jerk_mm_s3 = |dK| v^2 / dt;
// 0 where none) and pieces (index, move, corner, v_peak_mm_s, binding).
nlohmann::json plan_summary_json(const Path& path, const Timing& timing);

}  // namespace blendbench
