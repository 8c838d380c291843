#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Lint.Tidy.<part>: clang-tidy with the repository's .clang-tidy over the part's translation units
# (from the build's compile_commands.json; tests and generated code are not linted).
# Usage: tidy.sh BUILD_DIR SOURCE_DIR PATH_PREFIX. Exit 77 (ctest: skipped) without clang-tidy.
set -uo pipefail
build="$1" src="$2" prefix="$3"
tool="$(command -v clang-tidy-14 || command -v clang-tidy || true)"
if [ -z "$tool" ]; then
  echo "SKIPPED: clang-tidy is not installed (deploy/install-deps.sh --test installs it)"
  exit 77
fi
mapfile -t files < <(python3 - "$build/compile_commands.json" "$src/$prefix" <<'PY'
import json, sys
entries = json.load(open(sys.argv[1]))
print("\n".join(sorted({e["file"] for e in entries if e["file"].startswith(sys.argv[2])})))
PY
)
if [ "${#files[@]}" -eq 0 ]; then
  echo "no translation unit under $src/$prefix in $build/compile_commands.json"
  exit 1
fi
bad=0
for f in "${files[@]}"; do
  if ! out="$("$tool" -p "$build" --quiet "$f" 2>&1)"; then
    echo "$out" | grep -E 'error:|warning:|note:|^ ' | head -40
    bad=$((bad + 1))
  fi
done
echo "${#files[@]} files under $prefix checked with $("$tool" --version | grep -i version); $bad with findings"
[ "$bad" -eq 0 ]
