// blendbench: the command-line program (the contract: docs/output.md and docs/commands.md).
// Exit codes: 0 ok, 1 a check failed or a variant did not complete, 2 bad input (or an --out
// folder in use by another run), 128 + signal when stopped by SIGINT (130) or SIGTERM (143).

#include <CLI/CLI.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "blendbench/core/format.hpp"
#include "blendbench/core/input_file.hpp"
#include "blendbench/corner/blend.hpp"
#include "blendbench/timing/timing.hpp"
#include "blendbench/report/check.hpp"
#include "blendbench/report/output.hpp"
#include "blendbench/io/data_root.hpp"
#include "blendbench/io/program_io.hpp"
#include "blendbench/report/report.hpp"
#include "blendbench/report/run_folder.hpp"
#include "blendbench/core/interrupt.hpp"
#include "blendbench/papers/reproduce.hpp"
#include "blendbench/app/compare.hpp"
#include "blendbench/app/runner.hpp"
#include "blendbench/app/smoothing_flags.hpp"
#include "blendbench/app/sweep.hpp"
#include "blendbench/app/unit_text.hpp"
#include "blendbench/app/version.hpp"
#include "blendbench/io/scenario.hpp"
#include "blendbench/io/scenario_keys.hpp"

namespace bb = blendbench;

