#!/usr/bin/python3
"""Plots and the HTML report of a BlendBench run folder.

usage: /usr/bin/python3 plot_run.py RUN_DIR

Reads only what the run wrote: RUN_DIR/summary.json and, per variant, RUN_DIR/<variant>/
{trace,path,program}.csv and corners.json (corner points, arc lengths and the times the
reference passes each corner). Writes per variant
  path.png             the path in its plane: programmed, planned, actual
  corners.png          the path near every corner, programmed / planned / actual
  speed.png            planned and actual path speed over time, corners marked
  acceleration.png     planned tangential acceleration and jerk, and the actual TCP's jerk
  curvature.png        curvature of the planned path along s, transitions marked
  tracking_error.png   tracking error and contour errors (programmed, planned) over time
  following_error.png  each joint's drive following error (the error pulses)
  torques.png          each joint's motor torque against its limit
  vibration.png        the high-passed tracking error with the residual-vibration windows
  joints.png           joint angles and velocities
and in RUN_DIR compare_speed.png, compare_path.png, compare_metrics.png and report.html (first
the answer: the recommendation and the ranking per tolerance from the summary, ties shown as
ties; then the corners with the program lines they come from, the comparison table and every
figure; report_page.py then makes it one self-contained page). Paths and corners are drawn in the program's own
coordinates (summary.json's `frame` maps the base frame back to them), and every corner is named
as corners.json numbers it, C<index>, with its source line. Every file is written to a temporary
file and renamed, so a failed run never leaves a half-written picture.
"""

import html
import json
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from plotio import read_csv, save_png, variant_styles, write_text  # noqa: E402
import report_page  # noqa: E402

DPI = 100
CORNER_SHADE = dict(color="0.85", alpha=0.6, lw=0)
# The corner views cover the transition with this margin, at least this many mm around the corner.
CORNER_MARGIN = 1.6
CORNER_MIN_HALF_MM = 4.0


# A path plane whose normal is this close to a program axis is drawn in two of the program's axes.
AXIS_ALIGNED_COS = 0.99


class Frame:
    """The program frame (summary.json `frame`): maps base-frame points (mm) to the program's own
    coordinates, and picks the plane the paths are drawn in: two program axes (X, Y, Z as written)
    when the path lies in or near one of their planes, else the path's best-fit plane measured from
    the program origin (not re-centred)."""

    def __init__(self, summary, program_points):
        frame = summary.get("frame") or {}
        self.origin = np.array(frame.get("position_mm", [0.0, 0.0, 0.0]), dtype=float)
        self.rotation = np.array(frame.get("rotation", np.eye(3).tolist()), dtype=float)
        local = self.program(program_points)
        centred = local - local.mean(axis=0)
        _, _, vt = np.linalg.svd(centred, full_matrices=False)
        normal = vt[2] if vt.shape[0] > 2 else np.array([0.0, 0.0, 1.0])
        names = ["X", "Y", "Z"]
        axis = int(np.argmax(np.abs(normal)))
        if abs(normal[axis]) >= AXIS_ALIGNED_COS:
            i, j = [(1, 2), (0, 2), (0, 1)][axis]
            self.e1, self.e2 = np.eye(3)[i], np.eye(3)[j]
            self.labels = (f"program {names[i]} [mm]", f"program {names[j]} [mm]")
        else:
            self.e1, self.e2 = vt[0], vt[1]
            self.labels = ("u in the path's plane, from the program origin [mm]",
                           "v in the path's plane, from the program origin [mm]")

    def program(self, xyz):
        """Base-frame points (N x 3 or 3, mm) in program coordinates: R^T (p - origin)."""
        return (np.asarray(xyz, dtype=float) - self.origin) @ self.rotation

    def project(self, xyz):
        local = self.program(xyz)
        return local @ self.e1, local @ self.e2


def xyz(cols, prefix):
    return np.column_stack([cols[prefix + "x"], cols[prefix + "y"], cols[prefix + "z"]])


def corner_name(c):
    """A corner as every output names it: C<index> from corners.json, with the program line it
    comes from (the move that ends at it), e.g. "C7 (bracket.ngc:110)"."""
    name = f'C{c["index"]}'
    line = c.get("source_line")
    if line:
        source = c.get("source_file") or ""
        name += f" ({os.path.basename(source)}:{line})" if source else f" (line {line})"
    return name


def mark_corners(ax, corners):
    """Shades the time each corner's transition takes (a line for an exact stop)."""
    for c in corners:
        if c["t_end_s"] > c["t_start_s"]:
            ax.axvspan(c["t_start_s"], c["t_end_s"], **CORNER_SHADE)
        else:
            ax.axvline(c["t_start_s"], color="0.7", lw=0.8)


def finish(ax, title, xlabel, ylabel, legend=True):
    ax.set_title(title)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3)
    if legend:
        ax.legend(fontsize=8)


class Variant:
    """One variant's files."""

    def __init__(self, run_dir, entry):
        self.entry = entry
        self.name = entry["name"]
        self.dir = os.path.join(run_dir, self.name)
        self.trace = read_csv(os.path.join(self.dir, "trace.csv"))
        self.path = read_csv(os.path.join(self.dir, "path.csv"))
        self.program = read_csv(os.path.join(self.dir, "program.csv"))
        with open(os.path.join(self.dir, "corners.json")) as f:
            self.corners = json.load(f)
        self.title = f'{self.name} ({entry["method"]})'
        self.t = self.trace["t"]

    def png(self, name):
        return os.path.join(self.dir, name)


