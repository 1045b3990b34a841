// The simulator: loading the MuJoCo model and checking it, the model's analyses at a pose (link
// inertia, gravity torque, natural frequencies, servo tuning) and the servo loop. Over 700 lines
// on purpose: the three share the private helpers at the top (data allocation, MuJoCo's warning
// capture, joint limits from the model), and run() is one loop, the hot path bench_sim measures
// against a bare mj_step loop, kept in one piece so nothing but the drive runs per step.
#include "blendbench/sim/simulator.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstring>
#include <limits>
#include <mutex>
#include <regex>
#include <stdexcept>

#include "blendbench/core/format.hpp"
#include "blendbench/core/input_error.hpp"
#include "blendbench/core/interrupt.hpp"
#include "model_files.hpp"

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

// Servo rates a drive of this kind runs at (Hz).
constexpr double kMinServoRate = 125;
constexpr double kMaxServoRate = 8000;

// Two hinges are on the same axis when their axes and anchors agree to this (unit vector, m).
constexpr double kSameAxis = 1e-9;

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
  // a count a long cannot hold is no multiple the loop can run (converting it is undefined)
  if (!(n >= 1 && n <= 1e15) || std::abs(n * period - x) > kMultipleTolerance * x) return 0;
  return static_cast<long>(n);
}

[[noreturn]] void bad_input(const std::string& field, const std::string& message) {
  throw InputError("", 0, 0, field, message);
}

void check_finite(const std::vector<JointVector>& v, const std::string& field) {
  for (std::size_t k = 0; k < v.size(); ++k)
    if (!v[k].allFinite()) bad_input(field, "sample " + std::to_string(k) + " is not finite");
}

void check_gains(const JointVector& g, const std::string& field) {
  if (!g.allFinite() || (g.array() < 0).any()) bad_input(field, "must be finite and >= 0");
}

// The first unhealthy-state warning MuJoCo raised in d (it resets the state silently when it
// raises one of these), as text; empty when the state is healthy.
std::string unhealthy_state(const mjData& d) {
  for (const int w : {mjWARN_BADQPOS, mjWARN_BADQVEL, mjWARN_BADQACC, mjWARN_BADCTRL, mjWARN_INERTIA}) {
    if (d.warning[w].number > 0) return mju_warningText(w, d.warning[w].lastinfo);
  }
  return {};
}

// Six values of the custom numeric `name`, or +inf each when the model has none; `fail` reports
// a numeric of the wrong size.
template <class Fail>
JointVector custom_limits(const mjModel& m, const char* name, const Fail& fail) {
  JointVector out = JointVector::Constant(std::numeric_limits<double>::infinity());
  const int id = mj_name2id(&m, mjOBJ_NUMERIC, name);
  if (id < 0) return out;
  if (m.numeric_size[id] != 6) fail("custom", std::string("numeric '") + name + "' must have 6 values, one per joint");
  for (int i = 0; i < 6; ++i) {
    out[i] = m.numeric_data[m.numeric_adr[id] + i];
    if (!(out[i] > 0)) fail("custom", std::string("numeric '") + name + "' must be positive");
  }
  return out;
}

// The torque the links need for the motion (q, qd, qdd) with the arm rigid, per joint (N*m),
// and the gravity torque alone: mj_rne on `d` with every motor hinge at the link angle and every
// gear at zero. Also leaves the kinematics (site poses) of that configuration in d.
struct LinkTorques {
  JointVector full, gravity;
};

// The range of a model's own values the simulator accepts (beyond them a value is a typo or an
// attack, and what is computed from it overflows: a timestep of 1e-290 s made the number of
// physics steps per servo period overflow a long, a body of 1e308 kg an infinite servo gain).
//   timestep: 1 us (1 MHz physics, 125x the fastest servo rate) to the slowest servo period,
//             8 ms (125 Hz), which the timestep must divide;
//   mass:     at most 1e5 kg per body (the heaviest industrial arms weigh about 5 t in all);
//   inertia:  at most 1e6 kg m^2 per body and axis (1e5 kg at a radius of gyration of 3 m).
constexpr double kMinTimestep = 1e-6;     // s
constexpr double kMaxTimestep = 8e-3;     // s
constexpr double kMaxBodyMass = 1e5;      // kg
constexpr double kMaxBodyInertia = 1e6;   // kg m^2

// Checks the model's values the simulation computes with: finite, and the timestep, masses and
// inertias within the ranges above. `fail(field, message)` refuses, naming what is wrong.
template <class Fail>
void check_model_values(const mjModel& m, const Fail& fail) {
  const double dt = m.opt.timestep;
  if (!(dt >= kMinTimestep && dt <= kMaxTimestep)) {
    fail("option.timestep", "the timestep " + format_value(dt) + " s is outside [" + format_value(kMinTimestep) + ", " +
                                format_value(kMaxTimestep) + "] s");
  }
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(m.opt.gravity[k])) fail("option.gravity", "gravity must be finite");
  }
  for (int b = 0; b < m.nbody; ++b) {
    const std::string body = "body " + object_name(m, mjOBJ_BODY, b);
    if (!(m.body_mass[b] >= 0 && m.body_mass[b] <= kMaxBodyMass)) {
      fail("body.mass", body + " has a mass of " + format_value(m.body_mass[b]) + " kg; at most " + format_value(kMaxBodyMass) +
                            " kg are accepted");
    }
    for (int k = 0; k < 3; ++k) {
      if (!(m.body_inertia[3 * b + k] >= 0 && m.body_inertia[3 * b + k] <= kMaxBodyInertia)) {
        fail("body.inertia", body + " has a principal inertia of " + format_value(m.body_inertia[3 * b + k]) +
                                 " kg*m^2; at most " + format_value(kMaxBodyInertia) + " kg*m^2 are accepted");
      }
      if (!std::isfinite(m.body_pos[3 * b + k]) || !std::isfinite(m.body_ipos[3 * b + k])) {
        fail("body.pos", body + " has a position that is not finite");
      }
    }
  }
  const auto finite_non_negative = [&](const double* values, int count, const char* field, int object) {
    for (int i = 0; i < count; ++i) {
      if (!(values[i] >= 0) || !std::isfinite(values[i])) {
        fail(field, std::string(field) + " of " + (object == mjOBJ_JOINT ? "joint " : "dof ") + object_name(m, object, i) +
                        " must be finite and >= 0, got " + format_value(values[i]));
      }
    }
  };
  finite_non_negative(m.jnt_stiffness, m.njnt, "joint.stiffness", mjOBJ_JOINT);
  finite_non_negative(m.dof_damping, m.nv, "joint.damping", mjOBJ_DOF);
  finite_non_negative(m.dof_armature, m.nv, "joint.armature", mjOBJ_DOF);
  finite_non_negative(m.dof_frictionloss, m.nv, "joint.frictionloss", mjOBJ_DOF);
  for (int a = 0; a < m.nu; ++a) {
    const double values[] = {m.actuator_gear[6 * a], m.actuator_gainprm[mjNGAIN * a], m.actuator_ctrlrange[2 * a],
                             m.actuator_ctrlrange[2 * a + 1], m.actuator_forcerange[2 * a], m.actuator_forcerange[2 * a + 1]};
    for (const double v : values) {
      if (!std::isfinite(v)) fail("actuator", "actuator " + object_name(m, mjOBJ_ACTUATOR, a) + " has a value that is not finite");
    }
  }
}

