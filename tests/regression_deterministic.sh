#!/usr/bin/env bash
# Runs are deterministic: one scenario run twice on this machine gives bit-identical metrics
# (summary.json equal as text once the wall-clock "timings" blocks and *_wall_time_s figures
# are removed; nlohmann writes doubles with round-trip precision, so equal text is equal bits).
#   tests/regression_deterministic.sh BLENDBENCH_BINARY SCENARIO OUT_DIR
set -euo pipefail
binary=$1
scenario=$2
out=$3
rm -rf "$out"
for i in 1 2; do
  "$binary" run "$scenario" --no-video --no-plots --out "$out/run$i" > "$out.run$i.log"
done
/usr/bin/python3 - "$out/run1/summary.json" "$out/run2/summary.json" <<'PY'
import json, sys

def strip(v):
    if isinstance(v, dict):
        return {k: strip(x) for k, x in v.items() if k != "timings" and not k.endswith("wall_time_s")}
    if isinstance(v, list):
        return [strip(x) for x in v]
    return v

a, b = (strip(json.load(open(f))) for f in sys.argv[1:3])
if a != b:
    def diff(x, y, path=""):
        if isinstance(x, dict) and isinstance(y, dict):
            for k in sorted(set(x) | set(y)):
                yield from diff(x.get(k), y.get(k), f"{path}.{k}")
        elif isinstance(x, list) and isinstance(y, list) and len(x) == len(y):
            for i, (p, q) in enumerate(zip(x, y)):
                yield from diff(p, q, f"{path}[{i}]")
        elif x != y:
            yield f"{path}: {x!r} != {y!r}"
    for line in list(diff(a, b))[:20]:
        print("differs:", line)
    sys.exit(1)
variants = a["variants"]
print(f"deterministic: {len(variants)} variants, every metric bit-identical in two runs")
PY
