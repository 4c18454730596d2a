#!/usr/bin/env bash
# Runs docs/urdf.md's command line as written (the page quotes it), from a
# folder whose tests/ is the repository's.
#   run_symdyn_urdf.sh <repo> <symdyn-urdf> <scratch dir>
set -euo pipefail
repo=$1 generator=$2 scratch=$3
rm -rf "$scratch"
mkdir -p "$scratch"
ln -s "$repo/tests" "$scratch/tests"
PATH=$(dirname "$generator"):$PATH
cd "$scratch"
symdyn-urdf --urdf tests/urdf/robots/six_dof_arm.urdf --out generated --basename arm --stats

# The header and its struct, as the page names them.
grep -q "struct arm" generated/arm.hpp || { echo "error: generated/arm.hpp has no struct arm" >&2; exit 1; }
