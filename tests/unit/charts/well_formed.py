#!/usr/bin/python3
# SPDX-License-Identifier: Apache-2.0
# charts.WellFormed: every chart of the gallery (ncqual_charts_gallery) is a well-formed,
# self-contained SVG element that a report can inline:
#  - it parses as XML (xml.etree), the root is <svg> in the SVG namespace with viewBox, width,
#    height (agreeing), role="img" and data-chart, and its first children are a non-empty <title>
#    and <desc>;
#  - nothing in it runs or fetches: no <script>, <style>, <foreignObject>, <image>, no on*
#    attribute, no href, no url(...) anywhere;
#  - every chart kind is there, and the empty and non-finite samples say so ("no data", the
#    count of skipped values);
#  - hostile labels (<&"'>) come back from the parser as the text they were;
#  - the same input gives the same bytes (the gallery run twice).
# Usage: well_formed.py GALLERY_EXE OUTDIR. Debian's /usr/bin/python3, standard library only.
import os
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET

SVG = "{http://www.w3.org/2000/svg}"
KINDS = {"trend", "deviation-vectors", "point-deviation", "positioning", "polar", "budget"}
HOSTILE = "<&\"'> ]]>"  # the part of the gallery's hostile label that survives unchanged
FORBIDDEN_TAGS = {"script", "style", "foreignObject", "image", "use", "a", "iframe"}

failures = []


def fail(where, what):
    failures.append(f"{where}: {what}")


def finish(problems, summary):
    """Prints every problem and the summary; the exit code (1 with problems)."""
    for p in problems:
        print("FAIL", p)
    print(summary)
    return 1 if problems else 0


def run_gallery(exe, outdir):
    """The gallery drawn afresh into `outdir`; its manifest's rows (name, kind, expect, note)."""
    shutil.rmtree(outdir, ignore_errors=True)
    subprocess.run([exe, outdir], check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(outdir, "manifest.tsv"), encoding="utf-8") as f:
        return [line.rstrip("\n").split("\t") for line in f if line.strip()]


def check_chart(name, kind, path):
    raw = open(path, "rb").read()
    try:
        root = ET.fromstring(raw)
    except ET.ParseError as e:
        fail(name, f"not well-formed XML: {e}")
        return None
    if root.tag != SVG + "svg":
        fail(name, f"root is {root.tag}, not an SVG <svg>")
        return None
    a = root.attrib
    for attr in ("viewBox", "width", "height", "role", "data-chart"):
        if attr not in a:
            fail(name, f"root lacks {attr}")
    if a.get("role") != "img":
        fail(name, f"role is {a.get('role')!r}, not 'img'")
    if a.get("data-chart") != kind:
        fail(name, f"data-chart is {a.get('data-chart')!r}, the manifest says {kind!r}")
    vb = a.get("viewBox", "").split()
    if vb != ["0", "0", a.get("width"), a.get("height")]:
        fail(name, f"viewBox {a.get('viewBox')!r} disagrees with width/height")
    children = list(root)
    if len(children) < 2 or children[0].tag != SVG + "title" or children[1].tag != SVG + "desc":
        fail(name, "the first children are not <title> and <desc>")
    else:
        if not (children[1].text or "").strip():
            fail(name, "empty <desc>")
    for el in root.iter():
        local = el.tag.split("}")[-1]
        if not el.tag.startswith(SVG):
            fail(name, f"element outside the SVG namespace: {el.tag}")
        if local in FORBIDDEN_TAGS:
            fail(name, f"<{local}> in a chart")
        for attr, value in el.attrib.items():
            if attr.lower().startswith("on") or "href" in attr.lower():
                fail(name, f"attribute {attr} on <{local}>")
            if "url(" in value:
                fail(name, f"url(...) in {attr} of <{local}>")
    return root


def texts(root):
    return [t for el in root.iter() for t in (el.text, el.get("data-label"), el.get("data-trace")) if t]


def main():
    exe, outdir = sys.argv[1], sys.argv[2]
    first = run_gallery(exe, os.path.join(outdir, "run1"))
    second = run_gallery(exe, os.path.join(outdir, "run2"))
    if first != second:
        fail("manifest", "two runs of the gallery list different charts")
    seen = set()
    for name, kind, expect, note in first:
        path1 = os.path.join(outdir, "run1", name + ".svg")
        path2 = os.path.join(outdir, "run2", name + ".svg")
        if open(path1, "rb").read() != open(path2, "rb").read():
            fail(name, "not deterministic: two runs gave different bytes")
        root = check_chart(name, kind, path1)
        if root is None:
            continue
        seen.add(kind)
        desc = root.find(SVG + "desc").text or ""
        all_text = texts(root)
        expect = set(expect.split(","))
        if "empty" in expect:
            if "no data" not in all_text:
                fail(name, "an empty chart without 'no data'")
        if "skips" in expect:
            skipped = int(root.get("data-skipped", "0"))
            if skipped < 1 or "skipped" not in desc:
                fail(name, f"non-finite values not counted (data-skipped {skipped}, desc {desc!r})")
        if "hostile" in expect:
            title = root.find(SVG + "title").text or ""
            if HOSTILE not in title:
                fail(name, f"the hostile title did not survive escaping: {title!r}")
            if "\ufffd" not in title:
                fail(name, "the control character / bad byte was not replaced with U+FFFD")
            if sum(HOSTILE in t for t in all_text) < 3:
                fail(name, "the hostile label appears fewer than 3 times as text")
    missing = KINDS - seen
    if missing:
        fail("gallery", f"no well-formed chart of kind {sorted(missing)}")
    return finish(failures, f"{len(first)} charts checked; {len(failures)} problems")


if __name__ == "__main__":
    sys.exit(main())
