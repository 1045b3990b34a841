#!/usr/bin/python3
"""Corner figures: every method on the same corners, path and curvature side by side.

usage: /usr/bin/python3 corner_figures.py --name NAME [--description TEXT] --out FIGURE.png
           [--markdown SECTION.md [--link PATH]] [--title TEXT] --run NAME PATH.csv REPORT.json [--run ...]

Each --run is one variant of the same program as written by
`blendbench path SCENARIO.yaml --variant NAME --csv PATH.csv --report REPORT.json`
(CSV columns s,x,y,z,tx,ty,tz,kappa in mm, unit tangent, 1/mm; the report is the JSON array of
corner reports). At least one run must be an exact stop (every corner of method "none"): the
first one's path is the programmed path, drawn grey, and gives the arc length of each corner;
further exact-stop runs (e.g. velocity baselines) have the same path and are not drawn.

The corner points, their arc lengths along the programmed path and each transition's span on
its run's path come from the corner reports, as blendbench writes them (point_mm,
s_programmed_mm, s_start_mm, s_end_mm): nothing is re-derived from the scenario, so G-code
programs work as well. --name and --description title the figure and its index section.

The figure has an overview row (the whole program in its plane, corners labelled C0, C1, ...)
and one row per corner: the path near the corner in the corner's plane (equal aspect,
programmed path grey, every run overlaid, open circles where each transition starts and ends),
a closer view of the corner tip, the unsigned curvature kappa(s) around the corner for every
run, and the corner reports (case, length, deviation, kappa_max, feed_max, notes). Arc length
on the kappa axis is aligned between runs: 0 is the programmed corner, and run r's arc length is
shifted so that its point opposite the programmed corner (its transition's start plus trim_in)
is 0: each transition starts at -trim_in.

--markdown writes a Markdown section (title, one line of what the figure shows, a table of the
corner reports) for the figures index; --link is how the index refers to the figure. Every
output is written to a temporary file and renamed.
"""

import argparse
import io
import json
import math
import os
import sys
import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from PIL import Image  # noqa: E402

import plotio  # noqa: E402

# Colour and line style per method (biclothoid dashed: it often coincides with the clothoid
# pair); further runs of a method get the extra colours and styles.
METHOD_STYLES = {
    "arc": ("tab:blue", "-"),
    "bezier": ("tab:orange", "-"),
    "clothoid": ("tab:green", "-"),
    "biclothoid": ("tab:red", (0, (4, 2))),
}
EXTRA_COLOURS = ["tab:purple", "tab:brown", "tab:pink", "tab:olive", "tab:cyan"]
EXTRA_STYLES = ["--", "-.", ":"]
PROGRAMMED_COLOUR = "0.55"
# Line widths run from the first to the last blended run, so a later run drawn over an equal
# earlier one leaves the earlier one's colour visible at its edges.
WIDEST, THINNEST = 3.2, 1.2
# The corner view covers every run's trimmed part with this margin ...
WINDOW_MARGIN = 1.25
# ... and is at least this share of the program size (zero-length transitions).
MIN_WINDOW_SHARE = 0.04
# Padding of the corner view around what it frames.
VIEW_PAD = 1.15
# The tip view frames the corner and each transition's point nearest to it with this margin,
# and is between these shares of the corner view.
TIP_MARGIN = 1.6
TIP_MIN_SHARE = 0.1
TIP_MAX_SHARE = 0.5
# Report text: font size (pt), line pitch in font sizes, wrap width of notes (characters).
REPORT_FONT = 9
REPORT_PITCH = 1.3
NOTE_WIDTH = 66
NOTE_LINES = 2
DPI = 90
# Deviations below this (mm) are rounding and shown as 0 in titles.
SHOWN_ZERO_MM = 1e-9
# Points whose second principal extent is below this share of the first lie on a line.
STRAIGHT_RATIO = 1e-6
# A plane whose normal is this close to a base axis is drawn in base coordinates.
AXIS_ALIGNED_COS = 0.9999


def fail(message):
    print(f"corner_figures.py: {message}", file=sys.stderr)
    sys.exit(2)


