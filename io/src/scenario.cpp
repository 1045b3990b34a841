#include "blendbench/io/scenario.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <numbers>
#include <set>
#include <sstream>

#include "blendbench/geometry/arc_construction.hpp"
#include "blendbench/io/data_root.hpp"
#include "blendbench/io/program_io.hpp"

namespace blendbench {
namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

// A YAML node with its field path, so every error can name file, line, column and field.
struct Field {
  YAML::Node node;
  std::string path;
};

class Reader {
 public:
  Reader(std::string file, std::string base_dir) : file_(std::move(file)), base_dir_(std::move(base_dir)) {}

  [[noreturn]] void fail(const Field& f, const std::string& message) const {
    const YAML::Mark mark = f.node.IsDefined() ? f.node.Mark() : YAML::Mark::null_mark();
    const int line = mark.line >= 0 ? mark.line + 1 : 0;
    const int column = mark.column >= 0 ? mark.column + 1 : 0;
    throw InputError(file_, line, column, f.path, message);
  }

  // Fails on any key of the map `f` that is not in `allowed`.
  void check_keys(const Field& f, std::initializer_list<const char*> allowed) const {
    if (!f.node.IsMap()) fail(f, "expected a mapping (key: value pairs)");
    const std::set<std::string> keys(allowed.begin(), allowed.end());
    for (const auto& item : f.node) {
      // a key is a name: a list or mapping as a key (YAML's "? [a, b]") is refused where it stands
      if (!item.first.IsScalar()) fail({item.first, f.path}, "a key must be a name, not a list or mapping");
      const std::string key = item.first.as<std::string>();
      if (keys.count(key) == 0) {
        std::string list;
        for (const char* k : allowed) list += std::string(list.empty() ? "" : ", ") + k;
        fail({item.first, join(f.path, key)}, "unknown key '" + key + "' (allowed: " + list + ")");
      }
    }
  }

  static std::string join(const std::string& path, const std::string& key) {
    return path.empty() ? key : path + "." + key;
  }

  // The child `key` of map `f`; undefined when absent. Looked up through a const node and
  // copy-constructed: assigning a yaml-cpp node to one of another document merges the two
  // documents' node sets, which made every lookup cost the size of the file (loading was
  // quadratic in the number of moves).
  static Field child(const Field& f, const std::string& key) {
    if (f.node.IsMap()) {
      const YAML::Node& map = f.node;
      if (YAML::Node c = map[key]; c.IsDefined()) return {c, join(f.path, key)};
    }
    return {YAML::Node(YAML::NodeType::Undefined), join(f.path, key)};
  }

  Field require(const Field& f, const std::string& key) const {
    Field c = child(f, key);
    if (!c.node.IsDefined() || c.node.IsNull()) {
      Field at = f;
      at.path = c.path;
      fail(at, "missing required field");
    }
    return c;
  }

  double number(const Field& f) const {
    if (!f.node.IsScalar()) fail(f, "expected a number");
    try {
      const double value = f.node.as<double>();
      if (!std::isfinite(value)) fail(f, "expected a finite number");
      return value;
    } catch (const YAML::BadConversion&) {
      fail(f, "expected a number, got '" + f.node.Scalar() + "'");
    }
  }

  double positive(const Field& f) const {
    const double value = number(f);
    if (!(value > 0)) fail(f, "must be positive, got " + f.node.Scalar());
    return value;
  }

  double non_negative(const Field& f) const {
    const double value = number(f);
    if (value < 0) fail(f, "must be >= 0, got " + f.node.Scalar());
    return value;
  }

  int integer(const Field& f) const {
    if (!f.node.IsScalar()) fail(f, "expected an integer");
    try {
      return f.node.as<int>();
    } catch (const YAML::BadConversion&) {
      fail(f, "expected an integer, got '" + f.node.Scalar() + "'");
    }
  }

  bool boolean(const Field& f) const {
    if (!f.node.IsScalar()) fail(f, "expected true or false");
    try {
      return f.node.as<bool>();
    } catch (const YAML::BadConversion&) {
      fail(f, "expected true or false, got '" + f.node.Scalar() + "'");
    }
  }

  std::string text(const Field& f) const {
    if (!f.node.IsScalar()) fail(f, "expected a string");
    return f.node.Scalar();
  }

