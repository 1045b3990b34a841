#pragma once
// YAML scenarios: a program of moves placed in the robot's workspace, the robot and servo
// settings, and the variants (transition settings) to compare. The loader validates everything
// once and converts to SI; any problem is an InputError naming the file, line, column and the
// field path (e.g. "program.moves[3].arc.center").

#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "blendbench/program/program.hpp"
#include "blendbench/robot/kinematics.hpp"
#include "blendbench/timing/timing.hpp"

namespace blendbench {

// `robot.model`: which dynamics model runs, elastic joints (models/ur5e_like.xml, the default)
// or rigid ones (models/ur5e_like_rigid.xml); for another URDF the MJCF beside it (model_file).
enum class ArmModel { kElastic, kRigid };

struct RobotSettings {
  ArmModel model = ArmModel::kElastic;
  std::string urdf;  // absolute path of the kinematic model
  std::string mjcf;  // absolute path of the MuJoCo model (the model's file unless `mjcf` is given)
  std::string base_link;  // empty: the URDF's root link
  std::string tip_link;   // empty: the leaf reached through the most movable joints
  // an MJCF of the user's own (urdf empty): the chain ends at this site or body of it
  std::string tip_site, tip_body;
  Eigen::Matrix3d tool_rotation = Eigen::Matrix3d::Identity();  // fixed TCP orientation, base frame
  JointVector q_seed = JointVector::Zero();  // rad, IK seed at the start
  Eigen::Isometry3d tool = Eigen::Isometry3d::Identity();  // the TCP in the flange frame (m, rad)
  bool allow_branch_change = false;  // the joint reference may cross a singularity (reported)
  // no MJCF given and none beside the URDF (model_file): the dynamics are built from the URDF
  // (mjcf is empty)
  bool mjcf_from_urdf = false;
  double estimate_total_mass = 0;  // kg; 0 = no estimate (the URDF must carry inertias and efforts)
  SourceRef estimate_where;        // where `estimate_inertia` was given
  SourceRef urdf_where;   // where `urdf` was given (or the robot map), for the URDF's errors
  SourceRef model_where;  // where `model` (or, when absent, `mjcf`) was given, for later errors
};

// `servo.controller`: the cascade with every feed-forward (the default) or the plain PD without
// feed-forward kept for comparison (sim/servo.hpp states both).
enum class ServoController { kCascade, kPd };

// The servo: its rate, delay and encoder, and the switches of the cascade. The gains are tuned
// from the model at the start pose (sim/servo.hpp, ServoTuning); unset switches take the
// controller's defaults.
struct ServoSettings {
  ServoController controller = ServoController::kCascade;
  double rate_hz = 2000;                    // 125 .. 8000: the drives' cascade; must divide the model's physics rate
  double setpoint_rate_hz = 500;            // 125 .. rate_hz: the reference (and timing) rate; must divide rate_hz
  int measurement_delay_ticks = 1;          // >= 0
  double encoder_counts_per_turn = 1638400;  // per joint turn, >= 0 (0: exact)
  std::optional<bool> velocity_feedforward, acceleration_feedforward, gravity_compensation, deflection_compensation;
  SourceRef rate_where;  // where rate_hz was given (the runner checks it against the model's timestep)
};

// Settling, residual vibration and jerk filtering of the metrics (sim/metrics.hpp states why).
struct SimulationSettings {
  double settle_tolerance = 0.03e-3;     // m: within this of the end point ...
  double settle_speed_tolerance = 1e-3;  // m/s: ... and slower than this ...
  double settle_window = 0.2;            // s: ... for this long, after the reference has ended
  double settle_time = 1.0;              // s simulated after the reference ends (>= settle_window)
  double vibration_window = 0.5;         // s
  double vibration_highpass = 12;        // Hz
  double jerk_lowpass = 50;              // Hz
  SourceRef settle_time_where;           // where settle_time_s was given (or its map), for the runner's work bound
};

// `video.camera`: where the videos' camera stands (render/camera.hpp states the framing rule and
// the angle convention: the camera's azimuth and elevation seen from what it looks at).
//   part:  framed on the programmed path so that its bounding box spans `fill` of the frame,
//          at an oblique view from the path's plane unless azimuth / elevation are given;
//   fixed: at `position`, looking at `look_at` (robot base frame);
//   tcp:   following the actual TCP from `distance`, at azimuth / elevation (default: the
//          part camera's).
enum class CameraMode { kPart, kFixed, kTcp };

struct VideoCamera {
  CameraMode mode = CameraMode::kPart;
  double fill = 0.6;                                 // part: 0.1 .. 1
  std::optional<double> azimuth_deg, elevation_deg;  // part, tcp: deg, -360 .. 360 / -89 .. 89
  Vec3 position = Vec3::Zero(), look_at = Vec3::Zero();  // fixed: m, base frame, distinct
  double distance = 0.35;                            // tcp: m, > 0
  double fovy_deg = 45;                              // fixed, tcp: vertical field of view, 5 .. 120
};

struct VideoSettings {
  double fps = 30;    // 24 .. 120
  int width = 640;    // even, 64 .. 1920
  int height = 480;   // even, 64 .. 1920
  VideoCamera camera;
  SourceRef fps_where;  // where fps was given (or its map), for the runner's work bound
};

// One perturbed arm model of a sensitivity study (`sensitivity`, docs/sensitivity.md): the
// nominal model with one of its parameters changed (sim/simulator.hpp, ModelChanges, states what
// each one scales), so that the runs tell whether a conclusion survives the model's uncertainty.
struct Perturbation {
  std::string name;            // what it changes, e.g. "stiffness x0.5", "delay +1 tick"
  double stiffness_scale = 1;  // > 0: the gears' stiffness
  double inertia_scale = 1;    // > 0: every link's mass and inertia
  double friction_scale = 1;   // >= 0: the joints' viscous and Coulomb friction
  int extra_delay_ticks = 0;   // >= 0: servo ticks added to the measurement delay
};

// The perturbed models of `run --sensitivity` and `compare --sensitivity`, one parameter at a
// time; default_perturbations() unless the scenario's `sensitivity` map sets them.
struct SensitivitySettings {
  std::vector<Perturbation> perturbations;
  SourceRef where;  // the scenario's `sensitivity` map (line 0: the defaults)
};

// The model's stated uncertainty (docs/sensitivity.md states why each range): gear stiffness
// x0.5 and x1.5, link inertias x0.8 and x1.2, friction x0.5 and x1.5, one more tick of
// measurement delay; seven models.
std::vector<Perturbation> default_perturbations();

// One variant: the transition applied to every move that does not set its own, an optional
// buffer mode for all moves, an optional smoothing, and an optional velocity-planning baseline.
struct Variant {
  std::string name;
  std::optional<Transition> transition;
  std::optional<BufferMode> buffer;
  // its `smoothing` keys applied to the program's (program.smoothing); none: the program's
  std::optional<Smoothing> smoothing;
  TimingOptions::Baseline baseline = TimingOptions::Baseline::kNone;
  // the velocity planner of this variant; none: the scenario's
  std::optional<TimingOptions::Algorithm> timing;
  SourceRef where;
};

// A plausibility warning: the input is valid but looks like a mistake (coordinates in another
// unit, a feed beyond the arm, a G-code feed overriding the scenario's). Printed by the commands
// that load a scenario (run, compare, validate, path, plan) and listed in summary.json's
// `warnings`; never an error.
struct LoadWarning {
  SourceRef where;
  std::string field;    // the key or word it concerns, e.g. "units", "defaults.velocity", "F"
  std::string message;
};

// "file:line:column: 'field': message", as InputError formats a refusal.
std::string to_string(const LoadWarning& warning);

struct Scenario {
  std::string file;  // path as given
  std::string name;
  std::string description;
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();  // program frame in the robot base frame
  Vec3 start = Vec3::Zero();                                // start point, base frame (m)
  Program program;                                          // moves in the base frame (m, m/s, ...)
  std::vector<bool> explicit_transition;                    // per move: the move sets its own transition
  std::vector<bool> explicit_buffer;                        // per move: the move sets its own buffer mode
  std::vector<std::string> ignored;                         // G-code words accepted but ignored
  std::vector<Variant> variants;                            // at least one
  // `limits`: which limits the plans hold (cartesian.hpp; default cartesian), and the optional
  // `axis_limits: {a: [x, y, z], j: [x, y, z]}` on the TCP along the robot base frame's axes
  // (m/s^2, m/s^3 after conversion; cartesian only)
  LimitsMode limits = LimitsMode::kCartesian;
  std::optional<AxisLimits> axis_limits;
  // `timing`: the velocity planner of every variant that sets none (timing.hpp; default optimal; seed004 for the paper reproductions, docs/timing.md)
  TimingOptions::Algorithm timing = TimingOptions::Algorithm::kOptimal;
  RobotSettings robot;
  ServoSettings servo;
  SimulationSettings simulation;
  VideoSettings video;
  SensitivitySettings sensitivity;  // the perturbed models of a sensitivity run
  std::vector<LoadWarning> warnings;  // plausibility (plausibility.hpp), in the order found
};

// The most variants one scenario may have: each is planned, simulated and rendered.
inline constexpr std::size_t kMaxVariants = 1000;

// Reads and validates a scenario file (read_input_file: a regular file of at most
// kMaxInputBytes). The format, every key with its unit, default and range, is the table in
// scenario_keys.hpp (docs/scenario_format.md). Relative paths inside it (models, G-code) are resolved
// against the file's directory first, then against the data root. Throws InputError.
Scenario load_scenario(const std::string& path);

// The same from text; `file` names it in errors, `base_dir` resolves relative paths.
Scenario parse_scenario(const std::string& text, const std::string& file, const std::string& base_dir);

// The program of one variant: its transition on every move without its own, its buffer mode
// on every move without its own, its smoothing.
Program program_for(const Scenario& scenario, const Variant& variant);

// The velocity planner's options for a variant: the setpoint period (1 / servo.setpoint_rate_hz),
// the scenario's limits mode and axis limits, the variant's baseline, the variant's planner (or
// the scenario's).
TimingOptions timing_options(const Scenario& scenario, const Variant& variant);

// The variant named `name`; throws InputError (field "--variant") listing the names when absent.
const Variant& find_variant(const Scenario& scenario, const std::string& name);

// Scenario and variant names become folder names under the output folder, so they are
// restricted to letters, digits, '_', '-' and '.', start with a letter, digit or '_' (no '.'
// or '..', no hidden folder) and are at most 100 characters long. Returns why `name` is not
// such a name, or an empty string when it is.
std::string folder_name_problem(const std::string& name);

// The MJCF file of a dynamics model beside its URDF: X.urdf -> X.xml (elastic) or X_rigid.xml
// (rigid), in the URDF's folder (it may not exist).
std::string model_file(const std::string& urdf, ArmModel model);

}  // namespace blendbench
