#!/usr/bin/env bash
# Fuzzes every harness of a BLENDBENCH_FUZZ build for a bounded time each (the test command runs
# it after the sanitizer build's suite). The committed seed corpus (corpus/<harness>/) is read,
# never written: new inputs go to a scratch corpus. A crash, a leak, undefined behaviour, an
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
# system libraries' own findings only (tests/sanitizers/README.md)
export LSAN_OPTIONS="suppressions=$root/tests/sanitizers/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="suppressions=$root/tests/sanitizers/ubsan.supp:print_stacktrace=1:halt_on_error=1"

status=0
for harness in fuzz_scenario fuzz_gcode fuzz_sweep; do
  binary="$build/tests/fuzz/$harness"
  [ -x "$binary" ] || { echo "run_fuzzers: $binary is missing (configure with -DBLENDBENCH_FUZZ=ON)" >&2; exit 2; }
  work="$scratch/$harness"
  mkdir -p "$work/corpus" "$work/artifacts"
  log="$work/log.txt"
  start=$SECONDS
  # -timeout: seconds per input; -rss_limit_mb / -malloc_limit_mb: memory per process / allocation
  if "$binary" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=1024 \
       -print_final_stats=1 -dict="$here/$harness.dict" -artifact_prefix="$work/artifacts/" \
       "$work/corpus" "$here/corpus/$harness" >"$log" 2>&1; then
    stats=$(grep -E '^stat::(number_of_executed_units|new_units_added)' "$log" | sed 's/stat:://' | tr '\n' ' ')
    cov=$(grep -oE 'cov: [0-9]+ ft: [0-9]+' "$log" | tail -1)
    echo "fuzz $harness: ok in $((SECONDS - start)) s; $stats; $cov; corpus $(ls "$work/corpus" | wc -l) + $(ls "$here/corpus/$harness" | wc -l) seeds"
  else
    status=1
    echo "fuzz $harness: FAILED after $((SECONDS - start)) s" >&2
    tail -n 60 "$log" >&2
    for artifact in "$work/artifacts"/*; do
      [ -e "$artifact" ] || continue
      echo "reproducer $(basename "$artifact") ($(wc -c <"$artifact") bytes; rerun: $binary FILE), as C-escaped text:" >&2
      od -An -c "$artifact" | head -n 40 >&2
      echo "base64: $(head -c 4096 "$artifact" | base64 -w0)" >&2
    done
  fi
done
exit $status
