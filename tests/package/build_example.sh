#!/usr/bin/env bash
# Builds and runs the example project (examples/spinning_top) as a user would.
#   build_example.sh <example dir> <build dir> <symdyn> [cmake option]...
# <symdyn> says where symdyn comes from:
#   install:<symdyn build> `cmake --install` it into <build dir>/symdyn-prefix, then find_package
#   prefix:<dir>          find_package of symdyn installed under <dir> (/usr for the .deb)
#   source:<source dir>   built along with the example (SYMDYN_SOURCE_DIR, FetchContent)
# The options go to the example's configure step (generator, build type, launcher).
# Exits non-zero, saying which step failed, if any step or the example's own checks fail.
set -euo pipefail

example=$1 build=$2 symdyn=$3
shift 3

fail() { echo "error: $*" >&2; exit 1; }

symdyn_options() {
  case $symdyn in
    install:*)
      cmake --install "${symdyn#install:}" --prefix "$build/symdyn-prefix" >/dev/null ||
        fail "cmake --install ${symdyn#install:} failed"
      echo "-DCMAKE_PREFIX_PATH=$build/symdyn-prefix" ;;
    prefix:*) echo "-DCMAKE_PREFIX_PATH=${symdyn#prefix:}" ;;
    source:*) echo "-DSYMDYN_SOURCE_DIR=${symdyn#source:}" ;;
    *) fail "unknown symdyn origin '$symdyn' (install:, prefix: or source:)" ;;
  esac
}

rm -rf "$build"
mkdir -p "$build"
origin=$(symdyn_options)
echo "== example: configure with $origin"
cmake -S "$example" -B "$build" "$origin" "$@" >"$build/configure.log" 2>&1 ||
  { cat "$build/configure.log"; fail "configuring the example failed ($symdyn)"; }
echo "== example: build"
cmake --build "$build" || fail "building the example failed ($symdyn)"
echo "== example: run"
"$build/spinning_top_simulation" || fail "the example's checks failed ($symdyn)"
