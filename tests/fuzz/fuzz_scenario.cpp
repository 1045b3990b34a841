// libFuzzer harness: the scenario loader on arbitrary text. parse_scenario either returns a
// scenario (whose variants' programs are then built, as every command does next) or throws
// InputError; any other exception, a crash, a leak, undefined behaviour, an allocation beyond
// libFuzzer's limit or a timeout is a finding (tests/fuzz/run_fuzzers.sh).

#include <cstddef>
#include <cstdint>
#include <string>

#include "blendbench/core/input_error.hpp"
#include "blendbench/io/scenario.hpp"
#include "fuzz_setup.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    // relative model and G-code paths resolve against the data folder, as for a scenario in it
    const blendbench::Scenario scenario = blendbench::parse_scenario(text, "fuzz.yaml", BLENDBENCH_FUZZ_BASE_DIR);
    for (const blendbench::Variant& variant : scenario.variants) (void)blendbench::program_for(scenario, variant);
  } catch (const blendbench::InputError&) {
    // a clean refusal
  }
  return 0;
}
