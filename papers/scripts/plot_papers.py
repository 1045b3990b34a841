#!/usr/bin/python3
"""Figures for a paper reproduction folder written by `blendbench reproduce`.

usage: /usr/bin/python3 plot_papers.py DIR PAPER     (PAPER: 004, 000 or 002)

004: reads DIR/profile_<run>.csv, DIR/path_<run>.csv, DIR/listing1.csv and DIR/table2_fillets.csv
and writes velocity.png (path speed over time, cf. the paper's figs. 4, 12, 20), curvature.png
(curvature along the path, cf. figs. 10, 19), table2.png (curvature and sharpness of the two
fillets of table 2, cf. fig. 17) and path.png (Listing 1 with the fillets, cf. figs. 9, 18).
000: reads DIR/profile_<run>.csv and DIR/profile_<run>_optimal.csv and writes velocity.png (speed
and tangential acceleration over time under seed 004's and the optimal planner, cf. figs. 16, 17)
and path.png (the program in 3D, cf. fig. 15).
002: reads DIR/results.json and DIR/trace_<curve>.csv and writes following_error.png (each joint's
drive following error around the corner per curve, cf. fig. 18) and path.png (the TCP near the
corner and its tracking error along the path, cf. fig. 17).
Every image is written to a temporary file and renamed, so a failure never leaves half a picture.
"""

import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# the shared CSV and PNG helpers live with the run plots (report/scripts)
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "report", "scripts"))
from plotio import read_csv, save_png  # noqa: E402

DPI = 80


RUNS_004 = [
    ("exact_stop", "unsmoothed, exact stop", "0.55"),
    ("junction_slowdown", "unsmoothed, junction slow-down (cf. fig. 4)", "tab:red"),
    ("biclothoid_0.1mm", "biclothoid 0.1 mm (cf. fig. 12)", "tab:blue"),
    ("biclothoid_0.01mm", "biclothoid 0.01 mm", "tab:cyan"),
    ("bezier_0.1mm", "Bezier (000 cubic) 0.1 mm (cf. fig. 20)", "tab:orange"),
    ("bezier_0.01mm", "Bezier (000 cubic) 0.01 mm", "tab:brown"),
]


