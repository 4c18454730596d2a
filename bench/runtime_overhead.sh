#!/usr/bin/env bash
# Instructions per qdd evaluation (callgrind, repeatable on a shared machine) of
# MultibodySystem::accelerations against the emitted equations alone, on each of
# its two paths, for every model of symdyn_bench_runtime, as a Markdown table on
# stdout:
#
#   bench/runtime_overhead.sh [build/release/bench/symdyn_bench_runtime] [CALLS]
#
# Columns (the modes of runtime_bench.cpp): path (the system's default:
# recursive where the generator emitted forward_dynamics, else mass_matrix),
# system (what users call, that path), system via M (set_recursive(false)),
# equations (emitted mass_matrix + bias_forces + Eigen's dynamic LDLT), dynamics
# (emitted dynamics() + the runtime's SpdSolver: the floor of the M path),
# forward (emitted forward_dynamics(): the floor of the recursive path, "-"
# where not emitted), and the ratios of each path to its floor.
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

echo "| model | nq | path | system | system via M | equations | dynamics | forward | system / forward | system via M / dynamics |"
echo "|---|---:|---|---:|---:|---:|---:|---:|---:|---:|"
while read -r model nq path; do
  s=$(per_call system "$model")
  m=$(per_call system_mass_matrix "$model")
  e=$(per_call equations "$model")
  d=$(per_call dynamics "$model")
  f=-
  [ "$path" = recursive ] && f=$(per_call forward "$model")
  echo "| $model | $nq | $path | $s | $m | $e | $d | $f | $(ratio "$s" "$f") | $(ratio "$m" "$d") |"
done < <("$bench" --list)
