// libFuzzer harness: an MJCF model and an OBJ mesh on arbitrary text, as a run loads a model
// (sim/src/model_files: the files read and checked, then MuJoCo compiling from memory). The input
// is split at the first line "#obj": what comes before is the model (model.xml), what follows a
// mesh it may name as mesh.obj; both are written to a folder of this process's own. The model's
// element checks and the OBJ check run on our code; MuJoCo's compiler then gets what passed them,
// so a crash there is a check missing. Any exception other than InputError, a crash, a leak,
// undefined behaviour, an allocation beyond libFuzzer's limit or a timeout is a finding
// (tests/fuzz/run_fuzzers.sh).

#include <stdlib.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "blendbench/core/input_error.hpp"
#include "blendbench/sim/simulator.hpp"
#include "fuzz_setup.hpp"

namespace {

// The folder each input's files are written to, removed at exit. The path is never destroyed:
// a function-local static string would be destroyed before the atexit handler registered while
// it was being built runs.
const std::string& input_dir() {
  static const std::string* const path = [] {
    // under TMPDIR when set: run_fuzzers.sh points it into its scratch folder, which it removes
    // even when a finding ends the process before this atexit handler runs
    const char* tmp = std::getenv("TMPDIR");
    auto* pattern = new std::string(std::string(tmp != nullptr && *tmp != '\0' ? tmp : "/tmp") + "/blendbench-fuzz-mjcf-XXXXXX");
    if (::mkdtemp(pattern->data()) == nullptr) std::abort();
    std::atexit([] {
      std::error_code ec;
      std::filesystem::remove_all(input_dir(), ec);
    });
    return pattern;
  }();
  return *path;
}

void write(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(text.data(), static_cast<std::streamsize>(text.size()));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::size_t split = text.find("\n#obj\n");
  const std::string model = input_dir() + "/model.xml";
  write(model, text.substr(0, split));
  write(input_dir() + "/mesh.obj", split == std::string::npos ? std::string() : text.substr(split + 6));
  try {
    (void)blendbench::Simulator(model);
  } catch (const blendbench::InputError&) {
    // a clean refusal
  }
  return 0;
}
