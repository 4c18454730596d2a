#!/usr/bin/env bash
# Sets up, builds and runs every test. Exits non-zero on any failure.
# After the release tests, the Debian package: built, installed, used by the
# example against /usr and removed (tests/package/deb_test.sh; needs root,
# SYMDYN_SKIP_DEB_TEST=1 skips it). With CI=true it also builds and runs the
# tests under ASan and UBSan (preset debug).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib/setup.sh
symdyn_require_packages "${symdyn_base_packages[@]}"
symdyn_require_command npm npm            # bundles the HTML viewer
symdyn_require_command chromium chromium  # opens it in the viewer test
symdyn_require_command gnuplot gnuplot-nox  # plots the pictures of the docs (tests/docs)

# ccache serves the debug build and the package tests (which rebuild symdyn's
# libraries as a consumer would) from the objects already compiled.
# Its keys hold paths relative to the sources (base_dir), so that the package
# tests' own builds of the libraries find this build's objects.
launcher=()
if command -v ccache >/dev/null 2>&1; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  export CCACHE_BASEDIR=${CCACHE_BASEDIR:-$PWD}
fi

jobs=$(nproc)
run_preset() {
  local preset=$1
  echo "== symdyn: configure, build and test ($preset)"
  cmake --preset "$preset" -DSYMDYN_WERROR=ON "${launcher[@]}" >/dev/null
  cmake --build --preset "$preset" -j "$jobs"
  ctest --preset "$preset" -j "$jobs"
}

run_preset release
if [ "${SYMDYN_SKIP_DEB_TEST:-}" = "1" ]; then
  echo "== symdyn: Debian package test skipped (SYMDYN_SKIP_DEB_TEST=1)"
else
  echo "== symdyn: Debian package (install, build the example against /usr, remove)"
  tests/package/deb_test.sh -G Ninja -DCMAKE_BUILD_TYPE=Release -DSYMDYN_WERROR=ON "${launcher[@]}"
fi
if [ "${CI:-}" = "true" ]; then
  run_preset debug
fi
