#!/usr/bin/python3
"""Plots for a BlendBench run folder.

usage: /usr/bin/python3 plot_run.py RUN_DIR

Reads RUN_DIR/summary.json and, per variant, RUN_DIR/<variant>/{trace,path,program}.csv, and
writes per variant path.png (the path in its plane: programmed, planned, actual), speed.png
(planned and actual path speed over time), tracking_error.png (tracking and contour error over
time) and joints.png (joint angles and velocities); and in RUN_DIR compare_speed.png,
compare_path.png and compare_metrics.png across variants. Every image is written to a
temporary file and renamed, so a failed run never leaves a half-written picture.
"""

import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from plotio import read_csv, save_png  # noqa: E402

DPI = 110


def plane_basis(points):
    """Orthonormal in-plane axes (e1, e2) of the best-fit plane through points (N x 3)."""
    centred = points - points.mean(axis=0)
    _, _, vt = np.linalg.svd(centred, full_matrices=False)
    e1, e2 = vt[0], vt[1]
    # prefer the base x/y orientation when the plane is horizontal
    if abs(vt[2][2]) > 0.99:
        e1, e2 = np.array([1.0, 0, 0]), np.array([0, 1.0, 0])
    return e1, e2


def project(xyz, origin, e1, e2):
    rel = xyz - origin
    return rel @ e1, rel @ e2


def xyz(cols, prefix):
    return np.column_stack([cols[prefix + "x"], cols[prefix + "y"], cols[prefix + "z"]])


def plot_variant(run_dir, variant):
    vdir = os.path.join(run_dir, variant["name"])
    trace = read_csv(os.path.join(vdir, "trace.csv"))
    path = read_csv(os.path.join(vdir, "path.csv"))
    program = read_csv(os.path.join(vdir, "program.csv"))
    prog_xyz = xyz(program, "")
    origin = prog_xyz.mean(axis=0)
    e1, e2 = plane_basis(prog_xyz)
    title = f'{variant["name"]} ({variant["method"]})'

    # path in the plane
    fig, ax = plt.subplots(figsize=(7, 6))
    ax.plot(*project(prog_xyz, origin, e1, e2), color="0.6", lw=3, label="programmed")
    ax.plot(*project(xyz(path, ""), origin, e1, e2), color="tab:blue", lw=1.2, label="planned (blended)")
    ax.plot(*project(xyz(trace, "act_"), origin, e1, e2), color="tab:red", lw=0.8, ls="--", label="actual TCP")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("in-plane axis 1 [mm]")
    ax.set_ylabel("in-plane axis 2 [mm]")
    ax.set_title(f"Path — {title}")
    ax.legend(loc="best")
    ax.grid(alpha=0.3)
    save_png(fig, os.path.join(vdir, "path.png"), DPI)

    # speed over time
    t = trace["t"]
    act = xyz(trace, "act_")
    act_speed = np.zeros_like(t)
    if len(t) > 2:
        act_speed[1:-1] = np.linalg.norm(act[2:] - act[:-2], axis=1) / (t[2:] - t[:-2])
    fig, ax = plt.subplots(figsize=(8, 4))
    ax.plot(t, trace["v_mm_s"], label="planned path speed")
    ax.plot(t, act_speed, lw=0.8, alpha=0.8, label="actual TCP speed")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("speed [mm/s]")
    ax.set_title(f"Path speed — {title}")
    ax.legend()
    ax.grid(alpha=0.3)
    save_png(fig, os.path.join(vdir, "speed.png"), DPI)

    # tracking and contour error
    fig, ax = plt.subplots(figsize=(8, 4))
    ax.plot(t, trace["tracking_error_mm"], label="tracking error (actual vs commanded TCP)")
    ax.plot(t, trace["contour_error_mm"], label="contour error (actual TCP vs programmed path)")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("error [mm]")
    ax.set_title(f"Errors — {title}")
    ax.legend()
    ax.grid(alpha=0.3)
    save_png(fig, os.path.join(vdir, "tracking_error.png"), DPI)

    # joints
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    for i in range(1, 7):
        line, = ax1.plot(t, np.degrees(trace[f"q_{i}"]), label=f"joint {i}")
        ax2.plot(t, np.degrees(trace[f"qd_{i}"]), color=line.get_color())
    ax1.set_ylabel("angle [deg]")
    ax2.set_ylabel("velocity [deg/s]")
    ax2.set_xlabel("time [s]")
    ax1.set_title(f"Joints (actual) — {title}")
    ax1.legend(ncol=3, fontsize=8)
    ax1.grid(alpha=0.3)
    ax2.grid(alpha=0.3)
    save_png(fig, os.path.join(vdir, "joints.png"), DPI)
    return trace, path, prog_xyz, (origin, e1, e2)


