#pragma once
// The execution stage: a MuJoCo model of a six-joint arm, rigid or with elastic joints, driven
// by a cascaded servo per joint (servo.hpp) that tracks a joint reference, sampled at every
// setpoint into a Trace (trace.hpp).
//
// The model: six direct-torque <motor> actuators, each on a hinge joint (the motor hinge, angle
// theta: the encoder's angle); a model is elastic when each motor hinge's body carries a second
// hinge on the same axis after it (the gear, deflection delta, with a positive stiffness), so
// the link angle is theta + delta; otherwise rigid (link angle = theta). Joint vectors are in the
// order of the motor hinges' joint ids (the kinematic-chain order). Optional per-joint limits
// come from <custom><numeric name="velocity_limits"/"acceleration_limits" data="6 values"/>.
// Conventions: SI units (rad, rad/s, N*m, s, m); positions in the model's world frame.

#include <mujoco/mujoco.h>

#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "blendbench/robot/joint_trajectory.hpp"
#include "blendbench/robot/kinematics.hpp"
#include "blendbench/sim/servo.hpp"
#include "blendbench/sim/trace.hpp"

namespace blendbench {

// Changes to a model after it is compiled, before anything is derived from it (tests, and the
// perturbed models of a sensitivity study, issue 46): the arm the simulator then holds is the
// changed one, and everything the drive takes from the model (the tuning of tune_servo, the
// inverse-dynamics and friction feed-forward, gravity compensation) follows it, as a drive
// identified on that arm would; only the extra measurement delay is hidden from the drive.
//   stiffness_scale  the gears' stiffness (elastic models), the gear damping by its square root
//                    (the damping ratio kept);
//   inertia_scale    every moving link's mass and inertia tensor (the same mass distribution,
//                    heavier or lighter; gravity's torques scale with it), the gear damping by
//                    its square root (the damping ratio kept); not the rotor inertia (armature);
//   friction_scale   the motor hinges' viscous (damping) and Coulomb (frictionloss) friction;
//   extra_delay_ticks  servo ticks added to the measurement delay of every servo this simulator
//                    runs (run() adds them to ServoConfig::measurement_delay_ticks): the encoder's
//                    path slower than the drive was tuned for;
//   timestep         another physics timestep (0 keeps the model's);
//   fit_timestep     when the (changed) model's stiffest mode is too fast for the timestep
//                    (kMaxOmegaDt), the timestep divided by the smallest whole number that
//                    resolves it, instead of the refusal (a stiffer or lighter perturbed arm; the
//                    servo's period stays a whole number of steps).
// And, for an MJCF of the user's own (an arm in the style of MuJoCo Menagerie: its own actuators,
// no site "tcp"), what adapts it:
//   tcp_site / tcp_body  the tool centre point is this site, or this body's frame, instead of
//                    site "tcp" (at most one of them);
//   own_actuators_to_motors  each actuator that is not a direct-torque motor (a position servo
//                    with gain and bias, as Menagerie's arms have) becomes one on the same joint
//                    and gear, its force range kept as the torque limit (replaced_actuators()
//                    names them); one without a force range, or with activation dynamics, is
//                    refused naming it.
struct ModelChanges {
  double stiffness_scale = 1;  // > 0
  double timestep = 0;         // s; 0 keeps the model's
  double inertia_scale = 1;    // > 0
  double friction_scale = 1;   // >= 0
  int extra_delay_ticks = 0;   // >= 0
  bool fit_timestep = false;   // the timestep divided by the smallest whole number that resolves the stiffest mode
  std::string tcp_site{};
  std::string tcp_body{};
  bool own_actuators_to_motors = false;
};

// Natural frequencies of the arm at one configuration (Hz), from the mass matrix and the gear
// stiffness: per joint alone (its motor held and every other joint rigid: sqrt(K / I_link) / 2 pi),
// and the six modes of the whole arm with every motor held. Zero on a rigid arm.
struct NaturalFrequencies {
  JointVector per_joint = JointVector::Zero();
  JointVector arm = JointVector::Zero();  // ascending
  std::array<JointVector, 6> arm_shapes{};  // mode shapes (gear deflections), largest entry 1
};

struct RunOptions {
  double settle_time = 1.0;  // s simulated after the reference ends, holding its last position
                             // at zero velocity and acceleration
  double frame_rate = 0;     // Hz; when > 0, on_frame is called at this rate of simulated time
  // Called with the model, the data (kinematics current: poses describe the state at t) and t in
  // s, starting at t = 0; d.ctrl holds the control applied from t to the next physics step.
  std::function<void(const mjModel&, const mjData&, double t)> on_frame;
  // The tool centre point in the frame of site "tcp" (the flange when the model has no tool):
  // the trace's commanded and actual TCP positions and orientations are those of this point.
  Eigen::Isometry3d tool = Eigen::Isometry3d::Identity();
};

// The bound on omega_max * timestep the simulator accepts (omega_max: the model's highest mode
// with the motors free): semi-implicit Euler is stable up to 2 and oscillates at
// (2 / dt) asin(omega dt / 2), 1.5 % fast at 0.6.
inline constexpr double kMaxOmegaDt = 0.6;

class Simulator {
 public:
  // Loads an MJCF file. Throws InputError (file `mjcf_path`, field "mjcf") with MuJoCo's message
  // when it does not compile, or naming what is wrong when it is not a six-joint arm as above
  // with a site named "tcp", or when its timestep is too long for its stiffest mode
  // (kMaxOmegaDt; the message names the longest timestep that would do).
  explicit Simulator(const std::string& mjcf_path, const ModelChanges& changes = {});
  // The same from MJCF text (tests, the model built from a URDF), which may name no other file;
  // errors carry the file name `source`.
  static Simulator from_xml_string(const std::string& xml, const ModelChanges& changes = {},
                                   const std::string& source = "<string>");

