#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Configures and builds ncqual (Release) into build/ at the repository root.
# Usage: deploy/build.sh [cmake --build arguments, e.g. --target ncqual-solver]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${NCQUAL_BUILD_DIR:-$root/build}"
jobs="${NCQUAL_JOBS:-$(nproc)}"
# ccache hits across clones and build directories: paths below the root count as relative.
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$root}"
if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release > "$root/.cmake-configure.log" 2>&1 \
    || { cat "$root/.cmake-configure.log"; exit 1; }
  rm -f "$root/.cmake-configure.log"
fi
cmake --build "$build" -j "$jobs" "$@"
