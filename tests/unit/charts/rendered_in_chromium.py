#!/usr/bin/python3
# SPDX-License-Identifier: Apache-2.0
# charts.RenderedInChromium: the gallery page (ncqual_charts_gallery) in Debian's headless
# Chromium, the browser the dashboard and the report are looked at with.
#  - --dump-dom of gallery.html: every chart the manifest lists is in the DOM, by data-chart;
#  - --dump-dom of layout-check.html (the gallery plus a test-only script that measures the
#    rendered text): no text of a chart runs past the chart's edge, no two texts of a chart
#    overlap, every data marker lies inside its plot area;
#  - --screenshot of the gallery (kept: OUTDIR/gallery.png) and of every chart alone at its own
#    size (kept: OUTDIR/png/<name>.png): the trend's and the over-budget chart's pixels are not
#    blank and show the red of out-of-tolerance marks and the accent blue (the SVG was drawn).
# Exit 77 (ctest: skipped) with a SKIPPED line when Chromium is not installed.
# Usage: rendered_in_chromium.py GALLERY_EXE OUTDIR. Standard library only.
import html
import json
import os
import re
import struct
import sys
import zlib

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
from chromium import find_chromium, run_chromium  # noqa: E402 (tests/support/chromium.py)
from well_formed import finish, run_gallery  # noqa: E402 (this folder's well_formed.py)

LAYOUT_SCRIPT = r"""
<script>
(function () {
  const problems = [];
  const charts = [...document.querySelectorAll('svg.ncqual-chart')];
  const inside = (r, box, slack) => r.left >= box.left - slack && r.right <= box.right + slack &&
      r.top >= box.top - slack && r.bottom <= box.bottom + slack;
  for (const svg of charts) {
    const name = svg.closest('figure').id;
    const box = svg.getBoundingClientRect();
    const texts = [...svg.querySelectorAll('text')]
        .filter(t => t.textContent.trim() !== '')
        .map(t => ({text: t.textContent, r: t.getBoundingClientRect()}));
    for (const t of texts) {
      if (!inside(t.r, box, 0.5)) problems.push(name + ': "' + t.text + '" runs past the chart\'s edge');
    }
    for (let i = 0; i < texts.length; ++i) {
      for (let j = i + 1; j < texts.length; ++j) {
        const a = texts[i].r, b = texts[j].r;
        const w = Math.min(a.right, b.right) - Math.max(a.left, b.left) - 2;
        const h = Math.min(a.bottom, b.bottom) - Math.max(a.top, b.top) - 2;
        if (w > 0 && h > 0) {
          problems.push(name + ': "' + texts[i].text + '" overlaps "' + texts[j].text + '"');
        }
      }
    }
    const plot = svg.querySelector('.plot-area');
    if (plot) {
      const p = plot.getBoundingClientRect();
      for (const m of svg.querySelectorAll('.point, .mean, .nominal')) {
        const r = m.getBoundingClientRect();
        const cx = (r.left + r.right) / 2, cy = (r.top + r.bottom) / 2;
        if (cx < p.left - 0.5 || cx > p.right + 0.5 || cy < p.top - 0.5 || cy > p.bottom + 0.5) {
          problems.push(name + ': a marker lies outside the plot area');
        }
      }
    }
  }
  const report = document.createElement('pre');
  report.id = 'layout-report';
  report.textContent = JSON.stringify({
    charts: charts.length,
    height: Math.ceil(document.documentElement.scrollHeight),
    problems: problems,
  });
  document.body.appendChild(report);
})();
</script>
"""


