#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Lint.Format: every C++ file of the repository is laid out as .clang-format says.
# Usage: format.sh SOURCE_DIR. Exit 77 (ctest: skipped, with the reason) without clang-format.
set -uo pipefail
src="$1"
tool="$(command -v clang-format-14 || command -v clang-format || true)"
if [ -z "$tool" ]; then
  echo "SKIPPED: clang-format is not installed (deploy/install-deps.sh --test installs it)"
  exit 77
fi
cd "$src"
if git rev-parse --is-inside-work-tree > /dev/null 2>&1; then
  mapfile -t files < <(git ls-files '*.cpp' '*.hpp')
else
  mapfile -t files < <(find common services storage tests -name '*.cpp' -o -name '*.hpp')
fi
bad=0
for f in "${files[@]}"; do
  [ -f "$f" ] || continue
  if ! "$tool" --dry-run -Werror "$f" > /dev/null 2>&1; then
    echo "$f: not formatted; run: clang-format -i $f"
    "$tool" "$f" | diff -u "$f" - | head -20
    bad=$((bad + 1))
  fi
done
echo "${#files[@]} files checked with $("$tool" --version | head -1); $bad not formatted"
[ "$bad" -eq 0 ]