// Compiles a model from its files in memory: MuJoCo 2.2.2 reads text only through its virtual
// file system, and finds every file there (model_files.hpp), so it opens none itself. Throws
// InputError (file `source`, field "mjcf") with MuJoCo's message.
mjModel* load_model(const sim_detail::ModelFiles& files, const std::string& source) {
  install_mujoco_handlers();
  const auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  struct Deleter {
    mjVFS* v;
    ~Deleter() { mj_deleteVFS(v); }
  } deleter{vfs.get()};
  for (const auto& [name, content] : files.files) {
    if (name.size() >= mjMAXVFSNAME || content.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()) ||
        mj_makeEmptyFileVFS(vfs.get(), name.c_str(), static_cast<int>(std::max<std::size_t>(content.size(), 1))) != 0) {
      throw InputError(source, 0, 0, "mjcf", "cannot place the model file '" + name + "' in MuJoCo's virtual file system");
    }
    const int index = mj_findFileVFS(vfs.get(), name.c_str());
    std::memcpy(vfs->filedata[index], content.data(), content.size());
    vfs->filesize[index] = static_cast<int>(content.size());
  }
  char error[1024] = "";
  mjModel* model = nullptr;
  try {
    model = mj_loadXML(files.main.c_str(), vfs.get(), error, sizeof error);
  } catch (...) {
    // MuJoCo's fatal error (its handler throws, install_mujoco_handlers) while compiling this
    // model is bad input of the model
    rethrow_as_input_error({source, 0, 0}, "mjcf", "MuJoCo cannot compile the model: ");
  }
  if (model == nullptr) {
    const auto [message, line] = tidy_mujoco_message(error);
    throw InputError(source, line, 0, "mjcf", message);
  }
  return model;
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

ServoConfig with_controller(ServoConfig servo, Controller controller) {
  if (controller == Controller::kPd) {
    servo.ki.setZero();
    servo.velocity_feedforward = true;  // the PD's damping term acts on the velocity error
    servo.acceleration_feedforward = false;
    servo.deflection_compensation = false;
  }
  return servo;
}

Simulator::Simulator(const std::string& mjcf_path, const ModelChanges& changes)
    : Simulator(nullptr, mjcf_path, changes) {}

Simulator Simulator::from_xml_string(const std::string& xml, const ModelChanges& changes, const std::string& source) {
  return Simulator(load_model(sim_detail::model_text_files(xml, source), source), source, changes);
}

