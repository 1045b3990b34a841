// libFuzzer harness: `check`'s JSON on arbitrary text. The input is split at the first line
// "====": the run's summary before it, the baseline after (none: the baseline made from the
// summary itself). Both are parsed as `check` reads them (a parser error is a refusal), the
// summary is validated, a baseline made from it, and the run checked against both baselines under
// the committed tolerance file; the table of what moved is printed to nowhere. Any exception
// other than InputError (nlohmann's "cannot use value() with array" was one), a crash, a leak,
// undefined behaviour, an allocation beyond libFuzzer's limit or a timeout is a finding
// (tests/fuzz/run_fuzzers.sh).

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "blendbench/core/input_error.hpp"
#include "blendbench/report/check.hpp"
#include "fuzz_setup.hpp"

namespace {

// The committed tolerance file, read once.
const std::vector<blendbench::MetricTolerance>& tolerances() {
  static const std::vector<blendbench::MetricTolerance> parsed = [] {
    std::ifstream in(BLENDBENCH_FUZZ_BASE_DIR "/results/baselines/tolerances.json");
    std::stringstream text;
    text << in.rdbuf();
    return blendbench::parse_tolerances(nlohmann::json::parse(text.str()), "tolerances.json");
  }();
  return parsed;
}

// JSON as `check` reads it: a parser error (a number overflow included) is a refusal.
bool parse(const std::string& text, nlohmann::json& out) {
  try {
    out = nlohmann::json::parse(text);
    return true;
  } catch (const nlohmann::json::exception&) {
    return false;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::size_t split = text.find("\n====\n");
  nlohmann::json summary;
  if (!parse(text.substr(0, split), summary)) return 0;
  try {
    blendbench::validate_run_summary(summary, "summary.json");
    const nlohmann::json own = blendbench::make_baseline(summary, tolerances());
    (void)blendbench::moved_table(blendbench::check_run(summary, own, tolerances(), "own.json"));
    nlohmann::json baseline;
    if (split != std::string::npos && parse(text.substr(split + 6), baseline)) {
      (void)blendbench::moved_table(blendbench::check_run(summary, baseline, tolerances(), "baseline.json"));
    }
  } catch (const blendbench::InputError&) {
    // a clean refusal
  }
  return 0;
}
