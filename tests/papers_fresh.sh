#!/usr/bin/env bash
# The committed paper reproductions (results/papers/<paper>/results.json) must be what this
# build computes: reruns `blendbench reproduce all` without plots and compares every number
# (relative 1e-6, absolute 1e-9) and every string. A planner change that moves a published
# comparison fails here until `build/blendbench reproduce all` is rerun and committed.
#   tests/papers_fresh.sh BLENDBENCH_BINARY COMMITTED_DIR OUT_DIR
set -euo pipefail
binary=$1
committed=$2
out=$3
rm -rf "$out"
"$binary" reproduce all --no-plots --out "$out" >/dev/null
status=0
for fresh in "$out"/*/results.json; do
  paper=$(basename "$(dirname "$fresh")")
  /usr/bin/python3 "$(dirname "$0")/json_close.py" "$committed/$paper/results.json" "$fresh" \
    || status=1
done
if [[ $status -ne 0 ]]; then
  echo "results/papers is stale: rerun 'build/blendbench reproduce all' and commit it" >&2
fi
exit $status
