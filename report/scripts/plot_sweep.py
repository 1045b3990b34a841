#!/usr/bin/python3
"""The Pareto plot of a BlendBench sweep.

usage: /usr/bin/python3 plot_sweep.py SWEEP_DIR

Reads SWEEP_DIR/sweep.json (written by `blendbench sweep`) and writes SWEEP_DIR/pareto.png: per
method every row that ran ok as a point of (x, y) = the sweep's Pareto metrics, filled when it
meets the constraints and hollow when not, its Pareto front as a step line, its best setting under
the constraints as a star, and the constraint bounds on x or y as dashed lines. The fronts and the
best rows are the ones sweep.json names (computed by the program), not recomputed here.
"""

import json
import os
import sys
import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter  # noqa: E402
from plotio import method_colour, method_marker, metric_label, save_png  # noqa: E402

DPI = 110


def constraint_bounds(constraints, metric):
    """The bounds of the constraints on one metric ("metric <= 0.5" -> 0.5)."""
    bounds = []
    for text in constraints:
        for op in ("<=", ">=", "<", ">"):
            if op in text:
                name, value = text.split(op, 1)
                if name.strip() == metric:
                    bounds.append(float(value))
                break
    return bounds


def main(sweep_dir):
    with open(os.path.join(sweep_dir, "sweep.json")) as f:
        sweep = json.load(f)
    x_name, y_name = sweep["pareto"]["x"], sweep["pareto"]["y"]
    rows = sweep["rows"]
    # a row's metrics are a list in the order of sweep["metrics"]
    names = sweep["metrics"]
    for r in rows:
        r["metrics"] = dict(zip(names, r["metrics"]))

    fig, ax = plt.subplots(figsize=(8.5, 6))
    ys = []
    for k, method in enumerate(sweep["methods"]):
        # the method's colour and marker (plotio: the same in every figure), and a size per
        # method, so methods whose points coincide stay visible
        colour = method_colour(method["method"])
        marker = method_marker(method["method"])
        size = 70 - 12 * (k % 4)
        mine = [r for r in rows if r["method"] == method["method"] and r["status"] == "ok"]
        mine = [r for r in mine if r["metrics"].get(x_name) is not None and r["metrics"].get(y_name) is not None]
        meeting = [r for r in mine if r["meets_constraints"]]
        missing = [r for r in mine if not r["meets_constraints"]]
        label = f'{method["method"]} ({method["meeting_constraints"]}/{method["rows"]} meet)'
        ys += [r["metrics"][y_name] for r in mine]
        ax.scatter([r["metrics"][x_name] for r in meeting], [r["metrics"][y_name] for r in meeting], s=size,
                   marker=marker, color=colour, alpha=0.8, label=label, zorder=3)
        ax.scatter([r["metrics"][x_name] for r in missing], [r["metrics"][y_name] for r in missing], s=size,
                   marker=marker, facecolors="none", edgecolors=colour, zorder=3, label=None if meeting else label)
        front = [rows[i] for i in method["pareto_front"]]
        if front:
            ax.step([r["metrics"][x_name] for r in front], [r["metrics"][y_name] for r in front], where="post",
                    color=colour, lw=1.2, alpha=0.8, zorder=2)
        if method["best"] is not None:
            best = rows[method["best"]]
            ax.scatter([best["metrics"][x_name]], [best["metrics"][y_name]], marker="*", s=260, color=colour,
                       edgecolors="black", linewidths=0.8, zorder=4)
    for bound in constraint_bounds(sweep["constraints"], y_name):
        ax.axhline(bound, color="0.3", ls="--", lw=1)
    for bound in constraint_bounds(sweep["constraints"], x_name):
        ax.axvline(bound, color="0.3", ls="--", lw=1)
    # errors spread over decades read better on a log axis
    if ys and min(ys) > 0 and max(ys) / min(ys) > 5:
        ax.set_yscale("log")
        ax.yaxis.set_major_locator(LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
        ax.yaxis.set_major_formatter(FuncFormatter(lambda v, _: f"{v:g}"))
        ax.yaxis.set_minor_formatter(NullFormatter())
    ax.set_xlabel(metric_label(x_name))
    ax.set_ylabel(metric_label(y_name))
    constraints = ", ".join(sweep["constraints"]) or "no constraints"
    # the subtitle wrapped to the axes' width, so a long constraint is not cut off
    subtitle = textwrap.fill(f"filled: meets {constraints}; hollow: does not", width=95)
    ax.set_title(f"Pareto front per method (lines); star: best setting\n{subtitle}", fontsize=10)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    save_png(fig, os.path.join(sweep_dir, "pareto.png"), DPI, tight=True)


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
