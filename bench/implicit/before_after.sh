#!/usr/bin/env bash
# The implicit integrators today against the code before the exact derivatives
# (commit 2dd6e1f): Newmark on amru5 walking over 2 s and on the trike over 5 s,
# CVODE on the slider-crank over 1 s, each at a sweep of tolerances, with
# symdyn_bench_implicit_run (implicit_run.cpp) built from the same source in both
# trees. Errors against dop853 at 1e-12 of today's build (checked against dopri5
# at 1e-12, and against the old build's dop853: the same problem); work at the
# same error by report.py. Prints the results as a section of
# bench/results/derivatives.md (and keeps them in OLD_DIR/last/).
#
#   bench/implicit/before_after.sh [--old-dir DIR] [--reps N] [--count NAME]... [--build-only]
#
# --old-dir: where the old tree is unpacked and built, and kept for later runs
#   (default build/before-2dd6e1f; its first build takes a while, ccache helps);
# --reps: repetitions of each run (5), old and new interleaved; CPU: their median;
# --count NAME: also the instructions of that problem's runs (amru5_2s, trike_5s,
#   slider_crank_1s) under callgrind, one run each (about 50 times the CPU);
# --build-only: build both programs and stop.
set -euo pipefail
cd "$(git -C "$(dirname "$0")" rev-parse --show-toplevel)"
old_commit=2dd6e1f old_dir=build/before-$old_commit reps=5 build_only=0 count=()
while [ $# -gt 0 ]; do
  case $1 in
    --old-dir) old_dir=${2:?--old-dir needs a directory}; shift 2 ;;
    --reps) reps=${2:?--reps needs a number}; shift 2 ;;
    --build-only) build_only=1; shift ;;
    --count) count+=("${2:?--count needs a problem}"); shift 2 ;;
    -h|--help) sed -n '2,18p' "$0"; exit 0 ;;
    *) echo "unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
program=bench/implicit/symdyn_bench_implicit_run
here=$PWD

# The old tree as git archive gives it, configured with this directory's
# CMakeLists.txt included at the end (the old tree has no such target).
build_old() {
  local src=$old_dir/src log=$old_dir/build.log
  mkdir -p "$old_dir"
  old_dir=$(cd "$old_dir" && pwd) src=$old_dir/src log=$old_dir/build.log
  if [ ! -f "$src/CMakeLists.txt" ]; then
    mkdir -p "$src"
    git archive "$old_commit" | tar -x -C "$src" ||
      { echo "error: cannot unpack commit $old_commit into $src" >&2; exit 1; }
  fi
  # shellcheck disable=SC2016 # ${CMAKE_SOURCE_DIR} is CMake's
  printf 'cmake_language(DEFER DIRECTORY "${CMAKE_SOURCE_DIR}" CALL include "%s")\n' \
    "$here/bench/implicit/CMakeLists.txt" >"$old_dir/add_target.cmake"
  echo "building symdyn_bench_implicit_run of $old_commit in $src/build/release (log: $log)..."
  if ! (cd "$src" && export CCACHE_BASEDIR=$PWD &&
    cmake --preset release -DCMAKE_CXX_COMPILER_LAUNCHER=ccache \
      -DCMAKE_PROJECT_symdyn_INCLUDE="$old_dir/add_target.cmake" &&
    nice cmake --build --preset release -j2 --target symdyn_bench_implicit_run) >"$log" 2>&1; then
    tail -20 "$log" >&2
    echo "error: commit $old_commit could not be built in $src (full log: $log)" >&2
    exit 1
  fi
}

build_new() {
  [ -f build/release/CMakeCache.txt ] ||
    CCACHE_BASEDIR=$PWD cmake --preset release -DCMAKE_CXX_COMPILER_LAUNCHER=ccache >/dev/null
  CCACHE_BASEDIR=$PWD nice cmake --build --preset release -j2 --target symdyn_bench_implicit_run
}

# name scenario t_end integrator | tolerances before | tolerances after: the old
# Newmark's error goes as tol^(2/3), the new one's as tol, and the old CVODE is
# on the slider-crank as accurate at 1e-8 as the new one at 1e-6 (the same steps): the
# old sweeps reach further to meet the same errors (1e-4 .. 1e-6 and beyond).
sweeps=(
  "amru5_2s amru5 2 newmark | 1e-4 1e-5 1e-6 1e-7 1e-8 1e-9 | 1e-3 1e-4 1e-5 1e-6 1e-7"
  "trike_5s trike 5 newmark | 1e-4 1e-5 1e-6 1e-7 1e-8 1e-9 1e-10 | 1e-3 1e-4 1e-5 1e-6 1e-7"
  "slider_crank_1s slider_crank 1 cvode | 1e-7 1e-8 1e-9 1e-10 1e-11 1e-12 | 1e-6 1e-7 1e-8 1e-9 1e-10"
)
for name in "${count[@]}"; do
  [[ " ${sweeps[*]} " == *" $name "* ]] || { echo "error: --count $name: no such problem" >&2; exit 2; }
