#pragma once
// What a run produces, typed: per variant its identity, status, plan figures, metrics, health,
// timings and the comparison with the exact-stop variant; per run the scenario, the robot model
// and the servo. One serializer (to_json) writes summary.json; the runner returns these structs
// and the tests read them. Values are SI (m, s, rad) as in the stages; the JSON keys end in the
// units they are converted to (mm, s, deg, Hz, ...).

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "blendbench/app/ranking.hpp"
#include "blendbench/app/sensitivity.hpp"
#include "blendbench/io/scenario.hpp"
#include "blendbench/program/path.hpp"
#include "blendbench/report/report.hpp"
#include "blendbench/robot/singularity.hpp"
#include "blendbench/sim/metrics.hpp"
#include "blendbench/sim/servo.hpp"
#include "blendbench/sim/workspace.hpp"
#include "blendbench/timing/timing.hpp"

namespace blendbench {

// How a variant ended. Only kOk is clean tracking data: a saturated run or one outside the
// model's joint limits still carries its metrics, flagged; a run that did not settle has no
// cycle time; diverged and failed plans carry no metrics. kFailed: the variant could not run to
// the end (its path leaves the robot's reach or limits, its files cannot be written);
// kInterrupted: a stop request (SIGINT/SIGTERM) came before it finished.
enum class VariantStatus { kOk, kSaturated, kLimitExceeded, kNotSettled, kDiverged, kPlanningFailed, kFailed, kInterrupted };
std::string_view to_string(VariantStatus status);

// The plan of one variant.
struct PlanFigures {
  double path_length = 0;         // m
  double planned_cycle_time = 0;  // s
  double feed_share = 0;
  double path_deviation_max = 0;  // m: the largest deviation of the planned transitions and smoothed streams
  std::vector<CornerReport> corners;
  std::vector<CornerPlacement> placements;  // one per corner
  std::vector<CornerTiming> corner_times;   // one per corner, when the reference passes it
  nlohmann::json pieces = nlohmann::json::array();  // pieces_json
  LimitsMode limits = LimitsMode::kCartesian;        // the limits the plan holds
  double bound_cycle_time = 0;                       // s: the time-optimal bound (time_optimal.hpp)
  int moves_merged = 0;                              // collinear lines merged before blending (G64 Q)
  double merge_tolerance = 0;                        // m
  std::vector<Timing::CornerStep> corner_steps;      // one per corner (Timing::corner_steps)
  SmoothingReport smoothing;                         // what smoothing did (Path::smoothing)
  bool oriented = false;                             // the program sets tool orientations
  PlannerFigures planner;                            // the velocity planner and what it took
};

// Wall-clock figures of one variant (s) and the real-time factors of the simulation.
struct Timings {
  double planning = 0, inverse_kinematics = 0, simulation = 0, video = 0;
  double simulated = 0;  // s of simulated time
  [[nodiscard]] double real_time_factor() const { return simulation > 0 ? simulated / simulation : 0.0; }
  [[nodiscard]] double real_time_factor_with_video() const {
    return simulation + video > 0 ? simulated / (simulation + video) : 0.0;
  }
};

// A variant against the exact-stop variant of the run: cycle time saved (%) and the ratio of
// each error (this / the exact stop's; empty when the exact stop's is zero).
struct ExactStopComparison {
  std::string reference;  // name of the exact-stop variant
  std::optional<double> cycle_time_saved_percent;
  std::vector<std::pair<std::string, std::optional<double>>> ratios;  // key (ends in _ratio), value
};

// Where the TCP went that the model lets it go (it has no contacts): the zones and the report.
struct WorkspaceFigures {
  KeepOut zones;
  WorkspaceReport report;
};

// How much of the robot's joint-space limits a variant used, per joint: the peak velocity,
// acceleration and torque of the run over the model's limits (0 where a limit is infinite), and
// the smallest margin of the actual joint angles to the URDF's position range (rad; +inf for a
// continuous joint).
struct JointUsage {
  JointVector velocity_share = JointVector::Zero();
  JointVector acceleration_share = JointVector::Zero();
  JointVector torque_share = JointVector::Zero();
  JointVector position_margin = JointVector::Zero();
};

struct VariantSummary {
  std::string name;
  Method method = Method::kNone;  // the variant's transition method (or the first move's)
  double parameter = 0;           // m, the variant's transition parameter (0 when none)
  double tolerance = 0;           // m, the variant's transition tolerance (equal tolerance; 0 when none)
  TimingOptions::Baseline baseline = TimingOptions::Baseline::kNone;
  VariantStatus status = VariantStatus::kOk;
  std::string message;  // why the status is not ok
  std::string warning;  // non-fatal MuJoCo warnings
  PlanFigures plan;
  std::optional<Metrics> metrics;
  std::optional<Health> health;
  std::optional<WorkspaceFigures> workspace;  // with the metrics
  Timings timings;
  std::optional<ExactStopComparison> comparison;
  // where the joint reference passes near a singularity, and the IK branch changes it was
  // allowed to make (robot.allow_branch_change), in time order
  std::vector<SingularityPassage> singularities;
  std::vector<BranchChange> branch_changes;
  std::optional<JointUsage> joint_usage;  // with the metrics
};

// The arm that ran: its model, timestep and natural frequencies at the start pose.
struct RobotInfo {
  ArmModel model = ArmModel::kElastic;
  std::string mjcf;
  std::string urdf;
  IkMethod ik_method = IkMethod::kAuto;  // the solver the chain's geometry chose
  Eigen::Isometry3d tool = Eigen::Isometry3d::Identity();  // the TCP in the flange frame
  std::vector<JointSpec> joints;  // the chain's joints: names and URDF limits
  std::vector<std::string> notes;  // what was estimated or replaced (a model built from the URDF)
  double timestep = 0;  // s
  JointVector start_q = JointVector::Zero();  // rad, link angles at the program's start
  JointLimits limits;
  JointVector natural_frequency_per_joint = JointVector::Zero();  // Hz (zero when rigid)
  JointVector natural_frequency_arm = JointVector::Zero();        // Hz
};

struct RunSummary {
  std::string version;  // version_string() of the program that ran (version.hpp)
  std::string scenario, file, description;
  // the program frame in the robot base frame (a scenario's `frame`; for a G-code file the
  // placement of its part): plots and reports show corners in the program's own coordinates
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  std::vector<LoadWarning> warnings;  // the scenario's plausibility warnings (scenario.hpp)
  RobotInfo robot;
  ServoController controller = ServoController::kCascade;
  ServoConfig servo;  // as tuned at the start pose
  SimulationSettings simulation;
  std::vector<VariantSummary> variants;
  std::vector<std::string> notes;  // the driver's (RunInputs::notes)
  // the answer (ranking.hpp): summary.json's `ranking` and `recommendation`; none when the run
  // was interrupted
  std::optional<Ranking> ranking;
  // the perturbed models' runs and what they say of the nominal conclusions (`--sensitivity`,
  // sensitivity.hpp): summary.json's `sensitivity`; none without the flag or when interrupted
  std::optional<Sensitivity> sensitivity;
};

// The comparison block of every variant that has a cycle time against the first exact-stop
// variant (method none) that ran cleanly; nothing when there is none.
void compare_with_exact_stop(RunSummary& summary);

// The ranking of the run's variants (ranking.hpp) under `constraints`, at the resolution of its
// setpoint rate: each variant's cycle time, contour error against the program, and the larger
// of its residual vibration after the stop and after any corner.
Ranking rank_run(const RunSummary& summary, const Constraints& constraints, const OrderSpread& spread = {});

// The corners of a plan as corners.json holds them: corner_json with the placement and the
// times the reference passes the corner (t_start_s, t_end_s).
nlohmann::json corners_json(const PlanFigures& plan);

// The one serializer of run results (nlohmann's ADL hook): summary.json is to_json(RunSummary).
void to_json(nlohmann::json& out, const RunSummary& summary);
void to_json(nlohmann::json& out, const VariantSummary& variant);

}  // namespace blendbench
