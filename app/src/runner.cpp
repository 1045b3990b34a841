#include "blendbench/app/runner.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <numbers>
#include <optional>
#include <sstream>

#include "blendbench/core/interrupt.hpp"
#include "blendbench/corner/blend.hpp"
#include "blendbench/robot/ik.hpp"
#include "blendbench/robot/joint_mapping.hpp"
#include "blendbench/timing/timing.hpp"
#include "blendbench/sim/metrics.hpp"
#include "blendbench/report/output.hpp"
#include "blendbench/report/process.hpp"
#include "blendbench/report/report.hpp"
#include "blendbench/sim/simulator.hpp"
#include "blendbench/sim/workspace.hpp"
#include "blendbench/io/data_root.hpp"
#include "blendbench/io/urdf_chain.hpp"
#ifdef BLENDBENCH_HAS_RENDER
#include "blendbench/render/render.hpp"
#include "blendbench/render/video.hpp"
#endif

namespace blendbench {
namespace {

using Clock = std::chrono::steady_clock;
constexpr double kMm = 1e3;
// Path sampling for path.csv / program.csv (m): fine enough for plots, small enough for files.
constexpr double kCsvStep = 0.5e-3;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

nlohmann::json finite_or_null(double value) { return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(); }

nlohmann::json to_json(const JointVector& v) {
  nlohmann::json out = nlohmann::json::array();
  for (int i = 0; i < 6; ++i) out.push_back(v[i]);
  return out;
}

TimingOptions::Baseline baseline_of(const Variant& variant) {
  if (variant.baseline == "exact_stop") return TimingOptions::Baseline::kExactStop;
  if (variant.baseline == "junction_slowdown") return TimingOptions::Baseline::kJunctionSlowdown;
  return TimingOptions::Baseline::kNone;
}

// The method a variant mostly uses: its own transition, else the first move's.
Method variant_method(const Program& program, const Variant& variant) {
  if (variant.transition) return variant.transition->method;
  return program.moves.front().transition.method;
}

Eigen::Isometry3d tool_pose(const Vec3& position, const Eigen::Matrix3d& rotation) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = rotation;
  pose.translation() = position;
  return pose;
}

std::string pose_text(const Vec3& p) {
  char buffer[96];
  std::snprintf(buffer, sizeof buffer, "(%.1f, %.1f, %.1f) mm", p.x() * kMm, p.y() * kMm, p.z() * kMm);
  return buffer;
}

// The programmed move a path arc length belongs to (a transition counts as its incoming move).
std::size_t move_at(const Path& path, double s) {
  const PathPiece& piece = path.pieces()[path.locate(s).piece];
  if (piece.move >= 0) return static_cast<std::size_t>(piece.move);
  return static_cast<std::size_t>(std::max(piece.corner, 0));
}

// The error of move `move` of the program, positioned where it was written.
InputError move_error(const Scenario& sc, const Program& program, std::size_t move, const std::string& what) {
  const SourceRef& where = program.moves[move].where;
  return {where.file.empty() ? sc.file : where.file, where.line, where.column,
          "program.moves[" + std::to_string(move) + "]", what};
}

// The same as a message: "file:line:column: 'program.moves[i]': what".
std::string at_move(const Scenario& sc, const Program& program, std::size_t move, const std::string& what) {
  return move_error(sc, program, move, what).what();
}

// The scenario's servo: gains it gives, else the simulator's defaults for the start pose
// (stable at the servo rate, critically damped).
ServoConfig servo_config(const Scenario& sc, const Simulator& sim, const JointVector& q0) {
  const JointVector kp = sc.servo.kp ? JointVector(Eigen::Map<const JointVector>(sc.servo.kp->data())) : default_kp();
  ServoConfig servo = default_servo(sim, q0, sc.servo.rate_hz, kp);
  if (sc.servo.kp) servo.kp = kp;
  if (sc.servo.kd) servo.kd = Eigen::Map<const JointVector>(sc.servo.kd->data());
  servo.gravity_compensation = sc.servo.gravity_compensation;
  servo.feedforward = sc.servo.feedforward;
  return servo;
}

// Everything shared by the variants of one scenario: robot models and solvers.
struct Robot {
  KinematicChain chain;
  std::unique_ptr<IkSolver> ik;
  std::unique_ptr<Simulator> sim;
  KeepOut keep_out;  // the floor and the base, which the model does not collide with
};

// The keep-out report of a variant (sim/workspace.hpp), mm and s; null where none applies.
nlohmann::json workspace_json(const WorkspaceReport& w, const KeepOut& zones) {
  return {{"floor_z_mm", finite_or_null(zones.floor_z * kMm)},
          {"floor_clearance_mm", zones.floor_clearance * kMm},
          {"tcp_z_min_mm", finite_or_null(w.tcp_z_min * kMm)},
          {"below_floor", w.below_floor},
          {"below_floor_t_s", finite_or_null(w.below_floor_t)},
          {"base_radius_mm", zones.base_radius * kMm},
          {"base_top_mm", zones.base_top * kMm},
          {"base_distance_min_mm", finite_or_null(w.base_distance_min * kMm)},
          {"into_base", w.into_base},
          {"into_base_t_s", finite_or_null(w.into_base_t)}};
}

// trace.csv: planned profile, commanded/actual TCP, errors and joints at every servo tick.
std::string trace_csv(const Trace& trace, const Timing& timing, const Metrics& m) {
  std::string out = "t,s_mm,v_mm_s,a_mm_s2,j_mm_s3,cmd_x,cmd_y,cmd_z,act_x,act_y,act_z,tracking_error_mm,contour_error_mm";
  const char* groups[] = {"q_cmd_", "q_", "qd_cmd_", "qd_", "tau_"};
  for (const char* g : groups) {
    for (int i = 1; i <= 6; ++i) {
      out += ',';
      out += g;
      out += std::to_string(i);
    }
  }
  out += '\n';
  const TimedSample rest_end = timing.samples.back();
  for (std::size_t k = 0; k < trace.samples.size(); ++k) {
    const TraceSample& s = trace.samples[k];
    // after the planned motion the reference holds the end point at rest
    const TimedSample& p = k < timing.samples.size() ? timing.samples[k] : rest_end;
    const double row[] = {s.t, p.s * kMm, (k < timing.samples.size() ? p.v : 0.0) * kMm,
                          (k < timing.samples.size() ? p.a : 0.0) * kMm, (k < timing.samples.size() ? p.j : 0.0) * kMm,
                          s.tcp_cmd.x() * kMm, s.tcp_cmd.y() * kMm, s.tcp_cmd.z() * kMm, s.tcp.x() * kMm,
                          s.tcp.y() * kMm, s.tcp.z() * kMm, m.tracking_error[k] * kMm, m.contour_error[k] * kMm};
    bool first = true;
    for (const double v : row) {
      if (!first) out += ',';
      out += format_number(v, 10);
      first = false;
    }
    for (const JointVector* v : {&s.q_cmd, &s.q, &s.qd_cmd, &s.qd, &s.tau}) {
      for (int i = 0; i < 6; ++i) {
        out += ',';
        out += format_number((*v)[i], 10);
      }
    }
    out += '\n';
  }
  return out;
}

nlohmann::json metrics_json(const Metrics& m, const Timing& timing) {
  return {
      {"cycle_time_s", m.cycle_time ? nlohmann::json(*m.cycle_time) : nlohmann::json()},
      {"planned_cycle_time_s", timing.cycle_time},
      {"feed_share", timing.feed_share},
      {"tracking_error_max_mm", m.tracking_error_max * kMm},
      {"tracking_error_rms_mm", m.tracking_error_rms * kMm},
      {"contour_error_max_mm", m.contour_error_max * kMm},
      {"path_deviation_max_mm", m.path_deviation_max * kMm},
      {"cartesian_jerk_peak_mm_s3", m.cartesian_jerk_peak * kMm},
      {"joint_jerk_peak_rad_s3", m.joint_jerk_peak},
      {"joint_velocity_peak_rad_s", to_json(m.joint_velocity_peak)},
      {"joint_acceleration_peak_rad_s2", to_json(m.joint_acceleration_peak)},
      {"torque_peak_nm", to_json(m.torque_peak)},
      {"joint_velocity_limit_exceeded", m.joint_velocity_limit_exceeded},
      {"torque_limit_reached", m.torque_limit_reached},
      {"settled", m.cycle_time.has_value()},
  };
}

class VariantRun {
 public:
  VariantRun(const Scenario& sc, const Robot& robot, const RunRequest& request, const Variant& variant)
      : sc_(sc), robot_(robot), request_(request), variant_(variant), dir_(request.out_dir / variant.name) {}

