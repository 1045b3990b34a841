#!/usr/bin/python3
"""Writes CAM-style point streams as G-code: a curve as many short G1 lines of equal arc length,
every coordinate with four decimals of a millimetre (as CAM post-processors write them, so the
points carry their 0.05 um rounding).

    tools/make_cam_stream.py cardioid LINES OUT.ngc [--length MM] [--feed MM_PER_MIN] [--tolerance MM]
    tools/make_cam_stream.py wave LINES OUT.ngc [--length MM] [--feed MM_PER_MIN] [--tolerance MM]

cardioid: the dimpled limacon r = a (1.25 + cos t), closed, starting at its far point (at the
origin of the program), scaled to --length round (default 164 mm); bench_cam's BM_Cardioid and
issue 45's figure are 10000 lines of it. wave: x = t, y = 4 sin(2 pi t / 25 mm),
z = 2 sin(2 pi t / 40 mm) for t in [0, 80] mm (--length scales it; default 100 mm long);
bench_cam's BM_Wave is 5000 lines. `--tolerance` writes G64 P (the biclothoid tolerance of every
corner, default 0.05 mm). scenarios/process/cam_contour.ngc is `cardioid 2000 ... --length 60`.
"""
import argparse
import bisect
import math


def cardioid(t):
    r = 1.25 + math.cos(t)
    return (r * math.cos(t), r * math.sin(t), 0.0)


def wave(t):
    return (t, 4 * math.sin(2 * math.pi * t / 25), 2 * math.sin(2 * math.pi * t / 40))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("shape", choices=["cardioid", "wave"])
    parser.add_argument("lines", type=int)
    parser.add_argument("out")
    parser.add_argument("--length", type=float, help="mm round (cardioid) or along (wave)")
    parser.add_argument("--feed", type=float, default=6000, help="mm/min")
    parser.add_argument("--tolerance", type=float, default=0.05, help="G64 P, mm")
    args = parser.parse_args()
    closed = args.shape == "cardioid"
    curve, t_end = (cardioid, 2 * math.pi) if closed else (wave, 80.0)
    # a dense table of arc length, 64 samples per line
    m = 64 * args.lines
    dense = [curve(t_end * i / m) for i in range(m + 1)]
    s = [0.0]
    for i in range(m):
        s.append(s[-1] + math.dist(dense[i], dense[i + 1]))
    length = args.length if args.length else (164.0 if closed else s[-1])
    scale = length / s[-1]
    origin = dense[0]
    points = []
    for k in range(args.lines + 1):
        target = s[-1] * k / args.lines
        j = min(max(bisect.bisect_left(s, target) - 1, 0), m - 1)
        share = (target - s[j]) / (s[j + 1] - s[j]) if s[j + 1] > s[j] else 0.0
        p = [dense[j][c] + share * (dense[j + 1][c] - dense[j][c]) for c in range(3)]
        points.append([(p[c] - origin[c]) * scale for c in range(3)])
    if closed:
        points[-1] = points[0]
    with open(args.out, "w") as f:
        f.write("(%s: %d lines, %.3f mm, written by tools/make_cam_stream.py)\n" % (args.shape, args.lines, length))
        f.write("G21 G90 G64 P%g\n" % args.tolerance)
        f.write("F%g\nG1\n" % args.feed)
        for p in points[1:]:
            f.write("X%.4f Y%.4f Z%.4f\n" % tuple(0.0 if abs(v) < 5e-5 else v for v in p))
        f.write("M2\n")


if __name__ == "__main__":
    main()