def read_png(path):
    """Width, height and the RGB(A) rows of a PNG (8-bit RGB or RGBA, non-interlaced)."""
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("not a PNG")
    pos, idat, width, height, channels = 8, b"", 0, 0, 0
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or colour not in (2, 6) or interlace != 0:
                raise ValueError(f"unsupported PNG (depth {depth}, colour type {colour})")
            channels = 3 if colour == 2 else 4
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw = zlib.decompress(idat)
    stride = width * channels
    rows, prev = [], bytearray(stride)
    for y in range(height):
        start = y * (stride + 1)
        ftype, line = raw[start], bytearray(raw[start + 1:start + 1 + stride])
        for i in range(stride):
            a = line[i - channels] if i >= channels else 0
            b = prev[i]
            c = prev[i - channels] if i >= channels else 0
            if ftype == 1:
                line[i] = (line[i] + a) & 0xFF
            elif ftype == 2:
                line[i] = (line[i] + b) & 0xFF
            elif ftype == 3:
                line[i] = (line[i] + (a + b) // 2) & 0xFF
            elif ftype == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if pa <= pb and pa <= pc else b if pb <= pc else c
                line[i] = (line[i] + pred) & 0xFF
        rows.append(bytes(line))
        prev = line
    return width, height, channels, rows


def png_size(path):
    data = open(path, "rb").read(24)
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        return (0, 0)
    return struct.unpack(">II", data[16:24])


def colour_counts(path):
    width, height, channels, rows = read_png(path)
    ink = red = blue = 0
    for row in rows:
        for x in range(0, width * channels, channels * 2):  # every second pixel is enough
            r, g, b = row[x], row[x + 1], row[x + 2]
            if r < 235 or g < 235 or b < 235:
                ink += 1
            if r > 170 and g < 60 and b < 80:
                red += 1
            if r < 60 and 70 < g < 120 and b > 140:
                blue += 1
    return width, height, ink / max(1, (width * height) // 2), red, blue


def main():
    exe, outdir = sys.argv[1], sys.argv[2]
    chromium = find_chromium()
    if chromium is None:
        print("SKIPPED: chromium is not installed (deploy/install-deps.sh --test installs it)")
        return 77
    manifest = run_gallery(exe, outdir)
    failures = []

    # 1. The page as it is: every chart in the DOM Chromium built.
    gallery = os.path.join(outdir, "gallery.html")
    dom = run_chromium(chromium, ["--dump-dom", "file://" + gallery])
    if dom.returncode != 0:
        print(dom.stderr.decode(errors="replace")[-2000:])
        failures.append(f"chromium --dump-dom exited {dom.returncode}")
    text = dom.stdout.decode("utf-8", errors="replace")
    found = re.findall(r'<svg\b[^>]*\bdata-chart="([^"]+)"', text)
    for name, kind, _, _ in manifest:
        if f'<figure id="{name}"' not in text:
            failures.append(f"{name}: not in the DOM")
    for kind in sorted({m[1] for m in manifest}):
        want = sum(1 for m in manifest if m[1] == kind)
        got = found.count(kind)
        if got != want:
            failures.append(f'data-chart="{kind}": {got} in the DOM, the gallery has {want}')
    print(f"DOM: {len(found)} charts of kinds {sorted(set(found))}")

    # 2. The rendered text: nothing cut off, nothing overlapping, markers in their plots.
    page = open(gallery, encoding="utf-8").read()
    check = os.path.join(outdir, "layout-check.html")
    with open(check, "w", encoding="utf-8") as f:
        f.write(page.replace("</body>", LAYOUT_SCRIPT + "</body>"))
    # At the screenshot's width, so that the page's height it reports is the screenshot's.
    dom = run_chromium(chromium, ["--dump-dom", "--window-size=1600,1000", "file://" + check])
    m = re.search(r'<pre id="layout-report">(.*?)</pre>', dom.stdout.decode("utf-8", errors="replace"),
                  re.S)
    height = 4000
    if not m:
        failures.append("the layout check did not report (did the page's script run?)")
    else:
        report = json.loads(html.unescape(m.group(1)))
        height = report["height"]
        if report["charts"] != len(manifest):
            failures.append(f"layout check measured {report['charts']} charts, not {len(manifest)}")
        for p in report["problems"]:
            failures.append("layout: " + p)
        print(f"layout: {report['charts']} charts measured, {len(report['problems'])} problems")

    # 3. Screenshots: the gallery (kept), and every chart alone at its own size.
    shot = os.path.join(outdir, "gallery.png")
    res = run_chromium(chromium, ["--screenshot=" + shot, f"--window-size=1600,{min(height, 16000)}",
                                  "file://" + gallery])
    if res.returncode != 0 or not os.path.exists(shot):
        failures.append(f"chromium --screenshot exited {res.returncode}, no {shot}")
    else:
        width, h = png_size(shot)
        print(f"screenshot {shot}: {width}x{h}")
        if width != 1600 or h < 1000:
            failures.append(f"the gallery screenshot is {width}x{h}")
    os.makedirs(os.path.join(outdir, "png"), exist_ok=True)
    for name, _, _, _ in manifest:
        svg = os.path.join(outdir, name + ".svg")
        head = open(svg, encoding="utf-8").read(2000)
        w = re.search(r'\swidth="(\d+)"', head).group(1)
        h = re.search(r'\sheight="(\d+)"', head).group(1)
        png = os.path.join(outdir, "png", name + ".png")
        res = run_chromium(chromium, ["--screenshot=" + png, f"--window-size={w},{h}", "file://" + svg])
        if res.returncode != 0 or not os.path.exists(png):
            failures.append(f"{name}: no screenshot of the chart alone")
            continue
        if png_size(png) != (int(w), int(h)):
            failures.append(f"{name}: screenshot {png_size(png)}, the chart is {w}x{h}")
    # The pixels of two charts that must show both colours (decoding every PNG in Python is slow).
    for name in ("trend", "budget-over"):
        png = os.path.join(outdir, "png", name + ".png")
        if not os.path.exists(png):
            continue
        _, _, ink, red, blue = colour_counts(png)
        print(f"{name}.png: {ink:.1%} ink, {red} red and {blue} accent samples")
        if ink < 0.03:
            failures.append(f"{name}.png is nearly blank ({ink:.1%} ink)")
        if red < 20:
            failures.append(f"{name}.png: hardly any red ({red}): out-of-tolerance marks not drawn?")
        if name == "trend" and blue < 20:
            failures.append(f"{name}.png: hardly any accent blue ({blue})")

    return finish(failures,
                  f"{len(manifest)} charts; {len(failures)} problems; screenshot kept at {shot}")


if __name__ == "__main__":
    sys.exit(main())
