#include "blendbench/sim/workspace.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

namespace blendbench {
namespace {

// A vertical axis within this (|z component| of the unit axis >= 1 - kVertical).
constexpr double kVertical = 1e-6;

}  // namespace

KeepOut keep_out_of(const mjModel& m, double clearance) {
  KeepOut zones;
  zones.floor_clearance = clearance;
  const std::unique_ptr<mjData, void (*)(mjData*)> d(mj_makeData(&m), mj_deleteData);
  mj_kinematics(&m, d.get());

  // the floor: the highest world plane facing up (geom_xmat is row-major, its z column the normal)
  for (int g = 0; g < m.ngeom; ++g) {
    if (m.geom_bodyid[g] != 0 || m.geom_type[g] != mjGEOM_PLANE) continue;
    const double nz = d->geom_xmat[9 * g + 8];
    if (nz >= 1 - kVertical) zones.floor_z = std::max(zones.floor_z, d->geom_xpos[3 * g + 2]);
  }

  // the first arm joint: the lowest-numbered joint an actuator drives
  int first = -1;
  for (int a = 0; a < m.nu; ++a) {
    if (m.actuator_trntype[a] != mjTRN_JOINT) continue;
    const int j = m.actuator_trnid[2 * a];
    if (first < 0 || j < first) first = j;
  }
  if (first < 0 || m.jnt_type[first] != mjJNT_HINGE) return zones;
  const double* axis = d->xaxis + 3 * first;
  if (std::abs(axis[2]) < 1 - kVertical) return zones;
  zones.axis_x = d->xanchor[3 * first];
  zones.axis_y = d->xanchor[3 * first + 1];

  // the bodies from the world down to the first joint's: they stay in place or turn about it
  std::vector<char> base_body(static_cast<std::size_t>(m.nbody), 0);
  for (int b = m.jnt_bodyid[first]; b > 0; b = m.body_parentid[b]) base_body[static_cast<std::size_t>(b)] = 1;
  for (int g = 0; g < m.ngeom; ++g) {
    if (base_body[static_cast<std::size_t>(m.geom_bodyid[g])] == 0 || m.geom_type[g] == mjGEOM_PLANE) continue;
    const double* c = d->geom_xpos + 3 * g;
    const double r = m.geom_rbound[g];
    zones.base_radius = std::max(zones.base_radius, std::hypot(c[0] - zones.axis_x, c[1] - zones.axis_y) + r);
    zones.base_top = std::max(zones.base_top, c[2] + r);
  }
  return zones;
}

WorkspaceReport check_workspace(const Trace& trace, const KeepOut& zones) {
  WorkspaceReport report;
  for (const TraceSample& s : trace.samples) {
    for (const Eigen::Vector3d* p : {&s.tcp_cmd, &s.tcp}) {
      const double z = p->z();
      report.tcp_z_min = std::min(report.tcp_z_min, z);
      if (z < zones.floor_z + zones.floor_clearance && !report.below_floor) {
        report.below_floor = true;
        report.below_floor_t = s.t;
      }
      if (zones.base_radius > 0 && z < zones.base_top) {
        const double r = std::hypot(p->x() - zones.axis_x, p->y() - zones.axis_y);
        report.base_distance_min = std::min(report.base_distance_min, r);
        if (r < zones.base_radius && !report.into_base) {
          report.into_base = true;
          report.into_base_t = s.t;
        }
      }
    }
  }
  return report;
}

}  // namespace blendbench
