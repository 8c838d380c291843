#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# Installs the Debian 12 packages ncqual builds and runs with, when they are missing.
# Everything comes from Debian's archive; nothing else is downloaded.
# Usage: install-deps.sh [--test]   (--test adds what only the test suite needs: the linters,
#        iproute2 and nftables for the lossy-network test, which impairs a namespace's loopback,
#        LinuxCNC for the test that runs a probing program on a real controller, and Cyclone DDS
#        with its idlc for the test that reads and writes ncqual's topics from another vendor's
#        DDS, tests/interop/cyclone, and systemd for systemd-analyze, which verifies the units of
#        the .deb, tests/package), and node with npm for the independent MCAP reader of the
#        McapInterop.* tests (tests/interop/mcap), SciPy, the independent implementation the trend
#        library's statistics are checked against (tests/unit/trend), and Chromium, the real browser
#        that renders the charts and the dashboard in tests
set -euo pipefail

packages=(
  build-essential cmake ccache pkg-config
  libfastrtps-dev libfastcdr-dev fastddsgen fastdds-tools
  libeigen3-dev libceres-dev libsqlite3-dev sqlite3 libspdlog-dev libfmt-dev
  libyaml-cpp-dev nlohmann-json3-dev libgtest-dev
  libhowardhinnant-date-dev tzdata libcli11-dev libssl-dev libsystemd-dev
  libzstd-dev liblz4-dev zlib1g-dev libboost-math-dev libcpp-httplib-dev
)
if [ "${1:-}" = "--test" ]; then
  packages+=(clang-format-14 clang-tidy-14 iproute2 nftables linuxcnc-uspace
            cyclonedds-dev cyclonedds-tools systemd python3-scipy chromium fonts-dejavu-core)
  # Debian's nodejs and npm, unless a node with its npm is installed already (NodeSource's
  # nodejs package bundles npm and conflicts with Debian's npm package).
  if ! command -v npm > /dev/null; then packages+=(nodejs npm); fi
fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "ncqual: installing Debian packages: ${missing[*]}"
sudo_cmd=""
if [ "$(id -u)" -ne 0 ]; then sudo_cmd="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$sudo_cmd apt-get update -qq
$sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}"
