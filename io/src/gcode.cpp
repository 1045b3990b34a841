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
#include <memory>
#include <unordered_map>
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
// RADIUS_TOLERANCE_INCH / _MM (in program units); interp_arc.cc refuses a centre-format arc
// beyond kSpiralAbsoluteFactor times the absolute tolerance whatever the relative error.
constexpr double kCentreArcRadiusTolInch = 2 * 0.001 * std::numbers::sqrt2;
constexpr double kCentreArcRadiusTolMm = 2 * 0.01 * std::numbers::sqrt2;
constexpr double kSpiralRelativeTol = 0.001;
constexpr double kSpiralAbsoluteFactor = 100;
// The most arcs one programmed spiral becomes (arcs_along_spiral doubles its biarcs up to it):
// at least two a quarter turn, so kMaxArcTurns = 100 turns take 800; the error of a biarc chain
// falls as the cube of its spacing, and one turn of the widest spiral LinuxCNC accepts (5 m
// growing by 2.8 mm) is within a micrometre at 16 arcs (measured).
constexpr int kMaxSpiralArcs = 1024;
constexpr double kRadiusTolInch = 0.00005;
constexpr double kRadiusTolMm = kRadiusTolInch * 25.4;

// An arc end point this close to its start (m, in the plane) makes a full circle.
constexpr double kSamePoint = kZeroLengthMove;
// Arc centre corrections below this (m) are rounding, not worth a note.
constexpr double kNoteworthyRadiusError = 1e-9;
// Rad: a dropped move whose angles turn the tool by more than this would lose a rotation.
constexpr double kSameOrientation = 1e-9;

using Vec2 = Eigen::Vector2d;

enum class Plane { kXY, kXZ, kYZ };
// The motion mode: G0, G1, G2, G3, G33 (a thread), G33.1 (rigid tapping), a canned cycle (its
// code in Reader::cycle_code_), G80 (none).
enum class Motion { kNone, kRapid, kLinear, kCw, kCcw, kThread, kTap, kCycle };

// LinuxCNC interp_internal.hh G83_RAPID_DELTA: how far above the last peck (in) G73 and G83
// come back down at rapid before they feed again.
constexpr double kPeckClearanceInch = 0.010;

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


// One file of the program: the main program, or a subroutine file a call read (LinuxCNC's
// "Calling Files"), with its O-word structure and the lines already run once (notes once).
struct Source {
  std::string name;     // as messages and moves name it
  std::string owned;    // a subroutine file's text (the main program's belongs to the caller)
  std::string_view text;
  Flow flow;
  std::unordered_set<int> seen_lines;
};

// Where the reader is: the file (an index into the sources), the start of the next line to
// read, its number, and the first O-word line at or after it (an index into Flow::lines).
struct Pc {
  std::size_t offset = 0;
  int line = 1;
  std::size_t next_o = 0;
  std::size_t source = 0;
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
      : options_(options), params_(*this) {
    sources_.push_back(std::make_unique<Source>());
    cur_ = sources_.front().get();
    cur_->name = file;
    cur_->text = text;
    pos_ = options.start;
    path_orientation_ = options.start_orientation.normalized();
    if (options.angles) angles_.emplace(*options.angles);
    path_end_ = options.start;
    feed_value_ = options.limits.velocity * 60;
    transition_ = options.blending;
    tool_table_ = options.tool_offsets;
  }

  GcodeResult run() {
    check_options();
    result_.start = options_.start;
    prepare(*cur_);
    // line by line, never all lines at once (a file of empty lines would cost 16 bytes a byte);
    // O-words jump to the lines the flow names, in this file or a subroutine file
    Pc pc;
    while (true) {
      cur_index_ = pc.source;
      cur_ = sources_[cur_index_].get();
      if (pc.offset > cur_->text.size()) break;
      const std::size_t end = std::min(cur_->text.find('\n', pc.offset), cur_->text.size());
      const std::string_view line = cur_->text.substr(pc.offset, end - pc.offset);
      const int number = pc.line;
      Pc next{end + 1, pc.line + 1, pc.next_o, pc.source};
      const bool o_line = pc.next_o < cur_->flow.lines.size() && cur_->flow.lines[pc.next_o].line == number;
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
      throw InputError(main_name(), 0, 0, "", "the G-code program has no moves");
    }
    return std::move(result_);
  }

 private:
  // A subroutine call in progress: its `sub` line and the file that holds it, where to go on
  // return (in the calling file), the line of the call.
  struct Call {
    int sub = 0;
    std::size_t source = 0;
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
    repeated_line_ = !cur_->flow.lines.empty() && !cur_->seen_lines.insert(number).second;
  }

  // " (in o<name> called from line N, ...)" for an error inside a subroutine; a call from
  // another file than the subroutine's names the calling file ("line N of main.ngc").
  std::string call_context() const {
    std::string out;
    for (auto it = calls_.rbegin(); it != calls_.rend(); ++it) {
      out += out.empty() ? " (in " : ", ";
      const Source& sub = *sources_[it->source];
      out += sub.flow.lines[static_cast<std::size_t>(it->sub)].head.name() + " called from line " + std::to_string(it->line);
      if (it->ret.source != it->source) out += " of " + sources_[it->ret.source]->name;
    }
    return out + ")";
  }

  // The name the program is read under (messages about the program as a whole).
  const std::string& main_name() const { return sources_.front()->name; }

