#!/usr/bin/env bash
# The paper's tables (Tgen, Size, T1, T2) for every model, variant and case,
# with operation counts, compile time and errors, and the chain_N scaling study.
#
#   bench/paper_tables/run.sh [--models a,b] [--quick] [--reps N] [--gen-runs N] [--compile-runs N]
#                             [--build DIR] [--work DIR] [--results DIR] [--no-build]
#                             [--cas sympy,giac|none] [--cas-timeout S] [--cas-chain-max N]
#                             [--cas-only] [--note TEXT]
#
#   --models a,b   only these models (double_pendulum, robot3d, slider_crank, trike,
#                  amru5, hexapod_tree, chain = every chain_N, or chain_8 ...)
#   --quick        3 repetitions, 3 generator runs, 1 compilation, chain_N up to N = 16
# chain_32 and chain_64 are measured for generation only (sizes, operations,
# one Tgen): their emitted code is not compiled or timed.
#   --reps N       timed repetitions of T1 and T2 (median; default 7)
#   --gen-runs N   generations for Tgen (median; default 5)
#   --compile-runs N  compilations of each emitted source (median CPU time; default 3)
#   --build DIR    CMake build directory (default build/release, the release preset)
#   --work DIR     scratch directory for emitted code and raw results (default build/paper_tables)
#   --results DIR  where paper_tables.md/.json and chain_scaling.png go (default bench/results)
#   --no-build     do not build the generators and symdyn_paper_bench first
#   --cas LIST     computer algebra measured beside symdyn in cases 1-3 (default sympy,giac;
#                  none: neither): cagem_sympy.py and cagem_giac.py on the generator's --describe
#   --cas-timeout S  seconds each computer algebra derivation may take (default 300; then "timeout")
#   --cas-chain-max N  chain_N measured by the computer algebra up to N (default 64); a chain
#                  variant and case that timed out is not tried again for a longer chain
#   --cas-only     measure the computer algebra (--cas) again, keeping the other rows of
#                  --work from an earlier run, then write the report
#   --note TEXT    a sentence for the report's set-up line (e.g. which rows were measured again)
#
# Per model, variant and case (1: --no-simplify --partials numeric --no-eom,
# 2: --partials numeric --no-eom, 3: --no-eom, 4: default with mass_matrix and
# bias_forces): runs the generator once (its files, size and operation counts),
# symdyn_paper_tgen (Tgen: median of --gen-runs generations in process, CPU
# time), compiles the emitted source at -O2 --compile-runs times (CPU and wall time), links it with adapter.cpp into a shared
# object and runs symdyn_paper_bench on it (T1, T2, errors); in cases 1 and 2
# it also counts the instructions of T1's and T2's workloads under
# valgrind --tool=callgrind (repeatable, unlike timings on a shared machine:
# the case 2 against case 1 comparison). report.py then writes the tables.
# Runs everything one after another: timings never overlap.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
build=$root/build/release
work=$root/build/paper_tables
results=$root/bench/results
models=""
quick=0
reps=7
gen_runs=5
compile_runs=3
do_build=1
cas=sympy,giac
cas_timeout=300
cas_chain_max=64
cas_only=0
note=""

while [[ $# -gt 0 ]]; do
  case $1 in
    --models) models=$2; shift 2 ;;
    --quick) quick=1; reps=3; gen_runs=3; compile_runs=1; shift ;;
    --reps) reps=$2; shift 2 ;;
    --gen-runs) gen_runs=$2; shift 2 ;;
    --compile-runs) compile_runs=$2; shift 2 ;;
    --build) build=$(realpath -m "$2"); shift 2 ;;
    --work) work=$(realpath -m "$2"); shift 2 ;;
    --results) results=$(realpath -m "$2"); shift 2 ;;
    --no-build) do_build=0; shift ;;
    --cas) cas=$2; shift 2 ;;
    --cas-timeout) cas_timeout=$2; shift 2 ;;
    --cas-chain-max) cas_chain_max=$2; shift 2 ;;
    --cas-only) cas_only=1; shift ;;
    --note) note=$2; shift 2 ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) echo "run.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done

