#include "blendbench/io/urdf_chain.hpp"

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>

#include "blendbench/core/format.hpp"
#include "blendbench/core/input_error.hpp"

namespace blendbench {
namespace {

// Collects what urdfdom reports through console_bridge while it parses, so the InputError can
// carry urdfdom's reason instead of leaving it on stderr; restores the previous handler.
class CapturedLog : public console_bridge::OutputHandler {
 public:
  CapturedLog() : previous_(console_bridge::getOutputHandler()) { console_bridge::useOutputHandler(this); }
  ~CapturedLog() override { console_bridge::useOutputHandler(previous_); }
  CapturedLog(const CapturedLog&) = delete;
  CapturedLog& operator=(const CapturedLog&) = delete;

  void log(const std::string& text, console_bridge::LogLevel level, const char* /*filename*/, int /*line*/) override {
    if (level < console_bridge::CONSOLE_BRIDGE_LOG_WARN) return;
    if (!text_.empty()) text_ += "; ";
    text_ += text;
  }
  [[nodiscard]] const std::string& text() const { return text_; }

 private:
  console_bridge::OutputHandler* previous_;
  std::string text_;
};

Eigen::Isometry3d to_isometry(const urdf::Pose& pose) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::Quaterniond(pose.rotation.w, pose.rotation.x, pose.rotation.y, pose.rotation.z)
                   .normalized()
                   .toRotationMatrix();
  t.translation() << pose.position.x, pose.position.y, pose.position.z;
  return t;
}

// One revolute or continuous joint with its limits checked.
JointSpec to_joint_spec(const std::string& path, const urdf::Joint& joint, const Eigen::Isometry3d& origin) {
  const auto fail = [&](const std::string& what) { throw InputError(path, 0, 0, joint.name, what); };
  JointSpec spec;
  spec.name = joint.name;
  spec.origin = origin;
  spec.axis = Vec3(joint.axis.x, joint.axis.y, joint.axis.z);
  if (!(spec.axis.norm() > 1e-9)) fail("the joint axis is zero");
  spec.axis.normalize();
  if (joint.mimic) fail("mimic joints are not supported");
  if (!joint.limits) fail("the joint has no <limit> (velocity and effort are needed)");
  if (joint.type == urdf::Joint::CONTINUOUS) {
    spec.lower = -std::numeric_limits<double>::infinity();
    spec.upper = std::numeric_limits<double>::infinity();
  } else {
    spec.lower = joint.limits->lower;
    spec.upper = joint.limits->upper;
    if (!(spec.lower <= spec.upper)) {
      fail("lower limit " + format_value(spec.lower) + " rad is above upper limit " + format_value(spec.upper) + " rad");
    }
  }
  spec.velocity_limit = joint.limits->velocity;
  spec.effort_limit = joint.limits->effort;
  if (!(spec.velocity_limit > 0)) fail("velocity limit must be positive, got " + format_value(spec.velocity_limit) + " rad/s");
  if (!(spec.effort_limit > 0)) fail("effort limit must be positive, got " + format_value(spec.effort_limit) + " N*m");
  return spec;
}

}  // namespace

KinematicChain load_urdf_chain(const std::string& path, const std::string& base_link, const std::string& tip_link) {
  // read and parse the file
  std::ifstream file(path);
  if (!file) throw InputError(path, 0, 0, "", "cannot open the URDF file");
  std::stringstream text;
  text << file.rdbuf();
  urdf::ModelInterfaceSharedPtr model;
  {
    const CapturedLog log;
    model = urdf::parseURDF(text.str());
    if (!model) throw InputError(path, 0, 0, "", "not a valid URDF: " + (log.text().empty() ? "parse failed" : log.text()));
  }
  if (!model->getLink(base_link)) throw InputError(path, 0, 0, "base_link", "no link named '" + base_link + "'");
  if (!model->getLink(tip_link)) throw InputError(path, 0, 0, "tip_link", "no link named '" + tip_link + "'");

  // the joints from the tip up to the base, then in base-to-tip order
  std::vector<urdf::JointConstSharedPtr> joints;
  urdf::LinkConstSharedPtr link = model->getLink(tip_link);
  while (link && link->name != base_link) {
    if (!link->parent_joint) break;
    joints.push_back(link->parent_joint);
    link = link->getParent();
  }
  if (!link || link->name != base_link) {
    throw InputError(path, 0, 0, "tip_link", "link '" + tip_link + "' is not below link '" + base_link + "'");
  }
  std::reverse(joints.begin(), joints.end());

  // fold fixed joints into the next movable joint's origin, or into the TCP after the last one
  KinematicChain chain;
  Eigen::Isometry3d pending = Eigen::Isometry3d::Identity();
  for (const urdf::JointConstSharedPtr& joint : joints) {
    const Eigen::Isometry3d origin = pending * to_isometry(joint->parent_to_joint_origin_transform);
    switch (joint->type) {
      case urdf::Joint::FIXED: pending = origin; break;
      case urdf::Joint::REVOLUTE:
      case urdf::Joint::CONTINUOUS:
        chain.joints.push_back(to_joint_spec(path, *joint, origin));
        pending = Eigen::Isometry3d::Identity();
        break;
      default:
        throw InputError(path, 0, 0, joint->name, "only revolute, continuous and fixed joints are supported");
    }
  }
  chain.tcp = pending;
  if (chain.joints.size() != 6) {
    throw InputError(path, 0, 0, "tip_link",
                     "the chain from '" + base_link + "' to '" + tip_link + "' has " +
                         std::to_string(chain.joints.size()) + " movable joints; a six-axis arm needs 6");
  }
  return chain;
}

}  // namespace blendbench
