// The G-code reader (gcode.hpp): an interpreter of RS274/NGC blocks that keeps LinuxCNC's
// modal state and turns motion words into moves. The lexer (gcode_lexer.cpp) splits a line into
// words, gcode_words.cpp checks them against the RS274/NGC tables; this file executes them.

#include "blendbench/io/gcode.hpp"

#include "blendbench/geometry/arc_construction.hpp"
#include "blendbench/core/format.hpp"
#include "blendbench/core/units.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <utility>

#include "gcode_angles.hpp"
#include "gcode_lexer.hpp"
#include "gcode_words.hpp"

namespace blendbench {
namespace {

using namespace gcode_detail;  // the lexer and word checks private to the G-code reader

constexpr double kMetresPerMm = 1e-3;
constexpr double kMetresPerInch = 0.0254;
constexpr double kTwoPi = 2 * std::numbers::pi;

// LinuxCNC interp_internal.hh: CENTER_ARC_RADIUS_TOLERANCE_INCH / _MM, SPIRAL_RELATIVE_TOLERANCE,
// RADIUS_TOLERANCE_INCH / _MM (in program units).
constexpr double kCentreArcRadiusTolInch = 2 * 0.001 * std::numbers::sqrt2;
constexpr double kCentreArcRadiusTolMm = 2 * 0.01 * std::numbers::sqrt2;
constexpr double kSpiralRelativeTol = 0.001;
constexpr double kRadiusTolInch = 0.00005;
constexpr double kRadiusTolMm = kRadiusTolInch * 25.4;

// An arc end point this close to its start (m, in the plane) makes a full circle.
constexpr double kSamePoint = kZeroLengthMove;
// Arc centre corrections below this (m) are rounding, not worth a note.
constexpr double kNoteworthyRadiusError = 1e-9;
// Samples per turn when comparing a corrected arc with LinuxCNC's spiral.
constexpr int kSpiralSamples = 128;
// Rad: a dropped move whose angles turn the tool by more than this would lose a rotation.
constexpr double kSameOrientation = 1e-9;

using Vec2 = Eigen::Vector2d;

enum class Plane { kXY, kXZ, kYZ };
enum class Motion { kNone, kRapid, kLinear, kCw, kCcw };

// The plane's in-plane axes a1, a2 and normal n = a1 x a2 (RS274/NGC: G17 XY about +Z,
// G18 ZX about +Y, G19 YZ about +X; G2 is clockwise seen from the positive end of n).
struct PlaneAxes {
  Vec3 a1;
  Vec3 a2;
  Vec3 n;
  char off1;  // offset letter along a1
  char off2;  // offset letter along a2
  char off_normal;  // the offset letter that does not belong to the plane
  const char* name;
};

PlaneAxes axes_of(Plane plane) {
  switch (plane) {
    case Plane::kXY: return {Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ(), 'I', 'J', 'K', "G17 (XY)"};
    case Plane::kXZ: return {Vec3::UnitZ(), Vec3::UnitX(), Vec3::UnitY(), 'K', 'I', 'J', "G18 (XZ)"};
    case Plane::kYZ: return {Vec3::UnitY(), Vec3::UnitZ(), Vec3::UnitX(), 'J', 'K', 'I', "G19 (YZ)"};
  }
  return {};
}


class Reader {
 public:
  Reader(std::string_view text, const std::string& file, const GcodeOptions& options)
      : text_(text), file_(file), options_(options) {
    pos_ = options.start;
    path_orientation_ = options.start_orientation.normalized();
    if (options.angles) angles_.emplace(*options.angles);
    path_end_ = options.start;
    feed_ = options.limits.velocity;
    transition_ = options.blending;
  }