Simulator::Simulator(mjModel* model, const std::string& source, const ModelChanges& changes) {
  install_mujoco_handlers();
  // read from the file when not given a compiled model: every file of the model read and checked
  // here, MuJoCo loading from memory (model_files.hpp)
  if (model == nullptr) model = load_model(sim_detail::read_model_files(source), source);
  std::unique_ptr<mjModel, void (*)(mjModel*)> owned(model, mj_deleteModel);
  mjModel& m = *model;
  const auto fail = [&](const std::string& field, const std::string& message) {
    throw InputError(source, 0, 0, field, message);
  };
  // the model's own values, before anything is computed from them
  check_model_values(m, fail);

  // an MJCF of the user's own: its actuators made direct-torque motors, their force range kept
  source_ = source;
  if (changes.own_actuators_to_motors) {
    for (int a = 0; a < m.nu; ++a) {
      const std::string name = "actuator " + object_name(m, mjOBJ_ACTUATOR, a);
      const bool motor = m.actuator_dyntype[a] == mjDYN_NONE && m.actuator_gaintype[a] == mjGAIN_FIXED &&
                         m.actuator_biastype[a] == mjBIAS_NONE;
      if (motor) continue;
      if (m.actuator_dyntype[a] != mjDYN_NONE) {
        fail("actuator", name + " has activation dynamics: BlendBench's servo drives the joints with torque; give it a "
                                "<motor> (or a <general> without dynamics and a forcerange) instead");
      }
      if (!m.actuator_forcelimited[a]) {
        fail("actuator", name + " has no forcerange: BlendBench replaces it with a direct-torque motor and needs the "
                                "joint's torque limit; give the actuator forcerange=\"-T T\"");
      }
      m.actuator_gaintype[a] = mjGAIN_FIXED;
      m.actuator_biastype[a] = mjBIAS_NONE;
      for (int k = 0; k < mjNGAIN; ++k) m.actuator_gainprm[mjNGAIN * a + k] = k == 0 ? 1 : 0;
      for (int k = 0; k < mjNBIAS; ++k) m.actuator_biasprm[mjNBIAS * a + k] = 0;
      m.actuator_ctrllimited[a] = 1;
      m.actuator_ctrlrange[2 * a] = m.actuator_forcerange[2 * a];
      m.actuator_ctrlrange[2 * a + 1] = m.actuator_forcerange[2 * a + 1];
      const char* plain = mj_id2name(&m, mjOBJ_ACTUATOR, a);
      replaced_actuators_.push_back(plain != nullptr ? std::string(plain) : std::to_string(a));
    }
  }

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

  // the gears' stiffness and the timestep as asked
  if (!(changes.stiffness_scale > 0) || !std::isfinite(changes.stiffness_scale)) fail("mjcf", "stiffness scale must be positive");
  if (changes.timestep < 0 || !std::isfinite(changes.timestep) ||
      (changes.timestep > 0 && !(changes.timestep >= kMinTimestep && changes.timestep <= kMaxTimestep))) {
    fail("mjcf", "timestep must be 0 (the model's) or in [" + format_value(kMinTimestep) + ", " + format_value(kMaxTimestep) + "] s");
  }
  if (changes.timestep > 0) m.opt.timestep = changes.timestep;
  if (!(changes.inertia_scale > 0) || !std::isfinite(changes.inertia_scale)) fail("mjcf", "inertia scale must be positive");
  if (!(changes.friction_scale >= 0) || !std::isfinite(changes.friction_scale)) fail("mjcf", "friction scale must be >= 0");
  if (changes.extra_delay_ticks < 0) fail("mjcf", "extra measurement delay must be >= 0 ticks");
  changes_ = changes;
  // the links' masses and inertias (every body that moves: not welded to the world), then what
  // MuJoCo derives from them at compile time
  if (changes.inertia_scale != 1) {
    for (int b = 1; b < m.nbody; ++b) {
      if (m.body_weldid[b] == 0) continue;
      m.body_mass[b] *= changes.inertia_scale;
      for (int k = 0; k < 3; ++k) m.body_inertia[3 * b + k] *= changes.inertia_scale;
    }
    mjData* constants = mj_makeData(&m);
    mj_setConst(&m, constants);
    mj_deleteData(constants);
  }

  // per arm joint: addresses, the gear hinge after the motor hinge (elastic), limits
  int elastic_joints = 0;
  for (std::size_t i = 0; i < 6; ++i) {
    const auto ii = static_cast<Eigen::Index>(i);
    const auto [j, a] = joint_actuator[i];
    motor_qpos_[i] = m.jnt_qposadr[j];
    motor_dof_[i] = m.jnt_dofadr[j];
    actuator_[i] = a;
    const double gear = m.actuator_gear[6 * a];
    const double gain = m.actuator_gainprm[mjNGAIN * a];
    ctrl_per_torque_[i] = 1.0 / (gear * gain);
    double force = std::numeric_limits<double>::infinity();  // actuator force limit
    if (m.actuator_ctrllimited[a])
      force = std::min(std::abs(m.actuator_ctrlrange[2 * a]), std::abs(m.actuator_ctrlrange[2 * a + 1])) * std::abs(gain);
    if (m.actuator_forcelimited[a])
      force = std::min({force, std::abs(m.actuator_forcerange[2 * a]), std::abs(m.actuator_forcerange[2 * a + 1])});
    limits_.torque[ii] = std::abs(gear) * force;
    if (m.jnt_stiffness[j] != 0) fail("joint", "motor joint " + object_name(m, mjOBJ_JOINT, j) + " must have no stiffness");
    m.dof_damping[motor_dof_[i]] *= changes.friction_scale;
    m.dof_frictionloss[motor_dof_[i]] *= changes.friction_scale;
    motor_inertia_[ii] = m.dof_armature[motor_dof_[i]];
    viscous_[ii] = m.dof_damping[motor_dof_[i]];
    coulomb_[ii] = m.dof_frictionloss[motor_dof_[i]];

    gear_qpos_[i] = gear_dof_[i] = -1;
    stiffness_[ii] = std::numeric_limits<double>::infinity();
    const int g = j + 1;
    const bool same_body = g < m.njnt && m.jnt_bodyid[g] == m.jnt_bodyid[j] && m.jnt_type[g] == mjJNT_HINGE;
    if (same_body && (Eigen::Map<const Vec3>(m.jnt_axis + 3 * g) - Eigen::Map<const Vec3>(m.jnt_axis + 3 * j)).norm() < kSameAxis &&
        (Eigen::Map<const Vec3>(m.jnt_pos + 3 * g) - Eigen::Map<const Vec3>(m.jnt_pos + 3 * j)).norm() < kSameAxis) {
      if (!(m.jnt_stiffness[g] > 0))
        fail("joint", "gear joint " + object_name(m, mjOBJ_JOINT, g) + " (on the axis of motor joint " +
                          object_name(m, mjOBJ_JOINT, j) + ") needs a positive stiffness");
      m.jnt_stiffness[g] *= changes.stiffness_scale;
      m.dof_damping[m.jnt_dofadr[g]] *= std::sqrt(changes.stiffness_scale * changes.inertia_scale);
      gear_qpos_[i] = m.jnt_qposadr[g];
      gear_dof_[i] = m.jnt_dofadr[g];
      stiffness_[ii] = m.jnt_stiffness[g];
      ++elastic_joints;
    }
  }
  if (elastic_joints != 0 && elastic_joints != 6)
    fail("joint", "either every arm joint has a gear hinge (elastic) or none (rigid); found " +
                      std::to_string(elastic_joints) + " of 6");
  limits_.velocity = custom_limits(m, "velocity_limits", fail);
  limits_.acceleration = custom_limits(m, "acceleration_limits", fail);

  // the tool centre point
  if (!changes.tcp_site.empty() && !changes.tcp_body.empty()) fail("site", "name the TCP by a site or by a body, not both");
  if (!changes.tcp_body.empty()) {
    tcp_body_ = mj_name2id(&m, mjOBJ_BODY, changes.tcp_body.c_str());
    if (tcp_body_ <= 0) fail("body", "the model has no moving body named '" + changes.tcp_body + "'");
  } else {
    const std::string site = changes.tcp_site.empty() ? "tcp" : changes.tcp_site;
    tcp_site_ = mj_name2id(&m, mjOBJ_SITE, site.c_str());
    if (tcp_site_ < 0) fail("site", "the model has no site named '" + site + "'");
  }
  // the timestep must resolve the stiffest mode (motors free, at the model's qpos0); with
  // fit_timestep it is divided by the smallest whole number that does
  if (elastic()) {
    const DataPtr d = make_data(m);
    mj_forward(&m, d.get());
    const int nv = m.nv;
    Eigen::MatrixXd mass(nv, nv);
    std::vector<double> dense(static_cast<std::size_t>(nv * nv));
    mj_fullM(&m, dense.data(), d->qM);
    for (int r = 0; r < nv; ++r)
      for (int c = 0; c < nv; ++c) mass(r, c) = dense[static_cast<std::size_t>(r * nv + c)];
    Eigen::MatrixXd k = Eigen::MatrixXd::Zero(nv, nv);
    for (std::size_t i = 0; i < 6; ++i) k(gear_dof_[i], gear_dof_[i]) = stiffness_[static_cast<Eigen::Index>(i)];
    const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> modes(k, mass, Eigen::EigenvaluesOnly);
    const double omega_max = std::sqrt(std::max(0.0, modes.eigenvalues().maxCoeff()));
    if (changes.fit_timestep && omega_max * m.opt.timestep > kMaxOmegaDt) {
      m.opt.timestep /= std::ceil(omega_max * m.opt.timestep / kMaxOmegaDt);
    }
    if (omega_max * m.opt.timestep > kMaxOmegaDt) {
      fail("mjcf", "the timestep " + format_value(m.opt.timestep) + " s is too long for the model's stiffest mode (" +
                       format_value(omega_max / (2 * std::numbers::pi)) + " Hz): omega dt = " +
                       format_value(omega_max * m.opt.timestep) + " > " + format_value(kMaxOmegaDt) + "; use at most " +
                       format_value(kMaxOmegaDt / omega_max) + " s");
    }
  }
  model_ = std::shared_ptr<const mjModel>(owned.release(), [](const mjModel* p) { mj_deleteModel(const_cast<mjModel*>(p)); });
}

