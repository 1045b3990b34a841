// The YAML scenario loader (scenario.hpp): the file read into a tree with positions
// (yaml_document.hpp), walked map by map by the reader (scenario_reader.hpp) against the
// format's table (scenario_keys.hpp), and turned into a Scenario here.

#include "blendbench/core/units.hpp"
#include "blendbench/io/scenario.hpp"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <set>

#include "blendbench/core/format.hpp"
#include "blendbench/geometry/arc_construction.hpp"
#include "blendbench/io/data_root.hpp"
#include "blendbench/io/program_io.hpp"
#include "blendbench/io/run_inputs.hpp"
#include "blendbench/robot/kinematics.hpp"
#include "blendbench/io/plausibility.hpp"
#include "scenario_reader.hpp"

namespace blendbench {
namespace {

// Whether `path` is a regular file; a path the system cannot examine (a loop of symbolic links)
// is not one here (the file that is read next says why when it matters).
bool is_regular_file_here(const std::string& path) {
  std::error_code ec;
  return std::filesystem::is_regular_file(path, ec);
}


using namespace scenario_detail;  // the reader private to the scenario loader


Eigen::Matrix3d rpy_deg(const std::vector<double>& rpy) {
  // fixed-axis roll (x), pitch (y), yaw (z), as in URDF: R = Rz(yaw) Ry(pitch) Rx(roll); the
  // values are already radians (the unit deg converts like any other: by kDeg below)
  return rotation_from_rpy(Vec3(rpy[0], rpy[1], rpy[2]));
}

// Degrees read from the file, in radians.
std::vector<double> radians(std::vector<double> deg) {
  for (double& v : deg) v *= kDeg;
  return deg;
}

Transition read_transition(const Reader& r, const Field& f) {
  r.check_keys(f);
  Transition t;
  const Field method = r.require(f, "method");
  t.method = *method_from_string(r.choice(method));
  const Field parameter = r.child(f, "parameter");
  const Field start = r.child(f, "start_distance");
  const Field tolerance = r.child(f, "tolerance");
  if (tolerance.node.defined()) {
    // equal tolerance: the method's own parameter is solved for it at each corner
    for (const auto& [other, name] : {std::pair{parameter, "parameter"}, std::pair{start, "start_distance"}}) {
      if (other.node.defined()) {
        r.fail(tolerance, std::string("give the transition either a tolerance or a ") + name + ", not both (tolerance and " +
                              name + " exclude each other)");
      }
    }
    t.tolerance = r.number(tolerance);
  } else if (start.node.defined()) {
    if (t.method != Method::kBiclothoid) {
      r.fail(start, "a start distance sizes only a biclothoid transition, not " + r.choice(method));
    }
    if (parameter.node.defined()) {
      r.fail(start, "give the biclothoid either a maximum deviation (parameter) or a start distance, not both");
    }
    t.start_distance = r.number(start);
  } else if (parameter.node.defined()) {
    t.parameter = r.number(parameter);
  } else if (t.method != Method::kNone) {
    r.fail(parameter, r.missing() + " (give the method " + r.choice(method) + " a parameter or a tolerance)");
  }
  t.kappa_max = r.number(r.value(f, "kappa_max"));
  t.velocity = r.number(r.value(f, "velocity"));
  t.merge_tolerance = r.number(r.value(f, "merge_tolerance"));
  t.curvature_steps = *curvature_steps_from_string(r.choice(r.value(f, "curvature_steps")));
  return t;
}

BufferMode read_buffer(const Reader& r, const Field& f) { return *buffer_mode_from_string(r.choice(f)); }

// A `smoothing` map: each key it gives replaces `base`'s (the program's, or the defaults).
Smoothing read_smoothing(const Reader& r, const Field& f, Smoothing base) {
  r.check_keys(f);
  base.where = r.where(f);
  if (const Field m = r.child(f, "method"); m.node.defined()) base.method = *smoothing_method_from_string(r.choice(m));
  if (const Field t = r.child(f, "tolerance"); t.node.defined()) base.tolerance = r.number(t);
  if (const Field t = r.child(f, "max_turn_deg"); t.node.defined()) base.max_turn = r.number(t) * kDeg;
  if (const Field l = r.child(f, "stream_length"); l.node.defined()) base.stream_length = r.number(l);
  if (const Field t = r.child(f, "stream_turn_deg"); t.node.defined()) base.stream_turn = r.number(t) * kDeg;
  return base;
}

// Reads one arc specification; positions are in the program frame, in metres.
Arc read_arc(const Reader& r, const Field& f, const Vec3& start) {
  r.check_keys(f);
  const Vec3 end = r.vec3(r.require(f, "end"));
  const Field via = r.child(f, "via");
  const Field center = r.child(f, "center");
  const Field radius = r.child(f, "radius");
  const int given = static_cast<int>(via.node.defined()) + static_cast<int>(center.node.defined()) +
                    static_cast<int>(radius.node.defined());
  if (given != 1) r.fail(f, "an arc needs exactly one of 'center', 'radius' or 'via'");

  ArcBuild built;
  if (via.node.defined()) {
    for (const char* key : {"direction", "normal", "turns"}) {
      if (const Field k = r.child(f, key); k.node.defined()) r.fail(k, "not used with 'via' (the via point fixes the arc)");
    }
    built = arc_through(start, r.vec3(via), end);
    if (!built.outcome.ok()) r.fail(via, built.outcome.message);
    return built.arc;
  }
  const bool ccw = r.choice(r.require(f, "direction")) == "ccw";
  const Field n = r.value(f, "normal");
  const Vec3 normal = r.vec3(n);
  if (!(normal.norm() > 0)) r.fail(n, "the normal must not be zero");
  const Field turns_field = r.value(f, "turns");
  const int turns = r.integer(turns_field);
  if (center.node.defined()) {
    // a tolerance of a micrometre on the radii, like a CNC control's arc check
    built = arc_from_center(start, end, r.vec3(center), normal, ccw, turns, 1e-6);
    if (!built.outcome.ok()) r.fail(center, built.outcome.message);
  } else {
    if (turns != 0) r.fail(turns_field, "'turns' needs a 'center'");
    built = arc_from_radius(start, end, r.number(radius), normal, ccw, 1e-9);
    if (!built.outcome.ok()) r.fail(radius, built.outcome.message);
  }
  return built.arc;
}

// Transforms an arc by a rigid frame.
Arc transformed(const Arc& arc, const Eigen::Isometry3d& frame) {
  Arc out = arc;
  out.center = frame * arc.center;
  out.u = frame.linear() * arc.u;
  out.v = frame.linear() * arc.v;
  return out;
}

// Limits and buffer mode every move starts from.
struct MoveDefaults {
  Limits limits;
  AngularLimits angular;
  BufferMode buffer = BufferMode::kBlendingLow;
};

// The angular limits of a map (defaults or a move) over `base`, in rad/s, rad/s^2, rad/s^3.
AngularLimits read_angular(const Reader& r, const Field& f, AngularLimits base, bool with_fallback) {
  for (auto [key, target] : {std::pair{"angular_velocity", &base.velocity}, std::pair{"angular_acceleration", &base.acceleration},
                             std::pair{"angular_jerk", &base.jerk}}) {
    const Field v = with_fallback ? r.value(f, key) : r.child(f, key);
    if (v.node.defined()) *target = r.number(v) * kDeg;
  }
  return base;
}

// `orientation: {rpy_deg: [..]}` or `{quaternion: [w, x, y, z]}` in the program frame, as a
// unit quaternion in the base frame.
Quat read_orientation(const Reader& r, const Field& f, const Scenario& sc) {
  r.check_keys(f);
  const Field rpy = r.child(f, "rpy_deg");
  const Field quaternion = r.child(f, "quaternion");
  // each value checked where it stands first, then that exactly one is given
  Eigen::Matrix3d program = Eigen::Matrix3d::Identity();
  if (rpy.node.defined()) program = rpy_deg(radians(r.numbers(rpy)));
  if (quaternion.node.defined()) {
    const std::vector<double> q = r.numbers(quaternion);
    const Quat given(q[0], q[1], q[2], q[3]);
    if (!(given.norm() > 1e-9)) r.fail(quaternion, "a quaternion must not be zero");
    program = given.normalized().toRotationMatrix();
  }
  if (rpy.node.defined() == quaternion.node.defined()) r.fail(f, "an orientation needs exactly one of 'rpy_deg' or 'quaternion'");
  return Quat(sc.frame.linear() * program).normalized();
}

MoveDefaults read_defaults(const Reader& r, const Field& root) {
  const Field defaults = r.require(root, "defaults");
  r.check_keys(defaults);
  MoveDefaults d;
  d.limits.velocity = r.number(r.require(defaults, "velocity"));
  d.limits.acceleration = r.number(r.require(defaults, "acceleration"));
  const Field dec = r.child(defaults, "deceleration");
  d.limits.deceleration = dec.node.defined() ? r.number(dec) : d.limits.acceleration;
  d.limits.jerk = r.number(r.require(defaults, "jerk"));
  d.buffer = read_buffer(r, r.value(defaults, "buffer"));
  d.angular = read_angular(r, defaults, {}, true);
  return d;
}

// `gcode_angles: {a: .., b: .., c: ..}`: what A, B, C name, each of roll, pitch, yaw once.
GcodeAngles read_gcode_angles(const Reader& r, const Field& f) {
  r.check_keys(f);
  GcodeAngles angles;
  std::array<const char*, 3> named_by{};
  const std::array<const char*, 3> letters = {"a", "b", "c"};
  for (std::size_t k = 0; k < letters.size(); ++k) {
    const Field v = r.require(f, letters[k]);
    const std::string name = r.choice(v);
    const ToolAngle angle = name == "roll" ? ToolAngle::kRoll : name == "pitch" ? ToolAngle::kPitch : ToolAngle::kYaw;
    const auto index = static_cast<std::size_t>(angle);
    if (named_by[index]) {
      r.fail(v, name + " is named by both " + named_by[index] + " and " + letters[k] +
                    "; A, B, C name roll, pitch and yaw, each once");
    }
    named_by[index] = letters[k];
    angles.abc[k] = angle;
  }
  return angles;
}

// The moves of a G-code program (program frame) placed by the scenario's frame, with the
// tool's angular limits `angular`.
void place_gcode(const GcodeResult& parsed, const AngularLimits& angular, Scenario& sc) {
  sc.start = sc.frame * parsed.start;
  sc.ignored = parsed.ignored;
  sc.program.moves.reserve(parsed.program.moves.size());
  for (Move move : parsed.program.moves) {
    move.angular = angular;
    if (move.orientation) move.orientation = Quat(sc.frame.linear() * move.orientation->toRotationMatrix()).normalized();
    if (Line* line = std::get_if<Line>(&move.geometry)) {
      line->p0 = sc.frame * line->p0;
      line->p1 = sc.frame * line->p1;
    } else {
      move.geometry = transformed(std::get<Arc>(move.geometry), sc.frame);
    }
    sc.program.moves.push_back(std::move(move));
  }
  sc.explicit_transition.assign(sc.program.moves.size(), false);
  sc.explicit_buffer.assign(sc.program.moves.size(), false);
}

// The G-code reader's options for a program placed by `sc.frame`: the limits and buffer mode of
// the defaults, the tool's start orientation in the program frame (the reader checks a
// zero-length move against it).
GcodeOptions gcode_options(const MoveDefaults& defaults, const Scenario& sc) {
  GcodeOptions options;
  options.limits = defaults.limits;
  options.buffer = defaults.buffer;
  options.start_orientation = Quat(sc.frame.linear().transpose() * sc.program.start_orientation.toRotationMatrix()).normalized();
  return options;
}

// A program given as a G-code file: read in its own units (G20/G21), placed by the frame.
// Variants replace the transitions of all its moves (the file's G61/G64 apply when a variant
// sets no transition).
void read_gcode_program(const Reader& r, const Field& gcode, const Field& angles, const Field& subroutine_path,
                        const Field& start, const MoveDefaults& defaults, Scenario& sc) {
  GcodeOptions options = gcode_options(defaults, sc);
  if (subroutine_path.node.defined()) options.subroutine_path = r.existing_folders(subroutine_path);
  options.start = r.vec3(start);
  if (angles.node.defined()) options.angles = read_gcode_angles(r, angles);
  const GcodeResult parsed = load_gcode_file(r.existing_file(gcode), options);
  if (auto warning = gcode_feed_warning(parsed, defaults.limits.velocity)) sc.warnings.push_back(std::move(*warning));
  place_gcode(parsed, defaults.angular, sc);
}

// A folder name made of a file's name, extension included (folder_name_problem's rule):
// characters it may not hold become '_', an empty or too long one is cut or named "part". The
// extension keeps a G-code file's runs apart from a scenario of the same stem (bracket.yaml's
// run folder and baseline are "bracket", bracket.ngc's "bracket.ngc").
std::string name_from_file(const std::string& path) {
  std::string name = std::filesystem::path(path).filename().string();
  for (char& c : name) {
    const bool allowed = std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
    if (!allowed || static_cast<unsigned char>(c) >= 0x80) c = '_';
  }
  if (!name.empty() && (name.front() == '.' || name.front() == '-')) name.front() = '_';
  if (name.size() > 100) name.resize(100);
  return name.empty() ? "part" : name;
}

// The box around the path of `program` and its start point (program frame, m): each move's end
// points and, for an arc, its extreme points along each axis (sampled finely enough for a box:
// every 1/64 of a turn, which is within (1 - cos(pi/64)) R = 0.12 % of R of the true extreme).
std::pair<Vec3, Vec3> path_box(const Program& program, const Vec3& start) {
  Vec3 lo = start, hi = start;
  const auto add = [&](const Vec3& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  };
  for (const Move& m : program.moves) {
    const double len = length(m.geometry);
    // a line: its ends; an arc (at most kMaxArcTurns turns): every 1/64 of a turn
    const Arc* arc = std::get_if<Arc>(&m.geometry);
    const int n = arc == nullptr ? 1 : std::max(1, static_cast<int>(std::ceil(arc->sweep / (std::numbers::pi / 32))));
    for (int i = 0; i <= n; ++i) add(point(m.geometry, len * i / n));
  }
  return {lo, hi};
}

// One move of the list: its geometry from `current` (program frame, m), its limits and modes.
Move read_move(const Reader& r, const Field& m, std::size_t i, const MoveDefaults& defaults, Vec3& current, Scenario& sc) {
  r.check_keys(m);
  const Field line = r.child(m, "line");
  const Field arc = r.child(m, "arc");
  if (line.node.defined() == arc.node.defined()) r.fail(m, "a move needs exactly one of 'line' or 'arc'");
  Move move;
  move.where = r.where(m);
  move.name = "move " + std::to_string(i + 1) + " (line " + std::to_string(move.where.line) + ")";
  if (line.node.defined()) {
    const Vec3 end = r.vec3(line);
    if ((end - current).norm() <= 1e-12) r.fail(line, "zero-length move: the end point equals the start point");
    move.geometry = Line{sc.frame * current, sc.frame * end};
    current = end;
  } else {
    const Arc a = read_arc(r, arc, current);
    move.geometry = transformed(a, sc.frame);
    current = point(Segment(a), length(a));
  }
  move.limits = defaults.limits;
  const std::array<std::pair<const char*, double*>, 4> limits = {{{"velocity", &move.limits.velocity},
                                                                  {"acceleration", &move.limits.acceleration},
                                                                  {"deceleration", &move.limits.deceleration},
                                                                  {"jerk", &move.limits.jerk}}};
  for (const auto& [key, target] : limits) {
    if (const Field v = r.child(m, key); v.node.defined()) *target = r.number(v);
  }
  move.angular = read_angular(r, m, defaults.angular, false);
  if (const Field o = r.child(m, "orientation"); o.node.defined()) move.orientation = read_orientation(r, o, sc);
  move.buffer = defaults.buffer;
  if (const Field b = r.child(m, "buffer"); b.node.defined()) move.buffer = read_buffer(r, b);
  if (const Field t = r.child(m, "transition"); t.node.defined()) move.transition = read_transition(r, t);
  return move;
}

void read_program(const Reader& r, const Field& root, Scenario& sc) {
  const Field program = r.require(root, "program");
  r.check_keys(program);
  const Field moves = r.child(program, "moves");
  const Field gcode = r.child(program, "gcode");
  const Field angles = r.child(program, "gcode_angles");
  const Field subroutine_path = r.child(program, "subroutine_path");
  const MoveDefaults defaults = read_defaults(r, root);
  const Field start = r.value(program, "start");
  // the tool starts as the robot holds it (used only when a move sets an orientation)
  sc.program.start_orientation = Quat(sc.robot.tool_rotation).normalized();
  sc.program.orientation_interpolation =
      *orientation_interpolation_from_string(r.choice(r.value(program, "orientation_interpolation")));
  if (const Field f = r.child(program, "smoothing"); f.node.defined()) sc.program.smoothing = read_smoothing(r, f, Smoothing{});
  if (gcode.node.defined()) {
    if (moves.node.defined()) r.fail(moves, "give either 'moves' or 'gcode', not both");
    read_gcode_program(r, gcode, angles, subroutine_path, start, defaults, sc);
    return;
  }
  if (angles.node.defined()) r.fail(angles, "gcode_angles maps the words of a G-code program; this program has no 'gcode'");
  if (subroutine_path.node.defined()) r.fail(subroutine_path, "subroutine_path is searched by a G-code program's calls; this program has no 'gcode'");
  if (!moves.node.defined()) (void)r.require(program, "moves");
  if (!moves.node.is_sequence() || moves.node.size() == 0) {
    r.fail(moves, "expected a non-empty list of moves, got " + what_is(moves.node));
  }
  if (moves.node.size() > kMaxMoves) {
    r.fail(r.item(moves, kMaxMoves), "more than " + std::to_string(kMaxMoves) + " moves (the limit of one program)");
  }

  Vec3 current = r.vec3(start);
  sc.start = sc.frame * current;
  const std::size_t count = moves.node.size();
  sc.program.moves.reserve(count);
  sc.explicit_transition.reserve(count);
  sc.explicit_buffer.reserve(count);
  for (std::size_t i = 0; i < count; ++i) {
    const Field m = r.item(moves, i);
    sc.program.moves.push_back(read_move(r, m, i, defaults, current, sc));
    sc.explicit_transition.push_back(r.child(m, "transition").node.defined());
    sc.explicit_buffer.push_back(r.child(m, "buffer").node.defined());
  }
}

void read_robot(const Reader& r, const Field& root, Scenario& sc) {
  const Field robot = r.child(root, "robot");
  if (robot.node.defined()) r.check_keys(robot);
  // the shipped arm in the data root (data_root.hpp) unless the scenario names its own model;
  // the dynamics of the chosen `model` unless it names its own MJCF
  const Field model = r.value(robot, "model");
  sc.robot.model = r.choice(model) == "rigid" ? ArmModel::kRigid : ArmModel::kElastic;
  const Field mjcf = r.child(robot, "mjcf");
  const Field urdf = r.child(robot, "urdf");
  // an MJCF of the user's own: its chain ends at tip_site or tip_body, no URDF
  const Field tip_site = r.child(robot, "tip_site"), tip_body = r.child(robot, "tip_body");
  if (tip_site.node.defined() || tip_body.node.defined()) {
    const Field& tip = tip_site.node.defined() ? tip_site : tip_body;
    if (tip_site.node.defined() && tip_body.node.defined()) r.fail(tip_body, "give tip_site or tip_body, not both");
    if (!mjcf.node.defined()) r.fail(tip, "tip_site and tip_body name the end of an MJCF of your own: give robot.mjcf");
    if (urdf.node.defined()) {
      r.fail(urdf, "with tip_site or tip_body the chain is read from robot.mjcf; give the URDF (and its tip_link) or the "
                   "MJCF's tip, not both");
    }
    sc.robot.tip_site = tip_site.node.defined() ? r.text(tip_site) : "";
    sc.robot.tip_body = tip_body.node.defined() ? r.text(tip_body) : "";
    if (sc.robot.tip_site.empty() && sc.robot.tip_body.empty()) r.fail(tip, "must name a site or body of the MJCF");
    sc.robot.mjcf = r.existing_file(mjcf);
  } else {
    sc.robot.urdf = r.existing_file(r.value(robot, "urdf"));
  }
  // without an MJCF: the URDF's own MJCF beside it (model_file), else dynamics built from the URDF
  if (sc.robot.urdf.empty()) {
    // an MJCF of the user's own: read above
  } else if (mjcf.node.defined()) {
    sc.robot.mjcf = r.existing_file(mjcf);
  } else if (const std::string beside = model_file(sc.robot.urdf, sc.robot.model); is_regular_file_here(beside)) {
    sc.robot.mjcf = beside;
  } else {
    sc.robot.mjcf_from_urdf = true;
  }
  // where the model was chosen, for later errors: `model`, else `mjcf` (beside a URDF: an MJCF of
  // the user's own is what it is unless `model` says otherwise), else nowhere
  if (const Field given = r.child(robot, "model"); given.node.defined()) {
    sc.robot.model_where = r.where(given);
  } else if (mjcf.node.defined() && !sc.robot.urdf.empty()) {
    sc.robot.model_where = r.where(mjcf);
  }
  sc.robot.base_link = r.text(r.value(robot, "base_link"));
  sc.robot.tip_link = r.text(r.value(robot, "tip_link"));
  sc.robot.tool_rotation = rpy_deg(radians(r.numbers(r.value(robot, "tool_rpy_deg"))));
  const std::vector<double> q = radians(r.numbers(r.value(robot, "q_seed_deg")));
  for (int i = 0; i < 6; ++i) sc.robot.q_seed[i] = q[static_cast<std::size_t>(i)];
  // the tool on the flange, and what the joint reference may do
  if (const Field tool = r.child(robot, "tool"); tool.node.defined()) {
    r.check_keys(tool);
    sc.robot.tool.translation() = r.vec3(r.value(tool, "offset"));
    sc.robot.tool.linear() = rpy_deg(radians(r.numbers(r.value(tool, "rpy_deg"))));
  }
  sc.robot.allow_branch_change = r.flag(r.value(robot, "allow_branch_change"));
  sc.robot.urdf_where = r.where(urdf.node.defined() ? urdf : robot);
  if (const Field estimate = r.child(robot, "estimate_inertia"); estimate.node.defined()) {
    r.check_keys(estimate);
    sc.robot.estimate_total_mass = r.number(r.require(estimate, "total_mass_kg"));
    sc.robot.estimate_where = r.where(estimate);
  }
}

// Whether `a` is a whole multiple of `b` (both > 0), to 1e-9 of the ratio.
bool whole_multiple(double a, double b) {
  const double ratio = a / b;
  return std::abs(ratio - std::round(ratio)) <= 1e-9 * ratio;
}

void read_servo(const Reader& r, const Field& root, Scenario& sc) {
  const Field servo = r.child(root, "servo");
  if (servo.node.defined()) r.check_keys(servo);
  ServoSettings& s = sc.servo;
  s.controller = r.choice(r.value(servo, "controller")) == "pd" ? ServoController::kPd : ServoController::kCascade;
  const Field rate = r.value(servo, "rate_hz");
  s.rate_hz = r.number(rate);
  if (r.child(servo, "rate_hz").node.defined()) s.rate_where = r.where(rate);
  if (const Field f = r.child(servo, "setpoint_rate_hz"); f.node.defined()) {
    s.setpoint_rate_hz = r.number(f);
    if (s.setpoint_rate_hz > s.rate_hz) {
      r.fail(f, "the setpoint rate must be at most the servo rate (" + format_value(s.rate_hz) + " Hz), got " + f.node.scalar());
    }
    if (!whole_multiple(s.rate_hz, s.setpoint_rate_hz)) {
      r.fail(f, "the servo rate (" + format_value(s.rate_hz) + " Hz) must be a whole multiple of the setpoint rate");
    }
  } else if (s.rate_hz < s.setpoint_rate_hz || !whole_multiple(s.rate_hz, s.setpoint_rate_hz)) {
    // a servo rate given alone runs the setpoints at its own rate when it cannot take 500 Hz
    s.setpoint_rate_hz = s.rate_hz;
  }
  s.measurement_delay_ticks = r.integer(r.value(servo, "measurement_delay_ticks"));
  const Field counts = r.value(servo, "encoder_counts_per_turn");
  s.encoder_counts_per_turn = r.number(counts);
  if (s.encoder_counts_per_turn != std::round(s.encoder_counts_per_turn)) {
    r.fail(counts, "counts per turn must be a whole number (0: an exact encoder), got " + counts.node.scalar());
  }
  // unset switches take the controller's defaults (sim/servo.hpp)
  for (auto [key, target] : {std::pair{"velocity_feedforward", &s.velocity_feedforward},
                             std::pair{"acceleration_feedforward", &s.acceleration_feedforward},
                             std::pair{"gravity_compensation", &s.gravity_compensation},
                             std::pair{"deflection_compensation", &s.deflection_compensation}}) {
    if (const Field f = r.child(servo, key); f.node.defined()) *target = r.flag(f);
  }
}

void read_simulation(const Reader& r, const Field& root, Scenario& sc) {
  const Field sim = r.child(root, "simulation");
  if (sim.node.defined()) r.check_keys(sim);
  SimulationSettings& s = sc.simulation;
  s.settle_tolerance = r.number(r.value(sim, "settle_tolerance"));
  s.settle_speed_tolerance = r.number(r.value(sim, "settle_speed_tolerance"));
  s.settle_window = r.number(r.value(sim, "settle_window_s"));
  s.vibration_window = r.number(r.value(sim, "vibration_window_s"));
  s.vibration_highpass = r.number(r.value(sim, "vibration_highpass_hz"));
  s.jerk_lowpass = r.number(r.value(sim, "jerk_lowpass_hz"));
  const Field time = r.value(sim, "settle_time_s");
  s.settle_time = r.number(time);
  s.settle_time_where = r.where(time);
  // the settle window must fit into the simulated time after the reference
  if (s.settle_time < s.settle_window) {
    const Field window = r.child(sim, "settle_window_s");
    r.fail(r.child(sim, "settle_time_s").node.defined() || !window.node.defined() ? time : window,
           "settle_time_s (" + format_value(s.settle_time) + " s) must be at least the settle window settle_window_s (" +
               format_value(s.settle_window) + " s)");
  }
}

// `sensitivity`: the perturbed models, one per value of each key (absent keys take the table's
// defaults, so an absent map gives default_perturbations()). A value that is the nominal model's
// (a factor of 1) or repeats one of its list would run a model twice and is refused.
void read_sensitivity(const Reader& r, const Field& root, Scenario& sc) {
  const Field map = r.child(root, "sensitivity");
  if (map.node.defined()) r.check_keys(map);
  sc.sensitivity.where = map.node.defined() ? r.where(map) : SourceRef{};
  std::vector<Perturbation>& out = sc.sensitivity.perturbations;
  for (const char* key : {"stiffness_scale", "inertia_scale", "friction_scale", "extra_delay_ticks"}) {
    const Field list = r.value(map, key);
    const std::vector<double> values = r.numbers(list);
    const bool ticks = std::string_view(key) == "extra_delay_ticks";
    for (std::size_t i = 0; i < values.size(); ++i) {
      Field element = list;
      element.node = list.node[i];
      element.parent = &list;
      element.name = "";
      element.index = i;
      const double v = values[i];
      if (ticks && v != std::round(v)) r.fail(element, "a number of servo ticks must be whole, got " + element.node.scalar());
      if (!ticks && v == 1) r.fail(element, "a factor of 1 is the nominal model, which every sensitivity run includes");
      if (std::find(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(i), v) != values.begin() + static_cast<std::ptrdiff_t>(i)) {
        r.fail(element, "repeats an earlier value of the list: each value is one model, run once");
      }
      Perturbation p;
      if (ticks) {
        p.extra_delay_ticks = static_cast<int>(v);
        p.name = "delay +" + format_value(v) + (v == 1 ? " tick" : " ticks");
      } else {
        const std::string_view k(key);
        const std::string factor = " x" + format_value(v);
        if (k == "stiffness_scale") {
          p.stiffness_scale = v;
          p.name = "stiffness" + factor;
        } else if (k == "inertia_scale") {
          p.inertia_scale = v;
          p.name = "inertia" + factor;
        } else {
          p.friction_scale = v;
          p.name = "friction" + factor;
        }
      }
      out.push_back(std::move(p));
    }
  }
  if (out.empty()) r.fail(map, "every list is empty: a sensitivity run needs at least one perturbed model");
}

// `video`: size, rate and camera; each camera mode takes its own keys of the `camera` map.
void read_video(const Reader& r, const Field& root, Scenario& sc) {
  const Field video = r.child(root, "video");
  if (video.node.defined()) r.check_keys(video);
  const Field fps = r.value(video, "fps");
  sc.video.fps = r.number(fps);
  sc.video.fps_where = r.where(fps);
  for (auto [key, target] : {std::pair{"width", &sc.video.width}, std::pair{"height", &sc.video.height}}) {
    const Field f = r.value(video, key);
    *target = r.integer(f);
    if (*target % 2 != 0) r.fail(f, "must be an even number of pixels, got " + f.node.scalar());
  }
  const Field camera = r.child(video, "camera");
  if (!camera.node.defined()) return;
  r.check_keys(camera);
  VideoCamera& c = sc.video.camera;
  const std::string mode = r.choice(r.value(camera, "mode"));
  c.mode = mode == "fixed" ? CameraMode::kFixed : mode == "tcp" ? CameraMode::kTcp : CameraMode::kPart;
  // a key of another mode is named as such
  const std::vector<std::string_view> keys = c.mode == CameraMode::kPart    ? std::vector<std::string_view>{"mode", "fill", "azimuth_deg", "elevation_deg"}
                                             : c.mode == CameraMode::kFixed ? std::vector<std::string_view>{"mode", "position", "look_at", "fovy_deg"}
                                                                            : std::vector<std::string_view>{"mode", "distance", "azimuth_deg", "elevation_deg", "fovy_deg"};
  for (std::size_t i = 0; i < camera.node.size(); ++i) {
    const std::string& key = camera.node.key(i).scalar();
    if (std::find(keys.begin(), keys.end(), key) != keys.end()) continue;
    std::string list;
    for (const std::string_view k : keys) list.append(list.empty() ? "" : ", ").append(k);
    r.fail(r.child(camera, key), "not used with camera mode " + mode + " (its keys: " + list + ")");
  }
  c.fill = r.number(r.value(camera, "fill"));
  if (const Field f = r.child(camera, "azimuth_deg"); f.node.defined()) c.azimuth_deg = r.number(f);
  if (const Field f = r.child(camera, "elevation_deg"); f.node.defined()) c.elevation_deg = r.number(f);
  // defaults of the keys only some modes take: VideoCamera's
  if (const Field f = r.child(camera, "fovy_deg"); f.node.defined()) c.fovy_deg = r.number(f);
  if (const Field f = r.child(camera, "distance"); f.node.defined()) c.distance = r.number(f);
  if (c.mode == CameraMode::kFixed) {
    c.position = r.vec3(r.require(camera, "position"));
    const Field look = r.require(camera, "look_at");
    c.look_at = r.vec3(look);
    if ((c.look_at - c.position).norm() < 1e-6) r.fail(look, "the camera must look at a point other than its position");
  }
}

// `limits`, `axis_limits` and `timing`.
void read_limits(const Reader& r, const Field& root, Scenario& sc) {
  sc.timing = *algorithm_from_string(r.choice(r.value(root, "timing")));
  sc.limits = *limits_mode_from_string(r.choice(r.value(root, "limits")));
  const Field axes = r.child(root, "axis_limits");
  if (!axes.node.defined()) return;
  if (sc.limits != LimitsMode::kCartesian) {
    r.fail(axes, "per-axis limits need 'limits: cartesian' (path mode bounds no vector)");
  }
  r.check_keys(axes);
  AxisLimits out;
  out.acceleration = r.vec3(r.require(axes, "a"));
  out.jerk = r.vec3(r.require(axes, "j"));
  sc.axis_limits = out;
}

void read_variants(const Reader& r, const Field& root, Scenario& sc) {
  const Field variants = r.require(root, "variants");
  if (!variants.node.is_sequence() || variants.node.size() == 0) {
    r.fail(variants, "expected a non-empty list of variants, got " + what_is(variants.node));
  }
  if (variants.node.size() > kMaxVariants) {
    r.fail(r.item(variants, kMaxVariants), "more than " + std::to_string(kMaxVariants) + " variants (the limit of one scenario)");
  }
  std::set<std::string> names;
  for (std::size_t i = 0; i < variants.node.size(); ++i) {
    const Field f = r.item(variants, i);
    r.check_keys(f);
    Variant v;
    v.where = r.where(f);
    const Field name = r.require(f, "name");
    v.name = r.text(name);
    if (const std::string problem = folder_name_problem(v.name); !problem.empty()) r.fail(name, "variant " + problem);
    if (!names.insert(v.name).second) r.fail(name, "duplicate variant name '" + v.name + "'");
    if (const Field t = r.child(f, "transition"); t.node.defined()) v.transition = read_transition(r, t);
    if (const Field b = r.child(f, "buffer"); b.node.defined()) v.buffer = read_buffer(r, b);
    if (const Field s = r.child(f, "smoothing"); s.node.defined()) v.smoothing = read_smoothing(r, s, sc.program.smoothing);
    v.baseline = *baseline_from_string(r.choice(r.value(f, "baseline")));
    if (const Field t = r.child(f, "timing"); t.node.defined()) v.timing = *algorithm_from_string(r.choice(t));
    sc.variants.push_back(std::move(v));
  }
}

}  // namespace

std::string folder_name_problem(const std::string& name) {
  constexpr std::size_t kMaxLength = 100;
  const auto allowed = [](char c, bool first) {
    const bool alnum = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9');
    return alnum || c == '_' || (!first && (c == '-' || c == '.'));
  };
  const std::string rule = "(letters, digits, '_', '-', '.'; starting with a letter, digit or '_'; at most " +
                           std::to_string(kMaxLength) + " characters)";
  if (name.empty()) return "name is empty; it names the output folder " + rule;
  if (name.size() > kMaxLength) return "name is " + std::to_string(name.size()) + " characters long " + rule;
  for (std::size_t i = 0; i < name.size(); ++i) {
    if (!allowed(name[i], i == 0)) {
      return "name cannot name an output folder: character " + std::to_string(i + 1) + " is not allowed " + rule;
    }
  }
  return {};
}

std::string model_file(const std::string& urdf, ArmModel model) {
  const std::filesystem::path path(urdf);
  const std::string stem = path.stem().string() + (model == ArmModel::kElastic ? ".xml" : "_rigid.xml");
  return (path.parent_path() / stem).string();
}

std::vector<Perturbation> default_perturbations() {
  return {{"stiffness x0.5", 0.5, 1, 1, 0}, {"stiffness x1.5", 1.5, 1, 1, 0}, {"inertia x0.8", 1, 0.8, 1, 0},
          {"inertia x1.2", 1, 1.2, 1, 0},   {"friction x0.5", 1, 1, 0.5, 0},   {"friction x1.5", 1, 1, 1.5, 0},
          {"delay +1 tick", 1, 1, 1, 1}};
}

Scenario parse_scenario(const std::string& text, const std::string& file, const std::string& base_dir) {
  const Document doc(text, file);
  Reader r(doc, file, base_dir);
  const Field root = r.root();
  if (!root.node.is_map()) {
    r.fail(root, "a scenario must be a map with 'name', 'defaults', 'program' and 'variants', got " + what_is(root.node));
  }
  r.check_keys(root);
  Scenario sc;
  sc.file = file;
  const Field name = r.require(root, "name");
  sc.name = r.text(name);
  if (const std::string problem = folder_name_problem(sc.name); !problem.empty()) r.fail(name, "scenario " + problem);
  sc.description = r.text(r.value(root, "description"));
  const bool units_metres = r.choice(r.value(root, "units")) == "m";
  const double scale = units_metres ? 1.0 : 1e-3;
  r.set_scale(scale);
  if (const Field frame = r.child(root, "frame"); frame.node.defined()) {
    r.check_keys(frame);
    sc.frame.translation() = r.vec3(r.require(frame, "origin"));
    sc.frame.linear() = rpy_deg(radians(r.numbers(r.value(frame, "rpy_deg"))));
  }
  read_robot(r, root, sc);
  read_servo(r, root, sc);
  read_simulation(r, root, sc);
  read_sensitivity(r, root, sc);
  read_video(r, root, sc);
  read_limits(r, root, sc);
  read_program(r, root, sc);
  read_variants(r, root, sc);
  // the planner's own checks (joins, limits) on the first variant's program
  validate(program_for(sc, sc.variants.front()));
  // plausibility: valid, but looks like a mistake (warnings, not errors)
  const Field units = r.child(root, "units");
  if (auto warning = unit_warning(sc.program, units_metres, r.where(units.node.defined() ? units : root))) {
    sc.warnings.insert(sc.warnings.begin(), std::move(*warning));
  }
  if (auto warning = feed_speed_warning(sc)) sc.warnings.push_back(std::move(*warning));
  return sc;
}

Scenario load_scenario(const std::string& path) {
  const std::string text = read_input_file(path, "scenario file");
  const std::string dir = std::filesystem::path(path).parent_path().string();
  return parse_scenario(text, path, dir.empty() ? "." : dir);
}

Scenario gcode_scenario(const std::string& path, const std::optional<RobotSettings>& robot) {
  // no keys: every setting at the scenario format's default, as a scenario that gives none
  const Document doc("{}", path);
  const std::string dir = std::filesystem::path(path).parent_path().string();
  Reader r(doc, path, dir.empty() ? "." : dir);
  const Field root = r.root();
  Scenario sc;
  sc.file = path;
  sc.name = name_from_file(path);
  sc.description = "G-code part program " + std::filesystem::path(path).filename().string() +
                   " on the shipped arm, placed in front of it";
  read_robot(r, root, sc);
  if (robot) sc.robot = *robot;
  read_servo(r, root, sc);
  read_simulation(r, root, sc);
  read_sensitivity(r, root, sc);
  read_video(r, root, sc);
  read_limits(r, root, sc);
  sc.program.start_orientation = Quat(sc.robot.tool_rotation).normalized();
  MoveDefaults defaults;
  defaults.limits = {kGcodeFeed, kGcodeAcceleration, kGcodeAcceleration, kGcodeJerk};
  defaults.angular = read_angular(r, r.child(root, "defaults"), {}, true);
  // read in its own frame, then placed: the centre of its box at kGcodePartCentre
  const GcodeResult parsed = load_gcode_file(path, gcode_options(defaults, sc));
  const auto [lo, hi] = path_box(parsed.program, parsed.start);
  sc.frame.translation() = kGcodePartCentre - (lo + hi) / 2;
  place_gcode(parsed, defaults.angular, sc);
  Variant as_programmed;
  as_programmed.name = "as_programmed";
  Variant exact_stop;
  exact_stop.name = "exact_stop";
  exact_stop.transition = Transition{};
  sc.variants = {as_programmed, exact_stop};
  validate(program_for(sc, sc.variants.front()));
  return sc;
}

RobotSettings named_robot(const std::string& urdf_or_name, const std::string& flag) {
  std::string urdf;
  std::error_code ec;
  if (std::filesystem::is_regular_file(urdf_or_name, ec)) {
    urdf = urdf_or_name;
  } else if (folder_name_problem(urdf_or_name).empty()) {
    if (const std::string shipped = data_file("models/" + urdf_or_name + ".urdf"); std::filesystem::is_regular_file(shipped, ec)) {
      urdf = shipped;
    }
  }
  if (urdf.empty()) {
    throw InputError("", 0, 0, flag,
                     "'" + printable(urdf_or_name) + "' is neither a URDF file nor a shipped robot (ur5e_like, kr6_like)");
  }
  RobotSettings robot;
  robot.urdf = std::filesystem::absolute(urdf).string();
  if (const std::string beside = model_file(robot.urdf, robot.model); std::filesystem::is_regular_file(beside, ec)) {
    robot.mjcf = beside;
  } else {
    robot.mjcf_from_urdf = true;
    robot.model = ArmModel::kRigid;
  }
  return robot;
}

Program program_for(const Scenario& scenario, const Variant& variant) {
  Program program = scenario.program;
  for (std::size_t k = 0; k < program.moves.size(); ++k) {
    if (variant.transition && !scenario.explicit_transition[k]) program.moves[k].transition = *variant.transition;
    if (variant.buffer && !scenario.explicit_buffer[k]) program.moves[k].buffer = *variant.buffer;
  }
  if (variant.smoothing) program.smoothing = *variant.smoothing;
  return program;
}

TimingOptions timing_options(const Scenario& scenario, const Variant& variant) {
  TimingOptions options;
  options.dt = 1.0 / scenario.servo.setpoint_rate_hz;
  options.limits = scenario.limits;
  options.axis_limits = scenario.axis_limits;
  options.baseline = variant.baseline;
  options.algorithm = variant.timing.value_or(scenario.timing);
  return options;
}

const Variant& find_variant(const Scenario& scenario, const std::string& name) {
  std::string names;
  for (const Variant& v : scenario.variants) {
    if (v.name == name) return v;
    names += (names.empty() ? "" : ", ") + v.name;
  }
  throw InputError("", 0, 0, "--variant", "no variant '" + name + "' in " + scenario.file + " (variants: " + names + ")");
}

}  // namespace blendbench
