#!/usr/bin/env python3
# Writes corpus/: the long-form samples of this folder as other instruments and spreadsheets
# export them, each the twin of its long-form file (the same readings). Run it here:
#   python3 make_corpus.py
# tests/data/README.md lists the files; the solver's InstrumentFiles tests read each twin and
# compare its readings and figures with its long-form file's.
import csv

rows = []
with open("iso230-2_x.csv") as f:
    lines = [l for l in f if not l.startswith("#")]
for r in csv.DictReader(lines):
    rows.append((float(r["target_mm"]), int(r["cycle"]), r["direction"], float(r["measured_mm"])))

# A laser system's export through a spreadsheet set to a decimal comma: BOM, CRLF, ';', comment
# lines, the unit in brackets, deviations in micrometres, + and - for the directions.
with open("corpus/iso230-2_x_semicolon_um.csv", "w", encoding="utf-8", newline="") as f:
    f.write("\ufeff# Linear positioning, axis X, exported 2026-11-24\r\n")
    f.write("# Environment: air 20,1 °C, material 20,3 °C\r\n")
    f.write("Target (mm);Run;Dir;Error (µm);Air (°C)\r\n")
    for t, c, d, m in rows:
        err = "%.2f" % ((m - t) * 1000.0)
        f.write("%s;%d;%s;%s;20,1\r\n" % (("%.1f" % t).replace(".", ","), c,
                                          "+" if d == "up" else "-", err.replace(".", ",")))

# A tab-separated export in inches, forward/backward runs.
with open("corpus/iso230-2_x_inch_tab.txt", "w", newline="") as f:
    f.write("# X axis, inch\n")
    f.write("target_in\tcycle\tdirection\tmeasured_in\n")
    for t, c, d, m in rows:
        f.write("%.8f\t%d\t%s\t%.8f\n" % (t / 25.4, c, "fwd" if d == "up" else "bwd", m / 25.4))
