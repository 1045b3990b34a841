// The G-code reader (gcode.hpp): an interpreter of RS274/NGC blocks that keeps LinuxCNC's
// modal state, parameters, offsets and O-word control flow, and turns motion words into moves.
// gcode_flow.cpp finds the O-word structure before the run, the lexer (gcode_lexer.cpp) splits a
// line into words and evaluates their values, gcode_words.cpp checks them against the RS274/NGC
// tables; this file executes them.

#include "blendbench/io/gcode.hpp"

#include "blendbench/geometry/arc_construction.hpp"
#include "blendbench/core/format.hpp"
#include "blendbench/core/units.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <numbers>
#include <optional>
#include <unordered_set>
#include <utility>

#include "gcode_angles.hpp"
#include "gcode_flow.hpp"
#include "gcode_lexer.hpp"
#include "gcode_params.hpp"
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


// Where the reader is in the text: the start of the next line to read, its number, and the
// first O-word line at or after it (an index into Flow::lines).
struct Pc {
  std::size_t offset = 0;
  int line = 1;
  std::size_t next_o = 0;
};

// LinuxCNC's numbered parameters for offsets, tool and position (its G-code manual,
// "Parameters"): G28 and G30 positions, G92 offsets, the coordinate system in use and the nine
// systems' offsets (20 apart, rotation at +9), the tool, the current position.
constexpr int kParamG28 = 5161;
constexpr int kParamG30 = 5181;
constexpr int kParamG92On = 5210;
constexpr int kParamG92 = 5211;
constexpr int kParamCoordSystem = 5220;
constexpr int kParamCoordBase = 5201;  // system p (1..9): X at kParamCoordBase + 20 p
constexpr int kParamRotation = 9;       // offset of R from X
constexpr int kParamTool = 5400;
constexpr int kParamToolOffset = 5401;
constexpr int kParamPosition = 5420;

class Reader final : private SystemParams {
 public:
  Reader(std::string_view text, const std::string& file, const GcodeOptions& options)
      : text_(text), file_(file), options_(options), params_(*this) {
    pos_ = options.start;
    path_orientation_ = options.start_orientation.normalized();
    if (options.angles) angles_.emplace(*options.angles);
    path_end_ = options.start;
    feed_ = options.limits.velocity;
    transition_ = options.blending;
    tool_table_ = options.tool_offsets;
  }

  GcodeResult run() {
    check_options();
    result_.start = options_.start;
    // a UTF-8 byte order mark (editors on Windows) is not part of the program
    if (text_.substr(0, 3) == "\xEF\xBB\xBF") text_.remove_prefix(3);
    flow_ = build_flow(text_, file_);
    // line by line, never all lines at once (a file of empty lines would cost 16 bytes a byte);
    // O-words jump to the lines the flow names
    Pc pc;
    while (pc.offset <= text_.size()) {
      const std::size_t end = std::min(text_.find('\n', pc.offset), text_.size());
      const std::string_view line = text_.substr(pc.offset, end - pc.offset);
      const int number = pc.line;
      Pc next{end + 1, pc.line + 1, pc.next_o};
      const bool o_line = pc.next_o < flow_.lines.size() && flow_.lines[pc.next_o].line == number;
      if (o_line) ++next.next_o;
      const std::string_view stripped = strip_blanks(line);
      if (!stripped.empty()) count_line(number, stripped);
      try {
        if (o_line) {
          pc = control(pc.next_o, next);
          continue;
        }
        pc = next;
        if (!read_line(line, stripped, number, next.offset)) break;
      } catch (const InputError& e) {
        if (calls_.empty()) throw;
        throw InputError(e.file(), e.line(), e.column(), e.field(), e.detail() + call_context());
      }
    }
    if (result_.program.moves.empty()) {
      throw InputError(file_, 0, 0, "", "the G-code program has no moves");
    }
    return std::move(result_);
  }

 private:
  // A subroutine call in progress: its `sub` line, where to go on return, the line of the call.
  struct Call {
    int sub = 0;
    Pc ret;
    int line = 0;
  };
  // A repeat loop in progress: its `repeat` line, the passes left, the call depth it runs in.
  struct Repeat {
    int oline = 0;
    double remaining = 0;
    std::size_t depth = 0;
  };

  // Counts a line against the budget of executed lines, and marks lines run a second time (by
  // a loop or a second call), whose notes are not repeated.
  void count_line(int number, std::string_view stripped) {
    if (++executed_ > options_.max_lines) {
      fail(number, 1, std::string(stripped.substr(0, std::min<std::size_t>(stripped.size(), 20))),
           "more than " + std::to_string(options_.max_lines) +
               " lines executed (the limit of one program: a loop that never ends?)");
    }
    repeated_line_ = !flow_.lines.empty() && !seen_lines_.insert(number).second;
  }

