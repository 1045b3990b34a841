"""Makes a run's report.html one self-contained page (issue 47).

plot_run.py writes report.html with its figures beside it; finish() then rewrites it so that it
works copied alone and offline:
  - every <img> of the run folder inlined as a data URI (PNG, re-encoded with a 256-colour
    palette when that is smaller: matplotlib's line plots lose nothing visible);
  - a warnings box under the title (summary.json's `warnings`) and the program's version;
  - a table of contents of every section, after the first screen (the answer);
  - "Explore": zoomable, pannable time plots (Chart.js) of path speed, tracking error, contour
    error against the plan and residual vibration, every variant in its method's colour; and a
    3D view (three.js) of the programmed, planned and actual paths that turns, zooms and jumps
    to each corner C<index> (the one corner numbering of corners.json);
  - links to the videos, relative to the page (they stay beside it);
  - a self-check that runs in the browser and writes its result into the page
    (#selfcheck, data-status "ok" or "fail"): every image decoded, every plot and the 3D view
    drew something, no script error. The browser test (tests/report/report_browser_test.sh)
    reads it.
The scripts are Debian's libjs-chart.js (3.9.1) and libjs-three (r111, with OrbitControls from
its examples), inlined when the page is written; no network is used at view time. Without them
the page says so and keeps everything else.
"""

import base64
import html
import io
import json
import os
import re

import numpy as np
from plotio import variant_styles, write_text

SCRIPTS = {
    "chart": "/usr/share/javascript/chart.js/chart.min.js",
    "three": "/usr/share/javascript/three/three.min.js",
    "orbit": "/usr/share/javascript/three/examples/js/controls/OrbitControls.js",
}
# Each series of a time plot keeps at most this many points (the min and max of each of half as
# many buckets, so peaks survive); the 3D paths at most PATH_POINTS.
SERIES_POINTS = 1200
PATH_POINTS = 3000