def plot_004(d):
    fig, ax = plt.subplots(figsize=(9, 4.5))
    for name, label, color in RUNS_004:
        p = read_csv(os.path.join(d, f"profile_{name}.csv"))
        ax.plot(p["t"], p["v"] * 60, color=color, lw=1.2, label=f"{label}: {p['t'][-1]:.3f} s")
    ax.axhline(10000, color="0.3", lw=0.6, ls=":")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("path speed [mm/min]")
    ax.set_title("004 Listing 1 at F10000, a 9800 mm/s², j 200000 mm/s³")
    ax.legend(fontsize=8, loc="lower center")
    ax.grid(alpha=0.3)
    save_png(fig, os.path.join(d, "velocity.png"), DPI, tight=True)

    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(9, 6), sharex=True)
    for ax, name, label, color in [(ax1, "biclothoid_0.1mm", "biclothoid fillets, 0.1 mm (cf. fig. 10)", "tab:blue"),
                                   (ax2, "bezier_0.1mm", "chords + Bezier (000 cubic) fillets, 0.1 mm (cf. fig. 19)",
                                    "tab:orange")]:
        p = read_csv(os.path.join(d, f"path_{name}.csv"))
        ax.plot(p["s"], p["kappa"], color=color, lw=1)
        ax.set_ylabel("curvature [1/mm]")
        ax.set_title(label, fontsize=10)
        ax.grid(alpha=0.3)
    ax2.set_xlabel("arc length [mm]")
    save_png(fig, os.path.join(d, "curvature.png"), DPI, tight=True)

    f = read_csv(os.path.join(d, "table2_fillets.csv"))
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(7, 6), sharex=True)
    for name, label, color in [("biclothoid", "biclothoid", "tab:blue"), ("bezier", "Bezier (000 cubic)", "tab:orange")]:
        m = f["fillet"] == name
        ax1.plot(f["s"][m], f["kappa"][m], color=color, label=label)
        ax2.plot(f["s"][m], f["sharpness"][m], color=color, label=label)
    ax1.set_ylabel("curvature [1/mm]")
    ax2.set_ylabel("|dκ/ds| [1/mm²]")
    ax2.set_xlabel("arc length along the fillet [mm]")
    ax1.set_title("Table 2: the 150° corner, both fillets deviating 0.1 mm (cf. fig. 17)", fontsize=10)
    ax1.legend()
    ax1.grid(alpha=0.3)
    ax2.grid(alpha=0.3)
    save_png(fig, os.path.join(d, "table2.png"), DPI, tight=True)

    prog = read_csv(os.path.join(d, "listing1.csv"))
    bic = read_csv(os.path.join(d, "path_biclothoid_0.1mm.csv"))
    bez = read_csv(os.path.join(d, "path_bezier_0.1mm.csv"))
    fig, axes = plt.subplots(1, 3, figsize=(12, 5), gridspec_kw={"width_ratios": [1.2, 1, 1]})
    corners = [(None, "Listing 1"), ((-10, 10), "A"), ((0, 60), "C")]
    for ax, (centre, title) in zip(axes, corners):
        ax.plot(prog["x"], prog["y"], color="0.6", lw=3, label="programmed")
        ax.plot(bic["x"], bic["y"], color="tab:blue", lw=1.2, label="biclothoid 0.1 mm")
        ax.plot(bez["x"], bez["y"], color="tab:orange", lw=1, ls="--", label="chords + Bezier 0.1 mm")
        if centre is not None:
            ax.set_xlim(centre[0] - 0.5, centre[0] + 0.5)
            ax.set_ylim(centre[1] - 0.5, centre[1] + 0.5)
            title = f"near {title} ({centre[0]}, {centre[1]})"
        ax.set_aspect("equal", adjustable="box")
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("x [mm]")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("y [mm]")
    axes[0].legend(fontsize=8, loc="lower right")
    save_png(fig, os.path.join(d, "path.png"), DPI, tight=True)


def plot_000(d):
    runs = [("exact_stop", "without transitions (exact stop)", "0.45"),
            ("bezier_tp5", "Bezier TP 5 mm, eq. 25-27 enforced", "tab:orange"),
            ("bezier_tp20", "Bezier TP 20 mm (not in the paper)", "tab:green")]
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(9, 6), sharex=True)
    profiles = {}
    for name, label, color in runs:
        p = read_csv(os.path.join(d, f"profile_{name}.csv"))
        profiles[name] = p
        ax1.plot(p["t"], p["v"], color=color, label=f"{label}: {p['t'][-1]:.2f} s")
        ax2.plot(p["t"], p["a"], color=color)
        # the same path timed by the optimal planner, dashed beside seed 004's
        q = read_csv(os.path.join(d, f"profile_{name}_optimal.csv"))
        ax1.plot(q["t"], q["v"], color=color, ls="--", lw=1.0, label=f"  optimal planner: {q['t'][-1]:.2f} s")
        ax2.plot(q["t"], q["a"], color=color, ls="--", lw=1.0)
    ax1.set_ylabel("path speed [mm/s]")
    ax2.set_ylabel("tangential acc. [mm/s²]")
    ax2.set_xlabel("time [s]")
    ax1.set_title("000 section 3.2 program: 50 mm/s, 100 mm/s², 200 mm/s³ (cf. figs. 16, 17);\n"
                  "solid: seed 004's planner, dashed: the optimal planner", fontsize=10)
    ax1.legend(fontsize=8)
    ax1.grid(alpha=0.3)
    ax2.grid(alpha=0.3)
    save_png(fig, os.path.join(d, "velocity.png"), DPI, tight=True)

    fig = plt.figure(figsize=(6, 5))
    ax = fig.add_subplot(projection="3d")
    for name, label, color in runs:
        p = profiles[name]
        ax.plot(p["x"], p["y"], p["z"], color=color, label=label)
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_zlabel("z [mm]")
    ax.set_title("The program (robot base frame), cf. fig. 15", fontsize=10)
    ax.legend(fontsize=8)
    save_png(fig, os.path.join(d, "path.png"), DPI, tight=True)


