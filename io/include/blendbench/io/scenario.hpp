#pragma once
// YAML scenarios: a program of moves placed in the robot's workspace, the robot and servo
// settings, and the variants (transition settings) to compare. The loader validates everything
// once and converts to SI; any problem is an InputError naming the file, line, column and the
// field path (e.g. "program.moves[3].arc.center").

#include <Eigen/Geometry>
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "blendbench/program/program.hpp"
#include "blendbench/timing/timing.hpp"

namespace blendbench {

struct RobotSettings {
  std::string urdf;  // absolute path of the kinematic model
  std::string mjcf;  // absolute path of the MuJoCo model
  std::string base_link = "base_link";
  std::string tip_link = "tcp";
  Eigen::Matrix3d tool_rotation = Eigen::Matrix3d::Identity();  // fixed TCP orientation, base frame
  Eigen::Matrix<double, 6, 1> q_seed = Eigen::Matrix<double, 6, 1>::Zero();  // rad, IK seed at the start
};

struct ServoSettings {
  double rate_hz = 1000;
  std::optional<std::array<double, 6>> kp;  // N m/rad; unset = the simulator's defaults
  std::optional<std::array<double, 6>> kd;  // N m s/rad
  bool gravity_compensation = true;
  bool feedforward = false;
};

struct SimulationSettings {
  double settle_tolerance = 1e-4;  // m: the run has settled when the TCP stays this close to the end point
  double settle_time = 1.0;        // s simulated after the reference ends
};

struct VideoSettings {
  double fps = 30;
  int width = 640;
  int height = 480;
};

// One variant: the transition applied to every move that does not set its own, an optional
// buffer mode for all moves, and an optional velocity-planning baseline.
struct Variant {
  std::string name;
  std::optional<Transition> transition;
  std::optional<BufferMode> buffer;
  std::string baseline = "none";  // "none", "exact_stop" or "junction_slowdown"
  SourceRef where;
};

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
  RobotSettings robot;
  ServoSettings servo;
  SimulationSettings simulation;
  VideoSettings video;
};

// Reads and validates a scenario file. Relative paths inside it (models, G-code) are resolved
// against the file's directory first, then against the repository root. Throws InputError.
Scenario load_scenario(const std::string& path);

// The same from text; `file` names it in errors, `base_dir` resolves relative paths.
Scenario parse_scenario(const std::string& text, const std::string& file, const std::string& base_dir);

// The program of one variant: its transition on every move without its own, its buffer mode
// on every move without its own.
Program program_for(const Scenario& scenario, const Variant& variant);

// The velocity planner's options for a variant: the servo period, the scenario's limits mode
// and axis limits, the variant's baseline.
TimingOptions timing_options(const Scenario& scenario, const Variant& variant);

// The variant named `name`; throws InputError (field "--variant") listing the names when absent.
const Variant& find_variant(const Scenario& scenario, const std::string& name);

// Scenario and variant names become folder names under the output folder, so they are
// restricted to letters, digits, '_', '-' and '.', start with a letter, digit or '_' (no '.'
// or '..', no hidden folder) and are at most 100 characters long. Returns why `name` is not
// such a name, or an empty string when it is.
std::string folder_name_problem(const std::string& name);

}  // namespace blendbench