def plot_comparison(run_dir, summary, data):
    variants = summary["variants"]
    # over time (who finishes first) and along the path (where each variant slows down: the
    # corners line up, as a blended path is only slightly shorter than the programmed one)
    fig, (ax_t, ax_s) = plt.subplots(2, 1, figsize=(10, 6.5))
    for v in variants:
        trace = data[v["name"]][0]
        ax_t.plot(trace["t"], trace["v_mm_s"], lw=1.2, label=v["name"])
        ax_s.plot(trace["s_mm"], trace["v_mm_s"], lw=1.2, label=v["name"])
    ax_t.set_xlabel("time [s]")
    ax_s.set_xlabel("arc length along the planned path [mm]")
    for ax in (ax_t, ax_s):
        ax.set_ylabel("planned path speed [mm/s]")
        ax.grid(alpha=0.3)
    ax_t.set_title("Path speed by variant")
    ax_t.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
    fig.tight_layout()
    save_png(fig, os.path.join(run_dir, "compare_speed.png"), DPI)

    fig, ax = plt.subplots(figsize=(7, 6))
    first = data[variants[0]["name"]]
    origin, e1, e2 = first[3]
    ax.plot(*project(first[2], origin, e1, e2), color="0.6", lw=3, label="programmed")
    for v in variants:
        path = data[v["name"]][1]
        ax.plot(*project(xyz(path, ""), origin, e1, e2), lw=1, label=v["name"])
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_title("Planned path by variant")
    ax.legend()
    ax.grid(alpha=0.3)
    save_png(fig, os.path.join(run_dir, "compare_path.png"), DPI)

    keys = [("cycle_time_s", "cycle time [s]"), ("tracking_error_max_mm", "max tracking error [mm]"),
            ("contour_error_max_mm", "max contour error [mm]"), ("path_deviation_max_mm", "max path deviation [mm]")]
    fig, axes = plt.subplots(1, len(keys), figsize=(4 * len(keys), 4))
    names = [v["name"] for v in variants]
    for ax, (key, label) in zip(axes, keys):
        values = [v.get(key) if isinstance(v.get(key), (int, float)) else np.nan for v in variants]
        ax.bar(range(len(names)), values, color="tab:blue")
        ax.set_xticks(range(len(names)))
        ax.set_xticklabels(names, rotation=35, ha="right", fontsize=8)
        ax.set_title(label)
        ax.grid(alpha=0.3, axis="y")
    fig.tight_layout()
    save_png(fig, os.path.join(run_dir, "compare_metrics.png"), DPI)


def main(argv):
    if len(argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    run_dir = argv[1]
    with open(os.path.join(run_dir, "summary.json")) as f:
        summary = json.load(f)
    data = {}
    for v in summary["variants"]:
        if v.get("status", "ok") != "ok":
            continue
        data[v["name"]] = plot_variant(run_dir, v)
    ok = {"variants": [v for v in summary["variants"] if v["name"] in data]}
    if ok["variants"]:
        plot_comparison(run_dir, ok, data)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
