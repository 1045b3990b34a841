#include "blendbench/core/units.hpp"
#include "blendbench/app/runner.hpp"

#include <algorithm>
#include <atomic>
#include <cassert>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <mutex>
#include <numbers>
#include <optional>
#include <thread>

#include "blendbench/core/format.hpp"
#include "blendbench/core/interrupt.hpp"
#include "blendbench/corner/blend.hpp"
#include "blendbench/app/unit_text.hpp"
#include "blendbench/app/version.hpp"
#include "blendbench/io/urdf_chain.hpp"
#include "blendbench/io/urdf_model.hpp"
#include "blendbench/report/csv.hpp"
#include "blendbench/report/output.hpp"
#include "blendbench/report/process.hpp"
#include "blendbench/io/data_root.hpp"
#include "blendbench/robot/ik.hpp"
#include "blendbench/sim/execution.hpp"
#include "blendbench/sim/workspace.hpp"
#include "blendbench/timing/timing.hpp"
#include "progress_bar.hpp"
#include "sweep_pool.hpp"
#ifdef BLENDBENCH_HAS_RENDER
#include "run_video.hpp"
#endif

namespace blendbench {
namespace {

using Clock = std::chrono::steady_clock;
// Path sampling for path.csv / program.csv (m): fine enough for plots, small enough for files.
constexpr double kCsvStep = 0.5e-3;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

Eigen::Isometry3d tool_pose(const Vec3& position, const Eigen::Matrix3d& rotation) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = rotation;
  pose.translation() = position;
  return pose;
}

std::string pose_text(const Vec3& p) {
  char buffer[96];
  std::snprintf(buffer, sizeof buffer, "(%.1f, %.1f, %.1f) mm", p.x() / kMm, p.y() / kMm, p.z() / kMm);
  return buffer;
}

// The programmed move a path arc length belongs to (a transition counts as its incoming move).
std::size_t move_at(const Path& path, double s) {
  const PathPiece& piece = path.pieces()[path.locate(s).piece];
  if (piece.move >= 0) return static_cast<std::size_t>(piece.move);
  return static_cast<std::size_t>(std::max(piece.corner, 0));
}

// The error of move `move` of the program, positioned where it was written.
InputError move_error(const RunInputs& sc, const Program& program, std::size_t move, const std::string& what) {
  const SourceRef& where = program.moves[move].where;
  return {where.file.empty() ? sc.file : where.file, where.line, where.column,
          "program.moves[" + std::to_string(move) + "]", what};
}

// The same as a message: "file:line:column: 'program.moves[i]': what".
std::string at_move(const RunInputs& sc, const Program& program, std::size_t move, const std::string& what) {
  return move_error(sc, program, move, what).what();
}

[[noreturn]] void fail_at(const RunInputs& sc, const SourceRef& where, const std::string& field, const std::string& what) {
  throw InputError(where.file.empty() ? sc.file : where.file, where.line, where.column, field, what);
}

// The samples left to the plan of a variant (runner.hpp: the run's budget less the settle time's
// samples at `setpoint_rate`, Hz); InputError at settle_time_s when the settle time alone exceeds it.
double plan_budget(const RunInputs& sc, double setpoint_rate, double budget) {
  const double settle = std::ceil(sc.simulation.settle_time * setpoint_rate);
  if (settle < budget) return budget - settle;
  fail_at(sc, sc.simulation.settle_time_where, "simulation.settle_time_s",
          "the settle time alone would take " + format_value(settle, 3) + " samples at " +
              format_value(1e3 / setpoint_rate, 3) + " ms (" + format_value(settle * kRunBytesPerSample / 1e9, 2) +
              " GB); limit " + format_value(budget, 3) + " samples a run (--max-samples); shorten `settle_time_s`");
}

// Refuses (InputError at video.fps) a video of more than kMaxVideoFrames frames over `duration` (s).
void check_video_frames(const RunInputs& sc, double duration) {
  const double frames = std::ceil(duration * sc.video.fps);
  if (frames <= kMaxVideoFrames) return;
  fail_at(sc, sc.video.fps_where, "video.fps",
          "the video would have " + format_value(frames, 3) + " frames (" + format_value(duration, 3) + " s at " +
              format_value(sc.video.fps, 3) + " fps); limit " + format_value(kMaxVideoFrames, 3) +
              " frames; lower `fps` or run with --no-video");
}

// The share of each joint limit a run used and its closest approach to the position range.
JointUsage joint_usage(const Metrics& m, const Trace& trace, const JointLimits& limits, const KinematicChain& chain) {
  JointUsage u;
  const auto share = [](double peak, double limit) { return std::isfinite(limit) && limit > 0 ? peak / limit : 0.0; };
  for (int i = 0; i < 6; ++i) {
    u.velocity_share[i] = share(m.velocity_peak[i], limits.velocity[i]);
    u.acceleration_share[i] = share(m.acceleration_peak[i], limits.acceleration[i]);
    u.torque_share[i] = share(m.torque_peak[i], limits.torque[i]);
    const JointSpec& joint = chain.joints[static_cast<std::size_t>(i)];
    double margin = std::numeric_limits<double>::infinity();
    for (const TraceSample& s : trace.samples) margin = std::min({margin, s.q[i] - joint.lower, joint.upper - s.q[i]});
    u.position_margin[i] = margin;
  }
  return u;
}

// Everything shared by the variants of one scenario: robot models, solvers and the servo.
struct Robot {
  KinematicChain chain;
  std::unique_ptr<IkSolver> ik;
  std::unique_ptr<Simulator> sim;
  JointVector q0 = JointVector::Zero();  // link angles at the program's start
  ServoConfig servo;
  KeepOut keep_out;  // the floor and the base, which the model does not collide with
};

// The scenario's servo, tuned from the model at the start pose, with its switches.
ServoConfig servo_of(const RunInputs& sc, const Simulator& sim, const JointVector& q0) {
  ServoTuning tuning;
  tuning.rate_hz = sc.servo.rate_hz;
  tuning.setpoint_rate_hz = sc.servo.setpoint_rate_hz;
  tuning.measurement_delay_ticks = sc.servo.measurement_delay_ticks;
  tuning.encoder_counts_per_turn = sc.servo.encoder_counts_per_turn;
  ServoConfig servo = tune_servo(sim, q0, tuning);
  servo = with_controller(servo, sc.servo.controller == ServoController::kPd ? Controller::kPd : Controller::kCascade);
  if (sc.servo.velocity_feedforward) servo.velocity_feedforward = *sc.servo.velocity_feedforward;
  if (sc.servo.acceleration_feedforward) servo.acceleration_feedforward = *sc.servo.acceleration_feedforward;
  if (sc.servo.gravity_compensation) servo.gravity_compensation = *sc.servo.gravity_compensation;
  if (sc.servo.deflection_compensation) servo.deflection_compensation = *sc.servo.deflection_compensation;
  return servo;
}

// trace.csv: planned profile, commanded/actual TCP, errors and joints at every servo tick.
std::string trace_csv(const Trace& trace, const Timing& timing, const Metrics& m) {
  std::vector<std::string> columns = {"t",
                                      "s_mm",
                                      "v_mm_s",
                                      "a_mm_s2",
                                      "j_mm_s3",
                                      "cmd_x",
                                      "cmd_y",
                                      "cmd_z",
                                      "act_x",
                                      "act_y",
                                      "act_z",
                                      "cmd_qw",
                                      "cmd_qx",
                                      "cmd_qy",
                                      "cmd_qz",
                                      "act_qw",
                                      "act_qx",
                                      "act_qy",
                                      "act_qz",
                                      "tracking_error_mm",
                                      "orientation_error_deg",
                                      "contour_error_programmed_mm",
                                      "contour_error_planned_mm",
                                      "tcp_speed_mm_s",
                                      "jerk_actual_mm_s3",
                                      "vibration_x_mm",
                                      "vibration_y_mm",
                                      "vibration_z_mm"};
  const char* groups[] = {"q_cmd_", "q_", "qd_cmd_", "qd_", "q_motor_", "following_error_mrad_", "tau_"};
  for (const char* g : groups) {
    for (int i = 1; i <= 6; ++i) columns.push_back(g + std::to_string(i));
  }
  CsvWriter out(columns);
  out.reserve(trace.samples.size());
  std::vector<double> row(columns.size());
  const TimedSample rest_end = timing.samples.back();
  // quaternions on one hemisphere from row to row (q and -q are the same rotation), the actual
  // on the commanded one's, so the columns plot without sign flips
  Eigen::Quaterniond cmd_q = Eigen::Quaterniond::Identity();
  const auto same_side = [](Eigen::Quaterniond q, const Eigen::Quaterniond& ref) {
    if (q.dot(ref) < 0) q.coeffs() *= -1;
    return q;
  };
  for (std::size_t k = 0; k < trace.samples.size(); ++k) {
    const TraceSample& s = trace.samples[k];
    cmd_q = same_side(s.rotation_cmd, k == 0 ? s.rotation_cmd : cmd_q);
    const Eigen::Quaterniond act_q = same_side(s.rotation, cmd_q);
    // after the planned motion the reference holds the end point at rest
    const bool moving = k < timing.samples.size();
    const TimedSample& p = moving ? timing.samples[k] : rest_end;
    const double head[] = {s.t,
                           p.s / kMm,
                           (moving ? p.v : 0.0) / kMm,
                           (moving ? p.a : 0.0) / kMm,
                           (moving ? p.j : 0.0) / kMm,
                           s.tcp_cmd.x() / kMm,
                           s.tcp_cmd.y() / kMm,
                           s.tcp_cmd.z() / kMm,
                           s.tcp.x() / kMm,
                           s.tcp.y() / kMm,
                           s.tcp.z() / kMm,
                           cmd_q.w(),
                           cmd_q.x(),
                           cmd_q.y(),
                           cmd_q.z(),
                           act_q.w(),
                           act_q.x(),
                           act_q.y(),
                           act_q.z(),
                           m.tracking_error[k] / kMm,
                           m.orientation_error[k] / kDeg,
                           m.contour_error_programmed[k] / kMm,
                           m.contour_error_planned[k] / kMm,
                           m.tcp_speed[k] / kMm,
                           m.jerk_actual[k] / kMm,
                           m.vibration[k].x() / kMm,
                           m.vibration[k].y() / kMm,
                           m.vibration[k].z() / kMm};
    std::size_t c = 0;
    for (const double v : head) row[c++] = v;
    const JointVector following = s.following_error * 1e3;
    for (const JointVector* v : {&s.q_cmd, &s.q, &s.qd_cmd, &s.qd, &s.q_motor, &following, &s.tau}) {
      for (int i = 0; i < 6; ++i) row[c++] = (*v)[i];
    }
    out.row(row);
  }
  return out.text();
}

// The status of a run that did not diverge: saturation first, then limits, then settling.
VariantStatus status_of(const Metrics& m, const Health& h) {
  if (h.saturated) return VariantStatus::kSaturated;
  if (h.limits_exceeded()) return VariantStatus::kLimitExceeded;
  if (!m.cycle_time) return VariantStatus::kNotSettled;
  return VariantStatus::kOk;
}

std::string status_message(const Metrics& m, const Health& h) {
  const auto joint = [](int j) { return "joint " + std::to_string(j + 1); };
  if (h.saturated) {
    std::string out = "torque saturated:";
    for (std::size_t i = 0; i < 6; ++i) {
      if (h.saturated_ticks[i] > 0) {
        out += ' ';
        out += joint(static_cast<int>(i));
        out += ' ';
        out += std::to_string(h.saturated_ticks[i]);
        out += " ticks (";
        out += format_fixed(100 * h.saturated_share[static_cast<Eigen::Index>(i)], 1);
        out += " %)";
      }
    }
    return out + "; not clean tracking data";
  }
  for (const auto& [check, what] : {std::pair{&h.reference_velocity, "reference velocity"},
                                    std::pair{&h.reference_acceleration, "reference acceleration"},
                                    std::pair{&h.actual_velocity, "actual velocity"},
                                    std::pair{&h.actual_acceleration, "actual acceleration"}}) {
    if (check->exceeded) {
      return std::string(what) + " beyond the limit of " + joint(check->joint) + " at t = " + format_fixed(check->t, 3) +
             " s (" + format_value(check->value, 4) + " > " + format_value(check->limit, 4) + ")";
    }
  }
  if (!m.cycle_time) return "did not settle within the simulated time";
  return {};
}

#ifdef BLENDBENCH_HAS_RENDER
// What the variants' videos share and record: the settings, and one film per variant.
struct Videos {
  FilmSettings settings;
  std::vector<VariantFilm> films;
};
#else
struct Videos {};
#endif

// What identifies a variant in the summary: its name, method, parameter, tolerance and baseline.
VariantSummary identity(const VariantInputs& variant) {
  VariantSummary out;
  out.name = variant.name;
  out.method = variant.method;
  out.parameter = variant.parameter;
  out.tolerance = variant.tolerance;
  out.baseline = variant.timing.baseline;
  return out;
}

// What a sensitivity run re-runs of a variant (RunRequest::sensitivity): the plan and the joint
// reference of its nominal run, which do not depend on the arm's dynamics.
struct Replay {
  Program program;  // as run (the command line's smoothing applied)
  Path path;
  Timing timing;
  JointTrajectory joints;
};

// The execution options of every variant of the scenario on `robot` (its servo and start
// pose), without frames.
ExecutionOptions execution_options(const RunInputs& sc, const Robot& robot) {
  ExecutionOptions options;
  options.tool_rotation = sc.robot.tool_rotation;
  options.q0 = robot.q0;
  options.mapping.allow_branch_change = sc.robot.allow_branch_change;
  options.run.tool = sc.robot.tool;
  options.servo = robot.servo;
  options.run.settle_time = sc.simulation.settle_time;
  options.metrics.settle_tolerance = sc.simulation.settle_tolerance;
  options.metrics.settle_speed_tolerance = sc.simulation.settle_speed_tolerance;
  options.metrics.settle_window = sc.simulation.settle_window;
  options.metrics.vibration_window = sc.simulation.vibration_window;
  options.metrics.vibration_highpass = sc.simulation.vibration_highpass;
  options.metrics.jerk_lowpass = sc.simulation.jerk_lowpass;
  return options;
}

class VariantRun {
 public:
  // `videos` is null when no video is made; `replay`, when not null, receives the plan and the
  // joint reference of a variant that ran cleanly.
  VariantRun(const RunInputs& sc, const Robot& robot, const RunRequest& request, const VariantInputs& variant, Videos* videos,
             std::optional<Replay>* replay)
      : sc_(sc), robot_(robot), request_(request), variant_(variant), dir_(request.out_dir / variant.name), videos_(videos),
        replay_(replay) {}

