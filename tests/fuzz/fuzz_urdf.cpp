// libFuzzer harness: the URDF reader on arbitrary text, as a run reads a URDF alone: the chain
// (load_urdf_chain) and the MuJoCo model built from it with an inertia estimate
// (model_from_urdf), which MuJoCo then compiles from memory (Simulator::from_xml_string) — so the
// XML the writer produced from hostile names must parse, and hostile values must be refused by
// the model's checks. Each input goes through a file of this process's own (the readers take
// paths). Any exception other than InputError, a crash, a leak, undefined behaviour, an
// allocation beyond libFuzzer's limit or a timeout is a finding (tests/fuzz/run_fuzzers.sh).

#include <stdlib.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <string>

#include "blendbench/core/input_error.hpp"
#include "blendbench/io/urdf_chain.hpp"
#include "blendbench/io/urdf_model.hpp"
#include "blendbench/sim/simulator.hpp"
#include "fuzz_setup.hpp"

namespace {

// The file each input is written to, removed at exit. The path is never destroyed: a
// function-local static string would be destroyed before the atexit handler registered while it
// was being built runs.
const std::string& input_file() {
  static const std::string* const path = [] {
    // under TMPDIR when set: run_fuzzers.sh points it into its scratch folder, which it removes
    // even when a finding ends the process before this atexit handler runs
    const char* tmp = std::getenv("TMPDIR");
    auto* pattern = new std::string(std::string(tmp != nullptr && *tmp != '\0' ? tmp : "/tmp") + "/blendbench-fuzz-urdf-XXXXXX");
    const int fd = ::mkstemp(pattern->data());
    if (fd < 0) std::abort();
    ::close(fd);
    std::atexit([] { ::unlink(input_file().c_str()); });
    return pattern;
  }();
  return *path;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::ofstream(input_file(), std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  try {
    (void)blendbench::load_urdf_chain(input_file());
  } catch (const blendbench::InputError&) {
    // a clean refusal
  }
  try {
    const blendbench::UrdfModel built = blendbench::model_from_urdf(input_file(), "", "", 29);
    (void)blendbench::Simulator::from_xml_string(built.mjcf, {}, input_file());
  } catch (const blendbench::InputError&) {
    // a clean refusal
  }
  return 0;
}
