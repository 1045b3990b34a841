#pragma once
// A six-joint test arm with UR5e-like link lengths, masses and torque limits, written inline so
// the sim tests and benchmarks do not depend on models/. The zero pose points the arm straight
// up; test_arm_bent_pose() loads every gravity-bearing joint.

#include <Eigen/Core>

namespace blendbench::test {

inline constexpr const char* kTestArmXml = R"(
<mujoco model="test_arm">
  <compiler angle="radian" autolimits="true"/>
  <option timestep="0.001" integrator="Euler"/>
  <visual>
    <global offwidth="640" offheight="480"/>
    <headlight ambient="0.35 0.35 0.35" diffuse="0.5 0.5 0.5"/>
  </visual>
  <asset>
    <texture name="grid" type="2d" builtin="checker" rgb1="0.25 0.28 0.32" rgb2="0.18 0.2 0.23" width="256" height="256"/>
    <material name="grid" texture="grid" texrepeat="6 6"/>
  </asset>
  <default>
    <joint armature="0.05"/>
    <geom type="capsule" rgba="0.75 0.78 0.82 1" contype="0" conaffinity="0"/>
    <default class="wrist">
      <joint armature="0.02"/>
      <geom rgba="0.2 0.45 0.8 1"/>
    </default>
  </default>
  <worldbody>
    <light directional="true" pos="0 0 3" dir="0 0 -1" diffuse="0.6 0.6 0.6"/>
    <geom name="floor" type="plane" size="1.5 1.5 0.05" material="grid" contype="1" conaffinity="1"/>
    <camera name="overview" pos="1.3 -1.3 1.1" xyaxes="0.707 0.707 0 -0.236 0.236 0.943"/>
    <body name="base">
      <geom type="cylinder" size="0.075 0.04" pos="0 0 0.04" rgba="0.3 0.3 0.3 1"/>
      <body name="shoulder" pos="0 0 0.1625">
        <joint name="shoulder_pan" axis="0 0 1" range="-6.2832 6.2832"/>
        <inertial pos="0 0 0" mass="3.7" diaginertia="0.0103 0.0103 0.0067"/>
        <geom type="cylinder" size="0.06 0.07" pos="0 0 -0.05"/>
        <body name="upper_arm" pos="0 0.138 0">
          <joint name="shoulder_lift" axis="0 1 0" range="-6.2832 6.2832"/>
          <inertial pos="0 0 0.2125" mass="8.393" diaginertia="0.134 0.134 0.0151"/>
          <geom fromto="0 0 0 0 0 0.425" size="0.054"/>
          <body name="forearm" pos="0 -0.131 0.425">
            <joint name="elbow" axis="0 1 0" range="-3.1416 3.1416"/>
            <inertial pos="0 0 0.196" mass="2.275" diaginertia="0.0312 0.0312 0.004"/>
            <geom fromto="0 0 0 0 0 0.392" size="0.04"/>
            <body name="wrist_1" pos="0 0 0.392" childclass="wrist">
              <joint name="wrist_1" axis="0 1 0" range="-6.2832 6.2832"/>
              <inertial pos="0 0.127 0" mass="1.219" diaginertia="0.0025 0.0021 0.0025"/>
              <geom fromto="0 0 0 0 0.127 0" size="0.035"/>
              <body name="wrist_2" pos="0 0.127 0">
                <joint name="wrist_2" axis="0 0 1" range="-6.2832 6.2832"/>
                <inertial pos="0 0 0.1" mass="1.219" diaginertia="0.0025 0.0025 0.0021"/>
                <geom fromto="0 0 0 0 0 0.1" size="0.035"/>
                <body name="wrist_3" pos="0 0 0.1">
                  <joint name="wrist_3" axis="0 1 0" range="-6.2832 6.2832"/>
                  <inertial pos="0 0.05 0" mass="0.1879" diaginertia="0.0001 0.00013 0.0001"/>
                  <geom fromto="0 0 0 0 0.1 0" size="0.03" rgba="0.9 0.5 0.1 1"/>
                  <site name="tcp" pos="0 0.1 0" size="0.01"/>
                </body>
              </body>
            </body>
          </body>
        </body>
      </body>
    </body>
  </worldbody>
  <actuator>
    <motor name="shoulder_pan" joint="shoulder_pan" ctrlrange="-150 150"/>
    <motor name="shoulder_lift" joint="shoulder_lift" ctrlrange="-150 150"/>
    <motor name="elbow" joint="elbow" ctrlrange="-150 150"/>
    <motor name="wrist_1" joint="wrist_1" ctrlrange="-28 28"/>
    <motor name="wrist_2" joint="wrist_2" ctrlrange="-28 28"/>
    <motor name="wrist_3" joint="wrist_3" ctrlrange="-28 28"/>
  </actuator>
</mujoco>
)";

// A pose with every gravity-bearing joint loaded (rad).
inline Eigen::Matrix<double, 6, 1> test_arm_bent_pose() {
  Eigen::Matrix<double, 6, 1> q;
  q << 0.3, -0.9, 1.4, -0.6, 0.4, 0.2;
  return q;
}

}  // namespace blendbench::test