  template <std::size_t N>
  std::array<double, N> numbers(const Field& f) const {
    if (!f.node.IsSequence() || f.node.size() != N) fail(f, "expected a list of " + std::to_string(N) + " numbers");
    std::array<double, N> out{};
    for (std::size_t i = 0; i < N; ++i) out[i] = number({f.node[i], f.path + "[" + std::to_string(i) + "]"});
    return out;
  }

  Vec3 vec3(const Field& f) const {
    const auto v = numbers<3>(f);
    return {v[0], v[1], v[2]};
  }

  SourceRef where(const Field& f) const {
    const YAML::Mark mark = f.node.IsDefined() ? f.node.Mark() : YAML::Mark::null_mark();
    return {file_, mark.line >= 0 ? mark.line + 1 : 0, mark.column >= 0 ? mark.column + 1 : 0};
  }

  // An existing file named relative to the scenario's directory, then to the data root
  // (data_root.hpp: models/ and scenarios/ in the source tree or the install prefix).
  std::string existing_file(const Field& f) const {
    const std::string name = text(f);
    namespace fs = std::filesystem;
    const auto found = [](const fs::path& candidate) { return fs::is_regular_file(candidate); };
    const auto result = [](const fs::path& candidate) { return fs::absolute(candidate).lexically_normal().string(); };
    if (fs::path(name).is_absolute()) {
      if (found(name)) return result(name);
      fail(f, "file not found: " + name);
    }
    if (found(fs::path(base_dir_) / name)) return result(fs::path(base_dir_) / name);
    fs::path root;
    try {
      root = data_root();
    } catch (const DataRootError& e) {
      fail(f, "file not found: " + name + " (not beside the scenario, and " + e.what() + ")");
    }
    if (found(root / name)) return result(root / name);
    fail(f, "file not found: " + name);
  }

  [[nodiscard]] const std::string& file() const { return file_; }

