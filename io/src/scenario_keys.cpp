// The scenario format's table (scenario_keys.hpp) and the reference generated from it.

#include "blendbench/io/scenario_keys.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "blendbench/core/format.hpp"
#include "blendbench/geometry/arc_construction.hpp"
#include "blendbench/io/program_io.hpp"
#include "blendbench/io/scenario.hpp"
#include "yaml_document.hpp"

namespace blendbench {
namespace {

using K = KeyType;
using namespace key_units;  // the table names its units on most lines

constexpr std::string_view kBufferModes = "Aborting|Buffered|BlendingLow|BlendingPrevious|BlendingNext|BlendingHigh";
constexpr std::string_view kMethods = "none|arc|bezier|clothoid|biclothoid";

// Every key of a scenario file, one line each, grouped by the map it belongs to.
// clang-format off
constexpr std::array kKeys = {
    // the top level
    ScenarioKey{.map = "", .name = "name", .type = K::kText, .required = true, .meaning = "the scenario's name; it names the output folder (letters, digits, '_', '-', '.'; starting with a letter, digit or '_'; at most 100 characters)"},
    ScenarioKey{.map = "", .name = "description", .type = K::kText, .fallback = "\"\"", .meaning = "what the scenario shows, for the reader"},
    ScenarioKey{.map = "", .name = "units", .type = K::kChoice, .fallback = "mm", .choices = "mm|m", .meaning = "the unit of every length in the file (and of the lengths in every other unit)"},
    ScenarioKey{.map = "", .name = "frame", .type = K::kMap, .opens = "frame", .meaning = "where the program sits in the robot's base frame (default: at the base origin, unrotated)"},
    ScenarioKey{.map = "", .name = "robot", .type = K::kMap, .opens = "robot", .meaning = "the arm's models, tool and start configuration"},
    ScenarioKey{.map = "", .name = "servo", .type = K::kMap, .opens = "servo", .meaning = "the joint drives (the gains are tuned from the model at the start pose)"},
    ScenarioKey{.map = "", .name = "simulation", .type = K::kMap, .opens = "simulation", .meaning = "when the run counts as settled, and how vibration and jerk are measured"},
    ScenarioKey{.map = "", .name = "sensitivity", .type = K::kMap, .opens = "sensitivity", .meaning = "the perturbed arm models that `run --sensitivity` and `compare --sensitivity` re-run every variant on, one parameter at a time, to tell whether each conclusion survives the model's uncertainty (docs/sensitivity.md); each key a list of values, one model each, `[]` for none"},
    ScenarioKey{.map = "", .name = "video", .type = K::kMap, .opens = "video", .meaning = "the rendered video"},
    ScenarioKey{.map = "", .name = "limits", .type = K::kChoice, .fallback = "cartesian", .choices = "cartesian|path", .meaning = "what the limits bound: the TCP's speed, acceleration vector and jerk vector (cartesian), or the tangential values and the normal acceleration only, as seed 004 times a path (path; the paper reproductions)"},
    ScenarioKey{.map = "", .name = "axis_limits", .type = K::kMap, .opens = "axis_limits", .meaning = "limits per Cartesian axis of the program frame, as CNC users set them, on top of the vector limits (needs limits: cartesian)"},
    ScenarioKey{.map = "", .name = "timing", .type = K::kChoice, .fallback = "optimal", .choices = "optimal|seed004", .meaning = "the velocity planner: the minimum-time traversal of the blended path under every limit (optimal; docs/timing.md), or seed 004's S-curves under the caps of its eq. 25-27 (seed004; the paper reproductions); a variant may override it"},
    ScenarioKey{.map = "", .name = "defaults", .type = K::kMap, .opens = "defaults", .required = true, .meaning = "the limits and buffer mode of every move that does not set its own"},
    ScenarioKey{.map = "", .name = "program", .type = K::kMap, .opens = "program", .required = true, .meaning = "the path: a list of moves, or a G-code file"},
    ScenarioKey{.map = "", .name = "variants", .type = K::kList, .opens = "variant", .required = true, .meaning = "the settings to compare, each run and reported (at least one)"},

    ScenarioKey{.map = "axis_limits", .name = "a", .type = K::kNumbers, .count = 3, .unit = kAcceleration, .required = true, .range = kPositive, .meaning = "the acceleration limit of the x, y and z axes"},
    ScenarioKey{.map = "axis_limits", .name = "j", .type = K::kNumbers, .count = 3, .unit = kJerk, .required = true, .range = kPositive, .meaning = "the jerk limit of the x, y and z axes"},

    ScenarioKey{.map = "frame", .name = "origin", .type = K::kNumbers, .count = 3, .unit = kLength, .required = true, .meaning = "the program's origin in the base frame"},
    ScenarioKey{.map = "frame", .name = "rpy_deg", .type = K::kNumbers, .count = 3, .unit = kDegrees, .fallback = "[0, 0, 0]", .meaning = "the program's orientation: roll, pitch, yaw about the fixed x, y, z axes (as in URDF)"},

    ScenarioKey{.map = "robot", .name = "model", .type = K::kChoice, .fallback = "elastic", .choices = "elastic|rigid", .meaning = "the dynamics: elastic joints (gear stiffness and damping, models/ur5e_like.xml) or rigid ones (models/ur5e_like_rigid.xml)"},
    ScenarioKey{.map = "robot", .name = "urdf", .type = K::kFile, .fallback = "models/ur5e_like.urdf", .meaning = "the kinematic model (read with urdfdom)"},
    ScenarioKey{.map = "robot", .name = "mjcf", .type = K::kFile, .meaning = "a dynamic model of its own (MuJoCo MJCF); default: the URDF's own beside it (X.urdf: X.xml when elastic, X_rigid.xml when rigid), else one built from the URDF (a motor per joint at its effort limit, rigid joints, floor, lights, camera)"},
    ScenarioKey{.map = "robot", .name = "base_link", .type = K::kText, .fallback = "\"\"", .meaning = "the URDF link the chain starts at (empty: the URDF's root link)"},
    ScenarioKey{.map = "robot", .name = "tip_link", .type = K::kText, .fallback = "\"\"", .meaning = "the URDF link at the chain's end, the flange the tool is mounted on (empty: the leaf below base_link reached through the most movable joints, so frame links on fixed joints beside the chain such as base or flange are passed over and tool0 of ROS-Industrial files is found; an error naming them when several tie)"},
    ScenarioKey{.map = "robot", .name = "tip_site", .type = K::kText, .meaning = "an MJCF of your own without a URDF (robot.mjcf, no robot.urdf): the MJCF site at the chain's end, the TCP; the chain is read from the MJCF's bodies and joints, and its own actuators are replaced by direct-torque motors at their force range (named in the summary)"},
    ScenarioKey{.map = "robot", .name = "tip_body", .type = K::kText, .meaning = "as tip_site, the chain ending at this MJCF body's frame"},
    ScenarioKey{.map = "robot", .name = "tool_rpy_deg", .type = K::kNumbers, .count = 3, .unit = kDegrees, .fallback = "[180, 0, 0]", .meaning = "the fixed tool orientation in the base frame, roll, pitch, yaw (default: pointing down)"},
    ScenarioKey{.map = "robot", .name = "q_seed_deg", .type = K::kNumbers, .count = 6, .unit = kDegrees, .fallback = "[180, -90, 90, -90, -90, 0]", .meaning = "the joint angles that pick the inverse-kinematics branch at the start (the model's ready pose)"},
    ScenarioKey{.map = "robot", .name = "tool", .type = K::kMap, .opens = "tool", .meaning = "the tool mounted on the flange (tip_link): the path, every pose and every error are those of its centre point (default: none, the TCP is the flange)"},
    ScenarioKey{.map = "robot", .name = "allow_branch_change", .type = K::kBool, .fallback = "false", .meaning = "let the joint reference change IK branch (cross a shoulder, elbow or wrist singularity; reported) instead of refusing the run with the time and pose"},
    ScenarioKey{.map = "robot", .name = "estimate_inertia", .type = K::kMap, .opens = "estimate_inertia", .meaning = "for a kinematics-only URDF run without an MJCF: estimate the masses, inertias and torque limits the URDF lacks (stated in the summary)"},
    ScenarioKey{.map = "tool", .name = "offset", .type = K::kNumbers, .count = 3, .unit = kLength, .fallback = "[0, 0, 0]", .meaning = "the tool centre point in the flange frame"},
    ScenarioKey{.map = "tool", .name = "rpy_deg", .type = K::kNumbers, .count = 3, .unit = kDegrees, .fallback = "[0, 0, 0]", .meaning = "the tool frame's orientation in the flange frame: roll, pitch, yaw about the fixed x, y, z axes"},
    ScenarioKey{.map = "estimate_inertia", .name = "total_mass_kg", .type = K::kNumber, .unit = kKilograms, .required = true, .range = kPositive, .meaning = "the arm's moving mass, shared out over the links by their lengths"},

    ScenarioKey{.map = "servo", .name = "controller", .type = K::kChoice, .fallback = "cascade", .choices = "cascade|pd", .meaning = "the drive: the industrial cascade with every feed-forward, or the plain PD without feed-forward (sim/servo.hpp)"},
    ScenarioKey{.map = "servo", .name = "rate_hz", .type = K::kNumber, .unit = kHertz, .fallback = "2000", .range = {125, 8000}, .meaning = "the drives' cascade rate; its period must be a multiple of the model's physics step"},
    ScenarioKey{.map = "servo", .name = "setpoint_rate_hz", .type = K::kNumber, .unit = kHertz, .range = {125, 8000}, .meaning = "the reference (and timing) rate, at most rate_hz, which must be a whole multiple of it (default: 500, or rate_hz when 500 does not divide it)"},
    ScenarioKey{.map = "servo", .name = "measurement_delay_ticks", .type = K::kInteger, .fallback = "1", .range = {0, 100}, .meaning = "servo ticks between a measurement and its use"},
    ScenarioKey{.map = "servo", .name = "encoder_counts_per_turn", .type = K::kNumber, .fallback = "1638400", .range = kNonNegative, .meaning = "encoder counts per joint turn, a whole number (2^14 per motor turn x gear 100); 0: an exact encoder"},
    ScenarioKey{.map = "servo", .name = "velocity_feedforward", .type = K::kBool, .meaning = "feed the reference velocity forward (default: the controller's: on; the pd's damping acts on the velocity error)"},
    ScenarioKey{.map = "servo", .name = "acceleration_feedforward", .type = K::kBool, .meaning = "feed the reference's inertial torque forward (default: the controller's: cascade on, pd off)"},
    ScenarioKey{.map = "servo", .name = "gravity_compensation", .type = K::kBool, .meaning = "add the model's gravity torque (default: the controller's: on)"},
    ScenarioKey{.map = "servo", .name = "deflection_compensation", .type = K::kBool, .meaning = "correct the motor reference for the gear's deflection under gravity (default: the controller's: cascade on, pd off; no effect on a rigid arm)"},

    ScenarioKey{.map = "simulation", .name = "settle_tolerance", .type = K::kNumber, .unit = kLength, .fallback = "0.03", .range = kPositive, .meaning = "settled: the TCP within this of the end point (a UR-class repeatability) ..."},
    ScenarioKey{.map = "simulation", .name = "settle_speed_tolerance", .type = K::kNumber, .unit = kVelocity, .fallback = "1", .range = kPositive, .meaning = "... and slower than this ..."},
    ScenarioKey{.map = "simulation", .name = "settle_window_s", .type = K::kNumber, .unit = kSeconds, .fallback = "0.2", .range = {0, 60}, .meaning = "... for this long after the reference has ended (four periods of the arm's first mode)"},
    ScenarioKey{.map = "simulation", .name = "settle_time_s", .type = K::kNumber, .unit = kSeconds, .fallback = "1", .range = {0, 60}, .meaning = "how long the simulation goes on after the reference ends, at least settle_window_s (at 8 kHz at most 480,000 steps)"},
    ScenarioKey{.map = "simulation", .name = "vibration_window_s", .type = K::kNumber, .unit = kSeconds, .fallback = "0.5", .range = {0, 60, true, false}, .meaning = "the window of residual vibration after each corner and the final stop"},
    ScenarioKey{.map = "simulation", .name = "vibration_highpass_hz", .type = K::kNumber, .unit = kHertz, .fallback = "12", .range = {1, 4000}, .meaning = "the high-pass of the tracking error whose peak-to-peak is the vibration (clamped to 0.45 of the servo rate)"},
    ScenarioKey{.map = "simulation", .name = "jerk_lowpass_hz", .type = K::kNumber, .unit = kHertz, .fallback = "50", .range = {1, 4000}, .meaning = "the low-pass of the actual TCP before its jerk is measured (clamped to 0.45 of the servo rate)"},

    ScenarioKey{.map = "video", .name = "fps", .type = K::kNumber, .unit = {"1/s", 0}, .fallback = "30", .range = {24, 120}, .meaning = "frames per second"},
    ScenarioKey{.map = "video", .name = "width", .type = K::kInteger, .unit = kPixels, .fallback = "640", .range = {64, 1920}, .meaning = "frame width, even"},
    ScenarioKey{.map = "video", .name = "height", .type = K::kInteger, .unit = kPixels, .fallback = "480", .range = {64, 1920}, .meaning = "frame height, even"},
    ScenarioKey{.map = "video", .name = "camera", .type = K::kMap, .opens = "camera", .meaning = "where the camera stands (default: framed on the part)"},

    ScenarioKey{.map = "camera", .name = "mode", .type = K::kChoice, .fallback = "part", .choices = "part|fixed|tcp", .meaning = "part: framed on the programmed path, seen obliquely from its plane, away from the robot base; fixed: at position, looking at look_at; tcp: following the actual TCP from distance (each mode takes only its own keys)"},
    ScenarioKey{.map = "camera", .name = "fill", .type = K::kNumber, .fallback = "0.6", .range = {0.1, 1}, .meaning = "part: the share of the frame the programmed path's projected bounding box spans (its larger relative side)"},
    ScenarioKey{.map = "camera", .name = "azimuth_deg", .type = K::kNumber, .unit = kDegrees, .range = {-360, 360}, .meaning = "part, tcp: the camera's direction seen from what it looks at, in the base x-y plane from +x towards +y (default: the part view's)"},
    ScenarioKey{.map = "camera", .name = "elevation_deg", .type = K::kNumber, .unit = kDegrees, .range = {-89, 89}, .meaning = "part, tcp: the camera's height above the horizontal seen from what it looks at, positive looking down (default: the part view's)"},
    ScenarioKey{.map = "camera", .name = "position", .type = K::kNumbers, .count = 3, .unit = kLength, .meaning = "fixed, required: the camera's position in the base frame"},
    ScenarioKey{.map = "camera", .name = "look_at", .type = K::kNumbers, .count = 3, .unit = kLength, .meaning = "fixed, required: the point the camera looks at, in the base frame (not its position)"},
    ScenarioKey{.map = "camera", .name = "distance", .type = K::kNumber, .unit = kLength, .range = kPositive, .meaning = "tcp: how far the camera stays from the TCP (default: 350 mm)"},
    ScenarioKey{.map = "sensitivity", .name = "stiffness_scale", .type = K::kNumbers, .fallback = "[0.5, 1.5]", .range = {0, 10, true, false}, .meaning = "factors on the gears' stiffness (the catalogue value is the bare gear's, an upper bound of a real joint's); not 1"},
    ScenarioKey{.map = "sensitivity", .name = "inertia_scale", .type = K::kNumbers, .fallback = "[0.8, 1.2]", .range = {0, 10, true, false}, .meaning = "factors on every moving link's mass and inertia (UR's published values +-20 %); not 1"},
    ScenarioKey{.map = "sensitivity", .name = "friction_scale", .type = K::kNumbers, .fallback = "[0.5, 1.5]", .range = {0, 10}, .meaning = "factors on the joints' viscous and Coulomb friction (poorly known); not 1"},
    ScenarioKey{.map = "sensitivity", .name = "extra_delay_ticks", .type = K::kNumbers, .fallback = "[1]", .range = {1, 100}, .meaning = "servo ticks added to the measurement delay, whole numbers"},
    ScenarioKey{.map = "camera", .name = "fovy_deg", .type = K::kNumber, .unit = kDegrees, .range = {5, 120}, .meaning = "fixed, tcp: the vertical field of view (default: 45 deg; the part camera chooses its own to meet fill)"},

    ScenarioKey{.map = "defaults", .name = "velocity", .type = K::kNumber, .unit = kVelocity, .required = true, .range = kPositive, .meaning = "the programmed path speed"},
    ScenarioKey{.map = "defaults", .name = "acceleration", .type = K::kNumber, .unit = kAcceleration, .required = true, .range = kPositive, .meaning = "the acceleration limit along the path"},
    ScenarioKey{.map = "defaults", .name = "deceleration", .type = K::kNumber, .unit = kAcceleration, .range = kPositive, .meaning = "the deceleration limit along the path (default: the acceleration)"},
    ScenarioKey{.map = "defaults", .name = "jerk", .type = K::kNumber, .unit = kJerk, .required = true, .range = kPositive, .meaning = "the jerk limit along the path"},
    ScenarioKey{.map = "defaults", .name = "angular_velocity", .type = K::kNumber, .unit = kAngularVelocity, .fallback = "180", .range = kPositive, .meaning = "the tool's angular velocity limit where a move turns it (default: the model's wrist joint speed, 180 deg/s as on the UR5e)"},
    ScenarioKey{.map = "defaults", .name = "angular_acceleration", .type = K::kNumber, .unit = kAngularAcceleration, .fallback = "720", .range = kPositive, .meaning = "the tool's angular acceleration limit (default: 180 deg/s reached in 0.25 s; a chosen value, not a datasheet's)"},
    ScenarioKey{.map = "defaults", .name = "angular_jerk", .type = K::kNumber, .unit = kAngularJerk, .fallback = "7200", .range = kPositive, .meaning = "the tool's angular jerk limit (default: 720 deg/s^2 reached in 0.1 s; a chosen value)"},
    ScenarioKey{.map = "defaults", .name = "buffer", .type = K::kChoice, .fallback = "BlendingLow", .choices = kBufferModes, .meaning = "how a move hands over to the next (PLCopen buffer modes)"},

    ScenarioKey{.map = "program", .name = "orientation_interpolation", .type = K::kChoice, .fallback = "slerp", .choices = "slerp|spline", .meaning = "how the tool orientation runs between the moves' targets: slerp along each move by arc length, blended through each transition; or spline, one C2 curve through every target along the whole path (targets within 270 deg of the start orientation)"},
    ScenarioKey{.map = "program", .name = "start", .type = K::kNumbers, .count = 3, .unit = kLength, .fallback = "[0, 0, 0]", .meaning = "where the first move starts, in the program frame (with gcode: the position before the first line)"},
    ScenarioKey{.map = "program", .name = "moves", .type = K::kList, .opens = "move", .meaning = "the moves, each starting where the previous ends (this or gcode)"},
    ScenarioKey{.map = "program", .name = "gcode", .type = K::kFile, .meaning = "a G-code part program instead of moves, in its own units (G20/G21), placed by frame; defaults give its limits"},
    ScenarioKey{.map = "program", .name = "smoothing", .type = K::kMap, .opens = "smoothing", .meaning = "smooth the program's point streams (runs of short lines, as CAM writes curves) before blending, for every variant (default: none; docs/smoothing.md)"},
    ScenarioKey{.map = "program", .name = "subroutine_path", .type = K::kText, .meaning = "with gcode: folders searched for <name>.ngc when the program calls o<name> it does not define, after the program's own folder, separated by ':' as LinuxCNC's SUBROUTINE_PATH, relative to the scenario's folder"},
    ScenarioKey{.map = "program", .name = "gcode_angles", .type = K::kMap, .opens = "gcode_angles", .meaning = "with gcode: read its A, B, C words as tool angles in degrees, modal like X, Y, Z (G91 adds), giving each move's orientation as rpy_deg does; without it A, B, C are refused"},

    ScenarioKey{.map = "smoothing", .name = "method", .type = K::kChoice, .fallback = "none", .choices = "none|clothoid_points|g2_fit", .meaning = "none; clothoid_points: clothoid pairs through every point, curvature zero at each (seed 002 section 6); g2_fit: a curvature-continuous curve within tolerance of every point and line, as smooth as the tolerance allows"},
    ScenarioKey{.map = "smoothing", .name = "tolerance", .type = K::kNumber, .unit = kLength, .fallback = "0.02", .range = kPositive, .meaning = "g2_fit: the largest distance between the curve and the stream's points and lines, both ways (Hausdorff)"},
    ScenarioKey{.map = "smoothing", .name = "max_turn_deg", .type = K::kNumber, .unit = kDegrees, .fallback = "45", .range = {0, 180, true, true}, .meaning = "clothoid_points: the largest turn of one clothoid pair; points are added where a pair would turn more (seed 002 Fig. 11)"},
    ScenarioKey{.map = "smoothing", .name = "stream_length", .type = K::kNumber, .unit = kLength, .fallback = "1", .range = kPositive, .meaning = "a stream's lines are shorter than this (a curve of radius up to 12.5 mm written at a 0.01 mm chord tolerance)"},
    ScenarioKey{.map = "smoothing", .name = "stream_turn_deg", .type = K::kNumber, .unit = kDegrees, .fallback = "30", .range = {0, 180, true, true}, .meaning = "a stream turns by less than this at each vertex; a sharper vertex is a corner, blended by the variant's method"},

    ScenarioKey{.map = "gcode_angles", .name = "a", .type = K::kChoice, .required = true, .choices = "roll|pitch|yaw", .meaning = "the angle A names; A, B, C name roll, pitch and yaw, each once (KUKA's A, B, C: {a: yaw, b: pitch, c: roll}; rotary axes about x, y, z: {a: roll, b: pitch, c: yaw})"},
    ScenarioKey{.map = "gcode_angles", .name = "b", .type = K::kChoice, .required = true, .choices = "roll|pitch|yaw", .meaning = "the angle B names"},
    ScenarioKey{.map = "gcode_angles", .name = "c", .type = K::kChoice, .required = true, .choices = "roll|pitch|yaw", .meaning = "the angle C names"},

    ScenarioKey{.map = "move", .name = "line", .type = K::kNumbers, .count = 3, .unit = kLength, .meaning = "a straight move to this end point (each move is a line or an arc)"},
    ScenarioKey{.map = "move", .name = "arc", .type = K::kMap, .opens = "arc", .meaning = "a circular or helical move"},
    ScenarioKey{.map = "move", .name = "velocity", .type = K::kNumber, .unit = kVelocity, .range = kPositive, .meaning = "this move's speed (default: defaults.velocity)"},
    ScenarioKey{.map = "move", .name = "acceleration", .type = K::kNumber, .unit = kAcceleration, .range = kPositive, .meaning = "this move's acceleration limit (default: defaults.acceleration)"},
    ScenarioKey{.map = "move", .name = "deceleration", .type = K::kNumber, .unit = kAcceleration, .range = kPositive, .meaning = "this move's deceleration limit (default: defaults.deceleration)"},
    ScenarioKey{.map = "move", .name = "jerk", .type = K::kNumber, .unit = kJerk, .range = kPositive, .meaning = "this move's jerk limit (default: defaults.jerk)"},
    ScenarioKey{.map = "move", .name = "buffer", .type = K::kChoice, .choices = kBufferModes, .meaning = "this move's buffer mode (default: defaults.buffer, or the variant's)"},
    ScenarioKey{.map = "move", .name = "orientation", .type = K::kMap, .opens = "orientation", .meaning = "the tool orientation at the end of this move, in the program frame, reached with the end point (default: the orientation it starts with; the first move starts with robot.tool_rpy_deg)"},
    ScenarioKey{.map = "move", .name = "angular_velocity", .type = K::kNumber, .unit = kAngularVelocity, .range = kPositive, .meaning = "this move's angular velocity limit on the tool (default: defaults.angular_velocity)"},
    ScenarioKey{.map = "move", .name = "angular_acceleration", .type = K::kNumber, .unit = kAngularAcceleration, .range = kPositive, .meaning = "this move's angular acceleration limit (default: defaults.angular_acceleration)"},
    ScenarioKey{.map = "move", .name = "angular_jerk", .type = K::kNumber, .unit = kAngularJerk, .range = kPositive, .meaning = "this move's angular jerk limit (default: defaults.angular_jerk)"},
    ScenarioKey{.map = "move", .name = "transition", .type = K::kMap, .opens = "transition", .meaning = "the transition at the corner at the end of this move, whatever the variant sets"},

    ScenarioKey{.map = "arc", .name = "end", .type = K::kNumbers, .count = 3, .unit = kLength, .required = true, .meaning = "the end point"},
    ScenarioKey{.map = "arc", .name = "center", .type = K::kNumbers, .count = 3, .unit = kLength, .meaning = "the centre (an arc takes exactly one of center, radius and via)"},
    ScenarioKey{.map = "arc", .name = "radius", .type = K::kNumber, .unit = kLength, .meaning = "the radius; negative: the arc longer than a half circle (as in RS274)"},
    ScenarioKey{.map = "arc", .name = "via", .type = K::kNumbers, .count = 3, .unit = kLength, .meaning = "a point the arc passes through (fixes plane and direction)"},
    ScenarioKey{.map = "arc", .name = "direction", .type = K::kChoice, .choices = "cw|ccw", .meaning = "the turning sense about normal (required with center or radius)"},
    ScenarioKey{.map = "arc", .name = "normal", .type = K::kNumbers, .count = 3, .fallback = "[0, 0, 1]", .meaning = "the axis the arc turns about (not zero; with center or radius)"},
    ScenarioKey{.map = "arc", .name = "turns", .type = K::kInteger, .fallback = "0", .range = {0, kMaxArcTurns}, .meaning = "extra full turns (a helix when the end lies off the start's plane; with center)"},

    ScenarioKey{.map = "orientation", .name = "rpy_deg", .type = K::kNumbers, .count = 3, .unit = kDegrees, .meaning = "roll, pitch, yaw about the fixed x, y, z axes, read as robot.tool_rpy_deg (give this or quaternion)"},
    ScenarioKey{.map = "orientation", .name = "quaternion", .type = K::kNumbers, .count = 4, .meaning = "[w, x, y, z], normalised on reading; not zero (give this or rpy_deg)"},

    ScenarioKey{.map = "transition", .name = "method", .type = K::kChoice, .required = true, .choices = kMethods, .meaning = "none (exact stop), arc, bezier, clothoid or biclothoid"},
    ScenarioKey{.map = "transition", .name = "parameter", .type = K::kNumber, .unit = kLength, .range = kNonNegative, .meaning = "corner distance (arc), TP (bezier), maximum deviation (clothoid, biclothoid); required but for none, or with tolerance or a biclothoid's start_distance instead"},
    ScenarioKey{.map = "transition", .name = "tolerance", .type = K::kNumber, .unit = kLength, .range = kPositive, .meaning = "instead of parameter, for every method: the corner's deviation (the Hausdorff distance path_deviation_max_mm takes its maximum over), for which each corner's parameter is solved; where the moves are too short, the largest that fits (docs/methods.md, Equal tolerance)"},
    ScenarioKey{.map = "transition", .name = "start_distance", .type = K::kNumber, .unit = kLength, .range = kPositive, .meaning = "biclothoid only, instead of parameter: where the fillet starts before the corner (004 Algorithm 1)"},
    ScenarioKey{.map = "transition", .name = "kappa_max", .type = K::kNumber, .unit = kCurvature, .fallback = "0", .range = kNonNegative, .meaning = "a curvature cap (clothoid: clothoid-arc-clothoid); 0 = none"},
    ScenarioKey{.map = "transition", .name = "velocity", .type = K::kNumber, .unit = kVelocity, .fallback = "0", .range = kNonNegative, .meaning = "the speed through the transition; 0 = the junction speed of the buffer mode"},
    ScenarioKey{.map = "transition", .name = "curvature_steps", .type = K::kChoice, .fallback = "limit", .choices = "limit|allow", .meaning = "arc only: hold the curvature step at the arc's ends to the jerk limit over one setpoint period (limit), or run the arc at seed 001's transition speed and report the jerk the step implies (allow, as controllers do)"},
    ScenarioKey{.map = "transition", .name = "merge_tolerance", .type = K::kNumber, .unit = kLength, .fallback = "0", .range = kNonNegative, .meaning = "merge runs of lines whose inner points lie within this of their chord into one line before blending (G64 Q); 0 = no merging"},

    ScenarioKey{.map = "variant", .name = "name", .type = K::kText, .required = true, .meaning = "the variant's name, unique; it names its output folder (the rule of the scenario's name)"},
    ScenarioKey{.map = "variant", .name = "transition", .type = K::kMap, .opens = "transition", .meaning = "the transition of every move that sets none (default: none of its own, the moves' own)"},
    ScenarioKey{.map = "variant", .name = "buffer", .type = K::kChoice, .choices = kBufferModes, .meaning = "the buffer mode of every move that sets none"},
    ScenarioKey{.map = "variant", .name = "smoothing", .type = K::kMap, .opens = "smoothing", .meaning = "this variant's smoothing: each key it gives replaces the program's (program.smoothing)"},
    ScenarioKey{.map = "variant", .name = "baseline", .type = K::kChoice, .fallback = "none", .choices = "none|exact_stop|junction_slowdown", .meaning = "plan as a baseline: an exact stop, or a slow-down, at every junction"},
    ScenarioKey{.map = "variant", .name = "timing", .type = K::kChoice, .choices = "optimal|seed004", .meaning = "the velocity planner of this variant (default: the scenario's timing)"},
};
// clang-format on

// The table by map: each map's keys, looked up by a scan (a map has at most a dozen keys, and
// lookups run for every key of every move).
using KeyIndex = std::vector<std::pair<std::string_view, std::vector<const ScenarioKey*>>>;

const KeyIndex& key_index() {
  static const KeyIndex index = [] {
    KeyIndex out;
    for (const ScenarioKey& k : kKeys) {
      auto it = std::find_if(out.begin(), out.end(), [&](const auto& m) { return m.first == k.map; });
      if (it == out.end()) it = out.insert(out.end(), {k.map, {}});
      it->second.push_back(&k);
    }
    return out;
  }();
  return index;
}

// Edit distance with swaps of adjacent letters (optimal string alignment).
std::size_t edit_distance(std::string_view a, std::string_view b) {
  std::vector<std::vector<std::size_t>> d(a.size() + 1, std::vector<std::size_t>(b.size() + 1));
  for (std::size_t i = 0; i <= a.size(); ++i) d[i][0] = i;
  for (std::size_t j = 0; j <= b.size(); ++j) d[0][j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t cost = a[i - 1] == b[j - 1] ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  }
  return d[a.size()][b.size()];
}

// A count with thousands separators: 4,000,000.
std::string grouped(std::uintmax_t n) {
  const std::string digits = std::to_string(n);
  std::string out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

// The paths of a table map, each in backquotes: "`a` and `b`".
std::string quoted_paths(std::string_view map) {
  std::string out;
  for (const std::string& path : scenario_map_path_list(map)) {
    if (!out.empty()) out += " and ";
    out.append("`").append(path).append("`");
  }
  return out;
}

// `text` in backquotes (Markdown code).
std::string quoted(std::string_view text) {
  std::string out = "`";
  out.append(text).append("`");
  return out;
}

std::string type_text(const ScenarioKey& k) {
  switch (k.type) {
    case K::kMap: return "map";
    case K::kList: return "list of maps";
    case K::kText: return "text";
    case K::kFile: return "file";
    case K::kChoice: {
      std::string out = "one of ";
      std::string_view rest = k.choices;
      while (true) {
        const std::size_t bar = rest.find('|');
        out.append("`").append(rest.substr(0, bar)).append("`");
        if (bar == std::string_view::npos) break;
        out += ", ";
        rest.remove_prefix(bar + 1);
      }
      return out;
    }
    case K::kBool: return "true or false";
    case K::kInteger: return "integer";
    case K::kNumber: return "number";
    case K::kNumbers: return k.count > 0 ? std::to_string(k.count) + " numbers" : "list of numbers";
  }
  return "";
}

// A unit as the reference prints it: `units` stays (it is mm or m).
std::string unit_text(const ScenarioKey& k) { return k.unit.text.empty() ? "" : std::string(k.unit.text); }

// A default as the reference prints it: lengths in mm.
std::string default_text(const ScenarioKey& k) {
  if (k.required) return "required";
  if (k.fallback.empty()) return "";
  std::string out = "`";
  out.append(k.fallback).append("`");
  if (k.unit.length_power != 0 && k.fallback != "0") {
    std::string unit(k.unit.text);
    unit.replace(unit.find("units"), 5, "mm");
    out += " " + unit;
  }
  return out;
}

}  // namespace

std::string range_text(const KeyRange& r) {
  const bool low = std::isfinite(r.lo);
  const bool high = std::isfinite(r.hi);
  if (!low && !high) return "finite";
  if (low && !high) return std::string(r.lo_open ? "> " : ">= ") + format_value(r.lo);
  if (!low) return std::string(r.hi_open ? "< " : "<= ") + format_value(r.hi);
  return std::string(r.lo_open ? "(" : "[") + format_value(r.lo) + ", " + format_value(r.hi) + (r.hi_open ? ")" : "]");
}

std::span<const ScenarioKey> scenario_keys() { return kKeys; }

const ScenarioKey* find_scenario_key(std::string_view map, std::string_view name) {
  for (const auto& [m, keys] : key_index()) {
    if (m != map) continue;
    for (const ScenarioKey* k : keys) {
      if (k->name == name) return k;
    }
    return nullptr;
  }
  return nullptr;
}

std::vector<std::string> scenario_map_path_list(std::string_view map) {
  if (map.empty()) return {""};
  std::vector<std::string> out;
  for (const ScenarioKey& k : kKeys) {
    if (k.opens != map) continue;
    for (const std::string& parent : scenario_map_path_list(k.map)) {
      out.push_back((parent.empty() ? "" : parent + ".") + std::string(k.name) + (k.type == K::kList ? "[]" : ""));
    }
  }
  return out;
}

std::string scenario_map_paths(std::string_view map) {
  std::string out;
  for (const std::string& path : scenario_map_path_list(map)) out += (out.empty() ? "" : " and ") + path;
  return out;
}

std::vector<std::string> closest_names(std::string_view word, std::span<const std::string> candidates) {
  const std::size_t limit = std::max<std::size_t>(1, word.size() / 3);
  std::size_t best = limit + 1;
  std::vector<std::string> out;
  for (const std::string& c : candidates) {
    const std::size_t d = edit_distance(word, c);
    if (d > limit || d > best) continue;
    if (d < best) out.clear();
    best = d;
    out.push_back(c);
  }
  return out;
}

std::string scenario_format_markdown() {
  std::string out;
  out += "# Scenario format\n\n";
  out += "<!-- Generated from the loader's table (io/src/scenario_keys.cpp) by `blendbench validate --schema`;\n"
         "     the test ScenarioKeys.TheCommittedReferenceIsWhatTheTableGenerates fails when this file differs.\n"
         "     Do not edit by hand. -->\n\n";
  out += "A scenario is one YAML document (UTF-8). The loader checks it strictly and stops at the first problem\n"
         "with one line naming the file, line, column and key: an unknown key (with the closest valid key for a\n"
         "typo), a key given twice in one map, a key that is a list or a map, a wrong type, a value out of its\n"
         "range, a missing required key, an unclosed quoted string. `blendbench validate FILE...` checks files\n"
         "without running them.\n\n";
  out += "Units: every length is in `units` (`mm` or `m`); `units/s`, `units/s^2`, `units/s^3` and `1/units`\n"
         "follow it. Defaults of lengths are given in mm. Ranges hold for the value as written.\n\n";
  out += "Limits that bound the work before it is done: a file of at most " + grouped(kMaxInputBytes >> 20) +
         " MiB,\nat most " + grouped(yaml_detail::kMaxNodes) +
         " YAML nodes (an alias counts as the nodes it repeats), lists and maps nested at\nmost " +
         grouped(yaml_detail::kMaxDepth) + " deep, at most " + grouped(kMaxMoves) + " moves, " + grouped(kMaxVariants) +
         " variants and " + grouped(kMaxArcTurns) + " turns per arc (the G-code\nreader has the same limits of moves and turns: P up to " +
         grouped(kMaxArcTurns) + ").\n";
  std::vector<std::string_view> maps;
  for (const ScenarioKey& k : kKeys) {
    if (std::find(maps.begin(), maps.end(), k.map) == maps.end()) maps.push_back(k.map);
  }
  for (const std::string_view map : maps) {
    out.append("\n## ").append(map.empty() ? "Top level" : quoted_paths(map)).append("\n\n");
    out += "| key | type | unit | default | range | meaning |\n|---|---|---|---|---|---|\n";
    for (const ScenarioKey& k : kKeys) {
      if (k.map != map) continue;
      const bool numeric = k.type == K::kNumber || k.type == K::kInteger || k.type == K::kNumbers;
      std::string meaning(k.meaning);
      if (k.type == K::kMap || k.type == K::kList) meaning.append(" (see ").append(quoted_paths(k.opens)).append(")");
      // one row: | `key` | type | unit | default | range | meaning |
      for (const std::string& cell : {quoted(k.name), type_text(k), unit_text(k), default_text(k),
                                      numeric ? range_text(k.range) : std::string(), meaning}) {
        out.append("| ").append(cell).append(" ");
      }
      out += "|\n";
    }
  }
  return out;
}

}  // namespace blendbench
