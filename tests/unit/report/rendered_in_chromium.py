#!/usr/bin/python3
# SPDX-License-Identifier: Apache-2.0
# report.RenderedInChromium: the tests' sample report (ncqual_report_sample) in headless Chromium:
#  - --dump-dom: every section is in the DOM with its charts (the browser parsed what we wrote),
#    its times in the sample plant's zone (Europe/Berlin), none in UTC;
#  - --print-to-pdf: it prints (a PDF of several pages, one per section at least);
#  - --screenshot of the whole page, kept as OUTDIR/report.png to look at;
#  - the same historian's checks as ncqual's simulator's (report-simulated.html): the
#    simulated-data banner is in the DOM before the first heading and chart, every row of the
#    checks table is marked SIMULATED; the measured report has neither (screenshot
#    OUTDIR/report-simulated.png, its top OUTDIR/report-simulated-top.png).
# Usage: rendered_in_chromium.py SAMPLE_EXE OUTDIR. Skipped (77) without Chromium.
import os
import re
import subprocess
import sys

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "support"))
from chromium import find_chromium, run_chromium  # noqa: E402 (tests/support/chromium.py)

SECTIONS = ["state", "grid", "linear", "circles", "trends", "checks", "budget"]


def main(exe, outdir):
    chromium = find_chromium()
    if chromium is None:
        print("SKIPPED: chromium is not installed")
        return 77
    subprocess.run([exe, outdir], check=True)
    page = "file://" + os.path.abspath(os.path.join(outdir, "report.html"))
    failures = []
    dom = run_chromium(chromium, ["--dump-dom", page], timeout=120)
    dom = dom.stdout.decode("utf-8", "replace")
    for s in SECTIONS:
        if f'class="ncqual-report-{s}"' not in dom:
            failures.append(f"section {s} is not in the DOM")
    charts = re.findall(r'data-chart="([a-z-]+)"', dom)
    for kind in ("deviation-vectors", "point-deviation", "positioning", "polar", "trend",
                 "budget"):
        if kind not in charts:
            failures.append(f"no {kind} chart in the DOM")
    if "<script" in dom:
        failures.append("a script in the DOM")
    # One clock: the sample plant is in Berlin; its times and the trend axes say so, none UTC.
    if "+01:00 CET" not in dom or "date (Europe/Berlin)" not in dom:
        failures.append("the times are not in the plant's zone (Europe/Berlin, +01:00 CET)")
    if "(UTC)" in dom:
        failures.append("a time in UTC: " + dom[max(0, dom.find("(UTC)") - 80):dom.find("(UTC)") + 5])
    pdf = os.path.join(outdir, "report.pdf")
    run_chromium(chromium, ["--print-to-pdf=" + pdf, "--no-pdf-header-footer", page], timeout=120)
    if not os.path.exists(pdf):
        failures.append("no PDF printed")
    else:
        pages = len(re.findall(rb"/Type\s*/Page[^s]", open(pdf, "rb").read()))
        if pages < len(SECTIONS):
            failures.append(f"the PDF has {pages} pages, fewer than the {len(SECTIONS)} sections")
    shot = os.path.join(outdir, "report.png")
    run_chromium(chromium, ["--screenshot=" + shot, "--window-size=1200,16000", page], timeout=120)
    if not os.path.exists(shot):
        failures.append("no screenshot")
    # Simulated data: a banner above everything and a marker per check; none for measured data.
    for marker in ('class="ncqual-simulated-banner"', 'class="origin-badge simulated"'):
        if marker in dom:
            failures.append(f"the measured report shows {marker}")
    simulated_page = "file://" + os.path.abspath(os.path.join(outdir, "report-simulated.html"))
    sim = run_chromium(chromium, ["--dump-dom", simulated_page], timeout=120)
    sim = sim.stdout.decode("utf-8", "replace")
    banner = sim.find('class="ncqual-simulated-banner"')
    if banner < 0:
        failures.append("the simulated report has no banner")
    elif not banner < sim.find("<h2") < sim.find("<svg"):
        failures.append("the simulated report's banner is not above the sections and charts")
    rows = re.search(r'<table class="checks">.*?</table>', sim, re.S)
    body_rows = re.findall(r"<tr[ >]", rows.group(0)) if rows else []
    marked = re.findall(r'<tr class="simulated">', rows.group(0)) if rows else []
    if not rows or len(marked) != len(body_rows) - 1 or not marked:
        failures.append(f"simulated report: {len(marked)} rows marked of {len(body_rows) - 1}")
    for name, size in (("report-simulated", "1200,16000"), ("report-simulated-top", "1280,900")):
        shot_sim = os.path.join(outdir, name + ".png")
        run_chromium(chromium, ["--screenshot=" + shot_sim, "--window-size=" + size,
                                simulated_page], timeout=120)
        if not os.path.exists(shot_sim):
            failures.append(f"no screenshot {name}")
    for f in failures:
        print("FAIL:", f)
    print(f"{len(charts)} charts; PDF {pdf}; screenshot {shot}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1], sys.argv[2]))