  GcodeResult run() {
    check_options();
    result_.start = options_.start;
    // a UTF-8 byte order mark (editors on Windows) is not part of the program
    if (text_.substr(0, 3) == "\xEF\xBB\xBF") text_.remove_prefix(3);
    // line by line, never all lines at once (a file of empty lines would cost 16 bytes a byte)
    int line_no = 0;
    for (std::size_t begin = 0; begin <= text_.size(); ++line_no) {
      const std::size_t end = std::min(text_.find('\n', begin), text_.size());
      const std::string_view line = text_.substr(begin, end - begin);
      const std::size_t next = end + 1;
      begin = next;
      const int number = line_no + 1;
      const std::string_view stripped = strip_blanks(line);
      // tape markers: '%' alone on a line opens the program (first) or ends it
      if (stripped == "%") {
        if (!opened_ && !seen_code_) {
          opened_ = true;
          continue;
        }
        note_rest(next, number, "the closing % (line " + std::to_string(number) + ")");
        break;
      }
      if (!stripped.empty() && stripped.front() == '/') {
        result_.ignored.push_back("line " + std::to_string(number) + ": block delete '/', line skipped");
        seen_code_ = true;
        continue;
      }
      Block block = lex_block(line, number, file_);
      if (block.words.empty()) continue;
      seen_code_ = true;
      if (block.unicode_minus) {
        result_.ignored.push_back("line " + std::to_string(number) + ": Unicode minus sign (U+2212) read as '-'");
      }
      execute(block);
      if (ended_) {
        note_rest(next, number, end_word_ + " (line " + std::to_string(number) + ")");
        break;
      }
    }
    if (result_.program.moves.empty()) {
      throw InputError(file_, 0, 0, "", "the G-code program has no moves");
    }
    return std::move(result_);
  }

 private:
  [[noreturn]] void fail(int line, int column, const std::string& word, const std::string& message) const {
    throw InputError(file_, line, column, word, message);
  }

  void check_options() const {
    const std::array<std::pair<double, const char*>, 4> limits = {{{options_.limits.velocity, "limits.velocity"},
                                                                   {options_.limits.acceleration, "limits.acceleration"},
                                                                   {options_.limits.deceleration, "limits.deceleration"},
                                                                   {options_.limits.jerk, "limits.jerk"}}};
    for (const auto& [value, field] : limits) {
      if (!std::isfinite(value) || value <= 0) {
        throw InputError(file_, 0, 0, field, std::string("G-code options: ") + field + " must be positive, got " + format_value(value, 10));
      }
    }
    if (!std::isfinite(options_.rapid_velocity) || options_.rapid_velocity < 0) {
      throw InputError(file_, 0, 0, "rapid_velocity", "G-code options: rapid_velocity must be >= 0");
    }
    if (!options_.start.allFinite()) throw InputError(file_, 0, 0, "start", "G-code options: start must be finite");
    if (!options_.start_orientation.coeffs().allFinite() || !(options_.start_orientation.norm() > 0.5)) {
      throw InputError(file_, 0, 0, "start_orientation", "G-code options: start_orientation must be a unit quaternion");
    }
    if (options_.angles) {
      std::array<bool, 3> named{};
      for (const ToolAngle a : options_.angles->abc) named[static_cast<std::size_t>(a)] = true;
      if (!(named[0] && named[1] && named[2])) {
        throw InputError(file_, 0, 0, "angles", "G-code options: A, B and C must name roll, pitch and yaw, each once");
      }
    }
  }

  // Notes the non-blank lines not read: those from text offset `begin` on, line `line` being the
  // last one read.
  void note_rest(std::size_t begin, int line, const std::string& why) {
    int first = 0;
    int last = 0;
    for (; begin <= text_.size(); begin = std::min(text_.find('\n', begin), text_.size()) + 1) {
      ++line;
      const std::size_t end = std::min(text_.find('\n', begin), text_.size());
      if (strip_blanks(text_.substr(begin, end - begin)).empty()) continue;
      if (first == 0) first = line;
      last = line;
    }
    if (first == 0) return;
    const std::string range = first == last ? "line " + std::to_string(first)
                                            : "lines " + std::to_string(first) + "-" + std::to_string(last);
    result_.ignored.push_back(range + " after " + why + " not read");
  }

  std::string note_of(const Word& word, int line) const { return word.text + " (line " + std::to_string(line) + ")"; }

  // The move before this point ends with an exact stop.
  void stop_here() {
    if (!result_.program.moves.empty()) result_.program.moves.back().transition = Transition{};
  }

  double scale() const { return inch_ ? kMetresPerInch : kMetresPerMm; }
  std::string unit_name() const { return inch_ ? "in" : "mm"; }

