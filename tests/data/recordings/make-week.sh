#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Makes week-3-machines.mcap (README.md beside this file): the four real services run a
# simulated working week (Monday 2 November 2026, UTC) of the three machines of machines/ while
# `ncqual record` records every topic; the recorder is stopped once the historian holds every
# result and the recording every sample the historian stored.
#
# Usage: tests/data/recordings/make-week.sh BUILD_DIR OUT.mcap [DOMAIN]
set -euo pipefail
build="$(cd "${1:?usage: make-week.sh BUILD_DIR OUT.mcap [DOMAIN]}" && pwd)"
out="$(realpath -m "${2:?usage: make-week.sh BUILD_DIR OUT.mcap [DOMAIN]}")"
domain="${3:-169}"
here="$(cd "$(dirname "$0")" && pwd)"
work="$(mktemp -d)"
trap 'kill $(jobs -p) 2> /dev/null || true; wait; rm -rf "$work"' EXIT
cat > "$work/plant.yaml" << YAML
plant: recordings
domain_id: $domain
qos_profiles: $here/../../../deploy/qos/ncqual-qos.xml
historian: {database: $work/historian.db}
clock: {mode: simulated, start: "2026-11-02T00:00:00Z"}
scheduler:
  calendar:
    time_zone: UTC
    parts: {cycle_min: 240}
machines: [$here/machines/r01.yaml, $here/machines/r02.yaml, $here/machines/r03.yaml]
YAML
ncqual="$build/services/cli/ncqual"
"$ncqual" record --plant "$work/plant.yaml" --out "$out" --overwrite 2> "$work/record.log" &
recorder=$!
"$build/services/historian/ncqual-historian" --plant "$work/plant.yaml" 2> "$work/historian.log" &
"$build/services/solver/ncqual-solver" --plant "$work/plant.yaml" 2> "$work/solver.log" &
"$build/services/acquisition/ncqual-acquisition" --plant "$work/plant.yaml" --all \
  2> "$work/acquisition.log" &
"$build/services/scheduler/ncqual-scheduler" --plant "$work/plant.yaml" --days 5 \
  2> "$work/scheduler.log"
# Every machine's last cycle over in the historian, then every stored result in the recording.
for machine in r01 r02 r03; do
  "$ncqual" wait --plant "$work/plant.yaml" --settled --machine "$machine" --timeout 120 > /dev/null
done
stored="$("$ncqual" count --plant "$work/plant.yaml")"
for _ in $(seq 600); do
  recorded="$("$ncqual" recording info --json "$out" 2> /dev/null \
    | grep -A5 '"topic": "ncqual/CheckResult",' | grep -m1 -o '"messages": [0-9]*' \
    | grep -o '[0-9]*$' || true)"
  [ -n "$recorded" ] && [ "$recorded" -ge "$stored" ] && break
  sleep 0.1
done
kill -TERM "$recorder"
wait "$recorder"
cat "$work/record.log" >&2
