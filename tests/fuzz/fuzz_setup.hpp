#pragma once
// What every harness needs before the first input: the data folder (models, scenarios) that
// relative file names in a scenario or sweep resolve against, so a reproducer reruns as
// `HARNESS FILE` without the environment of run_fuzzers.sh.

#include <cstdlib>

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  setenv("BLENDBENCH_DATA_DIR", BLENDBENCH_FUZZ_BASE_DIR, 0);
  return 0;
}