def read_path_csv(path):
    """Columns of a sampled path as float arrays keyed by header name; fails on NaN or infinity."""
    cols = plotio.read_csv(path)
    for name, values in cols.items():
        if values.dtype.kind != "f" or not np.all(np.isfinite(values)):
            fail(f"{path}: column {name} has non-finite or non-numeric values")
    return cols


class Run:
    """One variant: sampled path (mm) and corner reports."""

    def __init__(self, name, csv_path, report_path):
        self.name = name
        cols = read_path_csv(csv_path)
        self.s = cols["s"]
        self.xyz = np.column_stack([cols["x"], cols["y"], cols["z"]])
        self.kappa = cols["kappa"]
        with open(report_path) as f:
            self.reports = json.load(f)
        methods = {r["method"] for r in self.reports}
        self.exact_stop = methods <= {"none"}
        self.method = "none" if self.exact_stop else "+".join(sorted(methods - {"none"}))

    def corner_zero(self, k):
        """Arc length (mm, along this run) opposite the programmed corner k: where its transition
        starts plus the length it trimmed from the incoming move."""
        return self.reports[k]["s_start_mm"] + self.reports[k]["trim_in_mm"]

    def transition_span(self, k):
        """Arc length (mm, along this run) where the transition at corner k starts and ends."""
        return self.reports[k]["s_start_mm"], self.reports[k]["s_end_mm"]

    def at(self, s):
        """Point (mm) at arc length s, interpolated between samples."""
        return np.array([np.interp(s, self.s, self.xyz[:, i]) for i in range(3)])


class Plane:
    """A drawing plane: base coordinates when it is a base plane, else axes u, v from `origin`."""

    def __init__(self, e1, e2, origin, labels, normal):
        self.e1, self.e2, self.origin, self.labels, self.normal = e1, e2, origin, labels, normal

    def uv(self, points):
        rel = np.asarray(points) - self.origin
        return rel @ self.e1, rel @ self.e2

    def caption(self, origin_name):
        if self.labels[0].startswith("u"):
            return f"plane normal {vec_text(self.normal)}, origin {origin_name}"
        return ""


def plane_for(points, origin, origin_label, fallback=None):
    """Best-fit plane of points (N x 3, mm); a straight set gives `fallback` or, without one,
    the plane through the line closest to horizontal. Non-base planes are measured from origin."""
    centred = points - points.mean(axis=0)
    _, sv, vt = np.linalg.svd(centred, full_matrices=False)
    base = np.eye(3)
    if sv.size < 2 or sv[1] <= STRAIGHT_RATIO * max(sv[0], 1e-12):
        if fallback is not None:
            return fallback
        d = vt[0]
        up = base[2] if abs(d[2]) < AXIS_ALIGNED_COS else base[1]
        normal = up - (up @ d) * d
        normal /= np.linalg.norm(normal)
        e1, e2 = d, np.cross(normal, d)
    else:
        e1, e2, normal = vt[0], vt[1], vt[2]
    names = ["x", "y", "z"]
    for axis in range(3):
        if abs(normal @ base[axis]) > AXIS_ALIGNED_COS:
            i, j = [(1, 2), (0, 2), (0, 1)][axis]
            return Plane(base[i], base[j], np.zeros(3), (f"{names[i]} (mm)", f"{names[j]} (mm)"), normal)
    return Plane(e1, e2, origin, (f"u from {origin_label} (mm)", f"v from {origin_label} (mm)"), np.cross(e1, e2))


def vec_text(v):
    return "(" + ", ".join(f"{x:.2f}" for x in v) + ")"


def report_text(run, report):
    """Two or more lines: the run and its case, the numbers, the note (wrapped)."""
    case = report["case"] + (f" [{report['fallback']}]" if report["fallback"] else "")
    feed = report["feed_max_mm_per_min"]
    feed_text = "inf" if feed is None else f"{feed:.0f}"
    text = (f"{run.name}: {case}\n   L {report['length_mm']:.2f} mm  dev {report['deviation_mm']:.3f} mm"
            f"  κmax {report['kappa_max_per_mm']:.4f}/mm  feed {feed_text} mm/min")
    if report["stop"]:
        text += "  stop"
    if report["note"]:
        lines = textwrap.wrap(report["note"], NOTE_WIDTH, max_lines=NOTE_LINES, placeholder=" ...")
        text += "".join("\n   " + line for line in lines)
    return text


