#pragma once
// Where the tool centre point must not go, though the simulation would let it: the model has no
// contacts (every arm geom has contype = conaffinity = 0), so a path through the floor or the
// robot's own base runs and is measured as if nothing were there. These checks report it.
//
// Two keep-out zones in the robot base frame (= MuJoCo's world frame, z up):
// - the floor: z below floor_z + floor_clearance;
// - the base: a vertical cylinder around the axis of the arm's first joint, from the floor up to
//   base_top, of radius base_radius.
// Both are derived from the model (keep_out_of) so they follow the MJCF.

#include <mujoco/mujoco.h>

#include <limits>

#include "blendbench/sim/simulator.hpp"

namespace blendbench {

struct KeepOut {
  double floor_z = -std::numeric_limits<double>::infinity();  // m; -inf: no floor in the model
  double floor_clearance = 0;  // m the TCP must stay above the floor (a tool's length, a margin)
  double axis_x = 0, axis_y = 0;  // m, where the base axis meets the floor plane
  double base_radius = 0;         // m; 0: no base zone
  double base_top = 0;            // m (z of the cylinder's top)
};

// The keep-out zones of a model of the arm (Simulator's conventions: six hinge joints in a
// chain). floor_z: the height of the highest world-attached plane geom whose normal is +z (the
// MJCF floor), -inf when there is none. The base: the cylinder about the first arm joint's axis
// (when that axis is vertical within 1e-6; otherwise base_radius = 0) that bounds the bounding
// spheres (geom_rbound) of every geom on the bodies from the world up to and including the
// first joint's body, at qpos0 — conservative: a few centimetres wider than the base itself.
// `clearance` (m, >= 0) becomes floor_clearance.
KeepOut keep_out_of(const mjModel& model, double clearance = 0);

// What a trace did with the keep-out zones, over the commanded and the actual TCP.
struct WorkspaceReport {
  double tcp_z_min = std::numeric_limits<double>::infinity();  // m, lowest TCP z (commanded or actual)
  // m, smallest horizontal distance of the TCP from the base axis while below base_top; +inf
  // when the TCP never is below base_top
  double base_distance_min = std::numeric_limits<double>::infinity();
  bool below_floor = false;  // some TCP z < floor_z + floor_clearance
  bool into_base = false;    // some TCP inside the base cylinder
  double below_floor_t = std::numeric_limits<double>::quiet_NaN();  // s, first sample below the floor
  double into_base_t = std::numeric_limits<double>::quiet_NaN();    // s, first sample in the base
};

// Checks every sample of `trace` (commanded and actual TCP) against `zones`.
WorkspaceReport check_workspace(const Trace& trace, const KeepOut& zones);

}  // namespace blendbench
