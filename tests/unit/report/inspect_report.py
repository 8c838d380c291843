#!/usr/bin/python3
# SPDX-License-Identifier: Apache-2.0
# Reads an `ncqual report` document with an XML parser of its own (xml.etree: the report is
# written as well-formed polyglot HTML) and prints what the report tests assert on as JSON:
# {"ok", "error", "title", "h1", "sections": [{"class", "h2", "charts": [data-chart...],
# "none": [sentences]}], "vectors": [{"label", "class", "dx", "dy", "value"}],
# "means": [{"class", "target", "value"}], "checks": [[cell texts]], "traces": [labels],
# "banners": [texts of the simulated-data banners], "simulated_badges": count,
# "forbidden": [what runs or fetches]}.
# Usage: inspect_report.py FILE. Debian's /usr/bin/python3, standard library only.
import json
import re
import sys
import xml.etree.ElementTree as ET

SVG = "{http://www.w3.org/2000/svg}"
RUNS = {"script", "iframe", "object", "embed", "link", "img", "image", "foreignObject", "use"}


def local(tag):
    return tag.split("}", 1)[-1] if isinstance(tag, str) else ""


def text_of(e):
    return re.sub(r"\s+", " ", " ".join(t.strip() for t in e.itertext() if t.strip()))


def main(path):
    raw = open(path, "rb").read()
    out = {"ok": True, "error": "", "sections": [], "vectors": [], "means": [], "checks": [],
           "traces": [], "forbidden": [], "banners": [], "simulated_badges": 0}
    if not raw.startswith(b"<!DOCTYPE html>"):
        out["ok"] = False
        out["error"] = "does not start with <!DOCTYPE html>"
    try:
        root = ET.fromstring(raw)
    except ET.ParseError as e:
        out["ok"] = False
        out["error"] = f"not well-formed: {e}"
        print(json.dumps(out))
        return
    for e in root.iter():
        name = local(e.tag)
        if name in RUNS:
            out["forbidden"].append(name)
        for a, v in e.attrib.items():
            if local(a).startswith("on") or local(a) in ("href", "src") or "url(" in v:
                out["forbidden"].append(f"{name}@{local(a)}")
    unnamespaced = raw.replace(b'xmlns="http://www.w3.org/2000/svg"', b"")
    if re.search(rb"url\(|@import|https?://", unnamespaced):
        out["forbidden"].append("url, @import or http in the text")
    title = root.find("head/title")
    out["title"] = text_of(title) if title is not None else None
    h1 = root.find(".//h1")
    out["h1"] = text_of(h1) if h1 is not None else None
    for s in root.iter("section"):
        h2 = s.find("h2")
        out["sections"].append({
            "class": s.get("class"),
            "h2": text_of(h2) if h2 is not None else None,
            "charts": [c.get("data-chart") for c in s.iter(SVG + "svg")],
            "none": [text_of(p) for p in s.iter("p") if p.get("class") == "none"],
        })
    for g in root.iter(SVG + "g"):
        cls = g.get("class", "")
        if cls.split()[:1] == ["vector"]:
            out["vectors"].append({"label": g.get("data-label"), "class": cls,
                                   "dx": float(g.get("data-dx")), "dy": float(g.get("data-dy")),
                                   "value": float(g.get("data-value"))})
    for e in root.iter():
        cls = e.get("class", "")
        if cls in ("mean up", "mean down"):
            out["means"].append({"class": cls, "target": float(e.get("data-target")),
                                 "value": float(e.get("data-value"))})
        if cls == "ncqual-simulated-banner":
            out["banners"].append(text_of(e))
        if cls == "origin-badge simulated":
            out["simulated_badges"] += 1
        if local(e.tag) == "path" and cls.split()[:1] == ["trace"]:
            out["traces"].append(e.get("data-trace"))
    table = root.find(".//table[@class='checks']")
    if table is not None:
        for tr in table.iter("tr"):
            cells = [text_of(td) for td in tr.findall("td")]
            if cells:
                out["checks"].append(cells)
    print(json.dumps(out))


if __name__ == "__main__":
    main(sys.argv[1])