def styles(runs):
    """Colour, line style and width per blended run."""
    out = {}
    seen = {}
    extra = iter(EXTRA_COLOURS)
    widths = np.linspace(WIDEST, THINNEST, max(len(runs), 2))
    for idx, run in enumerate(runs):
        n = seen.get(run.method, 0)
        seen[run.method] = n + 1
        if n == 0 and run.method in METHOD_STYLES:
            colour, ls = METHOD_STYLES[run.method]
        else:
            colour, ls = next(extra, "black"), EXTRA_STYLES[n % len(EXTRA_STYLES)]
        out[run.name] = dict(color=colour, ls=ls, lw=widths[idx])
    return out


def masked(values, mask):
    """values with NaN outside mask, so separate visits of a window are not joined."""
    out = np.array(values, dtype=float)
    out[~mask] = np.nan
    return out


def draw_paths(ax, plane, programmed, blended, style, c, centre_uv, half):
    """Programmed path (grey) and every run in a square window of half-width `half` (mm) around
    centre_uv, showing only what lies near the corner c in space (other parts of the program may
    project into the window)."""
    centre_gap = np.hypot(*(np.array(centre_uv) - np.array(plane.uv(c))))
    radius = centre_gap + 1.5 * math.sqrt(2) * half
    for run in [programmed] + blended:
        u, v = plane.uv(run.xyz)
        m = np.linalg.norm(run.xyz - c, axis=1) <= radius
        if run is programmed:
            ax.plot(masked(u, m), masked(v, m), color=PROGRAMMED_COLOUR, lw=5, solid_capstyle="butt")
        else:
            ax.plot(masked(u, m), masked(v, m), **style[run.name])
    ax.set_xlim(centre_uv[0] - half, centre_uv[0] + half)
    ax.set_ylim(centre_uv[1] - half, centre_uv[1] + half)
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel(plane.labels[0])
    ax.set_ylabel(plane.labels[1])
    ax.grid(alpha=0.3)


def mark_corner(ax, plane, c, blended, style, k, corner_s):
    """The corner (+) and open circles where each run's transition starts and ends."""
    u, v = plane.uv(c)
    ax.plot(u, v, "k+", ms=12, mew=1.5)
    for run in blended:
        ends = np.array([run.at(s) for s in run.transition_span(k)])
        u, v = plane.uv(ends)
        ax.plot(u, v, "o", mfc="none", mec=style[run.name]["color"], ms=7, mew=1.3)


def draw_overview(fig, cell, text_cell, programmed, blended, style, corners, name, description):
    """The whole program in its plane with the corners labelled; description and legend."""
    plane = plane_for(programmed.xyz, programmed.xyz.mean(axis=0), "the program's centre")
    ax = fig.add_subplot(cell)
    ax.plot(*plane.uv(programmed.xyz), color=PROGRAMMED_COLOUR, lw=5, label="programmed (exact stop)")
    for run in blended:
        ax.plot(*plane.uv(run.xyz), label=f"{run.name} ({run.method})", **style[run.name])
    for k, c in enumerate(corners):
        u, v = plane.uv(c)
        ax.plot(u, v, "k+", ms=12, mew=1.5)
        ax.annotate(f"C{k}", (u, v), textcoords="offset points", xytext=(7, 7), fontsize=12, fontweight="bold")
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel(plane.labels[0])
    ax.set_ylabel(plane.labels[1])
    caption = plane.caption("the program's centre")
    ax.text(0.01, 0.97, "whole program" + (f" ({caption})" if caption else ""), transform=ax.transAxes, va="top",
            fontsize=11)
    ax.grid(alpha=0.3)
    handles, labels = ax.get_legend_handles_labels()
    ax = fig.add_subplot(text_cell)
    ax.axis("off")
    ax.text(0, 1, f"{name}\n" + "\n".join(textwrap.wrap(description, 60)), va="top", fontsize=10)
    ax.legend(handles, labels, loc="lower left", fontsize=10, frameon=False)
    return plane