  nlohmann::json run() {
    const Program program = program_for(sc_, variant_);
    nlohmann::json out = {{"name", variant_.name},
                          {"method", std::string(to_string(variant_method(program, variant_)))},
                          {"parameter_mm", variant_.transition ? variant_.transition->parameter * kMm : 0.0},
                          {"baseline", variant_.baseline}};

    // plan: blend and time
    auto start = Clock::now();
    const Path path = blend(program);
    TimingOptions topt;
    topt.dt = 1.0 / sc_.servo.rate_hz;
    topt.baseline = baseline_of(variant_);
    const Timing timing = plan_timing(path, topt);
    {
      // the plan's own figures: length, corners, binding constraint per piece (issue 4)
      nlohmann::json plan = plan_summary_json(path, timing);
      out["path_length_mm"] = plan["path_length_mm"];
      out["corners"] = std::move(plan["corners"]);
      out["pieces"] = std::move(plan["pieces"]);
    }
    if (!timing.outcome.ok()) return failed(out, "planning failed: " + timing.outcome.message);
    say("planned " + format_fixed(path.length() * kMm, 1) + " mm in " + format_fixed(timing.cycle_time, 3) + " s (" +
        format_fixed(seconds_since(start) * 1e3, 1) + " ms)");

    // IK along the timed path
    start = Clock::now();
    std::vector<Eigen::Isometry3d> poses;
    poses.reserve(timing.samples.size());
    for (const TimedSample& s : timing.samples) poses.push_back(tool_pose(path.point(s.s), sc_.robot.tool_rotation));
    // a variant whose path leaves the reach fails alone (the start was checked for all)
    const IkSolver::Result q0 = robot_.ik->solve(poses.front(), sc_.robot.q_seed);
    if (!q0.outcome.ok()) {
      return failed(out, at_move(sc_, program, 0, "the start point " + pose_text(poses.front().translation()) +
                                                      " cannot be reached: " + q0.outcome.message));
    }
    const JointTrajectory joints = map_to_joints(*robot_.ik, poses, topt.dt, q0.q);
    if (!joints.outcome.ok()) {
      const double s = timing.samples[joints.failed_index].s;
      return failed(out, at_move(sc_, program, move_at(path, s),
                                 "the path leaves the robot's reach or limits at " + joints.outcome.message));
    }
    say("inverse kinematics for " + std::to_string(poses.size()) + " poses (" + format_fixed(seconds_since(start) * 1e3, 1) +
        " ms)");

    // simulate, rendering frames on the way
    JointReference reference;
    reference.dt = joints.dt;
    reference.q = joints.q;
    reference.qd = joints.qd;
    reference.qdd = joints.qdd;
    RunOptions options;
    options.settle_time = sc_.simulation.settle_time;
    double video_seconds = 0;
#ifdef BLENDBENCH_HAS_RENDER
    std::unique_ptr<OffscreenRenderer> renderer;
    std::unique_ptr<VideoWriter> video;
    if (request_.video) {
      RenderOptions ropt;
      ropt.width = sc_.video.width;
      ropt.height = sc_.video.height;
      for (const Move& m : program.moves) {
        const int n = std::max(2, static_cast<int>(std::ceil(length(m.geometry) / 2e-3)));
        for (int i = 0; i <= n; ++i) ropt.path_polyline.push_back(point(m.geometry, length(m.geometry) * i / n));
      }
      const int n = std::max(2, static_cast<int>(std::ceil(path.length() / 2e-3)));
      for (int i = 0; i <= n; ++i) ropt.planned_polyline.push_back(path.point(path.length() * i / n));
      renderer = std::make_unique<OffscreenRenderer>(robot_.sim->model(), ropt);
      std::filesystem::create_directories(dir_);
      video = std::make_unique<VideoWriter>((dir_ / "video.mp4").string(), ropt.width, ropt.height, sc_.video.fps);
      options.frame_rate = sc_.video.fps;
      options.on_frame = [&](const mjModel&, const mjData& d, double) {
        const auto frame_start = Clock::now();
        video->write(renderer->render(d));
        video_seconds += seconds_since(frame_start);
      };
    }
#endif
    start = Clock::now();
    const Trace trace = robot_.sim->run(reference, servo_config(sc_, *robot_.sim, q0.q), options);
    const double wall = seconds_since(start);
    const double simulated = trace.samples.empty() ? 0.0 : trace.samples.back().t;
    out["simulated_time_s"] = simulated;
    out["sim_wall_time_s"] = wall - video_seconds;
    out["video_wall_time_s"] = video_seconds;
    out["real_time_factor"] = wall - video_seconds > 0 ? simulated / (wall - video_seconds) : 0.0;
    out["real_time_factor_with_video"] = wall > 0 ? simulated / wall : 0.0;
    if (trace.diverged) {
      out["diverged"] = true;
      return failed(out, "the simulation diverged: " + trace.warning);
    }
#ifdef BLENDBENCH_HAS_RENDER
    if (video) video->finish();
#endif
    const double sim_wall = wall - video_seconds;
    say("simulated " + format_fixed(simulated, 2) + " s in " + format_fixed(sim_wall, 2) + " s wall (" +
        format_fixed(simulated / std::max(sim_wall, 1e-9), 0) + "x real time)" +
        (request_.video ? "; video " + format_fixed(video_seconds, 2) + " s (" +
                              format_fixed(simulated * sc_.video.fps / std::max(video_seconds, 1e-9), 0) + " frames/s)"
                        : std::string()));

    // metrics and files
    MetricsOptions mopt;
    mopt.end_point = point(program.moves.back().geometry, length(program.moves.back().geometry));
    mopt.settle_tolerance = sc_.simulation.settle_tolerance;
    for (int i = 0; i < 6; ++i) mopt.velocity_limits[i] = robot_.chain.joints[static_cast<std::size_t>(i)].velocity_limit;
    mopt.torque_limits = robot_.sim->torque_limits();
    const Metrics m = compute_metrics(trace, program, path, mopt);
    out.update(metrics_json(m, timing));
    // the model has no contacts: say where the TCP goes through the floor or into the base
    const WorkspaceReport workspace = check_workspace(trace, robot_.keep_out);
    out["workspace"] = workspace_json(workspace, robot_.keep_out);
    if (workspace.below_floor) {
      say("warning: the TCP goes below the floor (z " + format_fixed(workspace.tcp_z_min * kMm, 1) + " mm, from t = " +
          format_fixed(workspace.below_floor_t, 3) + " s); the model has no contacts");
    }
    if (workspace.into_base) {
      say("warning: the TCP enters the robot's base (" + format_fixed(workspace.base_distance_min * kMm, 1) +
          " mm from its axis, from t = " + format_fixed(workspace.into_base_t, 3) + " s); the model has no contacts");
    }
    out["diverged"] = false;
    out["status"] = "ok";
    if (!trace.warning.empty()) out["warning"] = trace.warning;
    if (request_.variant_files) {
      write_file_atomic(dir_ / "trace.csv", trace_csv(trace, timing, m));
      write_file_atomic(dir_ / "path.csv", path_csv(path, kCsvStep));
      write_file_atomic(dir_ / "program.csv", program_csv(program, kCsvStep));
      write_file_atomic(dir_ / "corners.json", out["corners"].dump(2) + "\n");
    }
    std::string cycle = m.cycle_time ? format_fixed(*m.cycle_time, 3) + " s" : std::string("not settled");
    say("cycle " + cycle + ", tracking error max " + format_fixed(m.tracking_error_max * kMm, 3) + " mm, contour error max " +
        format_fixed(m.contour_error_max * kMm, 3) + " mm");
    return out;
  }

