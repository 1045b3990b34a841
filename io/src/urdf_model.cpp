// The MuJoCo model of a URDF (urdf_model.hpp).

#include "blendbench/io/urdf_model.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "blendbench/core/format.hpp"
#include "blendbench/core/input_error.hpp"
#include "urdf_read.hpp"
#include "xml_writer.hpp"

namespace blendbench {
namespace {

constexpr double kGravity = 9.81;  // m/s^2

// A body's rigid inertia: mass (kg), centre (m, body frame), tensor about the centre (kg*m^2).
struct Inertia {
  double mass = 0;
  Vec3 centre = Vec3::Zero();
  Mat3 tensor = Mat3::Zero();
};

// The sum of two inertias in one frame (parallel-axis theorem about the joint centre).
Inertia combined(const Inertia& a, const Inertia& b) {
  Inertia out;
  out.mass = a.mass + b.mass;
  if (out.mass <= 0) return out;
  out.centre = (a.mass * a.centre + b.mass * b.centre) / out.mass;
  const auto shifted = [&](const Inertia& i) {
    const Vec3 d = i.centre - out.centre;
    return Mat3(i.tensor + i.mass * (d.squaredNorm() * Mat3::Identity() - d * d.transpose()));
  };
  out.tensor = shifted(a) + shifted(b);
  return out;
}

// A link's <inertial> in the frame `frame` maps it into.
Inertia inertia_of(const urdf::Inertial& in, const Eigen::Isometry3d& frame) {
  const Eigen::Isometry3d at = frame * urdf_read::to_isometry(in.origin);
  Mat3 local;
  local << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
  return {in.mass, at.translation(), at.linear() * local * at.linear().transpose()};
}

// A uniform solid rod of mass m (radius kRodRadius) centred halfway from 0 to `end`, along it,
// at least kMinLinkLength long. A shorter rod would break MuJoCo's check of the principal
// moments (A + B >= C, within its tolerance): 2 I_across - I_axial = m l^2 / 6, which is zero for
// a link of zero length (joint_6 to tool0 of ABB's IRB 120: the wrist centre and the flange
// coincide), so the rod keeps a length: then A + B - C >= m kMinLinkLength^2 / 6, half of C again
// for kRodRadius = 0.04 m. A link without direction (coincident frames) lies along its z axis.
Inertia rod(double m, const Vec3& end) {
  const double distance = end.norm();
  const Vec3 u = distance > 1e-9 ? Vec3(end / distance) : Vec3::UnitZ();
  const double l = std::max(distance, kMinLinkLength);
  const double axial = m * kRodRadius * kRodRadius / 2;
  const double across = m * (3 * kRodRadius * kRodRadius + l * l) / 12;
  return {m, end / 2, Mat3(across * Mat3::Identity() + (axial - across) * u * u.transpose())};
}

// The inertia about each joint's axis of the bodies it moves (each body's inertia in its joint's
// frame), at the pose where every joint is at zero: sum over the outboard bodies k of
// a^T I_k a + m_k |d_k - (d_k . a) a|^2, d_k from the joint's origin to body k's centre.
std::vector<double> reflected_rotor_inertia(const KinematicChain& chain, const std::vector<Inertia>& body) {
  std::vector<Eigen::Isometry3d> frame(6);  // joint i's frame in the base frame at q = 0
  for (std::size_t i = 0; i < 6; ++i) frame[i] = (i == 0 ? Eigen::Isometry3d::Identity() : frame[i - 1]) * chain.joints[i].origin;
  std::vector<double> out(6, 0.0);
  for (std::size_t i = 0; i < 6; ++i) {
    const Vec3 a = frame[i].linear() * chain.joints[i].axis.normalized();
    for (std::size_t k = i; k < 6; ++k) {
      const Mat3 r = frame[k].linear();
      const Vec3 d = frame[k] * body[k].centre - frame[i].translation();
      const Vec3 across = d - d.dot(a) * a;
      out[i] += a.dot(r * body[k].tensor * r.transpose() * a) + body[k].mass * across.squaredNorm();
    }
  }
  return out;
}

// A number in full precision (the model must reproduce the URDF's kinematics to 1e-9).
std::string num(double v) { return format_value(v, 17); }

std::string numbers(const Vec3& v) { return num(v.x()) + " " + num(v.y()) + " " + num(v.z()); }

// The "w x y z" quaternion of a transform's rotation.
std::string quaternion(const Eigen::Isometry3d& t) {
  const Eigen::Quaterniond q(t.linear());
  return num(q.w()) + " " + num(q.x()) + " " + num(q.y()) + " " + num(q.z());
}

std::string list_of(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "'" : ", '") + n + "'";
  return out;
}

}  // namespace

