#pragma once
// A reader for the RS274/NGC subset of G-code that describes a tool path of lines and arcs, as
// LinuxCNC reads it. It turns a part program's text into a Program in metres, in machine
// coordinates (the programmed points with the program's offsets applied; with none set, the
// program's own frame); the planner never opens files, so the caller passes the text and a file
// name that only appears in messages. docs/gcode.md is the user's reference.
//
// Path words (read and turned into moves):
//   G0 G1 G2 G3 (G2/G3 by I/J/K centre or by R, helical when the axis normal to the plane moves,
//   full circles by I/J/K with no end point or end = start, P = number of turns, at most
//   kMaxArcTurns = 100), G17 G18 G19,
//   G20 G21, G90 G91, G90.1 G91.1, G80 (cancels the motion mode; beside another motion code on
//   its line it is ignored, as LinuxCNC's read_g does), F (units per minute G94, or per
//   revolution G95), G61 G61.1 (exact stop), G64 [P tol] [Q tol], G4 P (dwell), X Y Z, @ ^
//   (polar), N, M2 M30, G7 G8 (lathe diameter and radius mode), G33 K (spindle-synchronised
//   line), G33.1 K (rigid tapping), canned cycles G73 G81 G82 G83 G84 G85 G86 G89 with R Q P L and
//   G98/G99 (see "Spindle, lathe and canned cycles" below), comments ( ) and ;, '/' block delete,
//   '%' tape markers. Words are case-insensitive; spaces and tabs are allowed anywhere outside
//   comments (RS274/NGC); numbers look like 1, -10., .5, +3. A B C as tool angles, only when
//   GcodeOptions::angles maps them (see "Tool angles" below).
// Offsets and stored positions (LinuxCNC's G-code manual; see "Offsets" below):
//   G54-G59.3 (switchable at any line), G10 L2/L20 P0-9 [R] (a system's offsets, rotation about
//   Z), G10 L1 P (a tool table entry), G52, G92, G92.1, G92.2, G92.3, G43 [H], G43.1, G43.2, G49
//   (tool length offsets), G53 (one move in machine coordinates), G28/G30 (through the point of
//   the axis words to the stored position), G28.1/G30.1 (store the current position).
// Parameters, expressions and control flow (see "Parameters and O-words" below):
//   #1-#5601, #<name>, #<_global>, ##n, #[expr], assignments "#n = value"; a word's value may be
//   a number, a parameter, [expression] or a function: binary ** * / MOD + - EQ NE GT GE LT LE AND
//   OR XOR (LinuxCNC's precedence), ABS ACOS ASIN ATAN[y]/[x] COS EXP FIX FUP LN ROUND SIN SQRT
//   TAN (degrees), EXISTS[#<name>]; O-words sub/endsub/call with arguments [..] (#1-#30), return
//   [value] (#<_value>), if/elseif/else/endif, while/endwhile, do/while, repeat/endrepeat,
//   break, continue.
// Words that do not change the path are accepted and listed in GcodeResult::ignored:
//   S (also the speed G33, G33.1 and G95 read), T (selects the tool M6 loads), H (read by G43), D,
//   M0 M1 M3 M4 M5 M6 M7 M8 M9 M48-M53 (M50-M53 with P), G40, G94, G95, G96, G97.
// Everything else stops with InputError(file, line, column, word, message): cutter radius
// compensation (G41 G42), canned cycles G87 G88 and lathe cycles (G70-G72, G74, G76), splines
// (G5), probing, inverse-time feed (G93), a called subroutine that no file defines, M98/M99,
// G10 L other than 1, 2, 20,
// axes A B C (unless mapped to tool angles) and U V W, unknown letters, codes and functions,
// two words of one modal group on a line, a word given twice, a word on a line with no command
// that uses it, axis words before any G0-G3 (LinuxCNC starts in G80), an O-word structure that
// does not close or closes another label, a named parameter read before it is set, a division
// by zero or a function outside its domain. Never a silently different path.
//
// Decisions where RS274/NGC leaves room or this reader departs from LinuxCNC:
// - Unicode minus (U+2212, as in text extracted from PDFs, e.g. Listing 1 of seed 004) is read as
//   '-', and each line where it happens is noted in `ignored`.
// - '/' as the first character of a line deletes the block (LinuxCNC with the block-delete
//   switch on): the line is skipped and noted.
// - G4 dwell, M0/M1 (pause) and M6 (tool change) make the machine stop: the move before them
//   gets transition method none (an exact stop at that point), noted in `ignored`.
// - G61 and G61.1 give transition method none on the following moves (an exact stop at every
//   junction, the "without transitions" baseline), even where LinuxCNC's G61 would pass a
//   tangent junction without stopping.
// - G64 P tol gives Transition{options.tolerance_method, tol} (other fields from
//   options.blending). For clothoid and biclothoid the parameter is the maximum deviation, as
//   in LinuxCNC. For arc and bezier it is the corner distance / TP (how far from the corner the
//   transition starts), which bounds the deviation at line-line corners: an arc fillet between
//   lines turning by delta deviates by d tan(delta/4) < d, and a Bezier whose control points lie
//   in the triangle of the two transition points and the corner stays inside it, within d of
//   the lines. G64 P0 is G64 without P. Q (LinuxCNC's naive CAM tolerance) gives
//   Transition::merge_tolerance: runs of collinear lines within it are merged before blending.
// - Arc end point off the circle (I/J/K format): with r1, r2 the distances from the centre to
//   the start and to the end in the plane, and tol = 0.002 sqrt(2) in (G20) / 0.02 sqrt(2) mm
//   (G21) (LinuxCNC's CENTER_ARC_RADIUS_TOLERANCE defaults, interp_internal.hh; its INI file may
//   tighten them), it is an error when |r1 - r2| > 100 tol, or when |r1 - r2| > tol and
//   |r1 - r2| / max(r1, r2) > 0.001 together (interp_arc.cc, arc_data_ijk, in the versions the
//   trajectory-planner tests were written for, and the rule LinuxCNC's G-code manual states in
//   "Center Format Arcs" with its older tolerance; some versions of interp_arc.cc refuse beyond
//   either tolerance alone); and when r1 or r2 is below 0.00005 in / 0.00127 mm (zero radius).
//   Within it LinuxCNC cuts a spiral about the programmed centre, the radius (and a helix's
//   height) linear in the angle. The path follows that spiral within
//   GcodeOptions::spiral_tolerance (kSpiralTolerance, 1 um): the circle through both end points
//   centred on their bisector where it is that close (a rounded end point; noted), else a chain
//   of tangent arcs (arcs_along_spiral: biarcs through points of the spiral, G1 at every joint;
//   noted with their count and distance), at most kMaxSpiralArcs; a spiral no chain follows
//   that closely (a helix whose height departs from one slope) is refused, never cut
//   differently. Every move of the chain carries the line's name and position.
// - R format (LinuxCNC arc_data_r): R > 0 the arc of at most 180 degrees, R < 0 the longer one;
//   an end point equal to the start is an error; half the chord longer than |R| by more than
//   0.00005 in / 0.00127 mm is an error, within that the arc is a semicircle on the chord.
// - F is read in the units in force after this line's G20/G21; a units change does not convert a
//   feed set earlier (the feed is kept in m/s). F must be positive.
// - Zero-length moves (shorter than kZeroLengthMove) are dropped and noted. The interpreter's
//   position still becomes the programmed end (so G91 stays exact); the next move starts where
//   the last kept move ended, so the path has no gap.
// - M2/M30 or a closing '%' ends the program; later lines are not read and are noted.
// - Work is bounded before it is done: at most kMaxMoves (10^6) moves, refused at the move past
//   it; the text is read line by line.
//
// Tool angles (GcodeOptions::angles set; robot G-code names the tool's orientation by three
// Euler angles where a CNC names rotary axes):
// - A, B and C are angles in degrees (G20/G21 do not change them), each naming the roll, pitch
//   or yaw of the mapping (a permutation). The tool orientation is R = Rz(yaw) Ry(pitch) Rx(roll):
//   roll about x, then pitch about y, then yaw about z, all fixed axes of the program frame (the
//   rpy_deg of a scenario's move orientation, as URDF reads rpy). KUKA's A, B, C (A about z,
//   B about the new y, C about the newest x: R = Rz(A) Ry(B) Rx(C)) is {A: yaw, B: pitch,
//   C: roll}; angles named after the axes they turn about, as RS274/NGC names its rotary axes
//   (A about x, B about y, C about z), is {A: roll, B: pitch, C: yaw}.
// - They are modal like X, Y, Z: an angle not written keeps its value; under G91 a word adds its
//   degrees to its angle (the three angles are the state, so an increment of one Euler angle
//   is exact). The angles start unset: the first line with an angle word must give all three,
//   under G90; before it, moves carry no orientation target (the tool keeps its start
//   orientation).
// - A move of a line with angle words gets Move::orientation = R (program frame), reached with
//   the move's end point and turned to the shorter way round (a move's orientation in a
//   scenario): A going from 0 to 270 turns the tool by -90 degrees. Arcs (G2/G3) take angles as
//   lines do. Moves of lines without angle words carry no target (they keep the orientation).
// - The orientation is interpolated along the path, so the tool cannot turn in place: a line
//   whose move is zero-length (dropped) while its angles turn the tool away from where the path
//   has it (options.start_orientation before any target) is an error, as are angle words with
//   no motion mode, and an angle beyond +-kMaxToolAngleDeg.

