#!/usr/bin/python3
"""docs/benchmarks.md from Google Benchmark's JSON output: tables, not prose.

usage:
  /usr/bin/python3 tools/benchmarks_md.py --run BUILD_DIR [--min-time S] [--out docs/benchmarks.md]
      runs every bench/bench_* of BUILD_DIR with --benchmark_format=json (one after the other),
      keeps their JSON in a temporary folder (or --keep DIR) and writes the page;
  /usr/bin/python3 tools/benchmarks_md.py FILE.json... [--out docs/benchmarks.md]
      writes the page from JSON files already made (`bench_x --benchmark_out=x.json
      --benchmark_out_format=json`).

The page states the machine and the date once (from the JSON's context: host, CPUs, MHz,
caches, load average when the run started, library build type; the CPU model from
/proc/cpuinfo when --run), then per benchmark program one table per family of benchmarks (the name before
its first '/'): each benchmark's wall and CPU time per iteration in a unit chosen per table (ns, µs, ms or s, so one column reads in one unit
with one count of decimals), its iterations, and its user counters (items_per_second etc.).
With repetitions, the median is shown and the coefficient of variation (stddev / mean) added.
The history of the figures is git's, not this page's.
"""

import argparse
import glob
import json
import os
import platform
import subprocess
import sys
import tempfile

TO_NS = {"ns": 1.0, "us": 1e3, "ms": 1e6, "s": 1e9}
UNITS = [("s", 1e9), ("ms", 1e6), ("µs", 1e3), ("ns", 1.0)]
# keys of a benchmark entry that are not user counters
STANDARD = {"name", "family_index", "per_family_instance_index", "run_name", "run_type", "repetitions",
            "repetition_index", "threads", "iterations", "real_time", "cpu_time", "time_unit", "aggregate_name",
            "aggregate_unit", "label", "error_occurred", "error_message", "big_o", "rms"}


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def unit_for(values_ns):
    """The largest unit in which the smallest value is at least 1 (ns at the least)."""
    smallest = min((v for v in values_ns if v > 0), default=1.0)
    for name, scale in UNITS:
        if smallest >= scale:
            return name, scale
    return "ns", 1.0


def decimals_for(values):
    """One count of decimals for a column: three significant digits of its smallest value."""
    smallest = min((abs(v) for v in values if v), default=1.0)
    digits = 0
    while smallest * 10 ** digits < 100 and digits < 6:
        digits += 1
    return digits


def counter_text(value):
    if isinstance(value, (int, float)):
        for suffix, scale in (("G", 1e9), ("M", 1e6), ("k", 1e3)):
            if abs(value) >= scale:
                return f"{value / scale:.3g} {suffix}"
        return f"{value:.3g}"
    return str(value)


def rows_of(benchmarks):
    """One row per benchmark: (name, real_ns, cpu_ns, iterations, counters, cv or None). With
    repetitions the median, and the CV from the mean and stddev aggregates."""
    plain = [b for b in benchmarks if b.get("run_type", "iteration") == "iteration" and not b.get("error_occurred")]
    aggregates = {}
    for b in benchmarks:
        if b.get("run_type") == "aggregate":
            aggregates.setdefault(b["run_name"], {})[b.get("aggregate_name")] = b
    rows = []
    seen = set()
    for b in plain:
        name = b.get("run_name", b["name"])
        if name in seen:
            continue
        seen.add(name)
        entry, cv = b, None
        agg = aggregates.get(name, {})
        if "median" in agg:
            entry = agg["median"]
        if "mean" in agg and "stddev" in agg and agg["mean"]["real_time"] > 0:
            cv = agg["stddev"]["real_time"] / agg["mean"]["real_time"]
        scale = TO_NS[entry.get("time_unit", "ns")]
        counters = {k: v for k, v in entry.items() if k not in STANDARD}
        rows.append((name, entry["real_time"] * scale, entry["cpu_time"] * scale, b["iterations"], counters, cv))
    for b in benchmarks:
        if b.get("error_occurred"):
            rows.append((b["name"], None, None, 0, {"error": b.get("error_message", "")}, None))
    return rows


def family_table(rows):
    """One Markdown table of rows of one family: one time unit and one count of decimals for its
    time columns, its own counter columns."""
    timed = [r for r in rows if r[1] is not None]
    unit, scale = unit_for([r[1] for r in timed] + [r[2] for r in timed])
    digits = decimals_for([r[1] / scale for r in timed] + [r[2] / scale for r in timed])
    counters = sorted({k for r in rows for k in r[4]})
    with_cv = any(r[5] is not None for r in rows)
    head = ["benchmark", f"wall [{unit}]", f"CPU [{unit}]", "iterations"] + (["CV"] if with_cv else []) + counters
    out = ["| " + " | ".join(head) + " |", "|" + "|".join(["---"] + ["---:"] * (len(head) - 1)) + "|"]
    for name, real, cpu, iterations, ctr, cv in rows:
        cells = [f"`{name}`",
                 "—" if real is None else f"{real / scale:.{digits}f}",
                 "—" if cpu is None else f"{cpu / scale:.{digits}f}",
                 str(iterations)]
        if with_cv:
            cells.append("—" if cv is None else f"{100 * cv:.1f} %")
        cells += [counter_text(ctr[k]) if k in ctr else "" for k in counters]
        out.append("| " + " | ".join(cells) + " |")
    return out