def plot_path(v, frame):
    fig, ax = plt.subplots(figsize=(7, 6))
    ax.plot(*frame.project(xyz(v.program, "")), color="0.6", lw=3, label="programmed")
    ax.plot(*frame.project(xyz(v.path, "")), color="tab:blue", lw=1.2, label="planned (blended)")
    ax.plot(*frame.project(xyz(v.trace, "act_")), color="tab:red", lw=0.8, ls="--", label="actual TCP")
    label_corners(ax, [(corner_name(c), *frame.project(np.array(c["point_mm"]))) for c in v.corners])
    ax.set_aspect("equal", adjustable="datalim")
    finish(ax, f"Path in program coordinates — {v.title}", *frame.labels)
    save_png(fig, v.png("path.png"), DPI)


def label_corners(ax, corners):
    """Each corner's name beside its point (name, u, w); a label that would sit on one already
    placed (within 4 % of the plot's extent) is stacked above it instead."""
    if not corners:
        return
    us = [u for _, u, _ in corners]
    ws = [w for _, _, w in corners]
    near = 0.04 * max(max(us) - min(us), max(ws) - min(ws), 1e-9)
    placed = []
    for index, u, w in corners:
        stack = sum(1 for pu, pw in placed if abs(pu - u) < near and abs(pw - w) < near)
        placed.append((u, w))
        ax.annotate(index, (u, w), fontsize=8, xytext=(4, 4 + 10 * stack), textcoords="offset points",
                    arrowprops=dict(arrowstyle="-", color="0.6", lw=0.5) if stack else None)


def plot_corners(v, frame):
    """A zoomed view of each corner: the actual TCP against the planned and the programmed path."""
    n = max(1, len(v.corners))
    cols = min(n, 4)
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(3.6 * cols, 3.4 * rows), squeeze=False)
    prog = frame.project(xyz(v.program, ""))
    plan = frame.project(xyz(v.path, ""))
    act = frame.project(xyz(v.trace, "act_"))
    for ax in axes.flat[n:]:
        ax.axis("off")
    for ax, c in zip(axes.flat, v.corners):
        cu, cw = frame.project(np.array(c["point_mm"]))
        half = max(CORNER_MIN_HALF_MM, CORNER_MARGIN * max(c["trim_in_mm"], c["trim_out_mm"]))
        ax.plot(*prog, color="0.6", lw=3, label="programmed")
        ax.plot(*plan, color="tab:blue", lw=1.2, label="planned")
        ax.plot(*act, color="tab:red", lw=0.8, ls="--", label="actual")
        ax.plot(cu, cw, "k+", ms=10)
        ax.set_xlim(cu - half, cu + half)
        ax.set_ylim(cw - half, cw + half)
        ax.set_aspect("equal", adjustable="box")
        ax.set_title(f'{corner_name(c)}: {c["method"]}, deviation {c["deviation_mm"]:.3g} mm', fontsize=9)
        ax.set_xlabel(frame.labels[0], fontsize=7)
        ax.set_ylabel(frame.labels[1], fontsize=7)
        ax.tick_params(labelsize=7)
        ax.grid(alpha=0.3)
    axes.flat[0].legend(fontsize=7)
    fig.suptitle(f"Corners (actual offsets are tens of µm: see the error plots) — {v.title}", fontsize=10)
    save_png(fig, v.png("corners.png"), DPI, tight=True)


def plot_speed(v):
    act_speed = v.trace["tcp_speed_mm_s"]
    fig, ax = plt.subplots(figsize=(8, 4))
    mark_corners(ax, v.corners)
    ax.plot(v.t, v.trace["v_mm_s"], label="planned path speed")
    ax.plot(v.t, act_speed, lw=0.8, alpha=0.8, label="actual TCP speed")
    finish(ax, f"Path speed (corners shaded) — {v.title}", "time [s]", "speed [mm/s]")
    save_png(fig, v.png("speed.png"), DPI)


def plot_acceleration(v):
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    mark_corners(ax1, v.corners)
    mark_corners(ax2, v.corners)
    ax1.plot(v.t, v.trace["a_mm_s2"], label="planned tangential acceleration")
    finish(ax1, f"Acceleration and jerk — {v.title}", "", "acceleration [mm/s²]")
    ax2.plot(v.t, v.trace["jerk_actual_mm_s3"], color="tab:red", lw=0.7, alpha=0.8,
             label="actual TCP |jerk| (low-passed)")
    ax2.plot(v.t, v.trace["j_mm_s3"], color="tab:blue", label="planned tangential jerk")
    finish(ax2, "", "time [s]", "jerk [mm/s³]")
    save_png(fig, v.png("acceleration.png"), DPI, tight=True)


