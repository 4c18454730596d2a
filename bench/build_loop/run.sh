#!/usr/bin/env bash
# The edit-build-run loop of big models: generate the emitted code and compile
# it as symdyn_add_model does (each source file its own compiler run, two at
# a time as `make -j2`/ninja on two cores), timed as a whole over repeated
# runs (median wall and CPU seconds); then the instructions per call of the
# emitted dynamics under callgrind (repeatable where times are not).
#
#   bench/build_loop/run.sh [--runs N] [--calls N] [--jobs N] [--results FILE]
#                           [--cases 'amru5 chain_64 ...'] [--configs 'before after ...']
#
# Prints a report (commit, load, one table row per case and configuration),
# or writes it to --results.
# A configuration is a number of source files (generator --sources) and the
# compiler's optimization flags for the emitted code; `before` is the one
# source file at the release flags (-O3), `after` what symdyn_add_model now
# uses. The generators come from build/release (built here first).
set -euo pipefail
cd "$(git -C "$(dirname "$0")" rev-parse --show-toplevel)"
runs=5 calls=64 jobs=2 results=/dev/stdout
cases="amru5 chain_64 six_dof_arm" configs=""
while [ $# -gt 0 ]; do
  case $1 in
    --runs) runs=$2; shift 2 ;;
    --calls) calls=$2; shift 2 ;;
    --jobs) jobs=$2; shift 2 ;;
    --results) results=$2; shift 2 ;;
    --cases) cases=$2; shift 2 ;;
    --configs) configs=$2; shift 2 ;;
    -h|--help) sed -n '2,16p' "$0"; exit 0 ;;
    *) echo "run.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
build=build/release
warnings="-Wall -Wextra -Wpedantic -std=c++20"
# What symdyn_add_model gives the emitted code (cmake/SymdynAddModel.cmake).
after_flags=$(sed -n 's/^ *set(SYMDYN_EMITTED_CODE_FLAGS "\(.*\)")$/\1/p' cmake/SymdynAddModel.cmake | head -n 1)
after_sources=$(sed -n 's/^ *set(SYMDYN_EMITTED_CODE_SOURCES \([0-9]*\))$/\1/p' cmake/SymdynAddModel.cmake)
# name|sources|flags
all_configs=(
  "before|1|-O3 -DNDEBUG"
  "O2|1|-O2 -DNDEBUG"
  "O1|1|-O1 -DNDEBUG"
  "Og|1|-Og -DNDEBUG"
  "O2_no_slp|1|-O2 -DNDEBUG -fno-tree-slp-vectorize"
  "after_flags_aacc368|4|-O3 -DNDEBUG -O2 -fno-tree-slp-vectorize -fno-schedule-insns2 -fno-tree-dse -fno-gcse -fno-tree-pre -fno-tree-vrp -fno-code-hoisting -fno-expensive-optimizations"
  "after_flags_17463bf|4|-O3 -DNDEBUG -O2 -fno-tree-slp-vectorize -fno-schedule-insns2 -fno-tree-dse -fno-gcse -fno-tree-pre -fno-tree-vrp -fno-code-hoisting -fno-expensive-optimizations -fno-tree-fre -fno-dse -fno-tree-dce -fno-ipa-pure-const -fno-ipa-reference -fno-ipa-modref"
  "after_1_source|1|-O3 -DNDEBUG ${after_flags:-?}"
  "after_2_sources|2|-O3 -DNDEBUG ${after_flags:-?}"
  "after|${after_sources:-1}|-O3 -DNDEBUG ${after_flags:-?}"
)
# name|generator and its arguments
all_cases=(
  "amru5|models/symdyn_generator_amru5 --variant dependent"
  "amru5_derivatives|models/symdyn_generator_amru5 --variant dependent --derivatives"
  "chain_16|models/symdyn_generator_chain --model chain_16 --variant absolute"
  "chain_64|models/symdyn_generator_chain --model chain_64 --variant absolute"
  "six_dof_arm|src/codegen/symdyn-urdf --urdf $PWD/tests/urdf/robots/six_dof_arm.urdf"
)
lookup() {  # lookup NAME ROW... -> the row named NAME
  local name=$1 row
  shift
  for row in "$@"; do [ "${row%%|*}" = "$name" ] && { echo "$row"; return; }; done
  echo "run.sh: unknown name $name" >&2
  exit 2
}
[ -n "$configs" ] || configs=$(for c in "${all_configs[@]}"; do printf '%s ' "${c%%|*}"; done)