  // One block, in the RS274/NGC order of execution: the words checked, units, feed and tool,
  // M6/spindle/coolant, dwell, plane and the other modal settings, path control, distance
  // modes, motion, and last the stops and the program end.
  void execute(const Block& block) {
    const int line = block.line;
    std::vector<Word> words = block.words;
    const std::string label = take_line_number(words, line);
    const LineWords lw = sort_words(words, line, file_, options_.angles.has_value());

    // units first: every value on the line is read in the units in force after it
    if (const auto units = lw.g_in(GGroup::kUnits)) inch_ = units->first == 200;
    set_feed_and_tool(lw, line);
    before_motion(lw.m_codes, line);

    // users of P and Q, checked once the motion of the line is known
    const auto dwell = lw.g_in(GGroup::kNonModal);
    const auto path_control = lw.g_in(GGroup::kPathControl);
    const bool g64 = path_control && path_control->first == 640;
    const Word* p = lw.get('P');
    const Word* q = lw.get('Q');
    if (q && !g64) fail(line, q->column, q->text, "Q word with no G64 that uses it");
    if (dwell) dwell_here(*dwell->second, p, line);
    set_modes(lw, line);
    if (path_control) set_path_control(g64, dwell ? nullptr : p, q, line);
    if (const auto d = lw.g_in(GGroup::kDistance)) incremental_ = d->first == 910;
    if (const auto d = lw.g_in(GGroup::kArcDistance)) ij_absolute_ = d->first == 901;
    motion(lw, label, line, (dwell ? 1 : 0) + (g64 ? 1 : 0));
    after_motion(lw.m_codes, line);
  }

  // N: the line number, first word only; removed from `words`. The block's label for move
  // names: the N word, else "line <n>".
  std::string take_line_number(std::vector<Word>& words, int line) const {
    std::string label = "line " + std::to_string(line);
    for (std::size_t k = 0; k < words.size(); ++k) {
      if (words[k].letter != 'N') continue;
      if (k != 0) fail(line, words[k].column, words[k].text, "the line number N must be the first word of the line");
      label = words[k].text;
    }
    if (!words.empty() && words.front().letter == 'N') words.erase(words.begin());
    return label;
  }

  // F, S, T, H, D (RS274/NGC order of execution: feed, speed, tool before motion)
  void set_feed_and_tool(const LineWords& lw, int line) {
    if (const Word* f = lw.get('F')) {
      if (!(f->value > 0)) fail(line, f->column, f->text, "the feed rate F must be positive");
      feed_ = f->value * scale() / 60.0;
    }
    for (const char letter : {'S', 'T', 'H', 'D'}) {
      if (const Word* w = lw.get(letter)) result_.ignored.push_back(note_of(*w, line));
    }
  }

  // M6, spindle, coolant (before motion)
  void before_motion(const std::vector<Code>& m_codes, int line) {
    for (const auto& [code, w] : m_codes) {
      if (code == 6) {
        stop_here();
        result_.ignored.push_back(note_of(*w, line) + ": tool change treated as an exact stop");
      } else if (m_group_of(code) == MGroup::kSpindle || m_group_of(code) == MGroup::kCoolant) {
        result_.ignored.push_back(note_of(*w, line));
      }
    }
  }

  // G4 dwell (the word `g4`, its time P): the machine stops here
  void dwell_here(const Word& g4, const Word* p, int line) {
    if (!p) fail(line, g4.column, g4.text, "G4 needs a P word (dwell time in seconds)");
    if (p->value < 0) fail(line, p->column, p->text, "the dwell time P must be >= 0");
    stop_here();
    result_.ignored.push_back(g4.text + " " + p->text + " (line " + std::to_string(line) +
                              "): dwell treated as an exact stop");
  }

  // The plane, and the modal codes that do not change the path (noted): cutter and tool length
  // compensation off, feed mode, one coordinate system
  void set_modes(const LineWords& lw, int line) {
    if (const auto plane = lw.g_in(GGroup::kPlane)) {
      plane_ = plane->first == 170 ? Plane::kXY : plane->first == 180 ? Plane::kXZ : Plane::kYZ;
    }
    for (const GGroup group : {GGroup::kCutterComp, GGroup::kToolLength, GGroup::kFeedMode}) {
      if (const auto g = lw.g_in(group)) result_.ignored.push_back(note_of(*g->second, line));
    }
    if (const auto cs = lw.g_in(GGroup::kCoordSystem)) {
      if (coord_system_ && *coord_system_ != cs->first && !result_.program.moves.empty()) {
        fail(line, cs->second->column, cs->second->text,
             "changing the coordinate system after moves shifts the rest of the path; not supported");
      }
      coord_system_ = cs->first;
      result_.ignored.push_back(note_of(*cs->second, line));
    }
  }

