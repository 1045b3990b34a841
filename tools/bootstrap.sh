#!/usr/bin/env bash
# One-command set-up for BlendBench on Debian 12: installs the Debian packages that are
# missing, configures and builds in Release, then either runs the default scenario ("run") or
# the whole test suite ("test").
#
#   bash tools/bootstrap.sh run [extra arguments for `blendbench run`]
#   bash tools/bootstrap.sh test
#
# "run" builds only the program and the libraries it links (no test suite, no benchmarks), so the
# first run on a fresh machine waits for what it needs; "test" builds everything.
#
# "test" runs, in order: the GCC Release build (build/) and its suite; a clang build of the whole
# project with assertions on, AddressSanitizer and UndefinedBehaviorSanitizer (build-clang/,
# Debug at -O1) and the same suite there; then each libFuzzer harness for
# BLENDBENCH_FUZZ_SECONDS (default 60) s. It prints how long each step took.
set -euo pipefail

mode=${1:-}
shift || true
case "$mode" in
  run|test) ;;
  *) echo "usage: bash tools/bootstrap.sh run|test [arguments]" >&2; exit 2 ;;
esac

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"

packages=(
  build-essential cmake ninja-build pkg-config ccache
  libeigen3-dev libmujoco-dev libosmesa6-dev liburdfdom-dev libyaml-dev libyaml-cpp-dev
  libcli11-dev nlohmann-json3-dev libexpat1-dev googletest libgtest-dev libbenchmark-dev
  ffmpeg python3 python3-matplotlib python3-numpy python3-pil python3-yaml
  libjs-chart.js libjs-three
)
# the test suite and benchmarks need GoogleTest and Google Benchmark; the suite also brings up a
# one-machine Slurm for the sweep's job-array test, opens a report in headless Chromium, and the
# sanitizer and fuzzing build needs clang with its sanitizer run-times
if [ "$mode" = test ]; then
  packages+=(googletest libgtest-dev libbenchmark-dev slurm-wlm munge clang libclang-rt-14-dev chromium)
fi
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "bootstrap: installing ${missing[*]}"
  if [ "$(id -u)" -eq 0 ]; then
    sudo=()
  elif command -v sudo >/dev/null 2>&1; then
    sudo=(sudo)
  else
    echo "bootstrap: these Debian packages are missing and this user cannot install them:" >&2
    echo "  ${missing[*]}" >&2
    echo "ask an administrator to run: apt-get install ${missing[*]}" >&2
    exit 1
  fi
  export DEBIAN_FRONTEND=noninteractive
  "${sudo[@]}" apt-get update -qq
  "${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

jobs=$(nproc 2>/dev/null || echo 2)
# how long each step took (wall clock, and the CPU time of the processes it ran), printed at
# the end of "test"
step_times=()
cpu_file=$(mktemp)
trap 'rm -f "$cpu_file"' EXIT
cpu_seconds=0
update_cpu() {  # user + system seconds of this shell's finished children (`times` runs here, not in a subshell)
  times >"$cpu_file"
  cpu_seconds=$(awk 'NR == 2 { n = 0; for (i = 1; i <= 2; ++i) { split($i, t, /[ms]/); n += t[1] * 60 + t[2] } printf "%d", n }' "$cpu_file")
}
step() {
  local name=$1 start=$SECONDS before
  shift
  update_cpu
  before=$cpu_seconds
  "$@"
  update_cpu
  step_times+=("$name $((SECONDS - start)) s (CPU $((cpu_seconds - before)) s)")
}

# configure (once) and build: build_in DIR CMAKE_ARGUMENTS... [-- TARGETS...] Compiles go through ccache with
# paths relative to the checkout, so a second build of the same sources (a re-run, another clone
# on the same machine) reuses the objects; on a fresh machine it costs what a plain build does.
export CCACHE_BASEDIR="$root"
build_in() {
  local dir=$1 configure=() targets=()
  shift
  while [ $# -gt 0 ] && [ "$1" != -- ]; do configure+=("$1"); shift; done
  [ $# -gt 0 ] && shift
  targets=("$@")
  cmake -S . -B "$dir" -G Ninja -DCMAKE_CXX_COMPILER_LAUNCHER=ccache "${configure[@]}"
  cmake --build "$dir" -j "$jobs" ${targets[@]+--target "${targets[@]}"}
}

if [ "$mode" = run ]; then
  # the program alone: its libraries, no tests or benchmarks (a later "test" turns them back on)
  step "gcc build" build_in build -DCMAKE_BUILD_TYPE=Release -DBLENDBENCH_TESTS=OFF -DBLENDBENCH_BENCH=OFF -- blendbench
  echo "bootstrap: built in ${step_times[0]#gcc build }"
  exec build/blendbench run "$@"
fi

step "gcc build" build_in build -DCMAKE_BUILD_TYPE=Release -DBLENDBENCH_TESTS=ON -DBLENDBENCH_BENCH=ON

step "gcc ctest" ctest --test-dir build --output-on-failure -j "$jobs" "$@"
# clang, assertions on, ASan + UBSan, libFuzzer's coverage (cmake/BlendbenchSanitize.cmake)
step "clang build" build_in build-clang -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=Debug -DBLENDBENCH_FUZZ=ON -DBLENDBENCH_TESTS=ON -DBLENDBENCH_BENCH=ON
step "clang ctest" ctest --test-dir build-clang --output-on-failure -j "$jobs" "$@"
step "fuzzing" bash tests/fuzz/run_fuzzers.sh build-clang "${BLENDBENCH_FUZZ_SECONDS:-60}"
echo "bootstrap: test steps: $(IFS=';'; echo "${step_times[*]}" | sed 's/;/; /g')"
