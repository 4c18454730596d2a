#!/usr/bin/env bash
# symdyn's programs as a user runs them from an installation: from <prefix>/bin
# alone (no build tree on PATH or in the environment), each with --help, --version
# and its man page; symdyn-sim on a built-in scenario and a sweep through the
# installed Python package; symdyn-urdf on a URDF file; symdyn-generate on a
# model file (docs/install.md's commands, as written). The CSV's and the emitted
# header's coordinates carry their names.
#   programs_test.sh <repo> <symdyn> <work dir>
# <symdyn>: install:<symdyn build> (`cmake --install` it into <work dir>/prefix)
# or prefix:<dir> (installed there: /usr for the .deb).
set -euo pipefail
repo=$(realpath "$1") symdyn=$2 work=$3
fail() { echo "error: installed programs: $*" >&2; exit 1; }

rm -rf "$work"
mkdir -p "$work"
case $symdyn in
  install:*)
    cmake --install "${symdyn#install:}" --prefix "$work/prefix" >/dev/null || fail "cmake --install failed"
    prefix=$work/prefix ;;
  prefix:*) prefix=${symdyn#prefix:} ;;
  *) fail "unknown symdyn origin '$symdyn' (install: or prefix:)" ;;
esac
prefix=$(realpath "$prefix")
cd "$work"
# Only the installation: no SYMDYN_SIM, PYTHONPATH or build tree to fall back on.
unset SYMDYN_SIM PYTHONPATH
export PATH=$prefix/bin:/usr/bin:/bin
export XDG_CACHE_HOME=$work/cache

for program in symdyn-sim symdyn-urdf symdyn-generate; do
  [ "$(command -v $program)" = "$prefix/bin/$program" ] || fail "$program is not installed in $prefix/bin"
  $program --help >help.txt || fail "$program --help failed"
  grep -q "Usage: $program" help.txt || fail "$program --help has no usage line: $(head -3 help.txt)"
  $program --version | grep -qx "$program [0-9.]*" || fail "$program --version: $($program --version)"
  page=$prefix/share/man/man1/$program.1
  [ -f "$page" ] || fail "no man page $page"
  # The page renders without a warning and holds the options and the sections added to --help.
  MANWIDTH=100 man --warnings -E UTF-8 -l "$page" >man.txt 2>man_warnings.txt ||
    fail "man -l $page failed: $(cat man_warnings.txt)"
  [ ! -s man_warnings.txt ] || fail "man -l $page warns: $(cat man_warnings.txt)"
  for section in NAME SYNOPSIS DESCRIPTION "SEE ALSO"; do
    grep -q "^$section" man.txt || fail "the man page of $program has no $section"
  done
  grep -q -- "--help" man.txt || fail "the man page of $program does not list --help"
  echo "ok: $program --help, --version, man page ($(wc -l <man.txt) lines)"
done

# docs/install.md's commands (The programs), as written: arm.urdf is the two-link arm.
cp "$repo/tests/urdf/robots/two_link_arm.urdf" arm.urdf
cp "$repo"/examples/spinning_top/spinning_top*.?pp .
{
symdyn-sim --list                                   # the built-in scenarios
symdyn-sim double_pendulum --out pendulum.csv       # one of them: a CSV and a summary with its checks
symdyn-urdf --urdf arm.urdf --out generated         # generated/<robot>_default.hpp and .cpp
symdyn-generate spinning_top.cpp --out generated    # generated/spinning_top_default.hpp and .cpp
} >programs.txt 2>&1 || { cat programs.txt; fail "docs/install.md's commands failed"; }
grep -q "^double_pendulum  *variants: absolute, relative" programs.txt || fail "symdyn-sim --list: $(head -3 programs.txt)"

# The built-in scenario, its CSV's columns named after the model's coordinates and bodies.
head -1 pendulum.csv | grep -q "^t,theta1,theta2,theta1_dot,theta2_dot," || fail "pendulum.csv's header: $(head -1 pendulum.csv)"
[ "$(wc -l <pendulum.csv)" -eq 1002 ] || fail "pendulum.csv has $(wc -l <pendulum.csv) lines, not 1 + 1001"
grep -q "energy drift .* ok$" programs.txt || fail "symdyn-sim double_pendulum's checks: $(grep -i drift programs.txt)"
echo "ok: symdyn-sim double_pendulum: $(head -1 pendulum.csv | cut -c1-60)..."

