#!/usr/bin/python3
"""Each plot script on a small run (tests/data/tiny.yaml): the images exist and are not trivial.

usage: plot_scripts_test.py BLENDBENCH SOURCE_DIR OUT_DIR

Runs `blendbench run tests/data/tiny.yaml --no-video --no-plots`, then report/scripts/plot_run.py
on the run folder, and report/scripts/corner_figures.py on `blendbench path` outputs of the same
scenario's variants; checks every image the scripts promise is a PNG of a sensible size with
real content (many colours, not one flat field), that report.html has every image inlined (each a PNG with content), a table of contents and the
interactive views,
that corner_figures.py wrote its Markdown section, and that a run at a tolerance no corner
reaches says so at the top of its report.html. Exit status 0 when all hold.
"""

import base64
import os
import re
import shutil
import subprocess
import sys

from PIL import Image

PYTHON = "/usr/bin/python3"
# an image with content: at least this size, this many colours, and no colour on most pixels
MIN_WIDTH, MIN_HEIGHT = 300, 200
MIN_COLOURS = 16
MAX_DOMINANT_SHARE = 0.97

VARIANT_PNGS = ["path.png", "corners.png", "speed.png", "acceleration.png", "curvature.png", "tracking_error.png",
                "following_error.png", "torques.png", "vibration.png", "joints.png"]
RUN_PNGS = ["compare_speed.png", "compare_path.png", "compare_metrics.png"]

failures = []


def check_png(path):
    if not os.path.isfile(path):
        failures.append(f"{path}: missing")
        return
    with Image.open(path) as image:
        if image.format != "PNG":
            failures.append(f"{path}: not a PNG ({image.format})")
        width, height = image.size
        if width < MIN_WIDTH or height < MIN_HEIGHT:
            failures.append(f"{path}: {width} x {height} pixels, too small")
        colours = image.convert("RGB").getcolors(maxcolors=1 << 20)
        if colours is None:
            return  # more colours than counted: content
        if len(colours) < MIN_COLOURS:
            failures.append(f"{path}: {len(colours)} colours, a blank image")
        if max(c for c, _ in colours) > MAX_DOMINANT_SHARE * width * height:
            failures.append(f"{path}: one colour covers almost every pixel")


def run(args, **kw):
    result = subprocess.run(args, capture_output=True, text=True, **kw)
    if result.returncode != 0:
        failures.append(f"{' '.join(args)} exited {result.returncode}:\n{result.stdout}{result.stderr}")
    return result


def main(argv):
    binary, source, out = argv[1:4]
    scripts = os.path.join(source, "report", "scripts")
    tiny = os.path.join(source, "tests", "data", "tiny.yaml")
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)

    # plot_run.py on what a run wrote
    run_dir = os.path.join(out, "run")
    run([binary, "run", tiny, "--no-video", "--no-plots", "--out", run_dir])
    run([PYTHON, os.path.join(scripts, "plot_run.py"), run_dir])
    for variant in ("exact", "arc"):
        for png in VARIANT_PNGS:
            check_png(os.path.join(run_dir, variant, png))
    for png in RUN_PNGS:
        check_png(os.path.join(run_dir, png))
    report = os.path.join(run_dir, "report.html")
    if not os.path.isfile(report):
        failures.append(f"{report}: missing")
    else:
        with open(report) as f:
            page = f.read()
        images = re.findall(r"<img src='([^']+)'", page)
        if len(images) < 2 * len(VARIANT_PNGS) + len(RUN_PNGS):
            failures.append(f"{report}: only {len(images)} images")
        # every figure inlined (the page works copied alone) and still a figure with content
        for k, src in enumerate(images):
            prefix = "data:image/png;base64,"
            if not src.startswith(prefix):
                failures.append(f"{report}: image {src[:60]} is not inlined")
                continue
            inlined = os.path.join(out, f"inlined_{k}.png")
            with open(inlined, "wb") as f:
                f.write(base64.b64decode(src[len(prefix):]))
            check_png(inlined)
        if "id='explore-data'" not in page or "<nav class='toc'>" not in page:
            failures.append(f"{report}: no interactive views or no table of contents")

    # a tolerance no corner reaches (100 mm on 60 mm lines): the run goes on, and report.html says
    # so at the top (equal tolerance, docs/methods.md); the plain run above says nothing of it
    if "reached at no corner" in open(report).read():
        failures.append(f"{report}: a tolerance note in a run without a tolerance")
    far = os.path.join(out, "far")
    run([binary, "run", tiny, "--tolerance", "100", "--variant", "arc", "--no-video", "--no-plots", "--out", far])
    run([PYTHON, os.path.join(scripts, "plot_run.py"), far])
    far_report = os.path.join(far, "report.html")
    if not os.path.isfile(far_report):
        failures.append(f"{far_report}: missing")
    else:
        page = open(far_report).read()
        top = page[:page.find("<h2")]
        if "arc: the tolerance 100 mm is reached at no corner" not in top:
            failures.append(f"{far_report}: no note at the top that the tolerance is reached at no corner")
        # above the answer (the recommendation, issue 44), which comes before the comparison
        answer = page.find("Recommended: ")
        if answer < 0 or not page.find("reached at no corner") < answer < page.find("Comparison</h2>"):
            failures.append(f"{far_report}: the recommendation is not first after the tolerance note")

    # corner_figures.py on the variants' planned paths and corner reports
    args = []
    for variant in ("exact", "arc"):
        csv = os.path.join(out, f"{variant}.csv")
        report_json = os.path.join(out, f"{variant}.json")
        run([binary, "path", tiny, "--variant", variant, "--csv", csv, "--report", report_json])
        args += ["--run", variant, csv, report_json]
    figure = os.path.join(out, "corners.png")
    markdown = os.path.join(out, "corners.md")
    run([PYTHON, os.path.join(scripts, "corner_figures.py"), "--name", "tiny", "--description", "two lines",
         "--out", figure, "--markdown", markdown] + args)
    check_png(figure)
    if not os.path.isfile(markdown) or "| C0 | arc | arc |" not in open(markdown).read():
        failures.append(f"{markdown}: missing or without the arc variant's corner row")

    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
