// The Slurm job array of a sweep: the sbatch script (sweep.hpp).

#include <string>

#include "blendbench/app/sweep.hpp"

namespace blendbench {
namespace {

bool has_control(const std::string& text) {
  for (const char c : text) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) return true;
  }
  return false;
}

// A word for bash: single-quoted, a quote inside written as '\''.
std::string shell_word(const std::string& text) {
  std::string out = "'";
  for (const char c : text) {
    if (c == '\'') {
      out += "'\\''";
    } else {
      out += c;
    }
  }
  return out + "'";
}

void check_path(const std::string& path, const std::string& field, bool in_directive) {
  if (path.empty() || path.front() != '/') throw InputError("", 0, 0, field, "'" + path + "' must be an absolute path for Slurm");
  if (has_control(path)) throw InputError("", 0, 0, field, "the path holds a control character");
  // #SBATCH lines are read by sbatch, not by a shell: no quoting there, and '%' is a pattern
  if (in_directive && path.find_first_of(" \t'\"\\%") != std::string::npos) {
    throw InputError("", 0, 0, field, "'" + path + "' cannot be named in an #SBATCH line (no spaces, quotes, '\\' or '%')");
  }
}

}  // namespace

std::string sbatch_script(const std::string& binary, const std::string& sweep_file, const std::filesystem::path& out_dir,
                          std::size_t tasks, const SbatchOptions& options) {
  check_path(binary, "blendbench", false);
  check_path(sweep_file, "FILE", false);
  check_path(out_dir.string(), "--out", true);
  if (tasks == 0) throw InputError("", 0, 0, "--array-size", "a job array needs at least one task");
  if (!options.partition.empty() &&
      options.partition.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_.,-") != std::string::npos) {
    throw InputError("", 0, 0, "--partition", "'" + options.partition + "' is not a partition name (letters, digits, '_', '.', '-', ',')");
  }
  if (!options.time.empty() && options.time.find_first_not_of("0123456789:-") != std::string::npos) {
    throw InputError("", 0, 0, "--time", "'" + options.time + "' is not a Slurm time (minutes, MM:SS, HH:MM:SS, D-HH, D-HH:MM)");
  }
  if (options.cpus_per_task < 1) throw InputError("", 0, 0, "--jobs", "must be at least 1");

  const std::string k = std::to_string(tasks);
  std::string s = "#!/bin/bash\n";
  s += "# A BlendBench sweep as a Slurm job array, written by `blendbench sweep --slurm`: task\n";
  s += "# SLURM_ARRAY_TASK_ID runs shard ID of " + k + " of the points into the shared output folder;\n";
  s += "# when every task has ended, `blendbench sweep --collect DIR` merges them into DIR/sweep.csv.\n";
  s += "#SBATCH --job-name=blendbench-sweep\n";
  s += "#SBATCH --array=0-" + std::to_string(tasks - 1) + "\n";
  s += "#SBATCH --ntasks=1\n";
  s += "#SBATCH --cpus-per-task=" + std::to_string(options.cpus_per_task) + "\n";
  s += "#SBATCH --output=" + (out_dir / "slurm" / "%A_%a.out").string() + "\n";
  if (!options.partition.empty()) s += "#SBATCH --partition=" + options.partition + "\n";
  if (!options.time.empty()) s += "#SBATCH --time=" + options.time + "\n";
  s += "set -eu\n";
  s += "exec " + shell_word(binary) + " sweep " + shell_word(sweep_file) + " --shard \"${SLURM_ARRAY_TASK_ID}/" + k +
       "\" --out " + shell_word(out_dir.string()) + " --jobs \"${SLURM_CPUS_PER_TASK:-" +
       std::to_string(options.cpus_per_task) + "}\"" + (options.resume ? " --resume" : "") +
       (options.timing.empty() ? "" : " --timing " + shell_word(options.timing)) + "\n";
  return s;
}

}  // namespace blendbench
