#!/usr/bin/env bash
# Issue 23's package test, on the machine itself (CI's, as root): builds the Debian package from the build
# directory with CPack, requires lintian to report no error, installs it with apt, runs the installed programs
# the way the units do, verifies the installed units, then purges it and requires that nothing of it is left.
#   package_test.sh BUILD_DIR WORK_DIR VERSION CHECK_SYSTEMD_FILES
# Exit 77 (skipped) when not root: installing a package needs it.
set -euo pipefail
build=$1 work=$2 version=$3 check_units=$4
arch=$(dpkg --print-architecture)
deb=$work/vifusion_${version}_${arch}.deb

source "$(dirname "${BASH_SOURCE[0]}")/package_common.sh"

if [ "$(id -u)" -ne 0 ]; then
  echo "package test: needs root (it installs and purges the package); skipped"
  exit 77
fi
if dpkg-query -W -f='${Status}' vifusion 2> /dev/null | grep -q 'ok installed'; then
  fail "vifusion is already installed here; this test installs and purges it: purge it first (dpkg -P vifusion)"
fi

build_and_lint "$build" "$work" "$deb"

# From here on a failure must not leave the package installed.
trap 'dpkg -P vifusion > /dev/null 2>&1 || true' EXIT

step "apt install"
apt-get install -y --no-install-recommends "$deb" > "$work/apt.log" 2>&1 || { cat "$work/apt.log"; fail "apt install failed"; }
dpkg -L vifusion > "$work/files.txt"

step "installed programs"
for program in vifusion vifusiond vifusion-health; do
  [ "$(/usr/bin/$program --version)" = "$program $version" ] || fail "/usr/bin/$program --version is not '$program $version'"
done
/usr/bin/vifusion selfcheck --frames 2 || fail "/usr/bin/vifusion selfcheck failed"
# The units' own command lines: the shipped configuration must load as it is.
/usr/bin/vifusiond --config /etc/vifusion/vifusiond.yaml --dump-config > "$work/vifusiond.yaml" ||
  fail "vifusiond --config /etc/vifusion/vifusiond.yaml --dump-config failed"
grep -q '^source:' "$work/vifusiond.yaml" || fail "vifusiond --dump-config printed no 'source:'"
/usr/bin/vifusion-health --config /etc/vifusion/vifusiond.yaml --dump-config > /dev/null ||
  fail "vifusion-health --config /etc/vifusion/vifusiond.yaml --dump-config failed"

step "what postinst set up"
getent passwd vifusion > /dev/null || fail "postinst created no user vifusion (sysusers.d)"
for dir in /var/lib/vifusion /var/log/vifusion; do
  [ "$(stat -c %U:%a "$dir")" = vifusion:750 ] || fail "$dir is $(stat -c %U:%a "$dir"), not vifusion:750 (tmpfiles.d)"
done
conffiles=$(dpkg-query -W -f='${Conffiles}' vifusion)
for file in /etc/vifusion/vifusiond.yaml /etc/vifusion/cyclonedds.xml; do
  grep -q " $file " <<< "$conffiles" || fail "$file is not a conffile"
done
for unit in vifusiond vifusion-health; do
  [ "$(systemctl is-enabled "$unit.service" 2> /dev/null || true)" != enabled ] || fail "$unit.service was enabled"
done

step "installed units"
for unit in vifusiond vifusion-health; do
  $check_units verify "/lib/systemd/system/$unit.service" || fail "systemd-analyze verify $unit.service"
done

step "purge"
# State the service would have written: purge removes it too.
touch /var/lib/vifusion/map.vfm /var/log/vifusion/report.json
dpkg -P vifusion > "$work/purge.log" 2>&1 || { cat "$work/purge.log"; fail "dpkg -P vifusion failed"; }
trap - EXIT
left=()
while read -r path; do
  [ -e "$path" ] && [ ! -d "$path" ] && left+=("$path")
done < "$work/files.txt"
for dir in /etc/vifusion /var/lib/vifusion /var/log/vifusion /usr/share/doc/vifusion; do
  [ -e "$dir" ] && left+=("$dir")
done
[ "${#left[@]}" -eq 0 ] || fail "left after dpkg -P: ${left[*]}"
! dpkg-query -W -f='${Status}' vifusion 2> /dev/null | grep -q 'ok installed' || fail "dpkg still lists vifusion"
echo "package test: vifusion_${version}_${arch}.deb built, lintian-clean (no errors), installed, run, purged clean"