def table(program, data):
    """A program's section: one table per benchmark family (the name before its first '/'), so
    the figures of a table are of one magnitude and share a unit."""
    rows = rows_of(data.get("benchmarks", []))
    out = [f"## {program}", ""]
    if not rows:
        return out + ["(no benchmark ran)", ""]
    families = {}
    for r in rows:
        families.setdefault(r[0].split("/", 1)[0], []).append(r)
    # families of one benchmark each share a table while their times stay within a factor
    # MAX_SPREAD of each other (one unit still reads well)
    groups = []
    for family, members in families.items():
        last = groups[-1] if groups else None
        if len(members) == 1 and last and last[1] and spread(last[2] + members) <= MAX_SPREAD:
            last[2].extend(members)
            last[0].append(family)
        else:
            groups.append(([family], len(members) == 1, list(members)))
    for names, _, members in groups:
        if len(groups) > 1:
            out += ["### " + (names[0] if len(names) == 1 else f"{names[0]} … {names[-1]}"), ""]
        out += family_table(members) + [""]
    return out


MAX_SPREAD = 1000


def spread(rows):
    times = [r[1] for r in rows if r[1]]
    return max(times) / min(times) if times else 1.0


def page(results, model):
    """The Markdown page from [(program, json)], the machine and date stated once."""
    context = results[0][1].get("context", {}) if results else {}
    caches = ", ".join(f'L{c["level"]} {c["type"].lower()} {c["size"] // 1024} KiB' for c in context.get("caches", []))
    load = context.get("load_avg")
    lines = [
        "# Benchmarks",
        "",
        "Generated by `tools/benchmarks_md.py` from Google Benchmark's JSON output (`bench/`); do not edit",
        "by hand: re-run `/usr/bin/python3 tools/benchmarks_md.py --run build` on a quiet machine and commit",
        "the page. Times are per iteration; compare figures only within one page (one machine, one run).",
        "",
        f"- machine: {model}, {context.get('num_cpus', '?')} CPUs at {context.get('mhz_per_cpu', '?')} MHz"
        + (f" ({caches})" if caches else ""),
        f"- date: {context.get('date', '?')}",
        f"- load average when the run started: {', '.join(f'{x:.2f}' for x in load)} (1, 5, 15 min)" if load else
        "- load average: not recorded",
        f"- Google Benchmark library build: {context.get('library_build_type', '?')}; CPU frequency scaling "
        f"{'on' if context.get('cpu_scaling_enabled') else 'off'}",
        "",
    ]
    for program, data in results:
        lines += table(program, data)
    return "\n".join(lines).rstrip() + "\n"


def run_benchmarks(build_dir, min_time, work):
    programs = sorted(p for p in glob.glob(os.path.join(build_dir, "bench", "bench_*"))
                      if os.path.isfile(p) and os.access(p, os.X_OK))
    if not programs:
        sys.exit(f"benchmarks_md: no bench/bench_* programs in {build_dir} (build them: cmake --build {build_dir})")
    results = []
    for k, program in enumerate(programs):
        name = os.path.basename(program)
        out = os.path.join(work, name + ".json")
        print(f"[{k + 1}/{len(programs)}] {name}", file=sys.stderr, flush=True)
        args = [program, f"--benchmark_out={out}", "--benchmark_out_format=json"]
        if min_time:
            args.append(f"--benchmark_min_time={min_time}")
        subprocess.run(args, check=True, stdout=subprocess.DEVNULL)
        with open(out) as f:
            results.append((name, json.load(f)))
    return results


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("json", nargs="*", help="Google Benchmark JSON files")
    parser.add_argument("--run", metavar="BUILD_DIR", help="run every bench/bench_* of BUILD_DIR first")
    parser.add_argument("--min-time", type=float, default=0, help="--benchmark_min_time for --run (s)")
    parser.add_argument("--keep", metavar="DIR", help="with --run: keep the programs' JSON files in DIR")
    parser.add_argument("--out", default="docs/benchmarks.md")
    args = parser.parse_args(argv[1:])
    if bool(args.run) == bool(args.json):
        parser.error("give --run BUILD_DIR or JSON files, not both")
    with tempfile.TemporaryDirectory(prefix="benchmarks_md-") as work:
        if args.run:
            if args.keep:
                os.makedirs(args.keep, exist_ok=True)
            results = run_benchmarks(args.run, args.min_time, args.keep or work)
        else:
            results = []
            for path in args.json:
                with open(path) as f:
                    results.append((os.path.splitext(os.path.basename(path))[0], json.load(f)))
    text = page(results, cpu_model())
    # written whole and renamed, never half-written
    tmp = args.out + ".tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, args.out)
    print(f"benchmarks_md: {args.out} ({sum(len(rows_of(d.get('benchmarks', []))) for _, d in results)} benchmarks)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
