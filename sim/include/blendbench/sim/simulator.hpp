#pragma once
// The execution stage: a MuJoCo model of a six-joint arm driven by PD servos that track a joint
// reference, sampled at every servo tick into a Trace (DESIGN: joint reference -> Trace).
//
// Conventions: SI units (rad, rad/s, N·m, s, m); positions in the world frame of the model.
// The arm's joints are the six hinge joints driven by the model's six actuators, in the order
// of their joint ids in the model (the kinematic-chain order); every JointVector uses it.

#include <mujoco/mujoco.h>

#include <Eigen/Core>
#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace blendbench {

// Joint-space vector of the six arm joints (rad, rad/s, rad/s², N·m, gains per joint).
using JointVector = Eigen::Matrix<double, 6, 1>;

// PD servo with optional model-based terms; per joint
//   tau = kp (q_cmd - q) + kd (qd_cmd - qd) [+ c(q, qd)] [+ feed-forward],
// then clamped to the actuator torque limits. c is MuJoCo's bias force qfrc_bias (gravity,
// Coriolis, centrifugal) at the actual state. The feed-forward is the inverse dynamics of the
// reference (mj_inverse at q_cmd, qd_cmd, qdd_cmd); when gravity compensation is also on, its
// bias part is left out so the bias is counted once, at the actual state. The default gains are
// zero: start from default_servo() below.
struct ServoConfig {
  double rate_hz = 1000;  // controller rate; the physics runs at the model timestep and the torque
                          // is held between servo ticks. 1/rate_hz must be a multiple of it.
  JointVector kp = JointVector::Zero();  // N·m/rad, >= 0
  JointVector kd = JointVector::Zero();  // N·m·s/rad, >= 0
  bool gravity_compensation = true;
  bool feedforward = false;
};

// Joint reference: sample k holds the commanded joint state at t = k * dt. q must be non-empty;
// qd and qdd are either empty (treated as zero) or as long as q. dt must be a positive multiple
// of the servo period (a single-sample reference may have dt = 0). Between samples the servo
// interpolates linearly.
struct JointReference {
  double dt = 0;  // s
  std::vector<JointVector> q, qd, qdd;  // rad, rad/s, rad/s²
};

// The state at one servo tick. q/qd are the measured joint state at time t; tau is the joint
// torque applied from t to the next tick, after saturation; tcp and tcp_cmd are the world
// positions of the model's `tcp` site for the actual and for the commanded joints.
struct TraceSample {
  double t = 0;  // s
  JointVector q_cmd, qd_cmd, q, qd, tau;
  Eigen::Vector3d tcp_cmd, tcp;  // m
};

// One sample per servo tick, t = k / rate_hz, from 0 to the end of the reference plus the settle
// time. A diverged run stops at the first unhealthy step: `diverged` is set, `warning` says why,
// and `samples` holds only the (finite) ticks before it — they are for diagnosis, never for
// tracking metrics. `warning` may also carry non-fatal MuJoCo warnings (e.g. contact buffer full)
// on a run that did not diverge.
struct Trace {
  std::vector<TraceSample> samples;
  bool diverged = false;
  std::string warning;
  JointVector peak_abs_tau = JointVector::Zero();  // N·m, max over the samples of |tau|
  bool torque_saturated = false;  // some commanded torque exceeded its limit and was clamped
};

struct RunOptions {
  double settle_time = 1.0;  // s simulated after the reference ends, holding its last position
                             // at zero velocity and acceleration
  double frame_rate = 0;     // Hz; when > 0, on_frame is called at this rate of simulated time
  // Called with the model, the data (kinematics current: poses describe the state at t) and t in
  // s, starting at t = 0; d.ctrl holds the control applied from t to the next physics step.
  std::function<void(const mjModel&, const mjData&, double t)> on_frame;
};