 private:
  std::string file_;
  std::string base_dir_;
};

Eigen::Matrix3d rpy_deg(const std::array<double, 3>& rpy) {
  // fixed-axis roll (x), pitch (y), yaw (z), as in URDF: R = Rz(yaw) Ry(pitch) Rx(roll)
  return (Eigen::AngleAxisd(rpy[2] * kDeg, Vec3::UnitZ()) * Eigen::AngleAxisd(rpy[1] * kDeg, Vec3::UnitY()) *
          Eigen::AngleAxisd(rpy[0] * kDeg, Vec3::UnitX()))
      .toRotationMatrix();
}

// Unit scale of lengths for a scenario: 1e-3 for mm, 1 for m.
double unit_scale(const Reader& r, const Field& root) {
  const Field f = Reader::child(root, "units");
  if (!f.node.IsDefined()) return 1e-3;
  const std::string units = r.text(f);
  if (units == "mm") return 1e-3;
  if (units == "m") return 1.0;
  r.fail(f, "units must be 'mm' or 'm', got '" + units + "'");
}

Transition read_transition(const Reader& r, const Field& f, double scale) {
  r.check_keys(f, {"method", "parameter", "start_distance", "kappa_max", "velocity"});
  Transition t;
  const Field method = r.require(f, "method");
  const auto m = method_from_string(r.text(method));
  if (!m) r.fail(method, "unknown method '" + r.text(method) + "' (none, arc, bezier, clothoid, biclothoid)");
  t.method = *m;
  const Field parameter = Reader::child(f, "parameter");
  const Field start = Reader::child(f, "start_distance");
  if (start.node.IsDefined()) {
    if (t.method != Method::kBiclothoid) {
      r.fail(start, "a start distance sizes only a biclothoid transition, not " + r.text(method));
    }
    if (parameter.node.IsDefined()) {
      r.fail(start, "give the biclothoid either a maximum deviation (parameter) or a start distance, not both");
    }
    t.start_distance = r.non_negative(start) * scale;
    if (!(t.start_distance > 0)) r.fail(start, "the start distance must be positive");
  } else if (parameter.node.IsDefined()) {
    t.parameter = r.non_negative(parameter) * scale;
  } else if (t.method != Method::kNone) {
    r.fail(r.require(f, "parameter"), "missing required field");
  }
  if (const Field k = Reader::child(f, "kappa_max"); k.node.IsDefined()) t.kappa_max = r.non_negative(k) / scale;
  if (const Field v = Reader::child(f, "velocity"); v.node.IsDefined()) t.velocity = r.non_negative(v) * scale;
  return t;
}

BufferMode read_buffer(const Reader& r, const Field& f) {
  const auto mode = buffer_mode_from_string(r.text(f));
  if (!mode) {
    r.fail(f, "unknown buffer mode '" + r.text(f) +
                  "' (Aborting, Buffered, BlendingLow, BlendingPrevious, BlendingNext, BlendingHigh)");
  }
  return *mode;
}

// Reads one arc specification; positions are in the program frame, scaled to metres.
Arc read_arc(const Reader& r, const Field& f, const Vec3& start, double scale) {
  r.check_keys(f, {"end", "center", "radius", "via", "direction", "normal", "turns"});
  const Vec3 end = r.vec3(r.require(f, "end")) * scale;
  const Field via = Reader::child(f, "via");
  const Field center = Reader::child(f, "center");
  const Field radius = Reader::child(f, "radius");
  const int given = static_cast<int>(via.node.IsDefined()) + static_cast<int>(center.node.IsDefined()) +
                    static_cast<int>(radius.node.IsDefined());
  if (given != 1) r.fail(f, "an arc needs exactly one of 'center', 'radius' or 'via'");

  ArcBuild built;
  if (via.node.IsDefined()) {
    for (const char* key : {"direction", "normal", "turns"}) {
      if (Reader::child(f, key).node.IsDefined()) r.fail(Reader::child(f, key), "not used with 'via' (the via point fixes the arc)");
    }
    built = arc_through(start, r.vec3(via) * scale, end);
    if (!built.outcome.ok()) r.fail(via, built.outcome.message);
    return built.arc;
  }
  const Field direction = r.require(f, "direction");
  const std::string dir = r.text(direction);
  if (dir != "cw" && dir != "ccw") r.fail(direction, "direction must be 'cw' or 'ccw', got '" + dir + "'");
  const bool ccw = dir == "ccw";
  Vec3 normal = Vec3::UnitZ();
  if (const Field n = Reader::child(f, "normal"); n.node.IsDefined()) {
    normal = r.vec3(n);
    if (!(normal.norm() > 0)) r.fail(n, "the normal must not be zero");
  }
  int turns = 0;
  if (const Field t = Reader::child(f, "turns"); t.node.IsDefined()) {
    turns = r.integer(t);
    if (turns < 0) r.fail(t, "turns must be >= 0");
  }
  if (center.node.IsDefined()) {
    // a tolerance of a micrometre (scaled) on the radii, like a CNC control's arc check
    built = arc_from_center(start, end, r.vec3(center) * scale, normal, ccw, turns, 1e-6);
    if (!built.outcome.ok()) r.fail(center, built.outcome.message);
  } else {
    if (turns != 0) r.fail(Reader::child(f, "turns"), "'turns' needs a 'center'");
    built = arc_from_radius(start, end, r.number(radius) * scale, normal, ccw, 1e-9);
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
  BufferMode buffer = BufferMode::kBlendingLow;
};

MoveDefaults read_defaults(const Reader& r, const Field& root, double scale) {
  const Field defaults = r.require(root, "defaults");
  r.check_keys(defaults, {"velocity", "acceleration", "deceleration", "jerk", "buffer"});
  MoveDefaults d;
  d.limits.velocity = r.positive(r.require(defaults, "velocity")) * scale;
  d.limits.acceleration = r.positive(r.require(defaults, "acceleration")) * scale;
  const Field dec = Reader::child(defaults, "deceleration");
  d.limits.deceleration = dec.node.IsDefined() ? r.positive(dec) * scale : d.limits.acceleration;
  d.limits.jerk = r.positive(r.require(defaults, "jerk")) * scale;
  if (const Field b = Reader::child(defaults, "buffer"); b.node.IsDefined()) d.buffer = read_buffer(r, b);
  return d;
}

// A program given as a G-code file: read in its own units (G20/G21), placed by the frame.
// Variants replace the transitions of all its moves (the file's G61/G64 apply when a variant
// sets no transition).
void read_gcode_program(const Reader& r, const Field& gcode, const Field& start, double scale,
                        const MoveDefaults& defaults, Scenario& sc) {
  GcodeOptions options;
  options.limits = defaults.limits;
  options.buffer = defaults.buffer;
  if (start.node.IsDefined()) options.start = r.vec3(start) * scale;
  const GcodeResult parsed = load_gcode_file(r.existing_file(gcode), options);
  sc.start = sc.frame * parsed.start;
  sc.ignored = parsed.ignored;
  for (Move move : parsed.program.moves) {
    if (Line* line = std::get_if<Line>(&move.geometry)) {
      line->p0 = sc.frame * line->p0;
      line->p1 = sc.frame * line->p1;
    } else {
      move.geometry = transformed(std::get<Arc>(move.geometry), sc.frame);
    }
    sc.program.moves.push_back(std::move(move));
    sc.explicit_transition.push_back(false);
    sc.explicit_buffer.push_back(false);
  }
}

void read_program(const Reader& r, const Field& root, double scale, Scenario& sc) {
  const Field program = r.require(root, "program");
  r.check_keys(program, {"start", "moves", "gcode"});
  const Field moves = Reader::child(program, "moves");
  const Field gcode = Reader::child(program, "gcode");
  const MoveDefaults defaults = read_defaults(r, root, scale);
  const Limits& base = defaults.limits;
  const BufferMode base_buffer = defaults.buffer;
  if (gcode.node.IsDefined()) {
    if (moves.node.IsDefined()) r.fail(moves, "give either 'moves' or 'gcode', not both");
    read_gcode_program(r, gcode, Reader::child(program, "start"), scale, defaults, sc);
    return;
  }
  if (!moves.node.IsDefined()) r.fail(r.require(program, "moves"), "missing required field");
  if (!moves.node.IsSequence() || moves.node.size() == 0) r.fail(moves, "expected a non-empty list of moves");

  Vec3 current = Vec3::Zero();
  if (const Field s = Reader::child(program, "start"); s.node.IsDefined()) current = r.vec3(s) * scale;
  sc.start = sc.frame * current;

  for (std::size_t i = 0; i < moves.node.size(); ++i) {
    const Field m{moves.node[i], moves.path + "[" + std::to_string(i) + "]"};
    r.check_keys(m, {"line", "arc", "velocity", "acceleration", "deceleration", "jerk", "buffer", "transition"});
    const Field line = Reader::child(m, "line");
    const Field arc = Reader::child(m, "arc");
    if (line.node.IsDefined() == arc.node.IsDefined()) r.fail(m, "a move needs exactly one of 'line' or 'arc'");
    Move move;
    move.where = r.where(m);
    move.name = "move " + std::to_string(i + 1) + " (line " + std::to_string(move.where.line) + ")";
    if (line.node.IsDefined()) {
      const Vec3 end = r.vec3(line) * scale;
      if ((end - current).norm() <= 1e-12) r.fail(line, "zero-length move: the end point equals the start point");
      move.geometry = Line{sc.frame * current, sc.frame * end};
      current = end;
    } else {
      const Arc a = read_arc(r, arc, current, scale);
      move.geometry = transformed(a, sc.frame);
      current = point(Segment(a), length(a));
    }
    move.limits = base;
    if (const Field v = Reader::child(m, "velocity"); v.node.IsDefined()) move.limits.velocity = r.positive(v) * scale;
    if (const Field a = Reader::child(m, "acceleration"); a.node.IsDefined()) {
      move.limits.acceleration = r.positive(a) * scale;
    }
    if (const Field d = Reader::child(m, "deceleration"); d.node.IsDefined()) {
      move.limits.deceleration = r.positive(d) * scale;
    }
    if (const Field j = Reader::child(m, "jerk"); j.node.IsDefined()) move.limits.jerk = r.positive(j) * scale;
    move.buffer = base_buffer;
    const Field b = Reader::child(m, "buffer");
    if (b.node.IsDefined()) move.buffer = read_buffer(r, b);
    const Field t = Reader::child(m, "transition");
    if (t.node.IsDefined()) move.transition = read_transition(r, t, scale);
    sc.explicit_transition.push_back(t.node.IsDefined());
    sc.explicit_buffer.push_back(b.node.IsDefined());
    sc.program.moves.push_back(std::move(move));
  }
}

void read_robot_fields(const Reader& r, const Field& root, Scenario& sc) {
  const Field robot = Reader::child(root, "robot");
  // default: tool pointing down (TCP z along -Z of the base)
  sc.robot.tool_rotation = rpy_deg({180, 0, 0});
  // the ready configuration of the model (keyframe "ready"): elbow up, tool down, facing +x
  sc.robot.q_seed << 180 * kDeg, -90 * kDeg, 90 * kDeg, -90 * kDeg, -90 * kDeg, 0;
  if (!robot.node.IsDefined()) return;
  r.check_keys(robot, {"urdf", "mjcf", "base_link", "tip_link", "tool_rpy_deg", "q_seed_deg"});
  if (const Field f = Reader::child(robot, "urdf"); f.node.IsDefined()) sc.robot.urdf = r.existing_file(f);
  if (const Field f = Reader::child(robot, "mjcf"); f.node.IsDefined()) sc.robot.mjcf = r.existing_file(f);
  if (const Field f = Reader::child(robot, "base_link"); f.node.IsDefined()) sc.robot.base_link = r.text(f);
  if (const Field f = Reader::child(robot, "tip_link"); f.node.IsDefined()) sc.robot.tip_link = r.text(f);
  if (const Field f = Reader::child(robot, "tool_rpy_deg"); f.node.IsDefined()) {
    sc.robot.tool_rotation = rpy_deg(r.numbers<3>(f));
  }
  if (const Field f = Reader::child(robot, "q_seed_deg"); f.node.IsDefined()) {
    const auto q = r.numbers<6>(f);
    for (int i = 0; i < 6; ++i) sc.robot.q_seed[i] = q[static_cast<std::size_t>(i)] * kDeg;
  }
}

void read_robot(const Reader& r, const Field& root, Scenario& sc) {
  read_robot_fields(r, root, sc);
  // the shipped arm in the data root (data_root.hpp) unless the scenario names its own model
  if (sc.robot.urdf.empty()) sc.robot.urdf = data_file("models/ur5e_like.urdf");
  if (sc.robot.mjcf.empty()) sc.robot.mjcf = data_file("models/ur5e_like.xml");
}

void read_settings(const Reader& r, const Field& root, double scale, Scenario& sc) {
  if (const Field servo = Reader::child(root, "servo"); servo.node.IsDefined()) {
    r.check_keys(servo, {"rate_hz", "kp", "kd", "gravity_compensation", "feedforward"});
    if (const Field f = Reader::child(servo, "rate_hz"); f.node.IsDefined()) {
      sc.servo.rate_hz = r.positive(f);
      // the physics step is 1 ms: a servo tick must fall on a step
      const double ratio = 1000.0 / sc.servo.rate_hz;
      if (sc.servo.rate_hz > 1000.0 || std::abs(ratio - std::round(ratio)) > 1e-9) {
        r.fail(f, "the servo rate must divide the 1000 Hz physics rate (1000, 500, 250, 200, ...)");
      }
    }
    if (const Field f = Reader::child(servo, "kp"); f.node.IsDefined()) sc.servo.kp = r.numbers<6>(f);
    if (const Field f = Reader::child(servo, "kd"); f.node.IsDefined()) sc.servo.kd = r.numbers<6>(f);
    if (const Field f = Reader::child(servo, "gravity_compensation"); f.node.IsDefined()) {
      sc.servo.gravity_compensation = r.boolean(f);
    }
    if (const Field f = Reader::child(servo, "feedforward"); f.node.IsDefined()) sc.servo.feedforward = r.boolean(f);
  }
  if (const Field sim = Reader::child(root, "simulation"); sim.node.IsDefined()) {
    r.check_keys(sim, {"settle_tolerance", "settle_time_s"});
    if (const Field f = Reader::child(sim, "settle_tolerance"); f.node.IsDefined()) {
      sc.simulation.settle_tolerance = r.positive(f) * scale;
    }
    if (const Field f = Reader::child(sim, "settle_time_s"); f.node.IsDefined()) {
      sc.simulation.settle_time = r.non_negative(f);
    }
  }
  if (const Field video = Reader::child(root, "video"); video.node.IsDefined()) {
    r.check_keys(video, {"fps", "width", "height"});
    if (const Field f = Reader::child(video, "fps"); f.node.IsDefined()) {
      sc.video.fps = r.positive(f);
      if (sc.video.fps < 24 || sc.video.fps > 120) r.fail(f, "fps must be between 24 and 120");
    }
    for (auto [key, target] : {std::pair{"width", &sc.video.width}, std::pair{"height", &sc.video.height}}) {
      const Field f = Reader::child(video, key);
      if (!f.node.IsDefined()) continue;
      *target = r.integer(f);
      if (*target < 64 || *target > 1920 || *target % 2 != 0) r.fail(f, "must be an even number of pixels in [64, 1920]");
    }
  }
}

void read_variants(const Reader& r, const Field& root, double scale, Scenario& sc) {
  const Field variants = r.require(root, "variants");
  if (!variants.node.IsSequence() || variants.node.size() == 0) r.fail(variants, "expected a non-empty list of variants");
  std::set<std::string> names;
  for (std::size_t i = 0; i < variants.node.size(); ++i) {
    const Field f{variants.node[i], variants.path + "[" + std::to_string(i) + "]"};
    r.check_keys(f, {"name", "transition", "buffer", "baseline"});
    Variant v;
    v.where = r.where(f);
    const Field name = r.require(f, "name");
    v.name = r.text(name);
    if (const std::string problem = folder_name_problem(v.name); !problem.empty()) r.fail(name, "variant " + problem);
    if (!names.insert(v.name).second) r.fail(name, "duplicate variant name '" + v.name + "'");
    if (const Field t = Reader::child(f, "transition"); t.node.IsDefined()) v.transition = read_transition(r, t, scale);
    if (const Field b = Reader::child(f, "buffer"); b.node.IsDefined()) v.buffer = read_buffer(r, b);
    if (const Field b = Reader::child(f, "baseline"); b.node.IsDefined()) {
      v.baseline = r.text(b);
      if (v.baseline != "none" && v.baseline != "exact_stop" && v.baseline != "junction_slowdown") {
        r.fail(b, "baseline must be 'none', 'exact_stop' or 'junction_slowdown'");
      }
    }
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

Scenario parse_scenario(const std::string& text, const std::string& file, const std::string& base_dir) {
  const Reader r(file, base_dir);
  YAML::Node doc;
  try {
    doc = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw InputError(file, e.mark.line + 1, e.mark.column + 1, "", "invalid YAML: " + e.msg);
  }
  const Field root{doc, ""};
  if (!doc.IsMap()) r.fail(root, "a scenario must be a mapping with 'name', 'program' and 'variants'");
  r.check_keys(root, {"name", "description", "units", "robot", "servo", "simulation", "video", "frame", "defaults",
                      "program", "variants"});
  Scenario sc;
  sc.file = file;
  const Field name = r.require(root, "name");
  sc.name = r.text(name);
  if (const std::string problem = folder_name_problem(sc.name); !problem.empty()) r.fail(name, "scenario " + problem);
  if (const Field d = Reader::child(root, "description"); d.node.IsDefined()) sc.description = r.text(d);
  const double scale = unit_scale(r, root);
  if (const Field frame = Reader::child(root, "frame"); frame.node.IsDefined()) {
    r.check_keys(frame, {"origin", "rpy_deg"});
    sc.frame.translation() = r.vec3(r.require(frame, "origin")) * scale;
    if (const Field rpy = Reader::child(frame, "rpy_deg"); rpy.node.IsDefined()) {
      sc.frame.linear() = rpy_deg(r.numbers<3>(rpy));
    }
  }
  read_robot(r, root, sc);
  read_settings(r, root, scale, sc);
  read_program(r, root, scale, sc);
  read_variants(r, root, scale, sc);
  // the planner's own checks (joins, limits) on the first variant's program
  validate(program_for(sc, sc.variants.front()));
  return sc;
}

Scenario load_scenario(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, 0, 0, "", "cannot open the scenario file");
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string dir = std::filesystem::path(path).parent_path().string();
  return parse_scenario(buffer.str(), path, dir.empty() ? "." : dir);
}

Program program_for(const Scenario& scenario, const Variant& variant) {
  Program program = scenario.program;
  for (std::size_t k = 0; k < program.moves.size(); ++k) {
    if (variant.transition && !scenario.explicit_transition[k]) program.moves[k].transition = *variant.transition;
    if (variant.buffer && !scenario.explicit_buffer[k]) program.moves[k].buffer = *variant.buffer;
  }
  return program;
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
