#!/usr/bin/env bash
# SPDX-License-Identifier: Apache-2.0
# The .deb that cpack makes from the build (CMakeLists.txt's install rules): its files, its
# dependencies, its maintainer scripts, its systemd units as systemd-analyze verifies them against
# this host's units, and its executables run from the unpacked package.
# Usage: check_deb.sh BUILD_DIR SOURCE_DIR. Exit 77 (skipped, ctest says so) without
# systemd-analyze or dpkg-deb.
set -euo pipefail
build="$(cd "$1" && pwd)"
source="$2"
for tool in dpkg-deb systemd-analyze cpack; do
  command -v "$tool" > /dev/null || { echo "SKIPPED: $tool is not installed"; exit 77; }
done
# Beside the build (its disk had room for the build), not in /tmp, which may be small.
work="$(mktemp -d "$build/package-check.XXXXXX")"
trap 'rm -rf "$work"' EXIT
fail() {
  echo "FAIL: $*"
  echo "(free space where the package was made: $(df -h --output=avail "$work" | tail -1))"
  exit 1
}

(cd "$build" && cpack -G DEB -B "$work/out" > "$work/cpack.log" 2>&1) || { cat "$work/cpack.log"; fail "cpack"; }
deb="$(ls "$work"/out/ncqual_*_amd64.deb 2> /dev/null || ls "$work"/out/ncqual_*.deb)"
echo "package: $(basename "$deb"), $(du -k "$deb" | cut -f1) KiB"

depends="$(dpkg-deb -f "$deb" Depends)"
for d in libfastrtps2.9 libfastcdr1 libsqlite3-0 libsystemd0 openssl; do
  [[ "$depends" == *"$d"* ]] || fail "Depends lacks $d: $depends"
done
# The list whole, then searched: `tar | grep -q` under pipefail fails when grep stops reading
# early and tar dies of SIGPIPE (seen: "no postinst" in one clean run of several).
control="$(dpkg-deb --ctrl-tarfile "$deb" | tar -tf -)"
grep -qx './postinst' <<< "$control" || fail "no postinst in the control files: $control"
[ "$(dpkg-deb --ctrl-tarfile "$deb" | tar -xOf - ./conffiles)" = \
  "$(cat "$source/deploy/systemd/conffiles")" ] || fail "conffiles differ from deploy/systemd/conffiles"

root="$work/root"
dpkg-deb -x "$deb" "$root"
for f in usr/bin/ncqual usr/bin/ncqual-historian usr/bin/ncqual-solver usr/bin/ncqual-scheduler \
  usr/bin/ncqual-acquisition usr/bin/ncqual-recorder usr/bin/ncqual-web usr/bin/ncqual-pki \
  usr/share/ncqual/qos/ncqual-qos.xml usr/lib/systemd/system/ncqual-web.service \
  usr/share/ncqual/idl/ncqual.idl usr/lib/sysusers.d/ncqual.conf etc/ncqual/plant.yaml \
  etc/ncqual/machines/pm1.yaml usr/lib/systemd/system/ncqual.target \
  usr/lib/systemd/system/ncqual-.service.d/10-ncqual.conf \
  usr/lib/systemd/system/ncqual-discovery.service \
  usr/lib/systemd/system/ncqual-discovery.service.d/20-not-notify.conf; do
  [ -e "$root/$f" ] || fail "/$f is not in the package"
done
# The plant file the package installs names the QoS profiles where the package puts them.
grep -q '^qos_profiles: /usr/share/ncqual/qos/ncqual-qos.xml' "$root/etc/ncqual/plant.yaml" \
  || fail "/etc/ncqual/plant.yaml does not name /usr/share/ncqual/qos/ncqual-qos.xml"

# The units, verified as on a host with the package installed: this host's units beside them.
units="$root/usr/lib/systemd/system"
# ncqual-discovery.service runs the recommended fastdds-tools' server: where this host has it,
# beside the package's programs (verify checks that ExecStart's program is there).
if [ -x /usr/bin/fast-discovery-server ]; then
  cp /usr/bin/fast-discovery-server "$root/usr/bin/"
fi
for u in /lib/systemd/system/*; do [ -e "$units/$(basename "$u")" ] || cp -a "$u" "$units/"; done
for unit in ncqual-historian.service ncqual-solver.service ncqual-scheduler.service \
  ncqual-acquisition@pm1.service ncqual-discovery.service ncqual-recorder.service \
  ncqual-web.service ncqual.target; do
  said="$(systemd-analyze --root="$root" verify "$units/${unit/@pm1/@}" 2>&1 \
    | sed "s|$units/||")" || fail "$unit: $said"
  [ -z "$said" ] || fail "$unit: systemd-analyze verify says: $said"
  echo "verified $unit"
done
# The hardening is the shared drop-in (ncqual-.service.d): rated as systemd applies it to each
# unit, every one must come out below 5 ("OK" or better; without the drop-in about 9.6, "UNSAFE").
for unit in ncqual-historian.service ncqual-solver.service ncqual-scheduler.service \
  ncqual-acquisition@pm1.service ncqual-discovery.service ncqual-recorder.service \
  ncqual-web.service; do
  rating="$(systemd-analyze --root="$root" --offline=yes security "$units/${unit/@pm1/@}" 2>&1 \
    | tail -1)"
  echo "$rating"
  exposure="$(echo "$rating" | sed -n 's/.*: \([0-9.]*\) .*/\1/p')"
  if [ -z "$exposure" ] || ! awk -v e="$exposure" 'BEGIN { exit !(e < 5) }'; then
    fail "$unit: $rating"
  fi
done

# The packaged executables run (their libraries are this host's Debian packages).
for exe in ncqual ncqual-historian ncqual-solver ncqual-scheduler ncqual-acquisition ncqual-recorder \
  ncqual-web; do
  "$root/usr/bin/$exe" --version > "$work/version" 2>&1 || fail "$exe --version: $(cat "$work/version")"
  echo "ran $(head -1 "$work/version")"
done
# The installed example plant does not simulate unnoticed: its machine has no instrument: section
# and the plant does not say `simulated: true`, so it is refused (exit 4) naming pm1 and the way
# out (docs/deploy.md, "Installing").
said="$("$root/usr/bin/ncqual" config check --plant "$root/etc/ncqual/plant.yaml" 2>&1)" && status=0 \
  || status=$?
[ "$status" = 4 ] || fail "config check of the installed plant: exit $status, expected 4: $said"
for part in "machine 'pm1'" "has no instrument: section" "say \`simulated: true\` in the plant"; do
  [[ "$said" == *"$part"* ]] || fail "config check of the installed plant does not say $part: $said"
done
echo "the installed plant is refused until pm1 has an instrument"
echo "PASS"
