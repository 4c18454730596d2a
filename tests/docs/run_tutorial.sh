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
