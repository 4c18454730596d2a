#!/usr/bin/env bash
# Runs docs/scenarios.md's commands as written (the page quotes these lines):
# its complete example (tests/docs/fixtures/swing.json) beside its module in
# build/, a built-in scenario, and the list of them.
#   run_scenarios.sh <repo> <symdyn-sim> <swing_module.so> <scratch dir>
set -euo pipefail
repo=$1 sim=$2 module=$3 scratch=$4
rm -rf "$scratch"
mkdir -p "$scratch/build"
cp "$repo/tests/docs/fixtures/swing.json" "$scratch/"
cp "$module" "$scratch/build/swing_module.so"
PATH=$(dirname "$sim"):$PATH
cd "$scratch"
symdyn-sim swing.json --out results/swing.csv      # a scenario file (*.json, or a path)
symdyn-sim trike                                    # the built-in scenario of a reference model
symdyn-sim --list                                   # the built-in scenarios and their variants

# The example's columns, as the page's Outputs section names them.
head -1 results/swing.csv | grep -q ',rod2.x,rod2.y,rod2.z,spring.length,tip_x$' ||
  { echo "error: swing.csv's header: $(head -1 results/swing.csv)" >&2; exit 1; }