  VariantSummary run() {
    Program program = variant_.program;
    if (request_.smoothing.given()) program.smoothing = apply_smoothing_flags_to_variant(request_.smoothing, program.smoothing);
    VariantSummary out = identity(variant_);

    // plan: blend and time
    auto start = Clock::now();
    const Path path = blend(program);
    // the variant's limits mode, axis limits and baseline (resolved: run_inputs.hpp) at the servo's setpoint period
    TimingOptions topt = variant_.timing;
    topt.dt = 1.0 / robot_.servo.setpoint_rate_hz;
    // the work is bounded before it is done (runner.hpp): the plan gets what the settle time leaves
    topt.max_samples = plan_budget(sc_, robot_.servo.setpoint_rate_hz, request_.max_samples.value_or(kMaxRunSamples));
    const Timing timing = plan_timing(path, topt);
    out.timings.planning = seconds_since(start);
    PlanFigures& plan = out.plan;
    plan.path_length = path.length();
    plan.planned_cycle_time = timing.cycle_time;
    plan.feed_share = timing.feed_share;
    plan.corners = path.corners;
    plan.oriented = path.oriented();
    // the planned path leaves the programmed one at the transitions and along smoothed streams
    plan.path_deviation_max = path.smoothing.max_distance;
    for (const CornerReport& c : path.corners) plan.path_deviation_max = std::max(plan.path_deviation_max, c.deviation);
    plan.placements = corner_placements(path, program);
    plan.pieces = pieces_json(path, timing);
    plan.limits = timing.limits;
    plan.bound_cycle_time = timing.bound_cycle_time;
    plan.moves_merged = path.moves_merged;
    plan.merge_tolerance = path.merge_tolerance;
    plan.corner_steps = timing.corner_steps;
    plan.smoothing = path.smoothing;
    plan.planner = planner_figures(timing);
    if (!timing.outcome.ok()) return failed(std::move(out), VariantStatus::kPlanningFailed, "planning failed: " + timing.outcome.message);
    if (request_.video || request_.compare) check_video_frames(sc_, timing.cycle_time + sc_.simulation.settle_time);
    say("planned " + format_fixed(path.length() / kMm, 1) + " mm in " + format_fixed(timing.cycle_time, 3) + " s (" +
        format_fixed(out.timings.planning * 1e3, 1) + " ms)");

    // execute: IK, the simulation (rendering frames on the way), metrics and health
    ExecutionOptions options = execution_options(sc_, robot_);
#ifdef BLENDBENCH_HAS_RENDER
    // the arm's pose at the video's rate, for rendering after the run
    if (videos_ != nullptr) {
      record_poses(film(), options.run, pose_rate(sc_, request_.compare), timing.cycle_time + options.run.settle_time,
                   robot_.sim->model().nq);
    }
#endif
    const Execution run = execute(*robot_.sim, *robot_.ik, program, path, timing, options);
    // a variant whose path leaves the reach fails alone (the start was checked for all)
    if (!run.joints.outcome.ok()) {
      const TimedSample& at = timing.samples[run.joints.failed_index];
      return failed(std::move(out), VariantStatus::kFailed,
                    at_move(sc_, program, move_at(path, at.s),
                            "the path leaves the robot's reach or limits at t = " + format_fixed(at.t, 3) +
                                " s: " + run.joints.outcome.message));
    }
    const Trace& trace = run.trace;
    plan.corner_times = run.corners;
    out.singularities = run.singularities;
    out.branch_changes = run.joints.branch_changes;
    for (const SingularityPassage& p : run.singularities) {
      say("near a " + std::string(to_string(p.kind)) + " singularity at t = " + format_fixed(p.t, 3) + " s, " +
          describe_pose(p.pose) + " (measure " + format_value(p.measure) + ", threshold " + format_value(p.threshold) + ")");
    }
    out.timings.inverse_kinematics = run.ik_seconds;
    out.timings.simulated = trace.samples.empty() ? 0.0 : trace.samples.back().t;
    out.timings.simulation = run.simulation_seconds;
    out.warning = trace.warning;
    say("inverse kinematics for " + std::to_string(timing.samples.size()) + " poses (" +
        format_fixed(out.timings.inverse_kinematics * 1e3, 1) + " ms)");
    if (trace.diverged) return failed(std::move(out), VariantStatus::kDiverged, "the simulation diverged: " + trace.warning);
    // the video, rendered from the recorded poses (the metrics give the overlay its numbers)
    const Metrics& m = run.metrics.value();
    const Health& health = run.health.value();
#ifdef BLENDBENCH_HAS_RENDER
    if (videos_ != nullptr) {
      record_run(film(), trace, m, run.corners);
      film().planned = film_polyline(path);
      if (request_.video) {
        std::filesystem::create_directories(dir_);
        out.timings.video = render_variant_video(robot_.sim->model(), film(), videos_->settings, dir_ / "video.mp4");
      }
    }
#endif
    say("simulated " + format_fixed(out.timings.simulated, 2) + " s in " + format_fixed(out.timings.simulation, 2) +
        " s wall (" + format_fixed(out.timings.real_time_factor(), 1) + "x real time)" +
        (request_.video ? "; video " + format_fixed(out.timings.video, 2) + " s (" +
                              format_fixed(out.timings.real_time_factor_with_video(), 1) + "x real time with it)"
                        : std::string()));

    // status and files (a sweep keeps only summary.json)
    out.status = status_of(m, health);
    out.message = status_message(m, health);
    out.metrics = m;
    out.health = health;
    // the model has no contacts: say where the TCP goes through the floor or into the base
    const WorkspaceReport& workspace = out.workspace.emplace(
        WorkspaceFigures{robot_.keep_out, check_workspace(trace, robot_.keep_out)}).report;
    if (workspace.below_floor) {
      say("warning: the TCP goes below the floor (z " + format_fixed(workspace.tcp_z_min / kMm, 1) + " mm, from t = " +
          format_fixed(workspace.below_floor_t, 3) + " s); the model has no contacts");
    }
    if (workspace.into_base) {
      say("warning: the TCP enters the robot's base (" + format_fixed(workspace.base_distance_min / kMm, 1) +
          " mm from its axis, from t = " + format_fixed(workspace.into_base_t, 3) + " s); the model has no contacts");
    }
    out.joint_usage = joint_usage(m, trace, robot_.sim->limits(), robot_.chain);
    if (request_.variant_files) {
      write_file_atomic(dir_ / "trace.csv", trace_csv(trace, timing, m));
      write_file_atomic(dir_ / "path.csv", path_csv(path, kCsvStep));
      write_file_atomic(dir_ / "program.csv", program_csv(program, kCsvStep));
      write_file_atomic(dir_ / "corners.json", corners_json(plan).dump(2) + "\n");
    }
    const std::string cycle = m.cycle_time ? format_fixed(*m.cycle_time, 3) + " s" : std::string("not settled");
    // the servo's errors in micrometres (docs/units.md)
    const std::string um = std::string(" ") + micrometre_text();
    say("cycle " + cycle + ", tracking error max " + format_fixed(m.tracking_error_max / kMm * 1e3, 1) + um +
        ", contour error (planned path) max " + format_fixed(m.contour_error_planned_max / kMm * 1e3, 1) + um +
        ", residual vibration " + format_fixed(m.vibration_final.peak_to_peak / kMm * 1e3, 1) + um);
    if (out.status != VariantStatus::kOk) say(std::string(to_string(out.status)) + ": " + out.message);
    if (replay_ != nullptr && out.status == VariantStatus::kOk) replay_->emplace(Replay{program, path, timing, run.joints.joints});
    return out;
  }

