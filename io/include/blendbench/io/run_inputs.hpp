#pragma once
// A scenario resolved once into what the pipeline's stages take (DESIGN.md, "Drivers call the
// same pipeline"): per variant its program (the variant's transition and buffer mode on every
// move that does not set its own, a tolerance applied), its velocity planner's options and what
// the summary says it is; for the run the robot, servo, simulation and video settings. `run`,
// `compare`, `sweep` points (and the sensitivity runs) resolve here and hand these down the
// stages; nothing below asks the scenario again.
//
// Also the inputs of a G-code file run without a scenario (`blendbench run part.ngc`,
// `blendbench compare part.ngc`): the shipped arm, its servo and settings, the part placed in
// front of the robot, the file's limits as `path` and `plan` read them.

#include <optional>
#include <string>
#include <vector>

#include "blendbench/io/scenario.hpp"

namespace blendbench {

// One variant as the stages take it.
struct VariantInputs {
  std::string name;
  SourceRef where;  // the variant's entry in the scenario (line 0 for one built by a driver)
  Program program;
  TimingOptions timing;  // setpoint period, limits mode and axis limits, the variant's baseline
  // what the summary reports of it: the method it mostly uses (its transition's, else the first
  // move's), its parameter (m; 0 when none) and its equal tolerance (m; 0 when sized otherwise)
  Method method = Method::kNone;
  double parameter = 0;
  double tolerance = 0;
};

// A run as the stages take it: the scenario's settings and its resolved variants.
struct RunInputs {
  std::string file;  // the scenario (or G-code) file, for messages
  std::string name, description;
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();  // program frame in the base frame
  Vec3 start = Vec3::Zero();                                // m, base frame: every variant's first pose
  std::vector<std::string> ignored;                         // G-code words read and ignored
  std::vector<LoadWarning> warnings;                        // plausibility warnings (scenario.hpp)
  RobotSettings robot;
  ServoSettings servo;
  SimulationSettings simulation;
  VideoSettings video;
  SensitivitySettings sensitivity;  // the perturbed models of `--sensitivity`
  std::vector<VariantInputs> variants;  // at least one
  // what the driver that built the variants says about them (compare: what it left out and why),
  // written into summary.json's `notes`
  std::vector<std::string> notes;
};

// What a command changes while resolving (all optional).
struct RunSelection {
  std::vector<std::string> variants;  // the names to run, in this order (`--variant`); empty: all
  std::optional<LimitsMode> limits;   // replaces the scenario's `limits` (`--limits`)
  std::optional<TimingOptions::Algorithm> timing;  // replaces the scenario's and variants' velocity planner (`--timing`)
  // m, > 0: every move with a transition method gets this tolerance in place of its parameter
  // and start distance, in every variant (`--tolerance`; apply_tolerance)
  std::optional<double> tolerance;
};

// `program` with `tolerance` (m, > 0) on every move whose transition has a method: its parameter
// and start distance cleared (equal tolerance, Transition::tolerance).
void apply_tolerance(Program& program, double tolerance);

// The run of `scenario` with `selection` applied. Throws InputError for an unknown variant name
// (field "--variant", listing the names) and a variant name that cannot name an output folder
// (field "variants[].name", at the variant).
RunInputs resolve_run(const Scenario& scenario, const RunSelection& selection = {});

// One variant of `scenario` as resolve_run resolves it (no name checks).
VariantInputs resolve_variant(const Scenario& scenario, const Variant& variant, const RunSelection& selection = {});

// The limits of a G-code program that carries none but its F words (as `path` and `plan` read
// it): the feed until the first F word, the acceleration and deceleration, the jerk (m/s, m/s^2,
// m/s^3). These are conservative machine-tool values, not an arm's: a scenario with
// `program: {gcode: ...}` and its own `defaults` sets them.
inline constexpr double kGcodeFeed = 1000e-3 / 60;    // 1000 mm/min
inline constexpr double kGcodeAcceleration = 1000e-3;  // 1000 mm/s^2
inline constexpr double kGcodeJerk = 10000e-3;         // 10000 mm/s^3

// Where a G-code part is placed when it comes without a scenario: the centre of the bounding box
// of its path (the start point included) at this point of the robot base frame, its axes along
// the base's (m). In front of the shipped arm at the default scenario's table height, a point its
// programs reach with the tool pointing down (the default scenario's part is centred at
// (460, 0, 200) mm).
inline const Vec3 kGcodePartCentre{0.45, 0.0, 0.2};

// The scenario of a G-code file run on its own: the shipped arm (or `robot`), the servo,
// simulation and video defaults of the scenario format, the part placed by kGcodePartCentre and
// read with the kGcode* limits (its F words set the feed), named after the file (its name with
// the extension, any character a folder name may not hold replaced by '_': "bracket.ngc", apart
// from bracket.yaml's "bracket"), and two variants:
// `as_programmed` (the file's own G61/G64 blending) and `exact_stop`. Throws the reader's
// InputError (file, line, column, word).
Scenario gcode_scenario(const std::string& path, const std::optional<RobotSettings>& robot = std::nullopt);

// A robot named on the command line (`--robot`): a URDF file (its MuJoCo model beside it when
// there is one, model_file; else the dynamics built from the URDF, rigid), or the name of a
// shipped one (models/<name>.urdf in the data root: ur5e_like, kr6_like). Throws InputError with
// field `flag` when it is neither.
RobotSettings named_robot(const std::string& urdf_or_name, const std::string& flag);

}  // namespace blendbench
