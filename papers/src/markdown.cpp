// The report text of the reproductions: numbers as the paper prints them, the tables of
// figures, and the section on the limits of the planned profiles.

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "blendbench/report/output.hpp"
#include "papers_internal.hpp"

namespace blendbench::papers_detail {
namespace {

// Decimals that show a number printed with step `step` (0.001 -> 3).
int decimals_of(double step) {
  if (!(step > 0)) return 4;
  return std::max(0, static_cast<int>(std::lround(-std::log10(step))));
}

}  // namespace

// Fixed-point text with `decimals` digits.
std::string fixed(double value, int decimals) { return std::isfinite(value) ? format_fixed(value, decimals) : "—"; }

std::string percent(double ratio) { return std::isfinite(ratio) ? fixed(100.0 * ratio, 1) + " %" : "—"; }

// "more" when ours > paper, else "less" (words given by the caller).
std::string more_or_less(double ours, double paper, const char* more, const char* less) {
  return ours > paper ? more : less;
}

std::string signed_percent(double ratio) {
  if (!std::isfinite(ratio)) return "—";
  const std::string text = percent(ratio);
  if (text == "0.0 %" || text == "-0.0 %") return "0.0 %";
  return (ratio > 0 ? "+" : "") + text;
}

namespace {

// A number as the paper prints it.
std::string paper_text(const Figure& f) {
  if (!std::isfinite(f.paper)) return "—";
  return f.printed_step > 0 ? fixed(f.paper, decimals_of(f.printed_step)) : format_value(f.paper, 4);
}

// Ours with two digits more than the paper prints (counts as integers).
std::string ours_text(const Figure& f) {
  if (f.printed_step >= 1) return fixed(f.ours, 0);
  return f.printed_step > 0 ? fixed(f.ours, decimals_of(f.printed_step) + 2) : format_value(f.ours, 4);
}

}  // namespace

std::string table_markdown(const FigureTable& t) {
  std::string out = "## " + t.title + "\n\n";
  out += "| quantity | paper | ours | relative difference | rounds to the paper's digits |\n";
  out += "|---|---:|---:|---:|:---:|\n";
  for (const Figure& f : t.rows) {
    const bool printed = f.printed_step > 0 && std::isfinite(f.paper);
    const std::string agrees = printed ? (f.within_print_rounding() ? "yes" : "no") : "—";
    out += "| " + f.label + " | " + paper_text(f) + " | " + ours_text(f) + " | " + signed_percent(f.relative_difference()) +
           " | " + agrees + " |\n";
  }
  out += "\n";
  for (const std::string& note : t.notes) out += note + "\n\n";
  return out;
}

namespace {

std::string margins_markdown(const std::vector<PlannedRun>& runs) {
  std::string out =
      "| run | cycle time (s) | optimal planner (s) | bound without jerk (s) | fillets | v / v_lim | a_t / a | j_t / j | "
      "κv² / a | eq. 24 jerk / j | axis a / a | axis j / j (at t; time above 1) |\n"
      "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const PlannedRun& r : runs) {
    const ProfileMargins& m = r.margins;
    out += "| " + r.name + " | " + fixed(r.timing.cycle_time, 4) + " | " + fixed(r.optimal.cycle_time, 4) + " | " +
           fixed(r.timing.bound_cycle_time, 4) + " | " + std::to_string(r.fillets) + " | " +
           fixed(m.velocity, 6) + " | " + fixed(m.tangential_acceleration, 6) + " | " + fixed(m.tangential_jerk, 6) +
           " | " + fixed(m.normal_acceleration, 6) + " | " + fixed(m.eq24_jerk, 6) + " | " +
           fixed(m.axis_acceleration, 3) + " | " + fixed(m.axis_jerk, 3) + " (" + fixed(m.axis_jerk_time, 3) +
           " s; " + fixed(m.axis_jerk_over_time, 3) + " s) |\n";
  }
  return out;
}

std::string runs_markdown(const std::vector<PlannedRun>& runs) {
  std::string out;
  for (const PlannedRun& r : runs) out += "- `" + r.name + "`: " + r.description + "\n";
  return out;
}

// The largest path-level ratio of a profile (the terms the planners guarantee).
double path_level_of(const ProfileMargins& m) {
  return std::max({m.velocity, m.tangential_acceleration, m.tangential_jerk, m.normal_acceleration, m.eq24_jerk});
}

std::string markdown_margins_section(const std::vector<PlannedRun>& runs) {
  double path_level = 0;
  double optimal_path_level = 0;
  for (const PlannedRun& r : runs) optimal_path_level = std::max(optimal_path_level, path_level_of(r.optimal_margins));
  double axis_a = 0;
  const PlannedRun* worst_axis_jerk = nullptr;
  for (const PlannedRun& r : runs) {
    const ProfileMargins& m = r.margins;
    path_level = std::max({path_level, m.velocity, m.tangential_acceleration, m.tangential_jerk, m.normal_acceleration,
                           m.eq24_jerk});
    axis_a = std::max(axis_a, m.axis_acceleration);
    if (worst_axis_jerk == nullptr || m.axis_jerk > worst_axis_jerk->margins.axis_jerk) worst_axis_jerk = &r;
  }
  std::string out = "## Limits on the planned profiles\n\n";
  out +=
      "Every profile above was sampled at the 1 ms servo period and checked against its path (`profile_margins`, "
      "planner/timing/src/profile_margins.cpp). The cycle time and the columns after the fillets are seed 004's "
      "planner's; the optimal planner's time of the same path is beside it, and the bound is the least time of the "
      "path under the same limits without the jerk limit (`Timing::bound_cycle_time`), which neither can beat. "
      "Each ratio column is the largest ratio of a quantity to its limit over all samples (≤ 1: "
      "within the limit). The path-level terms are those the planner guarantees: v against v_lim(s) (programmed feed "
      "and 004 eq. 25-27 at the sample's curvature and sharpness), tangential acceleration and jerk, normal "
      "acceleration κv², and eq. 24's constant-speed axis-jerk bound √(c² + κ⁴)·v³. The axis columns are what one "
      "machine axis (x, y or z of the program frame) sees: centred second and third differences of the sampled "
      "positions.\n\n";
  out += margins_markdown(runs) + "\n";
  out += "Largest path-level ratio over all runs: " + fixed(path_level, 9) + " (" +
         (path_level <= 1 + 1e-9 ? "no path-level limit is exceeded" : "A PATH-LEVEL LIMIT IS EXCEEDED") +
         "); over the optimal planner's profiles: " + fixed(optimal_path_level, 9) + " (" +
         (optimal_path_level <= 1 + 1e-9 ? "none exceeded either" : "A PATH-LEVEL LIMIT IS EXCEEDED") + ").";
  const double axis_j = worst_axis_jerk != nullptr ? worst_axis_jerk->margins.axis_jerk : 0.0;
  if (axis_a > 1 + 1e-9 || axis_j > 1 + 1e-9) {
    out +=
        " **The axis columns exceed 1** (largest: acceleration " + fixed(axis_a, 3) + ", jerk " + fixed(axis_j, 3) +
        " in `" + worst_axis_jerk->name + "` at t = " + fixed(worst_axis_jerk->margins.axis_jerk_time, 3) +
        " s, s = " + fixed(worst_axis_jerk->margins.axis_jerk_s / kMm, 2) +
        " mm). The planner bounds the tangential and normal parts separately (the path-limits model and 004 eq. 23-24, "
        "which assume a constant path speed), while an axis sees their sum: on a curve the path jerk is "
        "(j_t − κ²v³)·T + (3κ·v·a_t + κ'·v³)·N, so wherever the speed changes on a curve (an arc or a fillet; in "
        "Listing 1, speeding up from rest on the first arc and braking on the last) the term 3κ·v·a_t adds to j_t, and at a junction slow-down the direction "
        "change within one servo period adds to both. A planner that must hold per-axis jerk would have to share the "
        "limit between these terms; this one does not, and neither do the sources' formulas.";
  } else {
    out += " The axis columns are within the limits as well.";
  }
  return out + "\n\n";
}

}  // namespace

std::string markdown_runs(const std::vector<PlannedRun>& runs) {
  return markdown_margins_section(runs) + "## The runs\n\n" + runs_markdown(runs) + "\n";
}

}  // namespace blendbench::papers_detail