  // path control: G61/G61.1 exact stop, G64 [P tol] [Q]; `p` is the line's P unless a G4 uses it
  void set_path_control(bool g64, const Word* p, const Word* q, int line) {
    if (!g64) {
      transition_ = Transition{};
      return;
    }
    if (p && p->value < 0) fail(line, p->column, p->text, "the G64 tolerance P must be >= 0");
    transition_ = options_.blending;
    if (p && p->value > 0) {
      transition_.method = options_.tolerance_method;
      transition_.parameter = p->value * scale();
    }
    // Q: the naive CAM tolerance, collinear lines within it merged before blending
    if (q) {
      if (!(q->value >= 0)) fail(line, q->column, q->text, "the G64 naive CAM tolerance Q must be >= 0");
      transition_.merge_tolerance = q->value * scale();
    }
  }

  // The motion mode (G0-G3, G80) and the move of the line, if it has one; `p_users` counts the
  // other commands on the line that use its P word (G4, G64).
  void motion(const LineWords& lw, const std::string& label, int line, int p_users) {
    if (const auto motion_word = lw.g_in(GGroup::kMotion)) {
      switch (motion_word->first) {
        case 0: motion_ = Motion::kRapid; break;
        case 10: motion_ = Motion::kLinear; break;
        case 20: motion_ = Motion::kCw; break;
        case 30: motion_ = Motion::kCcw; break;
        default: motion_ = Motion::kNone; break;
      }
    }
    const bool arc_mode = motion_ == Motion::kCw || motion_ == Motion::kCcw;
    const Word* first_axis = lw.first_of("XYZABC");
    const Word* first_arc_word = lw.first_of("IJKR");
    if (first_arc_word && !arc_mode) {
      fail(line, first_arc_word->column, first_arc_word->text,
           std::string(1, first_arc_word->letter) + " word with no G2/G3 that uses it");
    }
    if (first_axis && motion_ == Motion::kNone) {
      fail(line, first_axis->column, first_axis->text, "axis words with no motion mode (G0, G1, G2, G3) in force");
    }
    const bool arc_here = arc_mode && (first_axis || first_arc_word);
    // P has exactly one user on the line
    const Word* p = lw.get('P');
    if (p) {
      const int users = p_users + (arc_here ? 1 : 0);
      if (users == 0) fail(line, p->column, p->text, "P word with no G4, G64 or G2/G3 that uses it");
      if (users > 1) fail(line, p->column, p->text, "P word used by two commands on one line (G4, G64, G2/G3)");
    }
    if (!first_axis && !arc_here) return;
    const auto motion_word = lw.g_in(GGroup::kMotion);
    const Word* at = motion_word ? motion_word->second : (first_axis ? first_axis : first_arc_word);
    const SourceRef where{file_, line, at->column};
    const std::string code = motion_ == Motion::kRapid ? "G0" : motion_ == Motion::kLinear ? "G1"
                             : motion_ == Motion::kCw  ? "G2" : "G3";
    const std::string name = label + " " + code;
    const Vec3 target = target_of(lw);
    line_orientation_ = angles_ ? angles_->apply(lw, incremental_, line, file_) : std::nullopt;
    if (arc_mode) {
      arc_move(target, lw, p, where, name, line);
    } else {
      line_move(target, where, name);
    }
  }

  // stops and program end (after motion)
  void after_motion(const std::vector<Code>& m_codes, int line) {
    for (const auto& [code, w] : m_codes) {
      if (code == 0 || code == 1) {
        stop_here();
        result_.ignored.push_back(note_of(*w, line) + ": program pause treated as an exact stop");
      } else if (code == 2 || code == 30) {
        ended_ = true;
        end_word_ = w->text;
      }
    }
  }

  // The end point of a motion (m): absent axes keep their value; G91 adds to the current point.
  Vec3 target_of(const LineWords& lw) const {
    Vec3 target = pos_;
    const std::array<char, 3> letters = {'X', 'Y', 'Z'};
    for (int axis = 0; axis < 3; ++axis) {
      if (const Word* w = lw.get(letters[static_cast<std::size_t>(axis)])) {
        const double value = w->value * scale();
        target[axis] = incremental_ ? pos_[axis] + value : value;
      }
    }
    return target;
  }

