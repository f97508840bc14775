# What both package tests do first (sourced by package_test.sh and package_cross_test.sh): build the package from a
# build directory with CPack into WORK_DIR and require lintian to report no error.
fail() { echo "package test: $*" >&2; exit 1; }
step() { echo "--- $*"; }

# build_and_lint BUILD_DIR WORK_DIR DEB: DEB is the file CPack must write into WORK_DIR (emptied first).
build_and_lint() {
  local build=$1 work=$2 deb=$3
  step "cpack"
  rm -rf "$work" && mkdir -p "$work"
  (cd "$build" && cpack -G DEB -B "$work" > "$work/cpack.log") || { cat "$work/cpack.log"; fail "cpack failed"; }
  [ -f "$deb" ] || fail "cpack wrote no $deb"
  dpkg-deb -I "$deb"

  step "lintian (errors fail; warnings and notes are shown)"
  local lintian_ok=yes
  lintian --fail-on error --display-info "$deb" > "$work/lintian.log" 2>&1 || lintian_ok=no
  grep -v 'root privileges is not recommended' "$work/lintian.log" || true
  [ "$lintian_ok" = yes ] || fail "lintian reports errors in $deb"
}
