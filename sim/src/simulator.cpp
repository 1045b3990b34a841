#include "blendbench/sim/simulator.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <mutex>
#include <regex>
#include <stdexcept>

#include "blendbench/core/format.hpp"
#include "blendbench/core/input_error.hpp"
#include "blendbench/core/interrupt.hpp"

namespace blendbench {
namespace {

thread_local std::string g_warnings;

void throw_on_mujoco_error(const char* message) { throw std::runtime_error(std::string("MuJoCo error: ") + message); }

// Recorded warnings are capped so a warning raised at every step cannot grow without bound.
constexpr std::size_t kMaxWarningText = 4096;

void record_mujoco_warning(const char* message) {
  if (g_warnings.size() >= kMaxWarningText) return;
  if (!g_warnings.empty()) g_warnings += "; ";
  g_warnings += message;
}

struct DataDeleter {
  void operator()(mjData* d) const { mj_deleteData(d); }
};
using DataPtr = std::unique_ptr<mjData, DataDeleter>;

DataPtr make_data(const mjModel& m) {
  install_mujoco_handlers();
  return DataPtr(mj_makeData(&m));
}

// A joint speed no arm reaches; beyond it the integration has blown up long before MuJoCo's own
// 1e10 check fires, so the run is stopped there.
constexpr double kMaxJointSpeed = 1e3;  // rad/s

// Relative tolerance for "dt is a multiple of the period".
constexpr double kMultipleTolerance = 1e-9;

std::string object_name(const mjModel& m, int type, int id) {
  const char* name = mj_id2name(&m, type, id);
  std::string out = name != nullptr && name[0] != '\0' ? "'" : "#";
  out += name != nullptr && name[0] != '\0' ? std::string(name) + "'" : std::to_string(id);
  return out;
}

// MuJoCo's multi-line compiler message on one line, and the XML line it names (0 if none).
std::pair<std::string, int> tidy_mujoco_message(std::string message) {
  std::replace(message.begin(), message.end(), '\n', ' ');
  while (!message.empty() && message.back() == ' ') message.pop_back();
  int line = 0;
  std::smatch match;
  if (std::regex_search(message, match, std::regex(R"(line\s*=?\s*(\d+))"))) line = std::stoi(match[1].str());
  return {message, line};
}

// n if x == n * period for an integer n >= 1 (relative tolerance), else 0.
long multiple_of(double x, double period) {
  if (!(x > 0) || !std::isfinite(x)) return 0;
  const double n = std::round(x / period);
  if (n < 1 || std::abs(n * period - x) > kMultipleTolerance * x) return 0;
  return static_cast<long>(n);
}

[[noreturn]] void bad_input(const std::string& field, const std::string& message) {
  throw InputError("", 0, 0, field, message);
}

void check_finite(const std::vector<JointVector>& v, const std::string& field) {
  for (std::size_t k = 0; k < v.size(); ++k)
    if (!v[k].allFinite()) bad_input(field, "sample " + std::to_string(k) + " is not finite");
}

// The first unhealthy-state warning MuJoCo raised in d (it resets the state silently when it
// raises one of these), as text; empty when the state is healthy.
std::string unhealthy_state(const mjData& d) {
  for (const int w : {mjWARN_BADQPOS, mjWARN_BADQVEL, mjWARN_BADQACC, mjWARN_BADCTRL, mjWARN_INERTIA}) {
    if (d.warning[w].number > 0) return mju_warningText(w, d.warning[w].lastinfo);
  }
  return {};
}

}  // namespace

void install_mujoco_handlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    mju_user_error = throw_on_mujoco_error;
    mju_user_warning = record_mujoco_warning;
  });
}

std::string take_mujoco_warnings() {
  std::string out;
  out.swap(g_warnings);
  return out;
}

Simulator::Simulator(const std::string& mjcf_path) : Simulator(nullptr, mjcf_path) {}

Simulator Simulator::from_xml_string(const std::string& xml) {
  install_mujoco_handlers();
  // MuJoCo 2.2.2 loads text only through its virtual file system
  const auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  const char* name = "model.xml";
  if (mj_makeEmptyFileVFS(vfs.get(), name, static_cast<int>(xml.size())) != 0) {
    mj_deleteVFS(vfs.get());
    throw InputError("<string>", 0, 0, "mjcf", "cannot place the model text in MuJoCo's virtual file system");
  }
  std::memcpy(vfs->filedata[mj_findFileVFS(vfs.get(), name)], xml.data(), xml.size());
  char error[1024] = "";
  mjModel* model = mj_loadXML(name, vfs.get(), error, sizeof error);
  mj_deleteVFS(vfs.get());
  if (model == nullptr) {
    const auto [message, line] = tidy_mujoco_message(error);
    throw InputError("<string>", line, 0, "mjcf", message);
  }
  return Simulator(model, "<string>");
}

