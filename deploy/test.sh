#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Installs what is missing, builds everything and runs the whole test suite (ctest).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/deploy/install-deps.sh" --test
# The independent MCAP reader of the McapInterop.* tests: the npm packages pinned in its
# package-lock.json (they skip, saying why, without them).
if command -v npm > /dev/null; then
  npm ci --prefix "$root/tests/interop/mcap" --no-audit --no-fund \
    || echo "note: npm ci failed (no registry?): the McapInterop.* tests will be skipped"
else
  echo "note: npm is not installed: the McapInterop.* tests will be skipped"
fi
"$root/deploy/build.sh"
cd "${NCQUAL_BUILD_DIR:-$root/build}"
# The restart test SIGKILLs a service on purpose; Fast DDS leaves that process's shared-memory
# segments behind. Remove stale ones (of dead processes only) before and after.
clean_shm() { if command -v fastdds > /dev/null; then fastdds shm clean > /dev/null 2>&1 || true; fi; }
clean_shm
status=0
ctest --output-on-failure -j "${NCQUAL_JOBS:-$(nproc)}" "$@" || status=$?
clean_shm
# With two tests at a time the output of a failed test is far above the summary: say it again
# at the end, where a log's tail shows it.
if [ "$status" -ne 0 ] && [ -s Testing/Temporary/LastTestsFailed.log ]; then
  echo "=== output of the failed tests, again ==="
  while IFS=: read -r _ name; do
    awk -v n="$name" '$0 ~ "^[0-9]+/[0-9]+ Testing: " n "$" { on = 1 }
      on { print } on && /^"[^"]*" end time:/ { exit }' Testing/Temporary/LastTest.log | tail -80
  done < Testing/Temporary/LastTestsFailed.log
fi
exit $status