def plot_curvature(v):
    fig, ax = plt.subplots(figsize=(8, 3.5))
    for c in v.corners:
        if c["s_end_mm"] > c["s_start_mm"]:
            ax.axvspan(c["s_start_mm"], c["s_end_mm"], **CORNER_SHADE)
    ax.plot(v.path["s"], v.path["kappa"], color="tab:green")
    finish(ax, f"Curvature of the planned path (transitions shaded) — {v.title}", "arc length s [mm]",
           "curvature κ [1/mm]", legend=False)
    save_png(fig, v.png("curvature.png"), DPI, tight=True)


def plot_errors(v):
    """The servo's errors in µm on top, the contour error against the programmed path (which
    holds the designed corner deviation) in mm below."""
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    mark_corners(ax1, v.corners)
    mark_corners(ax2, v.corners)
    ax1.plot(v.t, 1e3 * v.trace["tracking_error_mm"], label="tracking error (actual vs commanded TCP)")
    ax1.plot(v.t, 1e3 * v.trace["contour_error_planned_mm"], label="contour error vs planned path (servo's own)")
    finish(ax1, f"Errors (corners shaded) — {v.title}", "", "error [µm]")
    ax2.plot(v.t, v.trace["contour_error_programmed_mm"], color="tab:green",
             label="contour error vs programmed path (designed deviation + servo)")
    finish(ax2, "", "time [s]", "error [mm]")
    save_png(fig, v.png("tracking_error.png"), DPI, tight=True)


def plot_following(v):
    fig, ax = plt.subplots(figsize=(8, 4))
    mark_corners(ax, v.corners)
    for i in range(1, 7):
        ax.plot(v.t, v.trace[f"following_error_mrad_{i}"], lw=0.9, label=f"joint {i}")
    finish(ax, f"Drive following errors (reference − encoder) — {v.title}", "time [s]", "following error [mrad]")
    ax.legend(ncol=3, fontsize=8)
    save_png(fig, v.png("following_error.png"), DPI)


def plot_torques(v, limits):
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for i in range(1, 7):
        line, = ax.plot(v.t, v.trace[f"tau_{i}"], lw=0.9, label=f"joint {i}")
        if limits and limits[i - 1] is not None:
            ax.axhline(limits[i - 1], color=line.get_color(), ls=":", lw=0.8)
            ax.axhline(-limits[i - 1], color=line.get_color(), ls=":", lw=0.8)
    finish(ax, f"Motor torques (dotted: limits) — {v.title}", "time [s]", "torque [N·m]")
    ax.legend(ncol=3, fontsize=8)
    save_png(fig, v.png("torques.png"), DPI)


def plot_vibration(v, hp_hz, window_s):
    m = v.entry["metrics"]
    fig, ax = plt.subplots(figsize=(8, 4))
    for axis in "xyz":
        ax.plot(v.t, 1e3 * v.trace[f"vibration_{axis}_mm"], lw=0.8, label=f"{axis}")
    windows = [("after stop", m["residual_vibration_final"])] + [
        (f"C{w['corner']}", w) for w in m["residual_vibration_corners"]]
    top = ax.get_ylim()[1]
    for label, w in windows:
        if w["t_end_s"] > w["t_start_s"]:
            ax.axvspan(w["t_start_s"], w["t_end_s"], color="tab:orange", alpha=0.12, lw=0)
            ax.text(w["t_start_s"], top, f"{label}\n{1e3 * w['peak_to_peak_mm']:.1f} µm\n{w['frequency_hz']:.0f} Hz",
                    fontsize=6, va="top")
    finish(ax, f"Residual vibration: tracking error high-passed at {hp_hz:g} Hz, windows of {window_s:g} s"
           f" — {v.title}", "time [s]", "high-passed error [µm]")
    save_png(fig, v.png("vibration.png"), DPI)


def plot_joints(v):
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(8, 6), sharex=True)
    for i in range(1, 7):
        line, = ax1.plot(v.t, np.degrees(v.trace[f"q_{i}"]), label=f"joint {i}")
        ax2.plot(v.t, np.degrees(v.trace[f"qd_{i}"]), color=line.get_color())
    ax1.set_ylabel("angle [deg]")
    ax2.set_ylabel("velocity [deg/s]")
    ax2.set_xlabel("time [s]")
    ax1.set_title(f"Joints (actual link angles) — {v.title}")
    ax1.legend(ncol=3, fontsize=8)
    ax1.grid(alpha=0.3)
    ax2.grid(alpha=0.3)
    save_png(fig, v.png("joints.png"), DPI)


VARIANT_FIGURES = [
    ("path.png", "Path"), ("corners.png", "Corners"), ("speed.png", "Path speed"),
    ("acceleration.png", "Acceleration and jerk"), ("curvature.png", "Curvature along the path"),
    ("tracking_error.png", "Tracking and contour error"), ("following_error.png", "Joint following errors"),
    ("torques.png", "Torques"), ("vibration.png", "Residual vibration"), ("joints.png", "Joints"),
]


def plot_variant(v, frame, summary):
    limits = summary["robot"].get("torque_limits_nm")
    plot_path(v, frame)
    plot_corners(v, frame)
    plot_speed(v)
    plot_acceleration(v)
    plot_curvature(v)
    plot_errors(v)
    plot_following(v)
    plot_torques(v, limits)
    plot_vibration(v, summary["simulation"]["vibration_highpass_hz"], summary["simulation"]["vibration_window_s"])
    plot_joints(v)


