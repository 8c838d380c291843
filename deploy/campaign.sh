#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# A longer fault campaign than the test suite's, run by hand: the real services on a simulated
# plant, killed (SIGKILL) at random points alone and in pairs and restarted, compared with the
# undisturbed run of the same seed (tests/integration/test_campaign.cpp). Prints
# "checks N, kills K, lost L, duplicated D, conflicts C" and exits non-zero unless nothing was lost
# or duplicated. Installs and builds what it needs, as deploy/test.sh does.
#
# Usage: deploy/campaign.sh [--machines N] [--days N] [--kills N] [--seed N] [--keep]
#   defaults: 20 machines, 28 simulated days, 60 kills, a random seed (printed: pass it again to
#   repeat a campaign). --keep leaves the plants' directories (logs, databases) in /tmp.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
machines=20 days=28 kills=60 seed="" keep=""
usage() { sed -n '9,12p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//' >&2; exit 2; }
number() { [[ "$2" =~ ^[1-9][0-9]*$ ]] || { echo "campaign.sh: $1 '$2' is not a positive integer" >&2; exit 2; }; }
while [ $# -gt 0 ]; do
  case "$1" in
    --machines) number "$1" "${2:-}"; machines="$2"; shift 2 ;;
    --days) number "$1" "${2:-}"; days="$2"; shift 2 ;;
    --kills) number "$1" "${2:-}"; kills="$2"; shift 2 ;;
    --seed) number "$1" "${2:-}"; seed="$2"; shift 2 ;;
    --keep) keep=1; shift ;;
    -h|--help) usage ;;
    *) echo "campaign.sh: unknown argument '$1'" >&2; usage ;;
  esac
done
if [ "$kills" -lt 12 ]; then
  echo "campaign.sh: --kills $kills: each of the four services is killed at least 3 times (>= 12)" >&2
  exit 2
fi
"$root/deploy/install-deps.sh" --test
"$root/deploy/build.sh" --target ncqual_integration_tests
build="${NCQUAL_BUILD_DIR:-$root/build}"
export NCQUAL_CAMPAIGN_MACHINES="$machines" NCQUAL_CAMPAIGN_DAYS="$days"
export NCQUAL_CAMPAIGN_KILLS="$kills"
[ -n "$seed" ] && export NCQUAL_CAMPAIGN_SEED="$seed"
[ -n "$keep" ] && export NCQUAL_KEEP_TEST_DIRS=1
exec "$build/tests/integration/ncqual_integration_tests" --gtest_filter='FaultCampaign.*'