namespace {

// Evaluates configurations of the arm on a scratch mjData: every motor hinge at the link angle,
// every gear at zero deflection.
class LinkModel {
 public:
  LinkModel(const mjModel& m, const std::array<int, 6>& motor_qpos, const std::array<int, 6>& motor_dof)
      : m_(m), d_(make_data(m)), motor_qpos_(motor_qpos), motor_dof_(motor_dof) {}

  // Kinematics and the rigid-body torques of the motion (q, qd, qdd); `full` false: gravity only.
  LinkTorques torques(const JointVector& q, const JointVector& qd, const JointVector& qdd, bool full) {
    for (std::size_t i = 0; i < 6; ++i) {
      const auto ii = static_cast<Eigen::Index>(i);
      d_->qpos[motor_qpos_[i]] = q[ii];
      d_->qvel[motor_dof_[i]] = qd[ii];
      d_->qacc[motor_dof_[i]] = qdd[ii];
    }
    mj_kinematics(&m_, d_.get());
    mj_comPos(&m_, d_.get());
    LinkTorques out;
    if (full) {
      mj_comVel(&m_, d_.get());
      mj_rne(&m_, d_.get(), 1, d_->qfrc_inverse);
      for (std::size_t i = 0; i < 6; ++i) out.full[static_cast<Eigen::Index>(i)] = d_->qfrc_inverse[motor_dof_[i]];
    }
    // gravity alone: rne with the velocity terms zeroed
    mju_zero(d_->cvel, 6 * m_.nbody);
    mju_zero(d_->cdof_dot, 6 * m_.nv);
    mj_rne(&m_, d_.get(), 0, d_->qfrc_inverse);
    for (std::size_t i = 0; i < 6; ++i) out.gravity[static_cast<Eigen::Index>(i)] = d_->qfrc_inverse[motor_dof_[i]];
    if (!full) out.full = out.gravity;
    return out;
  }

  [[nodiscard]] const mjData& data() const { return *d_; }

 private:
  const mjModel& m_;
  DataPtr d_;
  std::array<int, 6> motor_qpos_, motor_dof_;
};

// The pose of `tool` (given in the frame of site `site`) in d.
Eigen::Isometry3d tool_pose(const mjData& d, int site, int body, const Eigen::Isometry3d& tool) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  if (site >= 0) {
    pose.linear() = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(d.site_xmat + 9 * site);
    pose.translation() = Eigen::Map<const Vec3>(d.site_xpos + 3 * site);
  } else {
    pose.linear() = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(d.xmat + 9 * body);
    pose.translation() = Eigen::Map<const Vec3>(d.xpos + 3 * body);
  }
  return pose * tool;
}

// A rotation as MuJoCo's quaternion of it (mju_mat2Quat writes w, x, y, z).
Eigen::Quaterniond mujoco_quaternion(const Mat3& r) {
  const Eigen::Matrix<double, 3, 3, Eigen::RowMajor> row_major = r;
  double wxyz[4];
  mju_mat2Quat(wxyz, row_major.data());
  return {wxyz[0], wxyz[1], wxyz[2], wxyz[3]};
}

// The dense mass matrix of `d` (kinematics and composite inertias current).
Eigen::MatrixXd mass_matrix(const mjModel& m, const mjData& d) {
  std::vector<double> dense(static_cast<std::size_t>(m.nv * m.nv));
  mj_fullM(&m, dense.data(), d.qM);
  Eigen::MatrixXd out(m.nv, m.nv);
  for (int r = 0; r < m.nv; ++r)
    for (int c = 0; c < m.nv; ++c) out(r, c) = dense[static_cast<std::size_t>(r * m.nv + c)];
  return out;
}

}  // namespace