// Spindle, lathe and canned cycles (LinuxCNC's G-code manual and interp_cycles.cc):
// - M3/M4 start the spindle at S (rev/min; under G96 S is a surface speed), M5 stops it. G95
//   reads F per revolution: the feed is F S per minute. G33 moves along its line by K per
//   revolution (at S K per minute); G33.1 taps to its end point and comes back along the same
//   line (an exact stop at the bottom, where the spindle reverses). These need the spindle
//   turning at S > 0 and are refused under G96 (the speed would change with the radius). The
//   synchronisation itself is not modelled: the planner holds that speed as the feed.
// - G7: X words (of every command) are diameters, so the tool goes to half of them; G8 radii
//   (the default). I stays a radius offset.
// - Polar coordinates, G17 only: '@' the distance from the program origin, '^' the angle in
//   degrees; under G90 the one not written keeps the current point's, under G91 they add to it;
//   refused with X or Y, at the origin where the angle is undefined, with G53, and in cycles.
// - Canned cycles G73 (chip break), G81 (drill), G82 (dwell), G83 (peck), G84 (tap; the spindle
//   turning), G85 (feed out), G86 (dwell, rapid out; the spindle turning), G89 (dwell, feed out),
//   in the plane in force (the hole along its normal: Z for G17, Y for G18, X for G19): below the
//   retract plane R a rapid straight up to it first; a rapid to the position at the current
//   level (first repeat) or the clearance level, down to R, the cycle's own moves, out to the
//   clearance level: R with G99, the level the run of cycles started at with G98 (also when
//   neither is given, noted where it matters). G73/G83 peck by Q and come back down 0.010 in
//   (0.254 mm) above the last depth. G91: the position and R are increments of the current
//   point and the initial level, the bottom of R; L repeats. R, the bottom, P and Q may be left
//   out on the lines that continue the same cycle. Every move of a cycle stops at its end (the
//   cycle runs in exact path mode); dwells are noted.