  Move make_move(Primitive geometry, const SourceRef& where, const std::string& name, bool rapid) const {
    Move move;
    move.geometry = std::move(geometry);
    move.limits = options_.limits;
    move.limits.velocity = rapid ? (options_.rapid_velocity > 0 ? options_.rapid_velocity : options_.limits.velocity) : feed_;
    move.buffer = options_.buffer;
    move.transition = transition_;
    move.where = where;
    move.name = name;
    move.orientation = line_orientation_;
    return move;
  }

  // Appends a move, or drops it when it is shorter than kZeroLengthMove. The interpreter's
  // position always becomes the programmed end; the path continues from the last kept move.
  void add_move(Move move, const Vec3& target) {
    pos_ = target;
    const double len = length(move.geometry);
    if (!(len > kZeroLengthMove)) {
      // the orientation follows the path, so a rotation without a move cannot be kept
      if (move.orientation && rotation_angle(path_orientation_, *move.orientation) > kSameOrientation) {
        fail(move.where.line, move.where.column, move.name.substr(move.name.rfind(' ') + 1),
             "the tool angles turn the tool by " + format_value(rotation_angle(path_orientation_, *move.orientation) / kDeg, 6) +
                 " degrees on a zero-length move; the orientation is interpolated along the path, so the tool cannot turn in place");
      }
      result_.ignored.push_back(move.name + ": zero-length move dropped");
      return;
    }
    if (result_.program.moves.size() == kMaxMoves) {
      fail(move.where.line, move.where.column, move.name.substr(move.name.rfind(' ') + 1),
           "more than " + std::to_string(kMaxMoves) + " moves (the limit of one program)");
    }
    // a line ends exactly at its programmed end (point(line, length) rounds, and an arc after it
    // would rise by 1e-19 m out of its plane); an arc where it computes its end
    const Line* line = std::get_if<Line>(&move.geometry);
    path_end_ = line ? line->p1 : point(move.geometry, len);
    if (move.orientation) path_orientation_ = *move.orientation;
    result_.program.moves.push_back(std::move(move));
  }

  void line_move(const Vec3& target, const SourceRef& where, const std::string& name) {
    add_move(make_move(Line{path_end_, target}, where, name, motion_ == Motion::kRapid), target);
  }