command -v valgrind >/dev/null || { echo "run.sh: valgrind is needed" >&2; exit 1; }
nice cmake --build --preset release -j2 --target symdyn_generator_amru5 symdyn_generator_chain symdyn-urdf >/dev/null
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
TIMEFORMAT='%R %U %S'
load_before=$(uptime | sed 's/.*load average/load average/')

median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }

# One generate-and-compile into $work/out: what is timed.
build_once() {  # build_once SOURCES FLAGS GENERATOR ARGS...
  local sources=$1 flags=$2
  shift 2
  rm -rf "$work/out" && mkdir -p "$work/out"
  "$build/$1" "${@:2}" --basename gen --out "$work/out" --sources "$sources" >/dev/null
  # shellcheck disable=SC2086  # the flags split into words
  ls "$work"/out/*.cpp | xargs -P "$jobs" -I{} sh -c "g++ $flags $warnings -I$work/out -c {} -o {}.o"
}

{
  echo "| case | configuration | wall s (median, min-max) | CPU s (median) | dynamics | inverse_dynamics | forward_dynamics |"
  echo "|---|---|---|---|---|---|---|"
} >"$work/table.md"
for case_name in $cases; do
  row=$(lookup "$case_name" "${all_cases[@]}")
  read -r -a generator <<<"${row#*|}"
  for config in $configs; do
    c=$(lookup "$config" "${all_configs[@]}")
    IFS='|' read -r _ sources flags <<<"$c"
    : >"$work/times"
    for ((r = 0; r < runs; ++r)); do
      # bash's time: wall, then user and system seconds of every process it waited for.
      { time build_once "$sources" "$flags" "${generator[@]}"; } 2>>"$work/times"
    done
    wall=$(awk '{ print $1 }' "$work/times" | median)
    wall_range=$(awk '{ print $1 }' "$work/times" | sort -g | sed -n '1p;$p' | paste -sd-)
    cpu=$(awk '{ print $2 + $3 }' "$work/times" | median)
    # The instructions per call, from the objects of the last run.
    g++ -O2 -std=c++20 -I"$work/out" bench/build_loop/driver.cpp "$work"/out/*.o -o "$work/driver"
    counts=()
    for entry in dynamics inverse_dynamics forward_dynamics; do
      if valgrind --tool=callgrind --toggle-collect='*counted_workload*' --callgrind-out-file="$work/cg.out" \
          "$work/driver" "$entry" "$calls" >"$work/cg.log" 2>&1; then
        total=$(grep -o 'Collected : [0-9]*' "$work/cg.log" | grep -o '[0-9]*$')
        counts+=("$((total / calls))")
      else
        counts+=("-")
      fi
    done
    echo "| $case_name | $config | $wall ($wall_range) | $cpu | ${counts[0]} | ${counts[1]} | ${counts[2]} |" |
      tee -a "$work/table.md" >&2
  done
done
{
  echo "Commit $(git rev-parse --short HEAD)$(git diff --quiet HEAD -- src cmake || echo ' (with uncommitted changes)'), $(date -u '+%Y-%m-%d %H:%M UTC'), $runs runs each, $jobs compiler runs at a time, g++ $(g++ -dumpfullversion)."
  echo "Load before: $load_before"
  echo
  echo "Configurations (source files, flags of the emitted code):"
  echo
  for config in $configs; do
    IFS='|' read -r _ sources flags <<<"$(lookup "$config" "${all_configs[@]}")"
    echo "- $config: $sources, \`$flags\`"
  done
  echo
  echo "Wall and CPU seconds: generating and compiling; the last three columns: instructions per call."
  echo
  cat "$work/table.md"
  echo
  echo "Load after: $(uptime | sed 's/.*load average/load average/')"
} >"$results"
[ "$results" = /dev/stdout ] || echo "run.sh: wrote $results" >&2
