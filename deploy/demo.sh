#!/usr/bin/env bash
# The main job: install, build, start the four ncqual services and one simulated machine on a
# private DDS domain, run a qualification cycle (the monthly global check with a laser tracker:
# master frame, grid, rotary C, A and W, circles in XY, YZ and XZ, an ISO 230-2 run of X; daily
# monument checks 1 to 4; the weekly fixture pre-calibration, with its post-calibration when it
# issues zero offsets; the set points of the first part), print a summary, stop everything. The probe is qualified on the monument before it
# measures the fixture: a bent stylus would otherwise be "corrected" into the fixture's zero
# offsets (patent: the fixture check "is performed only after all of the monument checks have
# been successfully completed").
#
# Usage: deploy/demo.sh [--scenario MACHINE.yaml] [--domain N] [--keep-logs]
#   --scenario  a machine config whose simulator section injects errors
#               (examples in deploy/scenarios/; default deploy/machines/pm1.yaml)
#   --domain    DDS domain id (default: NCQUAL_DOMAIN, else a random private one in 100..199)
# Data goes to $NCQUAL_VAR (default var/ at the repository root): the historian database
# var/historian.db, the logs var/log/, the plant config the demo writes var/demo-plant.yaml.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
scenario="$root/deploy/machines/pm1.yaml"
domain="${NCQUAL_DOMAIN:-$((100 + RANDOM % 100))}"
while [ $# -gt 0 ]; do
  case "$1" in
    --scenario) scenario="$(cd "$(dirname "$2")" && pwd)/$(basename "$2")"; shift 2 ;;
    --domain) domain="$2"; shift 2 ;;
    -h|--help) sed -n '2,16p' "$0"; exit 0 ;;
    *) echo "demo.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done
[ -f "$scenario" ] || { echo "demo.sh: scenario file '$scenario' not found" >&2; exit 2; }

"$root/deploy/install-deps.sh"
echo "== building (Release)"
"$root/deploy/build.sh" --target ncqual-scheduler ncqual-acquisition ncqual-solver \
  ncqual-historian ncqual > /dev/null
bin="${NCQUAL_BUILD_DIR:-$root/build}/services"

var="${NCQUAL_VAR:-$root/var}"
mkdir -p "$var/log"
plant="$var/demo-plant.yaml"
db="$var/historian.db"
machine_id="$(sed -n 's/^machine_id:[[:space:]]*\([^[:space:]#]*\).*/\1/p' "$scenario" | head -n1)"
[ -n "$machine_id" ] || { echo "demo.sh: no machine_id in $scenario" >&2; exit 2; }
cat > "$plant" <<YAML
# Written by deploy/demo.sh
plant: demo
domain_id: $domain
qos_profiles: $root/deploy/qos/ncqual-qos.xml
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
export NCQUAL_PLANT="$plant"
export NCQUAL_DOMAIN="$domain"

pids=()
stop_all() {
  for pid in "${pids[@]}"; do kill -TERM "$pid" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do wait "$pid" 2>/dev/null || true; done
  pids=()
}
trap stop_all EXIT

start() {  # start NAME ARGS...: a service in the background, its log in var/log/NAME.log
  local name="$1"; shift
  "$bin/$name/ncqual-$name" "$@" > "$var/log/$name.log" 2>&1 &
  pids+=($!)
}

since_ns="$(date +%s%N)"
echo "== starting the services on DDS domain $domain (logs in $var/log)"
start historian
start solver
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