 private:
  void say(const std::string& line) const {
    if (request_.progress) request_.progress("  " + variant_.name + ": " + line);
  }

  nlohmann::json failed(nlohmann::json out, const std::string& message) const {
    out["status"] = "failed";
    out["message"] = message;
    say(message);
    return out;
  }

  const Scenario& sc_;
  const Robot& robot_;
  const RunRequest& request_;
  const Variant& variant_;
  std::filesystem::path dir_;
};

// The program's start point is every variant's first pose: when the robot cannot reach it, the
// scenario itself is bad input (InputError at the first move), found before any variant runs.
void check_start_reachable(const Scenario& sc, const Robot& robot) {
  if (sc.program.moves.empty()) return;
  const IkSolver::Result q0 = robot.ik->solve(tool_pose(sc.start, sc.robot.tool_rotation), sc.robot.q_seed);
  if (!q0.outcome.ok()) {
    throw move_error(sc, sc.program, 0, "the start point " + pose_text(sc.start) + " cannot be reached: " + q0.outcome.message);
  }
}

// The summary entry of a variant that did not finish: what identifies it, and `status`.
nlohmann::json unfinished(const Scenario& sc, const Variant& variant, const std::string& status) {
  return {{"name", variant.name},
          {"method", std::string(to_string(variant_method(sc.program, variant)))},
          {"baseline", variant.baseline},
          {"status", status}};
}

// One variant, failing alone: an exception other than bad input (a file or video that cannot be
// written, an internal error) becomes its status; a stop request (Interrupted, or ffmpeg ended by
// the same Ctrl-C) marks it interrupted and removes its unfinished folder. InputError (a
// variant's bad parameter is bad input of the scenario) propagates.
nlohmann::json run_variant(const Scenario& sc, const Robot& robot, const RunRequest& request, const Variant& variant,
                           int& interrupted_by) {
  const std::filesystem::path dir = request.out_dir / variant.name;
  const auto discard = [&] {
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  };
  try {
    return VariantRun(sc, robot, request, variant).run();
  } catch (const Interrupted& stop) {
    interrupted_by = stop.signal;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    if (stop_signal() == 0) {
      discard();
      if (request.progress) request.progress("  " + variant.name + ": failed: " + e.what());
      nlohmann::json out = unfinished(sc, variant, "failed");
      out["message"] = e.what();
      return out;
    }
    interrupted_by = stop_signal();
  }
  discard();
  return unfinished(sc, variant, "interrupted");
}

}  // namespace