// Offsets (LinuxCNC's "Coordinate Systems" and emccanon.cc):
// - A programmed point p (after units) is reached at R p + O + G + T: O and R the offset and the
//   rotation about Z of the coordinate system in use (G54 = P1 ... G59.3 = P9), G the G92/G52
//   offset, T the tool length offset. The path is in these machine coordinates. Changing an
//   offset or the system never moves the machine: the next move's absent axes keep their
//   machine position (their programmed coordinates change). LinuxCNC's offsets come from the
//   machine's parameter file; here every system's offsets are zero until the program sets them
//   (G10, or the parameters #5221-#5390), and selecting a system it never set is noted.
// - G10 L2 sets a system's offsets (absent axes keep theirs) and R its rotation in degrees; G91
//   does not apply. G10 L20 sets them so that the current point gets the given coordinates in
//   that system. P0 is the system in use.
// - G92 sets G so that the current point gets the given coordinates; G52 sets G to the given
//   values (absent axes keep theirs); both store G in #5211-#5213. G92.1 clears G and the
//   parameters, G92.2 clears G and keeps the parameters, G92.3 restores G from them.
// - Tool length offsets: the tool table is GcodeOptions::tool_offsets (empty by default; G10 L1
//   P<tool> X Y Z writes an entry). G43 applies the entry of H (or of the tool M6 loaded, T
//   selecting it); a tool not in the table gets zero, noted. G43.1 takes the offset from its
//   axis words, G43.2 adds the entry of H and/or its axis words; G49 removes it.
// - G53 with G0 or G1 (G90 only): the line's axis words are machine coordinates, for this move.
// - G28/G30 [axes]: a rapid move to the point of the axis words (if any), then to the stored
//   position (#5161-#5163 / #5181-#5183, machine coordinates, zero until G28.1/G30.1 or the
//   parameters set them) of those axes, or of all without axis words.
// - A, B, C offsets (G92 A..., G10 L2 A...) are refused: they are not positions here.
//
// Parameters and O-words (LinuxCNC's "Overview" and "O Codes"):
// - Values on a line are read with the parameters as they were before the line; its
//   assignments then take effect (the last one of a parameter wins), and then its words run.
// - #1-#30 and names without a leading '_' are local to a subroutine call (a call starts them at
//   its arguments and zero, and they are restored on return); numbered parameters from #31 and
//   names with '_' are global. An unset numbered parameter is 0; reading an unset name is an
//   error. Names ignore case and blanks. Predefined, read-only: #<_x> #<_y> #<_z> (position,
//   program coordinates), #<_metric> #<_imperial> #<_absolute> #<_incremental>
//   #<_coord_system> #<_current_tool> #<_selected_tool> #<_feed> #<_motion_mode> #<_plane>
//   #<_value> #<_value_returned> #<_task> (1), #5210 #5220 #5400-#5409 #5420-#5428; the
//   offsets' parameters (#5161-#5163, #5181-#5183, #5211-#5213, #5221-#5390) are live.
// - EQ and NE compare within 1e-6 (LinuxCNC's TOLERANCE_EQUAL); a negative remainder of MOD
//   gets |divisor| added (LinuxCNC); ROUND rounds halves
//   away from zero; a negative number to a non-integer power is an error; ** groups from the
//   left like every other operator, as in LinuxCNC.
// - The O-word structure is checked before the program runs (gcode_flow): every sub, while, do,
//   repeat and if closes with its label, properly nested; subroutines are not nested; break and
//   continue name an enclosing loop, return the enclosing subroutine. A definition met in the
//   flow is skipped; a call may come before or after it.
// - Subroutine files (LinuxCNC's "Calling Files"): a call finds its subroutine in the file that
//   calls, else in the main program, else in the file <name>.ngc that
//   GcodeOptions::find_subroutine finds (only named labels; the name in lower case, letters,
//   digits, '-' and '_', so a label never names a path elsewhere). A file is read once and its
//   O-word structure checked as the program's; only the subroutine called runs. Its moves and
//   errors name the file and its lines; an error ends with "(in o<name> called from line N of
//   part.ngc)". Without find_subroutine (parse_gcode of text alone) such a call is refused.
// - The work is bounded: GcodeOptions::max_lines lines executed (kMaxExecutedLines; each loop
//   pass counts), kMaxCallDepth nested calls, 64 nested brackets, parameter
//   references and functions in one value, max_moves moves; each stops with InputError at the
//   line reached. An error inside a subroutine names the body's line and ends its message with
//   "(in o<name> called from line N, ...)".
// - The notes of a line (ignored words, dropped moves) are listed once, not once per pass.
//
#include <array>
#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "blendbench/program/program.hpp"