JointVector Simulator::link_inertia(const JointVector& q) const {
  const mjModel& m = *model_;
  const DataPtr d = make_data(m);
  for (std::size_t i = 0; i < 6; ++i) d->qpos[motor_qpos_[i]] = q[static_cast<Eigen::Index>(i)];
  mj_forward(&m, d.get());
  JointVector out;
  for (std::size_t i = 0; i < 6; ++i) {
    const int dof = motor_dof_[i];
    out[static_cast<Eigen::Index>(i)] = d->qM[m.dof_Madr[dof]] - m.dof_armature[dof];
  }
  return out;
}

JointVector Simulator::gravity_torque(const JointVector& q) const {
  LinkModel links(*model_, motor_qpos_, motor_dof_);
  return links.torques(q, JointVector::Zero(), JointVector::Zero(), false).gravity;
}

NaturalFrequencies Simulator::natural_frequencies(const JointVector& q) const {
  NaturalFrequencies out;
  if (!elastic()) return out;
  const mjModel& m = *model_;
  const DataPtr d = make_data(m);
  for (std::size_t i = 0; i < 6; ++i) d->qpos[motor_qpos_[i]] = q[static_cast<Eigen::Index>(i)];
  mj_forward(&m, d.get());
  const Eigen::MatrixXd mass = mass_matrix(m, *d);
  // the gear block of the mass matrix: the links' inertia with every motor held
  Eigen::Matrix<double, 6, 6> links;
  for (std::size_t r = 0; r < 6; ++r)
    for (std::size_t c = 0; c < 6; ++c) {
      links(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = mass(gear_dof_[r], gear_dof_[c]);
    }
  for (std::size_t i = 0; i < 6; ++i) links(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i)) -= m.dof_armature[gear_dof_[i]];
  const double two_pi = 2 * std::numbers::pi;
  for (int i = 0; i < 6; ++i) out.per_joint[i] = std::sqrt(stiffness_[i] / links(i, i)) / two_pi;
  const Eigen::Matrix<double, 6, 6> k = stiffness_.asDiagonal();
  const Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> modes(k, links);
  for (int i = 0; i < 6; ++i) {
    out.arm[i] = std::sqrt(std::max(0.0, modes.eigenvalues()[i])) / two_pi;
    JointVector shape = modes.eigenvectors().col(i);
    Eigen::Index largest = 0;
    shape.cwiseAbs().maxCoeff(&largest);
    out.arm_shapes[static_cast<std::size_t>(i)] = shape / shape[largest];
  }
  return out;
}

KinematicChain Simulator::kinematic_chain() const {
  const mjModel& m = *model_;
  const auto fail = [&](const std::string& message) { throw InputError(source_, 0, 0, "joint", message); };
  // the TCP's body and its pose in that body
  const int tip = tcp_site_ >= 0 ? m.site_bodyid[tcp_site_] : tcp_body_;
  Eigen::Isometry3d tip_in_body = Eigen::Isometry3d::Identity();
  if (tcp_site_ >= 0) {
    const double* q = m.site_quat + 4 * tcp_site_;
    tip_in_body.linear() = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
    tip_in_body.translation() = Eigen::Map<const Vec3>(m.site_pos + 3 * tcp_site_);
  }
  std::vector<int> path;  // world's child ... tip
  for (int b = tip; b > 0; b = m.body_parentid[b]) path.push_back(b);
  std::reverse(path.begin(), path.end());
  KinematicChain chain;
  Eigen::Isometry3d pending = Eigen::Isometry3d::Identity();  // from the last joint frame
  for (const int b : path) {
    Eigen::Isometry3d body = Eigen::Isometry3d::Identity();
    const double* q = m.body_quat + 4 * b;
    body.linear() = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
    body.translation() = Eigen::Map<const Vec3>(m.body_pos + 3 * b);
    pending = pending * body;
    for (int j = m.body_jntadr[b]; j >= 0 && j < m.body_jntadr[b] + m.body_jntnum[b]; ++j) {
      const auto motor = std::find(motor_qpos_.begin(), motor_qpos_.end(), m.jnt_qposadr[j]);
      const auto gear = std::find(gear_qpos_.begin(), gear_qpos_.end(), m.jnt_qposadr[j]);
      if (gear != gear_qpos_.end() && m.jnt_qposadr[j] >= 0 && *gear >= 0) continue;  // at zero deflection
      if (motor == motor_qpos_.end()) {
        fail("joint " + object_name(m, mjOBJ_JOINT, j) + " lies between the base and the TCP but no actuator drives it");
      }
      const auto i = static_cast<Eigen::Index>(motor - motor_qpos_.begin());
      if (static_cast<std::size_t>(i) != chain.joints.size()) fail("the driven joints are not in order from the base to the TCP");
      const Vec3 anchor = Eigen::Map<const Vec3>(m.jnt_pos + 3 * j);
      JointSpec spec;
      const char* plain = mj_id2name(&m, mjOBJ_JOINT, j);
      spec.name = plain != nullptr ? std::string(plain) : std::to_string(j);
      spec.origin = pending * Eigen::Translation3d(anchor);
      spec.axis = Eigen::Map<const Vec3>(m.jnt_axis + 3 * j).normalized();
      spec.lower = m.jnt_limited[j] ? m.jnt_range[2 * j] : -std::numeric_limits<double>::infinity();
      spec.upper = m.jnt_limited[j] ? m.jnt_range[2 * j + 1] : std::numeric_limits<double>::infinity();
      spec.velocity_limit = limits_.velocity[i];
      spec.effort_limit = limits_.torque[i];
      chain.joints.push_back(spec);
      pending = Eigen::Translation3d(-anchor) * Eigen::Isometry3d::Identity();
    }
  }
  if (chain.joints.size() != 6) {
    fail("only " + std::to_string(chain.joints.size()) + " of the six driven joints lie between the base and the TCP");
  }
  chain.tcp = pending * tip_in_body;
  return chain;
}

