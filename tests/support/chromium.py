# SPDX-License-Identifier: Apache-2.0
# Debian's headless Chromium for the browser tests (charts.RenderedInChromium,
# report.RenderedInChromium, web.DashboardInChromium): where it is, the flags every run takes, and
# one run in a throw-away profile. A script imports it with its own folder's ../../support (or
# ../support) on sys.path. Standard library only.
import shutil
import subprocess
import tempfile

# Headless, no GPU, no sandbox (ctest may run as root), nothing from a user's profile.
FLAGS = ["--headless", "--disable-gpu", "--no-sandbox", "--no-first-run",
         "--disable-extensions", "--hide-scrollbars", "--mute-audio"]


def find_chromium():
    """The path of chromium (or chromium-browser), None when neither is installed."""
    for candidate in ("chromium", "chromium-browser"):
        path = shutil.which(candidate)
        if path:
            return path
    return None


def run_chromium(chromium, args, timeout=90):
    """One headless run with `args` in a fresh profile; the CompletedProcess (stdout, stderr)."""
    with tempfile.TemporaryDirectory(prefix="ncqual-chromium-") as profile:
        cmd = [chromium] + FLAGS + ["--user-data-dir=" + profile] + args
        return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                              timeout=timeout, check=False)