CURVES_002 = [("large_circle", "tab:blue"), ("small_circle", "tab:red"), ("clothoid", "tab:green")]


def plot_002(d):
    with open(os.path.join(d, "results.json")) as f:
        results = json.load(f)
    curves = {c["name"]: c for c in results["curves"]}
    traces = {name: read_csv(os.path.join(d, f"trace_{name}.csv")) for name, _ in CURVES_002}

    # the error pulses: per curve, every joint's following error around the corner
    fig, axes = plt.subplots(len(CURVES_002), 1, figsize=(9, 8), sharex=True, sharey=True)
    for ax, (name, _) in zip(axes, CURVES_002):
        c, t = curves[name], traces[name]
        zero = c["t_start_s"]
        ax.axvspan(0, c["t_end_s"] - zero, color="0.88", lw=0)
        for i in range(1, 7):
            ax.plot(t["t"] - zero, t[f"following_error_mrad_{i}"], lw=0.9, label=f"joint {i}")
        ax.set_title(f'{c["label"]}: peak {c["following_error_peak_mrad"]:.3f} mrad, residual vibration '
                     f'{c["residual_vibration_um"]:.1f} µm', fontsize=9)
        ax.set_ylabel("following error [mrad]")
        ax.grid(alpha=0.3)
    axes[0].legend(ncol=6, fontsize=7, loc="upper left")
    axes[-1].set_xlabel("time from the start of the curve [s] (shaded: the curve)")
    axes[-1].set_xlim(-0.15, 0.35)
    fig.suptitle("Drive following errors at 400 mm/s (cf. the paper's fig. 18)", fontsize=11)
    save_png(fig, os.path.join(d, "following_error.png"), DPI, tight=True)

    # the path near the corner and the tracking error along it
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 5))
    ax1.plot([-45, 0, 0], [0, 0, 35], color="0.6", lw=3, label="programmed")
    for name, color in CURVES_002:
        t = traces[name]
        ax1.plot(t["u_cmd"], t["w_cmd"], color=color, lw=1.2, label=curves[name]["label"])
        ax1.plot(t["u"], t["w"], color=color, lw=0.8, ls="--")
        near = (t["t"] > curves[name]["t_start_s"] - 0.1) & (t["t"] < curves[name]["t_end_s"] + 0.2)
        ax2.plot(t["t"][near] - curves[name]["t_start_s"], t["tracking_error_um"][near], color=color, lw=1,
                 label=curves[name]["label"])
    ax1.set_xlim(-45, 10)
    ax1.set_ylim(-10, 35)
    ax1.set_aspect("equal")
    ax1.set_xlabel("along the leading line, from the corner [mm]")
    ax1.set_ylabel("towards the turn [mm]")
    ax1.set_title("TCP near the corner: planned (solid), actual (dashed)", fontsize=10)
    ax1.legend(fontsize=7, loc="upper left")
    ax1.grid(alpha=0.3)
    ax2.set_xlabel("time from the start of the curve [s]")
    ax2.set_ylabel("tracking error [µm]")
    ax2.set_title("Tracking error through the corner (cf. fig. 17)", fontsize=10)
    ax2.grid(alpha=0.3)
    save_png(fig, os.path.join(d, "path.png"), DPI, tight=True)


def main():
    if len(sys.argv) != 3 or sys.argv[2] not in ("004", "000", "002"):
        print(__doc__)
        return 2
    d, paper = sys.argv[1], sys.argv[2]
    {"004": plot_004, "000": plot_000, "002": plot_002}[paper](d)
    return 0


if __name__ == "__main__":
    sys.exit(main())
