#!/usr/bin/python3
# SPDX-License-Identifier: Apache-2.0
# Reads an `ncqual export` folder back with Python's csv module and compares it, value by value,
# with the historian it came from read through Python's sqlite3 module; used by
# tests/integration/test_export_cli.cpp (DbExport.*).
#
#   check_export.py DATABASE FOLDER
#
# The rows each file must hold are worked out here, independently of ncqual's SQL: every row of
# each table is read and filtered in Python by the manifest's filter (a row's own time, the parts
# of a sample by their sample's time, machines and services by their first..last span). Then for
# every row and column: an integer column equals int(field), a real column float(field) with the
# same bits (repr), a text the field, NULL an empty field; every *_utc column is the instant of the
# *_ns column before it; every *_name column after a kind names the same kind everywhere.
# Prints one JSON object (rows per file, values compared, the problems); exits 1 on any problem.
import csv
import calendar
import json
import math
import os
import sqlite3
import sys
import time

# table -> (parent table, join column of the table, key column of the parent) for the parts of a
# sample; the others are filtered by their own time.
PARENTS = {
    "request_parameters": ("requests", "request_id", "request_id"),
    "measurement_parameters": ("measurement_sets", "request_id", "request_id"),
    "touches": ("measurement_sets", "request_id", "request_id"),
    "tracker_points": ("measurement_sets", "request_id", "request_id"),
    "metrics": ("results", "request_id", "request_id"),
    "causes": ("results", "request_id", "request_id"),
    "result_offsets": ("results", "request_id", "request_id"),
    "compensation_offsets": ("compensations", "compensation_id", "id"),
}
# table -> (first time column, last time column)
TIMES = {
    "machines": ("first_seen_ns", "last_seen_ns"),
    "services": ("first_seen_ns", "last_seen_ns"),
    "checks": ("sort_ns", "sort_ns"),
    "conflicts": ("received_ns", "received_ns"),
    "trend_warnings": ("started_ns", "ended_ns"),  # ended_ns NULL: still active
}


def utc_ns(text):
    # 2027-01-15T08:00:01.000000123Z -> ns since the epoch
    if len(text) != 30 or text[19] != "." or text[-1] != "Z":
        raise ValueError("not an ISO 8601 UTC time with ns: %r" % text)
    seconds = calendar.timegm(time.strptime(text[:19], "%Y-%m-%dT%H:%M:%S"))
    return seconds * 1_000_000_000 + int(text[20:29])


def main():
    database, folder = sys.argv[1], sys.argv[2]
    with open(os.path.join(folder, "manifest.json"), encoding="utf-8") as f:
        manifest = json.load(f)
    flt = manifest["filter"]
    since = flt["since_ns"]
    until = flt["until_ns"] if flt["until_ns"] is not None else 2**63 - 1
    machines = set(flt["machines"])
    db = sqlite3.connect("file:%s?mode=ro" % database, uri=True)
    problems, compared, rows_of, kind_names = [], 0, {}, {}

    def rows(table):
        cur = db.execute('SELECT * FROM "%s"' % table)
        names = [d[0] for d in cur.description]
        return names, [dict(zip(names, r)) for r in cur.fetchall()]

    def wanted(table, row):
        if table in PARENTS:
            parent, column, key = PARENTS[table]
            p = parents[parent].get(row[column])
            return p is not None and wanted(parent, p)
        first, last = TIMES.get(table, ("time_ns", "time_ns"))
        end = row[last] if row[last] is not None else float("inf")
        if not (end >= since and row[first] < until):
            return False
        return not machines or row["machine_id"] in machines

    parents = {}
    for parent, key in {("requests", "request_id"), ("measurement_sets", "request_id"),
                        ("results", "request_id"), ("compensations", "id")}:
        parents[parent] = {r[key]: r for r in rows(parent)[1]}

    for entry in manifest["files"]:
        table, path = entry["table"], os.path.join(folder, entry["file"])
        names, all_rows = rows(table)
        expected = [r for r in all_rows if wanted(table, r)]
        with open(path, encoding="utf-8", newline="") as f:
            raw = f.read()
        if raw and not raw.endswith("\r\n"):
            problems.append("%s: a line does not end in CRLF" % entry["file"])
        if raw.startswith("\ufeff"):
            problems.append("%s: starts with a BOM" % entry["file"])
        with open(path, encoding="utf-8", newline="") as f:
            read = list(csv.reader(f))
        header, body = read[0], read[1:]
        if header != entry["columns"]:
            problems.append("%s: header %s is not the manifest's %s" % (entry["file"], header,
                                                                         entry["columns"]))
        # Each database column and where it is in the file.
        at = {}
        for name in names:
            if name not in header:
                problems.append("%s: no column %s" % (entry["file"], name))
            else:
                at[name] = header.index(name)
        for name in header:
            if name not in names and not name.endswith("_utc") and not name.endswith("_name"):
                problems.append("%s: column %s is not in the table" % (entry["file"], name))
        rows_of[entry["file"]] = len(body)
        if len(body) != len(expected) or len(body) != entry["rows"]:
            problems.append("%s: %d rows, the database %d, the manifest %d" %
                            (entry["file"], len(body), len(expected), entry["rows"]))
            continue
        key = lambda values: [str(v) for v in values]  # noqa: E731
        body.sort(key=lambda fields: key(fields[at[n]] for n in names))
        expected.sort(key=lambda r: key("" if r[n] is None else
                                        (repr(r[n]) if isinstance(r[n], float) else r[n])
                                        for n in names))
        for fields, row in zip(body, expected):
            if len(fields) != len(header):
                problems.append("%s: a row of %d fields" % (entry["file"], len(fields)))
                continue
            for name in names:
                field, value = fields[at[name]], row[name]
                compared += 1
                if value is None:
                    ok = field == ""
                elif isinstance(value, int):
                    ok = field == str(value)
                elif isinstance(value, float):
                    ok = repr(float(field)) == repr(value) or (math.isinf(value) and
                                                               float(field) == value)
                else:
                    ok = field == value
                if not ok:
                    problems.append("%s: %s = %r, the database has %r" % (entry["file"], name,
                                                                         field, value))
                if name.endswith("_ns"):
                    utc = fields[at[name] + 1]
                    compared += 1
                    if value is None or (value == 0 and name == "oldest_unacknowledged_ns"):
                        if utc != "":
                            problems.append("%s: %s_utc %r for %r" % (entry["file"], name, utc,
                                                                      value))
                    elif utc_ns(utc) != value:
                        problems.append("%s: %s %r is not %d" % (entry["file"], header[at[name] + 1],
                                                                 utc, value))
                elif (name == "kind" or name.endswith("_kind")) and \
                        header[at[name] + 1] == name + "_name":
                    compared += 1
                    if value is not None:
                        known = kind_names.setdefault(value, fields[at[name] + 1])
                        if known != fields[at[name] + 1] or not known:
                            problems.append("%s: kind %d named %r and %r" %
                                            (entry["file"], value, known, fields[at[name] + 1]))
    print(json.dumps({"rows": rows_of, "compared": compared, "kind_names": kind_names,
                      "problems": problems[:50]}, sort_keys=True))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