 private:
  void say(const std::string& line) const {
    if (request_.progress) request_.progress("  " + variant_.name + ": " + line);
  }

  VariantSummary failed(VariantSummary out, VariantStatus status, const std::string& message) {
    out.status = status;
    out.message = message;
    say(message);
#ifdef BLENDBENCH_HAS_RENDER
    // nothing to show but why
    if (videos_ != nullptr) {
      film().qpos.clear();
      film().failure = std::string(to_string(status)) + ": " + message;
    }
#endif
    return out;
  }

#ifdef BLENDBENCH_HAS_RENDER
  // This variant's film (the last one of the run's videos).
  VariantFilm& film() {
    if (videos_->films.empty() || videos_->films.back().name != variant_.name) {
      videos_->films.emplace_back();
      videos_->films.back().name = variant_.name;
      videos_->films.back().method = std::string(to_string(variant_.method));  // its colour in the videos
    }
    return videos_->films.back();
  }
#endif

  const RunInputs& sc_;
  const Robot& robot_;
  const RunRequest& request_;
  const VariantInputs& variant_;
  std::filesystem::path dir_;
  Videos* videos_;
  std::optional<Replay>* replay_;
};

// The summary entry of a variant that did not finish: what identifies it, and its status.
VariantSummary unfinished(const VariantInputs& variant, VariantStatus status, std::string message = {}) {
  VariantSummary out = identity(variant);
  out.status = status;
  out.message = std::move(message);
  return out;
}

// One variant, failing alone: an exception other than bad input (a file or video that cannot be
// written, an internal error) becomes its status; a stop request (Interrupted, or ffmpeg ended by
// the same Ctrl-C) marks it interrupted and removes its unfinished folder. InputError (a
// variant's bad parameter is bad input of the scenario) propagates.
VariantSummary run_variant(const RunInputs& sc, const Robot& robot, const RunRequest& request, const VariantInputs& variant,
                           Videos* videos, std::optional<Replay>* replay, int& interrupted_by) {
  const std::filesystem::path dir = request.out_dir / variant.name;
  const auto discard = [&] {
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  };
  try {
    return VariantRun(sc, robot, request, variant, videos, replay).run();
  } catch (const Interrupted& stop) {
    interrupted_by = stop.signal;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    if (stop_signal() == 0) {
      discard();
      if (request.progress) request.progress("  " + variant.name + ": failed: " + e.what());
      return unfinished(variant, VariantStatus::kFailed, e.what());
    }
    interrupted_by = stop_signal();
  }
  discard();
  return unfinished(variant, VariantStatus::kInterrupted);
}

// The robot of a run as run_pipeline runs it, checked as it checks it before the first
// variant: kinematics, dynamics (against robot.model), servo rate against the model's timestep,
// the start pose, the servo. A library's exception while the robot files are read is bad input
// of the scenario's robot (rethrow_as_input_error). `changes` perturb the dynamics model as it is
// loaded (sim/simulator.hpp ModelChanges: the perturbed models of a sensitivity study); none by
// default.
struct LoadedRobot {
  Robot robot;
  std::vector<std::string> notes;  // what was estimated or replaced (a URDF alone)
  std::string built_mjcf;          // the model built from a URDF alone; empty when the scenario names an MJCF
  ArmModel arm_model = ArmModel::kElastic;
};

LoadedRobot load_robot_files(const RunInputs& scenario, const ModelChanges& changes) {
  LoadedRobot loaded;
  Robot& robot = loaded.robot;
  loaded.arm_model = scenario.robot.model;
  if (scenario.robot.estimate_total_mass > 0 && !scenario.robot.mjcf_from_urdf) {
    fail_at(scenario, scenario.robot.estimate_where, "robot.estimate_inertia",
            "estimate_inertia applies only to a URDF run without an MJCF; " + scenario.robot.mjcf +
                " states the dynamics");
  }
  if (scenario.robot.urdf.empty()) {
    // an MJCF of the user's own: the chain from its bodies and joints to tip_site or tip_body,
    // its own actuators replaced by direct-torque motors (the servo drives the joints)
    ModelChanges own = changes;
    own.tcp_site = scenario.robot.tip_site;
    own.tcp_body = scenario.robot.tip_body;
    own.own_actuators_to_motors = true;
    robot.sim = std::make_unique<Simulator>(scenario.robot.mjcf, own);
    robot.chain = robot.sim->kinematic_chain();
    for (const JointSpec& j : robot.chain.joints) {
      if (!std::isfinite(j.velocity_limit)) {
        fail_at(scenario, scenario.robot.urdf_where, "robot.mjcf",
                scenario.robot.mjcf + " states no joint velocity limits (MJCF has none of its own): add <custom><numeric "
                                      "name=\"velocity_limits\" data=\"six values in rad/s\"/></custom>");
      }
    }
    const bool elastic = robot.sim->elastic();
    if (scenario.robot.model_where.line > 0 && elastic != (scenario.robot.model == ArmModel::kElastic)) {
      fail_at(scenario, scenario.robot.model_where, "robot.model",
              std::string("robot.model is ") + (elastic ? "rigid" : "elastic") + " but " + scenario.robot.mjcf + " has " +
                  (elastic ? "elastic" : "rigid") + " joints");
    }
    loaded.arm_model = elastic ? ArmModel::kElastic : ArmModel::kRigid;
    const std::string tip = scenario.robot.tip_site.empty() ? "body '" + scenario.robot.tip_body + "'"
                                                            : "site '" + scenario.robot.tip_site + "'";
    loaded.notes.push_back("the kinematic chain read from the MJCF: its bodies and joints from the world to " + tip);
    if (!robot.sim->replaced_actuators().empty()) {
      std::string names;
      for (const std::string& n : robot.sim->replaced_actuators()) names += (names.empty() ? "'" : ", '") + n + "'";
      loaded.notes.push_back("the MJCF's own actuators " + names +
                             " replaced by direct-torque motors at their force range (BlendBench's servo drives the joints)");
    }
  } else if (scenario.robot.mjcf_from_urdf) {
    // a URDF alone: its dynamics built from it (rigid joints: a URDF states no gear stiffness)
    if (scenario.robot.model == ArmModel::kElastic && scenario.robot.model_where.line > 0) {
      fail_at(scenario, scenario.robot.model_where, "robot.model",
              "elastic joints need gear stiffnesses a URDF does not state: give robot.mjcf, or robot.model: rigid");
    }
    UrdfModel built = model_from_urdf(scenario.robot.urdf, scenario.robot.base_link, scenario.robot.tip_link,
                                      scenario.robot.estimate_total_mass);
    robot.chain = std::move(built.chain);
    loaded.notes = std::move(built.notes);
    robot.sim = std::make_unique<Simulator>(
        Simulator::from_xml_string(built.mjcf, changes, scenario.robot.urdf + " (the MuJoCo model built from it)"));
    loaded.built_mjcf = std::move(built.mjcf);
    loaded.arm_model = ArmModel::kRigid;
  } else {
    robot.chain = load_urdf_chain(scenario.robot.urdf, scenario.robot.base_link, scenario.robot.tip_link);
    robot.sim = std::make_unique<Simulator>(scenario.robot.mjcf, changes);
    const bool want_elastic = scenario.robot.model == ArmModel::kElastic;
    if (robot.sim->elastic() != want_elastic) {
      fail_at(scenario, scenario.robot.model_where, "robot.model",
              std::string("robot.model is ") + (want_elastic ? "elastic" : "rigid") + " but " + scenario.robot.mjcf +
                  " has " + (robot.sim->elastic() ? "elastic" : "rigid") + " joints");
    }
  }
  // the tool on the flange: the chain, the solver and the trace all follow its centre point
  robot.chain.tcp = robot.chain.tcp * scenario.robot.tool;
  robot.ik = std::make_unique<IkSolver>(robot.chain);
  const double steps = 1 / (scenario.servo.rate_hz * robot.sim->timestep());
  if (std::abs(steps - std::round(steps)) > 1e-9 * steps || std::round(steps) < 1) {
    fail_at(scenario, scenario.servo.rate_where, "servo.rate_hz",
            "the servo period 1/" + format_value(scenario.servo.rate_hz, 6) + " s is not a multiple of the model's timestep " +
                format_value(robot.sim->timestep(), 6) + " s (" + format_value(1 / robot.sim->timestep(), 6) +
                " Hz physics: use a rate that divides it)");
  }
  // the program's start point is every variant's first pose: out of reach, the scenario itself
  // is bad input (at the first move), found before any variant runs
  const Program& first = scenario.variants.front().program;
  const IkSolver::Result start = robot.ik->solve(tool_pose(scenario.start, scenario.robot.tool_rotation), scenario.robot.q_seed);
  if (!start.outcome.ok()) {
    throw move_error(scenario, first, 0,
                     "the start point " + pose_text(scenario.start) + " cannot be reached: " + start.outcome.message);
  }
  robot.q0 = start.q;
  robot.servo = servo_of(scenario, *robot.sim, robot.q0);
  robot.keep_out = keep_out_of(robot.sim->model());
  return loaded;
}

LoadedRobot load_robot(const RunInputs& scenario, const ModelChanges& changes = {}) {
  try {
    return load_robot_files(scenario, changes);
  } catch (...) {
    rethrow_as_input_error(scenario.robot.urdf_where.line > 0 ? scenario.robot.urdf_where : SourceRef{scenario.file, 0, 0},
                           "robot", "cannot load the robot: ");
  }
}

// One variant's run on one perturbed model: its nominal plan and joint reference on `robot`
// (servo re-tuned on that arm by load_robot), with its status and, when clean, its figures.
SensitivityRun rerun(const RunInputs& sc, const Robot& robot, const Replay& replay) {
  SensitivityRun out;
  const Execution run = execute_mapped(*robot.sim, replay.program, replay.path, replay.timing, replay.joints,
                                       execution_options(sc, robot));
  if (run.trace.diverged) {
    out.status = std::string(to_string(VariantStatus::kDiverged));
    out.message = "the simulation diverged: " + run.trace.warning;
    return out;
  }
  const Metrics& m = run.metrics.value();
  const Health& h = run.health.value();
  const VariantStatus status = status_of(m, h);
  out.status = std::string(to_string(status));
  out.message = status_message(m, h);
  if (status == VariantStatus::kOk) out.figures = headline_figures(m);
  return out;
}

// The sensitivity study (RunRequest::sensitivity, docs/sensitivity.md): every variant of
// `summary` that ran cleanly (its `replays` entry set) re-run on each of the scenario's perturbed
// models, request.jobs simulations at a time on threads (a Simulator runs each reference on data
// of its own, so one model may run several at once; the sweep's pool runs child processes, each
// loading its own scenario, where these share the plans and models loaded once; a few lines of
// std::thread over an atomic counter need no pool library), progress on stderr; then the
// conclusions.
// A stop request ends it with interrupted_by set.
Sensitivity run_sensitivity(const RunInputs& sc, const RunRequest& request, const RunSummary& summary, ArmModel arm_model,
                            const std::vector<std::optional<Replay>>& replays, int& interrupted_by) {
  const auto start = Clock::now();
  Sensitivity study;
  // a rigid arm has no gear stiffness: those models would be the nominal one
  for (const Perturbation& p : sc.sensitivity.perturbations) {
    if (arm_model == ArmModel::kRigid && p.stiffness_scale != 1) {
      study.notes.push_back("'" + p.name + "' left out: the arm is rigid (no gear stiffness to change)");
      continue;
    }
    study.perturbations.push_back(p);
  }
  std::vector<const Replay*> replay_of;
  for (std::size_t i = 0; i < summary.variants.size(); ++i) {
    const VariantSummary& v = summary.variants[i];
    if (v.status != VariantStatus::kOk || !v.metrics || !replays[i]) {
      study.skipped.push_back(v.name + ": " + std::string(to_string(v.status)) + " on the nominal model");
      continue;
    }
    SensitivityVariant sv;
    sv.name = v.name;
    sv.nominal.figures = headline_figures(*v.metrics);
    sv.perturbed.resize(study.perturbations.size());
    study.variants.push_back(std::move(sv));
    replay_of.push_back(&*replays[i]);
  }
  // the perturbed models, loaded and checked as the nominal one
  std::vector<LoadedRobot> models;
  for (const Perturbation& p : study.perturbations) {
    ModelChanges changes;
    changes.stiffness_scale = p.stiffness_scale;
    changes.inertia_scale = p.inertia_scale;
    changes.friction_scale = p.friction_scale;
    changes.extra_delay_ticks = p.extra_delay_ticks;
    // a stiffer or lighter arm may need a shorter physics step than the nominal one
    changes.fit_timestep = true;
    models.push_back(load_robot(sc, changes));
    const double dt = models.back().robot.sim->timestep();
    if (dt != summary.robot.timestep) {
      study.notes.push_back("'" + p.name + "' ran at a physics timestep of " + format_value(dt * 1e6, 4) + " us (the nominal " +
                            format_value(summary.robot.timestep * 1e6, 4) + " us divided by " +
                            format_value(std::round(summary.robot.timestep / dt)) +
                            ": its highest mode is faster than the nominal step resolves)");
    }
  }
  const std::size_t total = models.size() * study.variants.size();
  const int cores = request.jobs > 0 ? request.jobs : sweep_detail::available_cores();
  study.jobs = static_cast<int>(std::clamp<std::size_t>(static_cast<std::size_t>(cores), 1, std::max<std::size_t>(total, 1)));
  if (request.progress) {
    request.progress("sensitivity: " + std::to_string(study.variants.size()) + " variants on " + std::to_string(models.size()) +
                     " perturbed models, " + std::to_string(total) + " simulations, " + std::to_string(study.jobs) +
                     " at a time");
  }
  // the runs: task t is variant t % variants on model t / variants
  std::atomic<std::size_t> next{0};
  std::atomic<int> stopped{0};
  std::mutex lock;  // guards `done` and the bar
  std::size_t done = 0;
  const ProgressBar bar;
  const auto work = [&] {
    for (std::size_t t = next++; t < total && stopped == 0; t = next++) {
      const std::size_t model = t / study.variants.size(), variant = t % study.variants.size();
      SensitivityRun& out = study.variants[variant].perturbed[model];
      try {
        out = rerun(sc, models[model].robot, *replay_of[variant]);
      } catch (const Interrupted& stop) {
        stopped = stop.signal;
        return;
      } catch (const std::exception& e) {
        out.status = std::string(to_string(VariantStatus::kFailed));
        out.message = e.what();
      }
      const std::lock_guard<std::mutex> guard(lock);
      ++done;
      if (out.status != "ok") {
        bar.say("sensitivity: " + study.variants[variant].name + " on '" + study.perturbations[model].name + "': " + out.status +
                (out.message.empty() ? std::string() : ": " + out.message));
      }
      bar.draw(done, total, "sensitivity");
    }
  };
  std::vector<std::thread> threads;
  for (int k = 1; k < study.jobs; ++k) threads.emplace_back(work);
  work();
  for (std::thread& th : threads) th.join();
  if (stopped != 0 || stop_signal() != 0) {
    interrupted_by = stopped != 0 ? stopped.load() : stop_signal();
    bar.finish();
    return study;
  }
  study.conclusions = conclude(study.perturbations, study.variants);
  study.wall_time = seconds_since(start);
  std::size_t all = 0;
  for (const Conclusion& c : study.conclusions) all += c.holds_in == OrderHolds::kAll ? 1 : 0;
  bar.finish("sensitivity: " + std::to_string(total) + " simulations in " + format_fixed(study.wall_time, 1) + " s; " +
             std::to_string(all) + " of " + std::to_string(study.conclusions.size()) +
             " conclusions hold in every perturbed model");
  return study;
}

}  // namespace