def decimate(t, y, points=SERIES_POINTS):
    """Indices of at most `points` samples of y(t) that keep each bucket's min and max (sorted)."""
    n = len(y)
    if n <= points:
        return np.arange(n)
    buckets = max(1, points // 2)
    edges = np.linspace(0, n, buckets + 1).astype(int)
    keep = []
    for a, b in zip(edges[:-1], edges[1:]):
        if b <= a:
            continue
        seg = y[a:b]
        keep.append(a + int(np.argmin(seg)))
        keep.append(a + int(np.argmax(seg)))
    keep.append(n - 1)
    return np.unique(np.array(keep))


def rounded(values, decimals):
    return [round(float(v), decimals) for v in values]


def series(v, column, scale=1.0):
    t = v.trace["t"]
    y = v.trace[column] * scale
    k = decimate(t, y)
    return {"t": rounded(t[k], 4), "y": rounded(y[k], 3)}


def vibration_um(v):
    t = v.trace["t"]
    y = np.sqrt(v.trace["vibration_x_mm"] ** 2 + v.trace["vibration_y_mm"] ** 2 + v.trace["vibration_z_mm"] ** 2) * 1e3
    k = decimate(t, y)
    return {"t": rounded(t[k], 4), "y": rounded(y[k], 3)}


def path_points(x, y, z, points=PATH_POINTS):
    n = len(x)
    k = np.unique(np.linspace(0, n - 1, min(n, points)).astype(int)) if n else np.arange(0)
    return [rounded(x[k], 4), rounded(y[k], 4), rounded(z[k], 4)]


def explore_data(summary, variants):
    """What the interactive views draw: per variant its time series (s; mm/s, µm) and paths (mm,
    robot base frame), the corners (C<index>, point, extent) and the colours."""
    colours = variant_styles(summary["variants"])
    out = {"variants": [], "program": None}
    for v in variants:
        colour, dash = colours[v.name]
        tr = v.trace
        cmd = [tr["cmd_x"], tr["cmd_y"], tr["cmd_z"]]
        act = [tr["act_x"], tr["act_y"], tr["act_z"]]
        k = np.unique(np.linspace(0, len(tr["t"]) - 1, min(len(tr["t"]), PATH_POINTS)).astype(int))
        corners = []
        for c in v.corners:
            if "point_mm" not in c:
                continue
            extent = max(float(c.get("trim_in_mm", 0) or 0), float(c.get("trim_out_mm", 0) or 0), 2.0)
            line = c.get("source_line")
            corners.append({"index": c["index"], "point": rounded(c["point_mm"], 4), "extent": round(extent, 3),
                            "source": f'{os.path.basename(str(c.get("source_file") or ""))}:{line}' if line else ""})
        out["variants"].append({
            "name": v.name,
            "method": v.entry.get("method", ""),
            "colour": colour,
            "dash": dash,
            "speed": series(v, "tcp_speed_mm_s"),
            "tracking": series(v, "tracking_error_mm", 1e3),
            "contour": series(v, "contour_error_planned_mm", 1e3),
            "vibration": vibration_um(v),
            "planned": path_points(v.path["x"], v.path["y"], v.path["z"]),
            # commanded and actual TCP at the same instants: the view exaggerates their difference
            "commanded": [rounded(a[k], 4) for a in cmd],
            "actual": [rounded(a[k], 4) for a in act],
            "corners": corners,
        })
        if out["program"] is None:
            out["program"] = path_points(v.program["x"], v.program["y"], v.program["z"])
    return out


def png_data_uri(path):
    """The PNG at `path` as a data URI: its bytes, or a 256-colour palette copy when smaller."""
    with open(path, "rb") as f:
        raw = f.read()
    best = raw
    try:
        from PIL import Image

        with Image.open(io.BytesIO(raw)) as im:
            quantised = im.convert("RGB").quantize(colors=256, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE)
            buf = io.BytesIO()
            quantised.save(buf, format="PNG", optimize=True)
            if buf.tell() < len(raw):
                best = buf.getvalue()
    except Exception:  # noqa: BLE001 -- PIL missing or an image it cannot read: the original bytes
        best = raw
    return "data:image/png;base64," + base64.b64encode(best).decode("ascii")


def inline_images(page, run_dir):
    """Every <img src='relative path inside run_dir'> as a data URI; others left for the self-check."""
    root = os.path.realpath(run_dir)

    def replace(m):
        quote, src = m.group(1), html.unescape(m.group(2))
        if src.startswith("data:"):
            return m.group(0)
        path = os.path.realpath(os.path.join(root, src))
        if not path.startswith(root + os.sep) or not os.path.isfile(path):
            return m.group(0)
        return f"<img src={quote}{png_data_uri(path)}{quote}"

    return re.sub(r"<img src=(['\"])([^'\"]*)\1", replace, page)


def slug(text):
    s = re.sub(r"[^a-z0-9]+", "-", text.lower()).strip("-")
    return s or "section"


def contents(page):
    """The page with an id on every <h2> and the table of contents (HTML) listing them."""
    items = []
    used = set()

    def replace(m):
        attrs, title = m.group(1), m.group(2)
        found = re.search(r"id=['\"]([^'\"]+)['\"]", attrs)
        ident = html.unescape(found.group(1)) if found else slug(re.sub(r"<[^>]+>", "", html.unescape(title)))
        while ident in used:
            ident += "-"
        used.add(ident)
        items.append((ident, re.sub(r"<[^>]+>", "", title)))
        return f"<h2 id='{html.escape(ident)}'>{title}</h2>" if not found else m.group(0)

    page = re.sub(r"<h2([^>]*)>(.*?)</h2>", replace, page, flags=re.S)
    return page, items


def warnings_box(summary):
    warnings = summary.get("warnings") or []
    if not warnings:
        return ""
    rows = "".join(f"<li><code>{html.escape(w.get('text') or w.get('message', ''))}</code></li>" for w in warnings)
    return (f"<div class='warnings'><b>{len(warnings)} plausibility warning(s)</b> (the input ran; check that it "
            f"means what it says):<ul>{rows}</ul></div>")


def videos_section(run_dir, variants):
    links = []
    for name in ["compare.mp4", "video.mp4"]:
        if os.path.isfile(os.path.join(run_dir, name)):
            links.append(f"<li><a href='{name}'>{name}</a> (all variants side by side)</li>")
    for v in variants:
        rel = f"{v.name}/video.mp4"
        if os.path.isfile(os.path.join(run_dir, rel)):
            links.append(f"<li><a href='{html.escape(rel)}'>{html.escape(v.name)}</a> ({html.escape(v.entry.get('method', ''))})</li>")
    if not links:
        return ("<h2 id='videos'>Videos</h2><p>No video in this run (<code>--no-video</code>, or rendering is not "
                "built).</p>")
    return ("<h2 id='videos'>Videos</h2><p>Beside this page in the run folder (links relative to it; copied alone, "
            "the page keeps everything else):</p><ul>" + "".join(links) + "</ul>")


EXPLORE_HTML = """
<h2 id='explore'>Explore: time plots and 3D paths</h2>
<p class='hint'>Time plots: drag to zoom into a time span, shift-drag to pan, wheel to zoom about the pointer,
double-click to reset; the four plots move together. Click a legend entry to hide a variant.</p>
<div class='charts'>
 <div class='chartbox'><canvas id='chart-speed' data-selfcheck='plot'></canvas></div>
 <div class='chartbox'><canvas id='chart-tracking' data-selfcheck='plot'></canvas></div>
 <div class='chartbox'><canvas id='chart-contour' data-selfcheck='plot'></canvas></div>
 <div class='chartbox'><canvas id='chart-vibration' data-selfcheck='plot'></canvas></div>
</div>
<h3>3D: programmed, planned and actual path (robot base frame, mm)</h3>
<p class='hint'>Drag to turn, wheel to zoom, right-drag to pan. Programmed: thick grey; planned: the variant's
colour; actual: dark, its deviation from the commanded point drawn exaggerated by the factor chosen.</p>
<div class='view3d-controls'>variant <select id='v3-variant'></select>
 actual deviation &times; <select id='v3-scale'><option>1</option><option>10</option><option selected>100</option>
 <option>1000</option></select> <span id='v3-corners'></span> <button id='v3-all'>whole path</button></div>
<div id='view3d' data-selfcheck='view3d'></div>
"""

EXPLORE_CSS = """
.toc{columns:3;font-size:14px;background:#f6f6f6;padding:0.6em 1em;border-radius:4px}
.toc ol{margin:0}
.warnings{background:#fff4d6;border:1px solid #e0b000;padding:0.5em 1em;margin:1em 0}
.charts{display:grid;grid-template-columns:1fr 1fr;gap:12px}
.chartbox{position:relative;height:300px;border:1px solid #ddd}
.hint{color:#555;font-size:13px}
#view3d{width:100%;height:520px;border:1px solid #ddd;position:relative}
.view3d-controls{margin:0.4em 0;font-size:14px}
.view3d-controls button{margin:1px}
.zoombox{position:absolute;background:rgba(80,120,200,0.15);border:1px solid rgba(80,120,200,0.6);pointer-events:none}
#selfcheck{font-size:11px;color:#777}
"""

# The page's own script: the plots, their zoom, the 3D view and the self-check. Written here (no
# plugin: Chart.js's zoom plugin is not packaged in Debian 12; the zoom is a few handlers on the
# x scale's min and max).
EXPLORE_JS = r"""
(function () {
  const data = JSON.parse(document.getElementById('explore-data').textContent);
  const problems = [];
  window.addEventListener('error', function (e) {
    const what = e.target && e.target !== window ? (e.target.tagName + ' ' + (e.target.src || e.target.href || '')) : e.message;
    problems.push('error: ' + what);
  }, true);
  const consoleError = console.error.bind(console);
  console.error = function () { problems.push('console.error: ' + Array.from(arguments).join(' ')); consoleError.apply(null, arguments); };

  const charts = [];
  function makeChart(id, key, title, unit) {
    const canvas = document.getElementById(id);
    const datasets = data.variants.map(function (v) {
      const pts = v[key].t.map(function (t, i) { return {x: t, y: v[key].y[i]}; });
      return {label: v.name, data: pts, borderColor: v.colour, backgroundColor: v.colour, borderDash: v.dash,
              borderWidth: 1.4, pointRadius: 0, tension: 0};
    });
    const chart = new Chart(canvas.getContext('2d'), {
      type: 'line', data: {datasets: datasets},
      options: {animation: false, parsing: false, normalized: true, maintainAspectRatio: false, responsive: true,
        interaction: {mode: 'nearest', intersect: false, axis: 'x'},
        plugins: {title: {display: true, text: title + ' [' + unit + ']'}, legend: {labels: {boxWidth: 14, font: {size: 11}}},
                  tooltip: {callbacks: {label: function (c) { return c.dataset.label + ': ' + c.parsed.y.toFixed(3) + ' ' + unit + ' at ' + c.parsed.x.toFixed(3) + ' s'; }}}},
        scales: {x: {type: 'linear', title: {display: true, text: 'time [s]'}},
                 y: {title: {display: true, text: unit}}}}
    });
    charts.push(chart);
    attachZoom(chart, canvas);
  }
  function setRange(min, max) {
    charts.forEach(function (c) { c.options.scales.x.min = min; c.options.scales.x.max = max; c.update('none'); });
  }
  function attachZoom(chart, canvas) {
    const box = document.createElement('div');
    box.className = 'zoombox'; box.style.display = 'none';
    canvas.parentNode.appendChild(box);
    let start = null, panFrom = null;
    canvas.addEventListener('mousedown', function (e) {
      if (e.shiftKey) { panFrom = {x: e.offsetX, min: chart.scales.x.min, max: chart.scales.x.max}; return; }
      start = e.offsetX;
      box.style.left = start + 'px'; box.style.width = '0px';
      box.style.top = chart.chartArea.top + 'px'; box.style.height = (chart.chartArea.bottom - chart.chartArea.top) + 'px';
      box.style.display = 'block';
    });
    canvas.addEventListener('mousemove', function (e) {
      if (panFrom) {
        const dt = chart.scales.x.getValueForPixel(panFrom.x) - chart.scales.x.getValueForPixel(e.offsetX);
        setRange(panFrom.min + dt, panFrom.max + dt);
        panFrom.x = e.offsetX; panFrom.min += dt; panFrom.max += dt;
      } else if (start !== null) {
        box.style.left = Math.min(start, e.offsetX) + 'px'; box.style.width = Math.abs(e.offsetX - start) + 'px';
      }
    });
    window.addEventListener('mouseup', function (e) {
      if (start !== null) {
        const rect = canvas.getBoundingClientRect();
        const end = e.clientX - rect.left;
        if (Math.abs(end - start) > 4) {
          const a = chart.scales.x.getValueForPixel(Math.min(start, end));
          const b = chart.scales.x.getValueForPixel(Math.max(start, end));
          setRange(a, b);
        }
      }
      start = null; panFrom = null; box.style.display = 'none';
    });
    canvas.addEventListener('wheel', function (e) {
      e.preventDefault();
      const x = chart.scales.x.getValueForPixel(e.offsetX);
      const f = e.deltaY > 0 ? 1.25 : 0.8;
      setRange(x - (x - chart.scales.x.min) * f, x + (chart.scales.x.max - x) * f);
    }, {passive: false});
    canvas.addEventListener('dblclick', function () { setRange(undefined, undefined); });
  }

  let renderer = null, drawn3d = false;
  function make3d() {
    const host = document.getElementById('view3d');
    const width = host.clientWidth || 800, height = host.clientHeight || 520;
    renderer = new THREE.WebGLRenderer({antialias: true, preserveDrawingBuffer: true});
    renderer.setSize(width, height);
    renderer.setClearColor(0xffffff, 1);
    host.appendChild(renderer.domElement);
    const scene = new THREE.Scene();
    const camera = new THREE.PerspectiveCamera(40, width / height, 0.01, 1e6);
    const controls = new THREE.OrbitControls(camera, renderer.domElement);
    camera.up.set(0, 0, 1);
    function line(xyz, colour, transform, opacity) {
      const n = xyz[0].length, pos = new Float32Array(3 * n);
      for (let i = 0; i < n; ++i) {
        const p = transform ? transform(i) : [xyz[0][i], xyz[1][i], xyz[2][i]];
        pos[3 * i] = p[0]; pos[3 * i + 1] = p[1]; pos[3 * i + 2] = p[2];
      }
      const g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.BufferAttribute(pos, 3));
      const op = opacity === undefined ? 1 : opacity;
      return new THREE.Line(g, new THREE.LineBasicMaterial({color: colour, transparent: op < 1, opacity: op}));
    }
    // the programmed path thick: a tube along it (WebGL draws lines one pixel wide)
    const prog = data.program;
    const pts = prog[0].map(function (x, i) { return new THREE.Vector3(x, prog[1][i], prog[2][i]); });
    const size = new THREE.Box3().setFromPoints(pts).getSize(new THREE.Vector3()).length() || 1;
    const progGroup = new THREE.Group();
    for (let i = 1; i < pts.length; ++i) {
      const a = pts[i - 1], b = pts[i], len = a.distanceTo(b);
      if (len <= 0) continue;
      const cyl = new THREE.Mesh(new THREE.CylinderBufferGeometry(size * 0.002, size * 0.002, len, 6, 1, true),
                                 new THREE.MeshBasicMaterial({color: 0xaaaaaa}));
      cyl.position.copy(a.clone().add(b).multiplyScalar(0.5));
      cyl.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), b.clone().sub(a).normalize());
      progGroup.add(cyl);
    }
    scene.add(progGroup);
    let variantGroup = null;
    const select = document.getElementById('v3-variant'), scaleSel = document.getElementById('v3-scale');
    data.variants.forEach(function (v, i) { const o = document.createElement('option'); o.value = i; o.textContent = v.name + ' (' + v.method + ')'; select.appendChild(o); });
    if (data.variants.length > 1) select.value = String(data.variants.length - 1);
    function showVariant() {
      if (variantGroup) scene.remove(variantGroup);
      const v = data.variants[+select.value], k = +scaleSel.value;
      variantGroup = new THREE.Group();
      variantGroup.add(line(v.planned, new THREE.Color(v.colour)));
      variantGroup.add(line(v.actual, 0x222222, function (i) {
        return [0, 1, 2].map(function (a) { return v.commanded[a][i] + k * (v.actual[a][i] - v.commanded[a][i]); });
      }, 0.55));
      scene.add(variantGroup);
      const bar = document.getElementById('v3-corners');
      bar.textContent = '';
      v.corners.forEach(function (c) {
        const b = document.createElement('button');
        b.textContent = 'C' + c.index; b.title = c.source ? ('corner C' + c.index + ', ' + c.source) : ('corner C' + c.index);
        b.addEventListener('click', function () { look(new THREE.Vector3(c.point[0], c.point[1], c.point[2]), 6 * c.extent); });
        bar.appendChild(b);
      });
      render();
    }
    const centre = new THREE.Box3().setFromPoints(pts).getCenter(new THREE.Vector3());
    function look(target, distance) {
      const dir = camera.position.clone().sub(controls.target);
      if (dir.length() === 0) dir.set(1, -1.5, 1);
      controls.target.copy(target);
      camera.position.copy(target.clone().add(dir.normalize().multiplyScalar(distance)));
      camera.near = distance / 1000; camera.far = distance * 1000; camera.updateProjectionMatrix();
      controls.update(); render();
    }
    function render() { renderer.render(scene, camera); drawn3d = true; }
    controls.addEventListener('change', render);
    select.addEventListener('change', showVariant);
    scaleSel.addEventListener('change', showVariant);
    document.getElementById('v3-all').addEventListener('click', function () { look(centre, 1.25 * size); });
    camera.position.set(centre.x + size, centre.y - 1.5 * size, centre.z + size);
    showVariant();
    look(centre, 1.25 * size);
  }

  // drew something: pixels that are neither background nor grey (the data's colours; a plot's
  // axes and labels are grey and drawn even without data), or with anyInk every pixel that is
  // not the white background (the 3D view clears to white and draws nothing else)
  function colouredPixels(canvas, anyInk) {
    const copy = document.createElement('canvas');
    copy.width = canvas.width; copy.height = canvas.height;
    const ctx = copy.getContext('2d');
    ctx.drawImage(canvas, 0, 0);
    const px = ctx.getImageData(0, 0, copy.width, copy.height).data;
    let n = 0;
    for (let i = 0; i < px.length; i += 4) {
      const r = px[i], g = px[i + 1], b = px[i + 2], a = px[i + 3];
      if (a > 0 && !(r > 245 && g > 245 && b > 245) && (anyInk || Math.max(r, g, b) - Math.min(r, g, b) > 40 || (r < 90 && g < 90 && b < 90))) ++n;
    }
    return n;
  }
  function selfCheck() {
    const out = document.getElementById('selfcheck');
    const imgs = Array.from(document.images);
    imgs.forEach(function (im) { if (!im.complete || im.naturalWidth === 0) problems.push('image not shown: ' + (im.alt || im.src.slice(0, 40))); });
    const plots = charts.map(function (c) { return colouredPixels(c.canvas); });
    plots.forEach(function (n, i) { if (n < 50) problems.push('plot ' + charts[i].canvas.id + ' drew nothing (' + n + ' pixels)'); });
    let view = 0;
    if (renderer) { view = colouredPixels(renderer.domElement, true); if (!drawn3d || view < 50) problems.push('3D view drew nothing (' + view + ' pixels)'); }
    else problems.push('3D view not created');
    out.dataset.status = problems.length ? 'fail' : 'ok';
    out.textContent = 'self-check: ' + (problems.length ? 'FAIL: ' + problems.join('; ')
      : 'ok (' + imgs.length + ' images shown, ' + plots.length + ' plots drew ' + plots.join('/') + ' px, 3D view drew ' + view + ' px)');
  }

  try {
    makeChart('chart-speed', 'speed', 'Path speed (actual TCP)', 'mm/s');
    makeChart('chart-tracking', 'tracking', 'Tracking error', '\u00b5m');
    makeChart('chart-contour', 'contour', 'Contour error against the planned path', '\u00b5m');
    makeChart('chart-vibration', 'vibration', 'Residual vibration (high-passed tracking error)', '\u00b5m');
  } catch (e) { problems.push('plots: ' + e.message); }
  try { make3d(); } catch (e) { problems.push('3D view: ' + e.message); }
  window.addEventListener('load', function () { requestAnimationFrame(function () { setTimeout(selfCheck, 50); }); });
})();
"""


def script_tags():
    """The inlined library scripts, or None when one is missing (the page then says so)."""
    texts = []
    for key in ["chart", "three", "orbit"]:
        path = SCRIPTS[key]
        if not os.path.isfile(path):
            return None
        with open(path, encoding="utf-8") as f:
            # a '</script' inside a library would end the element early
            texts.append("<script>" + f.read().replace("</script", "<\\/script") + "</script>")
    return "\n".join(texts)


def finish(run_dir, summary, variants):
    """Rewrites RUN_DIR/report.html as one self-contained page (see the module's comment)."""
    path = os.path.join(run_dir, "report.html")
    with open(path, encoding="utf-8") as f:
        page = f.read()
    page = inline_images(page, run_dir)
    libs = script_tags() if variants else None
    if libs:
        data = json.dumps(explore_data(summary, variants), separators=(",", ":")).replace("</", "<\\/")
        explore = EXPLORE_HTML + f"<script type='application/json' id='explore-data'>{data}</script>"
    elif variants:
        explore = ("<h2 id='explore'>Explore</h2><p>The interactive views need Debian's libjs-chart.js and libjs-three "
                   "(<code>bash tools/bootstrap.sh run</code> installs them); the figures below show the same data.</p>")
    else:
        explore = ""
    extra = explore + videos_section(run_dir, variants)
    # the explore and video sections go before the first variant's section (after the answer)
    first = None
    for v in variants:
        m = re.search(r"<h2 id=['\"]" + re.escape(html.escape(v.name)) + r"['\"]", page)
        if m and (first is None or m.start() < first):
            first = m.start()
    if first is None:
        first = page.rfind("</body>")
    page = page[:first] + extra + page[first:]
    page, items = contents(page)
    toc = "<nav class='toc'><b>Contents</b><ol>" + "".join(
        f"<li><a href='#{html.escape(i)}'>{t}</a></li>" for i, t in items) + "</ol></nav>"
    # the contents after the first section (the answer), so the first screen stays the answer
    heads = [m.start() for m in re.finditer(r"<h2", page)]
    at = heads[1] if len(heads) > 1 else (heads[0] if heads else page.rfind("</body>"))
    page = page[:at] + toc + page[at:]
    # warnings under the title, the version at the foot, the styles and scripts
    page = re.sub(r"(</h1>)", lambda m: m.group(1) + warnings_box(summary), page, count=1)
    version = html.escape(str(summary.get("version", "")))
    foot = (f"<p class='hint'>BlendBench {version}. This page is self-contained (figures and scripts inlined); the "
            "videos and CSV files are beside it in the run folder.</p><p id='selfcheck' data-status='pending'>"
            "self-check: pending</p>")
    scripts = (libs + f"<script>{EXPLORE_JS}</script>") if libs else (
        "<script>document.getElementById('selfcheck').dataset.status='ok';"
        "document.getElementById('selfcheck').textContent='self-check: ok (no interactive views)';</script>")
    page = page.replace("</style>", EXPLORE_CSS + "</style>", 1)
    end = page.rfind("</body>")
    page = page[:end] + foot + scripts + page[end:]
    write_text(path, page)
