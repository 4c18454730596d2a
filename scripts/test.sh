#!/usr/bin/env bash
# Sets up, builds and runs every test. Exits non-zero on any failure.
# With CI=true it also builds and runs the tests under ASan and UBSan (preset debug).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib/setup.sh
symdyn_require_packages "${symdyn_base_packages[@]}"
symdyn_require_command npm npm            # bundles the HTML viewer
symdyn_require_command chromium chromium  # opens it in the viewer test

jobs=$(nproc)
run_preset() {
  local preset=$1
  echo "== symdyn: configure, build and test ($preset)"
  cmake --preset "$preset" -DSYMDYN_WERROR=ON >/dev/null
  cmake --build --preset "$preset" -j "$jobs"
  ctest --preset "$preset" -j "$jobs"
}

run_preset release
if [ "${CI:-}" = "true" ]; then
  run_preset debug
fi
