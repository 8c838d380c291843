#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The main job: install, build, start the four ncqual services and one simulated machine on a
# private DDS domain, run a qualification cycle (the monthly global check with a laser tracker:
# master frame, grid, rotary C, A and W, circles in XY, YZ and XZ, an ISO 230-2 run of X; daily
# monument checks 1 to 4; the weekly fixture pre-calibration, with its post-calibration when it
# issues zero offsets; the set points of the first part), print a summary, stop everything and
# write the machine's report (docs/report.md) and print where it is. The probe is qualified on the monument before it
# measures the fixture: a bent stylus would otherwise be "corrected" into the fixture's zero
# offsets (patent: the fixture check "is performed only after all of the monument checks have
# been successfully completed").
#
# Usage: deploy/demo.sh [--scenario MACHINE.yaml] [--weeks N [--machines K]] [--domain N] [--secure]
#   --scenario  a machine config whose simulator section injects errors
#               (examples in deploy/scenarios/; default deploy/machines/pm1.yaml)
#   --weeks     instead of one cycle, run N weeks of the plant calendar on a simulated clock
#               (from Monday 5 January 2026, two shifts a day Monday to Friday, Europe/Berlin):
#               the monthly, daily and weekly checks at each shift start and a part every ~4 h,
#               as fast as the services answer; then every machine's status and the trend of
#               the daily checks, and the machine's report (var/.../report-MACHINE.html).
#               Try it with --scenario deploy/scenarios/drift.yaml: the historian's forecast
#               warning on check 3's center_dy_mm is raised on 9 or 12 January, four weeks before
#               the check fails on 9 February (docs/trends.md, "The drift scenario").
#   --machines  with --weeks: a plant of K machines (default 1), the scenario's and K-1 nominal
#               copies of pm1 (pm2, pm3, ...; each its own fixture and seed), all against one
#               scheduler, solver and historian, their instruments in one acquisition process
#   --domain    DDS domain id (default: NCQUAL_DOMAIN, else a random private one in 100..169)
#   --secure    run the plant with DDS Security: deploy/security/ncqual-pki makes (or keeps) the
#               plant CA, governance and one identity per service, acquisition and this host's
#               operator in var/pki, and every process authenticates, encrypts and is held to its
#               role's permissions (docs/deploy.md, "Security")
# Data goes to $NCQUAL_VAR (default var/ at the repository root): the historian database
# var/historian.db, the logs var/log/, the plant config the demo writes var/demo-plant.yaml.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
scenario="$root/deploy/machines/pm1.yaml"
domain="${NCQUAL_DOMAIN:-$((100 + RANDOM % 70))}"
weeks=""
machines=1
secure=""
while [ $# -gt 0 ]; do
  case "$1" in
    --scenario) scenario="$(cd "$(dirname "$2")" && pwd)/$(basename "$2")"; shift 2 ;;
    --domain) domain="$2"; shift 2 ;;
    --weeks) weeks="$2"; shift 2 ;;
    --machines) machines="$2"; shift 2 ;;
    --secure) secure=1; shift ;;
    -h|--help) awk 'NR > 2 && /^#/ { print; next } NR > 2 { exit }' "$0"; exit 0 ;;
    *) echo "demo.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done
[ -f "$scenario" ] || { echo "demo.sh: scenario file '$scenario' not found" >&2; exit 2; }
if [ -n "$weeks" ] && ! [[ "$weeks" =~ ^[1-9][0-9]?$ ]]; then
  echo "demo.sh: --weeks '$weeks': expected a whole number of weeks from 1 to 99" >&2; exit 2
fi
if ! [[ "$machines" =~ ^[1-9][0-9]?$ ]]; then
  echo "demo.sh: --machines '$machines': expected a whole number of machines from 1 to 99" >&2; exit 2
fi
if [ "$machines" -gt 1 ] && [ -z "$weeks" ]; then
  echo "demo.sh: --machines needs --weeks (the one-cycle demo qualifies one machine)" >&2; exit 2
fi

"$root/deploy/install-deps.sh"
echo "== building (Release)"
"$root/deploy/build.sh" --target ncqual-scheduler ncqual-acquisition ncqual-solver \
  ncqual-historian ncqual > /dev/null
bin="${NCQUAL_BUILD_DIR:-$root/build}/services"

