#!/usr/bin/env bash
# The Debian package as a user gets it, with docs/install.md's commands as written
# (the page quotes these lines): the release preset configured and built (already
# built: nothing left to do), the package made (cpack -G DEB), installed with apt-get,
# the example built and run against /usr, its programs run from /usr
# (programs_test.sh), then removed, also when a step fails. Needs root; refuses to
# run when symdyn is already installed, since it would replace that installation
# and then remove it.
#   deb_test.sh [cmake option]...   (options: as build_example.sh)
set -euo pipefail

here=$(dirname "$(realpath "$0")")
source_dir=$(realpath "$here/../..")
work=$source_dir/build/release/package

fail() { echo "error: .deb test: $*" >&2; exit 1; }
installed() { dpkg-query -W -f='${Status}' symdyn 2>/dev/null | grep -q "install ok installed"; }
remove() {
  apt-get purge -y -qq symdyn >/dev/null 2>&1 || true
  ! installed || { echo "error: .deb test: symdyn is still installed: run apt-get purge symdyn" >&2; return 1; }
}

[ "$(id -u)" -eq 0 ] ||
  fail "installing the package needs root (run as root, or set SYMDYN_SKIP_DEB_TEST=1 to skip it)"
! installed || fail "symdyn is already installed here; remove it first (apt-get purge symdyn)"

cd "$source_dir"
rm -rf "$work"
{
cmake --preset release && cmake --build --preset release
cpack -G DEB --config build/release/CPackConfig.cmake -B build/release/package
} >"$source_dir/build/release/package-deb.log" 2>&1 ||
  { cat "$source_dir/build/release/package-deb.log"; fail "building or packaging failed"; }
deb=build/release/package/symdyn_0.1.0_amd64.deb
[ -f $deb ] || fail "cpack made $(ls "$work"/*.deb), not the $(basename $deb) docs/install.md names"
echo "== .deb: $(basename $deb): $(dpkg-deb -f $deb Depends)"

# apt-get waits for another apt-get to finish rather than failing.
export DEBIAN_FRONTEND=noninteractive APT_CONFIG=$work/apt.conf
echo 'DPkg::Lock::Timeout "300";' >"$APT_CONFIG"
trap 'remove || exit 1' EXIT
{
apt-get install -y ./build/release/package/symdyn_0.1.0_amd64.deb   # as root
} >"$work/apt.log" 2>&1 || { cat "$work/apt.log"; fail "apt-get install $deb failed"; }
bash "$here/build_example.sh" "$source_dir/examples/spinning_top" "$work/example" prefix:/usr "$@"
bash "$here/programs_test.sh" "$source_dir" prefix:/usr "$work/programs"