  // A file's text ready to run: without a UTF-8 byte order mark (editors on Windows), its O-word
  // structure found and checked.
  static void prepare(Source& source) {
    if (source.text.substr(0, 3) == "\xEF\xBB\xBF") source.text.remove_prefix(3);
    source.flow = build_flow(source.text, source.name);
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
    const CompactLine compact = compact_line(line, number, cur_->name);
    if (compact.text.empty()) return true;
    seen_code_ = true;
    Block block = lex_block(compact, number, cur_->name, params_);
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
  Pc after(int k) const { return after(k, source_index()); }
  Pc at(int k) const {
    const OLine& o = cur_->flow.lines[static_cast<std::size_t>(k)];
    return {o.offset, o.line, static_cast<std::size_t>(k), source_index()};
  }
  // ... and the line after O-word line k of file `source`
  Pc after(int k, std::size_t source) const {
    const OLine& o = sources_[source]->flow.lines[static_cast<std::size_t>(k)];
    return {o.next, o.line + 1, static_cast<std::size_t>(k) + 1, source};
  }
  std::size_t source_index() const { return cur_index_; }

  // The bracketed values of O-word line k (its condition, count, arguments or return value).
  std::vector<double> values_of(int k, std::size_t min_count, std::size_t max_count) const {
    const OLine& o = cur_->flow.lines[static_cast<std::size_t>(k)];
    const std::size_t end = std::min(cur_->text.find('\n', o.offset), cur_->text.size());
    const CompactLine compact = compact_line(cur_->text.substr(o.offset, end - o.offset), o.line, cur_->name);
    return oword_values(compact, o.head, o.line, cur_->name, params_, min_count, max_count);
  }
  bool condition(int k) const { return values_of(k, 1, 1).front() != 0; }

  // Executes O-word line k; `next` is the line after it. Returns where to go on.
  Pc control(std::size_t index, const Pc& next) {
    const int k = static_cast<int>(index);
    const OLine& o = cur_->flow.lines[index];
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
        const OLine& loop = cur_->flow.lines[static_cast<std::size_t>(o.match)];
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
      const OLine& o = cur_->flow.lines[static_cast<std::size_t>(b)];
      if (o.kind == OKind::kEndif) return after(b);
      if (o.kind == OKind::kElse) return after(b);
      count_line(o.line, "elseif");
      if (condition(b)) return after(b);
      b = o.next_branch;
    }
  }

  Pc call(int k, const Pc& next) {
    const OLine& o = cur_->flow.lines[static_cast<std::size_t>(k)];
    if (calls_.size() >= kMaxCallDepth) {
      fail(o.line, o.head.column, o.head.name(),
           "subroutine calls nested deeper than " + std::to_string(kMaxCallDepth) + " (recursion that never ends?)");
    }
    const std::vector<double> args = values_of(k, 0, kCallArguments);
    const auto [source, sub] = find_sub(o);
    calls_.push_back({sub, source, next, o.line});
    params_.push_call(args);
    return after(sub, source);
  }

  // The subroutine an O-word call names, as (file, its `sub` line): defined in the calling file,
  // else in the main program, else the file <name>.ngc that options.find_subroutine finds
  // (LinuxCNC's "Calling Files"), read once and kept for the next call.
  std::pair<std::size_t, int> find_sub(const OLine& o) {
    const std::string& label = o.head.label;
    if (const auto it = cur_->flow.subs.find(label); it != cur_->flow.subs.end()) return {source_index(), it->second};
    if (const auto it = sources_.front()->flow.subs.find(label); it != sources_.front()->flow.subs.end()) return {0, it->second};
    const std::string name = o.head.name();
    if (label.front() != '<') {
      fail(o.line, o.head.column, name, name + " is not defined in this file (only named subroutines, o<name>, are looked up as files)");
    }
    const std::string base = label.substr(1, label.size() - 2);
    if (const auto it = sub_files_.find(base); it != sub_files_.end()) return {it->second, sub_in(*sources_[it->second], o)};
    // LinuxCNC's file names of subroutines: lower-case letters, digits, '-' and '_' (so a label
    // can never name a path outside the folders searched)
    const bool file_name = std::all_of(base.begin(), base.end(), [](char c) {
      return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' || c == '_';
    });
    if (!file_name) {
      fail(o.line, o.head.column, name,
           name + " is not defined in this file, and its name cannot name a subroutine file (letters, digits, '-' and '_' only)");
    }
    if (!options_.find_subroutine) {
      fail(o.line, o.head.column, name,
           name + " is not defined in this file, and no subroutine files are searched (read the program from a file)");
    }
    GcodeSubroutineLookup found;
    try {
      found = options_.find_subroutine(base);
    } catch (const InputError& e) {
      fail(o.line, o.head.column, name, "cannot read the subroutine file " + e.file() + ": " + e.detail());
    }
    if (!found.file) {
      fail(o.line, o.head.column, name, name + " is not defined in this file, and no file " + base + ".ngc was found (searched " + found.searched + ")");
    }
    auto source = std::make_unique<Source>();
    source->name = std::move(found.file->path);
    source->owned = std::move(found.file->text);
    source->text = source->owned;
    try {
      prepare(*source);
    } catch (const InputError& e) {
      throw InputError(e.file(), e.line(), e.column(), e.field(),
                       e.detail() + " (in the subroutine file of " + name + ", called from line " + std::to_string(o.line) +
                           " of " + cur_->name + ")");
    }
    const int sub = sub_in(*source, o);
    sources_.push_back(std::move(source));
    sub_files_.emplace(base, sources_.size() - 1);
    return {sources_.size() - 1, sub};
  }

  // The `sub` line of the subroutine call `o` names in a subroutine file.
  int sub_in(const Source& file, const OLine& o) const {
    const auto it = file.flow.subs.find(o.head.label);
    if (it == file.flow.subs.end()) {
      fail(o.line, o.head.column, o.head.name(), "the subroutine file " + file.name + " does not define " + o.head.name());
    }
    return it->second;
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
    throw InputError(cur_->name, line, column, word, message);
  }

