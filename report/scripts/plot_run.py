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
and in RUN_DIR compare_speed.png, compare_path.png, compare_metrics.png and report.html (the
comparison table and every figure; report_page.py then makes it one self-contained page). Every file is written
to a temporary file and renamed, so a failed run never leaves a half-written picture.
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
    origin, e1, e2 = frame
    fig, ax = plt.subplots(figsize=(7, 6))
    ax.plot(*project(xyz(v.program, ""), origin, e1, e2), color="0.6", lw=3, label="programmed")
    ax.plot(*project(xyz(v.path, ""), origin, e1, e2), color="tab:blue", lw=1.2, label="planned (blended)")
    ax.plot(*project(xyz(v.trace, "act_"), origin, e1, e2), color="tab:red", lw=0.8, ls="--", label="actual TCP")
    label_corners(ax, [(c["index"], *project(np.array(c["point_mm"]), origin, e1, e2)) for c in v.corners])
    ax.set_aspect("equal", adjustable="datalim")
    finish(ax, f"Path — {v.title}", "in-plane axis 1 [mm]", "in-plane axis 2 [mm]")
    save_png(fig, v.png("path.png"), DPI)


def label_corners(ax, corners):
    """C<index> beside each corner point (index, u, w); a label that would sit on one already
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
        ax.annotate(f"C{index}", (u, w), fontsize=8, xytext=(4, 4 + 10 * stack), textcoords="offset points",
                    arrowprops=dict(arrowstyle="-", color="0.6", lw=0.5) if stack else None)


def plot_corners(v, frame):
    """A zoomed view of each corner: the actual TCP against the planned and the programmed path."""
    origin, e1, e2 = frame
    n = max(1, len(v.corners))
    cols = min(n, 4)
    rows = (n + cols - 1) // cols
    fig, axes = plt.subplots(rows, cols, figsize=(3.6 * cols, 3.4 * rows), squeeze=False)
    prog = project(xyz(v.program, ""), origin, e1, e2)
    plan = project(xyz(v.path, ""), origin, e1, e2)
    act = project(xyz(v.trace, "act_"), origin, e1, e2)
    for ax in axes.flat[n:]:
        ax.axis("off")
    for ax, c in zip(axes.flat, v.corners):
        cu, cw = project(np.array(c["point_mm"]), origin, e1, e2)
        half = max(CORNER_MIN_HALF_MM, CORNER_MARGIN * max(c["trim_in_mm"], c["trim_out_mm"]))
        ax.plot(*prog, color="0.6", lw=3, label="programmed")
        ax.plot(*plan, color="tab:blue", lw=1.2, label="planned")
        ax.plot(*act, color="tab:red", lw=0.8, ls="--", label="actual")
        ax.plot(cu, cw, "k+", ms=10)
        ax.set_xlim(cu - half, cu + half)
        ax.set_ylim(cw - half, cw + half)
        ax.set_aspect("equal", adjustable="box")
        ax.set_title(f'C{c["index"]}: {c["method"]}, deviation {c["deviation_mm"]:.3g} mm', fontsize=9)
        ax.set_xlabel("axis 1 [mm]", fontsize=8)
        ax.set_ylabel("axis 2 [mm]", fontsize=8)
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
    origin, e1, e2 = frame
    zoom = widest_corner(variants)
    fig, axes = plt.subplots(1, 2 if zoom else 1, figsize=(13 if zoom else 7, 6), squeeze=False)
    for ax in axes[0]:
        ax.plot(*project(xyz(variants[0].program, ""), origin, e1, e2), color="0.6", lw=3, label="programmed")
        for v in variants:
            colour, dash = styles[v.name]
            ax.plot(*project(xyz(v.path, ""), origin, e1, e2), lw=1.2, label=v.name, color=colour,
                    dashes=dash or (None, None))
        ax.set_aspect("equal", adjustable="datalim")
    finish(axes[0][0], "Planned path by variant", "in-plane axis 1 [mm]", "in-plane axis 2 [mm]")
    if zoom:
        index, point, half = zoom
        u, w = project(np.array(point), origin, e1, e2)
        ax = axes[0][1]
        ax.set_xlim(u - half, u + half)
        ax.set_ylim(w - half, w + half)
        finish(ax, f"Corner C{index}, where the variants differ most", "in-plane axis 1 [mm]", "in-plane axis 2 [mm]",
               legend=False)
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


def comparison_table(entries):
    """The table's HTML and, per header, the best clean variant's name."""
    ok = [e for e in entries if e["status"] == "ok"]
    best = {}
    for header, key, _, _, lower, _ in TABLE:
        values = [(cell_value(e, key), e["name"]) for e in ok if cell_value(e, key) is not None]
        if values:
            best[header] = (min if lower else max)(values)[1]
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
            mark = " class='best'" if best.get(header) == e["name"] else ""
            cells.append(f"<td{mark}>{text}</td>")
        rows.append("<tr>" + "".join(cells) + "</tr>")
    head = "<tr><th>variant</th><th>status</th>" + "".join(f"<th>{html.escape(h)}</th>" for h, *_ in TABLE) + "</tr>"
    return f"<table>{head}{''.join(rows)}</table>", best


def tolerance_notes(summary):
    """Equal tolerance (docs/methods.md): a line per variant run at a tolerance, at the top of the
    report: at how many corners it was reached, and, where at none, that it was not, with the largest
    deviation reached (each corner's note in corners.json says why)."""
    lines = []
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
            lines.append(f"<p class='bad'><b>{name}: the tolerance {tol} mm is reached at no corner</b> "
                         f"(largest deviation {deviation:.4g} mm; each corner's note in {name}/corners.json says why: "
                         f"moves too short for it, or nothing to cut).</p>")
        else:
            lines.append(f"<p>{name}: tolerance {tol} mm reached at {reached} of {len(corners)} corners "
                         f"(largest deviation {deviation:.4g} mm).</p>")
    return lines


def report_html(run_dir, summary, variants):
    table, best = comparison_table(summary["variants"])

    def best_name(header):
        return html.escape(best.get(header, "—"))
    reading = (f"<p>Fastest (cycle time to settled at the end point): <b>{best_name('cycle time [s]')}</b>. "
               f"Most accurate against its own plan (contour error vs the planned path: the servo's error): "
               f"<b>{best_name('contour vs planned max [µm]')}</b>; closest to the programmed path: "
               f"<b>{best_name('contour vs programmed max [mm]')}</b> (that includes each method's designed "
               f"corner deviation). Least residual vibration after the stop: "
               f"<b>{best_name('vibration after stop [µm] / [Hz]')}</b>; after the corners: "
               f"<b>{best_name('largest corner vibration [µm]')}</b>. Best values are shaded; only variants with "
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
    parts = [f"<h1>BlendBench run: {html.escape(summary['scenario'])}</h1>", *tolerance_notes(summary),
             f"<p>{html.escape(summary.get('description', ''))}</p>", arm, "<h2>Comparison</h2>", reading, table]
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
        prog = xyz(variants[0].program, "")
        origin = prog.mean(axis=0)
        frame = (origin, *plane_basis(prog))
        for v in variants:
            plot_variant(v, frame, summary)
        plot_comparison(run_dir, variants, frame)
    report_html(run_dir, summary, variants)
    # one self-contained page: figures and scripts inlined, interactive views (report_page.py)
    report_page.finish(run_dir, summary, variants)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
