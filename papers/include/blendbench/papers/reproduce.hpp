#pragma once
// The source papers' published numbers reproduced (results/papers/): each reproduction
// computes our figures in-process next to the paper's, and can write them as a Markdown report
// with the CSV/JSON (and PNG) it used. The numbers come from the planner as it is (blend(),
// plan_timing()); the only inputs read are the repository's part program
// (scenarios/parts/listing1.ngc) and scenario (scenarios/papers/000_section_3_2.yaml).
//
// Units: the figures are in the paper's units (mm, 1/mm, 1/mm^2, mm/min, s) as their labels say;
// paths and timings inside PlannedRun are SI like the rest of the planner.

#include <cmath>
#include <filesystem>
#include <iosfwd>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "blendbench/program/path.hpp"
#include "blendbench/program/program.hpp"
#include "blendbench/timing/profile_margins.hpp"
#include "blendbench/timing/timing.hpp"

namespace blendbench {

// One published number next to ours. `paper` is NaN where the paper gives no value.
struct Figure {
  std::string key;    // short identifier for tests and results.json, e.g. "S1S2.sharpness"
  std::string label;  // for the report, with the unit, e.g. "S1S2 sharpness c (1/mm^2)"
  double paper = std::numeric_limits<double>::quiet_NaN();
  double ours = 0;
  // The unit of the paper's last printed digit (0.001 for "0.012"); 0 = not stated.
  double printed_step = 0;

  // (ours - paper) / |paper|; NaN when the paper gives no value.
  [[nodiscard]] double relative_difference() const { return (ours - paper) / std::abs(paper); }
  // Whether ours rounds to the paper's printed value (|ours - paper| <= printed_step / 2, with a
  // 1e-9 relative allowance for the decimal representation). False when printed_step is 0.
  [[nodiscard]] bool within_print_rounding() const;
};

// A table of figures with the notes that explain it.
struct FigureTable {
  std::string title;
  std::vector<Figure> rows;
  std::vector<std::string> notes;  // Markdown paragraphs

  // The row with this key; throws std::out_of_range naming the key when absent.
  [[nodiscard]] const Figure& at(std::string_view key) const;
};

// One planned program: what it is, its path, its timings and the checks of their profiles.
// `timing` is seed 004's planner (TimingOptions::Algorithm::kSeed004), the one the papers'
// figures are compared with; `optimal` is the same path under the same options planned by the
// optimal (minimum-time, jerk-limited) planner, shown beside it (issue 43).
struct PlannedRun {
  std::string name;         // file-name friendly, e.g. "biclothoid_0.1mm"
  std::string description;  // one line for the report
  Program program;
  Path path;
  Timing timing;
  ProfileMargins margins;  // profile_margins (timing/profile_margins.hpp) of `timing`
  Timing optimal;
  ProfileMargins optimal_margins;  // of `optimal`
  int fillets = 0;  // corners replaced by a transition curve of non-zero length
};

// Plans `program` (blend, then plan_timing with dt = 1 ms, the path limits mode and the given
// baseline, once with seed 004's planner and once with the optimal one) and checks both profiles.
// Throws std::runtime_error when the planner reports a failure (the reproductions expect none).
PlannedRun plan_run(std::string name, std::string description, Program program,
                    TimingOptions::Baseline baseline = TimingOptions::Baseline::kNone);

// seed 004 (Shahzadeh et al. 2018): section 5's worked example, tables 1-3 and the unsmoothed cycle
// times of section 3, on Listing 1 with a_lim 9800 mm/s^2, j_lim 200000 mm/s^3, F10000.
struct Paper004 {
  FigureTable section5;  // keys c1, s1, s2, x_end, y_end
  FigureTable table1;    // keys S1S2|S3S4|S5S6 . sharpness|kappa_max|feed_max
  FigureTable table2;    // keys biclothoid|bezier . length|kappa_max|sharpness_max|feed_max, time_ratio
  // keys biclothoid_0.1|biclothoid_0.01|bezier_0.1|bezier_0.01 . fillets|cycle_time|cycle_time_optimal,
  // chords_0.1, chords_0.01
  FigureTable table3;
  // keys unlimited, junction_slowdown, junction_slowdown_optimal, exact_stop, exact_stop_optimal,
  // ratio, ratio_optimal
  FigureTable section3;
  double table2_deviation = 0;         // m: the biclothoid's deviation on the 150 degree corner
  double table2_bezier_deviation = 0;  // m: the Bezier's, with TP chosen to match
  double table2_bezier_tp = 0;         // m
  Path table2_biclothoid;              // the two blended corners of table 2
  Path table2_bezier;
  std::vector<PlannedRun> runs;        // every profile behind table 3 and section 3
};
Paper004 reproduce_004();

// seed 000 (Bezier transitions, 2017) section 3.2: a program of lines and circles at 50 mm/s,
// 100 mm/s^2, 200 mm/s^3 with TP 5 mm, with and without transitions (the program is ours: the
// paper shows it only in a figure; scenarios/papers/000_section_3_2.yaml).
struct Paper000 {
  // keys with, with_optimal, without, without_optimal, ratio, ratio_optimal, with_tangential,
  // without_tangential, ratio_tangential, with_tp20, with_tp20_optimal
  FigureTable section3_2;
  FigureTable corners;     // per corner (ours only): corner<k>.length|deviation|kappa_max|sharpness_max|feed_max|...
  std::vector<PlannedRun> runs;  // bezier_tp5, exact_stop, bezier_tp20
};
Paper000 reproduce_000();

// The Markdown reports (README.md of results/papers/<paper>/).
std::string markdown_004(const Paper004& result);
std::string markdown_000(const Paper000& result);

// `blendbench reproduce NAME [--out DIR]`: NAME is "004", "000" or "all"; each paper's report
// and data go to DIR/<paper>/ (README.md, results.json, CSV profiles and, with `plots`, PNG
// figures drawn by papers/scripts/plot_papers.py). Progress lines go to `log`. Throws InputError
// (field "name") for an unknown NAME. Returns 0, or 1 when a plot script failed.
int reproduce(const std::string& name, const std::filesystem::path& out_dir, bool plots, std::ostream& log);

}  // namespace blendbench