  void check_options() const {
    const std::array<std::pair<double, const char*>, 4> limits = {{{options_.limits.velocity, "limits.velocity"},
                                                                   {options_.limits.acceleration, "limits.acceleration"},
                                                                   {options_.limits.deceleration, "limits.deceleration"},
                                                                   {options_.limits.jerk, "limits.jerk"}}};
    for (const auto& [value, field] : limits) {
      if (!std::isfinite(value) || value <= 0) {
        throw InputError(main_name(), 0, 0, field, std::string("G-code options: ") + field + " must be positive, got " + format_value(value, 10));
      }
    }
    if (!std::isfinite(options_.rapid_velocity) || options_.rapid_velocity < 0) {
      throw InputError(main_name(), 0, 0, "rapid_velocity", "G-code options: rapid_velocity must be >= 0");
    }
    if (!options_.start.allFinite()) throw InputError(main_name(), 0, 0, "start", "G-code options: start must be finite");
    if (!(options_.spiral_tolerance > 0) || !std::isfinite(options_.spiral_tolerance)) {
      throw InputError(main_name(), 0, 0, "spiral_tolerance", "G-code options: spiral_tolerance must be positive");
    }
    if (!options_.start_orientation.coeffs().allFinite() || !(options_.start_orientation.norm() > 0.5)) {
      throw InputError(main_name(), 0, 0, "start_orientation", "G-code options: start_orientation must be a unit quaternion");
    }
    if (options_.angles) {
      std::array<bool, 3> named{};
      for (const ToolAngle a : options_.angles->abc) named[static_cast<std::size_t>(a)] = true;
      if (!(named[0] && named[1] && named[2])) {
        throw InputError(main_name(), 0, 0, "angles", "G-code options: A, B and C must name roll, pitch and yaw, each once");
      }
    }
  }