namespace {

constexpr int kExitOk = 0;
constexpr int kExitCheckFailed = 1;
constexpr int kExitBadInput = 2;
// a stop by signal N exits 128 + N, as a shell reports a process killed by it
constexpr int kExitSignalBase = 128;

// A scenario's plausibility warnings, one line each on stderr (summary.json lists them too).
void print_warnings(const bb::Scenario& scenario) {
  for (const bb::LoadWarning& w : scenario.warnings) std::cerr << "blendbench: warning: " << bb::to_string(w) << std::endl;
}

const char* signal_name(int signal) {
  return signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : signal == SIGPIPE ? "SIGPIPE" : "a signal";
}

// What a run's staging folder must hold to be published: its summary and the folder of every
// variant the summary reports figures of (a failed or interrupted variant has none).
std::vector<std::string> published_entries(const bb::RunResult& result) {
  std::vector<std::string> entries = {"summary.json"};
  for (const bb::VariantSummary& v : result.summary.variants) {
    if (v.metrics) entries.push_back(v.name);
  }
  return entries;
}

// A run stopped by a signal: its finished variants are kept (in --out, or beside it as
// <out>.interrupted when --out holds a previous run, which stays intact); one line says where.
int interrupted_run(bb::RunFolder& folder, const bb::RunResult& result) {
  std::string finished;
  int count = 0;
  for (const bb::VariantSummary& v : result.summary.variants) {
    if (v.status == bb::VariantStatus::kInterrupted) continue;
    finished += (count++ == 0 ? "" : ", ") + v.name;
  }
  std::string where = "nothing kept";
  if (count > 0) {
    const std::filesystem::path kept =
        folder.had_previous_run() ? std::filesystem::path(folder.target().string() + ".interrupted") : folder.target();
    folder.commit_to(kept, published_entries(result));
    where = "kept " + std::to_string(count) + " finished variant(s) (" + finished + ") in " + kept.string();
  }
  std::cout << std::flush;
  std::cerr << "blendbench: interrupted by " << signal_name(result.interrupted_by) << ": " << where
            << (folder.had_previous_run() ? "; " + folder.target().string() + " still holds the previous run" : "")
            << std::endl;
  return kExitSignalBase + result.interrupted_by;
}

// --limits, --timing and --max-samples, shared by `run`, `plan` and (--timing) `sweep`.
struct TimingFlags {
  std::string limits;  // empty: the scenario's (cartesian by default)
  std::string timing;  // empty: the scenario's, or the variant's (optimal by default)
  std::optional<double> max_samples;
};

// --timing: the velocity planner, or none to keep the scenario's.
std::optional<bb::TimingOptions::Algorithm> timing_flag(const TimingFlags& flags) {
  if (flags.timing.empty()) return std::nullopt;
  const auto algorithm = bb::algorithm_from_string(flags.timing);
  if (!algorithm) throw bb::InputError("", 0, 0, "--timing", "must be 'optimal' or 'seed004', got '" + flags.timing + "'");
  return algorithm;
}

// Adds --timing to a command (a help text shared by every command that times a path).
void add_timing_flag(CLI::App* cmd, TimingFlags& flags) {
  cmd->add_option("--timing", flags.timing,
                  "Velocity planner: optimal (the minimum-time traversal under every limit; docs/timing.md) or seed004 "
                  "(seed 004's S-curves, kept for the paper reproductions and for comparison); replaces the scenario's `timing`");
}

std::optional<bb::LimitsMode> limits_flag(const TimingFlags& flags) {
  if (flags.limits.empty()) return std::nullopt;
  const auto mode = bb::limits_mode_from_string(flags.limits);
  if (!mode) throw bb::InputError("", 0, 0, "--limits", "must be 'path' or 'cartesian', got '" + flags.limits + "'");
  return mode;
}

std::optional<double> max_samples_flag(const TimingFlags& flags) {
  if (flags.max_samples && !(*flags.max_samples >= 1 && std::isfinite(*flags.max_samples))) {
    throw bb::InputError("", 0, 0, "--max-samples", "must be at least 1");
  }
  return flags.max_samples;
}

// A length flag in mm (`flag`): positive and finite, in m.
double positive_mm(double mm, const char* flag) {
  if (!(std::isfinite(mm) && mm > 0)) {
    throw bb::InputError("", 0, 0, flag, "must be > 0 and finite (mm), got " + bb::format_value(mm));
  }
  return mm * 1e-3;
}

// --tolerance MM: positive and finite, in m.
std::optional<double> tolerance_flag(const std::optional<double>& tolerance_mm) {
  if (!tolerance_mm) return std::nullopt;
  return positive_mm(*tolerance_mm, "--tolerance");
}

// The input of `run` and `compare`: a scenario, or a G-code file run on the shipped arm
// (run_inputs.hpp, gcode_scenario) or on `robot`.
bb::Scenario load_input(const std::string& path, const std::optional<bb::RobotSettings>& robot = std::nullopt) {
  if (bb::is_gcode_file(path)) return bb::gcode_scenario(path, robot);
  bb::Scenario scenario = bb::load_scenario(path);
  if (robot) scenario.robot = *robot;
  return scenario;
}

// The answer of a run, printed after its variants: the ranking per tolerance and the recommendation.
void print_answer(const bb::RunSummary& summary) {
  if (!summary.ranking) return;
  for (const bb::RankGroup& group : summary.ranking->groups) {
    std::cout << (group.tolerance > 0 ? "ranking at tolerance " + bb::format_value(group.tolerance * 1e3) + " mm"
                  : group.like_for_like ? std::string("ranking")
                                        : std::string("ranking of the variants sized by their parameter (not like for like)"))
              << ":";
    for (const bb::RankedVariant& v : group.ranked) {
      std::cout << " " << v.rank << ". " << v.name << " " << bb::format_fixed(v.cycle_time, 3) << " s"
                << (v.tie ? " =" : v.margin ? " <" : "");
    }
    for (const bb::UnrankedVariant& u : group.unranked) std::cout << " (" << u.name << ": " << bb::terminal_text(u.reason) << ")";
    std::cout << std::endl;
  }
  const bb::Recommendation& r = summary.ranking->recommendation;
  std::cout << "recommendation: " << (r.variant ? *r.variant + ", " : std::string("none: ")) << bb::terminal_text(r.reason)
            << std::endl;
}

// The common end of `run` and `compare`: the run folder committed, one line per variant, the
// answer, where the report is; the exit code.
int finish_run(bb::RunFolder& folder, const bb::RunResult& result, const std::string& out_dir, bool plots,
               std::chrono::steady_clock::time_point start) {
  if (result.interrupted_by != 0) return interrupted_run(folder, result);
  // a run without one clean variant (a disk that filled, a model every variant fails on) never
  // replaces a previous run: it is kept beside it
  const bool any_clean = std::any_of(result.summary.variants.begin(), result.summary.variants.end(),
                                     [](const bb::VariantSummary& v) { return v.status == bb::VariantStatus::kOk; });
  if (!any_clean && folder.had_previous_run()) {
    const std::filesystem::path kept(folder.target().string() + ".failed");
    folder.commit_to(kept, published_entries(result));
    std::cout << "no variant ran clean: " << out_dir << " still holds the previous run; this one is in " << kept.string()
              << std::endl;
    for (const bb::VariantSummary& v : result.summary.variants) {
      std::cout << "  " << v.name << ": " << bb::to_string(v.status) << " - " << v.message << std::endl;
    }
    return kExitCheckFailed;
  }
  folder.commit(published_entries(result));
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "done in " << bb::format_value(wall, 3) << " s: " << (std::filesystem::path(out_dir) / "summary.json").string()
            << std::endl;
  for (const bb::VariantSummary& v : result.summary.variants) {
    std::cout << "  " << v.name << ": ";
    if (!v.metrics) {
      std::cout << bb::to_string(v.status) << " - " << v.message << std::endl;
      continue;
    }
    const bb::Metrics& m = *v.metrics;
    // fixed decimals (a column of variants lines up) and the servo's errors in micrometres (docs/units.md)
    const char* um = bb::micrometre_text();
    std::cout << "cycle " << (m.cycle_time ? bb::format_fixed(*m.cycle_time, 3) + " s" : "not settled") << ", tracking max "
              << bb::format_fixed(m.tracking_error_max * 1e6, 1) << " " << um << ", contour (planned path) max "
              << bb::format_fixed(m.contour_error_planned_max * 1e6, 1) << " " << um << ", residual vibration "
              << bb::format_fixed(m.vibration_final.peak_to_peak * 1e6, 1) << " " << um;
    if (v.status != bb::VariantStatus::kOk) std::cout << " [" << bb::to_string(v.status) << ": " << v.message << "]";
    std::cout << std::endl;
  }
  print_answer(result.summary);
  if (result.report) {
    // written in the staging folder, now --out
    std::cout << "report: " << (std::filesystem::path(out_dir) / result.report->filename()).string() << std::endl;
  } else if (plots) {
    std::cout << "no report: the plot script failed (see above)" << std::endl;
  } else {
    std::cout << "no report (--no-plots)" << std::endl;
  }
  return result.all_ok ? kExitOk : kExitCheckFailed;
}

// `--sensitivity` and `--jobs` of `run` and `compare` (runner.hpp, RunRequest::sensitivity).
struct SensitivityFlags {
  bool on = false;
  std::optional<int> jobs;  // simulations at a time; unset: every core
};

// Sets the request's sensitivity study from the flags, refusing a --jobs that cannot apply.
void apply_sensitivity_flags(const SensitivityFlags& flags, bb::RunRequest& request) {
  if (flags.jobs && !flags.on) throw bb::InputError("", 0, 0, "--jobs", "runs the perturbed models of --sensitivity: add --sensitivity");
  if (flags.jobs && *flags.jobs < 1) throw bb::InputError("", 0, 0, "--jobs", "must be at least 1 (default: every core)");
  request.sensitivity = flags.on;
  request.jobs = flags.jobs.value_or(0);
}

int cmd_run(std::string scenario_path, std::string out_dir, bool no_video, bool no_plots, bool compare,
            const std::vector<std::string>& variants, const TimingFlags& timing_flags,
            const std::optional<double>& tolerance_mm, const bb::SmoothingFlags& smoothing,
            const SensitivityFlags& sensitivity) {
  const auto start = std::chrono::steady_clock::now();
  bb::RunSelection selection;
  selection.tolerance = tolerance_flag(tolerance_mm);  // refused before anything is loaded
  bb::check_smoothing_flags(smoothing);
  bb::RunRequest request;
  apply_sensitivity_flags(sensitivity, request);
  selection.limits = limits_flag(timing_flags);
  selection.timing = timing_flag(timing_flags);
  selection.variants = variants;
  // no scenario given: the default one in the data root (data_root.hpp)
  if (scenario_path.empty()) scenario_path = bb::data_file("scenarios/default.yaml");
  const bool gcode = bb::is_gcode_file(scenario_path);
  const bb::Scenario scenario = load_input(scenario_path);
  print_warnings(scenario);
  const bb::RunInputs inputs = bb::resolve_run(scenario, selection);
  if (out_dir.empty()) out_dir = "results/runs/" + scenario.name;
  // the run goes to a staging folder beside --out, locked, and replaces it as a whole at the end
  bb::RunFolder folder(out_dir);
  request.out_dir = folder.staging();
  request.published_dir = folder.target();
  request.video = !no_video;
  request.compare = compare;
  request.plots = !no_plots;
  request.max_samples = max_samples_flag(timing_flags);
  request.smoothing = smoothing;
  request.progress = [](const std::string& line) { std::cout << line << std::endl; };
  if (gcode) {
    std::cout << "blendbench: G-code part '" << scenario_path << "' -> " << out_dir
              << ": its own blending as written (as_programmed) and the exact stop, on the shipped arm, the part centred at ("
              << bb::format_value(bb::kGcodePartCentre.x() * 1e3) << ", " << bb::format_value(bb::kGcodePartCentre.y() * 1e3)
              << ", " << bb::format_value(bb::kGcodePartCentre.z() * 1e3)
              << ") mm in front of it" << std::endl
              << "note: for every method at equal tolerance, ranked: blendbench compare " << scenario_path << std::endl;
  } else {
    std::cout << "blendbench: scenario '" << scenario.name << "' (" << scenario_path << ") -> " << out_dir << std::endl;
  }
  const bb::RunResult result = bb::run_pipeline(inputs, request);
  return finish_run(folder, result, out_dir, request.plots, start);
}

// The flags of `compare`.
struct CompareFlags {
  std::string input;
  std::string out_dir;
  std::vector<double> tolerances_mm;
  std::string methods;
  bool no_video = false;
  bool no_plots = false;
  std::optional<double> max_contour_error_mm;
  std::optional<double> max_vibration_um;
  std::string robot;
  bb::SmoothingFlags smoothing;  // --smoothing, --smoothing-tolerance
  SensitivityFlags sensitivity;  // --sensitivity, --jobs
};

// `compare INPUT`: both baselines and every method at each tolerance (compare.hpp), ranked.
int cmd_compare(const CompareFlags& flags, const TimingFlags& timing_flags) {
  const auto start = std::chrono::steady_clock::now();
  // every flag checked before anything is loaded
  bb::CompareRequest compare;
  for (const double mm : flags.tolerances_mm) compare.tolerances.push_back(positive_mm(mm, "--tolerance"));
  if (!flags.methods.empty()) compare.methods = bb::methods_from_list(flags.methods, "--methods");
  bb::Constraints constraints;
  if (flags.max_contour_error_mm) constraints.max_contour_error = positive_mm(*flags.max_contour_error_mm, "--max-contour-error");
  if (flags.max_vibration_um) constraints.max_vibration = positive_mm(*flags.max_vibration_um, "--max-vibration") * 1e-3;
  const std::optional<bb::LimitsMode> limits = limits_flag(timing_flags);
  const std::optional<double> max_samples = max_samples_flag(timing_flags);
  bb::check_smoothing_flags(flags.smoothing);
  bb::RunRequest request;
  apply_sensitivity_flags(flags.sensitivity, request);
  std::optional<bb::RobotSettings> robot;
  if (!flags.robot.empty()) robot = bb::named_robot(flags.robot, "--robot");

  bb::Scenario scenario = load_input(flags.input, robot);
  print_warnings(scenario);
  if (limits) scenario.limits = *limits;
  if (limits == bb::LimitsMode::kPath) scenario.axis_limits.reset();
  if (const auto algorithm = timing_flag(timing_flags)) {
    scenario.timing = *algorithm;
    for (bb::Variant& v : scenario.variants) v.timing.reset();
  }
  const bb::ComparePlan plan = bb::plan_compare(scenario, compare);
  const std::string out_dir = flags.out_dir.empty() ? "results/runs/" + plan.inputs.name : flags.out_dir;
  bb::RunFolder folder(out_dir);
  request.out_dir = folder.staging();
  request.published_dir = folder.target();
  request.video = !flags.no_video;
  request.compare = !flags.no_video && plan.inputs.variants.size() > 1;
  request.plots = !flags.no_plots;
  request.max_samples = max_samples;
  request.constraints = constraints;
  request.smoothing = flags.smoothing;
  request.progress = [](const std::string& line) { std::cout << line << std::endl; };
  std::string tolerances;
  for (const double t : plan.tolerances) tolerances += (tolerances.empty() ? "" : ", ") + bb::format_value(t * 1e3);
  std::cout << "blendbench compare: '" << scenario.name << "' (" << flags.input << ") -> " << out_dir << ": "
            << plan.inputs.variants.size() << " variants, tolerance " << tolerances << " mm" << std::endl;
  for (const std::string& note : plan.notes) std::cout << "note: " << note << std::endl;
  const bb::RunResult result = bb::run_pipeline(plan.inputs, request);
  return finish_run(folder, result, out_dir, request.plots, start);
}

// Transition and limit overrides from the command line (mm-based units as the flags say).
struct ProgramFlags {
  std::string variant;
  std::string method;
  std::optional<double> param_mm;           // unset: not given
  std::optional<double> start_distance_mm;
  std::optional<double> tolerance_mm;       // equal tolerance: replaces the parameter of every move with a method
  double feed_mm_per_min = 0;
  double amax_mm_s2 = 0;
  double jmax_mm_s3 = 0;
  std::optional<double> merge_mm;  // G64 Q on every move: merge collinear lines within it
  bb::SmoothingFlags smoothing;    // --smoothing, --smoothing-tolerance
  std::vector<std::string> subroutine_path;  // G-code: folders searched for o<name> call files
};

struct LoadedProgram {
  bb::Program program;
  std::vector<std::string> ignored;
  // a scenario's (setpoint period, limits, its variant's baseline); G-code: 1 ms, cartesian
  bb::TimingOptions timing;
};

void check_positive(double value, const char* flag) {
  if (!(value > 0)) throw bb::InputError("", 0, 0, flag, "must be positive");
}

// A transition size from a flag (mm): 0 or at least the planner's smallest (program.hpp).
void check_transition_size(double mm, const char* flag) {
  if (mm > 0 && mm * 1e-3 < bb::kMinTransitionSize) {
    throw bb::InputError("", 0, 0, flag,
                         "is 0 (no transition) or at least " + bb::format_value(bb::kMinTransitionSize * 1e3) + " mm, got " +
                             bb::format_value(mm) + " mm");
  }
}

// Reads a G-code file or a scenario variant and applies the overrides: --method/--param replace
// the transition of every move; --tolerance replaces the parameter of every move with a method
// (with --method: of every move); --feed/--amax/--jmax replace the limits of every move.
LoadedProgram load_program(const std::string& input, const ProgramFlags& flags) {
  const std::optional<double> tolerance = tolerance_flag(flags.tolerance_mm);
  if (tolerance && flags.param_mm) {
    throw bb::InputError("", 0, 0, "--tolerance", "give --tolerance or --param, not both (--tolerance and --param exclude each other)");
  }
  if (tolerance && flags.start_distance_mm) {
    throw bb::InputError("", 0, 0, "--tolerance",
                         "give --tolerance or --start-distance, not both (--tolerance and --start-distance exclude each other)");
  }
  std::optional<bb::Transition> transition;
  if (!flags.method.empty()) {
    const auto method = bb::method_from_string(flags.method);
    if (!method) throw bb::InputError("", 0, 0, "--method", "unknown method '" + flags.method + "' (none, arc, bezier, clothoid, biclothoid)");
    transition = bb::Transition{};
    transition->method = *method;
    if (flags.start_distance_mm) {
      // a biclothoid sized by where it starts instead of by its deviation
      if (*method != bb::Method::kBiclothoid) {
        throw bb::InputError("", 0, 0, "--start-distance", "sizes only a biclothoid (--method biclothoid), not " + flags.method);
      }
      if (flags.param_mm) throw bb::InputError("", 0, 0, "--start-distance", "give --param or --start-distance, not both");
      check_positive(*flags.start_distance_mm, "--start-distance");
      check_transition_size(*flags.start_distance_mm, "--start-distance");
      transition->start_distance = *flags.start_distance_mm * 1e-3;
    } else if (*method == bb::Method::kNone) {
      if (flags.param_mm) throw bb::InputError("", 0, 0, "--param", "has no meaning with --method none (an exact stop)");
      if (tolerance) throw bb::InputError("", 0, 0, "--tolerance", "has no meaning with --method none (an exact stop)");
    } else if (tolerance) {
      transition->tolerance = *tolerance;
    } else {
      if (!flags.param_mm) {
        throw bb::InputError("", 0, 0, "--param", "required with --method " + flags.method + " (mm), or --tolerance" +
                                                      (*method == bb::Method::kBiclothoid ? ", or --start-distance" : ""));
      }
      if (!(*flags.param_mm >= 0)) throw bb::InputError("", 0, 0, "--param", "must be >= 0 (mm)");
      check_transition_size(*flags.param_mm, "--param");
      transition->parameter = *flags.param_mm * 1e-3;
    }
  } else if (flags.param_mm) {
    throw bb::InputError("", 0, 0, "--param", "needs --method");
  } else if (flags.start_distance_mm) {
    throw bb::InputError("", 0, 0, "--start-distance", "needs --method biclothoid");
  }
  for (const auto& [value, name] : {std::pair{flags.feed_mm_per_min, "--feed"}, std::pair{flags.amax_mm_s2, "--amax"},
                                    std::pair{flags.jmax_mm_s3, "--jmax"}}) {
    if (value != 0) check_positive(value, name);
  }

  LoadedProgram out;
  if (bb::is_gcode_file(input)) {
    if (!flags.variant.empty()) throw bb::InputError("", 0, 0, "--variant", "only for scenario files");
    bb::GcodeOptions options;
    // G-code carries no acceleration or jerk: the defaults of a G-code run (run_inputs.hpp, kGcode*)
    options.limits.velocity = flags.feed_mm_per_min > 0 ? flags.feed_mm_per_min * 1e-3 / 60.0 : bb::kGcodeFeed;
    options.limits.acceleration = flags.amax_mm_s2 > 0 ? flags.amax_mm_s2 * 1e-3 : bb::kGcodeAcceleration;
    options.limits.deceleration = options.limits.acceleration;
    options.limits.jerk = flags.jmax_mm_s3 > 0 ? flags.jmax_mm_s3 * 1e-3 : bb::kGcodeJerk;
    for (const std::string& folder : flags.subroutine_path) {
      std::error_code ec;
      if (!std::filesystem::is_directory(folder, ec)) throw bb::InputError("", 0, 0, "--subroutine-path", "folder not found: " + folder);
    }
    options.subroutine_path = flags.subroutine_path;
    bb::GcodeResult parsed = bb::load_gcode_file(input, options);
    out.program = std::move(parsed.program);
    out.ignored = std::move(parsed.ignored);
    out.timing.algorithm = bb::TimingOptions::Algorithm::kOptimal;  // the scenario format's default
  } else {
    const bb::Scenario scenario = bb::load_scenario(input);
    print_warnings(scenario);
    bb::VariantInputs v = bb::resolve_variant(
        scenario, flags.variant.empty() ? scenario.variants.front() : bb::find_variant(scenario, flags.variant));
    out.program = std::move(v.program);
    out.ignored = scenario.ignored;
    out.timing = v.timing;
  }
  if (flags.merge_mm && !(*flags.merge_mm >= 0 && std::isfinite(*flags.merge_mm))) {
    throw bb::InputError("", 0, 0, "--merge-tolerance", "must be >= 0 (mm)");
  }
  if (tolerance && !transition) bb::apply_tolerance(out.program, *tolerance);
  for (bb::Move& move : out.program.moves) {
    if (transition) move.transition = *transition;
    if (flags.merge_mm) move.transition.merge_tolerance = *flags.merge_mm * 1e-3;
    // an F word in a G-code file sets the feed; --feed overrides it as a machine override would
    if (flags.feed_mm_per_min > 0) move.limits.velocity = flags.feed_mm_per_min * 1e-3 / 60.0;
    if (flags.amax_mm_s2 > 0) move.limits.acceleration = move.limits.deceleration = flags.amax_mm_s2 * 1e-3;
    if (flags.jmax_mm_s3 > 0) move.limits.jerk = flags.jmax_mm_s3 * 1e-3;
  }
  if (flags.smoothing.given()) out.program.smoothing = bb::apply_smoothing_flags(flags.smoothing, out.program.smoothing);
  return out;
}

// One line on what smoothing did, and its notes (none without smoothing).
void print_smoothing(const bb::SmoothingReport& report) {
  if (report.method == bb::SmoothingMethod::kNone) return;
  std::cout << "  smoothing " << bb::to_string(report.method) << ": streams " << report.runs << ", points " << report.points
            << " -> pieces " << report.pieces << ", within " << bb::format_value(report.max_distance * 1e3, 4)
            << " mm, fitted in " << bb::format_value(report.wall_time * 1e3, 4) << " ms" << std::endl;
  for (const std::string& note : report.notes) std::cout << "  smoothing: " << note << std::endl;
}

int cmd_path(const std::string& input, const ProgramFlags& flags, const std::string& csv, const std::string& report,
             double ds_mm) {
  if (!(ds_mm > 0)) throw bb::InputError("", 0, 0, "--ds", "the sample spacing must be positive");
  bb::check_output_files({{"--csv", csv}, {"--report", report}});
  const LoadedProgram loaded = load_program(input, flags);
  const bb::Path path = bb::blend(loaded.program);
  // the rows are counted before any is sampled: a tiny spacing is refused, not an overflow
  if (const double rows = bb::path_sample_count(path, ds_mm * 1e-3); rows > bb::kMaxPathSamples) {
    throw bb::InputError("", 0, 0, "--ds",
                         "sampling the " + bb::format_value(path.length() * 1e3, 6) + " mm path every " +
                             bb::format_value(ds_mm, 6) + " mm would write " + bb::format_value(rows, 3) +
                             " rows; the limit is " + bb::format_value(bb::kMaxPathSamples, 3) + " (raise --ds)");
  }
  bb::throw_if_stop_requested();
  // the outputs locked while they are written: a second command writing them is refused
  const bb::OutputFilesLock lock({{"--csv", csv}, {"--report", report}});
  std::vector<std::pair<std::filesystem::path, std::string>> files = {{csv, bb::path_csv(path, ds_mm * 1e-3)}};
  if (!report.empty()) files.emplace_back(report, bb::corners_json(path, loaded.program).dump(2) + "\n");
  bb::write_files_atomic(files);
  std::cout << "path: " << bb::format_value(path.length() * 1e3, 6) << " mm, " << path.pieces().size() << " pieces, "
            << path.corners.size() << " corners -> " << csv << std::endl;
  print_smoothing(path.smoothing);
  return kExitOk;
}

int cmd_plan(const std::string& input, const ProgramFlags& flags, const TimingFlags& timing_flags, const std::string& csv,
             const std::string& summary) {
  const std::optional<bb::LimitsMode> limits = limits_flag(timing_flags);
  const std::optional<bb::TimingOptions::Algorithm> algorithm = timing_flag(timing_flags);
  const std::optional<double> max_samples = max_samples_flag(timing_flags);
  bb::check_output_files({{"--csv", csv}, {"--summary", summary}});
  const LoadedProgram loaded = load_program(input, flags);
  const auto start = std::chrono::steady_clock::now();
  const bb::Path path = bb::blend(loaded.program);
  bb::TimingOptions options = loaded.timing;
  if (limits) {
    options.limits = *limits;
    if (*limits == bb::LimitsMode::kPath) options.axis_limits.reset();
  }
  if (max_samples) options.max_samples = *max_samples;
  if (algorithm) options.algorithm = *algorithm;
  const bb::Timing timing = bb::plan_timing(path, options);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (!timing.outcome.ok()) {
    std::cerr << "blendbench: planning failed: " << timing.outcome.message << std::endl;
    return kExitCheckFailed;
  }
  nlohmann::json j = bb::plan_summary_json(path, timing, loaded.program);
  j["version"] = bb::version_string();
  j["ignored"] = loaded.ignored;
  bb::throw_if_stop_requested();
  const bb::OutputFilesLock lock({{"--csv", csv}, {"--summary", summary}});
  bb::write_files_atomic({{csv, bb::timed_csv(path, timing)}, {summary, j.dump(2) + "\n"}});
  std::cout << "plan: " << bb::format_value(path.length() * 1e3, 6) << " mm in " << bb::format_value(timing.cycle_time, 6)
            << " s, " << path.corners.size() << " corners, planned in " << bb::format_value(wall * 1e3, 3) << " ms -> "
            << csv << ", " << summary << std::endl;
  print_smoothing(path.smoothing);
  for (const std::string& line : loaded.ignored) std::cout << "  ignored: " << line << std::endl;
  return kExitOk;
}

// Checks one input without running it: loaded (a scenario, or G-code with the path/plan
// defaults), checked by the planner and blended, every variant of a scenario, so geometric
// refusals show. Returns what was checked and its plausibility warnings; throws InputError.
struct Validated {
  std::string checked;
  std::vector<bb::LoadWarning> warnings;
};

Validated validate_input(const std::string& input, const std::vector<std::string>& subroutine_path) {
  const auto blend_checked = [](const bb::Program& program) {
    bb::validate(program);
    return bb::blend(program).corners.size();
  };
  if (bb::is_gcode_file(input)) {
    ProgramFlags flags;
    flags.subroutine_path = subroutine_path;
    const LoadedProgram loaded = load_program(input, flags);
    const std::size_t corners = blend_checked(loaded.program);
    return {"G-code, " + std::to_string(loaded.program.moves.size()) + " moves, " + std::to_string(corners) +
                " corners blended, " + std::to_string(loaded.ignored.size()) + " notes",
            {}};
  }
  const bb::Scenario scenario = bb::load_scenario(input);
  for (const bb::Variant& v : scenario.variants) (void)blend_checked(bb::program_for(scenario, v));
  // the robot's files as `run` opens them (a URDF or MJCF that run refuses is refused here)
  bb::check_robot(scenario);
  return {"scenario '" + scenario.name + "', " + std::to_string(scenario.program.moves.size()) + " moves, " +
              std::to_string(scenario.variants.size()) + " variants blended, robot loaded" +
              (scenario.warnings.empty() ? "" : ", " + std::to_string(scenario.warnings.size()) + " warning(s)"),
          scenario.warnings};
}

// `validate FILE...`: one line per file, "FILE: ok (...)" or the refusal; exit 2 if any is bad.
int cmd_validate(const std::vector<std::string>& files, bool schema, const std::vector<std::string>& subroutine_path) {
  if (schema) {
    std::cout << bb::scenario_format_markdown();
    return kExitOk;
  }
  if (files.empty()) throw bb::InputError("", 0, 0, "FILE", "name at least one file to check (or --schema)");
  bool all_ok = true;
  for (const std::string& file : files) {
    bb::throw_if_stop_requested();
    try {
      const Validated checked = validate_input(file, subroutine_path);
      std::cout << file << ": ok (" << checked.checked << ")" << std::endl;
      // valid but suspicious: warned, still ok (exit 0)
      for (const bb::LoadWarning& w : checked.warnings) std::cout << "  warning: " << bb::to_string(w) << std::endl;
    } catch (const bb::InputError& e) {
      // the error names its file, except for a refusal that came from no file
      std::cout << (e.file().empty() ? bb::printable(file) + ": " : std::string()) << e.what() << std::endl;
      all_ok = false;
    }
  }
  return all_ok ? kExitOk : kExitBadInput;
}

// A JSON input file: read as every input is (a regular file, bounded: a FIFO never blocks), and
// any error of the parser (a number overflow such as 1e400 included) bad input naming the file.
nlohmann::json read_json(const std::string& path, const std::string& what) {
  const std::string text = bb::read_input_file(path, what);
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {
    // the parser's reason without its tag ("[json.exception.parse_error.101] ")
    const std::string reason = e.what();
    const std::size_t tag = reason.rfind("[json.exception.", 0) == 0 ? reason.find("] ") : std::string::npos;
    throw bb::InputError(path, 0, 0, "", "invalid JSON in the " + what + ": " + (tag == std::string::npos ? reason : reason.substr(tag + 2)));
  } catch (...) {
    bb::rethrow_as_input_error({path, 0, 0}, "", "invalid JSON in the " + what + ": ");
  }
}

// `blendbench check`: the run against its scenario's baseline under the one tolerance file.
int cmd_check(const std::string& run_dir, std::string baseline_file, std::string tolerance_file, bool update) {
  const std::string summary_file = (std::filesystem::path(run_dir) / "summary.json").string();
  const nlohmann::json summary = read_json(summary_file, "run summary");
  bb::validate_run_summary(summary, summary_file);
  const std::string name = summary.value("scenario", "");
  if (baseline_file.empty()) {
    // the scenario name picks the baseline file: never a path that leaves results/baselines/
    if (const std::string problem = bb::folder_name_problem(name); !problem.empty()) {
      throw bb::InputError(summary_file, 0, 0, "scenario", "scenario " + problem);
    }
    baseline_file = bb::data_file("results/baselines/" + name + ".json");
  }
  if (tolerance_file.empty()) tolerance_file = bb::data_file("results/baselines/tolerances.json");
  const std::vector<bb::MetricTolerance> tolerances =
      bb::parse_tolerances(read_json(tolerance_file, "tolerance file"), tolerance_file);
  if (update) {
    bb::check_output_files({{"--baseline", baseline_file}});
    bb::write_file_atomic(baseline_file, bb::make_baseline(summary, tolerances).dump(2) + "\n");
    std::cout << "baseline written: " << baseline_file << std::endl;
    return kExitOk;
  }
  std::error_code absent;
  if (!std::filesystem::exists(baseline_file, absent) && !absent) {
    throw bb::InputError(baseline_file, 0, 0, "",
                         "no baseline for scenario '" + name + "'; after checking the run is right, create it deliberately " +
                             "with `blendbench check " + run_dir + " --update` and commit it");
  }
  const bb::CheckReport report = bb::check_run(summary, read_json(baseline_file, "baseline"), tolerances, baseline_file);
  std::cout << bb::moved_table(report);
  for (const std::string& note : report.notes) std::cout << "note: " << note << std::endl;
  for (const std::string& r : report.regressions) std::cout << "REGRESSION: " << r << std::endl;
  std::cout << (report.passed() ? "check passed against " : "check FAILED against ") << baseline_file << " ("
            << report.rows.size() << " metrics compared; tolerances: " << tolerance_file << ")" << std::endl;
  return report.passed() ? kExitOk : kExitCheckFailed;
}

// An option or argument given with an empty value ("--out ''", "run ''") names nothing: refused,
// where its default would otherwise take its place silently. A value that is not UTF-8 (a file
// named "t\xff.yaml") is refused too: names and values are recorded in the JSON outputs, which
// hold only UTF-8, and nlohmann::json refused to write them after every variant had run
// ("[json.exception.type_error.316] invalid UTF-8 byte", exit 1).
void refuse_unusable_values(const CLI::App& app) {
  for (const CLI::App* command : app.get_subcommands()) {
    for (const CLI::Option* option : command->get_options()) {
      if (option->count() == 0) continue;
      for (const std::string& value : option->results()) {
        if (value.empty()) {
          throw bb::InputError("", 0, 0, option->get_name(), "an empty value names nothing: give one, or leave the option out");
        }
        if (!bb::is_utf8(value)) {
          throw bb::InputError("", 0, 0, option->get_name(),
                               "'" + bb::printable(value) +
                                   "' is not UTF-8 text: names are recorded in the JSON outputs, which hold only UTF-8; "
                                   "rename the file or folder");
        }
      }
    }
  }
}

// The exit code once what was printed has been handed on: standard output on a full device (or a
// closed pipe) lost everything printed, and a run that says "done" must not exit 0 then.
int finish(int code) {
  std::cout.flush();
  const bool lost = !std::cout.good() || std::fflush(stdout) != 0 || std::ferror(stdout) != 0;
  if (bb::stop_signal() == SIGPIPE) return kExitSignalBase + SIGPIPE;  // the reader went away
  if (lost) {
    std::cerr << "blendbench: error: cannot write to standard output (a full device?): what was printed is lost" << std::endl;
    if (code == kExitOk) return kExitCheckFailed;
  }
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  // SIGINT/SIGTERM only set a flag; the long loops unwind (core/interrupt.hpp)
  bb::install_stop_handlers();
  CLI::App app{"BlendBench: a testbench for blended robot trajectories"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string("blendbench ") + bb::version_string(), "Print the version (and the git commit it was built from) and exit");

  std::string scenario_path;  // empty: scenarios/default.yaml in the data root
  std::string out_dir;
  bool no_video = false;
  bool no_plots = false;
  bool compare = false;
  std::vector<std::string> variants;
  CLI::App* run = app.add_subcommand("run", "Run a scenario: plan, simulate, write metrics, plots and videos");
  run->add_option("scenario", scenario_path,
                  "Scenario YAML file (default: scenarios/default.yaml), or a G-code file (.ngc, ...): its own blending "
                  "and the exact stop on the shipped arm");
  run->add_option("--out", out_dir, "Output folder (default: results/runs/<scenario name>)");
  run->add_flag("--no-video", no_video, "Do not render videos");
  run->add_flag("--no-plots", no_plots, "Do not draw plots");
  run->add_flag("--compare", compare,
                "Also render DIR/compare.mp4: every variant side by side, synchronised, then the worst corner in slow "
                "motion (with --no-video: the comparison alone)");
  run->add_option("--variant", variants, "Run only this variant (repeatable)");
  std::optional<double> run_tolerance_mm;
  run->add_option("--tolerance", run_tolerance_mm,
                  "Equal tolerance in mm: every transition's parameter solved at each corner so that its deviation "
                  "equals it (every variant, every move with a method)");
  TimingFlags timing_flags;
  const auto add_timing_flags = [&](CLI::App* cmd) {
    cmd->add_option("--limits", timing_flags.limits,
                    "Limits the plan holds: cartesian (vectors on the TCP, the default) or path (tangential, as in 004)");
    cmd->add_option("--max-samples", timing_flags.max_samples,
                    "Refuse a plan of more servo samples than this (plan: default 1e7; run: a variant's plan and "
                    "settle time together, default 5e5)");
    add_timing_flag(cmd, timing_flags);
  };
  add_timing_flags(run);
  bb::SmoothingFlags run_smoothing;
  bb::add_smoothing_flags(run, run_smoothing);
  SensitivityFlags run_sensitivity;
  const auto add_sensitivity_flags = [](CLI::App* cmd, SensitivityFlags& flags) {
    cmd->add_flag("--sensitivity", flags.on,
                  "Also re-run every clean variant on perturbed arm models (the scenario's `sensitivity`, default: gear "
                  "stiffness x0.5/x1.5, inertias x0.8/x1.2, friction x0.5/x1.5, +1 tick of delay) and say which "
                  "conclusions hold in all of them (summary.json `sensitivity`; docs/sensitivity.md)");
    cmd->add_option("--jobs", flags.jobs, "With --sensitivity: simulations at a time (default: every core)");
  };
  add_sensitivity_flags(run, run_sensitivity);

  // shared by `path` and `plan`
  std::string input;
  ProgramFlags flags;
  std::string csv;
  const auto add_program_flags = [&](CLI::App* cmd) {
    cmd->add_option("input", input, "G-code program (.ngc, .nc, ...) or scenario YAML file")->required();
    cmd->add_option("--variant", flags.variant, "Scenario variant (default: the first)");
    cmd->add_option("--method", flags.method, "Transition on every move: none, arc, bezier, clothoid, biclothoid");
    cmd->add_option("--param", flags.param_mm,
                    "Transition parameter in mm: corner distance (arc), TP (bezier), maximum deviation (clothoid, biclothoid)");
    cmd->add_option("--tolerance", flags.tolerance_mm,
                    "Equal tolerance in mm, instead of --param: each corner's parameter solved so that its deviation "
                    "equals it (with --method: every move; else every move with a method)");
    cmd->add_option("--start-distance", flags.start_distance_mm,
                    "Biclothoid only, instead of --param: distance in mm from the corner at which the fillet starts");
    cmd->add_option("--feed", flags.feed_mm_per_min, "Feed on every move, mm/min (G-code default 1000 until an F word)");
    cmd->add_option("--amax", flags.amax_mm_s2, "Acceleration limit, mm/s^2 (G-code default 1000)");
    cmd->add_option("--jmax", flags.jmax_mm_s3, "Jerk limit, mm/s^3 (G-code default 10000)");
    cmd->add_option("--merge-tolerance", flags.merge_mm,
                    "Merge runs of collinear lines within this many mm before blending (LinuxCNC's G64 Q); 0 = off");
    bb::add_smoothing_flags(cmd, flags.smoothing);
    cmd->add_option("--subroutine-path", flags.subroutine_path,
                    "G-code: a folder searched for <name>.ngc when the program calls o<name> it does not define, after the "
                    "program's own folder (LinuxCNC's SUBROUTINE_PATH; repeatable)")
        ->allow_extra_args(false);
  };

  std::string report;
  double ds_mm = 0.05;
  CLI::App* path = app.add_subcommand("path", "Write the sampled planned (blended) path and the corner reports");
  add_program_flags(path);
  path->add_option("--csv", csv, "Output CSV: s,x,y,z,tx,ty,tz,kappa (mm, unit tangent, 1/mm)")->required();
  path->add_option("--report", report, "Output JSON: the corner reports");
  path->add_option("--ds", ds_mm, "Sample spacing in mm (default 0.05)");

  std::string summary;
  CLI::App* plan = app.add_subcommand("plan", "Write the timed profile (every servo period) and a plan summary");
  add_program_flags(plan);
  plan->add_option("--csv", csv, "Output CSV: t,s,x,y,z,v,a,j,kappa (s, mm, mm/s, mm/s^2, mm/s^3, 1/mm)")->required();
  plan->add_option("--summary", summary,
                   "Output JSON: cycle_time_s, path_length_mm, limits, timing, bound_cycle_time_s, planned_to_bound_ratio, iterations, corners, pieces")
      ->required();
  add_timing_flags(plan);

  CompareFlags compare_flags;
  CLI::App* compare_cmd = app.add_subcommand(
      "compare", "Every transition method at the same tolerance, both baselines, on a scenario's or a G-code file's program: "
                 "ranked, with a recommendation");
  compare_cmd->add_option("input", compare_flags.input, "Scenario YAML file or G-code file (.ngc, .nc, .gcode, .tap)")->required();
  compare_cmd->add_option("--tolerance", compare_flags.tolerances_mm,
                          "Tolerance in mm, repeatable (one ranking each; default: the program's G64 P, else 0.1)");
  compare_cmd->add_option("--methods", compare_flags.methods,
                          "Methods to compare, comma-separated (default: arc,bezier,clothoid,biclothoid)");
  compare_cmd->add_option("--out", compare_flags.out_dir, "Output folder (default: results/runs/<name>_compare)");
  compare_cmd->add_flag("--no-video", compare_flags.no_video, "Do not render videos (nor compare.mp4)");
  compare_cmd->add_flag("--no-plots", compare_flags.no_plots, "Do not draw plots (nor report.html)");
  compare_cmd->add_option("--max-contour-error", compare_flags.max_contour_error_mm,
                          "Recommend only variants whose contour error against the programmed path stays within this (mm)");
  compare_cmd->add_option("--max-vibration", compare_flags.max_vibration_um,
                          std::string("Recommend only variants whose residual vibration (after the stop and after every "
                                      "corner) stays within this (") +
                              bb::micrometre_text() + ", peak to peak)");
  compare_cmd->add_option("--robot", compare_flags.robot, "The arm: a URDF file, or a shipped one (ur5e_like, kr6_like)");
  bb::add_smoothing_flags(compare_cmd, compare_flags.smoothing);
  add_sensitivity_flags(compare_cmd, compare_flags.sensitivity);
  add_timing_flags(compare_cmd);

  std::string run_dir;
  std::string baseline;
  std::string tolerances;
  bool update = false;
  CLI::App* check = app.add_subcommand("check", "Compare a run's metrics with a committed baseline; exit 1 on regression");
  check->add_option("run_dir", run_dir, "Folder of a run (holds summary.json)")->required();
  check->add_option("--baseline", baseline, "Baseline JSON (default: results/baselines/<scenario>.json)");
  check->add_option("--tolerances", tolerances, "Tolerance file (default: results/baselines/tolerances.json)");
  check->add_flag("--update", update, "Write the baseline from this run instead of checking");

  std::vector<std::string> validate_files;
  bool schema = false;
  CLI::App* validate = app.add_subcommand(
      "validate", "Check scenario and G-code files without running them: load, the planner's checks, blend every variant");
  validate->add_option("files", validate_files, "Scenario YAML or G-code files");
  validate->add_flag("--schema", schema, "Print the scenario format (every key with unit, default and range) as Markdown");
  std::vector<std::string> validate_subroutine_path;
  validate->add_option("--subroutine-path", validate_subroutine_path,
                       "G-code: a folder searched for <name>.ngc when a program calls o<name> it does not define, after the "
                       "program's own folder (repeatable)")
      ->allow_extra_args(false);

  std::string paper;
  std::string papers_out = "results/papers";
  bool no_paper_plots = false;
  CLI::App* reproduce = app.add_subcommand("reproduce", "Reproduce a source paper's published numbers: report and data");
  reproduce->add_option("name", paper, "004, 000, 002 or all")->required();
  reproduce->add_option("--out", papers_out, "Parent folder; each paper goes to DIR/<paper>/ (default: results/papers)");
  reproduce->add_flag("--no-plots", no_paper_plots, "Do not draw the figures");

  bb::SweepCommand sweep_args;
  bool sweep_no_plots = false;
  CLI::App* sweep = app.add_subcommand("sweep", "Run a scenario over the product of axes, locally or as a Slurm array; tables and a Pareto front");
  sweep->add_option("file", sweep_args.file, "Sweep YAML file (scenario, variants, axes, metrics, constraints, pareto)");
  sweep->add_option("--out", sweep_args.out_dir, "Output folder (default: results/runs/sweeps/<file name>)");
  sweep->add_option("--jobs", sweep_args.jobs, "Runs at a time (default: every core)");
  sweep->add_flag("--resume", sweep_args.resume, "Skip points whose run finished (same expanded scenario)");
  sweep->add_flag("--no-plots", sweep_no_plots, "Do not draw pareto.png");
  sweep->add_flag("--slurm", sweep_args.slurm, "Write DIR/sweep.sbatch (a job array of shards) and submit it with sbatch");
  sweep->add_option("--array-size", sweep_args.array_size, "Slurm array tasks (default: one per point, at most 100)");
  sweep->add_option("--partition", sweep_args.partition, "Slurm partition");
  sweep->add_option("--time", sweep_args.time, "Slurm time limit per task");
  sweep->add_flag("--dry-run", sweep_args.dry_run, "With --slurm: write the script only");
  sweep->add_option("--shard", sweep_args.shard, "Run shard I of K (I/K, from 0), as a Slurm task does");
  sweep->add_option("--collect", sweep_args.collect, "Merge a sweep folder's results into sweep.csv, best.csv, pareto.png");
  sweep->add_option("--run-point", sweep_args.run_point, "")->group("");  // the child that runs one point
  add_timing_flag(sweep, timing_flags);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kExitOk : kExitBadInput;
  }