Simulator::Simulator(mjModel* model, const std::string& source) {
  install_mujoco_handlers();
  // load from the file when not given a compiled model
  if (model == nullptr) {
    char error[1024] = "";
    model = mj_loadXML(source.c_str(), nullptr, error, sizeof error);
    if (model == nullptr) {
      const auto [message, line] = tidy_mujoco_message(error);
      throw InputError(source, line, 0, "mjcf", message);
    }
  }
  model_ = std::shared_ptr<const mjModel>(model, [](const mjModel* m) { mj_deleteModel(const_cast<mjModel*>(m)); });
  const mjModel& m = *model_;
  const auto fail = [&](const std::string& field, const std::string& message) {
    throw InputError(source, 0, 0, field, message);
  };

  // six actuators, each a direct-torque motor on its own hinge joint
  if (m.nu != 6) fail("actuator", "expected 6 actuators (one per arm joint), found " + std::to_string(m.nu));
  std::array<std::pair<int, int>, 6> joint_actuator{};  // (joint id, actuator id)
  for (int a = 0; a < 6; ++a) {
    const std::string name = "actuator " + object_name(m, mjOBJ_ACTUATOR, a);
    if (m.actuator_trntype[a] != mjTRN_JOINT) fail("actuator", name + " must act on a joint");
    const int j = m.actuator_trnid[2 * a];
    if (m.jnt_type[j] != mjJNT_HINGE) fail("actuator", name + " must drive a hinge joint");
    if (m.actuator_dyntype[a] != mjDYN_NONE || m.actuator_gaintype[a] != mjGAIN_FIXED ||
        m.actuator_biastype[a] != mjBIAS_NONE)
      fail("actuator", name + " must be a direct-torque <motor>");
    const double gain = m.actuator_gear[6 * a] * m.actuator_gainprm[mjNGAIN * a];
    if (gain == 0 || !std::isfinite(gain)) fail("actuator", name + " has zero gear or gain");
    joint_actuator[static_cast<std::size_t>(a)] = {j, a};
  }
  std::sort(joint_actuator.begin(), joint_actuator.end());
  for (std::size_t i = 1; i < 6; ++i)
    if (joint_actuator[i].first == joint_actuator[i - 1].first)
      fail("actuator", "joint " + object_name(m, mjOBJ_JOINT, joint_actuator[i].first) + " is driven twice");

  // per arm joint: addresses, control scale and torque limit
  for (std::size_t i = 0; i < 6; ++i) {
    const auto [j, a] = joint_actuator[i];
    qpos_adr_[i] = m.jnt_qposadr[j];
    dof_adr_[i] = m.jnt_dofadr[j];
    actuator_[i] = a;
    const double gear = m.actuator_gear[6 * a];
    const double gain = m.actuator_gainprm[mjNGAIN * a];
    ctrl_per_torque_[i] = 1.0 / (gear * gain);
    double force = std::numeric_limits<double>::infinity();  // actuator force limit
    if (m.actuator_ctrllimited[a])
      force = std::min(std::abs(m.actuator_ctrlrange[2 * a]), std::abs(m.actuator_ctrlrange[2 * a + 1])) * std::abs(gain);
    if (m.actuator_forcelimited[a])
      force = std::min({force, std::abs(m.actuator_forcerange[2 * a]), std::abs(m.actuator_forcerange[2 * a + 1])});
    torque_limit_[static_cast<Eigen::Index>(i)] = std::abs(gear) * force;
  }

  // the tool centre point
  tcp_site_ = mj_name2id(&m, mjOBJ_SITE, "tcp");
  if (tcp_site_ < 0) fail("site", "the model has no site named 'tcp'");
}

JointVector Simulator::inertia_diagonal(const JointVector& q) const {
  const mjModel& m = *model_;
  const DataPtr d = make_data(m);
  for (int i = 0; i < 6; ++i) d->qpos[qpos_adr_[static_cast<std::size_t>(i)]] = q[i];
  mj_forward(&m, d.get());
  JointVector diagonal;
  for (int i = 0; i < 6; ++i) diagonal[i] = d->qM[m.dof_Madr[dof_adr_[static_cast<std::size_t>(i)]]];
  return diagonal;
}

