#!/usr/bin/env bash
# The regression gate in CI: runs a scenario without video or plots and checks its metrics
# against the committed baseline (results/baselines/<scenario>.json) under the tolerances of
# results/baselines/tolerances.json.
#   tests/regression.sh BLENDBENCH_BINARY SCENARIO OUT_DIR
# A variant that is not clean makes `run` exit 1; `check` then decides (the baseline records
# each variant's status). Bad input (exit 2) stops here.
set -uo pipefail
binary=$1
scenario=$2
out=$3
rm -rf "$out"
"$binary" run "$scenario" --no-video --no-plots --out "$out"
status=$?
if [ "$status" -ne 0 ] && [ "$status" -ne 1 ]; then
  echo "regression.sh: blendbench run $scenario exited $status" >&2
  exit "$status"
fi
exec "$binary" check "$out"
