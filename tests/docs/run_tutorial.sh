#!/usr/bin/env bash
# Does what docs/tutorial.md says, as written: symdyn installed under
# $HOME/.local (HOME a scratch folder), then from an empty folder the files of
# the page and its `sh run` commands, in order.
#   run_tutorial.sh <repo> <symdyn build dir> <scratch dir>
set -euo pipefail
repo=$1 build=$2 scratch=$3
rm -rf "$scratch"
mkdir -p "$scratch/home"
export HOME=$scratch/home
cmake --install "$build" --prefix "$HOME/.local" >/dev/null
# The page's commands as a user types them; the generator and compiler launcher
# come from the environment (CMake reads both), to reuse this build's objects.
export CMAKE_GENERATOR=Ninja
command -v ccache >/dev/null && export CMAKE_CXX_COMPILER_LAUNCHER=ccache
python3 "$repo/tests/docs/code_blocks.py" script "$repo" docs/tutorial.md > "$scratch/tutorial.sh"
cd "$scratch"
bash "$scratch/tutorial.sh"

cd "$scratch/spinning_top"
# The scenario's CSV names the columns after the model's coordinates.
head -1 top.csv | grep -q "^t,psi,theta,phi,psi_dot,theta_dot,phi_dot," ||
  { echo "error: top.csv's header: $(head -1 top.csv)" >&2; exit 1; }
# The viewer plots the coordinates under their names.
"$HOME/.local/bin/symdyn-sim" top.json --out top_viewed.csv --html top.html >/dev/null
grep -q '"names":\["t","psi","theta","phi"\]' top.html ||
  { echo "error: top.html's series: $(grep -o '"names":[^]]*]' top.html)" >&2; exit 1; }
# A coordinate the model does not have is refused, the model's own named.
status=0
"$HOME/.local/bin/symdyn-sim" top.json --set initial.q.q0=1 2>refused.txt >/dev/null || status=$?
[ $status -eq 2 ] && grep -q "'q0'.*psi, theta.*phi" refused.txt ||
  { echo "error: initial.q.q0 on the top: exit $status, $(cat refused.txt)" >&2; exit 1; }
# The emitted code is compiled optimized though the page gives no build type,
# and a project's own -O is left alone (cmake/SymdynAddModel.cmake).
emitted_flags() {  # the command that compiles the emitted source in build folder $1
  ninja -C "$1" -t commands spinning_top | grep "generated/spinning_top/spinning_top.cpp"
}
emitted_flags build | grep -q -- " -O2 " ||
  { echo "error: the emitted code is compiled without -O2: $(emitted_flags build)" >&2; exit 1; }
cmake -B build_own_flags -DCMAKE_PREFIX_PATH="$HOME/.local" -DCMAKE_CXX_FLAGS=-O1 >/dev/null
! emitted_flags build_own_flags | grep -q -- "-O2" ||
  { echo "error: -O2 overrides the project's -O1: $(emitted_flags build_own_flags)" >&2; exit 1; }
echo "ok: the emitted code compiled with -O2 without a build type, the project's -O1 alone with it"
