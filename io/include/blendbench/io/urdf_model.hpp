#pragma once
// A MuJoCo model (MJCF text) built from a URDF alone, for arms that come without one: the chain
// from base_link to tip_link as bodies with the URDF's frames, axes, limits, masses and
// inertias, rigid joints with the URDF's <dynamics> damping and friction and a rotor inertia
// (MuJoCo's armature, which a URDF never states) equal to the link inertia each joint moves at
// the URDF's zero pose (inertia-matched drives), a direct-torque motor
// per joint at the URDF's effort limit, site "tcp" at the chain's end, a floor, a light and a
// camera that frames the arm. The links are drawn as capsules between the joints (URDF meshes,
// often package:// paths, are not read).
//
// Kinematics-only URDFs (no <inertial>, effort 0, as ROS-Industrial's descriptions ship them)
// are refused unless an estimate is asked for (total_mass > 0). The estimate, stated in notes:
//   mass      total_mass shared over the moving links without <inertial> in proportion to their
//             length (the distance to the next joint or to the tip, at least kMinLinkLength);
//   inertia   each such link a uniform solid rod of radius kRodRadius centred halfway from its
//             joint to the next one, along them, of length l = that distance but at least
//             kMinLinkLength (zero-length links and coincident frames, as ROS-Industrial wrists
//             have them, keep a valid inertia; without direction it lies along the link's z):
//             I_axis = m r^2 / 2, I_across = m (3 r^2 + l^2) / 12 about its centre;
//   effort    for a joint with effort <= 0: kEffortMargin times a bound of the gravity torque
//             the outboard links exert in any configuration (g times the sum over them of mass
//             times the length of the chain of offsets from the joint to their centre, which no
//             configuration's distance exceeds), at least kMinEffort.

#include <string>
#include <vector>

#include "blendbench/robot/kinematics.hpp"

namespace blendbench {

inline constexpr double kMinLinkLength = 0.05;  // m
inline constexpr double kRodRadius = 0.04;      // m: the rod of an estimated link
inline constexpr double kEffortMargin = 2.0;    // torque limit over the static gravity bound
inline constexpr double kMinEffort = 5.0;       // N*m

struct UrdfModel {
  std::string mjcf;                 // the MJCF text
  KinematicChain chain;             // the chain, effort limits as the motors have them
  std::vector<std::string> notes;   // what was estimated or left out, one line each
};

// Throws InputError (file = urdf_path) as load_urdf_chain does, and, without an estimate, one
// naming every moving link without <inertial> (field "inertial") or else every joint whose
// effort is not positive (field "effort"), with the key that estimates them.
UrdfModel model_from_urdf(const std::string& urdf_path, const std::string& base_link, const std::string& tip_link,
                          double total_mass);

}  // namespace blendbench