ServoConfig tune_servo(const Simulator& sim, const JointVector& q, const ServoTuning& tuning) {
  if (!(tuning.rate_hz >= kMinServoRate && tuning.rate_hz <= kMaxServoRate)) {
    bad_input("servo.rate_hz", "must be between " + format_value(kMinServoRate) + " and " + format_value(kMaxServoRate) +
                                   " Hz, got " + format_value(tuning.rate_hz));
  }
  if (tuning.measurement_delay_ticks < 0) bad_input("servo.measurement_delay_ticks", "must be >= 0");
  ServoConfig servo;
  servo.rate_hz = tuning.rate_hz;
  servo.setpoint_rate_hz = tuning.setpoint_rate_hz;
  servo.measurement_delay_ticks = tuning.measurement_delay_ticks;
  servo.encoder_counts_per_turn = tuning.encoder_counts_per_turn;
  const double loop_delay = (tuning.measurement_delay_ticks + 1) / tuning.rate_hz;  // s
  const JointVector link = sim.link_inertia(q);
  const JointVector total = link + sim.motor_inertia();
  for (int i = 0; i < 6; ++i) {
    // velocity loop: delay-limited, and below the joint's antiresonance
    double omega_v = tuning.delay_phase / loop_delay;
    if (sim.elastic()) omega_v = std::min(omega_v, tuning.antiresonance_share * std::sqrt(sim.stiffness()[i] / link[i]));
    servo.velocity_bandwidth[i] = omega_v;
    servo.kv[i] = omega_v * total[i];
    servo.ki[i] = servo.kv[i] * omega_v * tuning.integral_share;
    servo.kp[i] = tuning.position_share * omega_v;
    servo.position_bandwidth[i] = servo.kp[i];
  }
  return servo;
}

namespace {

// What the controller prepared for one setpoint: its time, the motor reference (angle, speed)
// and the feed-forward torque; the drive interpolates linearly between setpoints.
struct Setpoint {
  double t = 0;
  JointVector motor = JointVector::Zero(), motor_speed = JointVector::Zero(), feedforward = JointVector::Zero();
};

// The last few setpoints, oldest first, and linear interpolation in time among them (clamped to
// the oldest and newest).
class SetpointHistory {
 public:
  explicit SetpointHistory(std::size_t capacity) : capacity_(capacity) {}
  void push(const Setpoint& s) {
    if (items_.size() == capacity_) items_.erase(items_.begin());
    items_.push_back(s);
  }
  [[nodiscard]] const Setpoint& newest() const { return items_.back(); }
  template <class Member>
  [[nodiscard]] JointVector at(double t, Member member) const {
    if (t <= items_.front().t) return items_.front().*member;
    for (std::size_t k = 1; k < items_.size(); ++k) {
      if (t <= items_[k].t) {
        const double u = (t - items_[k - 1].t) / (items_[k].t - items_[k - 1].t);
        return (1 - u) * (items_[k - 1].*member) + u * (items_[k].*member);
      }
    }
    return items_.back().*member;
  }

 private:
  std::size_t capacity_;
  std::vector<Setpoint> items_;
};

}  // namespace