# A sweep: symdyn-sim runs the installed Python package, which runs the installed symdyn-sim.
cat >sweep.json <<'JSON'
{
  "scenario": "double_pendulum",
  "factors": {"start": {"values": [0.1, 0.2]}},
  "set": {"initial.q.theta1": "start", "t_end": 0.2},
  "keep": {"final": false, "values": {"theta1_end": "end(theta1)"}}
}
JSON
symdyn-sim --sweep sweep.json --workers 1 --out sweep.csv >sweep.txt 2>&1 || { cat sweep.txt; fail "the sweep failed"; }
[ "$(grep -c ',ok,' sweep.csv)" -eq 2 ] || { cat sweep.csv; fail "the sweep did not make 2 runs"; }
# The package alone, from Python: it finds the symdyn-sim installed beside it.
python_dir=$prefix/lib/python3/dist-packages
found=$(PYTHONPATH=$python_dir /usr/bin/python3 -c 'from symdyn.engine import find_program; print(find_program())')
[ "$(realpath "$found")" = "$prefix/bin/symdyn-sim" ] || fail "the Python package runs '$found', not $prefix/bin/symdyn-sim"
echo "ok: a sweep of 2 runs; the Python package finds $found"

# symdyn-urdf: each coordinate is named after its joint.
header=generated/two_link_arm_default.hpp
[ -f generated/two_link_arm_default.cpp ] || fail "symdyn-urdf wrote $(ls generated)"
grep -q 'q_names\[2\] = {"shoulder", "elbow"}' "$header" || fail "$header: $(grep q_names "$header")"
echo "ok: symdyn-urdf: $(basename "$header"), $(grep -o 'q_names.*' "$header")"

# symdyn_add_urdf_model from the installed package runs the installed symdyn-urdf.
mkdir -p urdf_project
cp "$repo/tests/urdf/robots/two_link_arm.urdf" urdf_project/
cat >urdf_project/CMakeLists.txt <<'CMAKE'
cmake_minimum_required(VERSION 3.25)
project(urdf_project LANGUAGES CXX)
find_package(symdyn 0.1 REQUIRED)
symdyn_add_urdf_model(arm two_link_arm.urdf)
add_executable(names names.cpp)
target_link_libraries(names PRIVATE arm)
CMAKE
cat >urdf_project/names.cpp <<'CPP'
#include <cstdio>

#include "arm.hpp"

int main() {
  for (const char* name : symdyn_generated::arm::q_names) std::printf("%s\n", name);
}
CPP
{ cmake -S urdf_project -B urdf_project/build -DCMAKE_PREFIX_PATH="$prefix" &&
    cmake --build urdf_project/build; } >urdf_project.log 2>&1 || { cat urdf_project.log; fail "the URDF project failed"; }
[ "$(urdf_project/build/names | tr '\n' ' ')" = "shoulder elbow " ] ||
  fail "the URDF project's coordinates: $(urdf_project/build/names)"
echo "ok: symdyn_add_urdf_model of the installed package"

# symdyn-generate: a model file's generator built against the installation and run.
symdyn-generate spinning_top.cpp --list | grep -q "spinning_top" || fail "symdyn-generate --list"
grep -q 'q_names\[3\] = {"psi", "theta", "phi"}' generated/spinning_top_default.hpp ||
  fail "generated/spinning_top_default.hpp: $(grep q_names generated/spinning_top_default.hpp)"
set +e
symdyn-generate missing.cpp --out generated 2>error.txt
status=$?
set -e
[ $status -eq 2 ] && grep -q "no model file 'missing.cpp'" error.txt || fail "a missing model file: exit $status, $(cat error.txt)"
echo "ok: symdyn-generate spinning_top.cpp: generated/spinning_top_default.{hpp,cpp}"
