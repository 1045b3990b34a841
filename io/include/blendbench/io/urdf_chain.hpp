#pragma once
// Reads a URDF file into the planner's KinematicChain. Part of the edge library blendbench::io:
// urdfdom appears only here, so the planner stays Eigen-only.

#include <string>

#include "blendbench/robot/kinematics.hpp"

namespace blendbench {

// The serial chain from `base_link` to `tip_link` of the URDF at `path` (an empty base_link is the
// URDF's root link, an empty tip_link the leaf below the base reached through the most movable
// joints: `tool0` in ROS-Industrial files, whose `base` and `flange` frame links on fixed joints
// are passed over): one JointSpec per revolute or continuous joint, in order from the base, with every fixed joint folded into the
// next joint's origin (or into the TCP transform after the last joint). Limits come from each
// joint's <limit> (rad, rad/s, N*m); a continuous joint gets lower/upper = -+infinity.
//
// Throws InputError with file = path when the file cannot be read or is not a valid URDF (the
// message carries urdfdom's reason), a link is missing, tip_link is not below base_link, a joint
// on the way is not revolute, continuous or fixed (or is a mimic joint), a limit is missing or
// inconsistent (lower > upper, velocity or effort <= 0), an axis is zero, the chain does not
// have exactly six movable joints, or tip_link is empty and several leaves tie (field
// "tip_link", the message lists them; frame links fixed to one body are no tie when one of them
// is `tool0`). Not thread-safe: it swaps console_bridge's global log handler while parsing.
KinematicChain load_urdf_chain(const std::string& path, const std::string& base_link = "",
                               const std::string& tip_link = "");

}  // namespace blendbench
