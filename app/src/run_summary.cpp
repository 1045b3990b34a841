#include "blendbench/core/units.hpp"
#include "blendbench/app/run_summary.hpp"

#include <cmath>
#include <numbers>

#include "blendbench/report/json.hpp"

namespace blendbench {
namespace {

constexpr double kMrad = 1e3;   // mrad per rad
constexpr double kTwoPi = 2 * std::numbers::pi;

nlohmann::json values(const JointVector& v, double scale = 1) {
  nlohmann::json out = nlohmann::json::array();
  for (int i = 0; i < 6; ++i) out.push_back(finite_or_null(v[i] * scale));
  return out;
}

// A pose as position (mm) and roll, pitch, yaw (deg, fixed axes as in URDF).
nlohmann::json pose_json(const Eigen::Isometry3d& pose) {
  const Vec3 p = pose.translation() / kMm;
  const Vec3 rpy = rpy_from_rotation(pose.linear()) / kDeg;
  return {{"position_mm", {p.x(), p.y(), p.z()}}, {"rpy_deg", {rpy.x(), rpy.y(), rpy.z()}}};
}

// The program frame: origin (mm), roll, pitch, yaw (deg) and the rotation matrix (rows), so a
// reader maps a base-frame point p to program coordinates as R^T (p - origin).
nlohmann::json frame_json(const Eigen::Isometry3d& frame) {
  nlohmann::json out = pose_json(frame);
  nlohmann::json rows = nlohmann::json::array();
  for (int i = 0; i < 3; ++i) rows.push_back({frame.linear()(i, 0), frame.linear()(i, 1), frame.linear()(i, 2)});
  out["rotation"] = rows;
  return out;
}

nlohmann::json singularities_json(const std::vector<SingularityPassage>& passages) {
  nlohmann::json out = nlohmann::json::array();
  for (const SingularityPassage& p : passages) {
    out.push_back({{"kind", std::string(to_string(p.kind))},
                   {"t_s", p.t},
                   {"t_start_s", p.t_start},
                   {"t_end_s", p.t_end},
                   {"pose", pose_json(p.pose)},
                   {"measure", p.measure},
                   {"threshold", p.threshold}});
  }
  return out;
}

nlohmann::json branch_changes_json(const std::vector<BranchChange>& changes) {
  nlohmann::json out = nlohmann::json::array();
  for (const BranchChange& c : changes) {
    out.push_back({{"kind", std::string(to_string(c.kind))},
                   {"t_s", c.t},
                   {"pose", pose_json(c.pose)},
                   {"measure_before", c.before},
                   {"measure_after", c.after}});
  }
  return out;
}

// The chain's joints with their URDF limits (deg, deg/s, N*m; null where unlimited).
nlohmann::json joints_json(const std::vector<JointSpec>& joints) {
  nlohmann::json out = nlohmann::json::array();
  for (const JointSpec& j : joints) {
    out.push_back({{"name", j.name},
                   {"lower_deg", finite_or_null(j.lower / kDeg)},
                   {"upper_deg", finite_or_null(j.upper / kDeg)},
                   {"velocity_deg_s", finite_or_null(j.velocity_limit / kDeg)},
                   {"effort_nm", finite_or_null(j.effort_limit)}});
  }
  return out;
}

nlohmann::json vibration_json(const Vibration& v) {
  return {{"t_start_s", v.t_start},
          {"t_end_s", v.t_end},
          {"peak_to_peak_mm", v.peak_to_peak / kMm},
          {"frequency_hz", v.frequency}};
}

double corner_vibration_max(const Metrics& m) {
  double out = 0;
  for (const Vibration& v : m.vibration_corners) out = std::max(out, v.peak_to_peak);
  return out;
}

// The keep-out report of a variant (sim/workspace.hpp), mm and s; null where none applies.
nlohmann::json workspace_json(const WorkspaceFigures& w) {
  return {{"floor_z_mm", finite_or_null(w.zones.floor_z / kMm)},
          {"floor_clearance_mm", w.zones.floor_clearance / kMm},
          {"tcp_z_min_mm", finite_or_null(w.report.tcp_z_min / kMm)},
          {"below_floor", w.report.below_floor},
          {"below_floor_t_s", finite_or_null(w.report.below_floor_t)},
          {"base_radius_mm", w.zones.base_radius / kMm},
          {"base_top_mm", w.zones.base_top / kMm},
          {"base_distance_min_mm", finite_or_null(w.report.base_distance_min / kMm)},
          {"into_base", w.report.into_base},
          {"into_base_t_s", finite_or_null(w.report.into_base_t)}};
}

nlohmann::json metrics_json(const Metrics& m) {
  nlohmann::json corners = nlohmann::json::array();
  for (std::size_t c = 0; c < m.vibration_corners.size(); ++c) {
    nlohmann::json v = vibration_json(m.vibration_corners[c]);
    v["corner"] = c;
    corners.push_back(std::move(v));
  }
  return {
      {"cycle_time_s", m.cycle_time ? nlohmann::json(*m.cycle_time) : nlohmann::json()},
      {"settled", m.cycle_time.has_value()},
      {"tracking_error_max_mm", m.tracking_error_max / kMm},
      {"tracking_error_rms_mm", m.tracking_error_rms / kMm},
      {"orientation_error_max_deg", m.orientation_error_max / kDeg},
      {"orientation_error_rms_deg", m.orientation_error_rms / kDeg},
      {"angular_velocity_peak_deg_s", m.angular_velocity_peak / kDeg},
      {"angular_velocity_commanded_peak_deg_s", m.angular_velocity_commanded_peak / kDeg},
      {"contour_error_programmed_max_mm", m.contour_error_programmed_max / kMm},
      {"contour_error_planned_max_mm", m.contour_error_planned_max / kMm},
      {"jerk_actual_peak_mm_s3", m.jerk_actual_peak / kMm},
      {"jerk_actual_rms_mm_s3", m.jerk_actual_rms / kMm},
      {"jerk_commanded_peak_mm_s3", m.jerk_commanded_peak / kMm},
      {"jerk_commanded_rms_mm_s3", m.jerk_commanded_rms / kMm},
      {"residual_vibration_final_mm", m.vibration_final.peak_to_peak / kMm},
      {"residual_vibration_final_frequency_hz", m.vibration_final.frequency},
      {"residual_vibration_final", vibration_json(m.vibration_final)},
      {"residual_vibration_corner_max_mm", corner_vibration_max(m) / kMm},
      {"residual_vibration_corners", corners},
      // process figures on the actual TCP between the first and the last move (metrics.hpp)
      {"path_share_below_90pct_speed", m.process ? nlohmann::json(m.process->share_below_90pct_speed) : nlohmann::json()},
      {"min_speed_mm_s", m.process ? nlohmann::json(m.process->min_speed / kMm) : nlohmann::json()},
      {"process_window_mm", m.process ? nlohmann::json::array({m.process->s_start / kMm, m.process->s_end / kMm})
                                      : nlohmann::json()},
      {"joints",
       {{"following_error_max_mrad", values(m.following_error_max, kMrad)},
        {"following_error_rms_mrad", values(m.following_error_rms, kMrad)},
        {"torque_peak_nm", values(m.torque_peak)},
        {"torque_rms_nm", values(m.torque_rms)},
        {"energy_j", values(m.energy)},
        {"velocity_peak_rad_s", values(m.velocity_peak)},
        {"acceleration_peak_rad_s2", values(m.acceleration_peak)}}},
  };
}

nlohmann::json limit_json(const LimitCheck& c) {
  nlohmann::json out = {{"exceeded", c.exceeded}};
  if (c.exceeded) {
    out["t_s"] = c.t;
    out["joint"] = c.joint + 1;
    out["value"] = c.value;
    out["limit"] = c.limit;
  }
  return out;
}

nlohmann::json health_json(const Health& h) {
  nlohmann::json ticks = nlohmann::json::array();
  for (const long n : h.saturated_ticks) ticks.push_back(n);
  return {{"saturated", h.saturated},
          {"saturated_ticks", ticks},
          {"saturated_share", values(h.saturated_share)},
          {"limits_exceeded", h.limits_exceeded()},
          {"reference_velocity_limit", limit_json(h.reference_velocity)},
          {"reference_acceleration_limit", limit_json(h.reference_acceleration)},
          {"actual_velocity_limit", limit_json(h.actual_velocity)},
          {"actual_acceleration_limit", limit_json(h.actual_acceleration)}};
}

nlohmann::json plan_json(const PlanFigures& p) {
  nlohmann::json out = {{"path_length_mm", p.path_length / kMm},
                        {"planned_cycle_time_s", p.planned_cycle_time},
                        {"feed_share", p.feed_share},
                        {"path_deviation_max_mm", p.path_deviation_max / kMm},
                        {"corners", corners_json(p)},
                        {"pieces", p.pieces}};
  add_plan_figures(out, p.limits, p.moves_merged, p.merge_tolerance, p.planned_cycle_time, p.bound_cycle_time);
  out["smoothing"] = smoothing_json(p.smoothing);
  add_planner_figures(out, p.planner);
  return out;
}

nlohmann::json timings_json(const Timings& t) {
  return {{"planning_wall_time_s", t.planning},
          {"inverse_kinematics_wall_time_s", t.inverse_kinematics},
          {"simulated_s", t.simulated},
          {"sim_wall_time_s", t.simulation},
          {"video_wall_time_s", t.video},
          {"real_time_factor", t.real_time_factor()},
          {"real_time_factor_with_video", t.real_time_factor_with_video()}};
}

nlohmann::json comparison_json(const ExactStopComparison& c) {
  nlohmann::json out = {{"reference_variant", c.reference},
                        {"cycle_time_saved_percent", c.cycle_time_saved_percent ? nlohmann::json(*c.cycle_time_saved_percent)
                                                                                : nlohmann::json()}};
  for (const auto& [key, value] : c.ratios) out[key] = value ? finite_or_null(*value) : nlohmann::json();
  return out;
}

nlohmann::json servo_json(ServoController controller, const ServoConfig& s) {
  return {{"controller", controller == ServoController::kPd ? "pd" : "cascade"},
          {"rate_hz", s.rate_hz},
          {"setpoint_rate_hz", s.setpoint_rate_hz},
          {"measurement_delay_ticks", s.measurement_delay_ticks},
          {"encoder_counts_per_turn", s.encoder_counts_per_turn},
          {"velocity_feedforward", s.velocity_feedforward},
          {"acceleration_feedforward", s.acceleration_feedforward},
          {"gravity_compensation", s.gravity_compensation},
          {"deflection_compensation", s.deflection_compensation},
          {"velocity_bandwidth_hz", values(s.velocity_bandwidth, 1 / kTwoPi)},
          {"position_bandwidth_hz", values(s.position_bandwidth, 1 / kTwoPi)},
          {"kp_per_s", values(s.kp)},
          {"kv_nm_s_per_rad", values(s.kv)},
          {"ki_nm_per_rad", values(s.ki)}};
}

// The errors compared with the exact stop: (ratio key, value of a variant's metrics) pairs.
std::vector<std::pair<std::string, double>> compared_errors(const Metrics& m) {
  return {{"tracking_error_max_ratio", m.tracking_error_max},
          {"tracking_error_rms_ratio", m.tracking_error_rms},
          {"orientation_error_max_ratio", m.orientation_error_max},
          {"contour_error_programmed_max_ratio", m.contour_error_programmed_max},
          {"contour_error_planned_max_ratio", m.contour_error_planned_max},
          {"jerk_actual_peak_ratio", m.jerk_actual_peak},
          {"residual_vibration_final_ratio", m.vibration_final.peak_to_peak},
          {"residual_vibration_corner_max_ratio", corner_vibration_max(m)},
          {"following_error_max_ratio", m.following_error_max.maxCoeff()},
          {"energy_ratio", m.energy.sum()}};
}

nlohmann::json optional_json(const std::optional<double>& value, double scale = 1) {
  return value ? finite_or_null(*value * scale) : nlohmann::json();
}

// summary.json's `ranking` (ranking.hpp, docs/compare.md): the resolution the ties used, the
// constraints, and per tolerance the variants by cycle time.
nlohmann::json ranking_json(const Ranking& r) {
  nlohmann::json groups = nlohmann::json::array();
  for (const RankGroup& g : r.groups) {
    nlohmann::json ranked = nlohmann::json::array();
    for (const RankedVariant& v : g.ranked) {
      ranked.push_back({{"rank", v.rank},
                        {"variant", v.name},
                        {"cycle_time_s", v.cycle_time},
                        {"margin_to_next_s", optional_json(v.margin)},
                        {"margin_to_next_percent", optional_json(v.margin_percent)},
                        {"tie", v.tie},
                        {"meets_constraints", v.meets_constraints}});
    }
    nlohmann::json unranked = nlohmann::json::array();
    for (const UnrankedVariant& v : g.unranked) unranked.push_back({{"variant", v.name}, {"reason", v.reason}});
    groups.push_back({{"tolerance_mm", g.tolerance > 0 ? nlohmann::json(g.tolerance / kMm) : nlohmann::json()},
                      {"like_for_like", g.like_for_like},
                      {"variants", ranked},
                      {"unranked", unranked}});
  }
  const CycleResolution& res = r.resolution;
  const std::string rule =
      r.spread_used ? "a tie where the order of the two cycle times does not hold in every perturbed arm model, or where "
                      "they differ by less than grid_s"
                    : "a tie where two cycle times differ by less than max(grid_s, absolute_s, relative x the faster)";
  return {{"resolution",
           {{"grid_s", res.grid},
            {"absolute_s", res.absolute},
            {"relative", res.relative},
            {"model_spread", r.spread_used},
            {"rule", rule},
            {"source", r.spread_used ? "the sensitivity runs (the arm model's stated uncertainty) and the setpoint grid"
                                     : "two setpoint periods (each settle instant lies on the setpoint grid) and the "
                                       "regression gate's cycle-time tolerance (results/baselines/tolerances.json, "
                                       "metrics.cycle_time_s); no sensitivity run"}}},
          {"constraints",
           {{"max_contour_error_mm", optional_json(r.constraints.max_contour_error, 1 / kMm)},
            {"max_vibration_um", optional_json(r.constraints.max_vibration, 1e3 / kMm)}}},
          {"tolerances", groups}};
}

}  // namespace

Ranking rank_run(const RunSummary& summary, const Constraints& constraints, const OrderSpread& spread) {
  std::vector<RankCandidate> candidates;
  for (const VariantSummary& v : summary.variants) {
    RankCandidate c;
    c.name = v.name;
    c.method = v.method;
    c.tolerance = v.tolerance;
    c.clean = v.status == VariantStatus::kOk;
    c.status = std::string(to_string(v.status));
    if (v.metrics) {
      c.cycle_time = v.metrics->cycle_time;
      c.contour_error = v.metrics->contour_error_programmed_max;
      c.vibration = std::max(v.metrics->vibration_final.peak_to_peak, corner_vibration_max(*v.metrics));
    }
    candidates.push_back(std::move(c));
  }
  const double rate = summary.servo.setpoint_rate_hz;
  return rank(candidates, constraints, cycle_resolution(rate > 0 ? 1 / rate : 0), spread);
}

nlohmann::json corners_json(const PlanFigures& p) {
  nlohmann::json corners = nlohmann::json::array();
  for (std::size_t k = 0; k < p.corners.size(); ++k) {
    nlohmann::json c = k < p.placements.size() ? corner_json(p.corners[k], p.placements[k]) : corner_json(p.corners[k]);
    if (k >= p.placements.size()) add_corner_tolerance_and_source(c, p.corners[k]);
    if (k < p.corner_times.size()) {
      c["t_start_s"] = p.corner_times[k].t_start;
      c["t_end_s"] = p.corner_times[k].t_end;
    }
    add_corner_step(c, p.corners[k], k < p.corner_steps.size() ? p.corner_steps[k] : Timing::CornerStep{});
    if (p.oriented) add_orientation_change(c, p.corners[k]);
    corners.push_back(std::move(c));
  }
  return corners;
}

std::string_view to_string(VariantStatus status) {
  switch (status) {
    case VariantStatus::kOk:
      return "ok";
    case VariantStatus::kSaturated:
      return "saturated";
    case VariantStatus::kLimitExceeded:
      return "limit_exceeded";
    case VariantStatus::kNotSettled:
      return "not_settled";
    case VariantStatus::kDiverged:
      return "diverged";
    case VariantStatus::kPlanningFailed:
      return "planning_failed";
    case VariantStatus::kFailed:
      return "failed";
    case VariantStatus::kInterrupted:
      return "interrupted";
  }
  return "?";
}

void compare_with_exact_stop(RunSummary& summary) {
  const VariantSummary* reference = nullptr;
  for (const VariantSummary& v : summary.variants) {
    if (v.method == Method::kNone && v.status == VariantStatus::kOk && v.metrics && v.metrics->cycle_time) {
      reference = &v;
      break;
    }
  }
  if (reference == nullptr) return;
  const double t_ref = *reference->metrics->cycle_time;
  const auto errors_ref = compared_errors(*reference->metrics);
  for (VariantSummary& v : summary.variants) {
    if (!v.metrics) continue;
    ExactStopComparison c;
    c.reference = reference->name;
    if (v.metrics->cycle_time && t_ref > 0) c.cycle_time_saved_percent = 100 * (t_ref - *v.metrics->cycle_time) / t_ref;
    const auto errors = compared_errors(*v.metrics);
    for (std::size_t k = 0; k < errors.size(); ++k) {
      const double base = errors_ref[k].second;
      c.ratios.emplace_back(errors[k].first, base > 0 ? std::optional<double>(errors[k].second / base) : std::nullopt);
    }
    v.comparison = std::move(c);
  }
}

void to_json(nlohmann::json& out, const VariantSummary& v) {
  out = {{"name", v.name},
         {"method", std::string(to_string(v.method))},
         {"parameter_mm", v.parameter / kMm},
         {"tolerance_mm", v.tolerance > 0 ? nlohmann::json(v.tolerance / kMm) : nlohmann::json()},
         {"baseline", std::string(baseline_name(v.baseline))},
         {"status", std::string(to_string(v.status))},
         {"plan", plan_json(v.plan)},
         {"timings", timings_json(v.timings)}};
  if (!v.message.empty()) out["message"] = v.message;
  if (!v.warning.empty()) out["warning"] = v.warning;
  if (v.metrics) out["metrics"] = metrics_json(*v.metrics);
  if (v.health) out["health"] = health_json(*v.health);
  if (v.workspace) out["workspace"] = workspace_json(*v.workspace);
  if (v.comparison) out["comparison"] = comparison_json(*v.comparison);
  if (v.joint_usage) {
    const JointUsage& u = *v.joint_usage;
    out["joint_limits_used"] = {{"velocity_share", values(u.velocity_share)},
                                {"acceleration_share", values(u.acceleration_share)},
                                {"torque_share", values(u.torque_share)},
                                {"position_margin_deg", values(u.position_margin, 1 / kDeg)}};
  }
  out["singularities"] = singularities_json(v.singularities);
  if (!v.branch_changes.empty()) out["branch_changes"] = branch_changes_json(v.branch_changes);
}

void to_json(nlohmann::json& out, const RunSummary& s) {
  const RobotInfo& r = s.robot;
  const SimulationSettings& sim = s.simulation;
  nlohmann::json warnings = nlohmann::json::array();
  for (const LoadWarning& w : s.warnings) {
    warnings.push_back({{"file", w.where.file}, {"line", w.where.line}, {"column", w.where.column}, {"field", w.field},
                        {"message", w.message}, {"text", to_string(w)}});
  }
  out = {{"version", s.version},
         {"scenario", s.scenario},
         {"file", s.file},
         {"warnings", warnings},
         {"description", s.description},
         {"frame", frame_json(s.frame)},
         {"robot",
          {{"model", r.model == ArmModel::kElastic ? "elastic" : "rigid"},
           {"mjcf", r.mjcf},
           {"urdf", r.urdf},
           {"ik", std::string(to_string(r.ik_method))},
           {"tool", pose_json(r.tool)},
           {"joints", joints_json(r.joints)},
           {"notes", r.notes},
           {"timestep_s", r.timestep},
           {"start_q_deg", values(r.start_q, 1 / kDeg)},
           {"torque_limits_nm", values(r.limits.torque)},
           {"velocity_limits_rad_s", values(r.limits.velocity)},
           {"acceleration_limits_rad_s2", values(r.limits.acceleration)},
           {"natural_frequency_per_joint_hz", values(r.natural_frequency_per_joint)},
           {"natural_frequency_arm_hz", values(r.natural_frequency_arm)}}},
         {"servo", servo_json(s.controller, s.servo)},
         {"simulation",
          {{"settle_tolerance_mm", sim.settle_tolerance / kMm},
           {"settle_speed_tolerance_mm_s", sim.settle_speed_tolerance / kMm},
           {"settle_window_s", sim.settle_window},
           {"settle_time_s", sim.settle_time},
           {"vibration_window_s", sim.vibration_window},
           {"vibration_highpass_hz", sim.vibration_highpass},
           {"jerk_lowpass_hz", sim.jerk_lowpass}}},
         {"servo_rate_hz", s.servo.rate_hz},
         {"setpoint_rate_hz", s.servo.setpoint_rate_hz},
         {"notes", s.notes},
         {"variants", s.variants}};
  if (s.sensitivity) out["sensitivity"] = sensitivity_json(*s.sensitivity);
  if (s.ranking) {
    out["ranking"] = ranking_json(*s.ranking);
    out["recommendation"] = {{"variant", s.ranking->recommendation.variant ? nlohmann::json(*s.ranking->recommendation.variant)
                                                                           : nlohmann::json()},
                             {"reason", s.ranking->recommendation.reason}};
  }
}

}  // namespace blendbench
