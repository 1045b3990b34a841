"""Reading BlendBench's CSV files and writing figures atomically, shared by the plot scripts.

Every file is written to a temporary name in the same folder and renamed, so a failed or
interrupted script never leaves a half-written picture or page.
"""

import csv
import json
import os

import numpy as np


def read_csv(path):
    """Columns of a CSV file keyed by header name: float arrays, or string arrays for columns
    that are not numeric."""
    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        rows = [row for row in reader if row]
    cols = {}
    for i, name in enumerate(header):
        values = [row[i] for row in rows]
        try:
            cols[name] = np.array([float(v) for v in values], dtype=float)
        except ValueError:
            cols[name] = np.array(values)
    return cols


def save_png(fig, path, dpi, tight=False):
    """Saves and closes a matplotlib figure."""
    import matplotlib.pyplot as plt

    tmp = path + ".tmp.png"
    if tight:
        fig.tight_layout()
    fig.savefig(tmp, dpi=dpi)
    plt.close(fig)
    os.replace(tmp, path)


def write_text(path, text):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)


# One colour and one marker per method, the same in every figure, the report's interactive plots
# and the videos. The colours come from render/method_colours.json, the one table (the videos
# compile it in); clothoid and biclothoid get different markers as well as colours, so coinciding
# points stay apart.
def _method_palette():
    here = os.path.dirname(os.path.abspath(__file__))
    with open(os.path.join(here, "..", "..", "render", "method_colours.json")) as f:
        table = json.load(f)
    return table["methods"], table["others"]


METHOD_COLOURS, OTHER_COLOURS = _method_palette()
METHOD_MARKERS = {"none": "o", "arc": "^", "bezier": "s", "clothoid": "D", "biclothoid": "v"}
OTHER_MARKERS = ["P", "X", "<", ">", "h"]
# variants of one method (several tolerances) share its colour and differ by dash
DASHES = [[], [6, 3], [2, 2], [8, 2, 2, 2]]


def method_colour(method):
    """The method's colour (a stable pick from OTHER_COLOURS for a method not listed)."""
    if method in METHOD_COLOURS:
        return METHOD_COLOURS[method]
    return OTHER_COLOURS[sum(map(ord, method)) % len(OTHER_COLOURS)]


def method_marker(method):
    if method in METHOD_MARKERS:
        return METHOD_MARKERS[method]
    return OTHER_MARKERS[sum(map(ord, method)) % len(OTHER_MARKERS)]


def variant_styles(entries):
    """{variant name: (colour, dash)} for a summary's variants: the method's colour, and a dash
    that tells apart variants of the same method, in their order."""
    seen = {}
    out = {}
    for e in entries:
        method = e.get("method", "")
        count = seen.get(method, 0)
        seen[method] = count + 1
        out[e["name"]] = (method_colour(method), DASHES[count % len(DASHES)])
    return out


# Metric keys end in their unit (docs/units.md); a label for a key: its words and the unit.
UNIT_SUFFIXES = [("_mm_s3", "mm/s³"), ("_mm_s2", "mm/s²"), ("_mm_s", "mm/s"), ("_mm_per_min", "mm/min"),
                 ("_per_mm2", "1/mm²"), ("_per_mm", "1/mm"), ("_um", "µm"), ("_mm", "mm"), ("_s", "s"),
                 ("_hz", "Hz"), ("_deg_s", "deg/s"), ("_deg", "deg"), ("_percent", "%"), ("_nm", "N·m"),
                 ("_mrad", "mrad"), ("_j", "J")]


def metric_label(key):
    """'metrics.contour_error_planned_max_mm' -> 'contour error planned max [mm]'."""
    key = key.rsplit(".", 1)[-1]
    for suffix, unit in UNIT_SUFFIXES:
        if key.endswith(suffix):
            return key[: -len(suffix)].replace("_", " ") + f" [{unit}]"
    return key.replace("_", " ")
