#pragma once
// Metrics and health of one simulated run (per variant). Inputs are plain values (trace.hpp);
// no MuJoCo. Lengths in m, angles in rad, times in s; the summary converts to the units its
// keys name.

#include <array>
#include <optional>
#include <vector>

#include "blendbench/program/path.hpp"
#include "blendbench/program/program.hpp"
#include "blendbench/robot/joint_trajectory.hpp"
#include "blendbench/sim/trace.hpp"

namespace blendbench {

// When each corner is passed on the reference (s): the transition's start and end, or for an
// exact stop the instant the reference stops there (start = end).
struct CornerTiming {
  int index = 0;
  double t_start = 0;
  double t_end = 0;
};

struct MetricsOptions {
  Vec3 end_point = Vec3::Zero();         // programmed end point (m, world)
  // settled: within the position tolerance of the end point and below the speed tolerance for
  // the whole settle window. 0.03 mm is a UR-class repeatability; 1 mm/s is a standstill the
  // position tolerance cannot tell from drift within the window.
  double settle_tolerance = 0.03e-3;     // m
  double settle_speed_tolerance = 1e-3;  // m/s
  double settle_window = 0.2;            // s: at least four periods of the arm's first mode (~21 Hz)
  // residual vibration: the tracking error vector (actual - commanded TCP) high-passed at
  // vibration_highpass (zero phase, 2nd-order Butterworth forward and backward), its largest
  // peak-to-peak over the three axes in a window of vibration_window after the final stop and
  // after each corner (clipped at the next corner's start), and the dominant frequency there.
  // 12 Hz passes 90 % of the arm's first mode (21 Hz) and 3 % of the servo's position loops
  // (3-5 Hz), whose slow settling is not vibration; 0.5 s holds ten periods of the first mode.
  double vibration_window = 0.5;         // s
  double vibration_highpass = 12;        // Hz
  // the actual TCP is low-passed at jerk_lowpass (zero phase, as above) before its jerk is
  // taken: the arm's modes up to there count, the encoder's and integrator's noise does not
  double jerk_lowpass = 50;              // Hz
  std::vector<CornerTiming> corners;
  // the planned arc length of the reference (m, on `path`) at each trace sample, its end after
  // the reference has ended; empty: no process metrics (execute() fills it from the timing)
  std::vector<double> reference_s;
};

// Process figures for gluing and welding, measured on the actual TCP (what lays the bead) over
// the process window: the stretch of the planned path between the first and the last
// programmed move, from where the first move's own piece ends to where the last move's own
// piece begins, so the run-up and the final stop do not count (a corner between two moves
// alone: the transition, or for an exact stop the corner point).
//   share_below_90pct_speed  the share of the actual TCP's path length over the window (0..1)
//                            travelled slower than 90 % of the programmed speed of the piece the
//                            reference is on (a transition's: its junction velocity);
//   min_speed                the actual TCP's lowest speed there (m/s, central differences on the
//                            setpoint grid, as Metrics::tcp_speed).
struct ProcessMetrics {
  double share_below_90pct_speed = 0;
  double min_speed = 0;            // m/s
  double s_start = 0, s_end = 0;   // m: the window on the planned path
};

// The process figures of a sampled run: the actual TCP (m) and its speed (m/s) per sample, the
// reference's planned arc length (m) per sample, and the planned path. Empty when the path
// comes from a single move (no window), when the inputs are empty or differ in length.
std::optional<ProcessMetrics> process_metrics(const std::vector<Vec3>& actual, const std::vector<double>& speed,
                                              const std::vector<double>& reference_s, const Path& path);

// Residual vibration in one window.
struct Vibration {
  double t_start = 0, t_end = 0;  // s
  double peak_to_peak = 0;        // m
  double frequency = 0;           // Hz, dominant; 0 when the window is too short
};

struct Metrics {
  // first instant after the reference has ended from which the TCP stays settled for the settle
  // window; empty when it does not within the simulated time
  std::optional<double> cycle_time;
  // over the motion only (the reference running: t <= reference end)
  double tracking_error_max = 0;     // m: |actual TCP - commanded TCP| at the same instant
  double tracking_error_rms = 0;     // m
  double orientation_error_max = 0;  // rad: rotation angle between actual and commanded TCP
  double orientation_error_rms = 0;  // rad
  // rad/s: the tool's peak angular velocity, actual and commanded (central differences of the
  // orientation on the setpoint grid)
  double angular_velocity_peak = 0, angular_velocity_commanded_peak = 0;
  // over the whole run: actual TCP to the closest point of the programmed path (the designed
  // deviation plus the servo's error) and of the planned (blended) path (the servo's own)
  double contour_error_programmed_max = 0;  // m
  double contour_error_planned_max = 0;     // m
  // TCP jerk over the motion, m/s^3: the actual TCP low-passed (jerk_lowpass), the commanded
  // TCP as it is; central third differences on the servo grid
  double jerk_actual_peak = 0, jerk_actual_rms = 0;
  double jerk_commanded_peak = 0, jerk_commanded_rms = 0;
  Vibration vibration_final;
  std::vector<Vibration> vibration_corners;  // one per options.corners entry
  std::optional<ProcessMetrics> process;     // empty without options.reference_s or with one move
  // per joint: the drive's following error (TraceSample::following_error, rad) over the
  // motion; motor torque peak and RMS (N*m) and energy integral |tau * motor speed| dt (J) over
  // the run; actual link velocity (rad/s) and acceleration (rad/s^2, differences) peaks
  JointVector following_error_max = JointVector::Zero(), following_error_rms = JointVector::Zero();
  JointVector torque_peak = JointVector::Zero(), torque_rms = JointVector::Zero();
  JointVector energy = JointVector::Zero();
  JointVector velocity_peak = JointVector::Zero(), acceleration_peak = JointVector::Zero();
  // per trace sample, for trace.csv and plots
  std::vector<double> tracking_error;            // m
  std::vector<double> orientation_error;         // rad
  std::vector<double> contour_error_programmed;  // m
  std::vector<double> contour_error_planned;     // m
  std::vector<Vec3> vibration;                   // m: the high-passed tracking error vector
  std::vector<double> tcp_speed;                 // m/s, actual
  std::vector<double> jerk_actual;               // m/s^3, |filtered jerk| of the actual TCP
};

// Computes the metrics of a run that did not diverge (asserted: a diverged trace is not
// tracking data). `program` is the programmed path, `path` the blended one.
Metrics compute_metrics(const Trace& trace, const Program& program, const Path& path, const MetricsOptions& options);

// The first sample at which a joint exceeds its limit: when (s), which joint, value and limit.
struct LimitCheck {
  bool exceeded = false;
  double t = 0;
  int joint = -1;
  double value = 0;
  double limit = 0;
};

// Whether the run's data is clean tracking data: torque saturation per joint (ticks and share
// of the servo ticks the drive ran, at most 1), and the model's joint velocity and acceleration limits checked on the
// reference and on the actual link motion (accelerations of the actual motion by differences of
// the link velocity on the servo grid).
struct Health {
  std::array<long, 6> saturated_ticks{};
  JointVector saturated_share = JointVector::Zero();
  bool saturated = false;
  LimitCheck reference_velocity, reference_acceleration, actual_velocity, actual_acceleration;
  [[nodiscard]] bool limits_exceeded() const {
    return reference_velocity.exceeded || reference_acceleration.exceeded || actual_velocity.exceeded ||
           actual_acceleration.exceeded;
  }
};

Health check_health(const Trace& trace, const JointTrajectory& reference, const JointLimits& limits);

}  // namespace blendbench