namespace blendbench {

// A move shorter than this (m) is dropped (see above); far below any machine's resolution.
inline constexpr double kZeroLengthMove = 1e-9;

// The largest tool angle (degrees) a program may reach: 100 turns, far beyond any wrist, so that
// G91 increments cannot grow without bound.
inline constexpr double kMaxToolAngleDeg = 36000;

// How closely (m) the path follows the spiral LinuxCNC cuts for a centre-format arc whose end
// point is off the circle within its tolerance (see "Arc end point off the circle"): a
// micrometre, a tenth of the 0.01 mm that CAM output is rounded to and below the contour errors
// the testbench reports, so the path is LinuxCNC's for every figure it gives.
inline constexpr double kSpiralTolerance = 1e-6;

// The most lines a program may execute (loops and calls count each pass): at about a
// microsecond a line, a program that never ends is stopped within seconds, while 10^6 moves of
// a loop-generated program (kMaxMoves) fit ten times over.
inline constexpr std::size_t kMaxExecutedLines = 10'000'000;

// The deepest subroutine calls may nest (a call that recurses without end stops here).
inline constexpr std::size_t kMaxCallDepth = 100;

// The angle of the tool orientation that a G-code angle word names (see "Tool angles").
enum class ToolAngle { kRoll, kPitch, kYaw };

// What A, B and C name, in that order; a permutation of roll, pitch and yaw.
struct GcodeAngles {
  std::array<ToolAngle, 3> abc = {ToolAngle::kRoll, ToolAngle::kPitch, ToolAngle::kYaw};
};

// A subroutine file found by name (see GcodeOptions::find_subroutine).
struct GcodeSubroutineFile {
  std::string path;  // as messages and the moves' source references name it
  std::string text;
};

// What a search for a subroutine file found: the file, or none and where it looked.
struct GcodeSubroutineLookup {
  std::optional<GcodeSubroutineFile> file;
  std::string searched;  // for the refusal when none was found, e.g. "/parts, /subs"
};

struct GcodeOptions {
  // SI limits of every move: velocity is the feed until the first F word (m/s); acceleration,
  // deceleration and jerk apply throughout. All must be positive.
  Limits limits;
  // The transition of moves in G64 mode when G64 gives no P (also the start-up mode).
  Transition blending;
  // What G64 P<tol> maps to (see the header comment for the arc/bezier mapping).
  Method tolerance_method = Method::kBiclothoid;
  BufferMode buffer = BufferMode::kBlendingLow;
  // m/s for G0 moves; 0 = limits.velocity.
  double rapid_velocity = 0;
  // m, program frame: where the tool is before the first line (RS274/NGC's current point).
  Vec3 start = Vec3::Zero();
  // A, B, C as tool angles (see above); none: they are refused like any unsupported axis.
  std::optional<GcodeAngles> angles;
  // Unit quaternion, program frame: the tool's orientation before the first line; only checks
  // that a zero-length move does not turn the tool.
  Quat start_orientation = Quat::Identity();
  // The tool table: tool number -> length offset (m; X, Y, Z) that G43 H<n> applies. Empty by
  // default: G43 of a tool not in it applies zero and notes it.
  std::map<int, Vec3> tool_offsets;
  // Where "o<name> call" finds a subroutine the program does not define: the file <name>.ngc
  // (name in lower case; letters, digits, '-', '_'). It may throw InputError (a file that cannot
  // be read). Not set: such a call is refused. load_gcode_file sets it (see program_io.hpp).
  std::function<GcodeSubroutineLookup(const std::string& name)> find_subroutine;
  // Folders load_gcode_file searches for subroutine files after the program's own folder (as
  // LinuxCNC's [RS274NGC] SUBROUTINE_PATH); parse_gcode itself does not read it.
  std::vector<std::string> subroutine_path;
  // m: how closely the path follows LinuxCNC's spiral where an arc's end point is off its circle.
  double spiral_tolerance = kSpiralTolerance;
  // Bounds on the work (InputError beyond them): moves in the program, lines executed.
  std::size_t max_moves = kMaxMoves;
  std::size_t max_lines = kMaxExecutedLines;
};

struct GcodeResult {
  Program program;  // metres and orientations in the program frame (placing it in the robot workspace is done elsewhere)
  Vec3 start = Vec3::Zero();         // m: the position before the first move
  std::vector<std::string> ignored;  // e.g. "S1000 (line 3)", "G4 P0.5 (line 9): dwell treated as an exact stop"
  // The first F word of the program: where it stands (line 0: the program has none) and the feed
  // it sets (m/s). From there on the program's F words, not options.limits.velocity, set the feed
  // of its moves (a scenario warns when it differs from defaults.velocity).
  SourceRef first_feed_where;
  double first_feed = 0;
};

// Reads a part program. Each move gets where = {file_name, line, column of its motion word or
// first axis word} and a name like "line 7 G2" or "N120 G1". Throws InputError(file_name, line,
// column, word, message) on anything it does not support (see above), on invalid options, and
// when the program has no moves.
GcodeResult parse_gcode(std::string_view text, const std::string& file_name, const GcodeOptions& options);

}  // namespace blendbench