def number(v, key):
    value = v.get("metrics", {}).get(key)
    return value if isinstance(value, (int, float)) else np.nan


def widest_corner(variants):
    """(index, point_mm, half width mm) of the corner whose deviation differs most between the
    variants, for a zoomed view; None without corners."""
    spread = {}
    for v in variants:
        for c in v.corners:
            if "point_mm" not in c:
                continue
            lo, hi, point, reach = spread.get(c["index"], (np.inf, -np.inf, c["point_mm"], 0.0))
            d = float(c.get("deviation_mm") or 0)
            reach = max(reach, float(c.get("trim_in_mm") or 0), float(c.get("trim_out_mm") or 0))
            spread[c["index"]] = (min(lo, d), max(hi, d), point, reach)
    if not spread:
        return None
    index = max(spread, key=lambda k: spread[k][1] - spread[k][0])
    _, _, point, reach = spread[index]
    return index, point, max(CORNER_MIN_HALF_MM, 1.1 * reach)


def plot_comparison(run_dir, variants, frame):
    # over time (who finishes first) and along the path (where each variant slows down)
    styles = variant_styles([v.entry for v in variants])
    fig, (ax_t, ax_s) = plt.subplots(2, 1, figsize=(10, 6.5))
    for v in variants:
        colour, dash = styles[v.name]
        ax_t.plot(v.t, v.trace["v_mm_s"], lw=1.2, label=v.name, color=colour, dashes=dash or (None, None))
        ax_s.plot(v.trace["s_mm"], v.trace["v_mm_s"], lw=1.2, label=v.name, color=colour, dashes=dash or (None, None))
    ax_t.set_xlabel("time [s]")
    ax_s.set_xlabel("arc length along the planned path [mm]")
    for ax in (ax_t, ax_s):
        ax.set_ylabel("planned path speed [mm/s]")
        ax.grid(alpha=0.3)
    ax_t.set_title("Path speed by variant")
    ax_t.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8)
    save_png(fig, os.path.join(run_dir, "compare_speed.png"), DPI, tight=True)

    # the whole path, and beside it the corner where the variants differ most (at full scale
    # every transition sits on one line)
    zoom = widest_corner(variants)
    fig, axes = plt.subplots(1, 2 if zoom else 1, figsize=(13 if zoom else 7, 6), squeeze=False)
    for ax in axes[0]:
        ax.plot(*frame.project(xyz(variants[0].program, "")), color="0.6", lw=3, label="programmed")
        for v in variants:
            colour, dash = styles[v.name]
            ax.plot(*frame.project(xyz(v.path, "")), lw=1.2, label=v.name, color=colour, dashes=dash or (None, None))
        ax.set_aspect("equal", adjustable="datalim")
    label_corners(axes[0][0], [(corner_name(c), *frame.project(np.array(c["point_mm"]))) for c in variants[0].corners])
    finish(axes[0][0], "Planned path by variant, program coordinates", *frame.labels)
    if zoom:
        index, point, half = zoom
        u, w = frame.project(np.array(point))
        ax = axes[0][1]
        ax.set_xlim(u - half, u + half)
        ax.set_ylim(w - half, w + half)
        finish(ax, f"Corner C{index}, where the variants differ most", *frame.labels, legend=False)
        axes[0][0].add_patch(plt.Rectangle((u - half, w - half), 2 * half, 2 * half, fill=False, color="0.3", lw=0.8))
    save_png(fig, os.path.join(run_dir, "compare_path.png"), DPI, tight=True)

    keys = [("cycle_time_s", "cycle time [s]", 1), ("tracking_error_max_mm", "max tracking error [µm]", 1e3),
            ("contour_error_planned_max_mm", "max contour error vs plan [µm]", 1e3),
            ("residual_vibration_final_mm", "residual vibration after stop [µm]", 1e3),
            ("residual_vibration_corner_max_mm", "largest corner vibration [µm]", 1e3)]
    fig, axes = plt.subplots(1, len(keys), figsize=(3.6 * len(keys), 4))
    names = [v.name for v in variants]
    for ax, (key, label, scale) in zip(axes, keys):
        values = [scale * number(v.entry, key) for v in variants]
        ax.bar(range(len(names)), values, color=[styles[n][0] for n in names], edgecolor="black", linewidth=0.4)
        ax.set_xticks(range(len(names)))
        ax.set_xticklabels(names, rotation=35, ha="right", fontsize=8)
        ax.grid(alpha=0.3, axis="y")
        # the axis starts below the smallest bar (not at zero), so differences of a few per cent
        # show; the title says where it starts when that is not zero
        finite = [x for x in values if np.isfinite(x)]
        bottom = 0.0
        if finite and min(finite) > 0:
            lo, hi = min(finite), max(finite)
            bottom = max(0.0, lo - 0.25 * max(hi - lo, 0.02 * hi))
            ax.set_ylim(bottom, hi + 0.08 * max(hi - bottom, 1e-12))
        ax.set_title(label + (f"\n(axis from {bottom:.3g})" if bottom > 0 else ""), fontsize=10)
        for i, x in enumerate(values):
            if np.isfinite(x):
                ax.annotate(f"{x:.3g}", (i, x), ha="center", va="bottom", fontsize=7, xytext=(0, 1), textcoords="offset points")
    save_png(fig, os.path.join(run_dir, "compare_metrics.png"), DPI, tight=True)


