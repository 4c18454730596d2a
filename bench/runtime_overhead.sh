#!/usr/bin/env bash
# Instructions per qdd evaluation (callgrind, repeatable on a shared machine) of
# MultibodySystem::accelerations against the emitted equations alone, for every
# model of symdyn_bench_runtime, as a Markdown table on stdout:
#
#   bench/runtime_overhead.sh [build/release/bench/symdyn_bench_runtime] [CALLS]
#
# Columns: system (what users call), equations (emitted mass_matrix +
# bias_forces + Eigen's dynamic LDLT), dynamics (emitted dynamics() + the
# runtime's SpdSolver), and the ratios of system to each.
set -euo pipefail
bench=${1:-build/release/bench/symdyn_bench_runtime}
calls=${2:-1000}
command -v valgrind >/dev/null || { echo "runtime_overhead.sh: valgrind is needed (apt-get install valgrind)" >&2; exit 1; }
[ -x "$bench" ] || { echo "runtime_overhead.sh: $bench not built (cmake --build --preset release --target symdyn_bench_runtime)" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# Instructions per call of one workload.
per_call() {
  local mode=$1 model=$2
  if ! valgrind --tool=callgrind --toggle-collect='*counted_workload*' --callgrind-out-file="$tmp/out" \
      "$bench" --count "$mode" "$model" "$calls" >"$tmp/log" 2>&1; then
    echo "-"
    return
  fi
  local total
  total=$(grep -o 'Collected : [0-9]*' "$tmp/log" | grep -o '[0-9]*$')
  echo $((total / calls))
}

ratio() { awk -v a="$1" -v b="$2" 'BEGIN { if (b == "-" || a == "-" || b == 0) print "-"; else printf "%.2f", a / b }'; }

echo "| model | nq | system | equations | dynamics | system / equations | system / dynamics |"
echo "|---|---:|---:|---:|---:|---:|---:|"
while read -r model nq; do
  s=$(per_call system "$model")
  e=$(per_call equations "$model")
  d=$(per_call dynamics "$model")
  echo "| $model | $nq | $s | $e | $d | $(ratio "$s" "$e") | $(ratio "$s" "$d") |"
done < <("$bench" --list)
