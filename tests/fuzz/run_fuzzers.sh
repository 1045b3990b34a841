#!/usr/bin/env bash
# Fuzzes every harness of a BLENDBENCH_FUZZ build for a bounded time each, as many at a time as
# there are cores (the test command runs it after the sanitizer build's suite). The committed
# seed corpus (corpus/<harness>/) is read, never written: new inputs go to a scratch corpus. A crash, a leak, undefined behaviour, an
# exception other than InputError, an allocation over the limit or an input slower than the
# per-input timeout fails the run; the reproducer's path and bytes are printed.
#   tests/fuzz/run_fuzzers.sh BUILD_DIR [SECONDS_PER_HARNESS]
set -euo pipefail
build=$(cd "$1" && pwd)
seconds=${2:-60}
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
scratch=$(mktemp -d "${TMPDIR:-/tmp}/blendbench-fuzz.XXXXXX")
trap 'rm -rf "$scratch"' EXIT
export BLENDBENCH_DATA_DIR="$root"
# the harnesses' own input folders go under the scratch folder, so none survives a finding
mkdir -p "$scratch/tmp"
export TMPDIR="$scratch/tmp"
# system libraries' own findings only (tests/sanitizers/README.md)
export LSAN_OPTIONS="suppressions=$root/tests/sanitizers/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="suppressions=$root/tests/sanitizers/ubsan.supp:print_stacktrace=1:halt_on_error=1"

# fuzz_one HARNESS: fuzzes one harness; prints its one-line result, or the failure with the
# reproducer; returns non-zero on a finding
fuzz_one() {
  local harness=$1 binary="$build/tests/fuzz/$1" work="$scratch/$1" start=$SECONDS dict=$1 timeout=10
  # fuzz_plan reads G-code (the reader's dictionary), and its inputs are planned: a second or
  # more each under the sanitizers
  if [ "$harness" = fuzz_plan ]; then
    dict=fuzz_gcode
    timeout=30
  fi
  [ -x "$binary" ] || { echo "run_fuzzers: $binary is missing (configure with -DBLENDBENCH_FUZZ=ON)" >&2; return 2; }
  mkdir -p "$work/corpus" "$work/artifacts"
  # -timeout: seconds per input; -rss_limit_mb / -malloc_limit_mb: memory per process / allocation
  if "$binary" -max_total_time="$seconds" -timeout="$timeout" -rss_limit_mb=2048 -malloc_limit_mb=1024 \
       -print_final_stats=1 -dict="$here/$dict.dict" -artifact_prefix="$work/artifacts/" \
       "$work/corpus" "$here/corpus/$harness" >"$work/log.txt" 2>&1 </dev/null; then
    local stats cov
    stats=$(grep -E '^stat::(number_of_executed_units|new_units_added)' "$work/log.txt" | sed 's/stat:://' | tr '\n' ' ' || true)
    cov=$(grep -oE 'cov: [0-9]+ ft: [0-9]+' "$work/log.txt" | tail -1 || true)
    echo "fuzz $harness: ok in $((SECONDS - start)) s; ${stats}${cov}; corpus $(ls "$work/corpus" | wc -l) new + $(ls "$here/corpus/$harness" | wc -l) seeds"
    return 0
  fi
  {
    echo "fuzz $harness: FAILED after $((SECONDS - start)) s"
    tail -n 60 "$work/log.txt"
    for artifact in "$work/artifacts"/*; do
      [ -e "$artifact" ] || continue
      echo "reproducer $(basename "$artifact") ($(wc -c <"$artifact") bytes; rerun: $binary FILE), as C-escaped text:"
      od -An -c "$artifact" | head -n 40
      echo "base64: $(head -c 4096 "$artifact" | base64 -w0)"
    done
  } >&2
  return 1
}

# the harnesses, as many at a time as there are cores; each reports when it ends
harnesses=(fuzz_scenario fuzz_gcode fuzz_plan fuzz_sweep fuzz_urdf fuzz_mjcf fuzz_check)
parallel=$(nproc 2>/dev/null || echo 1)
status=0
pids=()
for harness in "${harnesses[@]}"; do
  fuzz_one "$harness" &
  pids+=($!)
  if [ ${#pids[@]} -ge "$parallel" ]; then
    wait "${pids[0]}" || status=1
    pids=("${pids[@]:1}")
  fi
done
for pid in "${pids[@]}"; do wait "$pid" || status=1; done
exit $status
