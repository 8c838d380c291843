#!/usr/bin/python3
# SPDX-License-Identifier: Apache-2.0
# web.DashboardInChromium: the real ncqual-web on a historian written by ncqual_web_fixture,
# looked at with Debian's headless Chromium (the browser of tests/unit/charts), every figure
# compared with the database read here with Python's sqlite3:
#  - the JSON API: /api/v1/plant (states, overdue, active warnings, last failures),
#    /api/v1/machines/pm1 (checks and their metrics), /api/v1/checks/<id> (verdict, metrics with
#    tolerances, causes, correction) equal the rows;
#  - refusals: unknown machine or check 404 (JSON under /api/, HTML elsewhere), POST/DELETE/PUT
#    405 with Allow, unknown or bad parameters 400, an over-long query bounded (414 or 400),
#    every list within its limit;
#  - --dump-dom of the plant, machine and check pages: the state, the metric values, the warning
#    and the failure that are in the database are in the DOM Chromium built; every chart of the
#    machine report (svg.ncqual-chart) that the server sent is in the DOM;
#  - screenshots of the pages (kept in OUTDIR: plant.png, machine-pm1.png, machine-pm2.png,
#    check.png);
#  - simulated data: pm1's checks are the simulator's, pm2's measured: the banner and badges are
#    on pm1's pages (above every chart) and the plant page, none on pm2's;
#  - live: the plant page open in Chromium (DevTools protocol over a WebSocket), a check added to
#    the historian, the change token moves and the open page shows the new check without a
#    reload; every wait polls with a deadline;
#  - SIGTERM stops ncqual-web with exit code 0; bad usage exits 2 naming the flag, a bad `web:`
#    section of the plant 1 naming the file, the key and the value.
# Exit 77 (ctest: skipped) with a SKIPPED line when Chromium is not installed.
#  - /api/v1/plant's status is `ncqual status --json`'s.
# Usage: dashboard_in_chromium.py NCQUAL_WEB FIXTURE NCQUAL SOURCE_DIR OUTDIR. Standard library
# only.
import base64
import glob
import html
import json
import math
import os
import queue
import re
import shutil
import signal
import socket
import sqlite3
import struct
import subprocess
import sys
import tempfile
import threading
import time
import urllib.error
import urllib.parse
import urllib.request
import zoneinfo
from datetime import datetime, timezone

sys.dont_write_bytecode = True  # no __pycache__ in the source tree
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "support"))
from chromium import FLAGS as CHROMIUM_FLAGS, find_chromium, run_chromium  # noqa: E402

FAILURES = []


def check(condition, message):
    if not condition:
        FAILURES.append(message)
        print("FAIL", message, flush=True)
    return condition


def wait_for(what, predicate, deadline_s=30.0, every_s=0.1):
    """Polls predicate() until it returns a true value; fails naming `what` at the deadline."""
    end = time.monotonic() + deadline_s
    while True:
        value = predicate()
        if value:
            return value
        if time.monotonic() > end:
            raise TimeoutError(f"{what}: not within {deadline_s} s")
        time.sleep(every_s)  # the pace of polling, not a synchronisation


def http(method, url, data=None):
    """(status, headers, body text) of one request; never raises for an HTTP status."""
    req = urllib.request.Request(url, method=method, data=data)
    try:
        with urllib.request.urlopen(req, timeout=30) as res:
            return res.status, res.headers, res.read().decode("utf-8")
    except urllib.error.HTTPError as e:
        return e.code, e.headers, e.read().decode("utf-8", errors="replace")


def get_json(url):
    status, headers, body = http("GET", url)
    check(status == 200, f"GET {url}: {status}")
    check(headers.get("Content-Type", "").startswith("application/json"),
          f"GET {url}: Content-Type {headers.get('Content-Type')}")
    return json.loads(body)