def fmt(value, decimals=3, scale=1.0):
    """A number with a fixed count of decimals, so a column lines up (5.390 over 6.188)."""
    if not isinstance(value, (int, float)) or value is None:
        return "—"
    return f"{scale * value:.{decimals}f}"


def on_off(value):
    """A switch as a word, not Python's True/False."""
    return "on" if value is True else "off" if value is False else html.escape(str(value))


# The comparison table: header, key of the value (part of the variant entry, name), decimals,
# scale, whether lower is better, and an optional second value shown after a slash (key, scale,
# decimals). Units as docs/units.md: lengths and deviations from the program in mm, the servo's
# errors and vibration in µm, jerk in mm/s³.
TABLE = [
    ("cycle time [s]", ("metrics", "cycle_time_s"), 3, 1, True, None),
    ("saved vs exact stop [%]", ("comparison", "cycle_time_saved_percent"), 1, 1, False, None),
    ("planned [s]", ("plan", "planned_cycle_time_s"), 3, 1, True, None),
    ("tracking max / RMS [µm]", ("metrics", "tracking_error_max_mm"), 1, 1e3, True,
     (("metrics", "tracking_error_rms_mm"), 1e3, 1)),
    ("orientation max [deg]", ("metrics", "orientation_error_max_deg"), 4, 1, True, None),
    ("contour vs programmed max [mm]", ("metrics", "contour_error_programmed_max_mm"), 3, 1, True, None),
    ("contour vs planned max [µm]", ("metrics", "contour_error_planned_max_mm"), 1, 1e3, True, None),
    ("path deviation max [mm]", ("plan", "path_deviation_max_mm"), 3, 1, True, None),
    ("actual jerk peak [mm/s³]", ("metrics", "jerk_actual_peak_mm_s3"), 0, 1, True, None),
    ("vibration after stop [µm] / [Hz]", ("metrics", "residual_vibration_final_mm"), 2, 1e3, True,
     (("metrics", "residual_vibration_final_frequency_hz"), 1, 1)),
    ("largest corner vibration [µm]", ("metrics", "residual_vibration_corner_max_mm"), 2, 1e3, True, None),
]


def cell_value(entry, key):
    part, name = key
    value = entry.get(part, {}).get(name)
    return value if isinstance(value, (int, float)) else None


# The regression gate's tolerances (beside this script in the data root): a value within a metric's
# tolerance of the best is as good as the best (a tie), and is shaded with it.
TOLERANCES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "results", "baselines",
                          "tolerances.json")


def gate_tolerances():
    """metric key ("metrics.cycle_time_s") -> (absolute, relative); empty when the file is absent."""
    try:
        with open(TOLERANCES) as f:
            metrics = json.load(f)["metrics"]
        return {k: (float(v["absolute"]), float(v["relative"])) for k, v in metrics.items()}
    except (OSError, ValueError, KeyError, TypeError):
        return {}


def cycle_tie_threshold(summary, a, b):
    """The summary's cycle-time resolution (ranking.resolution): the difference below which two
    cycle times tie, or None without a ranking."""
    res = summary.get("ranking", {}).get("resolution")
    if not res:
        return None
    return max(res["grid_s"], res["absolute_s"], res["relative"] * min(a, b))


def comparison_table(entries, summary=None):
    """The table's HTML and, per header, the names of the best clean variants: the best, and every
    one that ties with it (within the regression gate's tolerance of that metric; cycle times at
    the run's own resolution)."""
    ok = [e for e in entries if e["status"] == "ok"]
    gate = gate_tolerances()
    best = {}
    for header, key, _, _, lower, _ in TABLE:
        values = [(cell_value(e, key), e["name"]) for e in ok if cell_value(e, key) is not None]
        if not values:
            continue
        top = (min if lower else max)(values)[0]
        names = []
        for value, name in values:
            if key == ("metrics", "cycle_time_s") and summary is not None:
                limit = cycle_tie_threshold(summary, top, value)
            else:
                absolute, relative = gate.get(".".join(key), (None, None))
                limit = None if absolute is None else max(absolute, relative * min(abs(top), abs(value)))
            if value == top or (limit is not None and abs(value - top) < limit):
                names.append(name)
        best[header] = names
    rows = []
    for e in entries:
        status = e["status"]
        cells = [f"<td><b>{html.escape(e['name'])}</b><br><small>{html.escape(e['method'])}</small></td>",
                 f"<td class='{'ok' if status == 'ok' else 'bad'}'>{html.escape(status)}"
                 + (f"<br><small>{html.escape(e.get('message', ''))}</small>" if status != "ok" else "") + "</td>"]
        for header, key, digits, scale, _, extra in TABLE:
            text = fmt(cell_value(e, key), digits, scale)
            if extra is not None:
                text += " / " + fmt(cell_value(e, extra[0]), extra[2], extra[1])
            mark = " class='best'" if e["name"] in best.get(header, []) else ""
            cells.append(f"<td{mark}>{text}</td>")
        rows.append("<tr>" + "".join(cells) + "</tr>")
    head = "<tr><th>variant</th><th>status</th>" + "".join(f"<th>{html.escape(h)}</th>" for h, *_ in TABLE) + "</tr>"
    return f"<table>{head}{''.join(rows)}</table>", best


