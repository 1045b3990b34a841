#!/usr/bin/python3
"""report.html in a real browser (headless Chromium), copied alone into an empty folder.

usage: report_browser_test.py BLENDBENCH SOURCE_DIR OUT_DIR

Runs `blendbench run tests/data/tiny.yaml --no-video`, copies report.html ALONE into a fresh
folder (so a figure or script it still fetched from beside it would be missing), opens it in
Debian's `chromium --headless` with the network off, and fails on:
  - a console message from the page that is an error (window.onerror, console.error, a resource
    that did not load: the page's self-check records them) or an uncaught exception in the log;
  - the page's self-check (report_page.py) not reporting "ok": an image that did not decode, a
    time plot or the 3D view that drew nothing;
  - a src or href that leaves the file (anything but data: URIs, #anchors and the videos,
    which are linked relative to it), or a page larger than MAX_BYTES.
Prints the self-check line and the page's size. Exit 0 when all hold.
"""

import glob
import os
import re
import shutil
import subprocess
import sys

# the tiny run's page: 2 variants, 23 figures inlined, Chart.js and three.js (about 1 MB of
# scripts); measured 1.8 MB, so this bound catches an embedded trace that was not downsampled
MAX_BYTES = 4_000_000
# the flags that run Chromium headless here (docs/PLATFORM: no sandbox as root, software WebGL
# through SwiftShader, nothing fetched from the network, a profile of its own)
CHROMIUM_FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader",
                  "--disable-background-networking", "--disable-component-update", "--disable-sync",
                  "--no-first-run", "--disable-default-apps", "--enable-logging=stderr", "--v=0",
                  "--virtual-time-budget=8000", "--dump-dom"]
# Chromium's own console notes that are not the page's (SwiftShader's performance hints)
HARMLESS = re.compile(r"GL Driver Message|GPU stall due to ReadPixels")


def main(argv):
    binary, source, out = argv[1:4]
    browser = shutil.which("chromium")
    if browser is None:
        print("FAIL: chromium is not installed (apt-get install chromium; `bash tools/bootstrap.sh test` installs it)")
        return 1
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    run_dir = os.path.join(out, "run")
    r = subprocess.run([binary, "run", os.path.join(source, "tests", "data", "tiny.yaml"), "--no-video", "--out", run_dir],
                       capture_output=True, text=True)
    if r.returncode != 0:
        print(f"FAIL: blendbench run exited {r.returncode}:\n{r.stdout}{r.stderr}")
        return 1
    alone = os.path.join(out, "alone")
    os.makedirs(alone)
    page_file = os.path.join(alone, "report.html")
    shutil.copy(os.path.join(run_dir, "report.html"), page_file)
    failures = []

    with open(page_file, encoding="utf-8") as f:
        page = f.read()
    size = os.path.getsize(page_file)
    if size > MAX_BYTES:
        failures.append(f"report.html is {size} bytes, over {MAX_BYTES}")
    for attr, value in re.findall(r"\b(src|href)=['\"]([^'\"]*)['\"]", page):
        if value.startswith("data:") or value.startswith("#") or value.endswith(".mp4"):
            continue
        failures.append(f"{attr}='{value[:80]}' leaves the page")
    if re.search(r"<(link|iframe)\b", page):
        failures.append("a <link> or <iframe> in the page")

    profile = os.path.join(out, "profile")
    r = subprocess.run([browser, *CHROMIUM_FLAGS, f"--user-data-dir={profile}", "file://" + os.path.abspath(page_file)],
                       capture_output=True, text=True, timeout=300)
    dom, log = r.stdout, r.stderr
    check = re.search(r"<p id=\"selfcheck\" data-status=\"(\w+)\">([^<]*)", dom)
    if check is None:
        failures.append(f"no self-check in the page chromium rendered (exit {r.returncode}); log:\n{log[-2000:]}")
    else:
        print(check.group(2))
        if check.group(1) != "ok":
            failures.append(f"self-check: {check.group(2)}")
    for line in log.splitlines():
        if ("CONSOLE" in line and not HARMLESS.search(line)) or "Uncaught" in line:
            failures.append(f"console: {line}")
    print(f"report.html: {size} bytes ({size / 1e6:.2f} MB), opened alone in {os.path.basename(browser)} "
          f"({subprocess.run([browser, '--version'], capture_output=True, text=True).stdout.strip()})")
    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