# shellcheck source=../../scripts/lib/setup.sh
source "$root/scripts/lib/setup.sh"
symdyn_require_packages "${symdyn_base_packages[@]}" valgrind gnuplot-nox

# The computer algebra (bench only): Debian's python3-sympy (run by Debian's own
# python3, whatever python3 comes first in PATH) and xcas (the giac interpreter).
# Installed when missing if possible; otherwise skipped, saying so.
cas_python=/usr/bin/python3
cas_tools=()
[[ $cas == none ]] && cas=""
IFS=, read -ra cas_wanted <<< "$cas"
for tool in "${cas_wanted[@]}"; do
  case $tool in
    sympy) package=python3-sympy ;;
    giac) package=xcas ;;
    *) echo "run.sh: --cas: unknown tool '$tool' (sympy, giac or none)" >&2; exit 2 ;;
  esac
  if (symdyn_require_packages "$package") >&2; then
    cas_tools+=("$tool")
  else
    echo "run.sh: $package could not be installed: the $tool rows are skipped" >&2
  fi
done
declare -A cas_gave_up=()  # "tool variant case" of a chain_N that timed out

cxx=${CXX:-g++}
cxxflags=(-std=c++20 -O2 -fPIC -fvisibility=hidden)

# The model files present decide what is measured: models/<file>.cpp gives the
# generator symdyn_generator_<file>; chain.cpp registers chain_2 ... chain_64.
model_files=()
for f in "$root"/models/*.cpp; do model_files+=("$(basename "$f" .cpp)"); done

wanted() {  # wanted <model name>: is it selected by --models?
  [[ -z $models ]] && return 0
  local m
  IFS=, read -ra list <<< "$models"
  for m in "${list[@]}"; do
    [[ $m == "$1" ]] && return 0
    [[ $m == chain && $1 == chain_* ]] && return 0
  done
  return 1
}

if [[ $do_build == 1 ]]; then
  [[ -f $build/CMakeCache.txt ]] || cmake --preset release -S "$root"
  targets=(symdyn_paper_bench symdyn_paper_tgen)
  for f in "${model_files[@]}"; do targets+=("symdyn_generator_$f"); done
  cmake --build "$build" -j2 --target "${targets[@]}"
fi

bench=$build/bench/symdyn_paper_bench
tgen=$build/bench/symdyn_paper_tgen
mkdir -p "$work" "$results"
if [[ $cas_only == 0 ]]; then
  rm -rf "$work/rows"
elif [[ ! -d $work/rows ]]; then
  echo "run.sh: --cas-only: no earlier measurements in $work/rows" >&2
  exit 2
fi
mkdir -p "$work/rows"

chain_sizes=(2 4 8 16 32 64)
[[ $quick == 1 ]] && chain_sizes=(2 4 8 16)

case_flags() {
  case $1 in
    1) echo "--no-simplify --partials numeric --no-eom" ;;
    2) echo "--partials numeric --no-eom" ;;
    3) echo "--no-eom" ;;
    4) echo "" ;;
  esac
}

# timed <file> <command...>: runs the command, writes "wall user system" seconds to file.
timed() {
  local file=$1; shift
  /usr/bin/time -f "%e %U %S" -o "$file" "$@"
}

# count_instructions <dir> <lib> <model> <variant> <case>: instructions per
# evaluation of T1's and T2's workloads (callgrind), into <dir>/instructions.json.
count_instructions() {
  local dir=$1 lib=$2 model=$3 variant=$4 c=$5 w n collected json="{"
  for w in T1 T2; do
    n=100; [[ $w == T2 ]] && n=10
    collected=$(valgrind --tool=callgrind --callgrind-out-file=/dev/null --toggle-collect='*counted_workload*' \
      "$bench" --lib "$lib" --model "$model" --variant "$variant" --case "$c" --count "$w" \
      --count-evaluations "$n" 2>&1 >/dev/null | sed -n 's/.*Collected : *\([0-9]*\).*/\1/p')
    [[ -n $collected ]] || { echo "run.sh: callgrind counted nothing for $lib $w" >&2; exit 1; }
    json+="\"$w\": $((collected / n)), "
  done
  echo "${json%, }}" > "$dir/instructions.json"
}