def tolerance_notes(summary):
    """Equal tolerance (docs/methods.md): a line per variant run at a tolerance: at how many corners
    it was reached, and, where at none, that it was not, with the largest deviation reached (each
    corner's note in corners.json says why). Returns (the lines of tolerances reached nowhere, for
    the top of the report; the others)."""
    bad, lines = [], []
    for entry in summary["variants"]:
        corners = [c for c in entry.get("plan", {}).get("corners", []) if c.get("tolerance_mm") is not None]
        if not corners:
            continue
        name = html.escape(entry["name"])
        tolerances = sorted({c["tolerance_mm"] for c in corners})
        tol = " / ".join(f"{t:g}" for t in tolerances)
        reached = sum(1 for c in corners if c.get("tolerance_reached"))
        deviation = max(c["deviation_mm"] for c in corners)
        if reached == 0:
            bad.append(f"<p class='bad'><b>{name}: the tolerance {tol} mm is reached at no corner</b> "
                         f"(largest deviation {deviation:.4g} mm; each corner's note in {name}/corners.json says why: "
                         f"moves too short for it, or nothing to cut).</p>")
        else:
            lines.append(f"<li>{name}: tolerance {tol} mm reached at {reached} of {len(corners)} corners "
                         f"(largest deviation {deviation:.4g} mm)</li>")
    return bad, lines


def ms(value):
    return "—" if value is None else f"{1e3 * value:.0f}"


def answer_html(summary):
    """The answer, first on the page: the recommendation and its reason, then per tolerance the
    variants by cycle time with the margin to the next (ms and %) and the ties (summary.json
    `recommendation` and `ranking`; docs/compare.md)."""
    ranking = summary.get("ranking")
    rec = summary.get("recommendation")
    if not ranking or not rec:
        return []
    parts = ["<h2>Answer</h2>"]
    if rec.get("variant"):
        parts.append(f"<p class='answer'>Recommended: <b>{html.escape(rec['variant'])}</b>, "
                     f"{html.escape(rec['reason'])}.</p>")
    else:
        parts.append(f"<p class='answer bad'><b>No recommendation</b>: {html.escape(rec['reason'])}.</p>")
    res = ranking["resolution"]
    rule = (f"two cycle times tie when they differ by less than max({1e3 * res['grid_s']:.0f} ms, "
            f"{1e3 * res['absolute_s']:.0f} ms, {100 * res['relative']:g} % of the faster)"
            if not res.get("model_spread") else "two cycle times tie unless their order holds in every perturbed "
            f"arm model and they differ by {1e3 * res['grid_s']:.0f} ms or more")
    for note in summary.get("notes", []):
        parts.append(f"<p>Note: {html.escape(note)}.</p>")
    parts.append(f"<p><small>Ranked by cycle time; {html.escape(rule)} ({html.escape(res['source'])}). A variant "
                 "that ties with the first of a rank shares that rank. Only variants with status ok (clean tracking "
                 "data) are ranked.</small></p>")
    for group in ranking["tolerances"]:
        tol = group.get("tolerance_mm")
        if tol is not None:
            title = f"At tolerance {tol:g} mm (every corner's deviation solved to it; baselines without transitions)"
        elif group.get("like_for_like"):
            title = "The variants (no transitions)"
        else:
            title = ("Variants sized by their parameter (they cut corners by different amounts: not like for like; "
                     "give them a tolerance to compare them)")
        rows = []
        for v in group["variants"]:
            tie = "tie with the next" if v["tie"] else ""
            pct = "—" if v["margin_to_next_percent"] is None else f"{v['margin_to_next_percent']:.2f}"
            cls = " class='tie'" if v["tie"] else ""
            meets = "" if v.get("meets_constraints", True) else " <small class='bad'>(outside the constraints)</small>"
            rows.append(f"<tr{cls}><td>{v['rank']}</td><td>{html.escape(v['variant'])}{meets}</td>"
                        f"<td>{v['cycle_time_s']:.3f}</td><td>{ms(v['margin_to_next_s'])}</td><td>{pct}</td>"
                        f"<td>{tie}</td></tr>")
        for u in group["unranked"]:
            rows.append(f"<tr><td>—</td><td>{html.escape(u['variant'])}</td><td colspan='4' class='bad'>"
                        f"{html.escape(u['reason'])}</td></tr>")
        parts.append(f"<h3>{html.escape(title)}</h3><table class='ranking'><tr><th>rank</th><th>variant</th>"
                     "<th>cycle time [s]</th><th>margin to the next [ms]</th><th>margin to the next [%]</th>"
                     "<th></th></tr>" + "".join(rows) + "</table>")
    return parts


SENSITIVITY_METRICS = {
    "cycle_time_s": "cycle time (settled)",
    "contour_error_programmed_max_mm": "contour error, program",
    "contour_error_planned_max_mm": "contour error, plan",
    "residual_vibration_corner_max_mm": "vibration after corners",
    "residual_vibration_final_mm": "vibration after the stop",
}
# Beyond this many conclusions (a compare of many variants) the table keeps the cycle-time ones
# and those that do not hold in every model; summary.json has them all.
SENSITIVITY_MAX_ROWS = 60


