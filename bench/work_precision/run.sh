#!/usr/bin/env bash
# One command: builds symdyn_bench_work_precision, runs it (every integrator on
# every problem, the peers on the double pendulum over 1 s), and writes
# bench/results/work_precision.md, work_precision.tsv and one diagram per problem
# (work_precision_<problem>.png and .svg, gnuplot from Debian's gnuplot-nox).
#
#   bench/work_precision/run.sh [--reps N] [--budget S] [--problem NAME]... [--integrator NAME]...
#
# --reps: timed repetitions, the median is reported (5); --budget: a sweep stops
# after a run of more than S s of CPU (1); --problem: only these problems;
# --integrator: only these of symdyn's integrators, measured again: their rows of the
# committed work_precision.tsv are replaced (the others and the peers' kept, with the
# commit they were measured at), and the report and diagrams are written from it.
set -euo pipefail
cd "$(git -C "$(dirname "$0")" rev-parse --show-toplevel)"
# shellcheck source=../../scripts/lib/setup.sh
source scripts/lib/setup.sh
symdyn_require_command gnuplot gnuplot-nox
cmake --build --preset release -j2 --target symdyn_bench_work_precision
results=bench/results
commit=$(git rev-parse --short HEAD)
git diff --quiet HEAD -- src models bench/work_precision || commit="$commit (with uncommitted changes)"
partial=false
for a in "$@"; do [ "$a" = --integrator ] && partial=true; done
if $partial; then
  out=build/release/bench/work_precision/partial.tsv
  {
    printf 'meta\tload\t%s\n' "$(cut -d' ' -f1-3 /proc/loadavg)"
    build/release/bench/work_precision/symdyn_bench_work_precision "$@"
    printf 'meta\tload_after\t%s\n' "$(cut -d' ' -f1-3 /proc/loadavg)"
  } | tee "$out"
  python3 bench/work_precision/report.py --merge "$out" "$commit" "$results/work_precision.tsv"
  python3 bench/work_precision/report.py "$results/work_precision.tsv" "$results"
  exit 0
fi
{
  printf 'meta\tcommit\t%s\n' "$commit"
  printf 'meta\tmachine\tAMD EPYC, 2 vCPU under KVM, shared (/work/.library/env/machines/cpp.md)\n'
  printf 'meta\tcpu\t%s\n' "$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//')"
  printf 'meta\tcompiler\t%s, CMake release preset (-O3)\n' "$(g++ --version | head -1)"
  printf 'meta\tmujoco\t%s\n' "$(dpkg-query -W -f='${Version}' libmujoco-dev 2>/dev/null || echo none)"
  printf 'meta\tsimbody\t%s\n' "$(dpkg-query -W -f='${Version}' libsimbody-dev 2>/dev/null || echo none)"
  printf 'meta\tload\t%s\n' "$(cut -d' ' -f1-3 /proc/loadavg)"
  build/release/bench/work_precision/symdyn_bench_work_precision "$@"
  printf 'meta\tload_after\t%s\n' "$(cut -d' ' -f1-3 /proc/loadavg)"
} | tee "$results/work_precision.tsv"
python3 bench/work_precision/report.py "$results/work_precision.tsv" "$results"
