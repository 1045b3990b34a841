#!/usr/bin/python3
"""Every number in a summary says its unit in its key (docs/units.md).

usage: summary_units_test.py BLENDBENCH SOURCE_DIR OUT_DIR

Runs `blendbench run tests/data/tiny.yaml --no-video --no-plots` and walks its summary.json,
then every committed baseline (results/baselines/*.json): each key whose value is a number, or a
list of numbers, must end in one of the unit suffixes of docs/units.md, or be one of the named
unitless counts. A key renamed for a new unit must be renamed everywhere, or this fails on the
file that kept the old name; a new key without its unit fails here too. Exit 0 when all hold.
"""

import glob
import json
import os
import subprocess
import sys

# docs/units.md, "Keys": the unit suffixes, longest first where one ends another
UNIT_SUFFIXES = ["_nm_s_per_rad", "_nm_per_rad", "_mm_per_min", "_rad_s2", "_rad_s", "_deg_s", "_mm_s3", "_mm_s2",
                 "_mm_s", "_per_mm2", "_per_mm", "_per_s", "_mrad", "_deg", "_rad", "_um", "_mm", "_hz", "_nm", "_s",
                 "_j", "_kg", "_percent", "_ratio", "_share", "_ticks", "_per_turn", "_factor"]
# counts and numbers without a unit, by name
UNITLESS = {"index", "corner", "move", "pieces", "points", "points_added", "runs", "moves_merged", "source_line",
            "line", "column", "iterations", "seed004_stretches", "count", "rank", "point", "variants", "real_time_factor_with_video",
            "path_share_below_90pct_speed", "blendbench_baseline", "version",
            # tolerances.json: a metric's bounds, the absolute one in the unit of the metric's key
            "absolute", "relative"}


def numeric(value):
    if isinstance(value, bool):
        return False
    if isinstance(value, (int, float)):
        return True
    return isinstance(value, list) and bool(value) and all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in value)


def walk(node, where, failures):
    if isinstance(node, dict):
        for key, value in node.items():
            name = key.rsplit(".", 1)[-1]  # baselines flatten "metrics.cycle_time_s"
            if numeric(value) and name not in UNITLESS and not any(name.endswith(s) for s in UNIT_SUFFIXES):
                failures.append(f"{where}: '{key}' holds a number but names no unit")
            walk(value, f"{where}.{key}", failures)
    elif isinstance(node, list):
        for i, item in enumerate(node):
            walk(item, f"{where}[{i}]", failures)


def main(argv):
    binary, source, out = argv[1:4]
    run_dir = os.path.join(out, "run")
    r = subprocess.run([binary, "run", os.path.join(source, "tests", "data", "tiny.yaml"), "--no-video", "--no-plots",
                        "--out", run_dir], capture_output=True, text=True)
    failures = []
    if r.returncode != 0:
        failures.append(f"blendbench run exited {r.returncode}:\n{r.stdout}{r.stderr}")
    else:
        with open(os.path.join(run_dir, "summary.json")) as f:
            walk(json.load(f), "summary.json", failures)
    baselines = sorted(glob.glob(os.path.join(source, "results", "baselines", "*.json")))
    for path in baselines:
        with open(path) as f:
            walk(json.load(f), os.path.relpath(path, source), failures)
    print(f"checked the summary of a run and {len(baselines)} baseline files")
    failures = sorted(set(failures))
    for f in failures[:40]:
        print("FAIL:", f)
    if len(failures) > 40:
        print(f"... and {len(failures) - 40} more")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