  void arc_move(const Vec3& target, const LineWords& lw, const Word* p, const SourceRef& where, const std::string& name, int line) {
    const PlaneAxes ax = axes_of(plane_);
    const bool ccw = motion_ == Motion::kCcw;
    const double sign = ccw ? 1.0 : -1.0;
    const auto in_plane = [&](const Vec3& v) { return Vec2(v.dot(ax.a1), v.dot(ax.a2)); };
    const auto rot90 = [](const Vec2& v) { return Vec2(-v.y(), v.x()); };  // +90 degrees about n
    const double tol_abs = (inch_ ? kCentreArcRadiusTolInch : kCentreArcRadiusTolMm) * scale();
    const double tol_radius = (inch_ ? kRadiusTolInch : kRadiusTolMm) * scale();

    // turns: P (integer >= 1), one by default
    int turns = 1;
    if (p) {
      if (std::round(p->value) != p->value || p->value < 1 || p->value > kMaxArcTurns) {
        fail(line, p->column, p->text,
             "the number of turns P of G2/G3 must be an integer from 1 to " + std::to_string(kMaxArcTurns) +
                 " (the limit bounds the work per arc), got " + format_value(p->value, 10));
      }
      turns = static_cast<int>(p->value);
    }

    const Word* r_word = lw.get('R');
    const Word* off_normal = lw.get(ax.off_normal);
    if (off_normal) {
      fail(line, off_normal->column, off_normal->text,
           std::string(1, ax.off_normal) + " is not a centre offset in plane " + ax.name + "; use " + ax.off1 + "/" + ax.off2);
    }
    const Word* o1 = lw.get(ax.off1);
    const Word* o2 = lw.get(ax.off2);
    if (r_word && (o1 || o2)) {
      const Word* w = o1 ? o1 : o2;
      fail(line, w->column, w->text, "an arc takes either R or centre offsets, not both");
    }
    if (!r_word && !o1 && !o2) {
      fail(line, where.column, name.substr(name.rfind(' ') + 1),
           std::string("arc needs a radius R or centre offsets ") + ax.off1 + "/" + ax.off2 + " in plane " + ax.name);
    }

    const Vec3 start = path_end_;
    const Vec2 s2 = in_plane(start);
    const Vec2 e2 = in_plane(target);
    const double chord = (e2 - s2).norm();
    const bool full_circle = chord <= kSamePoint;
    const std::string units = unit_name();
    const auto in_units = [&](double metres) { return format_value(metres / scale(), 10) + " " + units; };

    Vec2 c2;
    if (r_word) {
      // R format (LinuxCNC arc_data_r): centre on the chord's bisector, on the right of the
      // chord for G2 with R > 0 (arc <= 180 degrees), on the left for G3; R < 0 swaps sides
      if (full_circle) {
        fail(line, r_word->column, r_word->text, "an R-format arc cannot be a full circle (end point = start); use I/J/K");
      }
      const double radius = std::abs(r_word->value) * scale();
      const double half = 0.5 * chord;
      if (half - radius > tol_radius) {
        fail(line, r_word->column, r_word->text,
             "radius too small to reach the end point (|R| = " + in_units(radius) + ", half the chord = " + in_units(half) + ")");
      }
      const double offset = std::sqrt(std::max(0.0, radius * radius - half * half));
      const Vec2 d = (e2 - s2) / chord;
      const bool right = (!ccw) == (r_word->value > 0);
      c2 = 0.5 * (s2 + e2) + (right ? -offset : offset) * rot90(d);
    } else {
      // centre format: offsets from the start (G91.1) or absolute (G90.1, both required)
      if (ij_absolute_ && !(o1 && o2)) {
        const Word* w = o1 ? o1 : o2;
        fail(line, w->column, w->text,
             std::string("with absolute arc centres (G90.1) both ") + ax.off1 + " and " + ax.off2 + " are required in plane " + ax.name);
      }
      const double i1 = o1 ? o1->value * scale() : 0.0;
      const double i2 = o2 ? o2->value * scale() : 0.0;
      c2 = ij_absolute_ ? Vec2(i1, i2) : in_plane(pos_) + Vec2(i1, i2);
      double r1 = (s2 - c2).norm();
      double r2 = full_circle ? r1 : (e2 - c2).norm();
      const std::string word = name.substr(name.rfind(' ') + 1);
      if (r1 < tol_radius || r2 < tol_radius) {
        fail(line, where.column, word, "zero-radius arc (r1 = " + in_units(r1) + ", r2 = " + in_units(r2) + ")");
      }
      // LinuxCNC arc_data_ijk: error beyond the absolute OR the relative tolerance
      const double abs_err = std::abs(r1 - r2);
      const double rel_err = abs_err / std::max(r1, r2);
      if (abs_err > tol_abs || rel_err > kSpiralRelativeTol) {
        fail(line, where.column, word,
             "radius to end of arc differs from radius to start: r1 = " + in_units(r1) + ", r2 = " + in_units(r2) +
                 " (difference " + in_units(abs_err) + ", " + format_value(100 * rel_err, 10) + "%; allowed " +
                 in_units(tol_abs) + " and 0.1%)");
      }
      if (!full_circle && abs_err > 0) {
        c2 = corrected_centre(s2, e2, c2, r1, r2, sign, turns, tol_abs, where, word, units);
        if (abs_err > kNoteworthyRadiusError) {
          result_.ignored.push_back(name + ": end point " + in_units(abs_err) +
                                    " off the circle; centre moved onto the bisector of start and end");
        }
      }
    }

    // the arc about the plane's normal (clockwise for G2), helical when the normal axis moves;
    // the centre already satisfies the radius rule, so only rounding is left to absorb
    const Vec3 centre = c2.x() * ax.a1 + c2.y() * ax.a2 + start.dot(ax.n) * ax.n;
    // a rise below kSamePoint is rounding (G91 sums, a units change), not a helix: the arc ends
    // in its start's plane, so the corners it makes stay planar
    const double rise = (target - start).dot(ax.n);
    // (n is a coordinate axis, so the end's normal coordinate becomes the start's exactly)
    const Vec3 end = std::abs(rise) <= kSamePoint ? Vec3(target - target.dot(ax.n) * ax.n + start.dot(ax.n) * ax.n) : target;
    const ArcBuild built = arc_from_center(start, end, centre, ax.a1.cross(ax.a2), sign > 0, turns - 1, tol_abs);
    if (!built.outcome.ok()) fail(line, where.column, name, built.outcome.message);
    const Arc& arc = built.arc;
    add_move(make_move(arc, where, name, false), target);
  }