Trace Simulator::run(const JointReference& reference, const ServoConfig& servo, const RunOptions& options) const {
  const mjModel& m = *model_;
  const double h = m.opt.timestep;

  // validate the servo: its period is a whole number of physics steps
  if (!(servo.rate_hz > 0) || !std::isfinite(servo.rate_hz)) bad_input("servo.rate_hz", "must be positive");
  const long steps_per_tick = multiple_of(1.0 / servo.rate_hz, h);
  if (steps_per_tick == 0)
    bad_input("servo.rate_hz", "the servo period 1/" + format_value(servo.rate_hz) +
                                   " s is not a multiple of the model timestep " + format_value(h) + " s");
  const double period = static_cast<double>(steps_per_tick) * h;
  if (!servo.kp.allFinite() || (servo.kp.array() < 0).any()) bad_input("servo.kp", "must be finite and >= 0");
  if (!servo.kd.allFinite() || (servo.kd.array() < 0).any()) bad_input("servo.kd", "must be finite and >= 0");

  // validate the reference
  const std::size_t n = reference.q.size();
  if (n == 0) bad_input("reference.q", "is empty");
  if (!reference.qd.empty() && reference.qd.size() != n) bad_input("reference.qd", "must be empty or as long as q");
  if (!reference.qdd.empty() && reference.qdd.size() != n) bad_input("reference.qdd", "must be empty or as long as q");
  check_finite(reference.q, "reference.q");
  check_finite(reference.qd, "reference.qd");
  check_finite(reference.qdd, "reference.qdd");
  long ticks_per_sample = 1;
  if (n > 1) {
    ticks_per_sample = multiple_of(reference.dt, period);
    if (ticks_per_sample == 0)
      bad_input("reference.dt", format_value(reference.dt) + " s is not a positive multiple of the servo period " +
                                    format_value(period) + " s");
  }
  if (!(options.settle_time >= 0) || !std::isfinite(options.settle_time)) bad_input("settle_time", "must be >= 0");
  if (!(options.frame_rate >= 0) || !std::isfinite(options.frame_rate)) bad_input("frame_rate", "must be >= 0");

  const long last_reference_tick = static_cast<long>(n - 1) * ticks_per_sample;
  const long last_tick = last_reference_tick + std::lround(options.settle_time / period);
  const long last_step = last_tick * steps_per_tick;

  // start at rest at q[0]; the scratch data evaluates the commanded joints
  const DataPtr d = make_data(m);
  const DataPtr scratch = make_data(m);
  for (std::size_t i = 0; i < 6; ++i) d->qpos[qpos_adr_[i]] = reference.q[0][static_cast<Eigen::Index>(i)];
  mj_forward(&m, d.get());

  Trace trace;
  trace.samples.reserve(static_cast<std::size_t>(last_tick + 1));
  const bool frames = options.frame_rate > 0 && options.on_frame;
  long next_frame = 0;
  JointVector tau = JointVector::Zero();

  for (long step = 0; step <= last_step; ++step) {
    const double t_step = static_cast<double>(step) * h;
    // a stop request (SIGINT/SIGTERM) unwinds from here, every ~1 s of simulated time at 1 ms
    if (step % 1024 == 0) throw_if_stop_requested();

    // position and velocity stages: poses and bias forces now describe the state at t_step
    mj_step1(&m, d.get());
    if (std::string why = unhealthy_state(*d); !why.empty()) {
      trace.diverged = true;
      trace.warning = why + " (t = " + format_value(t_step) + " s)";
      break;
    }

    if (step % steps_per_tick == 0) {
      const long tick = step / steps_per_tick;
      const double t = static_cast<double>(tick) * period;

      // the reference at this tick: linear between samples, then the last position at rest
      JointVector q_cmd, qd_cmd, qdd_cmd;
      if (tick < last_reference_tick) {
        const auto k = static_cast<std::size_t>(tick / ticks_per_sample);
        const double u = static_cast<double>(tick % ticks_per_sample) / static_cast<double>(ticks_per_sample);
        const auto lerp = [&](const std::vector<JointVector>& v) -> JointVector {
          return v.empty() ? JointVector::Zero() : JointVector((1 - u) * v[k] + u * v[k + 1]);
        };
        q_cmd = lerp(reference.q);
        qd_cmd = lerp(reference.qd);
        qdd_cmd = lerp(reference.qdd);
      } else {
        q_cmd = reference.q[n - 1];
        const bool at_last = tick == last_reference_tick;
        qd_cmd = at_last && !reference.qd.empty() ? reference.qd[n - 1] : JointVector::Zero();
        qdd_cmd = at_last && !reference.qdd.empty() ? reference.qdd[n - 1] : JointVector::Zero();
      }

      // the measured state
      JointVector q, qd;
      for (std::size_t i = 0; i < 6; ++i) {
        q[static_cast<Eigen::Index>(i)] = d->qpos[qpos_adr_[i]];
        qd[static_cast<Eigen::Index>(i)] = d->qvel[dof_adr_[i]];
      }
      if (!q.allFinite() || !qd.allFinite() || qd.cwiseAbs().maxCoeff() > kMaxJointSpeed) {
        trace.diverged = true;
        trace.warning = "joint speed beyond " + format_value(kMaxJointSpeed) +
                        " rad/s: the simulation is unstable (t = " + format_value(t) + " s)";
        break;
      }

      // the commanded joints on the scratch data: TCP, and inverse dynamics when fed forward
      for (std::size_t i = 0; i < 6; ++i) {
        const auto ii = static_cast<Eigen::Index>(i);
        scratch->qpos[qpos_adr_[i]] = q_cmd[ii];
        scratch->qvel[dof_adr_[i]] = qd_cmd[ii];
        scratch->qacc[dof_adr_[i]] = qdd_cmd[ii];
      }
      if (servo.feedforward) {
        mj_inverse(&m, scratch.get());
      } else {
        mj_kinematics(&m, scratch.get());
      }

      // PD + model terms, then saturation
      tau = servo.kp.cwiseProduct(q_cmd - q) + servo.kd.cwiseProduct(qd_cmd - qd);
      for (std::size_t i = 0; i < 6; ++i) {
        const auto ii = static_cast<Eigen::Index>(i);
        const int dof = dof_adr_[i];
        if (servo.gravity_compensation) tau[ii] += d->qfrc_bias[dof];
        if (servo.feedforward)
          tau[ii] += scratch->qfrc_inverse[dof] - (servo.gravity_compensation ? scratch->qfrc_bias[dof] : 0.0);
        if (std::abs(tau[ii]) > torque_limit_[ii]) {
          trace.torque_saturated = true;
          tau[ii] = std::clamp(tau[ii], -torque_limit_[ii], torque_limit_[ii]);
        }
        d->ctrl[actuator_[i]] = tau[ii] * ctrl_per_torque_[i];
      }
      if (!tau.allFinite()) {
        trace.diverged = true;
        trace.warning = "non-finite servo torque (t = " + format_value(t) + " s)";
        break;
      }
      trace.peak_abs_tau = trace.peak_abs_tau.cwiseMax(tau.cwiseAbs());

      // record the tick
      TraceSample& sample = trace.samples.emplace_back();
      sample.t = t;
      sample.q_cmd = q_cmd;
      sample.qd_cmd = qd_cmd;
      sample.q = q;
      sample.qd = qd;
      sample.tau = tau;
      sample.tcp = Eigen::Vector3d(d->site_xpos + 3 * tcp_site_);
      sample.tcp_cmd = Eigen::Vector3d(scratch->site_xpos + 3 * tcp_site_);
    }

    // frames at the requested rate of simulated time (at most one per physics step)
    if (frames && t_step >= static_cast<double>(next_frame) / options.frame_rate - 0.5 * h) {
      options.on_frame(m, *d, t_step);
      next_frame = static_cast<long>(std::floor(t_step * options.frame_rate + 0.5)) + 1;
    }

    // acceleration and integration with the held control
    if (step == last_step) break;
    mj_step2(&m, d.get());
    if (std::string why = unhealthy_state(*d); !why.empty()) {
      trace.diverged = true;
      trace.warning = why + " (t = " + format_value(t_step) + " s)";
      break;
    }
  }

  // non-fatal capacity warnings
  for (const int w : {mjWARN_CONTACTFULL, mjWARN_CNSTRFULL}) {
    if (d->warning[w].number > 0) {
      if (!trace.warning.empty()) trace.warning += "; ";
      trace.warning += mju_warningText(w, d->warning[w].lastinfo);
    }
  }
  return trace;
}

ServoConfig default_servo(const Simulator& sim, const JointVector& q, double rate_hz, const JointVector& kp,
                          double zeta) {
  assert(rate_hz > 0 && zeta >= 0);
  const JointVector inertia = sim.inertia_diagonal(q);
  const double omega_max = kMaxOmegaT * rate_hz;  // rad/s
  ServoConfig servo;
  servo.rate_hz = rate_hz;
  for (int i = 0; i < 6; ++i) {
    servo.kp[i] = std::min(kp[i], omega_max * omega_max * inertia[i]);
    servo.kd[i] = 2 * zeta * std::sqrt(servo.kp[i] * inertia[i]);
  }
  return servo;
}

}  // namespace blendbench
