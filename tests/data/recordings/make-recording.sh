#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Makes a committed recording (README.md beside this file says which arguments made which file):
# the four real services run simulated working days of the machines given (machines/) while
# `ncqual record` records every topic; the recorder is stopped once every machine has settled and
# the recording holds every result the historian stored.
#
# Usage: tests/data/recordings/make-recording.sh BUILD_DIR OUT.mcap MACHINES START DAYS
#          [COMPRESSION] [DOMAIN]
#   MACHINES    comma-separated machine ids of machines/ (r01,r02,r03)
#   START       the simulated clock's start, ISO 8601 UTC (2026-11-02T00:00:00Z: a Monday)
#   DAYS        days the scheduler plans (ncqual-scheduler --days)
#   COMPRESSION zstd (default), lz4 or none
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
usage="usage: make-recording.sh BUILD_DIR OUT.mcap MACHINES START DAYS [COMPRESSION] [DOMAIN]"
build="$(cd "${1:?$usage}" && pwd)"
out="$(realpath -m "${2:?$usage}")"
IFS=, read -r -a machines <<< "${3:?$usage}"
start="${4:?$usage}"
days="${5:?$usage}"
compression="${6:-zstd}"
domain="${7:-169}"
machine_files=""
for m in "${machines[@]}"; do machine_files+="${machine_files:+, }$here/machines/$m.yaml"; done
work="$(mktemp -d)"
trap 'kill $(jobs -p) 2> /dev/null || true; wait; rm -rf "$work"' EXIT
cat > "$work/plant.yaml" << YAML
plant: recordings
domain_id: $domain
qos_profiles: $here/../../../deploy/qos/ncqual-qos.xml
historian: {database: $work/historian.db}
simulated: true
clock: {mode: simulated, start: "$start"}
scheduler:
  calendar:
    time_zone: UTC
    parts: {cycle_min: 240}
machines: [$machine_files]
YAML
ncqual="$build/services/cli/ncqual"
"$ncqual" record --plant "$work/plant.yaml" --out "$out" --overwrite --compression "$compression" \
  2> "$work/record.log" &
recorder=$!
"$build/services/historian/ncqual-historian" --plant "$work/plant.yaml" 2> "$work/historian.log" &
"$build/services/solver/ncqual-solver" --plant "$work/plant.yaml" 2> "$work/solver.log" &
"$build/services/acquisition/ncqual-acquisition" --plant "$work/plant.yaml" --all \
  2> "$work/acquisition.log" &
"$build/services/scheduler/ncqual-scheduler" --plant "$work/plant.yaml" --days "$days" \
  2> "$work/scheduler.log"
# Every machine's last cycle over in the historian, then every stored result in the recording.
for machine in "${machines[@]}"; do
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
