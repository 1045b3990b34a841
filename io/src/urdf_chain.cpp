#include "blendbench/io/urdf_chain.hpp"

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <limits>

#include "blendbench/core/format.hpp"
#include "blendbench/core/input_error.hpp"
#include "blendbench/core/input_file.hpp"
#include "urdf_read.hpp"
#include "xml_check.hpp"

namespace blendbench {
namespace urdf_read {
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

// One revolute or continuous joint with its limits checked.
JointSpec to_joint_spec(const std::string& path, const urdf::Joint& joint, const Eigen::Isometry3d& origin,
                        bool require_effort) {
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
  if (require_effort && !(spec.effort_limit > 0)) {
    fail("effort limit must be positive, got " + format_value(spec.effort_limit) +
         " N*m (a kinematics-only URDF: robot.estimate_inertia estimates it)");
  }
  return spec;
}

// A leaf (a link without children) at or below the chain's base, with how many movable joints
// lead to it from the base and the last link one of them moves (the body it is fixed to).
struct Leaf {
  std::string name;
  int movable = 0;
  std::string body;
};

// The leaves at or below `link`, in the file's order; `movable` and `body` are the link's own.
void collect_leaves(const urdf::Link& link, int movable, const std::string& body, std::vector<Leaf>& out) {
  if (link.child_links.empty()) out.push_back({link.name, movable, body});
  for (const urdf::LinkSharedPtr& child : link.child_links) {
    const bool moves = child->parent_joint && child->parent_joint->type != urdf::Joint::FIXED;
    collect_leaves(*child, movable + (moves ? 1 : 0), moves ? child->name : body, out);
  }
}

// The chain's end when the scenario names none: the leaf reached through the most movable
// joints. ROS-Industrial descriptions hang frame links on fixed joints beside the chain (`base`
// on base_link, `flange` and `tool0` on the last link): fewer movable joints lead to them, so
// they are not candidates. Leaves that tie and are all fixed to one body are frames of it: the
// one named `tool0` (REP 199, the tool-mounting frame of ROS-Industrial arms) is the end, else
// the tie is an error naming them, as is a tie between branches that move apart (two fingers).
std::string default_tip(const urdf::Link& base, const std::string& path) {
  std::vector<Leaf> leaves;
  collect_leaves(base, 0, base.name, leaves);
  int most = 0;
  for (const Leaf& leaf : leaves) most = std::max(most, leaf.movable);
  std::vector<const Leaf*> candidates;
  for (const Leaf& leaf : leaves) {
    if (leaf.movable == most) candidates.push_back(&leaf);
  }
  if (candidates.size() == 1) return candidates.front()->name;
  const bool one_body = std::all_of(candidates.begin(), candidates.end(),
                                    [&](const Leaf* leaf) { return leaf->body == candidates.front()->body; });
  if (one_body) {
    for (const Leaf* leaf : candidates) {
      if (leaf->name == "tool0") return leaf->name;
    }
  }
  std::string list;
  for (const Leaf* leaf : candidates) list += (list.empty() ? "'" : ", '") + leaf->name + "'";
  throw InputError(path, 0, 0, "tip_link",
                   "the URDF branches below '" + base.name + "' into " + std::to_string(candidates.size()) +
                       " ends reached through " + std::to_string(most) + " movable joints each (" + list +
                       "): name the chain's end with robot.tip_link");
}

}  // namespace

urdf::ModelInterfaceSharedPtr parse(const std::string& path) {
  // read as every input is (a regular file of at most kMaxInputBytes: a 1.5 GB URDF was read
  // whole), then checked by expat before urdfdom's recursive parser sees it
  const std::string text = read_input_file(path, "URDF file");
  xml_detail::check_xml(text, path, "URDF file", xml_detail::XmlLimits{});
  const CapturedLog log;
  urdf::ModelInterfaceSharedPtr model;
  try {
    model = urdf::parseURDF(text);
  } catch (...) {
    // urdfdom's own exceptions (a number it cannot convert) are bad input of the URDF
    rethrow_as_input_error({path, 0, 0}, "", "not a valid URDF: ");
  }
  if (!model) throw InputError(path, 0, 0, "", "not a valid URDF: " + (log.text().empty() ? "parse failed" : log.text()));
  return model;
}

Eigen::Isometry3d to_isometry(const urdf::Pose& pose) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::Quaterniond(pose.rotation.w, pose.rotation.x, pose.rotation.y, pose.rotation.z)
                   .normalized()
                   .toRotationMatrix();
  t.translation() << pose.position.x, pose.position.y, pose.position.z;
  return t;
}

ChainPath find_chain(const urdf::ModelInterface& model, const std::string& path, const std::string& base,
                     const std::string& tip) {
  ChainPath out;
  // the base: the given link, else the root
  out.base = base.empty() ? model.getRoot()->name : base;
  const urdf::LinkConstSharedPtr base_link = model.getLink(out.base);
  if (!base_link) throw InputError(path, 0, 0, "base_link", "no link named '" + out.base + "'");
  // the tip: the given link, else the leaf reached through the most movable joints
  out.tip = tip.empty() ? default_tip(*base_link, path) : tip;
  if (!model.getLink(out.tip)) throw InputError(path, 0, 0, "tip_link", "no link named '" + out.tip + "'");

  // the joints from the tip up to the base, then in base-to-tip order
  urdf::LinkConstSharedPtr link = model.getLink(out.tip);
  while (link && link->name != out.base) {
    if (!link->parent_joint) break;
    out.joints.push_back(link->parent_joint);
    link = link->getParent();
  }
  if (!link || link->name != out.base) {
    throw InputError(path, 0, 0, "tip_link", "link '" + out.tip + "' is not below link '" + out.base + "'");
  }
  std::reverse(out.joints.begin(), out.joints.end());
  return out;
}

KinematicChain chain_of(const std::string& path, const ChainPath& chain_path, bool require_effort) {
  // fold fixed joints into the next movable joint's origin, or into the TCP after the last one
  KinematicChain chain;
  Eigen::Isometry3d pending = Eigen::Isometry3d::Identity();
  for (const urdf::JointConstSharedPtr& joint : chain_path.joints) {
    const Eigen::Isometry3d origin = pending * to_isometry(joint->parent_to_joint_origin_transform);
    switch (joint->type) {
      case urdf::Joint::FIXED: pending = origin; break;
      case urdf::Joint::REVOLUTE:
      case urdf::Joint::CONTINUOUS:
        chain.joints.push_back(to_joint_spec(path, *joint, origin, require_effort));
        pending = Eigen::Isometry3d::Identity();
        break;
      default:
        throw InputError(path, 0, 0, joint->name, "only revolute, continuous and fixed joints are supported");
    }
  }
  chain.tcp = pending;
  if (chain.joints.size() != 6) {
    throw InputError(path, 0, 0, "tip_link",
                     "the chain from '" + chain_path.base + "' to '" + chain_path.tip + "' has " +
                         std::to_string(chain.joints.size()) + " movable joints; a six-axis arm needs 6");
  }
  return chain;
}

}  // namespace urdf_read

KinematicChain load_urdf_chain(const std::string& path, const std::string& base_link, const std::string& tip_link) {
  const urdf::ModelInterfaceSharedPtr model = urdf_read::parse(path);
  return urdf_read::chain_of(path, urdf_read::find_chain(*model, path, base_link, tip_link), true);
}

}  // namespace blendbench