Trace Simulator::run(const JointTrajectory& reference, const ServoConfig& servo, const RunOptions& options) const {
  const mjModel& m = *model_;
  const double h = m.opt.timestep;

  // validate the servo: its period is a whole number of physics steps, the setpoint period a
  // whole number of servo periods
  const auto check_rate = [](double rate, const std::string& field) {
    if (!(rate >= kMinServoRate && rate <= kMaxServoRate)) {
      bad_input(field, "must be between " + format_value(kMinServoRate) + " and " + format_value(kMaxServoRate) +
                           " Hz, got " + format_value(rate));
    }
  };
  check_rate(servo.rate_hz, "servo.rate_hz");
  check_rate(servo.setpoint_rate_hz, "servo.setpoint_rate_hz");
  const long steps_per_tick = multiple_of(1.0 / servo.rate_hz, h);
  if (steps_per_tick == 0)
    bad_input("servo.rate_hz", "the servo period 1/" + format_value(servo.rate_hz) +
                                   " s is not a multiple of the model timestep " + format_value(h) + " s");
  const double period = static_cast<double>(steps_per_tick) * h;
  const long ticks_per_setpoint = multiple_of(1.0 / servo.setpoint_rate_hz, period);
  if (ticks_per_setpoint == 0)
    bad_input("servo.setpoint_rate_hz", "the setpoint period 1/" + format_value(servo.setpoint_rate_hz) +
                                            " s is not a multiple of the servo period " + format_value(period) + " s");
  const double setpoint_period = static_cast<double>(ticks_per_setpoint) * period;
  check_gains(servo.kp, "servo.kp");
  check_gains(servo.kv, "servo.kv");
  check_gains(servo.ki, "servo.ki");
  if (servo.measurement_delay_ticks < 0) bad_input("servo.measurement_delay_ticks", "must be >= 0");
  if (!(servo.encoder_counts_per_turn >= 0) || !std::isfinite(servo.encoder_counts_per_turn))
    bad_input("servo.encoder_counts_per_turn", "must be >= 0 (0: exact)");

  // validate the reference: sampled at a multiple of the setpoint period
  const std::size_t n = reference.q.size();
  if (n == 0) bad_input("reference.q", "is empty");
  if (!reference.qd.empty() && reference.qd.size() != n) bad_input("reference.qd", "must be empty or as long as q");
  if (!reference.qdd.empty() && reference.qdd.size() != n) bad_input("reference.qdd", "must be empty or as long as q");
  check_finite(reference.q, "reference.q");
  check_finite(reference.qd, "reference.qd");
  check_finite(reference.qdd, "reference.qdd");
  long setpoints_per_sample = 1;
  if (n > 1) {
    setpoints_per_sample = multiple_of(reference.dt, setpoint_period);
    if (setpoints_per_sample == 0)
      bad_input("reference.dt", format_value(reference.dt) + " s is not a positive multiple of the setpoint period " +
                                    format_value(setpoint_period) + " s");
  }
  if (!(options.settle_time >= 0) || !std::isfinite(options.settle_time)) bad_input("settle_time", "must be >= 0");
  if (!(options.frame_rate >= 0) || !std::isfinite(options.frame_rate)) bad_input("frame_rate", "must be >= 0");

  const long last_reference_setpoint = static_cast<long>(n - 1) * setpoints_per_sample;
  const long last_setpoint = last_reference_setpoint + std::lround(options.settle_time / setpoint_period);
  const long last_step = last_setpoint * ticks_per_setpoint * steps_per_tick;
  const bool elastic_arm = elastic();
  const bool compensate = elastic_arm && servo.deflection_compensation;
  const double quantum = servo.encoder_counts_per_turn > 0 ? 2 * std::numbers::pi / servo.encoder_counts_per_turn : 0.0;
  const auto quantise = [quantum](double angle) { return quantum > 0 ? std::round(angle / quantum) * quantum : angle; };

  // the reference at a setpoint: linear between samples, then the last position at rest
  const auto reference_at = [&](long setpoint, JointVector& q, JointVector& qd, JointVector& qdd) {
    if (setpoint < last_reference_setpoint) {
      const auto k = static_cast<std::size_t>(setpoint / setpoints_per_sample);
      const double u = static_cast<double>(setpoint % setpoints_per_sample) / static_cast<double>(setpoints_per_sample);
      const auto lerp = [&](const std::vector<JointVector>& v) -> JointVector {
        return v.empty() ? JointVector::Zero() : JointVector((1 - u) * v[k] + u * v[k + 1]);
      };
      q = lerp(reference.q);
      qd = lerp(reference.qd);
      qdd = lerp(reference.qdd);
    } else {
      q = reference.q[n - 1];
      const bool at_last = setpoint == last_reference_setpoint;
      qd = at_last && !reference.qd.empty() ? reference.qd[n - 1] : JointVector::Zero();
      qdd = at_last && !reference.qdd.empty() ? reference.qdd[n - 1] : JointVector::Zero();
    }
  };

  // scratch models of the links: the reference (feed-forward, commanded TCP) and the measured
  // angles (gravity compensation)
  LinkModel ref_links(m, motor_qpos_, motor_dof_);
  LinkModel measured_links(m, motor_qpos_, motor_dof_);
  const JointVector stiffness = stiffness_;

  // the controller's work for setpoint k: the motor reference (the link reference plus the gear
  // deflection its torque causes) and the acceleration feed-forward; also the commanded TCP
  struct Prepared {
    JointVector q, qd, deflection;
    Setpoint setpoint;
    Vec3 tcp;
    Eigen::Quaterniond rotation;
  };
  JointVector previous_deflection = JointVector::Zero();
  const auto prepare = [&](long k) {
    Prepared p;
    JointVector qdd;
    reference_at(k, p.q, p.qd, qdd);
    const bool need_torques = compensate || servo.acceleration_feedforward;
    const LinkTorques ref = ref_links.torques(p.q, p.qd, qdd, need_torques);
    p.deflection = compensate ? JointVector(ref.full.cwiseQuotient(stiffness)) : JointVector::Zero();
    p.setpoint.t = static_cast<double>(k) * setpoint_period;
    p.setpoint.motor = p.q + p.deflection;
    p.setpoint.motor_speed = p.qd + (k == 0 ? JointVector::Zero() : JointVector((p.deflection - previous_deflection) / setpoint_period));
    previous_deflection = p.deflection;
    if (servo.acceleration_feedforward) {
      for (int i = 0; i < 6; ++i) {
        p.setpoint.feedforward[i] = ref.full[i] - ref.gravity[i] + motor_inertia_[i] * qdd[i] + viscous_[i] * p.qd[i] +
                                    coulomb_[i] * std::tanh(p.qd[i] / kCoulombSmoothing);
      }
    }
    const Eigen::Isometry3d tcp = tool_pose(ref_links.data(), tcp_site_, tcp_body_, options.tool);
    p.tcp = tcp.translation();
    p.rotation = mujoco_quaternion(tcp.linear());
    return p;
  };

  // start at rest in the equilibrium of the first command: the motors at their first reference,
  // the gears deflected by the gravity load
  const DataPtr d = make_data(m);
  Prepared current = prepare(0);
  const JointVector gravity0 = ref_links.torques(current.q, JointVector::Zero(), JointVector::Zero(), false).gravity;
  for (std::size_t i = 0; i < 6; ++i) {
    const auto ii = static_cast<Eigen::Index>(i);
    d->qpos[motor_qpos_[i]] = current.setpoint.motor[ii];
    if (elastic_arm) d->qpos[gear_qpos_[i]] = -gravity0[ii] / stiffness[ii];
  }
  mj_forward(&m, d.get());
  Prepared next = prepare(1);

  // the drive's state: encoder history (true motor angles of the last ticks), speed estimate,
  // integrators; the setpoints it interpolates (enough to reach back over the delay)
  const auto delay = static_cast<std::size_t>(servo.measurement_delay_ticks + changes_.extra_delay_ticks);
  std::vector<JointVector> history(delay + 1);
  JointVector motor0;
  for (std::size_t i = 0; i < 6; ++i) motor0[static_cast<Eigen::Index>(i)] = d->qpos[motor_qpos_[i]];
  for (JointVector& past : history) past = motor0;
  JointVector measured_previous = motor0.unaryExpr(quantise);
  JointVector integral = JointVector::Zero();
  SetpointHistory setpoints(static_cast<std::size_t>(std::ceil((static_cast<double>(delay) + 1) * period / setpoint_period)) + 3);
  Setpoint before = current.setpoint;
  before.t = -setpoint_period;
  setpoints.push(before);
  setpoints.push(current.setpoint);
  setpoints.push(next.setpoint);
  JointVector gravity = JointVector::Zero();
  const JointVector& limit = limits_.torque;

  Trace trace;
  trace.period = setpoint_period;
  trace.reference_end = static_cast<double>(last_reference_setpoint) * setpoint_period;
  trace.samples.reserve(static_cast<std::size_t>(last_setpoint + 1));
  const bool frames = options.frame_rate > 0 && options.on_frame;
  long next_frame = 0;

  for (long step = 0; step <= last_step; ++step) {
    const double t_step = static_cast<double>(step) * h;
    // a stop request (SIGINT/SIGTERM) unwinds from here, every 1024 physics steps
    if (step % 1024 == 0) throw_if_stop_requested();

    // position and velocity stages: poses now describe the state at t_step
    mj_step1(&m, d.get());
    if (std::string why = unhealthy_state(*d); !why.empty()) {
      trace.diverged = true;
      trace.warning = why + " (t = " + format_value(t_step) + " s)";
      break;
    }

    if (step % steps_per_tick == 0) {
      const long tick = step / steps_per_tick;
      const double t = static_cast<double>(tick) * period;
      const bool at_setpoint = tick % ticks_per_setpoint == 0;
      const long k = tick / ticks_per_setpoint;

      // the true state
      JointVector motor, motor_speed, link, link_speed;
      for (std::size_t i = 0; i < 6; ++i) {
        const auto ii = static_cast<Eigen::Index>(i);
        motor[ii] = d->qpos[motor_qpos_[i]];
        motor_speed[ii] = d->qvel[motor_dof_[i]];
        link[ii] = motor[ii] + (elastic_arm ? d->qpos[gear_qpos_[i]] : 0.0);
        link_speed[ii] = motor_speed[ii] + (elastic_arm ? d->qvel[gear_dof_[i]] : 0.0);
      }
      if (!link.allFinite() || !link_speed.allFinite() || link_speed.cwiseAbs().maxCoeff() > kMaxJointSpeed ||
          motor_speed.cwiseAbs().maxCoeff() > kMaxJointSpeed) {
        trace.diverged = true;
        trace.warning = "joint speed beyond " + format_value(kMaxJointSpeed) +
                        " rad/s: the simulation is unstable (t = " + format_value(t) + " s)";
        break;
      }

      // the encoder: the motor angle `delay` ticks ago, quantised; the speed by difference
      for (std::size_t j = delay; j > 0; --j) history[j] = history[j - 1];
      history[0] = motor;
      const JointVector measured = history[delay].unaryExpr(quantise);
      const JointVector measured_speed = tick == 0 ? JointVector::Zero() : JointVector((measured - measured_previous) / period);
      measured_previous = measured;

      // the controller, once per setpoint: the next setpoint (the reference is known ahead), and
      // the gravity torque at the measured angles
      if (at_setpoint && k > 0) {
        current = next;
        next = prepare(k + 1);
        setpoints.push(next.setpoint);
      }
      if (at_setpoint && servo.gravity_compensation) {
        gravity = measured_links.torques(measured, JointVector::Zero(), JointVector::Zero(), false).gravity;
      }

      // the drive: position P and velocity PI on the reference of the instant its measurements
      // describe (the speed estimate is a backward difference: half a tick earlier still), the
      // controller's torques, saturation
      const JointVector motor_cmd_then = setpoints.at(t - static_cast<double>(delay) * period, &Setpoint::motor);
      const JointVector motor_speed_then =
          setpoints.at(t - (static_cast<double>(delay) + 0.5) * period, &Setpoint::motor_speed);
      JointVector speed_cmd = servo.kp.cwiseProduct(motor_cmd_then - measured);
      if (servo.velocity_feedforward) speed_cmd += motor_speed_then;
      const JointVector speed_error = speed_cmd - measured_speed;
      JointVector tau = servo.kv.cwiseProduct(speed_error) + integral + gravity + setpoints.at(t, &Setpoint::feedforward);
      ++trace.servo_ticks;
      for (std::size_t i = 0; i < 6; ++i) {
        const auto ii = static_cast<Eigen::Index>(i);
        const bool saturated = std::abs(tau[ii]) > limit[ii];
        // anti-windup: hold the integrator while the torque is clamped in the error's direction
        if (!saturated || tau[ii] * speed_error[ii] < 0) integral[ii] += servo.ki[ii] * speed_error[ii] * period;
        if (saturated) {
          ++trace.saturated_ticks[i];
          tau[ii] = std::clamp(tau[ii], -limit[ii], limit[ii]);
        }
        d->ctrl[actuator_[i]] = tau[ii] * ctrl_per_torque_[i];
      }
      if (!tau.allFinite()) {
        trace.diverged = true;
        trace.warning = "non-finite servo torque (t = " + format_value(t) + " s)";
        break;
      }

      // record the setpoint ticks
      if (at_setpoint) {
        TraceSample& sample = trace.samples.emplace_back();
        sample.t = t;
        sample.q_cmd = current.q;
        sample.qd_cmd = current.qd;
        sample.q_motor_cmd = current.setpoint.motor;
        sample.q_measured = measured;
        sample.following_error = motor_cmd_then - measured;
        sample.q_motor = motor;
        sample.qd_motor = motor_speed;
        sample.q = link;
        sample.qd = link_speed;
        sample.tau = tau;
        const Eigen::Isometry3d tcp = tool_pose(*d, tcp_site_, tcp_body_, options.tool);
        sample.tcp = tcp.translation();
        sample.tcp_cmd = current.tcp;
        sample.rotation = mujoco_quaternion(tcp.linear());
        sample.rotation_cmd = current.rotation;
      }
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

}  // namespace blendbench