  // " (in o<name>, called from line N ...)" for an error inside a subroutine.
  std::string call_context() const {
    std::string out;
    for (auto it = calls_.rbegin(); it != calls_.rend(); ++it) {
      out += out.empty() ? " (in " : ", ";
      out += flow_.lines[static_cast<std::size_t>(it->sub)].head.name() + " called from line " + std::to_string(it->line);
    }
    return out + ")";
  }

  // One line that is not an O-word; false when the program ends here.
  bool read_line(std::string_view line, std::string_view stripped, int number, std::size_t next) {
    // tape markers: '%' alone on a line opens the program (first) or ends it
    if (stripped == "%") {
      if (!opened_ && !seen_code_) {
        opened_ = true;
        return true;
      }
      note_rest(next, number, "the closing % (line " + std::to_string(number) + ")");
      return false;
    }
    if (!stripped.empty() && stripped.front() == '/') {
      note("line " + std::to_string(number) + ": block delete '/', line skipped");
      seen_code_ = true;
      return true;
    }
    const CompactLine compact = compact_line(line, number, file_);
    if (compact.text.empty()) return true;
    seen_code_ = true;
    Block block = lex_block(compact, number, file_, params_);
    if (block.unicode_minus) note("line " + std::to_string(number) + ": Unicode minus sign (U+2212) read as '-'");
    assign(block);
    if (block.words.empty()) return true;
    execute(block);
    if (ended_) {
      if (calls_.empty()) note_rest(next, number, end_word_ + " (line " + std::to_string(number) + ")");
      return false;
    }
    return true;
  }

  // The parameter assignments of a line, after all its values were read (RS274/NGC).
  void assign(const Block& block) {
    for (const Assignment& a : block.assignments) {
      if (a.number == 0) {
        if (!params_.set_named(a.name, a.value)) fail(block.line, a.column, a.text, "#<" + a.name + "> is predefined and read-only");
        continue;
      }
      const bool read_only = a.number == kParamG92On || a.number == kParamCoordSystem ||
                             (a.number >= kParamTool && a.number <= kParamTool + 9) ||
                             (a.number >= kParamPosition && a.number <= kParamPosition + 8);
      if (read_only) fail(block.line, a.column, a.text, a.text + " is set by the interpreter and read-only here");
      params_.set(a.number, a.value);
    }
  }

  // Jump targets: the line after O-word line k, and O-word line k itself.
  Pc after(int k) const {
    const OLine& o = flow_.lines[static_cast<std::size_t>(k)];
    return {o.next, o.line + 1, static_cast<std::size_t>(k) + 1};
  }
  Pc at(int k) const {
    const OLine& o = flow_.lines[static_cast<std::size_t>(k)];
    return {o.offset, o.line, static_cast<std::size_t>(k)};
  }

  // The bracketed values of O-word line k (its condition, count, arguments or return value).
  std::vector<double> values_of(int k, std::size_t min_count, std::size_t max_count) const {
    const OLine& o = flow_.lines[static_cast<std::size_t>(k)];
    const std::size_t end = std::min(text_.find('\n', o.offset), text_.size());
    const CompactLine compact = compact_line(text_.substr(o.offset, end - o.offset), o.line, file_);
    return oword_values(compact, o.head, o.line, file_, params_, min_count, max_count);
  }
  bool condition(int k) const { return values_of(k, 1, 1).front() != 0; }

  // Executes O-word line k; `next` is the line after it. Returns where to go on.
  Pc control(std::size_t index, const Pc& next) {
    const int k = static_cast<int>(index);
    const OLine& o = flow_.lines[index];
    seen_code_ = true;
    switch (o.kind) {
      case OKind::kSub:
        // a definition met in the flow is skipped; it runs when called
        (void)values_of(k, 0, 0);
        return after(o.match);
      case OKind::kCall: return call(k, next);
      case OKind::kEndsub: case OKind::kReturn: {
        const std::vector<double> value = values_of(k, 0, 1);
        value_ = value.empty() ? 0.0 : value.front();
        value_returned_ = value.empty() ? 0.0 : 1.0;
        return end_call(o);
      }
      case OKind::kDo: (void)values_of(k, 0, 0); return next;
      case OKind::kWhile:
        if (o.closes_do) return condition(k) ? after(o.match) : next;
        return condition(k) ? next : after(o.match);
      case OKind::kEndwhile: (void)values_of(k, 0, 0); return at(o.match);
      case OKind::kIf: return condition(k) ? next : branch(o.next_branch);
      case OKind::kElseif: case OKind::kElse: return after(o.match);  // the branch before was taken
      case OKind::kEndif: (void)values_of(k, 0, 0); return next;
      case OKind::kRepeat: {
        const double count = std::floor(values_of(k, 1, 1).front());
        if (!(count >= 1)) return after(o.match);
        repeats_.push_back({k, count, calls_.size()});
        return next;
      }
      case OKind::kEndrepeat:
        (void)values_of(k, 0, 0);
        if (!repeats_.empty() && repeats_.back().oline == o.match && --repeats_.back().remaining >= 1) return after(o.match);
        if (!repeats_.empty() && repeats_.back().oline == o.match) repeats_.pop_back();
        return next;
      case OKind::kBreak: case OKind::kContinue: {
        (void)values_of(k, 0, 0);
        const OLine& loop = flow_.lines[static_cast<std::size_t>(o.match)];
        // repeats inside the loop are left; the loop's own only on break
        const int last = loop.match;
        while (!repeats_.empty() && repeats_.back().depth == calls_.size() && repeats_.back().oline > o.match &&
               repeats_.back().oline < last) {
          repeats_.pop_back();
        }
        if (o.kind == OKind::kBreak) {
          if (loop.kind == OKind::kRepeat && !repeats_.empty() && repeats_.back().oline == o.match) repeats_.pop_back();
          return after(last);
        }
        // continue: a while loop tests again, a do loop at its closing while, a repeat at its end
        return loop.kind == OKind::kWhile ? at(o.match) : at(last);
      }
    }
    return next;
  }