UrdfModel model_from_urdf(const std::string& urdf_path, const std::string& base_link, const std::string& tip_link,
                          double total_mass) {
  const urdf::ModelInterfaceSharedPtr model = urdf_read::parse(urdf_path);
  const urdf_read::ChainPath path = urdf_read::find_chain(*model, urdf_path, base_link, tip_link);
  UrdfModel out;
  out.chain = urdf_read::chain_of(urdf_path, path, false);
  KinematicChain& chain = out.chain;

  // each moving body's inertia from the links it carries (itself and the links fixed to it),
  // in its joint frame; which bodies carry no <inertial> at all
  std::vector<Inertia> body(6);
  std::vector<bool> given(6, false);
  std::vector<double> damping(6, 0), friction(6, 0);
  int current = -1;
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();  // the link's frame in the current body's
  for (const urdf::JointConstSharedPtr& joint : path.joints) {
    if (joint->type == urdf::Joint::FIXED) {
      frame = frame * urdf_read::to_isometry(joint->parent_to_joint_origin_transform);
    } else {
      ++current;
      frame = Eigen::Isometry3d::Identity();
      if (joint->dynamics) {
        damping[static_cast<std::size_t>(current)] = std::max(0.0, joint->dynamics->damping);
        friction[static_cast<std::size_t>(current)] = std::max(0.0, joint->dynamics->friction);
      }
    }
    if (current < 0) continue;
    const urdf::LinkConstSharedPtr link = model->getLink(joint->child_link_name);
    if (link && link->inertial && link->inertial->mass > 0) {
      const auto i = static_cast<std::size_t>(current);
      body[i] = combined(body[i], inertia_of(*link->inertial, frame));
      given[i] = true;
    }
  }
  // each body's extent: to the next joint, the last to the tip
  std::vector<Vec3> extent(6);
  for (std::size_t i = 0; i < 6; ++i) extent[i] = i + 1 < 6 ? chain.joints[i + 1].origin.translation() : chain.tcp.translation();

  // links without <inertial>: refused, or the stated estimate
  std::vector<std::string> missing;
  for (std::size_t i = 0; i < 6; ++i) {
    if (!given[i]) missing.push_back(chain.joints[i].name);
  }
  if (!missing.empty()) {
    if (!(total_mass > 0)) {
      throw InputError(urdf_path, 0, 0, "inertial",
                       "the links moved by joints " + list_of(missing) +
                           " have no <inertial> (a kinematics-only URDF): give robot.mjcf, or robot.estimate_inertia: "
                           "{total_mass_kg: M} for an estimate");
    }
    double length = 0;
    for (std::size_t i = 0; i < 6; ++i) {
      if (!given[i]) length += std::max(kMinLinkLength, extent[i].norm());
    }
    for (std::size_t i = 0; i < 6; ++i) {
      if (given[i]) continue;
      const double m = total_mass * std::max(kMinLinkLength, extent[i].norm()) / length;
      body[i] = rod(m, extent[i]);
    }
    out.notes.push_back("estimated masses and inertias (robot.estimate_inertia, " + format_value(total_mass) +
                        " kg shared by length; uniform rods of radius " + format_value(kRodRadius * 1e3) +
                        " mm) for the links of " + list_of(missing));
  }

  // joints without a usable effort: refused, or twice a bound of the gravity torque that holds in
  // every configuration
  std::vector<std::string> no_effort;
  for (const JointSpec& j : chain.joints) {
    if (!(j.effort_limit > 0)) no_effort.push_back(j.name);
  }
  if (!no_effort.empty()) {
    if (!(total_mass > 0)) {
      throw InputError(urdf_path, 0, 0, "effort",
                       "joints " + list_of(no_effort) +
                           " have no positive effort limit (a kinematics-only URDF): give robot.mjcf, or "
                           "robot.estimate_inertia: {total_mass_kg: M} for an estimate");
    }
    // Gravity's torque about joint i is at most g sum_k m_k |r_k|, r_k from the joint's origin
    // (a point of its axis) to the centre of outboard body k. r_k is a sum of fixed-length
    // vectors that the joints between only turn (the offsets from joint i to joint k, then the
    // centre in body k's frame), so |r_k| is at most the sum of their lengths, in every
    // configuration; it is reached where the joints can line them up. (The distances at q = 0,
    // used before, are not a bound: UrdfModel.TheEstimateIsStatedAndItsTorquesHoldTheArmAnywhere
    // at 1500 random poses found gravity taking 0.500056 of such a limit on the offset-wrist arm.)
    for (std::size_t i = 0; i < 6; ++i) {
      if (chain.joints[i].effort_limit > 0) continue;
      double bound = 0;
      double reach = 0;  // the offsets' lengths from joint i to joint k
      for (std::size_t k = i; k < 6; ++k) {
        if (k > i) reach += chain.joints[k].origin.translation().norm();
        bound += body[k].mass * (reach + body[k].centre.norm());
      }
      chain.joints[i].effort_limit = std::max(kMinEffort, kEffortMargin * kGravity * bound);
    }
    out.notes.push_back("estimated torque limits (" + format_value(kEffortMargin) +
                        " x a bound of the gravity torque over every configuration) for " + list_of(no_effort));
  }
  // each joint's rotor inertia (as reflected through its gear, MuJoCo's armature), which a URDF
  // never states: the link inertia the joint moves at the URDF's zero pose. That is the
  // inertia-matched drive (the gear ratio N that gives a load the most acceleration for a motor's
  // torque makes N^2 J_motor equal the load's inertia), and it is needed: without it the joints'
  // coupling, which a per-joint servo does not see, made the servo of ABB's IRB 120 (ROS-Industrial
  // URDF, 25 kg estimate) oscillate at 250 Hz against its torque limits (joint 3 saturated 44 % of
  // the run); with it the servo's loops stay nearly decoupled, as on a geared arm.
  std::vector<double> armature = reflected_rotor_inertia(chain, body);
  out.notes.push_back("built from the URDF: rigid joints, each with a rotor inertia equal to the link inertia it moves "
                      "at the URDF's zero pose (inertia-matched drives; a URDF states none), no acceleration limits, the "
                      "links drawn as capsules between the joints");
  // the URDF's meshes are not drawn: say which, and whether their files are there at all
  std::vector<std::string> meshes;
  for (const auto& [name, link] : model->links_) {
    for (const urdf::VisualSharedPtr& visual : link->visual_array) {
      if (visual && visual->geometry && visual->geometry->type == urdf::Geometry::MESH) {
        meshes.push_back(static_cast<const urdf::Mesh&>(*visual->geometry).filename);
      }
    }
  }
  if (!meshes.empty()) {
    std::size_t missing_files = 0;
    for (const std::string& m : meshes) {
      std::error_code ec;
      if (m.starts_with("package://") || !std::filesystem::is_regular_file(m, ec)) ++missing_files;
    }
    out.notes.push_back(std::to_string(meshes.size()) + " visual meshes replaced by simple shapes (" +
                        std::to_string(missing_files) + " of them missing here, e.g. '" + meshes.front() + "')");
  }

  // the arm's size, for the floor and the camera
  double reach = 0;
  for (std::size_t i = 0; i < 6; ++i) reach += extent[i].norm();
  reach = std::max(reach, 0.3);

  // the MJCF, every name and number written through the XML writer (escaped: a name from the
  // URDF is text, never markup): options as the shipped models have them (8 kHz semi-implicit
  // Euler), world, bodies
  if (!xml_detail::xml_writable(model->getName())) {
    throw InputError(urdf_path, 0, 0, "robot.name", "the robot's name holds a control character");
  }
  for (const JointSpec& j : chain.joints) {
    if (!xml_detail::xml_writable(j.name)) throw InputError(urdf_path, 0, 0, "joint.name", "a joint's name holds a control character");
  }
  xml_detail::XmlWriter xml;
  xml.open("mujoco", {{"model", model->getName() + "_from_urdf"}});
  xml.leaf("compiler", {{"angle", "radian"}, {"autolimits", "true"}});
  xml.leaf("option", {{"timestep", "0.000125"}, {"integrator", "Euler"}});
  xml.open("visual");
  xml.leaf("global", {{"offwidth", "1280"}, {"offheight", "720"}});
  xml.leaf("headlight", {{"ambient", "0.35 0.35 0.35"}, {"diffuse", "0.45 0.45 0.45"}, {"specular", "0.1 0.1 0.1"}});
  xml.close();
  xml.open("asset");
  xml.leaf("texture", {{"name", "sky"}, {"type", "skybox"}, {"builtin", "gradient"}, {"rgb1", "0.78 0.84 0.9"},
                       {"rgb2", "0.32 0.36 0.42"}, {"width", "256"}, {"height", "256"}});
  xml.leaf("texture", {{"name", "grid"}, {"type", "2d"}, {"builtin", "checker"}, {"rgb1", "0.86 0.86 0.84"},
                       {"rgb2", "0.76 0.76 0.74"}, {"width", "512"}, {"height", "512"}});
  xml.leaf("material", {{"name", "floor"}, {"texture", "grid"}, {"texrepeat", "10 10"}, {"texuniform", "true"}});
  xml.leaf("material", {{"name", "link"}, {"rgba", "0.55 0.6 0.7 1"}});
  xml.close();
  xml.open("default");
  xml.leaf("geom", {{"contype", "0"}, {"conaffinity", "0"}, {"material", "link"}});
  xml.close();
  xml.open("worldbody");
  xml.leaf("light", {{"name", "sun"}, {"directional", "true"}, {"pos", "0 0 4"}, {"dir", "-0.3 0.25 -1"},
                     {"diffuse", "0.6 0.6 0.6"}});
  const std::string floor = format_value(2 * reach);
  xml.leaf("geom", {{"name", "floor"}, {"type", "plane"}, {"size", floor + " " + floor + " 0.05"}, {"material", "floor"}});
  // the camera in front of the arm, to its right and above, looking at the middle of its reach
  const Vec3 eye(1.6 * reach, -1.0 * reach, 1.1 * reach);
  const Vec3 target(0.3 * reach, 0, 0.35 * reach);
  const Vec3 forward = (target - eye).normalized();
  const Vec3 right = forward.cross(Vec3::UnitZ()).normalized();
  const Vec3 up = right.cross(forward);
  xml.leaf("camera", {{"name", "overview"}, {"pos", numbers(eye)}, {"xyaxes", numbers(right) + " " + numbers(up)}, {"fovy", "45"}});
  // the fixed base: from the base frame to the first joint
  if (chain.joints[0].origin.translation().norm() > 1e-3) {
    xml.leaf("geom", {{"name", "base"}, {"type", "capsule"}, {"fromto", "0 0 0 " + numbers(chain.joints[0].origin.translation())},
                      {"size", num(1.5 * kRodRadius)}});
  }
  for (std::size_t i = 0; i < 6; ++i) {
    const JointSpec& j = chain.joints[i];
    const Inertia& b = body[i];
    xml.open("body", {{"name", j.name + "_body"}, {"pos", numbers(j.origin.translation())}, {"quat", quaternion(j.origin)}});
    const std::string range = std::isfinite(j.lower) && std::isfinite(j.upper) ? num(j.lower) + " " + num(j.upper) : "";
    if (range.empty()) {
      xml.leaf("joint", {{"name", j.name}, {"type", "hinge"}, {"axis", numbers(j.axis.normalized())},
                         {"damping", num(damping[i])}, {"frictionloss", num(friction[i])}, {"armature", num(armature[i])}});
    } else {
      xml.leaf("joint", {{"name", j.name}, {"type", "hinge"}, {"axis", numbers(j.axis.normalized())}, {"range", range},
                         {"damping", num(damping[i])}, {"frictionloss", num(friction[i])}, {"armature", num(armature[i])}});
    }
    const Mat3& I = b.tensor;
    xml.leaf("inertial", {{"pos", numbers(b.centre)},
                          {"mass", num(b.mass)},
                          {"fullinertia", num(I(0, 0)) + " " + num(I(1, 1)) + " " + num(I(2, 2)) + " " + num(I(0, 1)) + " " +
                                              num(I(0, 2)) + " " + num(I(1, 2))}});
    if (extent[i].norm() > 1e-3) {
      xml.leaf("geom", {{"type", "capsule"}, {"fromto", "0 0 0 " + numbers(extent[i])}, {"size", num(kRodRadius)}});
    } else {
      xml.leaf("geom", {{"type", "sphere"}, {"size", format_value(0.6 * kRodRadius)}});
    }
  }
  xml.leaf("site", {{"name", "tcp"}, {"pos", numbers(chain.tcp.translation())}, {"quat", quaternion(chain.tcp)},
                    {"size", "0.008"}, {"rgba", "0.9 0.15 0.1 1"}});
  for (std::size_t i = 0; i < 6; ++i) xml.close();
  xml.close();  // worldbody
  xml.open("actuator");
  for (const JointSpec& j : chain.joints) {
    xml.leaf("motor", {{"name", j.name}, {"joint", j.name}, {"gear", "1"},
                       {"ctrlrange", num(-j.effort_limit) + " " + num(j.effort_limit)}});
  }
  xml.close();
  std::string velocity_limits;
  for (std::size_t i = 0; i < 6; ++i) {
    if (i > 0) velocity_limits += ' ';  // appended apart: " " + num(...) drew GCC 12's -Wrestrict false positive
    velocity_limits += num(chain.joints[i].velocity_limit);
  }
  xml.open("custom");
  xml.leaf("numeric", {{"name", "velocity_limits"}, {"data", velocity_limits}});
  xml.close();
  xml.close();  // mujoco
  out.mjcf = xml.text();
  return out;
}

}  // namespace blendbench
