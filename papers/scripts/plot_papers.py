#!/usr/bin/python3
"""Figures for a paper reproduction folder written by `blendbench reproduce`.

usage: /usr/bin/python3 plot_papers.py DIR PAPER     (PAPER: 004 or 000)

004: reads DIR/profile_<run>.csv, DIR/path_<run>.csv, DIR/listing1.csv and DIR/table2_fillets.csv
and writes velocity.png (path speed over time, cf. the paper's figs. 4, 12, 20), curvature.png
(curvature along the path, cf. figs. 10, 19), table2.png (curvature and sharpness of the two
fillets of table 2, cf. fig. 17) and path.png (Listing 1 with the fillets, cf. figs. 9, 18).
000: reads DIR/profile_<run>.csv and writes velocity.png (speed and tangential acceleration over
time, cf. figs. 16, 17) and path.png (the program in 3D, cf. fig. 15).
Every image is written to a temporary file and renamed, so a failure never leaves half a picture.
"""

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
    ax1.set_ylabel("path speed [mm/s]")
    ax2.set_ylabel("tangential acc. [mm/s²]")
    ax2.set_xlabel("time [s]")
    ax1.set_title("000 section 3.2 program: 50 mm/s, 100 mm/s², 200 mm/s³ (cf. figs. 16, 17)", fontsize=10)
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


def main():
    if len(sys.argv) != 3 or sys.argv[2] not in ("004", "000"):
        print(__doc__)
        return 2
    d, paper = sys.argv[1], sys.argv[2]
    if paper == "004":
        plot_004(d)
    else:
        plot_000(d)
    return 0


if __name__ == "__main__":
    sys.exit(main())