def draw_corner(fig, cells, k, c, corner_s, programmed, blended, style, program_plane, extent):
    """One row: corner view, tip view, kappa(s), reports."""
    reports = [r.reports[k] for r in blended]
    reach = max([WINDOW_MARGIN * max(r["trim_in_mm"], r["trim_out_mm"]) for r in reports] +
                [MIN_WINDOW_SHARE * extent])
    # the corner's plane from the programmed path near it, the program's plane when straight
    near = np.linalg.norm(programmed.xyz - c, axis=1) <= reach
    plane = plane_for(programmed.xyz[near], c, f"C{k}", fallback=program_plane)
    cases = sorted({r["case"] for r in reports})
    caption = plane.caption(f"C{k}")

    # corner view: framed on everything within reach of the corner
    uv = [np.column_stack(plane.uv(run.xyz[np.linalg.norm(run.xyz - c, axis=1) <= reach]))
          for run in [programmed] + blended]
    uv = np.vstack(uv + [np.column_stack(plane.uv(c[None, :]))])
    lo, hi = uv.min(axis=0), uv.max(axis=0)
    half = VIEW_PAD * max(0.5 * (hi - lo).max(), 1e-3)
    ax = fig.add_subplot(cells[0])
    draw_paths(ax, plane, programmed, blended, style, c, 0.5 * (lo + hi), half)
    mark_corner(ax, plane, c, blended, style, k, corner_s)
    ax.set_title(f"C{k}: {', '.join(cases)}" + (f"\n{caption}" if caption else ""), fontsize=11,
                 fontweight="bold")

    # tip view: the corner and each transition's point nearest to it (a zero-length transition
    # or a kink leaves the corner elsewhere and is not framed)
    nearest = [c]
    for run, report in zip(blended, reports):
        if report["length_mm"] > 0:
            a, b = run.transition_span(k)
            on = (run.s >= a) & (run.s <= b)
            if on.any():
                nearest.append(run.xyz[on][np.argmin(np.linalg.norm(run.xyz[on] - c, axis=1))])
    tip_centre = np.mean(nearest, axis=0)
    spread = max(np.linalg.norm(p - tip_centre) for p in nearest)
    tip = min(max(TIP_MARGIN * spread, TIP_MIN_SHARE * half), TIP_MAX_SHARE * half)
    ax = fig.add_subplot(cells[1])
    draw_paths(ax, plane, programmed, blended, style, c, plane.uv(tip_centre), tip)
    mark_corner(ax, plane, c, blended, style, k, corner_s)
    dev = max(r["deviation_mm"] for r in reports) if reports else 0.0
    dev_text = "0" if dev < SHOWN_ZERO_MM else f"{dev:.3g}"
    ax.set_title(f"C{k} tip (largest reported deviation {dev_text} mm)", fontsize=11)

    # curvature around the corner, arc length aligned on the programmed corner
    ax = fig.add_subplot(cells[2])
    rel = programmed.s - corner_s
    m = np.abs(rel) <= reach
    ax.plot(masked(rel, m), masked(programmed.kappa, m), color=PROGRAMMED_COLOUR, lw=5)
    for run in blended:
        zero = run.corner_zero(k)
        rel = run.s - zero
        m = np.abs(rel) <= reach
        ax.plot(masked(rel, m), masked(run.kappa, m), **style[run.name])
        ends = np.array(run.transition_span(k)) - zero
        ax.plot(ends, [0, 0], "|", color=style[run.name]["color"], ms=14, mew=2, clip_on=False)
    ax.axvline(0, color="k", lw=0.8, ls=":")
    ax.set_xlim(-reach, reach)
    ax.set_ylim(bottom=0)
    ax.set_xlabel("s − s(corner) (mm); ticks: each transition's start and end")
    ax.set_ylabel("κ, unsigned (1/mm)")
    ax.set_title(f"C{k}: curvature κ(s)", fontsize=11)
    ax.grid(alpha=0.3)

    # corner reports, each in its run's colour
    ax = fig.add_subplot(cells[3])
    ax.axis("off")
    ax.text(0, 1.02, f"C{k} corner reports", va="top", fontsize=11, fontweight="bold", transform=ax.transAxes)
    line = REPORT_PITCH * REPORT_FONT / 72 / (ax.get_position().height * fig.get_figheight())
    y = 1.02 - 1.6 * line
    for run, report in zip(blended, reports):
        text = report_text(run, report)
        ax.text(0, y, text, va="top", fontsize=REPORT_FONT, color=style[run.name]["color"], transform=ax.transAxes,
                linespacing=1.15)
        y -= line * (text.count("\n") + 1.4)