  [[nodiscard]] const mjModel& model() const { return *model_; }
  [[nodiscard]] bool elastic() const { return gear_dof_[0] >= 0; }
  [[nodiscard]] double timestep() const { return model_->opt.timestep; }

  // Velocity, acceleration and torque limits. The torque limit is |gear| times the smaller of
  // the actuator's control range (ctrlrange, when ctrllimited) and force range (forcerange,
  // when forcelimited); +inf when neither is limited.
  [[nodiscard]] const JointLimits& limits() const { return limits_; }
  [[nodiscard]] JointVector torque_limits() const { return limits_.torque; }
  // The changes the model was loaded with.
  [[nodiscard]] const ModelChanges& changes() const { return changes_; }
  // The actuators own_actuators_to_motors turned into direct-torque motors (empty otherwise).
  [[nodiscard]] const std::vector<std::string>& replaced_actuators() const { return replaced_actuators_; }
  // The arm's kinematic chain as the model has it (for an MJCF without a URDF): the path of
  // bodies from the world to the TCP's body, each motor hinge a JointSpec (origin: the hinge's
  // frame at its anchor in the previous one's, axis in it, range, the model's velocity limit and
  // the motor's torque limit), bodies without joints folded in, the gear hinges (elastic
  // models: on the motor's axis) at zero deflection; tcp from the last hinge to the TCP. Throws
  // InputError (field "joint") when another joint lies on that path or the six hinges are not
  // all on it.
  [[nodiscard]] KinematicChain kinematic_chain() const;
  // Gear stiffness per joint (N*m/rad; +inf on a rigid arm).
  [[nodiscard]] JointVector stiffness() const { return stiffness_; }
  // Reflected rotor inertia per joint (the motor hinge's armature, kg*m^2).
  [[nodiscard]] JointVector motor_inertia() const { return motor_inertia_; }
  // Link-side inertia about each joint at link angles q with the other joints held (the mass
  // matrix diagonal without rotor inertia, kg*m^2).
  [[nodiscard]] JointVector link_inertia(const JointVector& q) const;
  // Gravity torque per joint at link angles q (N*m, the torque that holds the arm still).
  [[nodiscard]] JointVector gravity_torque(const JointVector& q) const;
  // Natural frequencies at link angles q (see NaturalFrequencies).
  [[nodiscard]] NaturalFrequencies natural_frequencies(const JointVector& q) const;

  // Runs the reference from rest at reference.q[0] (the motors at their first reference, the
  // gears deflected by the gravity load: the arm starts in equilibrium; non-arm degrees of
  // freedom at the model's qpos0). The reference's dt must be a positive multiple of the setpoint
  // period (a single sample may have dt = 0); between samples it is interpolated linearly, and
  // the drives interpolate linearly between setpoints. The trace holds one sample per setpoint,
  // t = k / setpoint_rate_hz, until the end of the reference plus options.settle_time. Each
  // physics step is mj_step1, the servo tick when one falls due, mj_step2. Throws InputError
  // (field "reference.*" or "servo.*") for a malformed reference or servo; a physically
  // unstable run is not an error but a Trace with diverged = true. Throws Interrupted
  // (core/interrupt.hpp) within ~1024 physics steps of a stop request (SIGINT/SIGTERM).
  [[nodiscard]] Trace run(const JointTrajectory& reference, const ServoConfig& servo, const RunOptions& options) const;

 private:
  // Takes ownership of `model`; `source` names it in errors.
  Simulator(mjModel* model, const std::string& source, const ModelChanges& changes);

  std::shared_ptr<const mjModel> model_;
  std::array<int, 6> motor_qpos_{};  // qpos address of motor hinge i
  std::array<int, 6> motor_dof_{};   // its dof address
  std::array<int, 6> gear_qpos_{};   // qpos address of gear hinge i (-1 when rigid)
  std::array<int, 6> gear_dof_{};    // its dof address (-1 when rigid)
  std::array<int, 6> actuator_{};    // actuator driving joint i
  std::array<double, 6> ctrl_per_torque_{};  // ctrl = tau * ctrl_per_torque (1 / (gear * gain))
  JointLimits limits_;
  JointVector stiffness_;
  JointVector motor_inertia_;
  JointVector viscous_;  // motor-side viscous friction (N*m*s/rad)
  JointVector coulomb_;  // motor-side Coulomb friction (N*m)
  int tcp_site_ = -1;  // the TCP: this site, or (when -1) body tcp_body_
  int tcp_body_ = -1;
  ModelChanges changes_;
  std::vector<std::string> replaced_actuators_;
  std::string source_;
};

// The servo of `tuning` with gains derived from the model at link angles q (ServoTuning states
// the rule), every feed-forward on (Controller::kCascade). Throws InputError (field "servo.*")
// for a rate outside 125 Hz .. 8 kHz or a negative delay.
ServoConfig tune_servo(const Simulator& sim, const JointVector& q, const ServoTuning& tuning = {});

// Makes MuJoCo's error handler throw std::runtime_error and its warning handler record instead
// of printing (MuJoCo's defaults print "Press Enter", write MUJOCO_LOG.TXT and exit). Idempotent;
// called by Simulator and the renderer.
void install_mujoco_handlers();

// The MuJoCo warnings recorded on this thread since the last call ("; "-separated), then clears
// them. Tests use it to turn any MuJoCo warning into a failure.
std::string take_mujoco_warnings();

}  // namespace blendbench
