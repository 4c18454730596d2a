#!/usr/bin/env bash
# Every reference model's emitted code, generated as the build generates it
# (the generator commands of models/ in build/release, each into its own directory of OUT),
# plus chain_64 and the URDF six-DOF arm; to check that a change to the
# engine or the generator leaves the output byte for byte the same:
#
#   bench/build_loop/emitted_snapshot.sh /tmp/before [GENERATOR_DIR]
#   ... change, rebuild the generators ...
#   bench/build_loop/emitted_snapshot.sh /tmp/after && diff -r /tmp/before /tmp/after
#
# GENERATOR_DIR: where to take the generator executables from (a copy of
# the old ones; default: build/release's). Build them first (the
# symdyn_generator_* targets and symdyn-urdf).
set -euo pipefail
cd "$(git -C "$(dirname "$0")" rev-parse --show-toplevel)"
[ $# -ge 1 ] || { sed -n '2,14p' "$0"; exit 2; }
out=$1 generators=${2:-}
build=$PWD/build/release
mkdir -p "$out"
# The build's generator commands: "GENERATOR --out DIR ARGS...".
commands=$(ninja -C "$build" -t commands | grep -o '[^ ]*/models/symdyn_generator_[a-z0-9_]* --out .*$' | sort -u)
commands+=$'\n'"$build/models/symdyn_generator_chain --out chain_64 --basename chain_64 --model chain_64 --variant absolute --sources 4"
commands+=$'\n'"$build/src/codegen/symdyn-urdf --out six_dof_arm --basename six_dof_arm --urdf $PWD/tests/urdf/robots/six_dof_arm.urdf --sources 4"
while read -r generator _ dir args; do
  [ -z "$generators" ] || generator=$generators/$(basename "$generator")
  [ -x "$generator" ] || { echo "emitted_snapshot.sh: $generator is not built" >&2; exit 1; }
  # shellcheck disable=SC2086  # the arguments split into words
  "$generator" --out "$out/$(basename "$dir")" $args >/dev/null
done <<<"$commands"
echo "emitted_snapshot.sh: $(find "$out" -type f | wc -l) files in $out" >&2
