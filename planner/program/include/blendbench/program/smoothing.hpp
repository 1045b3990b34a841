#pragma once
// Smoothing of CAM point streams before corner blending (docs/smoothing.md).
//
// CAM systems write curves as runs of tiny lines. Blending each vertex on its own gives a fillet
// whose curvature rises and falls within a fraction of a line, and the jerk limit then caps the
// speed at every vertex. Smoothing replaces such a run, a *stream*, by one curvature-continuous
// (G2) curve through or near its points; the corners around it keep the variant's method.
//
//   - which moves are a stream: runs of lines shorter than `stream_length`, each vertex turning
//     by less than `stream_turn`, sharing limits and buffer mode and setting no orientation, at
//     least kMinStreamLines long (find_streams); for g2_fit, the turn at a vertex is also taken
//     between the directions over two tolerances of the lines each side, so a cusp drawn with
//     many tiny lines is a corner too;
//   - `clothoid_points` (seed 002, Makino, section 6 and Fig. 11): clothoid pairs through every
//     point, curvature zero at each, points added so that no pair turns by more than `max_turn`
//     (clothoid_points.hpp);
//   - `g2_fit`: a quintic spline within `tolerance` of every point and line of the stream, both
//     ways, with the least integral of |d^3p/ds^3|^2 the tolerance allows (g2_fit.hpp).
//
// Where a stream meets the moves before and after it, the first half of its first line and the
// second half of its last line stay lines: the corner there is blended by the variant's method
// as any other, and the curve leaves and joins those half lines tangentially at zero curvature,
// so the path is G2 across them. A stream that is the whole program and ends where it starts is
// closed: its curve starts and ends at the program's start point, G2 across it.

#include <cstddef>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "blendbench/core/input_error.hpp"
#include "blendbench/core/status.hpp"
#include "blendbench/geometry/segment.hpp"

namespace blendbench {

struct Program;

enum class SmoothingMethod { kNone, kClothoidPoints, kG2Fit };

std::string_view to_string(SmoothingMethod method);  // "none", "clothoid_points", "g2_fit"
// The name as used in files and flags (case-insensitive); nullopt when unknown.
std::optional<SmoothingMethod> smoothing_method_from_string(std::string_view name);

// Defaults, and why.
// g2_fit's tolerance: 0.02 mm, the chord tolerance CAM systems commonly write finishing paths
// at, so the smoothed path stays as close to the part as the lines themselves are.
inline constexpr double kDefaultSmoothingTolerance = 0.02e-3;  // m
// clothoid_points' largest turn per clothoid pair: seed 002 Fig. 11's 45 deg.
inline constexpr double kDefaultSmoothingMaxTurn = std::numbers::pi / 4;  // rad
// A stream's lines are shorter than 1 mm: a curve of radius up to 12.5 mm written at a chord
// tolerance of 0.01 mm comes as lines of at most sqrt(8 R e) = 1 mm; a longer line is more
// likely a straight the programmer meant.
inline constexpr double kDefaultStreamLength = 1e-3;  // m
// A vertex of a stream turns by less than 30 deg: lines of length l on a curve of radius R turn
// by l / R at each vertex, so 30 deg admits curves down to twice the line length in radius; a
// sharper turn is a corner the programmer meant, blended by the variant's method.
inline constexpr double kDefaultStreamTurn = std::numbers::pi / 6;  // rad
// The fewest lines a stream has: two lines are one corner, for the corner methods.
inline constexpr std::size_t kMinStreamLines = 3;

// What the smoothing stage does (a program default, set per variant by the scenario).
struct Smoothing {
  SmoothingMethod method = SmoothingMethod::kNone;
  double tolerance = kDefaultSmoothingTolerance;  // m, g2_fit: the largest distance, both ways
  double max_turn = kDefaultSmoothingMaxTurn;     // rad, clothoid_points: the largest turn of a clothoid pair
  double stream_length = kDefaultStreamLength;    // m: a stream's lines are shorter than this
  double stream_turn = kDefaultStreamTurn;        // rad: a stream's vertices turn by less than this
  SourceRef where;                                // where it was set, for errors
};

// Checks a smoothing spec: tolerance, stream_length > 0 and finite; max_turn and stream_turn in
// (0, pi). Throws InputError at `where` naming the field (smoothing.tolerance, ...).
void validate(const Smoothing& smoothing);

// A run of moves `first`..`last` (inclusive) of a program that is a stream.
struct StreamRun {
  std::size_t first = 0;
  std::size_t last = 0;
  // the run is the whole program and ends where it starts (within the program's join tolerance),
  // turning by less than stream_turn there
  bool closed = false;
};

// The streams of `program` under `smoothing`, in order, disjoint (the method matters only for
// g2_fit's windowed turn).
std::vector<StreamRun> find_streams(const Program& program, const Smoothing& smoothing);

// A smoothing fit of one stream: G2 pieces from its start to its end (each piece's start joins
// the previous piece's end, tangent and curvature continuous), the stream's segment (index into
// its points) each piece starts on, and the arc-length span of the points' polyline each piece
// corresponds to (for measuring the distance between the two, polyline_distance.hpp).
struct CurveFit {
  Outcome outcome;
  std::vector<Segment> pieces;
  std::vector<std::size_t> piece_segment;
  std::vector<double> span_begin, span_end;  // m along the polyline of the points
  int points_added = 0;  // clothoid_points: points added (seed 002 Fig. 11's double circles)
};

// How a fit starts and ends. A tangent given: the curve leaves the first point (reaches the last)
// along it, unit, at zero curvature, joining a line G2. None: in the direction the points give
// (clothoid_points) or any (g2_fit), at rest (the program's start or end). Closed: the points
// end where they start and the curve is G2 across that point.
struct CurveEnds {
  std::optional<Vec3> start_tangent;
  std::optional<Vec3> end_tangent;
  bool closed = false;
};

// One smoothed stream of a program.
struct SmoothedRun {
  StreamRun run;
  // the curve starts at the middle of move run.first, whose first half stays a line (a move
  // before the stream); likewise it ends at the middle of move run.last
  bool start_anchored = false;
  bool end_anchored = false;
  std::vector<Segment> curve;
  std::vector<std::size_t> piece_move;  // per piece of `curve`: the program's move its start lies on
  double distance = 0;                  // m: the measured Hausdorff distance to the run's lines (an upper bound)
  int points = 0;                       // the programmed points of the run (its lines + 1)
};

// What smoothing did to a program, for the plan summary (plan.smoothing).
struct SmoothingReport {
  SmoothingMethod method = SmoothingMethod::kNone;
  double tolerance = 0;     // m: g2_fit's tolerance; 0 for clothoid_points and none
  double max_turn = 0;      // rad: clothoid_points' largest turn per pair; 0 otherwise
  int runs = 0;             // streams smoothed
  int points = 0;           // programmed points in them
  int pieces = 0;           // curve pieces that replaced them
  int points_added = 0;     // clothoid_points: points added
  double max_distance = 0;  // m: the largest measured Hausdorff distance, both ways (an upper bound)
  double wall_time = 0;     // s spent finding and fitting the streams (0 without smoothing)
  std::vector<std::string> notes;  // streams left as lines, and why
};

struct SmoothedProgram {
  std::vector<SmoothedRun> runs;
  SmoothingReport report;
};

// Finds the streams of `program` (program.smoothing) and fits each. A stream the method cannot
// fit (g2_fit out of tolerance, a degenerate biarc) is left as lines, with a note naming its
// moves and why. Empty runs for method none. The program must be valid (validate).
SmoothedProgram smooth_streams(const Program& program);

}  // namespace blendbench
