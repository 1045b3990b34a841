#pragma once
// The drive of every joint: an industrial cascade on the motor side, as plain configuration.
// The simulator (simulator.hpp) runs it; tune_servo there derives its gains from the model.
//
// Two rates, as on a UR-class arm: the controller takes the reference at the setpoint rate
// (setpoint_rate_hz, 500 Hz by default like a UR's real-time interface) and computes there, per
// setpoint, the motor reference, the feed-forward torque and the gravity torque at the measured
// angles; the joint drives run the cascade at the servo rate (rate_hz, 2 kHz by default),
// interpolating the setpoints linearly (the controller prepares each setpoint one ahead, as the
// planned reference is known) and holding the gravity torque. Why not the cascade at 500 Hz:
// with one tick of measurement delay its loop delay is 4 ms, 90 degrees of phase at 62 Hz, so
// the velocity loop pumps energy into the arm's modes above that (the 67 Hz mode with the motors
// free, measured: the friction-free arm's oscillation grows); at 2 kHz that point is 250 Hz,
// above every mode the motors take part in (the 681 Hz wrist-3 mode barely moves its rotor).
//
// Per joint, once per servo tick (period T = 1 / rate_hz):
//   encoder          theta_m[k] = round(theta(t_k - d T) / q) q: the motor angle (joint side),
//                    d = measurement_delay_ticks old, quantised to q = 2 pi / counts per turn;
//   speed estimate   omega_m[k] = (theta_m[k] - theta_m[k-1]) / T (what drives do);
//   motor reference  theta_r = q_r + delta_r with delta_r = tau_g / K, tau_g the torque the gear
//                    must carry for the link reference (q_r, qd_r, qdd_r): the rigid-body
//                    inverse dynamics of the links (mj_rne), K the gear stiffness. This is the
//                    flatness-based feed-forward of an elastic joint (the link is where the
//                    reference says when the spring carries tau_g), to first order: the
//                    deflection's own acceleration is neglected. theta_r = q_r without
//                    deflection_compensation or on a rigid arm; thetad_r = qd_r + d(delta_r)/dt.
//   position P       omega_cmd = kp (theta_r - theta_m) [+ thetad_r: velocity feed-forward],
//                    with theta_r of d ticks ago and thetad_r of d + 1/2 ticks ago: the drive
//                    compares its measurements with the reference of the instant they describe
//                    (else the loop would make the delayed measurement follow the current
//                    reference and the arm run d ticks ahead of it, and the lag of the speed
//                    estimate would read as a speed error while accelerating);
//   velocity PI      e = omega_cmd - omega_m; tau_pi = kv e + I, I += ki e T (not integrated
//                    while the torque is saturated in the direction of e: anti-windup);
//   torque           tau = tau_pi [+ g(theta_m): gravity compensation, the gravity torque alone
//                    at the measured angles, mj_rne with zero velocity and acceleration, taken at
//                    each setpoint]
//                    [+ tau_ff: acceleration feed-forward, the inverse dynamics of the reference
//                    without gravity: link inertia and Coriolis terms (mj_rne at q_r, qd_r,
//                    qdd_r, minus g(q_r)), rotor inertia J_m qdd_r, and the motor-side friction
//                    b qd_r + F_c tanh(qd_r / kCoulombSmoothing)];
//   limit            |tau| <= the actuator's torque limit (saturated ticks are counted).
// The feed-forward terms use the current reference. They use the simulation's own model, i.e. a perfectly identified arm; what is
// left to the feedback is the servo's delay, the encoder, the elasticity and what the first-order
// deflection compensation leaves out.

#include <numbers>

#include "blendbench/robot/kinematics.hpp"

namespace blendbench {

// Velocity (rad/s) over which the Coulomb friction feed-forward tanh(v / s) reaches its full value.
inline constexpr double kCoulombSmoothing = 0.01;

struct ServoConfig {
  double rate_hz = 2000;             // 125 Hz .. 8 kHz; 1/rate_hz must be a multiple of the model timestep
  double setpoint_rate_hz = 500;     // 125 Hz .. rate_hz; the reference's rate; rate_hz a multiple of it
  int measurement_delay_ticks = 1;   // >= 0
  double encoder_counts_per_turn = 1638400;  // per turn of the joint: 2^14 counts per motor turn x ratio 100; 0 = exact
  JointVector kp = JointVector::Zero();  // 1/s: position loop gain, >= 0
  JointVector kv = JointVector::Zero();  // N*m*s/rad: velocity loop gain, >= 0
  JointVector ki = JointVector::Zero();  // N*m/rad: velocity loop integral gain, >= 0
  bool velocity_feedforward = true;
  bool acceleration_feedforward = true;
  bool gravity_compensation = true;
  bool deflection_compensation = true;  // no effect on a rigid arm
  // What tune_servo aimed the gains at (rad/s, 0 when set by hand), for reports.
  JointVector velocity_bandwidth = JointVector::Zero();
  JointVector position_bandwidth = JointVector::Zero();
};

// Named configurations: kCascade is the default above (every feed-forward on); kPd is the plain
// PD servo without feed-forward kept for comparison: tau = kv kp (theta_r - theta_m) +
// kv (thetad_r - omega_m) + g(theta_m), i.e. no integral action, no acceleration feed-forward
// and no deflection compensation (the velocity reference stays in the damping term, as a PD on
// the error has it).
enum class Controller { kCascade, kPd };

// `servo` switched to the named configuration (gains kept; kPd zeroes ki).
ServoConfig with_controller(ServoConfig servo, Controller controller);

// How tune_servo derives the gains per joint from the model at the start pose:
//   loop delay        T_d = (d + 1) T: d ticks of measurement delay, half a tick of the speed
//                     estimate's backward difference and half a tick of the torque hold;
//   velocity loop     omega_v = min(delay_phase / T_d, antiresonance_share * omega_a), omega_a
//                     = sqrt(K / I_link) the joint's antiresonance (its locked-motor frequency;
//                     infinite on a rigid arm): the delay costs delay_phase of phase margin at
//                     crossover, and below omega_a the motor still drives the whole joint
//                     inertia, so the loop stays clear of the two-mass resonance;
//                     kv = omega_v (J_m + I_link), the joint's inertia on the motor side;
//   integral          ki = kv omega_v integral_share (PI corner at integral_share omega_v);
//   position loop     kp = position_share omega_v.
struct ServoTuning {
  double rate_hz = 2000;
  double setpoint_rate_hz = 500;
  int measurement_delay_ticks = 1;
  double encoder_counts_per_turn = 1638400;
  double delay_phase = std::numbers::pi / 6;  // rad (30 deg)
  double antiresonance_share = 0.5;
  double integral_share = 0.25;
  double position_share = 0.25;
};

}  // namespace blendbench
