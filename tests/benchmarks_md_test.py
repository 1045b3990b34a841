#!/usr/bin/python3
"""tools/benchmarks_md.py on Google Benchmark JSON made here: the page states the machine and
date once, one table per program, each time column in one unit with one count of decimals, the
median of repetitions with its coefficient of variation, user counters, and errors shown.

usage: benchmarks_md_test.py SOURCE_DIR OUT_DIR
"""

import json
import os
import subprocess
import sys

failures = []


def expect(condition, what):
    if not condition:
        failures.append(what)


def main(argv):
    source, out = argv[1:3]
    os.makedirs(out, exist_ok=True)
    context = {"date": "2026-12-07T10:00:00+00:00", "host_name": "vm", "num_cpus": 2, "mhz_per_cpu": 2600,
               "cpu_scaling_enabled": False, "caches": [{"type": "Data", "level": 1, "size": 49152}],
               "load_avg": [1.5, 2.0, 2.5], "library_build_type": "release"}
    fast = {"context": context, "benchmarks": [
        {"name": "BM_A", "run_name": "BM_A", "run_type": "iteration", "iterations": 1000, "real_time": 1500.0,
         "cpu_time": 1400.0, "time_unit": "ns", "items_per_second": 2.5e6},
        {"name": "BM_B/8", "run_name": "BM_B/8", "run_type": "iteration", "iterations": 10, "real_time": 2.25,
         "cpu_time": 2.0, "time_unit": "ms"},
        {"name": "BM_C", "run_name": "BM_C", "run_type": "iteration", "iterations": 0, "real_time": 0, "cpu_time": 0,
         "time_unit": "ns", "error_occurred": True, "error_message": "unreachable pose"}]}
    # three repetitions: the median (not the first) is shown, CV = stddev / mean
    reps = [{"name": "BM_R", "run_name": "BM_R", "run_type": "iteration", "iterations": 5, "real_time": t, "cpu_time": t,
             "time_unit": "us", "repetitions": 3, "repetition_index": i} for i, t in enumerate([30.0, 10.0, 20.0])]
    reps += [{"name": "BM_R_mean", "run_name": "BM_R", "run_type": "aggregate", "aggregate_name": "mean",
              "iterations": 3, "real_time": 20.0, "cpu_time": 20.0, "time_unit": "us"},
             {"name": "BM_R_median", "run_name": "BM_R", "run_type": "aggregate", "aggregate_name": "median",
              "iterations": 3, "real_time": 20.0, "cpu_time": 19.0, "time_unit": "us"},
             {"name": "BM_R_stddev", "run_name": "BM_R", "run_type": "aggregate", "aggregate_name": "stddev",
              "iterations": 3, "real_time": 10.0, "cpu_time": 10.0, "time_unit": "us"}]
    with open(os.path.join(out, "bench_fast.json"), "w") as f:
        json.dump(fast, f)
    with open(os.path.join(out, "bench_reps.json"), "w") as f:
        json.dump({"context": context, "benchmarks": reps}, f)
    page_file = os.path.join(out, "benchmarks.md")
    r = subprocess.run(["/usr/bin/python3", os.path.join(source, "tools", "benchmarks_md.py"),
                        os.path.join(out, "bench_fast.json"), os.path.join(out, "bench_reps.json"), "--out", page_file],
                       capture_output=True, text=True)
    expect(r.returncode == 0, f"exit {r.returncode}: {r.stderr}")
    page = open(page_file).read() if os.path.exists(page_file) else ""
    expect(page.count("2026-12-07T10:00:00+00:00") == 1, "the date stated once")
    expect(page.count("2 CPUs at 2600 MHz") == 1, "the machine stated once")
    expect("## bench_fast" in page and "## bench_reps" in page, "a table per program")
    # smallest time 1.4 µs: the table is in µs, with 2 decimals (three significant digits of 1.40)
    expect("### BM_A" in page and "### BM_B" in page, "a table per family")
    expect("| benchmark | wall [µs] | CPU [µs] | iterations | items_per_second |" in page, "BM_A's header")
    expect("| `BM_A` | 1.50 | 1.40 | 1000 | 2.5 M |" in page, "BM_A's row (µs, 2 decimals, counter)")
    expect("| `BM_B/8` | 2.25 | 2.00 | 10 |" in page, "BM_B's row in its own table's unit (ms)")
    expect("| `BM_C` | — | — | 0 | unreachable pose |" in page, "an error shown")
    expect("| `BM_R` | 20.0 | 19.0 | 5 | 50.0 % |" in page, "the median and CV of repetitions")
    if failures:
        print(page)
    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