class Simulator {
 public:
  // Loads an MJCF file. Throws InputError (file `mjcf_path`, field "mjcf") with MuJoCo's message
  // when it does not compile, or naming what is missing when it is not a six-joint arm driven by
  // six direct-torque <motor> actuators with a site named "tcp".
  explicit Simulator(const std::string& mjcf_path);
  // The same from MJCF text (tests); errors carry the file name "<string>".
  static Simulator from_xml_string(const std::string& xml);

  [[nodiscard]] const mjModel& model() const { return *model_; }

  // Joint torque limit per joint (N·m): |gear| times the smaller of the actuator's control range
  // (ctrlrange, when ctrllimited) and force range (forcerange, when forcelimited); +inf when
  // neither is limited.
  [[nodiscard]] JointVector torque_limits() const { return torque_limit_; }

  // Joint-space inertia diagonal (kg·m², armature included) at the configuration q.
  [[nodiscard]] JointVector inertia_diagonal(const JointVector& q) const;

  // Runs the reference from rest at reference.q[0] (non-arm degrees of freedom at the model's
  // qpos0). Each physics step is mj_step1, the servo tick when one falls due, mj_step2 — MuJoCo's
  // split for control between stages; it integrates with Euler or implicit as the model says
  // (an RK4 model is integrated with Euler). Throws InputError (field "reference.*" or "servo.*") for a malformed reference or
  // servo; a physically unstable run is not an error but a Trace with diverged = true. Throws
  // Interrupted (core/interrupt.hpp) within ~1024 steps of a stop request (SIGINT/SIGTERM).
  [[nodiscard]] Trace run(const JointReference& reference, const ServoConfig& servo,
                          const RunOptions& options) const;

 private:
  // Takes ownership of `model`; `source` names it in errors.
  Simulator(mjModel* model, const std::string& source);

  std::shared_ptr<const mjModel> model_;
  std::array<int, 6> qpos_adr_{};   // qpos address of arm joint i
  std::array<int, 6> dof_adr_{};    // qvel/qfrc address of arm joint i
  std::array<int, 6> actuator_{};   // actuator driving arm joint i
  std::array<double, 6> ctrl_per_torque_{};  // ctrl = tau * ctrl_per_torque (1 / (gear * gain))
  JointVector torque_limit_;
  int tcp_site_ = -1;
};

// Default PD gains for a UR5e-like arm (N·m/rad), shoulder to wrist.
inline JointVector default_kp() {
  JointVector kp;
  kp << 4000, 4000, 3000, 500, 500, 300;
  return kp;
}

// A servo that is stable at `rate_hz` on this model near configuration q: kp from `kp` (default
// default_kp()), lowered on a joint whose natural frequency sqrt(kp / I) would exceed
// kMaxOmegaT · rate_hz, and kd for the damping ratio `zeta` w.r.t. I, the joint-space inertia
// diagonal at q. Gravity compensation on, feed-forward off.
ServoConfig default_servo(const Simulator& sim, const JointVector& q, double rate_hz = 1000,
                          const JointVector& kp = default_kp(), double zeta = 1.0);

// Bound on omega_n · T_servo used by default_servo. The discrete PD loop on a double integrator
// (semi-implicit Euler, torque held for T) with critical damping is stable up to omega_n T ≈ 0.83
// (derived: with a = kp T²/I, b = kd T/I the Jury conditions give b < 2 and a + 2b < 4); 0.25
// keeps the discrete damping close to the continuous one.
inline constexpr double kMaxOmegaT = 0.25;

// Makes MuJoCo's error handler throw std::runtime_error and its warning handler record instead
// of printing (MuJoCo's defaults print "Press Enter", write MUJOCO_LOG.TXT and exit). Idempotent;
// called by Simulator and the renderer.
void install_mujoco_handlers();

// The MuJoCo warnings recorded on this thread since the last call ("; "-separated), then clears
// them. Tests use it to turn any MuJoCo warning into a failure.
std::string take_mujoco_warnings();

}  // namespace blendbench