def sensitivity_html(summary):
    """Next to the answer: what the sensitivity runs say of each conclusion of the nominal run
    (summary.json `sensitivity`, docs/sensitivity.md): the statement and in how many of the
    perturbed models its order holds."""
    sens = summary.get("sensitivity")
    if not sens:
        return []
    names = ", ".join(p["name"] for p in sens["perturbations"])
    parts = ["<h2>Sensitivity to the arm model</h2>",
             f"<p><small>Every clean variant re-run on {sens['models']} perturbed models, one parameter at a time "
             f"({html.escape(names)}); the plan and joint reference are the nominal run's. <i>holds in</i>: in how "
             "many perturbed models the nominal order holds (all, some, none); the range of the difference spans "
             f"the nominal and the perturbed models. {len(sens['conclusions'])} conclusions; "
             f"{sens['wall_time_s']:.1f} s on {sens['jobs']} threads.</small></p>"]
    for note in sens.get("notes", []) + [f"not re-run: {s}" for s in sens.get("skipped", [])]:
        parts.append(f"<p><small>Note: {html.escape(note)}.</small></p>")
    rows = sens["conclusions"]
    if len(rows) > SENSITIVITY_MAX_ROWS:
        kept = [c for c in rows if c["metric"] == "cycle_time_s" or c["holds_in"] != "all"]
        parts.append(f"<p><small>Shown: the cycle-time conclusions and those that do not hold in every model "
                     f"({len(kept)} of {len(rows)}; summary.json lists all).</small></p>")
        rows = kept
    cells = []
    for c in rows:
        cls = "" if c["holds_in"] == "all" else " class='tie'"
        fails = ", ".join(c["fails_in"]) or "—"
        cells.append(f"<tr{cls}><td>{html.escape(SENSITIVITY_METRICS.get(c['metric'], c['metric']))}</td>"
                     f"<td>{html.escape(c['statement'])}</td><td>{c['holds_in']} ({c['holds']}/{c['models']})</td>"
                     f"<td>{html.escape(fails)}</td></tr>")
    parts.append("<table class='sensitivity'><tr><th>metric</th><th>conclusion</th><th>holds in</th>"
                 "<th>not in</th></tr>" + "".join(cells) + "</table>")
    return parts


def corners_html(summary, frame):
    """Every corner as corners.json numbers it (C<index>), the program line it comes from, its point
    in program coordinates, and per variant the deviation it was given (mm; a tolerance not reached
    marked)."""
    entries = [e for e in summary["variants"] if e.get("plan", {}).get("corners")]
    if not entries:
        return []
    first = entries[0]["plan"]["corners"]
    head = "<tr><th>corner</th><th>source</th><th>point, program coordinates [mm]</th>" + "".join(
        f"<th>{html.escape(e['name'])}<br><small>deviation [mm]</small></th>" for e in entries) + "</tr>"
    rows = []
    for c in first:
        source = (f"{html.escape(os.path.basename(c.get('source_file') or ''))}:{c['source_line']}"
                  if c.get("source_line") else "—")
        point = "—"
        if c.get("point_mm") is not None and frame is not None:
            p = frame.program(np.array(c["point_mm"]))
            point = ", ".join(f"{x:.3f}" for x in p)
        cells = [f"<td>C{c['index']}</td><td>{source}</td><td>{point}</td>"]
        for e in entries:
            d = next((x for x in e["plan"]["corners"] if x["index"] == c["index"]), None)
            if d is None:
                cells.append("<td>—</td>")
                continue
            mark = " <small class='bad'>not reached</small>" if d.get("tolerance_reached") is False else ""
            cells.append(f"<td>{d['deviation_mm']:.4g}{mark}</td>")
        rows.append("<tr>" + "".join(cells) + "</tr>")
    return ["<h2>Corners</h2><p><small>Numbered as in corners.json, the plots and the videos (C&lt;index&gt;: the "
            "corner at the end of move index); source: the G-code line, or the YAML line, of the move that ends at "
            "the corner.</small></p>", f"<table>{head}{''.join(rows)}</table>"]