  // The first branch of an if chain, from O-word line b on, whose condition holds.
  Pc branch(int b) {
    while (true) {
      const OLine& o = flow_.lines[static_cast<std::size_t>(b)];
      if (o.kind == OKind::kEndif) return after(b);
      if (o.kind == OKind::kElse) return after(b);
      count_line(o.line, "elseif");
      if (condition(b)) return after(b);
      b = o.next_branch;
    }
  }

  Pc call(int k, const Pc& next) {
    const OLine& o = flow_.lines[static_cast<std::size_t>(k)];
    const auto it = flow_.subs.find(o.head.label);
    if (it == flow_.subs.end()) {
      fail(o.line, o.head.column, o.head.name(),
           o.head.name() + " is not defined in this file (subroutines in separate files are not supported)");
    }
    if (calls_.size() >= kMaxCallDepth) {
      fail(o.line, o.head.column, o.head.name(),
           "subroutine calls nested deeper than " + std::to_string(kMaxCallDepth) + " (recursion that never ends?)");
    }
    const std::vector<double> args = values_of(k, 0, kCallArguments);
    calls_.push_back({it->second, next, o.line});
    params_.push_call(args);
    return after(it->second);
  }

  Pc end_call(const OLine& o) {
    if (calls_.empty()) fail(o.line, o.head.column, o.head.name(), o.head.keyword + " outside a subroutine call");
    while (!repeats_.empty() && repeats_.back().depth == calls_.size()) repeats_.pop_back();
    const Pc ret = calls_.back().ret;
    calls_.pop_back();
    params_.pop_call();
    return ret;
  }

  // A note in GcodeResult::ignored, once per line of the program (not again when a loop or a
  // second call runs the line again).
  void note(std::string text) {
    if (!repeated_line_) result_.ignored.push_back(std::move(text));
  }

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

