#!/usr/bin/env bash
# The gate can fail: a copy of scenarios/corners/line_line_90deg.yaml with half the jerk limit
# (a deliberately worse planner setting, every variant slower through the corner) keeps the
# scenario's name, so `blendbench check` compares it with the committed baseline: it must exit
# 1 and name metrics.cycle_time_s as a regression (not a missing variant or a status). Then the
# two errors that say what to run: a baseline of another scenario, and a missing baseline
# (exit 2 each, with the command in the message).
#   tests/regression_gate_fails.sh BLENDBENCH_BINARY SOURCE_DIR OUT_DIR
set -uo pipefail
binary=$1
source=$2
out=$3
rm -rf "$out"
mkdir -p "$out"
fail() { echo "regression_gate_fails: $*" >&2; exit 1; }

sed 's/jerk: 50000/jerk: 25000/' "$source/scenarios/corners/line_line_90deg.yaml" > "$out/worse.yaml"
grep -q 'jerk: 25000' "$out/worse.yaml" || fail "the copy did not change the jerk limit"
"$binary" run "$out/worse.yaml" --no-video --no-plots --out "$out/run" > "$out/run.log" 2>&1
[ $? -le 1 ] || { cat "$out/run.log"; fail "the run of the worse copy did not complete"; }
"$binary" check "$out/run" > "$out/check.log" 2>&1
code=$?
cat "$out/check.log"
[ "$code" -eq 1 ] || fail "check exited $code on the worse planner setting, expected 1"
grep -q '^REGRESSION: exact_stop: metrics.cycle_time_s = ' "$out/check.log" || fail "check did not name metrics.cycle_time_s"
grep -q 'REGRESSION: .*plan.planned_cycle_time_s' "$out/check.log" || fail "check did not name plan.planned_cycle_time_s"
grep -q 'variant missing\|: status ' "$out/check.log" && fail "the regression is a missing variant or a status, not a metric"
grep -q 'metrics.cycle_time_s .* REGRESSION$' "$out/check.log" || fail "the table of what moved lacks the cycle time"

# a baseline of another scenario
"$binary" check "$out/run" --baseline "$source/results/baselines/default.json" > "$out/other.log" 2>&1
code=$?
cat "$out/other.log"
[ "$code" -eq 2 ] || fail "check against another scenario's baseline exited $code, expected 2"
grep -q "baseline of scenario 'default', but the run is of scenario 'line_line_90deg'" "$out/other.log" || fail "no clear message for another scenario's baseline"
grep -q 'results/baselines/line_line_90deg.json' "$out/other.log" || fail "the message does not say which baseline to use"

# a missing baseline: the same run renamed
mkdir -p "$out/renamed"
/usr/bin/python3 -c "
import json, sys
s = json.load(open(sys.argv[1])); s['scenario'] = 'gate_test_without_baseline'
json.dump(s, open(sys.argv[2], 'w'))" "$out/run/summary.json" "$out/renamed/summary.json"
"$binary" check "$out/renamed" > "$out/missing.log" 2>&1
code=$?
cat "$out/missing.log"
[ "$code" -eq 2 ] || fail "check without a baseline exited $code, expected 2"
grep -q "no baseline for scenario 'gate_test_without_baseline'" "$out/missing.log" || fail "no clear message for a missing baseline"
grep -q -- "check $out/renamed --update" "$out/missing.log" || fail "the message does not say what to run"
echo "regression_gate_fails: the gate failed as it must"