def report_html(run_dir, summary, variants, frame=None):
    table, best = comparison_table(summary["variants"], summary)

    def best_name(header):
        names = best.get(header)
        return html.escape(" = ".join(names) + (" (a tie)" if len(names) > 1 else "")) if names else "—"
    reading = (f"<p>Fastest (cycle time to settled at the end point): <b>{best_name('cycle time [s]')}</b>. "
               f"Most accurate against its own plan (contour error vs the planned path: the servo's error): "
               f"<b>{best_name('contour vs planned max [µm]')}</b>; closest to the programmed path: "
               f"<b>{best_name('contour vs programmed max [mm]')}</b> (that includes each method's designed "
               f"corner deviation). Least residual vibration after the stop: "
               f"<b>{best_name('vibration after stop [µm] / [Hz]')}</b>; after the corners: "
               f"<b>{best_name('largest corner vibration [µm]')}</b>. Best values are shaded, with every value "
               f"that ties with the best (within the regression gate's tolerance of that metric, "
               f"results/baselines/tolerances.json; cycle times at the resolution above); only variants with "
               f"status ok (clean tracking data) compete.</p>"
               "<p>Why, in the plots: the cycle time follows the planned path speed (<i>Path speed</i>: an exact "
               "stop comes to rest at every corner, a circular arc slows where its curvature jumps, a G2 "
               "transition keeps its speed); the vibration follows what the reference asks of the arm at the "
               "corners (<i>Acceleration and jerk</i>, <i>Curvature</i>: stopping and restarting, or a curvature "
               "step, against curvature that ramps) and shows in <i>Residual vibration</i> and the joints' "
               "<i>following errors</i>; the contour error against the programmed path is mostly each method's "
               "designed corner deviation, the one against the planned path the servo's own error.</p>")
    r = summary["robot"]
    s = summary["servo"]
    sim = summary["simulation"]
    freqs = ", ".join(f"{f:.1f}" for f in r["natural_frequency_arm_hz"] if isinstance(f, (int, float)) and f > 0)
    arm = (f"<p>Arm: <b>{html.escape(r['model'])}</b> joints ({html.escape(os.path.basename(r['mjcf']))}, physics step "
           f"{1e6 * r['timestep_s']:.0f} µs)"
           + (f"; natural frequencies at the start pose with the motors held: {freqs} Hz" if freqs else "")
           + f". Servo: {html.escape(s['controller'])}, {s['rate_hz']:g} Hz, measurement delay "
           f"{s['measurement_delay_ticks']} tick(s), {s['encoder_counts_per_turn']:.0f} counts per turn; velocity "
           f"feed-forward {on_off(s['velocity_feedforward'])}, acceleration (inverse-dynamics) feed-forward "
           f"{on_off(s['acceleration_feedforward'])}, gravity compensation {on_off(s['gravity_compensation'])}, deflection "
           f"compensation {on_off(s['deflection_compensation'])}; velocity-loop bandwidth "
           + ", ".join(f"{b:.1f}" for b in s["velocity_bandwidth_hz"])
           + f" Hz per joint. Settled: within {sim['settle_tolerance_mm']:g} mm and "
           f"{sim['settle_speed_tolerance_mm_s']:g} mm/s for {sim['settle_window_s']:g} s after the reference ends. "
           f"Residual vibration: tracking error high-passed at {sim['vibration_highpass_hz']:g} Hz, peak-to-peak in "
           f"{sim['vibration_window_s']:g} s windows.</p>")
    unreached, reached = tolerance_notes(summary)
    parts = [f"<h1>BlendBench run: {html.escape(summary['scenario'])}</h1>", *unreached, *answer_html(summary),
             *sensitivity_html(summary)]
    if reached:
        parts.append("<p><small>Tolerances reached:</small></p><ul style='font-size:smaller'>" + "".join(reached) + "</ul>")
    parts += [f"<p>{html.escape(summary.get('description', ''))}</p>", arm, "<h2>Comparison</h2>", reading, table,
              *corners_html(summary, frame)]
    for png, title in [("compare_speed.png", "Path speed"), ("compare_metrics.png", "Metrics"),
                       ("compare_path.png", "Paths")]:
        if os.path.exists(os.path.join(run_dir, png)):
            parts.append(f"<h3>{title}</h3><img src='{png}' alt='{title}'>")
    for v in variants:
        parts.append(f"<h2 id='{html.escape(v.name)}'>{html.escape(v.title)}</h2>")
        for png, title in VARIANT_FIGURES:
            parts.append(f"<figure><img src='{html.escape(v.name)}/{png}' alt='{title}'>"
                         f"<figcaption>{title}</figcaption></figure>")
    style = ("body{font-family:sans-serif;margin:2em;max-width:1400px} table{border-collapse:collapse;font-size:13px}"
             " td,th{border:1px solid #bbb;padding:4px 6px;text-align:right} td:first-child{text-align:left}"
             " .best{background:#d8f0d8} .ok{color:#070} .bad{color:#b00;text-align:left;max-width:18em}"
             " .answer{font-size:16px} tr.tie td{background:#eef3fb}"
             " figure{display:inline-block;margin:0.5em} img{max-width:100%}")
    page = ("<!DOCTYPE html><html><head><meta charset='utf-8'><title>BlendBench: "
            f"{html.escape(summary['scenario'])}</title><style>{style}</style></head><body>"
            + "\n".join(parts) + "</body></html>\n")
    write_text(os.path.join(run_dir, "report.html"), page)


def main(argv):
    if len(argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    run_dir = argv[1]
    with open(os.path.join(run_dir, "summary.json")) as f:
        summary = json.load(f)
    variants = [Variant(run_dir, e) for e in summary["variants"] if "metrics" in e]
    if variants:
        frame = Frame(summary, xyz(variants[0].program, ""))
        for v in variants:
            plot_variant(v, frame, summary)
        plot_comparison(run_dir, variants, frame)
    else:
        frame = None
    report_html(run_dir, summary, variants, frame)
    # one self-contained page: figures and scripts inlined, interactive views (report_page.py)
    report_page.finish(run_dir, summary, variants)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