  // One block, in the RS274/NGC order of execution (LinuxCNC's G-code manual, "Order of
  // Execution"): the words checked, units, feed and tool, M6/spindle/coolant, dwell, plane,
  // tool length offset, coordinate system, path control, distance modes, G10/G28/G30/G52/G92,
  // motion, and last the stops and the program end.
  void execute(const Block& block) {
    const int line = block.line;
    std::vector<Word> words = block.words;
    const std::string label = take_line_number(words, line);
    const LineWords lw = sort_words(words, line, file_, options_.angles.has_value());

    // units first: every value on the line is read in the units in force after it
    if (const auto units = lw.g_in(GGroup::kUnits)) inch_ = units->first == 200;
    set_feed_and_tool(lw, line);
    before_motion(lw.m_codes, line);

    // users of P, Q, L, H, checked once the commands of the line are known
    const auto non_modal = lw.g_in(GGroup::kNonModal);
    const int nm = non_modal ? non_modal->first : -1;
    const bool dwell = nm == 40;
    const auto path_control = lw.g_in(GGroup::kPathControl);
    const bool g64 = path_control && path_control->first == 640;
    const Word* p = lw.get('P');
    const Word* q = lw.get('Q');
    if (q && !g64) fail(line, q->column, q->text, "Q word with no G64 that uses it");
    if (const Word* l = lw.get('L'); l && nm != 100) fail(line, l->column, l->text, "L word with no G10 that uses it");
    if (dwell) dwell_here(*non_modal->second, p, line);
    set_modes(lw, line);
    const bool tool_axes = tool_length(lw, line);
    set_coordinate_system(lw, line);
    if (path_control) set_path_control(g64, (dwell || nm == 100) ? nullptr : p, q, line);
    if (const auto d = lw.g_in(GGroup::kDistance)) incremental_ = d->first == 910;
    if (const auto d = lw.g_in(GGroup::kArcDistance)) ij_absolute_ = d->first == 901;
    const bool offset_axes = non_modal && offsets_and_stored(lw, *non_modal->second, nm, label, line);
    const bool axes_taken = tool_axes || offset_axes;
    if (const auto m = lw.g_in(GGroup::kMotion); axes_taken && m && m->first != 800 && lw.first_of("XYZABC")) {
      fail(line, m->second->column, m->second->text,
           "the axis words of this line belong to " + (offset_axes ? non_modal->second->text : lw.g_in(GGroup::kToolLength)->second->text) +
               "; a motion cannot use them too");
    }
    motion(lw, label, line, (dwell ? 1 : 0) + (g64 ? 1 : 0) + (nm == 100 ? 1 : 0), axes_taken, nm);
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

  // F, S, T, H, D (RS274/NGC order of execution: feed, speed, tool before motion); T selects
  // the tool that M6 loads, H is read by G43 (noted when nothing uses it)
  void set_feed_and_tool(const LineWords& lw, int line) {
    if (const Word* f = lw.get('F')) {
      if (!(f->value > 0)) fail(line, f->column, f->text, "the feed rate F must be positive");
      feed_ = f->value * scale() / 60.0;
      if (result_.first_feed_where.line == 0) {
        result_.first_feed_where = {file_, line, f->column};
        result_.first_feed = feed_;
      }
    }
    if (const Word* t = lw.get('T')) tool_selected_ = integer_of(*t, line, "the tool number T");
    const auto tl = lw.g_in(GGroup::kToolLength);
    const bool h_used = tl && (tl->first == 430 || tl->first == 432);
    for (const char letter : {'S', 'T', 'H', 'D'}) {
      if (letter == 'H' && h_used) continue;
      if (const Word* w = lw.get(letter)) note(note_of(*w, line));
    }
  }

  // A word whose value must be an integer >= 0 (a tool, a coordinate system, an L).
  int integer_of(const Word& w, int line, const std::string& what) const {
    const double rounded = std::round(w.value);
    if (std::abs(w.value - rounded) > 1e-9 || rounded < 0 || rounded > 1e6) {
      fail(line, w.column, w.text, what + " must be a whole number >= 0, got " + format_value(w.value, 10));
    }
    return static_cast<int>(rounded);
  }

  // M6, spindle, coolant (before motion)
  void before_motion(const std::vector<Code>& m_codes, int line) {
    for (const auto& [code, w] : m_codes) {
      if (code == 6) {
        stop_here();
        tool_ = tool_selected_;
        note(note_of(*w, line) + ": tool change treated as an exact stop");
      } else if (m_group_of(code) == MGroup::kSpindle || m_group_of(code) == MGroup::kCoolant) {
        note(note_of(*w, line));
      }
    }
  }

  // G4 dwell (the word `g4`, its time P): the machine stops here
  void dwell_here(const Word& g4, const Word* p, int line) {
    if (!p) fail(line, g4.column, g4.text, "G4 needs a P word (dwell time in seconds)");
    if (p->value < 0) fail(line, p->column, p->text, "the dwell time P must be >= 0");
    stop_here();
    note(g4.text + " " + p->text + " (line " + std::to_string(line) + "): dwell treated as an exact stop");
  }

  // The plane, and the modal codes that do not change the path (noted): cutter compensation
  // off, feed mode
  void set_modes(const LineWords& lw, int line) {
    if (const auto plane = lw.g_in(GGroup::kPlane)) {
      plane_ = plane->first == 170 ? Plane::kXY : plane->first == 180 ? Plane::kXZ : Plane::kYZ;
    }
    for (const GGroup group : {GGroup::kCutterComp, GGroup::kFeedMode}) {
      if (const auto g = lw.g_in(group)) note(note_of(*g->second, line));
    }
  }

  // The tool length offset of tool h: the tool table's entry (GcodeOptions::tool_offsets, or
  // G10 L1), zero for tool 0 and, noted, for a tool not in the table.
  Vec3 tool_entry(int h, const Word& at, int line) {
    if (h == 0) return Vec3::Zero();
    const auto it = tool_table_.find(h);
    if (it != tool_table_.end()) return it->second;
    note(note_of(at, line) + ": tool " + std::to_string(h) +
         " has no entry in the tool table (none is given; G10 L1 sets one), so its length offset is zero");
    return Vec3::Zero();
  }

  // G43 [H], G43.1 axes, G43.2 [H] [axes], G49: the tool length offset, which moves every
  // programmed point by the offset (LinuxCNC). Returns true when the line's axis words are the
  // offset's (G43.1, G43.2).
  bool tool_length(const LineWords& lw, int line) {
    const auto g = lw.g_in(GGroup::kToolLength);
    if (!g) return false;
    const Word& w = *g->second;
    const Word* h = lw.get('H');
    const int tool = h ? integer_of(*h, line, "the tool number H") : tool_;
    switch (g->first) {
      case 430:
        tool_offset_ = tool_entry(tool, h ? *h : w, line);
        return false;
      case 431: case 432: {
        Vec3 offset = g->first == 432 ? Vec3(tool_offset_ + (h ? tool_entry(tool, *h, line) : Vec3::Zero())) : Vec3::Zero();
        const bool axes = axis_values(lw, line, w, [&](int a, double v) { offset[a] += v; });
        if (g->first == 431 && !axes) fail(line, w.column, w.text, "G43.1 needs the offset as axis words (e.g. G43.1 Z10)");
        tool_offset_ = offset;
        return axes;
      }
      default:
        tool_offset_ = Vec3::Zero();
        return false;
    }
  }

  // Calls `take(axis, metres)` for each of the line's X, Y, Z words; A, B, C are refused for
  // the command `cmd`, whose axis words they would be. True if there was any.
  template <class Take>
  bool axis_values(const LineWords& lw, int line, const Word& cmd, Take take) const {
    if (const Word* abc = lw.first_of("ABC")) {
      fail(line, abc->column, abc->text, "offsets of the tool angles A, B, C (" + cmd.text + ") are not supported");
    }
    bool any = false;
    for (int a = 0; a < 3; ++a) {
      if (const Word* v = lw.get(static_cast<char>('X' + a))) {
        take(a, v->value * scale());
        any = true;
      }
    }
    return any;
  }

  // G54-G59.3: the coordinate system whose offsets apply from here on (LinuxCNC's offsets live
  // in the machine's parameter file; here they are zero until the program sets them).
  void set_coordinate_system(const LineWords& lw, int line) {
    const auto cs = lw.g_in(GGroup::kCoordSystem);
    if (!cs) return;
    static constexpr std::array<int, 9> kCodes = {540, 550, 560, 570, 580, 590, 591, 592, 593};
    cs_ = static_cast<int>(std::find(kCodes.begin(), kCodes.end(), cs->first) - kCodes.begin()) + 1;
    if (!cs_set_[static_cast<std::size_t>(cs_ - 1)]) {
      note(note_of(*cs->second, line) + ": its offsets are zero (none set by the program with G10 or parameters)");
    }
  }

  // G10 L1/L2/L20, G28/G30 (and .1), G52, G92/G92.1/G92.2/G92.3. Returns true when the line's
  // axis words were theirs.
  bool offsets_and_stored(const LineWords& lw, const Word& g, int nm, const std::string& label, int line) {
    switch (nm) {
      case 100: set_g10(lw, g, line); return true;
      case 280: case 300: {
        // G28/G30: through the point of the axis words (if any), then to the stored position
        // (LinuxCNC: of those axes only, or of all axes without axis words)
        const std::size_t k = nm == 280 ? 0 : 1;
        const Word* first = lw.first_of("XYZ");
        (void)axis_values(lw, line, g, [](int, double) {});
        const SourceRef where{file_, line, g.column};
        const std::string name = label + " " + g.text;
        if (first) line_move(target_of(lw, false), where, name, true);
        Vec3 stored = pos_;
        for (int a = 0; a < 3; ++a) {
          if (!first || lw.get(static_cast<char>('X' + a))) stored[a] = stored_[k][a];
        }
        line_move(stored, where, name, true);
        return true;
      }
      case 281: case 301: stored_[nm == 281 ? 0 : 1] = pos_; return false;
      case 920: {
        // the current point gets the given coordinates: the offset takes up the difference
        Vec3 prog = to_program(pos_);
        if (!axis_values(lw, line, g, [&](int a, double v) { prog[a] = v; })) {
          fail(line, g.column, g.text, "G92 needs at least one axis word (the coordinates the current point gets)");
        }
        g92_ = pos_ - cs_offset_[cs_index()] - tool_offset_ - rotation_of(cs_) * prog;
        g92_saved_ = g92_;
        g92_on_ = true;
        return true;
      }
      case 520:
        // G52: the local offset itself, sharing G92's (LinuxCNC)
        if (!axis_values(lw, line, g, [&](int a, double v) { g92_[a] = v; })) {
          fail(line, g.column, g.text, "G52 needs at least one axis word (the offset)");
        }
        g92_saved_ = g92_;
        g92_on_ = true;
        return true;
      case 921: g92_ = g92_saved_ = Vec3::Zero(); g92_on_ = false; return false;
      case 922: g92_ = Vec3::Zero(); g92_on_ = false; return false;
      case 923: g92_ = g92_saved_; g92_on_ = true; return false;
      default: return false;
    }
  }

  // G10 L1 (tool table), L2 (a coordinate system's offsets), L20 (offsets that give the current
  // point the given coordinates); P names the tool or the system (0 = the current one), R the
  // rotation about Z in degrees (L2, L20). G91 does not apply (LinuxCNC: G10 L2 values are
  // absolute).
  void set_g10(const LineWords& lw, const Word& g, int line) {
    const Word* l = lw.get('L');
    const Word* p = lw.get('P');
    if (!l) fail(line, g.column, g.text, "G10 needs an L word (L1 tool table, L2 or L20 coordinate system offsets)");
    if (!p) fail(line, g.column, g.text, "G10 needs a P word (the coordinate system 0-9 or the tool number)");
    const int lv = integer_of(*l, line, "the G10 L number");
    if (lv == 1) {
      const int tool = integer_of(*p, line, "the tool number P");
      // (a new entry starts at zero: Eigen leaves a default-constructed vector uninitialised)
      Vec3& entry = tool_table_.try_emplace(tool, Vec3::Zero()).first->second;
      (void)axis_values(lw, line, g, [&](int a, double v) { entry[a] = v; });
      return;
    }
    if (lv != 2 && lv != 20) {
      fail(line, l->column, l->text, "G10 " + l->text + " is not supported (L1, L2 and L20 are)");
    }
    const int sys_word = integer_of(*p, line, "the coordinate system P");
    if (sys_word > 9) fail(line, p->column, p->text, "the coordinate system P must be 0 (the current one) to 9 (G59.3)");
    const int sys = sys_word == 0 ? cs_ : sys_word;
    const std::size_t k = static_cast<std::size_t>(sys - 1);
    cs_set_[k] = true;
    if (lv == 2) {
      (void)axis_values(lw, line, g, [&](int a, double v) { cs_offset_[k][a] = v; });
      if (const Word* r = lw.get('R')) cs_rotation_[k] = r->value;
      return;
    }
    // L20: the current point's coordinates in system `sys`, with the given axes replaced
    if (const Word* r = lw.get('R')) cs_rotation_[k] = r->value;
    const Eigen::Matrix3d rot = rotation_of(sys);
    Vec3 prog = rot.transpose() * (pos_ - cs_offset_[k] - g92_ - tool_offset_);
    (void)axis_values(lw, line, g, [&](int a, double v) { prog[a] = v; });
    cs_offset_[k] = pos_ - g92_ - tool_offset_ - rot * prog;
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
  // other commands on the line that use its P word (G4, G10, G64); `axes_taken`: the axis words
  // belong to another command (G10, G28, G30, G43.1, G52, G92); `nm` the line's non-modal code.
  void motion(const LineWords& lw, const std::string& label, int line, int p_users, bool axes_taken, int nm) {
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
    const Word* first_axis = axes_taken ? nullptr : lw.first_of("XYZABC");
    const Word* first_arc_word = lw.first_of(nm == 100 ? "IJK" : "IJKR");
    if (first_arc_word && !arc_mode) {
      fail(line, first_arc_word->column, first_arc_word->text,
           std::string(1, first_arc_word->letter) + " word with no G2/G3 that uses it");
    }
    if (first_axis && motion_ == Motion::kNone) {
      fail(line, first_axis->column, first_axis->text, "axis words with no motion mode (G0, G1, G2, G3) in force");
    }
    const bool arc_here = arc_mode && !axes_taken && (first_axis || first_arc_word);
    // P has exactly one user on the line
    const Word* p = lw.get('P');
    if (p) {
      const int users = p_users + (arc_here ? 1 : 0);
      if (users == 0) fail(line, p->column, p->text, "P word with no G4, G10, G64 or G2/G3 that uses it");
      if (users > 1) fail(line, p->column, p->text, "P word used by two commands on one line (G4, G10, G64, G2/G3)");
    }
    // G53: this line's axis words are machine coordinates (LinuxCNC: G0 or G1, G90 only)
    const bool machine = nm == 530;
    if (machine) {
      const Word& g53 = *lw.g_in(GGroup::kNonModal)->second;
      if (motion_ != Motion::kRapid && motion_ != Motion::kLinear) fail(line, g53.column, g53.text, "G53 needs G0 or G1 in force");
      if (incremental_) fail(line, g53.column, g53.text, "G53 cannot be used in incremental distance mode (G91)");
    }
    if (!first_axis && !arc_here) return;
    const auto motion_word = lw.g_in(GGroup::kMotion);
    const Word* at = motion_word ? motion_word->second : (first_axis ? first_axis : first_arc_word);
    const SourceRef where{file_, line, at->column};
    const std::string code = motion_ == Motion::kRapid ? "G0" : motion_ == Motion::kLinear ? "G1"
                             : motion_ == Motion::kCw  ? "G2" : "G3";
    const std::string name = label + " " + code;
    const Vec3 target = target_of(lw, machine);
    line_orientation_ = angles_ ? angles_->apply(lw, incremental_, line, file_) : std::nullopt;
    if (arc_mode) {
      arc_move(target, lw, p, where, name, line);
    } else {
      line_move(target, where, name, motion_ == Motion::kRapid);
    }
  }

  // stops and program end (after motion)
  void after_motion(const std::vector<Code>& m_codes, int line) {
    for (const auto& [code, w] : m_codes) {
      if (code == 0 || code == 1) {
        stop_here();
        note(note_of(*w, line) + ": program pause treated as an exact stop");
      } else if (code == 2 || code == 30) {
        ended_ = true;
        end_word_ = w->text;
      }
    }
  }

  // Program and machine coordinates (LinuxCNC, emccanon.cc): a programmed point p is reached at
  // machine point R p + (coordinate system offset) + (G92/G52 offset) + (tool length offset),
  // R the system's rotation about Z. The path is in machine coordinates.
  std::size_t cs_index() const { return static_cast<std::size_t>(cs_ - 1); }
  Eigen::Matrix3d rotation_of(int sys) const {
    const double deg = cs_rotation_[static_cast<std::size_t>(sys - 1)];
    if (deg == 0) return Eigen::Matrix3d::Identity();
    return Eigen::AngleAxisd(deg * kDeg, Vec3::UnitZ()).toRotationMatrix();
  }
  Vec3 offsets() const { return cs_offset_[cs_index()] + g92_ + tool_offset_; }
  Vec3 to_machine(const Vec3& prog) const {
    if (cs_rotation_[cs_index()] == 0) return prog + offsets();
    return rotation_of(cs_) * prog + offsets();
  }
  Vec3 to_program(const Vec3& machine) const {
    if (cs_rotation_[cs_index()] == 0) return machine - offsets();
    return rotation_of(cs_).transpose() * (machine - offsets());
  }

  // The end point of a motion (m, machine coordinates): absent axes keep their value; G91 adds
  // to the current point; `machine` (G53): the words are machine coordinates.
  Vec3 target_of(const LineWords& lw, bool machine) const {
    Vec3 target = machine ? pos_ : to_program(pos_);
    const std::array<char, 3> letters = {'X', 'Y', 'Z'};
    for (int axis = 0; axis < 3; ++axis) {
      if (const Word* w = lw.get(letters[static_cast<std::size_t>(axis)])) {
        const double value = w->value * scale();
        target[axis] = incremental_ ? target[axis] + value : value;
      }
    }
    return machine ? target : to_machine(target);
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
      note(move.name + ": zero-length move dropped");
      return;
    }
    if (result_.program.moves.size() >= options_.max_moves) {
      fail(move.where.line, move.where.column, move.name.substr(move.name.rfind(' ') + 1),
           "more than " + std::to_string(options_.max_moves) + " moves (the limit of one program)");
    }
    // a line ends exactly at its programmed end (point(line, length) rounds, and an arc after it
    // would rise by 1e-19 m out of its plane); an arc where it computes its end
    const Line* line = std::get_if<Line>(&move.geometry);
    path_end_ = line ? line->p1 : point(move.geometry, len);
    if (move.orientation) path_orientation_ = *move.orientation;
    result_.program.moves.push_back(std::move(move));
  }

  void line_move(const Vec3& target, const SourceRef& where, const std::string& name, bool rapid) {
    add_move(make_move(Line{path_end_, target}, where, name, rapid), target);
  }

  void arc_move(const Vec3& target, const LineWords& lw, const Word* p, const SourceRef& where, const std::string& name, int line) {
    // the plane's axes in machine coordinates (a coordinate system may turn them about Z)
    PlaneAxes ax = axes_of(plane_);
    const Eigen::Matrix3d rot = rotation_of(cs_);
    ax.a1 = rot * ax.a1;
    ax.a2 = rot * ax.a2;
    ax.n = rot * ax.n;
    const PlaneAxes prog_ax = axes_of(plane_);
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
      // the centre in program coordinates (offsets from the current point, or absolute with
      // the current point's normal coordinate), then in machine coordinates
      const Vec3 current = to_program(pos_);
      const Vec3 centre_prog = ij_absolute_ ? Vec3(i1 * prog_ax.a1 + i2 * prog_ax.a2 + current.dot(prog_ax.n) * prog_ax.n)
                                            : Vec3(current + i1 * prog_ax.a1 + i2 * prog_ax.a2);
      c2 = in_plane(to_machine(centre_prog));
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
          note(name + ": end point " + in_units(abs_err) +
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

  static std::array<Vec3, 9> make_zero_offsets() {
    std::array<Vec3, 9> out;
    out.fill(Vec3::Zero());
    return out;
  }

  // SystemParams: the numbered and named parameters the interpreter owns, in program units.
  [[nodiscard]] std::optional<double> read(int n) const override {
    const double s = scale();
    const auto in = [n](int first, int count) { return n >= first && n < first + count; };
    if (in(kParamG28, 3)) return stored_[0][n - kParamG28] / s;
    if (in(kParamG30, 3)) return stored_[1][n - kParamG30] / s;
    if (n == kParamG92On) return g92_on_ ? 1.0 : 0.0;
    if (in(kParamG92, 3)) return g92_saved_[n - kParamG92] / s;
    if (n == kParamCoordSystem) return cs_;
    if (const auto slot = coord_slot(n)) {
      return slot->second == kParamRotation ? cs_rotation_[slot->first] : cs_offset_[slot->first][slot->second] / s;
    }
    if (n == kParamTool) return tool_;
    if (in(kParamToolOffset, 3)) return tool_offset_[n - kParamToolOffset] / s;
    if (in(kParamPosition, 3)) return to_program(pos_)[n - kParamPosition] / s;
    return std::nullopt;
  }
  bool write(int n, double value) override {
    const double v = value * scale();
    const auto in = [n](int first, int count) { return n >= first && n < first + count; };
    if (in(kParamG28, 3)) {
      stored_[0][n - kParamG28] = v;
    } else if (in(kParamG30, 3)) {
      stored_[1][n - kParamG30] = v;
    } else if (in(kParamG92, 3)) {
      g92_saved_[n - kParamG92] = v;
      if (g92_on_) g92_[n - kParamG92] = v;
    } else if (const auto slot = coord_slot(n)) {
      cs_set_[slot->first] = true;
      if (slot->second == kParamRotation) {
        cs_rotation_[slot->first] = value;
      } else {
        cs_offset_[slot->first][slot->second] = v;
      }
    } else {
      return false;
    }
    return true;
  }
  // (system index 0-8, axis 0-2 or kParamRotation) of a coordinate system parameter
  static std::optional<std::pair<std::size_t, int>> coord_slot(int n) {
    const int rel = n - kParamCoordBase;
    const int sys = rel / 20;
    const int axis = rel % 20;
    if (rel < 20 || sys > 9 || !(axis < 3 || axis == kParamRotation)) return std::nullopt;
    return std::make_pair(static_cast<std::size_t>(sys - 1), axis);
  }
  [[nodiscard]] std::optional<double> read_named(std::string_view name) const override {
    if (name.size() < 2 || name.front() != '_') return std::nullopt;
    const double s = scale();
    if (name == "_x" || name == "_y" || name == "_z") return to_program(pos_)[name[1] - 'x'] / s;
    if (name == "_metric") return inch_ ? 0.0 : 1.0;
    if (name == "_imperial") return inch_ ? 1.0 : 0.0;
    if (name == "_absolute") return incremental_ ? 0.0 : 1.0;
    if (name == "_incremental") return incremental_ ? 1.0 : 0.0;
    if (name == "_coord_system") {
      static constexpr std::array<double, 9> kCodes = {540, 550, 560, 570, 580, 590, 591, 592, 593};
      return kCodes[cs_index()];
    }
    if (name == "_current_tool") return tool_;
    if (name == "_selected_tool") return tool_selected_;
    if (name == "_feed") return feed_ * 60.0 / s;
    if (name == "_value") return value_;
    if (name == "_value_returned") return value_returned_;
    if (name == "_motion_mode") {
      switch (motion_) {
        case Motion::kRapid: return 0.0;
        case Motion::kLinear: return 10.0;
        case Motion::kCw: return 20.0;
        case Motion::kCcw: return 30.0;
        case Motion::kNone: return 800.0;
      }
    }
    if (name == "_plane") return plane_ == Plane::kXY ? 170.0 : plane_ == Plane::kXZ ? 180.0 : 190.0;
    // LinuxCNC: 1 when the machine's task runs the program, 0 in a preview; this plans what runs
    if (name == "_task") return 1.0;
    return std::nullopt;
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
  // offsets (m) and rotations (degrees) of the nine coordinate systems, the one in use (1-9),
  // whether the program set each; the G92/G52 offset applied and as stored in #5211-#5213;
  // the tool length offset, the tool in the spindle and the one selected; the tool table; the
  // G28 and G30 positions (machine coordinates)
  std::array<Vec3, 9> cs_offset_ = make_zero_offsets();
  std::array<double, 9> cs_rotation_{};
  std::array<bool, 9> cs_set_{};
  int cs_ = 1;
  Vec3 g92_ = Vec3::Zero();
  Vec3 g92_saved_ = Vec3::Zero();
  bool g92_on_ = false;
  Vec3 tool_offset_ = Vec3::Zero();
  int tool_ = 0;
  int tool_selected_ = 0;
  std::map<int, Vec3> tool_table_;
  std::array<Vec3, 2> stored_ = {Vec3::Zero(), Vec3::Zero()};
  // parameters, the O-word structure, the calls and repeat loops in progress, the value of the
  // last return (#<_value>), the lines executed (bounded) and those seen (notes once per line)
  Params params_;
  Flow flow_;
  std::vector<Call> calls_;
  std::vector<Repeat> repeats_;
  double value_ = 0;
  double value_returned_ = 0;
  std::size_t executed_ = 0;
  std::unordered_set<int> seen_lines_;
  bool repeated_line_ = false;
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
