// `blendbench reproduce`: runs the reproductions and writes each paper's report and data
// (README.md, results.json, CSV profiles, and the plots drawn by papers/scripts/plot_papers.py).

#include "blendbench/papers/reproduce.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <ostream>
#include <utility>

#include <nlohmann/json.hpp>

#include "blendbench/core/input_error.hpp"
#include "blendbench/core/interrupt.hpp"
#include "blendbench/io/data_root.hpp"
#include "blendbench/papers/paper_002.hpp"
#include "blendbench/report/json.hpp"
#include "blendbench/report/output.hpp"
#include "blendbench/report/process.hpp"
#include "blendbench/report/report.hpp"
#include "blendbench/report/run_folder.hpp"
#include "papers_internal.hpp"

namespace blendbench {
using namespace papers_detail;  // the helpers private to the reproductions
namespace {

// Runs with more corners than this list a summary instead of every corner report.
constexpr std::size_t kCornersListed = 12;

nlohmann::json table_json(const FigureTable& t) {
  nlohmann::json rows = nlohmann::json::array();
  for (const Figure& f : t.rows) {
    rows.push_back({{"key", f.key},
                    {"label", f.label},
                    {"paper", finite_or_null(f.paper)},
                    {"ours", f.ours},
                    {"relative_difference", finite_or_null(f.relative_difference())},
                    {"printed_step", f.printed_step},
                    {"within_print_rounding", f.within_print_rounding()}});
  }
  return {{"title", t.title}, {"rows", rows}};
}

// Corner reports of a run with many corners, summarised.
nlohmann::json corner_summary(const Path& path) {
  const FilletFeeds f = fillet_feeds(path);
  return {{"count", path.corners.size()},
          {"fillets", f.count},
          {"deviation_max_mm", largest_deviation(path) / kMm},
          {"feed_max_lowest_mm_per_min", f.min_feed / kMm * kPerMin},
          {"limited_by_jerk_eq26", f.jerk_bound}};
}

nlohmann::json margins_json(const ProfileMargins& m) {
  return {{"velocity", m.velocity},
          {"tangential_acceleration", m.tangential_acceleration},
          {"tangential_jerk", m.tangential_jerk},
          {"normal_acceleration", m.normal_acceleration},
          {"eq24_jerk", m.eq24_jerk},
          {"axis_acceleration", m.axis_acceleration},
          {"axis_jerk", m.axis_jerk},
          {"axis_jerk_time_s", m.axis_jerk_time},
          {"axis_jerk_s_mm", m.axis_jerk_s / kMm},
          {"axis_jerk_over_time_s", m.axis_jerk_over_time}};
}

// Per run: seed 004's plan at the top level (as before issue 43), the optimal planner's in the
// "optimal" block with the same keys, and the bound both are measured against.
nlohmann::json runs_json(const std::vector<PlannedRun>& runs) {
  nlohmann::json out = nlohmann::json::array();
  for (const PlannedRun& r : runs) {
    out.push_back({{"name", r.name},
                   {"description", r.description},
                   {"cycle_time_s", r.timing.cycle_time},
                   {"bound_cycle_time_s", r.timing.bound_cycle_time},
                   {"path_length_mm", r.path.length() / kMm},
                   {"feed_share", r.timing.feed_share},
                   {"fillets", r.fillets},
                   {"margins", margins_json(r.margins)},
                   {"optimal",
                    {{"cycle_time_s", r.optimal.cycle_time},
                     {"feed_share", r.optimal.feed_share},
                     {"seed004_stretches", r.optimal.seed004_stretches},
                     {"margins", margins_json(r.optimal_margins)}}},
                   {"corners", r.path.corners.size() <= kCornersListed ? corners_json(r.path) : corner_summary(r.path)}});
  }
  return out;
}

// "v0,v1,...\n" with 7 significant digits.
std::string csv_row(std::initializer_list<double> values) {
  std::string row;
  for (const double v : values) {
    if (!row.empty()) row += ',';
    row += format_value(v, 7);
  }
  row += '\n';
  return row;
}

// Every `decimate`-th sample of the timed profile `timing` of run `r` (and the last):
// t,s,x,y,z,v,a,j,kappa in s, mm, mm/s, mm/s^2, mm/s^3, 1/mm.
std::string profile_csv(const PlannedRun& r, const Timing& timing, int decimate) {
  std::string out = "t,s,x,y,z,v,a,j,kappa\n";
  const auto& x = timing.samples;
  for (std::size_t k = 0; k < x.size(); ++k) {
    if (k % static_cast<std::size_t>(decimate) != 0 && k + 1 != x.size()) continue;
    const TimedSample& q = x[k];
    const Vec3 p = r.path.point(q.s);
    const double kappa = r.path.curvature_vector(q.s).norm();
    out += csv_row({q.t, q.s / kMm, p.x() / kMm, p.y() / kMm, p.z() / kMm, q.v / kMm, q.a / kMm, q.j / kMm,
                    kappa * kMm});
  }
  return out;
}

// The path every `ds` m at most: s,x,y,z,kappa (mm, 1/mm), each piece sampled separately so the
// jumps of curvature at junctions show.
std::string curvature_csv(const Path& path, double ds) {
  std::string out = "s,x,y,z,kappa\n";
  for (std::size_t k = 0; k < path.pieces().size(); ++k) {
    const Segment& seg = path.pieces()[k].segment;
    const double len = length(seg);
    const int n = std::max(2, static_cast<int>(std::ceil(len / ds)));
    for (int i = 0; i <= n; ++i) {
      const double s = len * i / n;
      const Vec3 p = point(seg, s);
      out += csv_row({(path.offset(k) + s) / kMm, p.x() / kMm, p.y() / kMm, p.z() / kMm,
                      curvature_vector(seg, s).norm() * kMm});
    }
  }
  return out;
}

// Curvature and sharpness along the transition pieces of the two table 2 corners:
// fillet,s,kappa,sharpness (mm, 1/mm, 1/mm^2; s from the start of the fillet).
std::string table2_fillets_csv(const Paper004& r) {
  std::string out = "fillet,s,kappa,sharpness\n";
  constexpr int kSamples = 200;  // per piece
  for (const auto& [name, path] : {std::pair{"biclothoid", &r.table2_biclothoid}, std::pair{"bezier", &r.table2_bezier}}) {
    double offset = 0;
    for (const PathPiece& piece : path->pieces()) {
      if (piece.corner < 0) continue;
      const double len = length(piece.segment);
      for (int i = 0; i <= kSamples; ++i) {
        const double s = len * i / kSamples;
        out += std::string(name) + "," + format_value((offset + s) / kMm, 7) + "," +
               format_value(curvature_vector(piece.segment, s).norm() * kMm, 7) + "," +
               format_value(sharpness(piece.segment, s) * kMm * kMm, 7) + "\n";
      }
      offset += len;
    }
  }
  return out;
}

// Runs the plot script on `dir`; true when it succeeded.
bool plot(const std::filesystem::path& dir, const std::string& paper, std::ostream& log) {
  // an argument vector, no shell: the output folder is data, whatever characters it holds
  const ProcessResult plotted =
      run_process({"/usr/bin/python3", data_file("papers/scripts/plot_papers.py"), dir.string(), paper});
  if (!plotted.ok) log << "warning: the plot script failed (" << plotted.message << ")" << std::endl;
  return plotted.ok;
}

}  // namespace

int reproduce(const std::string& name, const std::filesystem::path& out_dir, bool plots, std::ostream& log) {
  if (name != "004" && name != "000" && name != "002" && name != "all") {
    throw InputError("", 0, 0, "name", "unknown reproduction '" + name + "' (004, 000, 002 or all)");
  }
  bool plots_ok = true;
  if (name == "004" || name == "all") {
    const Paper004 r = reproduce_004();
    // each paper's folder is staged and replaces the previous one as a whole when complete
    // (report/run_folder.hpp): killed between two files, the old README never sits beside new data
    RunFolder folder(out_dir / "004", "results.json", "--out");
    const std::filesystem::path& dir = folder.staging();
    const nlohmann::json j = {{"paper", "004"},
                              {"tables",
                               {table_json(r.section5), table_json(r.table1), table_json(r.table2), table_json(r.table3),
                                table_json(r.section3)}},
                              {"table2_deviation_mm", r.table2_deviation / kMm},
                              {"table2_bezier_deviation_mm", r.table2_bezier_deviation / kMm},
                              {"table2_bezier_tp_mm", r.table2_bezier_tp / kMm},
                              {"runs", runs_json(r.runs)}};
    write_file_atomic(dir / "results.json", j.dump(1) + "\n");
    for (const PlannedRun& run : r.runs) {
      write_file_atomic(dir / ("profile_" + run.name + ".csv"), profile_csv(run, run.timing, kDecimate004));
      if (run.name == "biclothoid_0.1mm" || run.name == "bezier_0.1mm") {
        write_file_atomic(dir / ("path_" + run.name + ".csv"), curvature_csv(run.path, 0.1 * kMm));
      }
    }
    write_file_atomic(dir / "listing1.csv", program_csv(listing1(Transition{}), 0.5 * kMm));
    write_file_atomic(dir / "table2_fillets.csv", table2_fillets_csv(r));
    write_file_atomic(dir / "README.md", markdown_004(r));
    if (plots) plots_ok = plot(dir, "004", log) && plots_ok;
    throw_if_stop_requested();
    folder.commit({"results.json", "README.md"});
    log << "reproduce 004 -> " << folder.target().string() << std::endl;
  }
  if (name == "000" || name == "all") {
    const Paper000 r = reproduce_000();
    RunFolder folder(out_dir / "000", "results.json", "--out");
    const std::filesystem::path& dir = folder.staging();
    const nlohmann::json j = {{"paper", "000"},
                              {"tables", {table_json(r.section3_2), table_json(r.corners)}},
                              {"runs", runs_json(r.runs)}};
    write_file_atomic(dir / "results.json", j.dump(1) + "\n");
    for (const PlannedRun& run : r.runs) {
      write_file_atomic(dir / ("profile_" + run.name + ".csv"), profile_csv(run, run.timing, kDecimate000));
      write_file_atomic(dir / ("profile_" + run.name + "_optimal.csv"), profile_csv(run, run.optimal, kDecimate000));
    }
    write_file_atomic(dir / "README.md", markdown_000(r));
    if (plots) plots_ok = plot(dir, "000", log) && plots_ok;
    throw_if_stop_requested();
    folder.commit({"results.json", "README.md"});
    log << "reproduce 000 -> " << folder.target().string() << std::endl;
  }
  if (name == "002" || name == "all") {
    const Paper002 r = reproduce_002();
    RunFolder folder(out_dir / "002", "results.json", "--out");
    const std::filesystem::path& dir = folder.staging();
    write_002(r, dir);
    if (plots) plots_ok = plot(dir, "002", log) && plots_ok;
    throw_if_stop_requested();
    folder.commit({"results.json", "README.md"});
    log << "reproduce 002 -> " << folder.target().string() << std::endl;
  }
  return plots_ok ? 0 : 1;
}

}  // namespace blendbench
