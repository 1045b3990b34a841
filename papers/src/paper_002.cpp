// Seed 002 section 7 (Makino 1988): the 90 degree corner at 400 mm/s with a large circle, a
// small circle and the clothoid pair, executed on the elastic arm (paper_002.hpp).

#include "blendbench/papers/paper_002.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "blendbench/corner/blend.hpp"
#include "blendbench/corner/clothoid_blend.hpp"
#include "blendbench/io/data_root.hpp"
#include "blendbench/io/urdf_chain.hpp"
#include "blendbench/papers/constant_speed.hpp"
#include "blendbench/report/csv.hpp"
#include "blendbench/report/output.hpp"
#include "papers_internal.hpp"

namespace blendbench {
using namespace papers_detail;
namespace {

// The servo's setpoint period: the reference's sample period (servo.hpp).
constexpr double kSetpointPeriod = 1.0 / 500;
// Simulated after the reference ends, and the residual-vibration window after the corner: the
// run-out holds the speed for 0.26 s after the curve before its ramp down begins.
constexpr double kSettleTime = 0.3;     // s
constexpr double kVibrationWindow = 0.2;  // s
// The following error is compared from this long before the curve begins.
constexpr double kBeforeCorner = 0.05;  // s
constexpr double kDeflection = std::numbers::pi / 2;  // rad: the corner turns by 90 degrees

// The arm, loaded once: kinematics for IK, dynamics for the simulation.
struct Arm {
  KinematicChain chain = load_urdf_chain(data_file("models/ur5e_like.urdf"));
  IkSolver ik{chain};
  Simulator sim{data_file("models/ur5e_like.xml")};
};
const Arm& arm() {
  static const Arm loaded;
  return loaded;
}

// The seed's clothoid pair for the corner: a symmetric pair (seed 002 eq. 9) starting corner_size
// before the corner.
ClothoidPair seed_pair(const Corner002& c) { return clothoid_pair_for_tangent_length(kDeflection, c.corner_size); }

std::string curve_name(Curve002 curve) {
  switch (curve) {
    case Curve002::kLargeCircle:
      return "large_circle";
    case Curve002::kSmallCircle:
      return "small_circle";
    case Curve002::kClothoid:
      return "clothoid";
  }
  return "?";
}

// The program: the leading line (with its run-up) to the corner, the following line (with its
// run-out) from it, the curve as the leading move's transition.
Program program_002(Curve002 curve, const Corner002& c) {
  const Vec3 e1(std::cos(c.heading), std::sin(c.heading), 0);
  const Vec3 e2(-std::sin(c.heading), std::cos(c.heading), 0);
  const Vec3 start = c.corner - (c.run_up + c.leading) * e1;
  const Vec3 end = c.corner + (c.following + c.run_out) * e2;
  const ClothoidPair pair = seed_pair(c);
  Transition t;
  switch (curve) {
    case Curve002::kLargeCircle:
      // an arc blend with corner distance d between perpendicular lines has radius d
      t = transition(Method::kArc, c.corner_size);
      break;
    case Curve002::kSmallCircle:
      t = transition(Method::kArc, 1 / pair.kappa_peak);
      break;
    case Curve002::kClothoid:
      t = transition(Method::kClothoid, pair.deviation);
      break;
  }
  Program program;
  for (int i = 0; i < 2; ++i) {
    Move& m = program.moves.emplace_back();
    m.geometry = Line{i == 0 ? start : c.corner, i == 0 ? c.corner : end};
    // the limits do not enter the constant-speed timing; they document the run for validate()
    m.limits = {c.speed, 20, 20, 2000};
    m.transition = t;
  }
  return program;
}

ServoConfig servo_002(Servo002 setting, const JointVector& q0) {
  ServoTuning tuning;
  switch (setting) {
    case Servo002::kDefault:
      break;
    case Servo002::kSlow:
      // a quarter of both bandwidth caps: a quarter of every velocity loop
      tuning.delay_phase /= 4;
      tuning.antiresonance_share /= 4;
      break;
    case Servo002::kFast:
      tuning.rate_hz = 8000;
      tuning.measurement_delay_ticks = 0;
      tuning.encoder_counts_per_turn = 0;
      break;
  }
  return tune_servo(arm().sim, q0, tuning);
}

// The corner frame: origin at the corner, u along the leading line, w towards the turn.
std::pair<double, double> corner_uv(const Corner002& c, const Vec3& p) {
  const Vec3 d = p - c.corner;
  return {d.x() * std::cos(c.heading) + d.y() * std::sin(c.heading), -d.x() * std::sin(c.heading) + d.y() * std::cos(c.heading)};
}

bool clean(const Execution& e) { return e.health && !e.health->saturated && !e.health->limits_exceeded(); }

}  // namespace

CurveRun002 run_curve_002(Curve002 curve, const Corner002& corner, Servo002 servo) {
  CurveRun002 run;
  run.curve = curve;
  run.name = curve_name(curve);
  const ClothoidPair pair = seed_pair(corner);
  const std::string r_small = fixed(1e3 / pair.kappa_peak, 2);
  run.label = curve == Curve002::kLargeCircle  ? "A: large circle, r 25 mm"
              : curve == Curve002::kSmallCircle ? "C: small circle, r " + r_small + " mm (the clothoid's minimum)"
                                                : "B: clothoid pair, 25 x 25 mm";
  run.program = program_002(curve, corner);
  validate(run.program);
  run.path = blend(run.program);
  run.timing = constant_speed_timing(run.path, corner.speed, corner.ramp, kSetpointPeriod);

  // the start pose (the ready configuration's branch), the servo tuned there, the run
  const Arm& a = arm();
  Eigen::Isometry3d start = Eigen::Isometry3d::Identity();
  start.linear() = Eigen::AngleAxisd(std::numbers::pi, Vec3::UnitX()).toRotationMatrix();
  start.translation() = run.path.point(0);
  JointVector seed;
  seed << std::numbers::pi, -std::numbers::pi / 2, std::numbers::pi / 2, -std::numbers::pi / 2, -std::numbers::pi / 2, 0;
  const IkSolver::Result q0 = a.ik.solve(start, seed);
  if (!q0.outcome.ok()) throw std::runtime_error("002: the start of the corner run is out of reach: " + q0.outcome.message);
  ExecutionOptions options;
  options.tool_rotation = start.linear();
  options.q0 = q0.q;
  options.servo = servo_002(servo, q0.q);
  options.run.settle_time = kSettleTime;
  options.metrics.vibration_window = kVibrationWindow;
  run.execution = execute(a.sim, a.ik, run.program, run.path, run.timing, options);
  if (!run.execution.joints.outcome.ok()) throw std::runtime_error("002: " + run.execution.joints.outcome.message);
  if (!run.execution.metrics) throw std::runtime_error("002: the simulation diverged: " + run.execution.trace.warning);

  // the error pulses around the corner
  const CornerTiming& when = run.execution.corners.at(0);
  const double t0 = when.t_start - kBeforeCorner, t1 = when.t_end + kVibrationWindow;
  double sum = 0;
  std::size_t count = 0;
  for (const TraceSample& s : run.execution.trace.samples) {
    if (s.t < t0 || s.t > t1) continue;
    for (int i = 0; i < 6; ++i) {
      const double e = std::abs(s.following_error[i]);
      if (e > run.following_peak) {
        run.following_peak = e;
        run.following_joint = i + 1;
      }
      sum += e * e;
      ++count;
    }
  }
  run.following_rms = count > 0 ? std::sqrt(sum / static_cast<double>(count)) : 0.0;
  return run;
}

Paper002 reproduce_002() {
  Paper002 out;
  const std::array<Curve002, 3> curves = {Curve002::kLargeCircle, Curve002::kSmallCircle, Curve002::kClothoid};
  for (const Curve002 c : curves) out.runs.push_back(run_curve_002(c, out.corner));
  // the servo decides how much shows (the paper's own remark): slow and fast settings
  for (const Servo002 s : {Servo002::kDefault, Servo002::kSlow, Servo002::kFast}) {
    std::vector<std::pair<double, double>> row;
    for (const Curve002 c : curves) {
      const CurveRun002 r = s == Servo002::kDefault ? out.runs[static_cast<std::size_t>(c)] : run_curve_002(c, out.corner, s);
      row.emplace_back(r.following_peak, r.execution.metrics->vibration_corners.at(0).peak_to_peak);
    }
    out.servos.push_back(row);
  }
  // the same corner elsewhere in the workspace, turned the other ways
  struct Where {
    const char* description;
    Vec3 corner;
    double heading;
  };
  for (const Where& w : {Where{"corner at (450, 0, 100) mm, leading line along -x", Vec3(0.45, 0, 0.10), std::numbers::pi},
                         Where{"corner at (450, -250, 100) mm, leading line along +y", Vec3(0.45, -0.25, 0.10), std::numbers::pi / 2}}) {
    Corner002 c = out.corner;
    c.corner = w.corner;
    c.heading = w.heading;
    Paper002::Placement p;
    p.description = w.description;
    for (const Curve002 curve : curves) {
      const CurveRun002 r = run_curve_002(curve, c);
      p.vibration.push_back(r.execution.metrics->vibration_corners.at(0).peak_to_peak);
      p.clean = p.clean && clean(r.execution);
    }
    out.placements.push_back(p);
  }
  return out;
}

namespace {

// Per curve figures for results.json and the report.
nlohmann::json curve_json(const CurveRun002& r) {
  const Metrics& m = *r.execution.metrics;
  const Health& h = *r.execution.health;
  const CornerReport& c = r.path.corners.at(0);
  const Vibration& v = m.vibration_corners.at(0);
  const CornerTiming& when = r.execution.corners.at(0);
  return {{"name", r.name},
          {"label", r.label},
          {"kappa_max_per_mm", c.kappa_max * kMm},
          {"length_mm", c.length / kMm},
          {"trim_mm", c.trim_in / kMm},
          {"deviation_mm", c.deviation / kMm},
          {"t_start_s", when.t_start},
          {"t_end_s", when.t_end},
          {"following_error_peak_mrad", r.following_peak * 1e3},
          {"following_error_rms_mrad", r.following_rms * 1e3},
          {"following_error_peak_joint", r.following_joint},
          {"residual_vibration_um", v.peak_to_peak * 1e6},
          {"residual_vibration_frequency_hz", v.frequency},
          {"tracking_error_max_um", m.tracking_error_max * 1e6},
          {"contour_error_planned_max_um", m.contour_error_planned_max * 1e6},
          {"contour_error_programmed_max_mm", m.contour_error_programmed_max / kMm},
          {"jerk_commanded_peak_m_s3", m.jerk_commanded_peak},
          {"jerk_actual_peak_m_s3", m.jerk_actual_peak},
          {"torque_peak_nm", m.torque_peak.maxCoeff()},
          {"saturated", h.saturated},
          {"limits_exceeded", h.limits_exceeded()}};
}

// trace_<curve>.csv: the run at every setpoint, in the corner frame.
std::string trace_csv(const CurveRun002& r, const Corner002& corner) {
  std::vector<std::string> columns = {"t", "s", "v", "kappa", "u", "w", "u_cmd", "w_cmd", "tracking_error_um", "vibration_um"};
  for (int i = 1; i <= 6; ++i) columns.push_back("following_error_mrad_" + std::to_string(i));
  CsvWriter out(columns);
  const Trace& trace = r.execution.trace;
  const Metrics& m = *r.execution.metrics;
  std::vector<double> row(columns.size());
  for (std::size_t k = 0; k < trace.samples.size(); ++k) {
    const TraceSample& s = trace.samples[k];
    const TimedSample& p = k < r.timing.samples.size() ? r.timing.samples[k] : r.timing.samples.back();
    const auto [u, w] = corner_uv(corner, s.tcp);
    const auto [uc, wc] = corner_uv(corner, s.tcp_cmd);
    std::size_t c = 0;
    for (const double v : {s.t, p.s / kMm, (k < r.timing.samples.size() ? p.v : 0.0) / kMm,
                           r.path.curvature_vector(p.s).norm() * kMm, u / kMm, w / kMm, uc / kMm, wc / kMm,
                           m.tracking_error[k] * 1e6, m.vibration[k].norm() * 1e6}) {
      row[c++] = v;
    }
    for (int i = 0; i < 6; ++i) row[c++] = s.following_error[i] * 1e3;
    out.row(row);
  }
  return out.text();
}

const char* servo_label(std::size_t s) {
  return s == 0 ? "tuned (2 kHz drive, 1 tick delay, 2^14 x 100 counts)"
                : s == 1 ? "slow (a quarter of the tuned bandwidths)" : "fast (8 kHz drive, no delay, exact encoder)";
}

}  // namespace

void write_002(const Paper002& r, const std::filesystem::path& dir) {
  nlohmann::json curves = nlohmann::json::array();
  for (const CurveRun002& run : r.runs) curves.push_back(curve_json(run));
  nlohmann::json servos = nlohmann::json::array();
  for (std::size_t s = 0; s < r.servos.size(); ++s) {
    nlohmann::json row = {{"servo", servo_label(s)}};
    for (std::size_t c = 0; c < r.servos[s].size(); ++c) {
      row[r.runs[c].name] = {{"following_error_peak_mrad", r.servos[s][c].first * 1e3},
                             {"residual_vibration_um", r.servos[s][c].second * 1e6}};
    }
    servos.push_back(row);
  }
  nlohmann::json placements = nlohmann::json::array();
  for (const Paper002::Placement& p : r.placements) {
    nlohmann::json row = {{"placement", p.description}, {"clean", p.clean}};
    for (std::size_t c = 0; c < p.vibration.size(); ++c) row[r.runs[c].name + "_residual_vibration_um"] = p.vibration[c] * 1e6;
    placements.push_back(row);
  }
  const Corner002& c = r.corner;
  const nlohmann::json j = {{"paper", "002"},
                            {"corner_mm", {c.corner.x() / kMm, c.corner.y() / kMm, c.corner.z() / kMm}},
                            {"heading_deg", c.heading * 180 / std::numbers::pi},
                            {"speed_mm_s", c.speed / kMm},
                            {"curves", curves},
                            {"servos", servos},
                            {"placements", placements}};
  write_file_atomic(dir / "results.json", j.dump(1) + "\n");
  for (const CurveRun002& run : r.runs) write_file_atomic(dir / ("trace_" + run.name + ".csv"), trace_csv(run, r.corner));
  write_file_atomic(dir / "README.md", markdown_002(r));
}

std::string markdown_002(const Paper002& r) {
  const auto um = [](double m) { return fixed(m * 1e6, 1); };
  const auto mrad = [](double rad) { return fixed(rad * 1e3, 3); };
  const CurveRun002& large = r.runs[0];
  const CurveRun002& small = r.runs[1];
  const CurveRun002& clothoid = r.runs[2];
  const auto vib = [](const CurveRun002& run) { return run.execution.metrics->vibration_corners.at(0).peak_to_peak; };
  std::string out = "# Seed 002 (Makino, clothoidal interpolation, 1988): section 7's experiment on the elastic arm\n\n";
  out += "Generated by `blendbench reproduce 002` (or `all`); do not edit by hand. The paper runs a 90° corner, "
         "interpolated over 25 × 25 mm between a 40 mm leading and a 30 mm following line, at a pen speed of 400 mm/s "
         "with three curves (its fig. 15): A a circle of radius 25 mm, C a circle of the clothoid's minimum radius, B the "
         "clothoid pair; fig. 17 shows the pen's path, fig. 18 the axes' positional error pulses. It prints no numbers, so "
         "the tables below are ours alone.\n\n";
  out += "## Set-up\n\n";
  out += "- Arm: `models/ur5e_like.xml`, elastic joints (its header states and `tests/sim/elastic_model_test.cpp` "
         "measures the natural frequencies: 21.2 Hz first mode with the motors held), the default cascade servo "
         "(`sim/servo.hpp`: 2 kHz drive under 500 Hz setpoints, velocity and inverse-dynamics feed-forward, gravity and "
         "deflection compensation).\n";
  out += "- Path: the leading line with a run-up of 200 mm before it, the following line with a run-out of 200 mm after "
         "it; the corner at (" + fixed(r.corner.corner.x() / kMm, 0) + ", " + fixed(r.corner.corner.y() / kMm, 0) + ", " +
         fixed(r.corner.corner.z() / kMm, 0) + ") mm in the base frame, tool down, in the horizontal plane, leading line "
         "along +x. This placement is one where all three curves stay within the arm's joint velocity and acceleration "
         "limits at 400 mm/s (the small circle needs " + fixed(0.16 / (1 / clothoid.path.corners[0].kappa_max), 1) +
         " m/s² at the tool); elsewhere the small circle exceeds the shoulder's 19 rad/s².\n";
  out += "- Timing: a constant line speed of 400 mm/s over the paper's lines and the curve, reached by a sinusoidal "
         "ramp over the first 100 mm of the run-up and left over the last 100 mm of the run-out "
         "(`papers/constant_speed.hpp`). The circles' curvature steps therefore become acceleration steps κv² at their "
         "ends, as on the paper's controller. The velocity planner's own option for this (curvature steps allowed) is "
         "work of another branch; this reference is built directly.\n";
  out += "- Measured around the corner: the drive's following error (motor reference − encoder, per joint; the "
         "paper's error pulses) from 50 ms before the curve to 200 ms after it; the residual vibration in the 200 ms after "
         "the curve (the tracking error high-passed at 12 Hz, peak-to-peak, as `blendbench run` reports it).\n\n";
  out += "## The three curves (cf. figs. 15, 17, 18)\n\n";
  out += "| curve | κmax (1/mm) | length (mm) | starts before the corner (mm) | following error peak / RMS (mrad) | peak at joint "
         "| residual vibration (µm) | its frequency (Hz) | tracking error max (µm) | contour error vs its path max (µm) | "
         "commanded jerk peak (m/s³) | clean run |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|:---:|\n";
  for (const CurveRun002& run : r.runs) {
    const Metrics& m = *run.execution.metrics;
    const CornerReport& c = run.path.corners.at(0);
    out += "| " + run.label + " | " + fixed(c.kappa_max * kMm, 4) + " | " + fixed(c.length / kMm, 2) + " | " +
           fixed(c.trim_in / kMm, 2) + " | " + mrad(run.following_peak) + " / " + mrad(run.following_rms) + " | " +
           std::to_string(run.following_joint) + " | " + um(vib(run)) + " | " +
           fixed(m.vibration_corners.at(0).frequency, 1) + " | " + um(m.tracking_error_max) + " | " +
           um(m.contour_error_planned_max) + " | " + fixed(m.jerk_commanded_peak, 0) + " | " +
           (clean(run.execution) ? "yes" : "no") + " |\n";
  }
  out += "\n![following error per joint around the corner (cf. fig. 18)](following_error.png)\n"
         "![TCP path near the corner (cf. fig. 17)](path.png)\n\n";
  out += "## The servo decides how much shows\n\n";
  out += "| servo | following error peak (mrad) A / C / B | residual vibration (µm) A / C / B |\n|---|---|---|\n";
  for (std::size_t s = 0; s < r.servos.size(); ++s) {
    out += std::string("| ") + servo_label(s) + " | ";
    for (std::size_t c = 0; c < r.servos[s].size(); ++c) out += (c ? " / " : "") + mrad(r.servos[s][c].first);
    out += " | ";
    for (std::size_t c = 0; c < r.servos[s].size(); ++c) out += (c ? " / " : "") + um(r.servos[s][c].second);
    out += " |\n";
  }
  out += "\n## Elsewhere in the workspace\n\n| placement | residual vibration (µm) A / C / B | within the joint limits |\n|---|---|:---:|\n";
  for (const Paper002::Placement& p : r.placements) {
    out += "| " + p.description + " | ";
    for (std::size_t c = 0; c < p.vibration.size(); ++c) out += (c ? " / " : "") + um(p.vibration[c]);
    out += std::string(" | ") + (p.clean ? "yes" : "no (an acceleration limit is exceeded; physics unchanged)") + " |\n";
  }
  // the note: what agrees and what the servo decides
  out += "\n## Where we agree with the paper, and where the servo decides\n\n";
  out += "- **Same peak curvature, G1 against G2** (C against B): the clothoid pair's continuous curvature leaves " +
         fixed(vib(small) / vib(clothoid), 1) + " times less residual vibration than the circle of the same minimum radius (" +
         um(vib(clothoid)) + " against " + um(vib(small)) + " µm) and " +
         fixed(small.following_peak / clothoid.following_peak, 1) +
         " times smaller error pulses: the circle's curvature steps put acceleration steps of κv² = " +
         fixed(0.16 * small.path.corners[0].kappa_max, 1) + " m/s² into the reference, the clothoid ramps its curvature "
         "over its length. This is the paper's conclusion, and it holds for the reason the paper gives.\n";
  out += "- **The large circle** (A, a curvature of " + fixed(large.path.corners[0].kappa_max * kMm, 3) + " 1/mm against the "
         "clothoid's " + fixed(clothoid.path.corners[0].kappa_max * kMm, 3) + "): it excites " +
         (vib(large) > vib(clothoid) ? fixed(vib(large) / vib(clothoid), 1) + " times more residual vibration than the "
                                                                             "clothoid here, as the paper found"
                                     : "less residual vibration than the clothoid here, against the paper") +
         ". Its steps are smaller (κv² = " + fixed(0.16 * large.path.corners[0].kappa_max, 1) +
         " m/s²) than the clothoid's peak acceleration, so the ordering of A and B depends on where the steps land on the "
         "arm's modes: at the other placements above it ";
  bool large_above = true;
  for (const Paper002::Placement& p : r.placements) large_above = large_above && p.vibration[0] > p.vibration[2];
  out += large_above ? "holds as well.\n" : "does not always hold (see the table), while C above B holds everywhere.\n";
  // the servo settings: does the same-curvature ordering hold, and how do the pulses scale
  bool g2_below = true;
  for (const auto& row : r.servos) g2_below = g2_below && row[2].second < row[1].second && row[2].first < row[1].first;
  const auto spread = [&](std::size_t s) { return r.servos[s][1].first / r.servos[s][2].first; };
  out += "- **The servo**: the paper remarks that a servo with much delay hides the difference between the curves and "
         "an ideal one exposes it. Measured at the drive, the small circle's error pulses are " + fixed(spread(1), 1) +
         " times the clothoid's under the slow servo, " + fixed(spread(0), 1) + " times under the tuned one and " +
         fixed(spread(2), 1) + " times under the fast one; " +
         (spread(1) < spread(0) && spread(0) < spread(2)
              ? "the faster the servo, the more the curves differ, as the paper says."
              : "so on this arm the ratio does not grow with the servo's speed as the paper suggests: the elastic "
                "joints, not only the servo, shape the pulses.") +
         " The residual vibration is the arm's, excited by the reference; " +
         (g2_below ? "the clothoid stays below the small circle in both the error pulses and the vibration under all "
                     "three settings."
                   : "under at least one setting the clothoid does not stay below the small circle (table above).") +
         "\n";
  return out;
}

}  // namespace blendbench
