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

# The wide form: one row per target, one column per run and direction.
targets = sorted({t for t, _, _, _ in rows})
cycles = sorted({c for _, c, _, _ in rows})
by_key = {(t, c, d): m for t, c, d, m in rows}

# A laser calibration system's export: deviations in micrometres, "Run n Fwd/Bwd (µm)" columns,
# what the values are said in a comment before the header.
with open("corpus/iso230-2_x_wide_um.csv", "w", encoding="utf-8", newline="") as f:
    f.write("# Linear axis calibration, X\n# Values: deviation\n")
    f.write("Target (mm)," + ",".join("Run %d %s (µm)" % (c, "Fwd" if d == "up" else "Bwd")
                                      for c in cycles for d in ("up", "down")) + "\n")
    for t in targets:
        f.write("%.1f," % t + ",".join("%.2f" % ((by_key[(t, c, d)] - t) * 1000.0)
                                       for c in cycles for d in ("up", "down")) + "\n")

# The wide form with the unit only in the instrument's header comment: positions in inches,
# tab separated, "Cycle n +/-" columns.
with open("corpus/iso230-2_x_wide_declared_in.txt", "w", newline="") as f:
    f.write("# Axis: X\n# Units: in\n# Values: measured\n")
    f.write("Target\t" + "\t".join("Cycle %d %s" % (c, "+" if d == "up" else "-")
                                   for c in cycles for d in ("up", "down")) + "\n")
    for t in targets:
        f.write("%.8f\t" % (t / 25.4) + "\t".join("%.8f" % (by_key[(t, c, d)] / 25.4)
                                                  for c in cycles for d in ("up", "down")) + "\n")

# ---- Circles: circle_xy.csv as other instruments export it -------------------------------------
import math

circle = []
with open("circle_xy.csv") as f:
    lines = [l for l in f if not l.startswith("#")]
for r in csv.DictReader(lines):
    circle.append((float(r["x_mm"]), float(r["y_mm"]), r["direction"]))


def polar(x, y):
    return math.degrees(math.atan2(y, x)) % 360.0, math.hypot(x, y)


# A ballbar's software: the radial deviation from the ballbar's length in micrometres against
# the angle, the plane and the length in its header comments; BOM, CRLF, ';' and the decimal
# comma; the directions written out.
with open("corpus/circle_xy_ballbar_um.csv", "w", encoding="utf-8", newline="") as f:
    f.write("\ufeff# Ballbar test 2026-11-24, machine pm1\r\n# Plane: XY\r\n# Radius: 150 mm\r\n")
    f.write("Angle (deg);Deviation (µm);Direction\r\n")
    for x, y, d in circle:
        a, r = polar(x, y)
        f.write("%s;%s;%s\r\n" % (("%.6f" % a).replace(".", ","),
                                  ("%.4f" % ((r - 150.0) * 1000.0)).replace(".", ","),
                                  "Anticlockwise" if d == "ccw" else "Clockwise"))

# A tracker or grid encoder export in inches, tab separated, the unit only in a comment.
with open("corpus/circle_xy_inch_tab.txt", "w", newline="") as f:
    f.write("# Circle XY\n# Units: in\n")
    f.write("X\tY\tDir\n")
    for x, y, d in circle:
        f.write("%.8f\t%.8f\t%s\n" % (x / 25.4, y / 25.4, d.upper()))

# ISO 230-4's 220 deg partial arc, as a vertical plane's test runs above the table: the points
# of circle_xy.csv from -20 deg counter-clockwise to 200 deg, deviations in micrometres, the
# plane given on the command line.
with open("corpus/circle_xy_arc220_um.txt", "w", newline="") as f:
    f.write("# 220 deg partial arc, -20 .. 200 deg\n# Radius: 150 mm\n")
    f.write("angle_deg\tdeviation_um\tdirection\n")
    for x, y, d in circle:
        a, r = polar(x, y)
        if 200.5 < a < 339.5:
            continue  # below the table
        if a >= 339.5:
            a -= 360.0  # -20 .. 200
        f.write("%.6f\t%.4f\t%s\n" % (a, (r - 150.0) * 1000.0, d))
