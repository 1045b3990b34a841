#pragma once
// The command line's smoothing override, `--smoothing METHOD` and `--smoothing-tolerance MM`,
// shared by the subcommands that plan (path, plan, run, and compare): one parser, one meaning.

#include <optional>
#include <string>

#include "blendbench/program/smoothing.hpp"

namespace blendbench {

struct SmoothingFlags {
  std::string method;                  // none, clothoid_points or g2_fit; empty: not given
  std::optional<double> tolerance_mm;  // g2_fit's tolerance in mm; unset: not given
  [[nodiscard]] bool given() const { return !method.empty() || tolerance_mm.has_value(); }
};

// Adds both flags to a CLI11 subcommand (a template so the app library needs no CLI11).
template <class Command>
void add_smoothing_flags(Command* command, SmoothingFlags& flags) {
  command->add_option("--smoothing", flags.method,
                      "Smooth point streams (runs of short lines) before blending: none, clothoid_points (seed 002) or "
                      "g2_fit (a G2 curve within --smoothing-tolerance); replaces the scenario's smoothing");
  command->add_option("--smoothing-tolerance", flags.tolerance_mm,
                      "g2_fit's tolerance in mm: the curve stays this close to every point and line of a stream, both "
                      "ways (default 0.02)");
}

// Checks the flags' values: a known method, a positive finite tolerance. Throws InputError naming
// the flag.
void check_smoothing_flags(const SmoothingFlags& flags);

// `smoothing` with the flags applied: the method replaced when given, the tolerance when given.
// Throws InputError as check_smoothing_flags does, and for a tolerance when the resulting method
// is not g2_fit (the flag would change nothing).
Smoothing apply_smoothing_flags(const SmoothingFlags& flags, Smoothing smoothing);

// The same for one variant of a run of several: the tolerance is set only where the resulting
// method is g2_fit (a variant without smoothing keeps none). Throws as check_smoothing_flags.
Smoothing apply_smoothing_flags_to_variant(const SmoothingFlags& flags, Smoothing smoothing);

}  // namespace blendbench
