#pragma once
// Private to io: parsing a URDF with urdfdom and finding the serial chain in it, shared by the
// chain reader (urdf_chain.cpp) and the MuJoCo model builder (urdf_model.cpp).

#include <urdf_model/model.h>
#include <urdf_parser/urdf_parser.h>

#include <string>
#include <vector>

#include "blendbench/robot/kinematics.hpp"

namespace blendbench::urdf_read {

// The parsed model; throws InputError (file = path) when the file cannot be read or is not a
// valid URDF (with urdfdom's reason).
urdf::ModelInterfaceSharedPtr parse(const std::string& path);

// The chain's end links and its joints from base to tip. An empty base is the URDF's root link;
// an empty tip is the leaf (a link without children) below the base reached through the most
// movable joints (among frame links fixed to one body that tie, `tool0`). Throws InputError
// naming the field ("base_link", "tip_link") for a missing link, a tip not below the base, or no
// tip and several leaves that tie (listing them).
struct ChainPath {
  std::string base, tip;
  std::vector<urdf::JointConstSharedPtr> joints;
};
ChainPath find_chain(const urdf::ModelInterface& model, const std::string& path, const std::string& base,
                     const std::string& tip);

// The pose of a URDF origin as an isometry.
Eigen::Isometry3d to_isometry(const urdf::Pose& pose);

// The KinematicChain of a chain path: one JointSpec per revolute or continuous joint, fixed
// joints folded into the next joint's origin or the TCP. Throws InputError (file = path, field =
// the joint's name) for an unsupported joint type, a mimic joint, a zero axis, a missing
// <limit>, lower > upper, a velocity limit <= 0, or (when require_effort) an effort limit <= 0;
// with require_effort false such a joint keeps its effort (<= 0) for the caller to estimate;
// and (field "tip_link") when the chain does not have six movable joints.
KinematicChain chain_of(const std::string& path, const ChainPath& chain_path, bool require_effort);

}  // namespace blendbench::urdf_read
