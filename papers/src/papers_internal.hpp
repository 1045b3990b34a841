#pragma once
// Private to papers/src (not installed): the units, run statistics and Markdown pieces that the
// reproductions share — the runs (planned_run.cpp), the papers (paper_004.cpp, paper_000.cpp),
// the report text (markdown.cpp) and the files written (reproduce.cpp).

#include <cstddef>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "blendbench/core/units.hpp"
#include "blendbench/papers/reproduce.hpp"

namespace blendbench::papers_detail {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
// Unit conversions for the paper's units.
inline constexpr double kPerMin = 60.0;      // s per min
inline constexpr double kServoPeriod = 1e-3;  // s: the planner's sample period (at most 1 ms)

// Rows of the sampled profiles written for the plots: every n-th servo sample (results/papers
// stays small).
inline constexpr int kDecimate004 = 4;
inline constexpr int kDecimate000 = 20;

Figure figure(std::string key, std::string label, double paper, double ours, double printed_step);
Transition transition(Method method, double parameter);

// Corners replaced by a transition of non-zero length, and the largest corner deviation (m).
int fillet_count(const Path& path);
double largest_deviation(const Path& path);

// The pieces of the path, or the moves of the program, as one curve for hausdorff() (closest.hpp).
std::vector<Segment> segments_of(const Path& path);
std::vector<Segment> segments_of(const Program& program);

// The rest-to-rest time (s) of one S-curve over `distance` (m) with tangential limits only: what
// a planner that ignores corners and curvature achieves on a path of that length.
double tangential_only_time(double distance, const Limits& limits);

// Over the transitions of a path: how many are limited by eq. 26 (jerk) rather than eq. 25,
// how many of those have c > kappa^2 (the sharpness dominates eq. 26), and the lowest limit.
struct FilletFeeds {
  int count = 0;
  int jerk_bound = 0;
  int sharpness_dominated = 0;
  double min_feed = std::numeric_limits<double>::infinity();  // m/s
};
FilletFeeds fillet_feeds(const Path& path);

// Corners whose transition parameter the blender shrank because a move is short.
int shrunk(const Path& path);

// Transition pieces of a run, and those whose peak velocity is bound by the programmed feed.
std::pair<int, int> fillet_pieces_at_feed(const PlannedRun& run);

// The label of a row that shows `run`'s optimal plan beside the row `label` of its seed 004 plan:
// "<label>, optimal planner", plus how many stretches between stops kept seed 004's motion.
std::string optimal_label(const std::string& label, const PlannedRun& run);

// Listing 1 (scenarios/parts/listing1.ngc) in metres, with `transition` on every move and the
// limits of the seed 004 (Shahzadeh et al.) experiments (paper_004.cpp).
Program listing1(const Transition& transition);

// Report text (markdown.cpp). Fixed-point text with `decimals` digits ("—" when not finite).
std::string fixed(double value, int decimals);
std::string percent(double ratio);         // "12.3 %"
std::string signed_percent(double ratio);  // "+12.3 %", "0.0 %"
// `more` when ours > paper, else `less`.
std::string more_or_less(double ours, double paper, const char* more, const char* less);
// A table as Markdown: the paper's numbers next to ours, then the table's notes.
std::string table_markdown(const FigureTable& t);
// The sections on the runs: the limits on their planned profiles (the margins of every run),
// then one line per run with its name and description.
std::string markdown_runs(const std::vector<PlannedRun>& runs);

}  // namespace blendbench::papers_detail
