#!/usr/bin/env bash
# Regression metrics in CI: runs a scenario without video or plots and checks its metrics
# against the committed baseline (results/baselines/<scenario>.json).
#   tests/regression.sh BLENDBENCH_BINARY SCENARIO OUT_DIR
set -euo pipefail
binary=$1
scenario=$2
out=$3
rm -rf "$out"
"$binary" run "$scenario" --no-video --no-plots --out "$out"
"$binary" check "$out"
