"""Reading BlendBench's CSV files and writing figures atomically, shared by the plot scripts.

Every file is written to a temporary name in the same folder and renamed, so a failed or
interrupted script never leaves a half-written picture or page.
"""

import csv
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