def at_band(v, lower, upper):
    """A metric's value or bound as the pages write it: to a tenth of its tolerance band (the
    band's width, or the one limit's size), 4 decimals without one; "-0.000" is "0.000"."""
    if v is None or math.isnan(v):
        return "not evaluated"
    if math.isinf(v):
        return "&mdash;"
    finite = [b for b in (lower, upper) if b is not None and math.isfinite(b)]
    band = upper - lower if len(finite) == 2 else abs(finite[0]) if finite else 0.0
    decimals = 4 if not band > 0 else min(9, max(0, math.ceil(-math.log10(band / 10) - 1e-9)))
    text = f"{v:.{decimals}f}"
    return text[1:] if text.startswith("-") and not text.strip("-0.") else text


# ---- A minimal WebSocket client for the DevTools protocol (RFC 6455, text frames) ---------------

class DevTools:
    def __init__(self, ws_url):
        u = urllib.parse.urlparse(ws_url)
        self.sock = socket.create_connection((u.hostname, u.port), timeout=30)
        key = base64.b64encode(os.urandom(16)).decode()
        self.sock.sendall((f"GET {u.path} HTTP/1.1\r\nHost: {u.hostname}:{u.port}\r\n"
                           "Upgrade: websocket\r\nConnection: Upgrade\r\n"
                           f"Sec-WebSocket-Key: {key}\r\nSec-WebSocket-Version: 13\r\n\r\n").encode())
        head = b""
        while b"\r\n\r\n" not in head:
            chunk = self.sock.recv(1)
            if not chunk:
                raise ConnectionError("DevTools closed the WebSocket handshake")
            head += chunk
        if b" 101 " not in head.split(b"\r\n")[0]:
            raise ConnectionError("DevTools refused the WebSocket: " + head.decode(errors="replace"))
        self.next_id = 0

    def _recv_exact(self, n):
        data = b""
        while len(data) < n:
            chunk = self.sock.recv(n - len(data))
            if not chunk:
                raise ConnectionError("DevTools closed the WebSocket")
            data += chunk
        return data

    def _send(self, text):
        payload = text.encode()
        head = bytearray([0x81])
        n = len(payload)
        if n < 126:
            head.append(0x80 | n)
        elif n < 65536:
            head.append(0x80 | 126)
            head += struct.pack(">H", n)
        else:
            head.append(0x80 | 127)
            head += struct.pack(">Q", n)
        mask = os.urandom(4)
        head += mask
        self.sock.sendall(bytes(head) + bytes(b ^ mask[i % 4] for i, b in enumerate(payload)))

    def _recv(self):
        message = b""
        while True:
            b0, b1 = self._recv_exact(2)
            n = b1 & 0x7F
            if n == 126:
                n = struct.unpack(">H", self._recv_exact(2))[0]
            elif n == 127:
                n = struct.unpack(">Q", self._recv_exact(8))[0]
            mask = self._recv_exact(4) if b1 & 0x80 else None
            payload = self._recv_exact(n)
            if mask:
                payload = bytes(b ^ mask[i % 4] for i, b in enumerate(payload))
            opcode = b0 & 0x0F
            if opcode == 0x8:
                raise ConnectionError("DevTools closed the WebSocket")
            if opcode in (0x9, 0xA):  # ping, pong: not part of a message
                continue
            message += payload
            if b0 & 0x80:
                return json.loads(message.decode())

    def call(self, method, **params):
        self.next_id += 1
        self._send(json.dumps({"id": self.next_id, "method": method, "params": params}))
        while True:
            reply = self._recv()
            if reply.get("id") == self.next_id:
                if "error" in reply:
                    raise RuntimeError(f"{method}: {reply['error']}")
                return reply["result"]

    def evaluate(self, expression):
        result = self.call("Runtime.evaluate", expression=expression, returnByValue=True)
        return result["result"].get("value")

    def close(self):
        self.sock.close()


# ---- The server ------------------------------------------------------------------------------