  // Notes the non-blank lines not read: those from text offset `begin` on, line `line` being the
  // last one read.
  void note_rest(std::size_t begin, int line, const std::string& why) {
    int first = 0;
    int last = 0;
    for (; begin <= cur_->text.size(); begin = std::min(cur_->text.find('\n', begin), cur_->text.size()) + 1) {
      ++line;
      const std::size_t end = std::min(cur_->text.find('\n', begin), cur_->text.size());
      if (strip_blanks(cur_->text.substr(begin, end - begin)).empty()) continue;
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
    line_ = line;
    std::vector<Word> words = block.words;
    const std::string label = take_line_number(words, line);
    const LineWords lw = sort_words(words, line, cur_->name, options_.angles.has_value());

    // units first: every value on the line is read in the units in force after it; G7 (lathe
    // diameter mode) halves the line's X words, as LinuxCNC reads X in it; the feed mode before F
    if (const auto units = lw.g_in(GGroup::kUnits)) inch_ = units->first == 200;
    if (const auto lathe = lw.g_in(GGroup::kLatheDiameter)) diameter_ = lathe->first == 70;
    if (diameter_) {
      for (Word& w : words) {
        if (w.letter == 'X') w.value *= 0.5;
      }
    }
    if (const auto feed_mode = lw.g_in(GGroup::kFeedMode)) per_revolution_ = feed_mode->first == 950;
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
    // the motion mode after this line: canned cycles read Q (G73, G83) and L (repeats)
    const Motion next = lw.g_in(GGroup::kMotion) ? motion_of(lw.g_in(GGroup::kMotion)->first) : motion_;
    const int next_cycle = lw.g_in(GGroup::kMotion) ? lw.g_in(GGroup::kMotion)->first : cycle_code_;
    const bool pecks = next == Motion::kCycle && (next_cycle == 730 || next_cycle == 830);
    if (q && !g64 && !pecks) fail(line, q->column, q->text, "Q word with no G64, G73 or G83 that uses it");
    if (const Word* l = lw.get('L'); l && nm != 100 && next != Motion::kCycle) {
      fail(line, l->column, l->text, "L word with no G10 or canned cycle that uses it");
    }
    if (dwell) dwell_here(*non_modal->second, p, line);
    // polar coordinates are a motion's end point, never an offset's or a tool's coordinates
    const bool command_axes = nm == 100 || nm == 280 || nm == 300 || nm == 520 || nm == 920 ||
                              (lw.g_in(GGroup::kToolLength) && lw.g_in(GGroup::kToolLength)->first != 430 &&
                               lw.g_in(GGroup::kToolLength)->first != 490);
    if (const Word* polar = lw.first_of("@^"); polar && command_axes) {
      fail(line, polar->column, polar->text, "polar coordinates (@, ^) are for motion, not for this line's offset or tool command");
    }
    set_modes(lw, line);
    const bool tool_axes = tool_length(lw, line);
    set_coordinate_system(lw, line);
    if (path_control) set_path_control(g64, (dwell || nm == 100) ? nullptr : p, g64 ? q : nullptr, line);
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
      // F0 is a valid setting (LinuxCNC); a feed move at it is refused (feed_velocity). Units
      // per minute (G94) or per revolution (G95), as the mode in force reads the number.
      if (!(f->value >= 0)) fail(line, f->column, f->text, "the feed rate F must be >= 0");
      feed_value_ = f->value * scale();
      // the first F word in units per minute, for the warning that it overrides defaults.velocity
      if (result_.first_feed_where.line == 0 && !per_revolution_ && feed_value_ > 0) {
        result_.first_feed_where = {cur_->name, line, f->column};
        result_.first_feed = feed_value_ / 60.0;
      }
    }
    if (const Word* sw = lw.get('S')) {
      if (!(sw->value >= 0)) fail(line, sw->column, sw->text, "the spindle speed S must be >= 0");
      spindle_speed_ = sw->value;
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

  // M6, spindle, coolant (before motion); M3/M4 start the spindle (the speed S sets the feed of
  // G33, G33.1 and G95), M5 stops it
  void before_motion(const std::vector<Code>& m_codes, int line) {
    for (const auto& [code, w] : m_codes) {
      if (code == 3 || code == 4) {
        spindle_on_ = true;
        spindle_clockwise_ = code == 3;
      }
      if (code == 5) spindle_on_ = false;
      if (code == 6) {
        stop_here();
        tool_ = tool_selected_;
        note(note_of(*w, line) + ": tool change treated as an exact stop");
      } else if (m_group_of(code) == MGroup::kSpindle || m_group_of(code) == MGroup::kCoolant ||
                 m_group_of(code) == MGroup::kOverride) {
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

  // The plane, the canned cycles' retract mode (G98 to the initial level, G99 to R), and the
  // modal codes that do not change the path (noted): cutter compensation off, feed mode, spindle
  // speed mode (G96 constant surface speed, G97 rpm)
  void set_modes(const LineWords& lw, int line) {
    if (const auto plane = lw.g_in(GGroup::kPlane)) {
      plane_ = plane->first == 170 ? Plane::kXY : plane->first == 180 ? Plane::kXZ : Plane::kYZ;
    }
    if (const auto retract = lw.g_in(GGroup::kRetractMode)) {
      retract_to_r_ = retract->first == 990;
      retract_given_ = true;
    }
    if (const auto spindle = lw.g_in(GGroup::kSpindleMode)) surface_speed_ = spindle->first == 960;
    for (const GGroup group : {GGroup::kCutterComp, GGroup::kFeedMode, GGroup::kSpindleMode}) {
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
        const SourceRef where{cur_->name, line, g.column};
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
  // The motion mode a G code of the motion group selects.
  static Motion motion_of(int code) {
    switch (code) {
      case 0: return Motion::kRapid;
      case 10: return Motion::kLinear;
      case 20: return Motion::kCw;
      case 30: return Motion::kCcw;
      case 330: return Motion::kThread;
      case 331: return Motion::kTap;
      case 800: return Motion::kNone;
      default: return Motion::kCycle;
    }
  }

  void motion(const LineWords& lw, const std::string& label, int line, int p_users, bool axes_taken, int nm) {
    const Motion before = motion_;
    const int cycle_before = cycle_code_;
    if (const auto motion_word = lw.g_in(GGroup::kMotion)) {
      motion_ = motion_of(motion_word->first);
      if (motion_ == Motion::kCycle) cycle_code_ = motion_word->first;
    }
    // a run of canned cycles starts at the level it finds (LinuxCNC's cycle_il); another motion
    // mode ends it
    if (motion_ != Motion::kCycle) cycle_initial_.reset();
    const bool arc_mode = motion_ == Motion::kCw || motion_ == Motion::kCcw;
    const bool cycle = motion_ == Motion::kCycle;
    const bool spindle = motion_ == Motion::kThread || motion_ == Motion::kTap;
    const Word* first_axis = axes_taken ? nullptr : lw.first_of("XYZABC@^");
    // I, J, K, R: arc words, but R is a cycle's retract plane and K the pitch of G33/G33.1
    std::string_view arc_letters = nm == 100 ? "IJK" : "IJKR";
    if (cycle) arc_letters = "IJK";
    if (spindle) arc_letters = nm == 100 ? "IJ" : "IJR";
    const Word* first_arc_word = lw.first_of(arc_letters);
    if (first_arc_word && !arc_mode) {
      fail(line, first_arc_word->column, first_arc_word->text,
           std::string(1, first_arc_word->letter) + " word with no G2/G3 that uses it");
    }
    if (const Word* k = lw.get('K'); k && !arc_mode && !spindle && nm != 100) {
      fail(line, k->column, k->text, "K word with no G2/G3, G33 or G33.1 that uses it");
    }
    if (first_axis && motion_ == Motion::kNone) {
      fail(line, first_axis->column, first_axis->text, "axis words with no motion mode in force (G0-G3, G33, G33.1, a canned cycle)");
    }
    if (const Word* r = lw.get('R'); r && cycle && !first_axis && nm != 100) {
      fail(line, r->column, r->text, "R word with no axis word: a canned cycle runs where a line names its position");
    }
    const bool arc_here = arc_mode && !axes_taken && (first_axis || first_arc_word);
    const bool dwell_cycle = cycle && (cycle_code_ == 820 || cycle_code_ == 860 || cycle_code_ == 890) && first_axis;
    // P has exactly one user on the line
    const Word* p = lw.get('P');
    if (p) {
      const int users = p_users + (arc_here ? 1 : 0) + (dwell_cycle ? 1 : 0) + (takes_p(lw.m_codes) ? 1 : 0);
      if (users == 0) fail(line, p->column, p->text, "P word with no G4, G10, G64, G2/G3, G82/G86/G89 or M50-M53 that uses it");
      if (users > 1) fail(line, p->column, p->text, "P word used by two commands on one line (G4, G10, G64, G2/G3, G82/G86/G89, M50-M53)");
    }
    // G53: this line's axis words are machine coordinates (LinuxCNC: G0 or G1, G90 only)
    const bool machine = nm == 530;
    if (machine) {
      const Word& g53 = *lw.g_in(GGroup::kNonModal)->second;
      if (motion_ != Motion::kRapid && motion_ != Motion::kLinear) fail(line, g53.column, g53.text, "G53 needs G0 or G1 in force");
      if (incremental_) fail(line, g53.column, g53.text, "G53 cannot be used in incremental distance mode (G91)");
      if (const Word* polar = lw.first_of("@^")) fail(line, polar->column, polar->text, "G53 takes no polar coordinates");
    }
    if (!first_axis && !arc_here) return;
    const auto motion_word = lw.g_in(GGroup::kMotion);
    const Word* at = motion_word ? motion_word->second : (first_axis ? first_axis : first_arc_word);
    const SourceRef where{cur_->name, line, at->column};
    const std::string name = label + " " + motion_name();
    if (cycle) {
      if (const Word* abc = lw.first_of("ABC")) fail(line, abc->column, abc->text, "tool angles cannot change in a canned cycle");
      canned_cycle(lw, before == Motion::kCycle && cycle_before == cycle_code_, where, name);
      return;
    }
    const Vec3 target = target_of(lw, machine);
    line_orientation_ = angles_ ? angles_->apply(lw, incremental_, line, cur_->name) : std::nullopt;
    if (arc_mode) {
      arc_move(target, lw, p, where, name, line);
    } else if (spindle) {
      spindle_move(target, lw, where, name);
    } else {
      line_move(target, where, name, motion_ == Motion::kRapid);
    }
  }

  // "G0" ... "G33.1", "G81" ...: the motion mode as move names give it.
  std::string motion_name() const {
    switch (motion_) {
      case Motion::kRapid: return "G0";
      case Motion::kLinear: return "G1";
      case Motion::kCw: return "G2";
      case Motion::kCcw: return "G3";
      case Motion::kThread: return "G33";
      case Motion::kTap: return "G33.1";
      case Motion::kCycle: return "G" + std::to_string(cycle_code_ / 10);
      case Motion::kNone: return "G80";
    }
    return "";
  }

  // G33 (spindle-synchronised motion) and G33.1 (rigid tapping), LinuxCNC's: the tool moves along
  // a line by K per spindle revolution, so at S K per minute with the spindle at S (the
  // synchronisation itself is not modelled: the planner holds that speed as the feed). G33.1
  // then reverses the spindle and comes back along the same line to where it started, stopping
  // at the bottom.
  void spindle_move(const Vec3& target, const LineWords& lw, const SourceRef& where, const std::string& name) {
    const std::string word = name.substr(name.rfind(' ') + 1);
    const Word* k = lw.get('K');
    if (!k) fail(where.line, where.column, word, word + " needs K, the distance per spindle revolution");
    if (!(k->value > 0)) fail(where.line, k->column, k->text, "the distance per revolution K must be positive");
    const double velocity = k->value * scale() * spindle_rpm(where, word, word) / 60.0;
    if (motion_ == Motion::kThread) {
      line_move(target, where, name, false, velocity);
      return;
    }
    const Vec3 start = pos_;
    line_move(target, where, name, false, velocity);
    stop_here();
    note(name + ": the spindle reverses at the bottom (an exact stop) and the tap comes back along its line");
    line_move(start, where, name, false, velocity);
    stop_here();
  }

  // A canned cycle at the position the line names (LinuxCNC's interp_cycles.cc, convert_cycle and
  // its CYCLE_MACRO), in the plane's terms: (a, b) in the plane, c along its normal (Z for G17,
  // Y for G18, X for G19), all in program coordinates. `continuing`: the same cycle was in force
  // (R, the bottom, P and Q may then be left out). Every move of the cycle stops at its end (the
  // cycle runs in exact path mode); L repeats it, in G91 each time further by the line's X, Y.
  void canned_cycle(const LineWords& lw, bool continuing, const SourceRef& where, const std::string& name) {
    const std::string word = name.substr(name.rfind(' ') + 1);
    const PlaneAxes ax = axes_of(plane_);
    const char letters[3] = {"XYZ"[ax_index(ax.a1)], "XYZ"[ax_index(ax.a2)], "XYZ"[ax_index(ax.n)]};
    const auto word_of = [&](char letter) { return lw.get(letter); };
    const auto fail_here = [&](const std::string& message) { fail(where.line, where.column, word, message); };
    if (const Word* polar = lw.first_of("@^")) fail(where.line, polar->column, polar->text, "polar coordinates are not supported in canned cycles");
    // R, the bottom (the normal axis word), P, Q: given, or kept from the same cycle
    const Word* r_word = word_of('R');
    if (!r_word && !continuing) fail_here(word + " needs R, the retract plane");
    if (r_word) cycle_r_ = r_word->value * scale();
    const Word* bottom_word = word_of(letters[2]);
    if (!bottom_word && !continuing) fail_here(word + " needs " + letters[2] + ", the bottom of the hole");
    if (bottom_word) cycle_bottom_ = bottom_word->value * scale();
    const bool dwells = cycle_code_ == 820 || cycle_code_ == 860 || cycle_code_ == 890;
    if (dwells) {
      const Word* p = word_of('P');
      if (!p && !continuing) fail_here(word + " needs P, the dwell at the bottom in seconds");
      if (p && !(p->value >= 0)) fail(where.line, p->column, p->text, "the dwell time P must be >= 0");
      if (p) cycle_p_ = p->value;
    }
    const bool pecks = cycle_code_ == 730 || cycle_code_ == 830;
    if (pecks) {
      const Word* q = word_of('Q');
      if (!q && !continuing) fail_here(word + " needs Q, the depth of each peck");
      if (q && !(q->value > 0)) fail(where.line, q->column, q->text, "the peck depth Q must be positive");
      if (q) cycle_q_ = q->value * scale();
    }
    int repeats = 1;
    if (const Word* l = word_of('L')) {
      repeats = integer_of(*l, where.line, "the repeat count L");
      if (repeats < 1) fail(where.line, l->column, l->text, "a canned cycle cannot be repeated zero times (L0)");
    }
    // spindle checks (LinuxCNC's): G84 taps with the spindle turning clockwise, G86 needs it turning
    if ((cycle_code_ == 840 || cycle_code_ == 860) && (!spindle_on_ || !(spindle_speed_ > 0))) {
      fail_here(word + " needs the spindle turning: M3 or M4 with a speed S > 0");
    }
    if (cycle_code_ == 840 && !spindle_clockwise_) fail_here("G84 taps with the spindle turning clockwise (M3), not M4");
    // where: (a, b, c) of the current point; the cycle's levels
    const Vec3 current = to_program(pos_);
    const auto plane_of = [&](const Vec3& v) { return Vec3(v.dot(ax.a1), v.dot(ax.a2), v.dot(ax.n)); };
    const Vec3 here = plane_of(current);
    if (!cycle_initial_) cycle_initial_ = here.z();
    double old_c = *cycle_initial_;
    double a = here.x();
    double b = here.y();
    double da = 0;
    double db = 0;
    double r = cycle_r_;
    double bottom = cycle_bottom_;
    if (incremental_) {
      // X, Y are increments of the position, R of the initial level, the bottom of R (NCMS)
      if (const Word* w = word_of(letters[0])) da = w->value * scale();
      if (const Word* w = word_of(letters[1])) db = w->value * scale();
      r = cycle_r_ + old_c;
      bottom = r + cycle_bottom_;
    } else {
      if (const Word* w = word_of(letters[0])) a = w->value * scale();
      if (const Word* w = word_of(letters[1])) b = w->value * scale();
    }
    if (r < bottom) fail_here("the retract plane R is below the bottom of the hole (" + std::string(1, letters[2]) + ")");
    const auto to_point = [&](double pa, double pb, double pc) { return to_machine(pa * ax.a1 + pb * ax.a2 + pc * ax.n); };
    // every move of the cycle stops at its end (LinuxCNC runs cycles in exact path mode)
    const Transition saved = transition_;
    transition_ = Transition{};
    const auto go = [&](double pa, double pb, double pc, bool rapid) {
      const Vec3 target = to_point(pa, pb, pc);
      if ((target - pos_).norm() <= kZeroLengthMove) return;
      line_move(target, where, name, rapid);
    };
    double current_c = here.z();
    // below the retract plane: straight up to it first
    if (old_c < r) {
      go(here.x(), here.y(), r, true);
      old_c = r;
      current_c = r;
    }
    if (!retract_given_ && old_c > r) {
      note(name + ": neither G98 nor G99 given: the cycle retracts to the initial level (G98)");
    }
    const double clear = retract_to_r_ ? r : old_c;
    const double peck_clearance = kPeckClearanceInch * kMetresPerInch;
    for (int repeat = repeats; repeat > 0; --repeat) {
      a += da;
      b += db;
      if (repeat == repeats && current_c > r) {
        go(a, b, current_c, true);
        go(a, b, r, true);
      } else {
        go(a, b, clear, true);
        if (clear > r) go(a, b, r, true);
      }
      switch (cycle_code_) {
        case 810:  // drill: feed to the bottom, rapid out
          go(a, b, bottom, false);
          go(a, b, clear, true);
          break;
        case 820:  // drill with a dwell at the bottom
        case 860:  // bore: dwell, the spindle stops, rapid out
          go(a, b, bottom, false);
          note(name + ": dwell of " + format_value(cycle_p_, 6) + " s at the bottom (an exact stop)" +
               (cycle_code_ == 860 ? "; the spindle stops for the retract" : ""));
          go(a, b, clear, true);
          break;
        case 730:  // chip break: feed by Q, back off a little at rapid, until the bottom
        case 830:  // peck: feed by Q, rapid out to R and back down near the last depth
          // (a Q too small to change the depth in floating point would peck forever without a
          // move: refused; every peck that changes it adds moves, which max_moves bounds)
          for (double depth = r - cycle_q_; depth > bottom; depth -= cycle_q_) {
            if (!(depth - cycle_q_ < depth) || !(depth < r)) {
              fail_here("the peck depth Q is too small for the depth of this hole (" + format_value(cycle_q_ / scale(), 6) +
                        " " + unit_name() + " from R at " + format_value(r / scale(), 6) + ")");
            }
            go(a, b, depth, false);
            if (cycle_code_ == 830) go(a, b, r, true);
            go(a, b, depth + peck_clearance, true);
          }
          go(a, b, bottom, false);
          go(a, b, clear, true);
          break;
        case 840:  // tap: feed in, the spindle reverses, feed out
          go(a, b, bottom, false);
          note(name + ": the spindle reverses at the bottom (an exact stop)");
          go(a, b, clear, false);
          break;
        case 850:  // bore or ream: feed in, feed out to R, rapid to the clearance
          go(a, b, bottom, false);
          go(a, b, r, false);
          go(a, b, clear, true);
          break;
        case 890:  // bore: feed in, dwell, feed out
          go(a, b, bottom, false);
          note(name + ": dwell of " + format_value(cycle_p_, 6) + " s at the bottom (an exact stop)");
          go(a, b, clear, false);
          break;
        default:
          fail_here(word + " is not a supported canned cycle");
      }
    }
    transition_ = saved;
  }

  // 0, 1, 2 for the coordinate axis a unit vector is (the program frame's plane axes).
  static std::size_t ax_index(const Vec3& axis) { return axis.x() != 0 ? 0 : axis.y() != 0 ? 1 : 2; }

  // Whether the line's M codes use its P word (M50-M53 take an optional P: the override's state).
  static bool takes_p(const std::vector<Code>& m_codes) {
    return std::any_of(m_codes.begin(), m_codes.end(), [](const Code& c) { return c.first >= 50 && c.first <= 53; });
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
    if (lw.first_of("@^")) {
      const Vec2 xy = polar_point(lw, Vec2(target.x(), target.y()));
      target.x() = xy.x();
      target.y() = xy.y();
    }
    return machine ? target : to_machine(target);
  }

  // LinuxCNC's polar coordinates (interp_find.cc, find_ends; G17 only, in program coordinates):
  // '@' the distance from the origin, '^' the angle in degrees from +X; under G90 the one not
  // written keeps the current point's, under G91 '@' adds to its distance and '^' to its angle.
  // `current` is the current point's X and Y.
  Vec2 polar_point(const LineWords& lw, const Vec2& current) const {
    const Word* first = lw.first_of("@^");
    const Word* radius = lw.get('@');
    const Word* angle = lw.get('^');
    const int line = line_;
    if (plane_ != Plane::kXY) fail(line, first->column, first->text, "polar coordinates (@, ^) are only for the XY plane (G17)");
    if (const Word* xy = lw.first_of("XY")) fail(line, xy->column, xy->text, "X and Y cannot be given with polar coordinates (@, ^)");
    const bool at_origin = current.x() == 0 && current.y() == 0;
    double r = current.norm();
    double a = std::atan2(current.y(), current.x());
    if (incremental_) {
      if (at_origin) fail(line, first->column, first->text, "incremental polar coordinates are not defined at the origin");
      if (radius) r += radius->value * scale();
      if (angle) a += angle->value * kDeg;
    } else {
      if (!angle && at_origin) fail(line, first->column, first->text, "at the origin a polar move needs its angle ^");
      if (radius) r = radius->value * scale();
      if (angle) a = angle->value * kDeg;
    }
    return {r * std::cos(a), r * std::sin(a)};
  }


  // The feed (m/s) of a feed move: F units per minute (G94), or F units per revolution times the
  // spindle speed (G95, LinuxCNC's units per revolution). Refused at the move: F0 (LinuxCNC:
  // "Cannot do G1 with zero feed rate"), and G95 without a spindle speed (spindle_rpm).
  double feed_velocity(const SourceRef& where, const std::string& name) const {
    if (!per_revolution_ && feed_value_ > 0) return feed_value_ / 60.0;
    const std::string word = name.substr(name.rfind(' ') + 1);
    if (!(feed_value_ > 0)) {
      fail(where.line, where.column, word, "a feed move with feed rate 0 (the last F word was F0): program F before it");
    }
    return feed_value_ * spindle_rpm(where, word, "feed per revolution (G95)") / 60.0;
  }

  // The spindle speed (rev/min) that sets the feed of `what`: the S in force with the spindle
  // turning (M3/M4). Under constant surface speed (G96) the speed, and with it the feed, would
  // change along the path with the radius: refused.
  double spindle_rpm(const SourceRef& where, const std::string& word, const std::string& what) const {
    if (surface_speed_) {
      fail(where.line, where.column, word,
           what + " under constant surface speed (G96): the spindle speed, and so the feed, changes along the path "
                  "(not supported; G97 sets a speed)");
    }
    if (!spindle_on_ || !(spindle_speed_ > 0)) {
      fail(where.line, where.column, word, what + " needs the spindle turning: M3 or M4 with a speed S > 0");
    }
    return spindle_speed_;
  }

  // `velocity` (m/s) replaces the feed (G33, G33.1: the spindle sets it).
  Move make_move(Primitive geometry, const SourceRef& where, const std::string& name, bool rapid,
                 std::optional<double> velocity = std::nullopt) const {
    Move move;
    move.geometry = std::move(geometry);
    move.limits = options_.limits;
    move.limits.velocity = rapid      ? (options_.rapid_velocity > 0 ? options_.rapid_velocity : options_.limits.velocity)
                           : velocity ? *velocity
                                      : feed_velocity(where, name);
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

  void line_move(const Vec3& target, const SourceRef& where, const std::string& name, bool rapid,
                 std::optional<double> velocity = std::nullopt) {
    add_move(make_move(Line{path_end_, target}, where, name, rapid, velocity), target);
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
      // LinuxCNC's acceptance (interp_arc.cc, arc_data_ijk, as its G-code manual states it in
      // "Center Format Arcs"): refused beyond 100 times the absolute tolerance, or beyond the
      // absolute and the relative tolerance together
      const double abs_err = std::abs(r1 - r2);
      const double rel_err = abs_err / std::max(r1, r2);
      if (abs_err > kSpiralAbsoluteFactor * tol_abs || (rel_err > kSpiralRelativeTol && abs_err > tol_abs)) {
        fail(line, where.column, word,
             "radius to end of arc differs from radius to start: r1 = " + in_units(r1) + ", r2 = " + in_units(r2) +
                 " (difference " + in_units(abs_err) + ", " + format_value(100 * rel_err, 10) + "%; LinuxCNC allows " +
                 in_units(kSpiralAbsoluteFactor * tol_abs) + ", or " + in_units(tol_abs) + " beyond 0.1%)");
      }
      if (!full_circle && abs_err > 0) {
        spiral_move(start, target, c2, r1, r2, sign, turns, ax, where, name);
        return;
      }
    }

    // the arc about the plane's normal (clockwise for G2), helical when the normal axis moves;
    // the centre already satisfies the radius rule, so only rounding is left to absorb
    const Vec3 centre = c2.x() * ax.a1 + c2.y() * ax.a2 + start.dot(ax.n) * ax.n;
    const Vec3 end = end_of_arc(start, target, ax);
    const ArcBuild built = arc_from_center(start, end, centre, ax.a1.cross(ax.a2), sign > 0, turns - 1);
    if (!built.outcome.ok()) fail(line, where.column, name, built.outcome.message);
    const Arc& arc = built.arc;
    add_move(make_move(arc, where, name, false), target);
  }

  // The end point of an arc from `start` to `target` in the plane of `ax`: a rise below
  // kSamePoint is rounding (G91 sums, a units change), not a helix, so the arc ends in its
  // start's plane and the corners it makes stay planar (n is a coordinate axis: the end's normal
  // coordinate becomes the start's exactly).
  static Vec3 end_of_arc(const Vec3& start, const Vec3& target, const PlaneAxes& ax) {
    const double rise = (target - start).dot(ax.n);
    return std::abs(rise) <= kSamePoint ? Vec3(target - target.dot(ax.n) * ax.n + start.dot(ax.n) * ax.n) : target;
  }

  // An arc whose end radius r2 differs from its start radius r1 within LinuxCNC's tolerance:
  // LinuxCNC cuts a spiral about the programmed centre c2, the radius linear in the angle
  // (arcs_along_spiral). The path follows it within options.spiral_tolerance: one circle through
  // both end points where that is close enough, else tangent arcs; never further from it.
  void spiral_move(const Vec3& start, const Vec3& target, const Vec2& c2, double r1, double r2, double sign, int turns,
                   const PlaneAxes& ax, const SourceRef& where, const std::string& name) {
    const auto in_plane = [&](const Vec3& v) { return Vec2(v.dot(ax.a1), v.dot(ax.a2)); };
    const auto to_3d = [&](const Vec2& v) { return Vec3(v.x() * ax.a1 + v.y() * ax.a2); };
    const Vec3 end = end_of_arc(start, target, ax);
    const Vec2 u = (in_plane(start) - c2) / r1;
    const Vec2 v = sign * Vec2(-u.y(), u.x());
    const Vec2 rel = in_plane(end) - c2;
    double sweep = std::atan2(rel.dot(v), rel.dot(u));
    if (sweep <= 0) sweep += kTwoPi;
    Spiral spiral;
    spiral.center = to_3d(c2) + start.dot(ax.n) * ax.n;
    spiral.u = to_3d(u);
    spiral.v = to_3d(v);
    spiral.r0 = r1;
    spiral.r1 = r2;
    spiral.sweep = sweep + kTwoPi * (turns - 1);
    // (w = u x v is +n counter-clockwise, -n clockwise)
    spiral.rise = sign * (end - start).dot(ax.n);
    const SpiralArcs chain = arcs_along_spiral(spiral, options_.spiral_tolerance, kMaxSpiralArcs);
    const std::string word = name.substr(name.rfind(' ') + 1);
    const std::string units = unit_name();
    const auto in_units = [&](double metres) { return format_value(metres / scale(), 10) + " " + units; };
    if (!chain.outcome.ok()) {
      fail(where.line, where.column, word,
           "the end point is within LinuxCNC's radius tolerance (r1 = " + in_units(r1) + ", r2 = " + in_units(r2) +
               "), where LinuxCNC cuts a spiral, but " + chain.outcome.message + "; correct the end point or the centre");
    }
    const double abs_err = std::abs(r1 - r2);
    if (chain.arcs.size() > 1) {
      note(name + ": end point " + in_units(abs_err) + " off the circle: LinuxCNC's spiral followed by " +
           std::to_string(chain.arcs.size()) + " tangent arcs within " + in_units(chain.deviation));
    } else if (abs_err > kNoteworthyRadiusError) {
      note(name + ": end point " + in_units(abs_err) + " off the circle; centre moved onto the bisector of start and end (within " +
           in_units(chain.deviation) + " of LinuxCNC's spiral)");
    }
    // a tool orientation target is reached at the chain's end: the arcs before take the slerp
    // at their share of its length, which is the one move's orientation along the way (the
    // planner slerps each move by its arc length)
    double total = 0;
    for (const Arc& arc : chain.arcs) total += length(arc);
    const Quat from = path_orientation_;
    double done = 0;
    for (std::size_t k = 0; k < chain.arcs.size(); ++k) {
      const Arc& arc = chain.arcs[k];
      const bool last = k + 1 == chain.arcs.size();
      Move move = make_move(arc, where, name, false);
      done += length(arc);
      if (move.orientation && !last) move.orientation = from.slerp(done / total, *move.orientation).normalized();
      add_move(std::move(move), last ? target : point(arc, length(arc)));
    }
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
    if (name == "_feed") return feed_value_ / s;
    if (name == "_value") return value_;
    if (name == "_value_returned") return value_returned_;
    if (name == "_motion_mode") {
      switch (motion_) {
        case Motion::kRapid: return 0.0;
        case Motion::kLinear: return 10.0;
        case Motion::kCw: return 20.0;
        case Motion::kCcw: return 30.0;
        case Motion::kThread: return 330.0;
        case Motion::kTap: return 331.0;
        case Motion::kCycle: return cycle_code_;
        case Motion::kNone: return 800.0;
      }
    }
    if (name == "_plane") return plane_ == Plane::kXY ? 170.0 : plane_ == Plane::kXZ ? 180.0 : 190.0;
    // LinuxCNC: 1 when the machine's task runs the program, 0 in a preview; this plans what runs
    if (name == "_task") return 1.0;
    return std::nullopt;
  }

  // the main program (first) and the subroutine files read, the one being read; the files read
  // by subroutine name (lower case, without < >) -> index into sources_
  std::vector<std::unique_ptr<Source>> sources_;
  Source* cur_ = nullptr;
  std::size_t cur_index_ = 0;
  std::unordered_map<std::string, std::size_t> sub_files_;
  const GcodeOptions& options_;
  GcodeResult result_;

  Vec3 pos_;       // m: the interpreter's current point (the programmed end of the last motion)
  Vec3 path_end_;  // m: where the last kept move ends (differs from pos_ only after a dropped move)
  // the F number in metres per minute (G94) or per revolution (G95, per_revolution_); the spindle
  // speed S (rpm, or surface speed under G96), whether it turns (M3/M4); G7 lathe diameter mode
  double feed_value_ = 0;
  bool per_revolution_ = false;
  double spindle_speed_ = 0;
  bool spindle_on_ = false;
  bool spindle_clockwise_ = true;
  bool surface_speed_ = false;
  bool diameter_ = false;
  int line_ = 0;  // the line being executed
  // canned cycles: the cycle in force (730, 810, ...), its R, bottom (as written), P and Q, the
  // initial level of a run of cycles (program coordinates along the plane's normal), and whether
  // G98/G99 was ever given
  int cycle_code_ = 0;
  double cycle_r_ = 0;
  double cycle_bottom_ = 0;
  double cycle_p_ = 0;
  double cycle_q_ = 0;
  std::optional<double> cycle_initial_;
  bool retract_given_ = false;
  Transition transition_;
  Plane plane_ = Plane::kXY;
  Motion motion_ = Motion::kNone;  // LinuxCNC starts in G80
  bool inch_ = false;
  bool incremental_ = false;
  bool ij_absolute_ = false;
  bool retract_to_r_ = false;  // G99 (else G98, LinuxCNC's default)
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
  std::vector<Call> calls_;
  std::vector<Repeat> repeats_;
  double value_ = 0;
  double value_returned_ = 0;
  std::size_t executed_ = 0;
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
