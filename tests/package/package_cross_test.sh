#!/usr/bin/env bash
# Issue 23's package test of a cross build (the arm64 package, on the build machine): builds it with CPack, requires
# lintian to report no error, the target's architecture, programs for the target's machine, the conffiles, and a
# Depends that names the package of every shared library the programs load — dpkg-shlibdeps resolves them in the
# sysroot (.ci/arm64-sysroot gathers the packages' symbols and shlibs files in its DEBIAN/), and CPack runs it with
# --ignore-missing-info, so a library it could not place would silently be left out. Then the packaged programs
# run from the unpacked package under the emulator.
#   package_cross_test.sh BUILD_DIR WORK_DIR VERSION DEB_ARCH ELF_MACHINE SYSROOT EMULATOR...
set -euo pipefail
build=$1 work=$2 version=$3 arch=$4 machine=$5 sysroot=$6
shift 6
emulator=("$@")
deb=$work/vifusion_${version}_${arch}.deb

source "$(dirname "${BASH_SOURCE[0]}")/package_common.sh"

build_and_lint "$build" "$work" "$deb"
[ "$(dpkg-deb -f "$deb" Architecture)" = "$arch" ] || fail "$deb is for $(dpkg-deb -f "$deb" Architecture), not $arch"

step "contents"
root=$work/root
dpkg-deb -x "$deb" "$root"
dpkg-deb --ctrl-tarfile "$deb" | tar -xO ./conffiles > "$work/conffiles"
for file in /etc/vifusion/vifusiond.yaml /etc/vifusion/cyclonedds.xml; do
  [ -f "$root$file" ] || fail "$deb has no $file"
  grep -qx "$file" "$work/conffiles" || fail "$file is not a conffile of $deb"
done
for unit in vifusiond vifusion-health; do
  [ -f "$root/lib/systemd/system/$unit.service" ] || fail "$deb has no $unit.service"
done

step "Depends covers every library the programs load"
depends=$(dpkg-deb -f "$deb" Depends)
echo "Depends: $depends"
depends_names=$(tr ',' '\n' <<< "$depends" | awk '{ print $1 }')
for program in vifusion vifusiond vifusion-health; do
  elf=$root/usr/bin/$program
  [ "$(readelf -h "$elf" | awk -F: '/Machine:/ { gsub(/^ +/, "", $2); print $2 }')" = "$machine" ] ||
    fail "/usr/bin/$program is not built for $machine"
  for soname in $(readelf -d "$elf" | sed -n 's/.*Shared library: \[\(.*\)\]/\1/p'); do
    # symbols files: "libfoo.so.1 libfoo1 #MINVER#"; shlibs files: "libfoo 1 libfoo1 (>= 1.0)".
    package=$(awk -v s="$soname" '$1 == s { print $2; exit }' "$sysroot/DEBIAN/symbols")
    if [ -z "$package" ]; then
      name=${soname%%.so.*} soversion=${soname##*.so.}
      package=$(awk -v n="$name" -v v="$soversion" '$1 == n && $2 == v { print $3; exit }' "$sysroot/DEBIAN/shlibs")
    fi
    [ -n "$package" ] || fail "$soname (loaded by /usr/bin/$program) belongs to no package of the sysroot"
    grep -qxF "$package" <<< "$depends_names" || fail "Depends lacks $package, which ships $soname"
  done
done

step "the packaged programs run (under the emulator)"
for program in vifusion vifusiond vifusion-health; do
  [ "$("${emulator[@]}" "$root/usr/bin/$program" --version)" = "$program $version" ] ||
    fail "the packaged $program --version is not '$program $version'"
done
"${emulator[@]}" "$root/usr/bin/vifusiond" --config "$root/etc/vifusion/vifusiond.yaml" --dump-config > /dev/null ||
  fail "the packaged vifusiond does not load the packaged configuration"
echo "package test: vifusion_${version}_${arch}.deb built, lintian-clean (no errors), Depends complete, programs run"