class Web:
    def __init__(self, exe, plant, log):
        self.log = open(log, "w", encoding="utf-8")
        self.proc = subprocess.Popen([exe, "--plant", plant, "--port", "0", "--log-level", "debug"],
                                     stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        self.lines = queue.Queue()
        threading.Thread(target=self._read, daemon=True).start()
        url = None
        end = time.monotonic() + 30
        while url is None:
            try:
                line = self.lines.get(timeout=max(0.0, end - time.monotonic()))
            except queue.Empty:
                raise TimeoutError("ncqual-web did not say where it serves within 30 s")
            if line is None:
                raise RuntimeError(f"ncqual-web exited {self.proc.wait()} before serving (log {log})")
            m = re.search(r"on (http://127\.0\.0\.1:\d+)/", line)
            if m:
                url = m.group(1)
        self.url = url

    def _read(self):
        for line in self.proc.stderr:
            self.log.write(line)
            self.log.flush()
            self.lines.put(line)
        self.lines.put(None)

    def stop(self):
        self.proc.send_signal(signal.SIGTERM)
        try:
            return self.proc.wait(timeout=30)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            return None


# ---- The checks ------------------------------------------------------------------------------

def check_same_as_status(url, cli, plant):
    """/api/v1/plant's status is `ncqual status --json`'s (one copy of the logic, plant_status)."""
    r = subprocess.run([cli, "status", "--plant", plant, "--json"], stdout=subprocess.PIPE,
                       stderr=subprocess.PIPE, text=True, timeout=60, check=False)
    check(r.returncode == 0, f"ncqual status --json: exit {r.returncode}: {r.stderr}")
    cli_status = json.loads(r.stdout)
    web_status = get_json(url + "/api/v1/plant")["status"]
    # A period that is due falls due "now": the wall clock of each, which differ.
    for status in (cli_status, web_status):
        for m in status["machines"]:
            for p in m["periods"]:
                if p["due"]:
                    p["next_due_ns"] = "now"
    for key in ("plant", "machines", "heartbeat_period_ms"):
        check(web_status[key] == cli_status[key],
              f"/api/v1/plant status.{key} differs from ncqual status --json's")
    strip = lambda services: [{k: v for k, v in s.items() if k != "age_ns"} for s in services]
    check(strip(web_status["services"]) == strip(cli_status["services"]),
          "/api/v1/plant status.services differ from ncqual status --json's")


def check_api(url, db):
    # The plant: every configured machine's state is its newest stored status.
    plant = get_json(url + "/api/v1/plant")
    machines = {m["machine_id"]: m for m in plant["status"]["machines"]}
    check(sorted(machines) == ["pm1", "pm2"], f"plant machines {sorted(machines)}")
    for machine_id, m in machines.items():
        state = db.execute("SELECT state FROM status_changes WHERE machine_id = ? "
                           "ORDER BY time_ns DESC, id DESC LIMIT 1", (machine_id,)).fetchone()[0]
        check(m["state"] == state, f"{machine_id}: API state {m['state']}, database {state}")
        active = db.execute("SELECT metric, kind, text FROM trend_warnings WHERE machine_id = ? "
                            "AND ended_ns IS NULL ORDER BY metric", (machine_id,)).fetchall()
        api = sorted((w["metric"], w["kind"], w["text"]) for w in m["warnings"])
        check(api == sorted(active), f"{machine_id}: API warnings {api}, database {active}")
        check(len(m["periods"]) > 0, f"{machine_id}: no periods")
    check(machines["pm1"]["state"] == "NEEDS_INTERVENTION", "pm1 is not held")
    newest_failures = db.execute("SELECT request_id, verdict, reason FROM results WHERE "
                                 "verdict <> 'PASS' ORDER BY time_ns DESC LIMIT 20").fetchall()
    api_failures = [(f["request_id"], f["verdict"], f["reason"]) for f in plant["failures"]]
    check(api_failures == newest_failures,
          f"API failures {api_failures}, database {newest_failures}")
    check(re.fullmatch(r"[0-9.]+", plant["token"]) is not None, f"token {plant['token']!r}")

    # A machine: its newest checks, their metrics as stored.
    machine = get_json(url + "/api/v1/machines/pm1")
    check(machine["machine"]["machine_id"] == "pm1", "machine document names another machine")
    ids = [c["request_id"] for c in machine["checks"]]
    rows = [r[0] for r in db.execute("SELECT request_id FROM results WHERE machine_id = 'pm1' "
                                     "ORDER BY time_ns DESC LIMIT 50")]
    check(ids == rows, f"machine checks {ids}, database {rows}")
    for c in machine["checks"]:
        stored = db.execute("SELECT m.name, m.value, m.lower, m.upper FROM metrics AS m WHERE "
                            "m.request_id = ? ORDER BY m.idx", (c["request_id"],)).fetchall()
        api = [(m["name"], m["value"], m["lower"], m["upper"]) for m in c["metrics"]]
        check(api == stored, f"{c['request_id']}: API metrics {api}, database {stored}")
    limited = get_json(url + "/api/v1/machines/pm1?checks=3")
    check(len(limited["checks"]) == 3, f"?checks=3 gave {len(limited['checks'])}")
    most = get_json(url + "/api/v1/machines/pm1?checks=200")
    check(len(most["checks"]) <= 200 and len(most["checks"]) == len(rows),
          f"?checks=200 gave {len(most['checks'])}")

    # A check: request, verdict, metrics with tolerances, causes, correction.
    fail_id = newest_failures[0][0]
    c = get_json(url + "/api/v1/checks/" + urllib.parse.quote(fail_id))
    verdict, reason = db.execute("SELECT verdict, reason FROM results WHERE request_id = ?",
                                 (fail_id,)).fetchone()
    check((c["verdict"], c["reason"]) == (verdict, reason),
          f"check {fail_id}: API {(c['verdict'], c['reason'])}, database {(verdict, reason)}")
    causes = [r[0] for r in db.execute("SELECT cause FROM causes WHERE request_id = ? ORDER BY rank",
                                       (fail_id,))]
    check(c["likely_causes"] == causes, f"causes {c['likely_causes']}, database {causes}")
    offsets = db.execute("SELECT name, value, unit FROM result_offsets WHERE request_id = ? "
                         "ORDER BY idx", (fail_id,)).fetchall()
    api_offsets = [(o["name"], o["value"], o["unit"]) for o in c["correction"]["offsets"]]
    check(api_offsets == offsets, f"correction {api_offsets}, database {offsets}")
    return fail_id


def check_refusals(url):
    for path, status in [("/api/v1/machines/nope", 404), ("/api/v1/checks/no-such-check", 404),
                         ("/api/v1/nothing", 404), ("/machines/nope", 404), ("/checks/nope", 404),
                         ("/api/v1/machines/pm1?checks=0", 400),
                         ("/api/v1/machines/pm1?checks=201", 400),
                         ("/api/v1/machines/pm1?checks=abc", 400), ("/api/v1/plant?x=1", 400),
                         ("/api/v1/changes?since=abc", 400),
                         ("/api/v1/changes?since=" + "1" * 300, 400),
                         ("/api/v1/machines/" + "m" * 300, 400), ("/machines/pm1?days=0", 400),
                         ("/machines/pm1?days=367", 400), ("/machines/pm1?checks=5", 400)]:
        got, headers, body = http("GET", url + path)
        check(got == status, f"GET {path[:60]}: {got}, expected {status}")
        if path.startswith("/api/"):
            try:
                document = json.loads(body)
                check(document["error"]["status"] == status, f"GET {path[:60]}: body {body[:200]}")
            except (ValueError, KeyError):
                check(False, f"GET {path[:60]}: not a JSON error: {body[:200]}")
        else:
            check("<!DOCTYPE html>" in body, f"GET {path}: not an HTML page")
        check(len(body) < 4096, f"GET {path[:60]}: {len(body)} bytes for a refusal")
    # An over-long query: refused, bounded, whatever its length.
    got, _, body = http("GET", url + "/api/v1/changes?since=" + "1" * 20000)
    check(got in (400, 414), f"a 20000-character query: {got}")
    check(len(body) < 4096, f"a 20000-character query: {len(body)} bytes answered")
    for method in ("POST", "PUT", "DELETE", "PATCH"):
        for path in ("/", "/api/v1/plant", "/api/v1/machines/pm1"):
            got, headers, _ = http(method, url + path, data=b"x" if method != "DELETE" else None)
            check(got == 405, f"{method} {path}: {got}, expected 405")
            check(headers.get("Allow") == "GET, HEAD", f"{method} {path}: Allow {headers.get('Allow')}")


def check_pages(chromium, url, db, outdir, fail_id):
    pages = {"plant": "/", "machine-pm1": "/machines/pm1", "machine-pm2": "/machines/pm2",
             "check": "/checks/" + urllib.parse.quote(fail_id)}
    doms = {}
    for name, path in pages.items():
        res = run_chromium(chromium, ["--dump-dom", "--window-size=1280,2000", url + path])
        check(res.returncode == 0, f"chromium --dump-dom {path} exited {res.returncode}")
        doms[name] = res.stdout.decode("utf-8", errors="replace")
        with open(os.path.join(outdir, name + ".dom.html"), "w", encoding="utf-8") as f:
            f.write(doms[name])
        shot = os.path.join(outdir, name + ".png")
        res = run_chromium(chromium, ["--screenshot=" + shot, "--window-size=1280,2000", url + path])
        check(res.returncode == 0 and os.path.exists(shot), f"no screenshot of {path}")
    plant, machine, check_dom = doms["plant"], doms["machine-pm1"], doms["check"]

    # The plant page: each machine's state, the active warning, the newest failure.
    for machine_id in ("pm1", "pm2"):
        state = db.execute("SELECT state FROM status_changes WHERE machine_id = ? "
                           "ORDER BY time_ns DESC, id DESC LIMIT 1", (machine_id,)).fetchone()[0]
        section = re.search(r'<section class="nw-machine"[^>]*data-machine="' + machine_id +
                            r'".*?</section>', plant, re.S)
        check(section is not None, f"plant page: no section of {machine_id}")
        if section:
            check(f'data-state="{state}"' in section.group(0),
                  f"plant page: {machine_id} is not shown {state}")
    warning = db.execute("SELECT metric, text FROM trend_warnings WHERE machine_id = 'pm1' AND "
                         "ended_ns IS NULL").fetchone()
    check(html.escape(warning[1], quote=False) in plant, f"plant page: warning text {warning[1]!r}")
    check(fail_id in plant, f"plant page: the newest failure {fail_id} is not shown")
    ended = db.execute("SELECT text FROM trend_warnings WHERE ended_ns IS NOT NULL").fetchone()[0]
    check(ended not in plant, "plant page: an ended warning is shown as active")

    # Simulated data (issue 37 point 5): pm1's checks are the simulator's, pm2's measured, as the
    # database says. The plant page bears a banner naming pm1 alone and a SIMULATED badge on pm1's
    # card; pm1's page and its check's a banner above everything, and each simulated row of its
    # checks table a marker; pm2's page (measured) none of these.
    origins = {m: {o for (o,) in db.execute("SELECT origin FROM results WHERE machine_id = ?", (m,))}
               for m in ("pm1", "pm2")}
    check(origins == {"pm1": {"simulated"}, "pm2": {"measured"}}, f"fixture origins {origins}")
    banner = re.search(r'<div class="nw-simulated-banner"[^>]*>(.*?)</div>', plant, re.S)
    check(banner is not None, "plant page: no simulated-data banner")
    if banner:
        check("pm1" in banner.group(1) and "pm2" not in banner.group(1),
              f"plant page: the banner names {banner.group(1)!r}")
        check(banner.start() < plant.find('<div class="nw-machines"'),
              "plant page: the banner is not above the machines")
    for machine_id, simulated in (("pm1", True), ("pm2", False)):
        section = re.search(r'<section class="nw-machine"[^>]*data-machine="' + machine_id +
                            r'".*?</section>', plant, re.S)
        if section:
            check(("nw-badge nw-simulated" in section.group(0)) == simulated,
                  f"plant page: {machine_id}'s SIMULATED badge is {'missing' if simulated else 'shown'}")
    for name, page in (("machine-pm1", machine), ("check", check_dom)):
        at = page.find('class="nw-simulated-banner"')
        check(at >= 0, f"{name} page: no simulated-data banner")
        first_chart = page.find("<svg")
        check(first_chart < 0 or at < first_chart, f"{name} page: the banner is below a chart")
    pm1_rows = re.findall(r'<tr data-request="[^"]*" data-origin="([a-z]+)"', machine)
    check(pm1_rows and set(pm1_rows) == {"simulated"},
          f"machine page pm1: rows of origin {pm1_rows}, database simulated")
    marked = machine.count('class="nw-simulated-row"')
    check(marked == len(pm1_rows), f"machine page pm1: {marked} rows marked, {len(pm1_rows)} listed")
    check('class="ncqual-simulated-banner"' in machine, "machine page pm1: the report has no banner")
    pm2 = doms["machine-pm2"]
    # (the stylesheets name these classes on every page: the markers are the elements)
    for marker in ('class="nw-simulated-banner"', '"nw-badge nw-simulated"',
                   'class="nw-simulated-row"', 'class="ncqual-simulated-banner"',
                   'class="origin-badge simulated"', ">SIMULATED<"):
        check(marker not in pm2, f"machine page pm2 (measured): {marker} is shown")
    pm2_rows = re.findall(r'<tr data-request="[^"]*" data-origin="([a-z]+)"', pm2)
    check(pm2_rows and set(pm2_rows) == {"measured"}, f"machine page pm2: rows of origin {pm2_rows}")

    # The check page: every metric's value and band as stored, the causes, the correction.
    for name, value, lower, upper in db.execute(
            "SELECT name, value, lower, upper FROM metrics WHERE request_id = ? ORDER BY idx",
            (fail_id,)):
        row = re.search(r'<tr data-metric="' + name + r'".*?</tr>', check_dom, re.S)
        check(row is not None, f"check page: no row of {name}")
        if row:
            cells = re.findall(r'<td class="nw-num[^"]*">([^<]*)</td>', row.group(0))
            check(cells == [at_band(x, lower, upper) for x in (value, lower, upper)],
                  f"check page: {name} shows {cells}, database {[value, lower, upper]}")
    for (cause,) in db.execute("SELECT cause FROM causes WHERE request_id = ?", (fail_id,)):
        check(html.escape(cause, quote=False) in check_dom, f"check page: cause {cause!r}")

    # The machine page: the machine's state, its checks, and every chart the server sent.
    check('data-state="NEEDS_INTERVENTION"' in machine, "machine page: pm1 not shown held")
    check(fail_id in machine, "machine page: the newest failure is not listed")
    _, _, served = http("GET", url + "/machines/pm1")
    served_charts = len(re.findall(r'<svg\b[^>]*class="[^"]*ncqual-chart', served))
    dom_charts = len(re.findall(r'<svg\b[^>]*class="[^"]*ncqual-chart', machine))
    sections = len(re.findall(r'<section class="ncqual-report-', machine))
    print(f"machine page: {sections} report sections, {served_charts} charts served, "
          f"{dom_charts} in the DOM", flush=True)
    check(sections > 0, "machine page: no report section (report/ built in?)")
    check(served_charts > 0, "machine page: no chart (svg.ncqual-chart) served")
    check(dom_charts == served_charts, f"machine page: {dom_charts} charts in the DOM, "
          f"{served_charts} served")

    # One clock: the newest failure's time, worked out here with Python's zoneinfo, reads the same
    # in the page's own table and in the report's checks table (the fixture plant is in Berlin),
    # and no time on the page is in UTC (but the budget's reason for a held machine, which still
    # writes its status time in UTC: docs/report.md).
    (t_ns,) = db.execute("SELECT time_ns FROM results WHERE request_id = ?", (fail_id,)).fetchone()
    local = datetime.fromtimestamp(t_ns // 1_000_000_000, timezone.utc).astimezone(
        zoneinfo.ZoneInfo("Europe/Berlin"))
    text = local.strftime("%Y-%m-%d %H:%M ") + local.strftime("%z")[:3] + ":" + \
        local.strftime("%z")[3:] + " " + local.tzname()
    report_at = machine.find('class="ncqual-report-checks"')
    check(0 <= machine.find(text) < report_at, f"machine page: its own table lacks {text}")
    check(report_at >= 0 and machine.find(text, report_at) >= 0,
          f"machine page: the report's checks table lacks {text}")
    budget_at = machine.find('class="ncqual-report-budget"')
    utc = re.search(r"\(UTC\)|\d\d:\d\d(:\d\d)? (\+00:00 )?UTC", machine[:budget_at])
    check(utc is None, f"machine page: a time in UTC: {utc.group(0) if utc else ''}")
    check("date (Europe/Berlin)" in machine, "machine page: the trend axes do not name the zone")


def check_live(chromium, url, fixture, directory):
    profile = tempfile.mkdtemp(prefix="ncqual-chromium-live-")
    proc = subprocess.Popen([chromium] + CHROMIUM_FLAGS +
                            ["--user-data-dir=" + profile, "--remote-debugging-port=0",
                             "--window-size=1280,2000", url + "/"],
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    devtools = None
    try:
        port_file = os.path.join(profile, "DevToolsActivePort")
        port = wait_for("Chromium's DevToolsActivePort",
                        lambda: os.path.exists(port_file) and
                        open(port_file).read().split("\n")[0].strip())
        targets = wait_for("the page's DevTools target", lambda: [
            t for t in json.loads(urllib.request.urlopen(
                f"http://127.0.0.1:{port}/json/list", timeout=10).read())
            if t.get("type") == "page" and t.get("url", "").startswith(url)])
        devtools = DevTools(targets[0]["webSocketDebuggerUrl"])
        # Live: the page has asked for changes at least once.
        wait_for("the open page's first poll of /api/v1/changes", lambda: devtools.evaluate(
            "parseInt(document.body.dataset.polls || '0', 10) >= 1"))
        before = devtools.evaluate("document.body.dataset.token")
        _, _, body = http("GET", url + "/api/v1/changes")
        check(json.loads(body)["token"] == before, f"the page's token {before} is not the server's")
        subprocess.run([fixture, "add", directory, "pm1-live-1"], check=True)
        after = wait_for("the change token to move after a check was stored", lambda: (
            lambda t: t if t != before else None)(json.loads(
                http("GET", url + "/api/v1/changes?since=" + before)[2])["token"]))
        print(f"change token {before} -> {after}", flush=True)
        shown = wait_for("the open page to show the new check", lambda: devtools.evaluate(
            "document.body.dataset.token === " + json.dumps(after) + " && "
            "document.querySelector('main').innerHTML.includes('pm1-live-1') && "
            "document.body.dataset.updates"), deadline_s=30)
        print(f"the open page updated ({shown} update(s)) without a reload", flush=True)
        check(devtools.evaluate("document.querySelector('section[data-machine=\"pm1\"] "
                                ".nw-last-failure').textContent.includes('pm1-live-1')"),
              "live: pm1's last failure is not the new check")
    finally:
        if devtools:
            devtools.close()
        proc.terminate()
        try:
            proc.wait(timeout=30)
        except subprocess.TimeoutExpired:
            proc.kill()
        shutil.rmtree(profile, ignore_errors=True)


def check_command_line(web_exe, directory):
    """Bad usage and a bad `web:` section are refused, naming the flag, key and value."""
    def run(*args):
        return subprocess.run([web_exe] + list(args), stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                              text=True, timeout=60, check=False)
    plant = os.path.join(directory, "plant.yaml")
    r = run("--bogus")
    check(r.returncode == 2 and "--bogus" in r.stderr, f"--bogus: exit {r.returncode}: {r.stderr}")
    r = run("--plant", plant, "--port", "70000")
    check(r.returncode == 2 and "--port" in r.stderr, f"--port 70000: exit {r.returncode}: {r.stderr}")
    r = run("--plant", plant, "--bind", "10.0.0.300")
    check(r.returncode == 1 and "--bind '10.0.0.300'" in r.stderr,
          f"--bind 10.0.0.300: exit {r.returncode}: {r.stderr}")
    r = run("--plant", plant, "--db", os.path.join(directory, "missing.db"))
    check(r.returncode == 1 and "missing.db" in r.stderr, f"--db missing.db: exit {r.returncode}: {r.stderr}")
    bad = os.path.join(directory, "bad-web.yaml")
    with open(plant, encoding="utf-8") as f:
        text = f.read().replace("bind: 127.0.0.1", "bind: my-host").replace("port: 8470", "port: 99999")
    with open(bad, "w", encoding="utf-8") as f:
        f.write(text)
    r = run("--plant", bad)
    for part in ("bad-web.yaml", "web.bind", "my-host", "web.port", "99999"):
        check(r.returncode == 1 and part in r.stderr,
              f"a bad web: section: exit {r.returncode}, {part!r} not named: {r.stderr}")
    r = run("--version")
    check(r.returncode == 0 and r.stdout.startswith("ncqual-web "), f"--version: {r.stdout}")


def main():
    web_exe, fixture, cli, source_dir, outdir = sys.argv[1:6]
    chromium = find_chromium()
    if chromium is None:
        print("SKIPPED: chromium is not installed (deploy/install-deps.sh --test installs it)")
        return 77
    shutil.rmtree(outdir, ignore_errors=True)
    os.makedirs(outdir)
    directory = os.path.join(outdir, "plant")
    subprocess.run([fixture, "make", directory, source_dir], check=True)
    db = sqlite3.connect("file:" + os.path.join(directory, "historian.db") + "?mode=ro", uri=True)
    check_command_line(web_exe, directory)
    web = Web(web_exe, os.path.join(directory, "plant.yaml"), os.path.join(outdir, "ncqual-web.log"))
    print(f"ncqual-web serves {web.url}", flush=True)
    try:
        fail_id = check_api(web.url, db)
        check_same_as_status(web.url, cli, os.path.join(directory, "plant.yaml"))
        check_refusals(web.url)
        check_pages(chromium, web.url, db, outdir, fail_id)
        check_live(chromium, web.url, fixture, directory)
    except (TimeoutError, ConnectionError, RuntimeError, subprocess.SubprocessError) as e:
        check(False, f"{type(e).__name__}: {e}")
    finally:
        code = web.stop()
        check(code == 0, f"ncqual-web after SIGTERM: exit {code}")
    for f in FAILURES:
        print("FAIL", f)
    print(f"{len(FAILURES)} problems; screenshots and DOMs in {outdir}: "
          f"{sorted(os.path.basename(p) for p in glob.glob(os.path.join(outdir, '*.png')))}")
    return 1 if FAILURES else 0


if __name__ == "__main__":
    sys.exit(main())
