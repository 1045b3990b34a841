// The Slurm job array script: the array, the resources asked for, the shard command with every
// path quoted for bash, and what cannot be written into it refused.

#include <gtest/gtest.h>

#include "support/input_error.hpp"

#include <string>

#include "blendbench/app/sweep.hpp"

namespace blendbench {
namespace {

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

TEST(Sbatch, ArrayResourcesAndTheShardCommand) {
  SbatchOptions options;
  options.partition = "debug";
  options.time = "1-00:30";
  options.cpus_per_task = 4;
  options.resume = true;
  const std::string s = sbatch_script("/opt/bb/blendbench", "/home/a b/it's.yaml", "/scratch/out", 16, options);
  EXPECT_EQ(s.rfind("#!/bin/bash\n", 0), 0U);
  EXPECT_TRUE(has(s, "\n#SBATCH --array=0-15\n")) << s;
  EXPECT_TRUE(has(s, "\n#SBATCH --cpus-per-task=4\n")) << s;
  EXPECT_TRUE(has(s, "\n#SBATCH --partition=debug\n")) << s;
  EXPECT_TRUE(has(s, "\n#SBATCH --time=1-00:30\n")) << s;
  EXPECT_TRUE(has(s, "\n#SBATCH --output=/scratch/out/slurm/%A_%a.out\n")) << s;
  // a quote in a path closes, escapes and reopens the single-quoted word
  EXPECT_TRUE(has(s, "\nexec '/opt/bb/blendbench' sweep '/home/a b/it'\\''s.yaml' --shard \"${SLURM_ARRAY_TASK_ID}/16\" "
                     "--out '/scratch/out' --jobs \"${SLURM_CPUS_PER_TASK:-4}\" --resume\n"))
      << s;
  // no partition or time: no line for them
  const std::string plain = sbatch_script("/b", "/f.yaml", "/o", 1, {});
  EXPECT_FALSE(has(plain, "--partition")) << plain;
  EXPECT_FALSE(has(plain, "--time")) << plain;
  EXPECT_FALSE(has(plain, "--resume")) << plain;
  EXPECT_TRUE(has(plain, "#SBATCH --array=0-0\n")) << plain;
}

TEST(Sbatch, RefusesWhatTheScriptCannotCarry) {
  const auto refused = [](const std::string& binary, const std::string& file, const std::string& out, std::size_t tasks,
                          const SbatchOptions& options, const std::string& field) {
    test::expect_input_error([&] { (void)sbatch_script(binary, file, out, tasks, options); }, {.field = field}, field);
  };
  refused("/b", "/f.yaml", "/out dir", 1, {}, "--out");
  refused("/b", "/f.yaml", "/out%j", 1, {}, "--out");
  refused("/b", "/f.yaml", "relative/out", 1, {}, "--out");
  refused("/b", "f.yaml", "/o", 1, {}, "FILE");
  refused("/b", "/f\n.yaml", "/o", 1, {}, "FILE");
  refused("/b", "/f.yaml", "/o", 0, {}, "--array-size");
  SbatchOptions partition;
  partition.partition = "debug\n#SBATCH --mem=1T";
  refused("/b", "/f.yaml", "/o", 1, partition, "--partition");
  SbatchOptions time;
  time.time = "1h";
  refused("/b", "/f.yaml", "/o", 1, time, "--time");
}

}  // namespace
}  // namespace blendbench