  // Inside LinuxCNC's tolerance the end radius r2 differs from the start radius r1 and LinuxCNC
  // cuts a spiral. A circle keeps both end points if its centre is on their bisector: take the
  // point of the bisector nearest the programmed centre, and check that the circle stays within
  // tol_abs of the spiral (compared at equal fractions of the sweep, an upper bound on the
  // distance between the curves). Beyond that (nearly full circles) fail rather than cut a
  // different path.
  Vec2 corrected_centre(const Vec2& s2, const Vec2& e2, const Vec2& c2, double r1, double r2, double sign, int turns,
                        double tol_abs, const SourceRef& where, const std::string& word, const std::string& units) const {
    const auto rot90 = [](const Vec2& v) { return Vec2(-v.y(), v.x()); };
    const auto sweep_of = [&](const Vec2& centre) {
      const Vec2 u = (s2 - centre).normalized();
      const Vec2 v = sign * rot90(u);
      const Vec2 rel = e2 - centre;
      double a = std::atan2(rel.dot(v), rel.dot(u));
      if (a <= 0) a += kTwoPi;
      return a + kTwoPi * (turns - 1);
    };
    const Vec2 mid = 0.5 * (s2 + e2);
    const Vec2 d = (e2 - s2).normalized();
    const Vec2 c_new = c2 - (c2 - mid).dot(d) * d;
    const double r_new = (s2 - c_new).norm();

    const double sweep_old = sweep_of(c2);
    const double sweep_new = sweep_of(c_new);
    const Vec2 u_old = (s2 - c2) / r1;
    const Vec2 v_old = sign * rot90(u_old);
    const Vec2 u_new = (s2 - c_new) / r_new;
    const Vec2 v_new = sign * rot90(u_new);
    double deviation = 0;
    const int samples = kSpiralSamples * turns;
    for (int k = 0; k <= samples; ++k) {
      const double t = static_cast<double>(k) / samples;
      const double a_old = t * sweep_old;
      const double a_new = t * sweep_new;
      const Vec2 spiral = c2 + (r1 + (r2 - r1) * t) * (std::cos(a_old) * u_old + std::sin(a_old) * v_old);
      const Vec2 circle = c_new + r_new * (std::cos(a_new) * u_new + std::sin(a_new) * v_new);
      deviation = std::max(deviation, (spiral - circle).norm());
    }
    if (!(deviation <= tol_abs)) {
      const double s = inch_ ? kMetresPerInch : kMetresPerMm;
      fail(where.line, where.column, word,
           "the end point is within LinuxCNC's radius tolerance (r1 = " + format_value(r1 / s, 10) + " " + units +
               ", r2 = " + format_value(r2 / s, 10) + " " + units +
               "), but no circle through both end points stays within " + format_value(tol_abs / s, 10) + " " + units +
               " of the spiral LinuxCNC would cut (it departs by " + format_value(deviation / s, 10) + " " + units +
               "); correct the end point or the centre");
    }
    return c_new;
  }

  std::string_view text_;
  const std::string& file_;
  const GcodeOptions& options_;
  GcodeResult result_;

  Vec3 pos_;       // m: the interpreter's current point (the programmed end of the last motion)
  Vec3 path_end_;  // m: where the last kept move ends (differs from pos_ only after a dropped move)
  double feed_ = 0;  // m/s
  Transition transition_;
  Plane plane_ = Plane::kXY;
  Motion motion_ = Motion::kNone;  // LinuxCNC starts in G80
  bool inch_ = false;
  bool incremental_ = false;
  bool ij_absolute_ = false;
  std::optional<int> coord_system_;
  // tool angles (options_.angles, else none): their modal state; the target of this line's
  // move; the orientation where the last kept move ends (program frame)
  std::optional<ToolAngles> angles_;
  std::optional<Quat> line_orientation_;
  Quat path_orientation_ = Quat::Identity();
  bool opened_ = false;
  bool seen_code_ = false;
  bool ended_ = false;
  std::string end_word_;
};

}  // namespace

GcodeResult parse_gcode(std::string_view text, const std::string& file_name, const GcodeOptions& options) {
  return Reader(text, file_name, options).run();
}

}  // namespace blendbench