var="${NCQUAL_VAR:-$root/var}"
mkdir -p "$var/log"
plant="$var/demo-plant.yaml"
db="$var/historian.db"
machine_id="$(sed -n '/^machine_id:/{s/^machine_id:[[:space:]]*\([^[:space:]#]*\).*/\1/p;q}' "$scenario")"
[ -n "$machine_id" ] || { echo "demo.sh: no machine_id in $scenario" >&2; exit 2; }
if [ -n "$weeks" ]; then
  # A fresh plant history for the simulated weeks, beside the one-cycle demo's.
  var="$var/weeks"
  mkdir -p "$var/log"
  plant="$var/demo-plant.yaml"
  db="$var/historian.db"
  # The simulated weeks start at the same instant each run, so their request ids repeat: the
  # scheduler's, the acquisition's and the solver's state of an earlier run must go with its
  # history (the solver would answer the repeated ids as already solved).
  rm -f "$db" "$db-wal" "$db-shm" "$var/scheduler.db" "$var/scheduler.db-wal" "$var/scheduler.db-shm" \
    "$var"/acquisition-*.db "$var"/acquisition-*.db-wal "$var"/acquisition-*.db-shm \
    "$var/solver.db" "$var/solver.db-wal" "$var/solver.db-shm"
  # The other machines of the plant: nominal pm1s, each with its own fixture and noise.
  rm -rf "$var/machines"
  mkdir -p "$var/machines"
  machine_files=("$scenario")
  for i in $(seq 2 "$machines"); do
    cat > "$var/machines/pm$i.yaml" <<YAML
extends: $root/deploy/machines/pm1.yaml
machine_id: pm$i
fixture: {fixture_id: UHF$i}
simulator: {seed: $((42 + i))}
YAML
    machine_files+=("$var/machines/pm$i.yaml")
  done
  cat > "$plant" <<YAML
# Written by deploy/demo.sh --weeks $weeks
plant: demo
domain_id: $domain
qos_profiles: $root/deploy/qos/ncqual-qos.xml
simulated: true  # its machines are measured by the simulator
historian:
  database: $db
clock: {mode: simulated, start: "2026-01-05T00:00:00Z"}
scheduler:
  state_database: $var/scheduler.db
  calendar:
    time_zone: Europe/Berlin
    shifts:
      - {name: early, start: "06:00", end: "14:00", days: mon-fri}
      - {name: late, start: "14:00", end: "22:00", days: mon-fri}
    # The patent's order: the probe is qualified on the monument before it measures the fixture,
    # so a bent stylus is never "corrected" into the fixture's zero offsets.
    periods:
      - {name: monthly, every: month, checks: [global_master_frame, global_grid, rotary_c,
                                               rotary_a, rotary_w, circle_xy, circle_yz,
                                               circle_xz, linear_axis_run]}
      - {name: daily, every: day, checks: [monument_c_alignment, monument_tool_length,
                                           monument_positioning, monument_c_rotation]}
      - {name: weekly, every: week, checks: [fixture_precal]}
    parts: {checks: [part_setpoints], cycle_min: 220}
machines:
$(printf '  - %s\n' "${machine_files[@]}")
YAML
else
  # The one-cycle demo starts the scheduler afresh: no hold or pending check of an earlier run.
  rm -f "$var/scheduler.db" "$var/scheduler.db-wal" "$var/scheduler.db-shm"
cat > "$plant" <<YAML
# Written by deploy/demo.sh
plant: demo
domain_id: $domain
qos_profiles: $root/deploy/qos/ncqual-qos.xml
simulated: true  # its machines are measured by the simulator
historian:
  database: $db
scheduler:
  startup_checks: [global_master_frame, global_grid, rotary_c, rotary_a, rotary_w, circle_xy,
                   circle_yz, circle_xz, linear_axis_run, monument_c_alignment,
                   monument_tool_length, monument_positioning, monument_c_rotation, fixture_precal,
                   part_setpoints]
machines:
  - $scenario
YAML
fi
acquisition_identity=()
if [ -n "$secure" ]; then
  echo "== DDS Security: the plant's identities in $var/pki (deploy/security/ncqual-pki)"
  NCQUAL_CLI="$bin/cli/ncqual" "$root/deploy/security/ncqual-pki" init --demo --plant "$plant" \
    --out "$var/pki" --operator "$(hostname)" | sed 's/^/   /'
  if [ "$machines" -gt 1 ]; then
    # One acquisition process serves the whole plant here: one identity for all its machines.
    all="$(printf '%s,' "$machine_id" $(seq -f 'pm%g' 2 "$machines"))"
    NCQUAL_CLI="$bin/cli/ncqual" "$root/deploy/security/ncqual-pki" add --demo --out "$var/pki" \
      --role acquisition --name acquisition-plant --machines "${all%,}" | sed 's/^/   /'
    acquisition_identity=(--identity acquisition-plant)
  fi
  echo "security: {dir: $var/pki}" >> "$plant"
  # Peers, not multicast: Fast DDS 2.9 can leave two secured participants that discover others
  # at once unauthenticated for good when discovery is multicast (docs/deploy.md, "Security").
  echo "network: {discovery: peers, peers: [127.0.0.1]}" >> "$plant"