# measure <generator> <model> <variant> <case> [--model name]
measure() {
  local gen=$1 model=$2 variant=$3 c=$4; shift 4
  local dir=$work/rows/$model/$variant/case$c
  mkdir -p "$dir"
  local flags
  read -ra flags <<< "$(case_flags "$c")"
  echo "== $model $variant case $c" >&2
  timed "$dir/generator_time.txt" "$gen" "$@" --variant "$variant" --out "$dir" "${flags[@]}" --stats \
    > "$dir/stats.txt"
  "$tgen" --model "$model" --variant "$variant" --case "$c" --runs "$gen_runs" > "$dir/tgen.json"
  local base=${model}_${variant}
  local run
  : > "$dir/compile_time.txt"
  for ((run = 0; run < compile_runs; ++run)); do  # one "wall user system" line each
    timed "$dir/compile_time.run" "$cxx" "${cxxflags[@]}" -c "$dir/$base.cpp" -o "$dir/$base.o"
    cat "$dir/compile_time.run" >> "$dir/compile_time.txt"
  done
  rm -f "$dir/compile_time.run"
  "$cxx" "${cxxflags[@]}" -I"$here" -I"$dir" -include "$base.hpp" \
    -DSYMDYN_PAPER_STRUCT="symdyn_generated::$base" -c "$here/adapter.cpp" -o "$dir/adapter.o"
  "$cxx" -shared -o "$dir/$base.so" "$dir/$base.o" "$dir/adapter.o"
  "$bench" --lib "$dir/$base.so" --model "$model" --variant "$variant" --case "$c" \
    --reps "$reps" --out "$dir/bench.json"
  (( c <= 2 )) && count_instructions "$dir" "$dir/$base.so" "$model" "$variant" "$c"
  rm -f "$dir/$base.o" "$dir/adapter.o"
}

