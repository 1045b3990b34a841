#include "blendbench/sim/workspace.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "support/property.hpp"

namespace blendbench {
namespace {

// models/ur5e_like.xml: the floor plane at z = 0; the base cylinder (radius 75 mm, 0-90 mm) and
// the shoulder (a cylinder of radius 60 mm from 90 to 217.5 mm, and a horizontal cap cylinder of
// radius 60 mm from y = -75 to 60 mm at z = 162.5 mm) under the first joint's vertical axis at the
// origin. Each geom's bounding sphere (radius sqrt(r^2 + h^2), h the half-length) bounds the zone:
// the cap's, 7.5 mm off the axis with radius sqrt(0.06^2 + 0.0675^2), is the widest and highest.
TEST(Workspace, KeepOutZonesOfTheArmModel) {
  const Simulator sim(test::source_path("models/ur5e_like.xml"));
  const KeepOut zones = keep_out_of(sim.model(), 0.01);
  EXPECT_DOUBLE_EQ(zones.floor_z, 0.0);
  EXPECT_DOUBLE_EQ(zones.floor_clearance, 0.01);
  EXPECT_NEAR(zones.axis_x, 0.0, 1e-12);
  EXPECT_NEAR(zones.axis_y, 0.0, 1e-12);
  const double cap_rbound = std::hypot(0.06, 0.0675);
  EXPECT_NEAR(zones.base_radius, 0.0075 + cap_rbound, 1e-6);
  EXPECT_NEAR(zones.base_top, 0.1625 + cap_rbound, 1e-6);
  // it covers the base itself
  EXPECT_GT(zones.base_radius, 0.075);
}

TEST(Workspace, ReportsTheFirstSampleBelowTheFloorAndInsideTheBase) {
  KeepOut zones;
  zones.floor_z = 0.0;
  zones.floor_clearance = 0.005;
  zones.base_radius = 0.1;
  zones.base_top = 0.25;
  Trace trace;
  const auto sample = [&](double t, Eigen::Vector3d cmd, Eigen::Vector3d act) {
    TraceSample s;
    s.q_cmd = s.qd_cmd = s.q = s.qd = s.tau = JointVector::Zero();
    s.t = t;
    s.tcp_cmd = cmd;
    s.tcp = act;
    trace.samples.push_back(s);
  };
  sample(0.0, {0.5, 0, 0.3}, {0.5, 0, 0.3});
  sample(0.1, {0.5, 0, 0.006}, {0.5, 0, 0.006});    // above the clearance
  sample(0.2, {0.5, 0, 0.006}, {0.5, 0, 0.004});    // the actual TCP dips into the clearance
  sample(0.3, {0.2, 0, 0.2}, {0.2, 0, 0.2});        // low, but outside the base
  sample(0.4, {0.09, 0.0, 0.3}, {0.09, 0.0, 0.3});  // above the base: not inside
  sample(0.5, {0.06, 0.08, 0.2}, {0.07, 0.08, 0.2});  // 100 mm / 106 mm from the axis
  sample(0.6, {0.05, 0.0, 0.1}, {0.05, 0.0, 0.1});  // inside
  WorkspaceReport report = check_workspace(trace, zones);
  EXPECT_TRUE(report.below_floor);
  EXPECT_DOUBLE_EQ(report.below_floor_t, 0.2);
  EXPECT_DOUBLE_EQ(report.tcp_z_min, 0.004);
  EXPECT_TRUE(report.into_base);
  EXPECT_DOUBLE_EQ(report.into_base_t, 0.6);
  EXPECT_DOUBLE_EQ(report.base_distance_min, 0.05);

  // without the dips nothing is reported, and the distances say how close it came
  trace.samples.resize(5);
  trace.samples[2].tcp.z() = 0.006;
  report = check_workspace(trace, zones);
  EXPECT_FALSE(report.below_floor);
  EXPECT_TRUE(std::isnan(report.below_floor_t));
  EXPECT_FALSE(report.into_base);
  EXPECT_DOUBLE_EQ(report.base_distance_min, 0.2);

  // a model without a floor or a vertical first axis checks nothing
  report = check_workspace(trace, KeepOut{});
  EXPECT_FALSE(report.below_floor);
  EXPECT_FALSE(report.into_base);
}

}  // namespace
}  // namespace blendbench