done
if [ ${#count[@]} -gt 0 ] && ! command -v valgrind >/dev/null; then
  echo "error: --count needs valgrind (Debian: apt-get install valgrind)" >&2
  exit 1
fi
build_old
build_new
old=$old_dir/src/build/release/symdyn_bench_implicit_run new=build/release/$program
[ "$build_only" = 1 ] && exit 0

work=$old_dir/last
rm -rf "$work" && mkdir -p "$work"
start=$(date +%s) load_start=$(cut -d" " -f1-3 /proc/loadavg)

# One run appended to runs.tsv; a run that fails is said and left out.
run() {  # side program name scenario t_end integrator tol rep
  local line
  if line=$("$2" "$4" "$5" "$6" "$7"); then
    printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$1" "$3" "$6" "$7" "$8" "$line" >>"$work/runs.tsv"
  else
    echo "warning: $1 $3 $6 at $7 failed; left out" >&2
  fi
}

echo "references: dop853 and dopri5 at 1e-12 after, dop853 at 1e-12 before..."
for sweep in "${sweeps[@]}"; do
  read -r name scenario t_end _ <<<"$sweep"
  run new "$new" "$name" "$scenario" "$t_end" dop853 1e-12 1
  run new "$new" "$name" "$scenario" "$t_end" dopri5 1e-12 1
  run old "$old" "$name" "$scenario" "$t_end" dop853 1e-12 1
done
for rep in $(seq "$reps"); do
  echo "repetition $rep of $reps..."
  for sweep in "${sweeps[@]}"; do
    IFS='|' read -r problem old_tols new_tols <<<"$sweep"
    read -r name scenario t_end integrator <<<"$problem"
    # shellcheck disable=SC2086 # the lists split into their tolerances
    for tol in $(printf '%s\n' $old_tols $new_tols | sort -gr | uniq); do
      if [[ " $old_tols " == *" $tol "* ]]; then run old "$old" "$name" "$scenario" "$t_end" "$integrator" "$tol" "$rep"; fi
      if [[ " $new_tols " == *" $tol "* ]]; then run new "$new" "$name" "$scenario" "$t_end" "$integrator" "$tol" "$rep"; fi
    done
  done
done

# Instructions of the integration alone, one run each, where asked (--count).
for sweep in "${sweeps[@]}"; do
  IFS='|' read -r problem old_tols new_tols <<<"$sweep"
  read -r name scenario t_end integrator <<<"$problem"
  [[ " ${count[*]} " == *" $name "* ]] || continue
  echo "instructions of $name (callgrind)..."
  for side in old new; do
    tols=$old_tols program=$old
    if [ "$side" = new ]; then tols=$new_tols program=$new; fi
    for tol in $tols; do
      n=$(valgrind --tool=callgrind --callgrind-out-file=/dev/null --toggle-collect='*integrate_with_breakpoints*' \
        "$program" "$scenario" "$t_end" "$integrator" "$tol" 2>&1 >/dev/null | sed -n 's/.*Collected : //p')
      if [ -n "$n" ]; then
        printf '%s\t%s\t%s\t%s\t%s\n' "$side" "$name" "$integrator" "$tol" "${n// /}" >>"$work/instructions.tsv"
      else
        echo "warning: $side $name $integrator at $tol failed under callgrind; left out" >&2
      fi
    done
  done
done

commit=$(git rev-parse --short HEAD)
git diff --quiet HEAD -- src models apps bench/implicit/implicit_run.cpp || commit="$commit (with uncommitted changes)"
cat >"$work/meta.txt" <<META
command = bench/implicit/before_after.sh --reps $reps$(for c in "${count[@]}"; do printf ' --count %s' "$c"; done)
machine = AMD EPYC, 2 vCPU under KVM, shared with other work (/work/.library/env/machines/cpp.md)
compiler = $(g++ --version | head -1), CMake release preset (-O3, no -march)
old = $old_commit
new = $commit
reps = $reps
load_start = $load_start
load_end = $(cut -d" " -f1-3 /proc/loadavg)
duration = $(($(date +%s) - start))
META
python3 bench/implicit/report.py "$work" --into bench/results/derivatives.md
cat "$work/section.md"
echo "wrote the section of bench/results/derivatives.md (and $work/section.md)"