def draw(name, description, out, title, runs):
    """Draws the figure; returns the blended runs for the index."""
    stops = [r for r in runs if r.exact_stop]
    if not stops:
        fail("no run is an exact stop (method none at every corner): one is needed as the programmed path")
    programmed = stops[0]
    for r in programmed.reports:
        for key in ("point_mm", "s_programmed_mm", "s_start_mm", "s_end_mm"):
            if key not in r:
                fail(f"run {programmed.name}: corner report {r.get('index')} has no {key} (write it with blendbench path --report)")
    corners = [np.array(r["point_mm"], dtype=float) for r in programmed.reports]
    corner_s = [r["s_programmed_mm"] for r in programmed.reports]
    blended = [r for r in runs if not r.exact_stop]
    for run in runs:
        if len(run.reports) != len(corners):
            fail(f"run {run.name}: {len(run.reports)} corner reports, the program has {len(corners)} corners")
    style = styles(blended)
    extent = np.ptp(programmed.xyz, axis=0).max()

    rows = 1 + len(corners)
    height = 1.0 + 3.7 * rows
    fig = plt.figure(figsize=(19, height))
    grid = fig.add_gridspec(rows, 4, width_ratios=[1.0, 1.0, 1.4, 1.6], height_ratios=[1.15] + [1.0] * len(corners),
                            hspace=0.45, wspace=0.3, left=0.045, right=0.995, top=1 - 0.55 / height,
                            bottom=0.75 / height)
    fig.suptitle(title or name, fontsize=15, fontweight="bold", y=1 - 0.12 / height, va="top")
    program_plane = draw_overview(fig, grid[0, 0:3], grid[0, 3], programmed, blended, style, corners, name,
                                  description)
    for k, c in enumerate(corners):
        draw_corner(fig, [grid[k + 1, i] for i in range(4)], k, c, corner_s[k], programmed, blended, style,
                    program_plane, extent)
    save_atomic(fig, out)
    return blended


def save_atomic(fig, path):
    """PNG with a 256-colour palette (line art loses nothing visible, the file a third)."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=DPI)
    plt.close(fig)
    buf.seek(0)
    image = Image.open(buf).convert("RGB").quantize(colors=256, method=Image.Quantize.MEDIANCUT)
    tmp = path + ".tmp.png"
    image.save(tmp, format="PNG", optimize=True)
    os.replace(tmp, path)


def markdown(link, name, description, blended):
    """An index section: the figure, what it shows, and the corner reports as a table."""
    lines = [f"### {name}", "", f"[`{link}`]({link}): {description}", "",
             "| corner | variant | method | case | length (mm) | deviation (mm) | κmax (1/mm) | feed_max (mm/min) | note |",
             "|---|---|---|---|---|---|---|---|---|"]
    for k in range(len(blended[0].reports) if blended else 0):
        for run in blended:
            r = run.reports[k]
            case = r["case"] + (f" ({r['fallback']})" if r["fallback"] else "")
            feed = r["feed_max_mm_per_min"]
            note = "; ".join(([] if not r["stop"] else ["stop"]) + ([r["note"]] if r["note"] else []))
            lines.append(f"| C{k} | {run.name} | {r['method']} | {case} | {r['length_mm']:.3f} |"
                         f" {r['deviation_mm']:.4f} | {r['kappa_max_per_mm']:.4f} |"
                         f" {'∞' if feed is None else f'{feed:.0f}'} | {note} |")
    return "\n".join(lines) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--name", required=True)
    parser.add_argument("--description", default="")
    parser.add_argument("--out", required=True)
    parser.add_argument("--markdown")
    parser.add_argument("--link", help="the figure's path as the Markdown index refers to it (default: its name)")
    parser.add_argument("--title")
    parser.add_argument("--run", nargs=3, action="append", metavar=("NAME", "CSV", "REPORT"), required=True)
    args = parser.parse_args()
    runs = [Run(*r) for r in args.run]
    blended = draw(args.name, args.description, args.out, args.title, runs)
    if args.markdown:
        plotio.write_text(args.markdown,
                          markdown(args.link or os.path.basename(args.out), args.name, args.description, blended))


if __name__ == "__main__":
    main()
