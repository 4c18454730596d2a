#!/usr/bin/env bash
# Runs docs/install.md's commands as written (the page quotes these lines), in
# folders of links to the sources, HOME a scratch folder: its configure line in
# one (configured only: its preset and options checked, the build is this one);
# its build and install lines in another whose build/release is this build
# (built already: nothing left to do), then the example project against that
# installation, and configured with symdyn built along.
#   run_install.sh <repo> <symdyn build dir> <scratch dir>
set -euo pipefail
repo=$(realpath "$1") build=$(realpath "$2") scratch=$3
fail() { echo "error: docs/install.md: $*" >&2; exit 1; }
sources() {  # a folder of links to the sources, without their build folder
  mkdir -p "$1/build"
  for entry in "$repo"/*; do
    [ "$(basename "$entry")" = build ] || ln -s "$entry" "$1/"
  done
}

rm -rf "$scratch"
mkdir -p "$scratch/home"
# The generator and compiler launcher from the environment (CMake reads both), and
# ccache's own cache whatever HOME is, to reuse this build's objects.
export CMAKE_GENERATOR=Ninja
if command -v ccache >/dev/null; then
  export CMAKE_CXX_COMPILER_LAUNCHER=ccache CCACHE_DIR=${CCACHE_DIR:-$(ccache -k cache_dir)}
fi
export HOME=$scratch/home

sources "$scratch/configured"
cd "$scratch/configured"
{
cmake --preset release -DSYMDYN_BUILD_TESTS=OFF -DSYMDYN_BUILD_BENCH=OFF
} >configure.log 2>&1 || { cat configure.log; fail "the configure line failed"; }
! grep -q "not used by the project" configure.log || fail "$(grep -A4 "not used by the project" configure.log)"
grep -qx "SYMDYN_BUILD_TESTS:BOOL=OFF" build/release/CMakeCache.txt || fail "the tests are still on"

sources "$scratch/sources"
ln -s "$build" "$scratch/sources/build/release"
cd "$scratch/sources"
{
cmake --build --preset release
} >build.log 2>&1 || { cat build.log; fail "the build line failed"; }
grep -qx "ninja: no work to do." build.log || fail "$build was not up to date: build it before its tests"
{
cmake --install build/release --prefix "$HOME/.local"   # or /usr/local as root
} >install.log 2>&1 || { cat install.log; fail "the install line failed"; }
export PATH="$HOME/.local/bin:$PATH"   # man then finds their pages too
[ "$(command -v symdyn-sim)" = "$HOME/.local/bin/symdyn-sim" ] || fail "symdyn-sim is not in ~/.local/bin"
[ "$(man -w symdyn-sim)" = "$HOME/.local/share/man/man1/symdyn-sim.1" ] || fail "man finds $(man -w symdyn-sim)"

# The example project against symdyn installed under ~/.local; then configured
# with symdyn built along (built by the package test "example with symdyn built along").
{
cmake -S examples/spinning_top -B build/top -DCMAKE_PREFIX_PATH="$HOME/.local"
cmake --build build/top
} >example.log 2>&1 || { cat example.log; fail "building the example failed"; }
./build/top/spinning_top_simulation
rm -rf build/top
{
cmake -S examples/spinning_top -B build/top -DSYMDYN_SOURCE_DIR="$PWD"
} >along.log 2>&1 || { cat along.log; fail "configuring the example with symdyn built along failed"; }
grep -qx "SYMDYN_SOURCE_DIR:PATH=$PWD" build/top/CMakeCache.txt || fail "SYMDYN_SOURCE_DIR is not $PWD"