# measure_generation <generator> <model> <variant> <case> [--model name]: the
# generator's files, sizes and operation counts and Tgen (one generation) only.
# For chain_32 and chain_64, whose case-4 sources (6 to 27 MB) would take many
# minutes each to compile at -O2.
measure_generation() {
  local gen=$1 model=$2 variant=$3 c=$4; shift 4
  local dir=$work/rows/$model/$variant/case$c
  rm -rf "$dir" && mkdir -p "$dir"
  local flags
  read -ra flags <<< "$(case_flags "$c")"
  echo "== $model $variant case $c (generation only)" >&2
  timed "$dir/generator_time.txt" "$gen" "$@" --variant "$variant" --out "$dir" "${flags[@]}" --stats \
    > "$dir/stats.txt"
  "$tgen" --model "$model" --variant "$variant" --case "$c" --runs 1 > "$dir/tgen.json"
  rm -f "$dir"/*.cpp
}

# measure_cas <generator> <model> <variant> <case> [--model name]: CAGeM's
# derivation by each computer algebra tool, on the generator's --describe.
measure_cas() {
  local gen=$1 model=$2 variant=$3 c=$4; shift 4
  (( c <= 3 )) || return 0
  local dir=$work/rows/$model/$variant/case$c/cas
  mkdir -p "$dir"
  "$gen" "$@" --variant "$variant" --describe > "$dir/describe.json"
  local tool key rc n
  for tool in "${cas_tools[@]}"; do
    rm -f "$dir/${tool}_case$c".* "$dir/$tool.err"
    key="$tool $variant $c"
    if [[ $model == chain_* ]]; then
      n=${model#chain_}
      if (( n > cas_chain_max )); then
        echo "{\"tool\": \"$tool\", \"case\": $c, \"status\": \"not run\", \"message\": \"chain_N beyond --cas-chain-max $cas_chain_max\"}" \
          > "$dir/${tool}_case$c.json"
        continue
      fi
      if [[ -n ${cas_gave_up[$key]:-} ]]; then
        echo "{\"tool\": \"$tool\", \"case\": $c, \"status\": \"not run\", \"message\": \"${cas_gave_up[$key]} timed out\"}" \
          > "$dir/${tool}_case$c.json"
        continue
      fi
    fi
    echo "== $model $variant case $c: $tool" >&2
    rc=0
    if [[ $tool == sympy ]]; then
      timeout --kill-after=10 "$cas_timeout" "$cas_python" "$here/cagem_sympy.py" --describe "$dir/describe.json" \
        --case "$c" --out "$dir" > /dev/null 2> "$dir/sympy.err" || rc=$?
      if (( rc == 124 || rc == 137 )); then
        echo "{\"tool\": \"SymPy\", \"case\": $c, \"status\": \"timeout\", \"timeout\": $cas_timeout}" > "$dir/sympy_case$c.json"
      elif (( rc != 0 )); then
        "$cas_python" -c 'import json, sys; print(json.dumps({"tool": "SymPy", "case": int(sys.argv[1]), "status": "error",
          "message": (open(sys.argv[2]).read().strip().splitlines() or ["?"])[-1]}))' "$c" "$dir/sympy.err" > "$dir/sympy_case$c.json"
      fi
    else
      "$cas_python" "$here/cagem_giac.py" --describe "$dir/describe.json" --case "$c" --out "$dir" \
        --timeout "$cas_timeout" > /dev/null 2> "$dir/giac.err" || rc=$?
      (( rc == 0 )) || echo "{\"tool\": \"Giac\", \"case\": $c, \"status\": \"error\", \"message\": \"cagem_giac.py exited with $rc\"}" \
        > "$dir/giac_case$c.json"
    fi
    if [[ $model == chain_* ]] && grep -q '"status": "timeout"' "$dir/${tool}_case$c.json"; then
      cas_gave_up[$key]=$model
    fi
  done
  rm -f "$dir"/*.txt
}

missing=()
for f in double_pendulum robot3d slider_crank trike amru5 hexapod_tree chain; do
  [[ -f $root/models/$f.cpp ]] || missing+=("$f")
done

for f in "${model_files[@]}"; do
  gen=$build/models/symdyn_generator_$f
  if [[ $f == chain ]]; then
    for n in "${chain_sizes[@]}"; do
      wanted "chain_$n" || continue
      for variant in relative absolute; do
        how=measure
        (( n >= 32 )) && how=measure_generation
        for c in 1 2 3 4; do
          [[ $cas_only == 1 ]] || $how "$gen" "chain_$n" "$variant" "$c" --model "chain_$n"
          measure_cas "$gen" "chain_$n" "$variant" "$c" --model "chain_$n"
        done
      done
    done
    continue
  fi
  wanted "$f" || continue
  # "double_pendulum: variants absolute, relative"
  variants=$("$gen" --list | sed 's/^[^:]*: variants //; s/,//g')
  for variant in $variants; do
    for c in 1 2 3 4; do
      [[ $cas_only == 1 ]] || measure "$gen" "$f" "$variant" "$c"
      measure_cas "$gen" "$f" "$variant" "$c"
    done
  done
done

python3 "$here/report.py" --work "$work/rows" --results "$results" --paper "$here/paper_numbers.json" \
  --missing "${missing[*]}" --reps "$reps" --gen-runs "$gen_runs" --note "$note"