bool video_supported() {
#ifdef BLENDBENCH_HAS_RENDER
  return true;
#else
  return false;
#endif
}

void check_robot(const Scenario& scenario) {
  if (scenario.variants.empty()) return;
  (void)load_robot(resolve_run(scenario));
}

RunResult run_scenario(const Scenario& scenario, const RunRequest& request) { return run_pipeline(resolve_run(scenario), request); }

RunResult run_pipeline(const RunInputs& scenario, const RunRequest& request) {
  if (request.video && !video_supported()) {
    throw InputError("", 0, 0, "--no-video", "this build has no rendering (BLENDBENCH_RENDER=OFF): pass --no-video");
  }
  if (request.compare && !video_supported()) {
    throw InputError("", 0, 0, "--compare", "this build has no rendering (BLENDBENCH_RENDER=OFF)");
  }
  // variant names become folders under out_dir: resolve_run refused any that would leave it
  assert(!scenario.variants.empty());
  // the command line's smoothing: a tolerance must reach a variant that fits g2_fit
  check_smoothing_flags(request.smoothing);
  if (request.smoothing.tolerance_mm &&
      std::none_of(scenario.variants.begin(), scenario.variants.end(), [&](const VariantInputs& v) {
        return apply_smoothing_flags_to_variant(request.smoothing, v.program.smoothing).method == SmoothingMethod::kG2Fit;
      })) {
    throw InputError("", 0, 0, "--smoothing-tolerance", "no variant run smooths with g2_fit (add --smoothing g2_fit)");
  }

  // the robot: kinematics, dynamics (checked against robot.model), the start pose, the servo
  LoadedRobot loaded = load_robot(scenario);
  Robot& robot = loaded.robot;
  const std::vector<std::string>& robot_notes = loaded.notes;
  std::string mjcf = scenario.robot.mjcf;
  if (!loaded.built_mjcf.empty()) {
    // the model built from the URDF, written into the run folder for the reader (the run itself
    // compiled it from memory: a message names the URDF, never a staging folder)
    write_file_atomic(request.out_dir / "robot_from_urdf.xml", loaded.built_mjcf);
    mjcf = ((request.published_dir.empty() ? request.out_dir : request.published_dir) / "robot_from_urdf.xml").string();
  }
  if (request.progress) {
    for (const std::string& note : robot_notes) request.progress("robot: " + note);
  }
  const ArmModel arm_model = loaded.arm_model;
  const Program& first = scenario.variants.front().program;

  RunResult result;
  RunSummary& summary = result.summary;
  summary.version = version_string();
  summary.scenario = scenario.name;
  summary.file = scenario.file;
  summary.warnings = scenario.warnings;
  summary.description = scenario.description;
  summary.frame = scenario.frame;
  summary.notes = scenario.notes;
  summary.robot.model = arm_model;
  summary.robot.mjcf = mjcf;
  summary.robot.notes = robot_notes;
  summary.robot.urdf = scenario.robot.urdf;
  summary.robot.ik_method = robot.ik->method();
  summary.robot.tool = scenario.robot.tool;
  summary.robot.joints = robot.chain.joints;
  summary.robot.timestep = robot.sim->timestep();
  summary.robot.start_q = robot.q0;
  summary.robot.limits = robot.sim->limits();
  const NaturalFrequencies frequencies = robot.sim->natural_frequencies(robot.q0);
  summary.robot.natural_frequency_per_joint = frequencies.per_joint;
  summary.robot.natural_frequency_arm = frequencies.arm;
  summary.controller = scenario.servo.controller;
  summary.servo = robot.servo;
  summary.simulation = scenario.simulation;
  Videos videos;
  Videos* with_videos = request.video || request.compare ? &videos : nullptr;
#ifdef BLENDBENCH_HAS_RENDER
  if (with_videos != nullptr) videos.settings = film_settings(scenario, first);
#endif
  // the plans and joint references a sensitivity study re-runs, one per variant
  std::vector<std::optional<Replay>> replays(scenario.variants.size());
  std::size_t index = 0;
  for (const VariantInputs& variant : scenario.variants) {
    ++index;
    // after a stop request the rest are not started
    if (result.interrupted_by == 0) result.interrupted_by = stop_signal();
    if (result.interrupted_by != 0) {
      summary.variants.push_back(unfinished(variant, VariantStatus::kInterrupted));
      continue;
    }
    if (request.progress) {
      request.progress(std::string("[") + std::to_string(index) + "/" + std::to_string(scenario.variants.size()) + "] " +
                       variant.name);
    }
    summary.variants.push_back(run_variant(scenario, robot, request, variant, with_videos,
                                           request.sensitivity ? &replays[index - 1] : nullptr, result.interrupted_by));
    result.all_ok = result.all_ok && summary.variants.back().status == VariantStatus::kOk;
  }
  if (result.interrupted_by == 0 && request.sensitivity) {
    summary.sensitivity = run_sensitivity(scenario, request, summary, arm_model, replays, result.interrupted_by);
    if (result.interrupted_by != 0) summary.sensitivity.reset();
  }
  replays.clear();
  if (result.interrupted_by != 0) result.all_ok = false;
  compare_with_exact_stop(summary);
  // the answer: the variants by cycle time per tolerance, and the recommendation; the ties
  // decided by the sensitivity study's cycle-time conclusions when it ran
  if (result.interrupted_by == 0) {
    const OrderSpread spread = request.spread ? request.spread
                               : summary.sensitivity ? order_spread(*summary.sensitivity)
                                                     : OrderSpread{};
    summary.ranking = rank_run(summary, request.constraints, spread);
  }
#ifdef BLENDBENCH_HAS_RENDER
  // every variant side by side (the corners are the programmed ones: the same in every variant)
  if (request.compare && result.interrupted_by == 0) {
    for (const VariantSummary& v : summary.variants) {
      for (std::size_t k = 0; k < v.plan.placements.size(); ++k) {
        const CornerPlacement& p = v.plan.placements[k];
        const auto same = [&](const CornerPlacement& q) { return q.index == p.index; };
        if (std::none_of(videos.settings.corners.begin(), videos.settings.corners.end(), same)) videos.settings.corners.push_back(p);
        // named as corners.json, the report and the plots name it
        if (k < v.plan.corners.size()) videos.settings.corner_names.emplace(p.index, corner_name(p.index, v.plan.corners[k].source));
      }
    }
    std::filesystem::create_directories(request.out_dir);
    const double seconds = render_compare_video(robot.sim->model(), videos.films, videos.settings, request.out_dir / "compare.mp4");
    if (request.progress) {
      request.progress("comparison of " + std::to_string(videos.films.size()) + " variants written (" + format_fixed(seconds, 1) +
                       " s): " + (request.out_dir / "compare.mp4").string());
    }
  }
#endif
  write_file_atomic(request.out_dir / "summary.json", nlohmann::json(summary).dump(2) + "\n");

  if (request.plots && result.interrupted_by == 0) {
    const auto plot_start = Clock::now();
    // an argument vector, no shell: the output folder is data, whatever characters it holds
    const ProcessResult plotted =
        run_process({"/usr/bin/python3", data_file("report/scripts/plot_run.py"), request.out_dir.string()});
    if (plotted.ok) result.report = request.out_dir / "report.html";
    if (request.progress && stop_signal() == 0) {
      request.progress(plotted.ok ? "plots and report written (" + format_fixed(seconds_since(plot_start), 1) + " s)"
                                  : "warning: the plot script failed (" + plotted.message + ")");
    }
  }
  // a stop request while the plots were drawn (the script was stopped with it): the variants
  // are finished, the run was not
  if (result.interrupted_by == 0 && stop_signal() != 0) {
    result.interrupted_by = stop_signal();
    result.all_ok = false;
  }
  return result;
}

}  // namespace blendbench
