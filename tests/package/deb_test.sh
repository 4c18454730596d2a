#!/usr/bin/env bash
# The Debian package as a user gets it: made from the release build (cpack -G DEB),
# installed with apt-get, the example built and run against /usr, its programs run
# from /usr (programs_test.sh), then removed,
# also when a step fails. Needs root; refuses to run when symdyn is already
# installed, since it would replace that installation and then remove it.
#   deb_test.sh <release build dir> [cmake option]...   (options: as build_example.sh)
set -euo pipefail

build=$(realpath "$1")
shift
here=$(dirname "$(realpath "$0")")
source_dir=$(realpath "$here/../..")
work=$build/package-deb

fail() { echo "error: .deb test: $*" >&2; exit 1; }
installed() { dpkg-query -W -f='${Status}' symdyn 2>/dev/null | grep -q "install ok installed"; }
remove() {
  apt-get purge -y -qq -o DPkg::Lock::Timeout=300 symdyn >/dev/null 2>&1 || true
  ! installed || { echo "error: .deb test: symdyn is still installed: run apt-get purge symdyn" >&2; return 1; }
}

[ "$(id -u)" -eq 0 ] ||
  fail "installing the package needs root (run as root, or set SYMDYN_SKIP_DEB_TEST=1 to skip it)"
! installed || fail "symdyn is already installed here; remove it first (apt-get purge symdyn)"

rm -rf "$work"
mkdir -p "$work"
cpack -G DEB --config "$build/CPackConfig.cmake" -B "$work" >"$work/cpack.log" 2>&1 ||
  { cat "$work/cpack.log"; fail "cpack -G DEB failed"; }
debs=("$work"/symdyn_*.deb)
[ -f "${debs[0]}" ] || fail "cpack made no symdyn_*.deb in $work"
echo "== .deb: $(basename "${debs[0]}"): $(dpkg-deb -f "${debs[0]}" Depends)"

trap 'remove || exit 1' EXIT
DEBIAN_FRONTEND=noninteractive apt-get install -y -qq -o DPkg::Lock::Timeout=300 "${debs[0]}" \
  >"$work/apt.log" 2>&1 || { cat "$work/apt.log"; fail "apt-get install ${debs[0]} failed"; }
bash "$here/build_example.sh" "$source_dir/examples/spinning_top" "$work/example" prefix:/usr "$@"
bash "$here/programs_test.sh" "$source_dir" prefix:/usr "$work/programs"