bool video_supported() {
#ifdef BLENDBENCH_HAS_RENDER
  return true;
#else
  return false;
#endif
}

RunResult run_scenario(const Scenario& scenario, const RunRequest& request) {
  if (request.video && !video_supported()) {
    throw InputError("", 0, 0, "--no-video", "this build has no rendering (BLENDBENCH_RENDER=OFF): pass --no-video");
  }
  std::vector<const Variant*> selected;
  for (const std::string& name : request.variants) selected.push_back(&find_variant(scenario, name));
  if (request.variants.empty()) {
    for (const Variant& v : scenario.variants) selected.push_back(&v);
  }
  // variant names become folders under out_dir: never a path that leaves it
  for (const Variant* v : selected) {
    if (const std::string problem = folder_name_problem(v->name); !problem.empty()) {
      throw InputError(scenario.file, v->where.line, v->where.column, "variants[].name", "variant " + problem);
    }
  }

  Robot robot;
  robot.chain = load_urdf_chain(scenario.robot.urdf, scenario.robot.base_link, scenario.robot.tip_link);
  robot.ik = std::make_unique<IkSolver>(robot.chain);
  robot.sim = std::make_unique<Simulator>(scenario.robot.mjcf);
  robot.keep_out = keep_out_of(robot.sim->model());

  RunResult result;
  result.summary = {{"scenario", scenario.name},
                    {"file", scenario.file},
                    {"description", scenario.description},
                    {"servo_rate_hz", scenario.servo.rate_hz},
                    {"variants", nlohmann::json::array()}};
  check_start_reachable(scenario, robot);
  std::size_t index = 0;
  for (const Variant* variant : selected) {
    ++index;
    if (result.interrupted_by == 0) result.interrupted_by = stop_signal();
    if (result.interrupted_by != 0) {
      result.summary["variants"].push_back(unfinished(scenario, *variant, "interrupted"));
      continue;
    }
    if (request.progress) {
      request.progress(std::string("[") + std::to_string(index) + "/" + std::to_string(selected.size()) + "] " +
                       variant->name);
    }
    nlohmann::json v = run_variant(scenario, robot, request, *variant, result.interrupted_by);
    result.all_ok = result.all_ok && v["status"] == "ok";
    result.summary["variants"].push_back(std::move(v));
  }

  // relative figures against the first exact-stop variant, when there is one
  const nlohmann::json* reference = nullptr;
  for (const auto& v : result.summary["variants"]) {
    if (v["method"] == "none" && v["status"] == "ok" && v["cycle_time_s"].is_number()) {
      reference = &v;
      break;
    }
  }
  if (reference != nullptr) {
    const double t_ref = (*reference)["cycle_time_s"].get<double>();
    const std::string ref_name = (*reference)["name"];
    for (auto& v : result.summary["variants"]) {
      if (v["status"] == "ok" && v["cycle_time_s"].is_number()) {
        v["cycle_time_vs_reference"] = finite_or_null(v["cycle_time_s"].get<double>() / t_ref);
        v["reference_variant"] = ref_name;
      }
    }
  }
  if (result.interrupted_by != 0) result.all_ok = false;
  write_file_atomic(request.out_dir / "summary.json", result.summary.dump(2) + "\n");

  if (request.plots && result.interrupted_by == 0) {
    const auto start = Clock::now();
    // an argument vector, no shell: the output folder is data, whatever characters it holds
    const ProcessResult plotted =
        run_process({"/usr/bin/python3", data_file("report/scripts/plot_run.py"), request.out_dir.string()});
    if (request.progress) {
      request.progress(plotted.ok ? "plots written (" + format_fixed(seconds_since(start), 1) + " s)"
                                  : "warning: the plot script failed (" + plotted.message + ")");
    }
  }
  return result;
}

}  // namespace blendbench