fi
export NCQUAL_PLANT="$plant"
export NCQUAL_DOMAIN="$domain"

pids=()
stop_all() {  # the historian (started first) last: it stores the others' "stopped" heartbeats
  local rest=("${pids[@]:1}")
  for pid in "${rest[@]}"; do kill -TERM "$pid" 2>/dev/null || true; done
  for pid in "${rest[@]}"; do wait "$pid" 2>/dev/null || true; done
  for pid in "${pids[@]:0:1}"; do kill -TERM "$pid" 2>/dev/null || true; wait "$pid" 2>/dev/null || true; done
  pids=()
}
trap stop_all EXIT

start() {  # start NAME ARGS...: a service in the background, its log in var/log/NAME.log
  local name="$1"; shift
  "$bin/$name/ncqual-$name" "$@" > "$var/log/$name.log" 2>&1 &
  pids+=($!)
}

# The machine's report, one self-contained HTML file (docs/report.md); its path is printed.
write_report() {
  local report="$var/report-$machine_id.html"
  "$bin/cli/ncqual" report --machine "$machine_id" "$@" --out "$report" > /dev/null \
    || { echo "demo.sh: the report of $machine_id could not be written" >&2; exit 1; }
  echo
  echo "== the report of $machine_id (open it in a browser; it prints to PDF):"
  echo "   $report"
}

# How to go on from here with the operator's tool, against this run's plant and historian.
look_further() {
  echo
  echo "== to look further (the services are stopped; the historian stays):"
  echo "   export NCQUAL_PLANT=$plant"
  echo "   $bin/cli/ncqual status          # every machine's state and what is due"
  echo "   $bin/cli/ncqual history --machine $machine_id --limit 20"
  echo "   $bin/cli/ncqual config check --print"
  echo "   $bin/web/ncqual-web             # the dashboard: open http://127.0.0.1:8470/ (docs/dashboard.md)"
}

since_ns="$(date +%s%N)"
echo "== starting the services on DDS domain $domain (logs in $var/log)"
start historian
start solver
if [ -n "$weeks" ]; then
  start acquisition --all "${acquisition_identity[@]}"
  if [ "$machines" -gt 1 ]; then
    echo "== $weeks simulated weeks of shifts for $machine_id (scenario $(basename "$scenario")) and pm2..pm$machines"
  else
    echo "== $weeks simulated weeks of shifts for $machine_id (scenario $(basename "$scenario"))"
  fi
  started="$(date +%s)"
  "$bin/scheduler/ncqual-scheduler" --days "$((weeks * 7))" > "$var/log/scheduler.log" 2>&1 \
    || { echo "demo.sh: the scheduler failed; see $var/log/scheduler.log" >&2; exit 1; }
  for id in "$machine_id" $(seq -f 'pm%g' 2 "$machines"); do
    "$bin/cli/ncqual" wait --settled --machine "$id" --timeout 120 > /dev/null \
      || { echo "demo.sh: the historian did not settle for $id; see $var/log" >&2; exit 1; }
  done
  elapsed="$(( $(date +%s) - started ))"
  stop_all
  echo "   $("$bin/cli/ncqual" count) checks of $machines machine(s) stored in ${elapsed} s of wall time"
  echo
  echo "== status (historian $db)"
  "$bin/cli/ncqual" status
  echo
  echo "== the daily checks and the fixture, week by week"
  "$bin/cli/ncqual" trend --machine "$machine_id" --every week
  write_report
  look_further
  exit 0
fi
start acquisition --machine "$machine_id"
start scheduler

echo "== qualification cycle of $machine_id (scenario $(basename "$scenario"))"
state="$("$bin/cli/ncqual" wait --settled --machine "$machine_id" --since-ns "$since_ns" \
  --timeout 120)" \
  || { echo "demo.sh: the cycle did not finish; see $var/log" >&2; exit 1; }
echo "   $machine_id is $state"
if [ "$state" = QUALIFIED ]; then
  echo "== next part loaded: the operator orders its set-point check through the scheduler"
  request="$("$bin/cli/ncqual" check --machine "$machine_id" --kind part_setpoints)"
  "$bin/cli/ncqual" wait --request "$request" --timeout 60 > /dev/null \
    || { echo "demo.sh: operator check not stored; see $var/log" >&2; exit 1; }
fi

stop_all
echo
echo "== summary (historian $db), newest first"
"$bin/cli/ncqual" history --machine "$machine_id" --since-ns "$since_ns"
write_report
look_further
