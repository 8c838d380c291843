#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Installs what is missing, builds everything and runs the whole test suite (ctest).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/deploy/install-deps.sh" --test
"$root/deploy/build.sh"
cd "${NCQUAL_BUILD_DIR:-$root/build}"
# The restart test SIGKILLs a service on purpose; Fast DDS leaves that process's shared-memory
# segments behind. Remove stale ones (of dead processes only) before and after.
clean_shm() { command -v fastdds > /dev/null && fastdds shm clean > /dev/null 2>&1 || true; }
clean_shm
status=0
ctest --output-on-failure -j "${NCQUAL_JOBS:-$(nproc)}" "$@" || status=$?
clean_shm
exit $status