  const int code = [&]() -> int {
    try {
      refuse_unusable_values(app);
      if (*run) return cmd_run(scenario_path, out_dir, no_video, no_plots, compare, variants, timing_flags, run_tolerance_mm, run_smoothing,
                                 run_sensitivity);
      if (*compare_cmd) return cmd_compare(compare_flags, timing_flags);
      if (*path) return cmd_path(input, flags, csv, report, ds_mm);
      if (*plan) return cmd_plan(input, flags, timing_flags, csv, summary);
      if (*check) return cmd_check(run_dir, baseline, tolerances, update);
      if (*validate) return cmd_validate(validate_files, schema, validate_subroutine_path);
      if (*reproduce) return bb::reproduce(paper, papers_out, !no_paper_plots, std::cout);
      if (*sweep) {
        sweep_args.plots = !sweep_no_plots;
        if (const auto algorithm = timing_flag(timing_flags)) sweep_args.timing = std::string(bb::algorithm_name(*algorithm));
        return bb::sweep_command(sweep_args, std::cout);
      }
    } catch (const bb::Interrupted& stop) {
      // unwound: temporary files and a staging folder are gone, previous outputs untouched (a
      // sweep keeps the points it finished, for --resume)
      std::cerr << "blendbench: interrupted by " << signal_name(stop.signal) << "; no output file was replaced" << std::endl;
      return kExitSignalBase + stop.signal;
    } catch (const bb::InputError& e) {
      std::cerr << "blendbench: error: " << e.what() << std::endl;
      return kExitBadInput;
    } catch (const std::exception& e) {
      std::cerr << "blendbench: failed: " << bb::printable(e.what()) << std::endl;
      return kExitCheckFailed;
    }
    return kExitOk;
  }();
  return finish(code);
}
