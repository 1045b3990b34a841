#pragma once
// `blendbench compare`: every transition method at the same tolerance, with both baselines, on
// one program (docs/compare.md). It chooses the variants and hands them to the same pipeline a
// `run` walks (runner.hpp); the ranking and the recommendation come from the summary
// (ranking.hpp). Nothing here plans, simulates or measures.

#include <optional>
#include <string>
#include <vector>

#include "blendbench/io/run_inputs.hpp"

namespace blendbench {

// The tolerance compared when neither the command line nor the program gives one (m).
inline constexpr double kDefaultCompareTolerance = 0.1e-3;

// At most this many tolerances in one comparison: each adds a variant per method, every one of
// them simulated (and rendered).
inline constexpr std::size_t kMaxCompareTolerances = 20;

struct CompareRequest {
  // m, each > 0 and finite; empty: the program's G64 P values (program_tolerances), else
  // kDefaultCompareTolerance
  std::vector<double> tolerances;
  // the transition methods to compare (not kNone: the baselines always run); empty: all four
  std::vector<Method> methods;
};

// What `compare` runs: the resolved variants, the tolerances and methods compared, and notes on
// what it left out (printed and written into summary.json).
struct ComparePlan {
  RunInputs inputs;
  std::vector<double> tolerances;  // m, ascending
  std::vector<Method> methods;     // the methods that run (those that apply to the program)
  std::vector<std::string> notes;
};

// The distinct G64 P values of the moves read from a G-code file (a scenario's `program: {gcode:}`
// or a G-code INPUT), in the order they first appear: the tolerances the program asks for (m).
std::vector<double> program_tolerances(const Program& program);

// The name of a compared variant: "<method>_<T>mm" with T the tolerance in mm as %g writes it
// (arc_0.5mm, biclothoid_0.05mm, clothoid_2mm).
std::string compare_variant_name(Method method, double tolerance);

// The comparison of `scenario`'s program (its robot, servo, frame, limits and settings; its own
// variants are not run, and the methods replace the transition of every move, including moves
// that set their own): `exact_stop`, `junction_slowdown`, then per tolerance ascending every
// requested method in the order arc, bezier, clothoid, biclothoid. A method whose blend of the
// program fails (a corner it refuses) is left out with a note; a program where no method cuts any
// corner at any tolerance runs the exact stop alone, with a note. The run is named
// "<scenario name>_compare". Throws InputError for a
// tolerance that is not > 0 and finite (field "--tolerance") and for more than
// kMaxCompareTolerances of them.
ComparePlan plan_compare(const Scenario& scenario, const CompareRequest& request);

// The methods of a comma-separated list ("arc,clothoid"); throws InputError naming `flag` for an
// unknown one, `none`, or an empty list.
std::vector<Method> methods_from_list(const std::string& list, const std::string& flag);

}  // namespace blendbench
