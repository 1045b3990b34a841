#pragma once
// A program of Cartesian moves in the PLCopen Part 4 style (MovL / MovC), in SI units.
// Loaders (YAML scenarios, G-code) produce it; the blender consumes it.

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "blendbench/core/input_error.hpp"
#include "blendbench/geometry/segment.hpp"
#include "blendbench/program/orientation.hpp"
#include "blendbench/program/smoothing.hpp"

namespace blendbench {

// How a move hands over to the next one (PLCopen buffer modes). Buffered stops between moves
// wherever the path keeps a tangent discontinuity; the Blending modes choose the junction
// velocity (Low: the slower move's, Previous: the first's, Next: the second's, High: the
// faster's). Aborting starts the next move at once (treated like BlendingNext here).
enum class BufferMode { kAborting, kBuffered, kBlendingLow, kBlendingPrevious, kBlendingNext, kBlendingHigh };

// The velocity (m/s) the buffer mode gives the junction from a move programmed at v_prev to one
// programmed at v_next where the path does not stop: min (BlendingLow, and Buffered where it
// keeps no kink), v_prev (BlendingPrevious), v_next (BlendingNext, Aborting), max (BlendingHigh).
double junction_velocity(BufferMode mode, double v_prev, double v_next);

// The transition curve inserted at the corner at the end of a move.
enum class Method { kNone, kArc, kBezier, kClothoid, kBiclothoid };

// What the velocity planner does where a transition leaves a curvature step (a circular blend
// meeting a line or an arc of another radius): kLimit keeps the step of the normal acceleration
// within j dt per servo period (a junction velocity bound, timing.hpp); kAllow lets it step,
// as a controller running a G1 blend does, and reports the jerk the step implies.
enum class CurvatureSteps { kLimit, kAllow };

// How the tool orientation runs between targets (orientation.hpp): kSlerp, the geodesic of each
// move by its arc length, blended through each transition; kSpline, one C2 spline through all
// targets along the whole path.
enum class OrientationInterpolation { kSlerp, kSpline };

std::string_view to_string(BufferMode mode);
std::string_view to_string(Method method);
std::string_view to_string(CurvatureSteps steps);  // "limit", "allow"
std::string_view to_string(OrientationInterpolation interpolation);  // "slerp", "spline"
// Parse the names used in files ("Buffered", "BlendingLow", ...; "none", "arc", ...);
// case-insensitive; nullopt when unknown.
std::optional<BufferMode> buffer_mode_from_string(std::string_view name);
std::optional<Method> method_from_string(std::string_view name);
std::optional<CurvatureSteps> curvature_steps_from_string(std::string_view name);
std::optional<OrientationInterpolation> orientation_interpolation_from_string(std::string_view name);

// The transition mode and its parameter, on the move that ends at the corner.
struct Transition {
  Method method = Method::kNone;
  // m: corner distance (arc), transition parameter TP (bezier), maximum deviation from the
  // programmed path (clothoid, biclothoid).
  double parameter = 0;
  // 1/m: optional curvature cap for the clothoid method (clothoid-arc-clothoid); 0 = none.
  double kappa_max = 0;
  // m: biclothoid only, the alternative to a maximum deviation: the fillet starts this far
  // before the corner on the incoming move (seed 004 (Shahzadeh et al.) Algorithm 1); 0 = sized by `parameter`.
  double start_distance = 0;
  // m/s: transition velocity (seed 001: the transition takes its velocity from the transition
  // parameter); 0 = the junction velocity of the move's buffer mode (junction_velocity; with
  // BlendingLow the slower of the two moves).
  double velocity = 0;
  // The curvature steps this transition leaves at its ends (an arc's, or the corner's own when
  // it is left tangent): limited by the junction rule, or allowed and reported.
  CurvatureSteps curvature_steps = CurvatureSteps::kLimit;
  // m: LinuxCNC's G64 Q ("naive CAM detector"): a run of lines whose corners all set this (and
  // share limits and buffer mode) is merged into one line before blending where every inner
  // vertex lies within it of that line, in order along it (blend.hpp); 0 = off.
  double merge_tolerance = 0;
  // m: the corner's Hausdorff deviation to reach instead of a parameter (equal tolerance,
  // docs/methods.md): the method's own parameter is solved at each corner so that the deviation
  // the corner report gives (CornerReport::deviation) equals it, or is the largest that fits;
  // 0 = sized by `parameter` (or `start_distance`). Exclusive with both. (Last, so that the
  // positional initialisers of the fields above keep their meaning.)
  double tolerance = 0;
};

// Kinematic limits of one move along the path (PLCopen Velocity, Acceleration, Deceleration, Jerk).
struct Limits {
  double velocity = 0;      // m/s
  double acceleration = 0;  // m/s^2
  double deceleration = 0;  // m/s^2
  double jerk = 0;          // m/s^3
};

struct Move {
  Primitive geometry;  // as programmed; starts where the previous move ends
  Limits limits;
  BufferMode buffer = BufferMode::kBlendingLow;
  Transition transition;  // applies to the corner at the end of this move
  SourceRef where;        // where the move was written, for error messages
  std::string name;       // e.g. "move 3" or "N120 G1", for reports
  // The tool orientation at the end of the move (unit quaternion, base frame), reached together
  // with the end point (orientation.hpp); none: the move keeps the orientation it starts with.
  std::optional<Quat> orientation;
  AngularLimits angular;  // on the tool's rotation along this move
};

struct Program {
  std::vector<Move> moves;
  // The tool orientation at the start (unit quaternion, base frame); used only when a move sets
  // an orientation (a program without any keeps the robot's fixed tool orientation).
  Quat start_orientation = Quat::Identity();
  OrientationInterpolation orientation_interpolation = OrientationInterpolation::kSlerp;
  // Point streams smoothed before blending (smoothing.hpp); none by default.
  Smoothing smoothing;
};

// Whether any move of `program` sets an orientation.
bool oriented(const Program& program);

// The most moves a program may have: 10^6, ten times the largest program the loaders are
// benchmarked on; it bounds the work of blending and planning before any is done. Readers refuse
// the move past it where it is written.
inline constexpr std::size_t kMaxMoves = 1'000'000;

// The smallest transition (parameter or start distance) other than none: 1 nm. Below it the
// rounding of a corner's coordinates (1e-16 of a path of about 1 m) swamps the curve, as the
// Bezier blend's own kMinLength says; the clothoid and biclothoid fits squared their size into
// an underflow at about 1e-200 mm and wrote rows of NaN (issue 42).
inline constexpr double kMinTransitionSize = 1e-9;  // m

// Checks what the blender assumes: at least one move and at most kMaxMoves; finite coordinates; arcs of positive
// radius and sweep; no zero-length move; consecutive moves joined (end of move k equals start
// of move k+1 within 1e-9 of the program size); positive finite limits; finite non-negative
// transition values, each 0 or at least kMinTransitionSize, a start distance only on a
// biclothoid and not with a parameter, a tolerance not with a parameter or a start distance; unit
// quaternions (to 1e-9) and angular limits > 0 (infinity: none); the smoothing spec (smoothing.hpp). Throws
// InputError located at the move (at move k+1 for a gap), naming it and the field; a move's own
// geometry is reported before its join to the previous move.
void validate(const Program& program);

}  // namespace blendbench
