#!/usr/bin/env bash
# One command: builds symdyn_bench_peers (and the chain_32, chain_64 code it
# needs), verifies every peer against symdyn, times them, counts instructions of
# forward dynamics under callgrind, and writes bench/results/peers.md.
#
#   bench/peers/run.sh [--rounds N] [--calls N] [--no-count] [--results FILE] [MODEL...]
#
# --rounds: interleaved timing rounds (31); --calls: calls counted per workload
# (256); --no-count: skip callgrind; MODEL...: only these (e.g. chain_8_absolute);
# a partial run should go to another --results file.
set -euo pipefail
cd "$(git -C "$(dirname "$0")" rev-parse --show-toplevel)"
rounds=31 calls=256 count=1 results=bench/results/peers.md models=()
while [ $# -gt 0 ]; do
  case $1 in
    --rounds) rounds=$2; shift 2 ;;
    --calls) calls=$2; shift 2 ;;
    --no-count) count=0; shift ;;
    --results) results=$2; shift 2 ;;
    -h|--help) sed -n '2,11p' "$0"; exit 0 ;;
    *) models+=("$1"); shift ;;
  esac
done
start=$(date +%s)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

cmake --preset release -DSYMDYN_PEERS_BENCH=ON >"$work/configure.log" || { cat "$work/configure.log"; exit 1; }
grep 'peers bench' "$work/configure.log" || true
cmake --build --preset release -j2 --target symdyn_bench_peers
built=$(date +%s)
bench=build/release/bench/peers/symdyn_bench_peers
[ -x "$bench" ] || { echo "run.sh: no peer library found, nothing to compare (bench/README.md)" >&2; exit 1; }

echo "verifying and timing ($rounds rounds)..."
"$bench" time --rounds "$rounds" "${models[@]}" | tee "$work/time.tsv" | grep -E '^(time|skip)|DISAGREES' || true

: >"$work/counts.tsv"
if [ "$count" = 1 ]; then
  command -v valgrind >/dev/null || { echo "run.sh: valgrind is needed (apt-get install valgrind)" >&2; exit 1; }
  echo "counting instructions (callgrind)..."
  libraries=$("$bench" --list | awk '$1 == "library" { print $2 }')
  for model in $(awk -F'\t' '$1 == "mass" { print $2 }' "$work/time.tsv"); do
    for lib in $libraries; do
      # Only the libraries that agreed with symdyn (and can compute the model's forward dynamics).
      if awk -F'\t' -v m="$model" -v l="$lib" '($1 == "skip" && $2 == m && $3 == l) ||
          ($1 == "skipop" && $2 == m && $3 == l && $4 == "forward_dynamics") ||
          ($1 == "verify" && $2 == m && $3 == l && $7 != "ok") { bad = 1 } END { exit !bad }' "$work/time.tsv"; then
        continue
      fi
      if valgrind --tool=callgrind --toggle-collect='*counted_workload*' --callgrind-out-file="$work/cg.out" \
          "$bench" --count "$lib" forward_dynamics "$model" "$calls" >"$work/cg.log" 2>&1; then
        total=$(grep -o 'Collected : [0-9]*' "$work/cg.log" | grep -o '[0-9]*$')
        printf '%s\t%s\t%s\n' "$lib" "$model" $((total / calls)) | tee -a "$work/counts.tsv"
      else
        echo "run.sh: callgrind of $lib $model failed:" >&2
        tail -5 "$work/cg.log" >&2
      fi
    done
  done
fi

# Generation and compilation of chain_32 and chain_64, from ninja's log when
# this build ran them, else as recorded when an earlier build did (a rebuild
# of the manifest can drop old entries from the log).
recorded=build/release/bench/peers/chain_build.tsv
: >"$work/build.tsv"
for n in 32 64; do
  t=chain_${n}_absolute
  awk -v t="$t" -F'\t' '
    $4 ~ ("generated/" t "/" t ".hpp$") { gen = ($2 - $1) / 1000 }
    $4 ~ ("/" t ".dir/.*" t ".cpp.o$") { obj = ($2 - $1) / 1000 }
    END { if (gen != "") printf "%s\tgeneration (symdyn generator)\t%.1f\n", t, gen
          if (obj != "") printf "%s\tcompilation of the emitted source (g++ -O3)\t%.1f\n", t, obj }' \
    build/release/.ninja_log >>"$work/build.tsv"
done
if [ -s "$work/build.tsv" ]; then cp "$work/build.tsv" "$recorded"; elif [ -f "$recorded" ]; then cp "$recorded" "$work/build.tsv"; fi

version() { dpkg-query -W -f='${Package} ${Version}' "$1" 2>/dev/null || echo "$1: not installed"; }
commit=$(git rev-parse --short HEAD)
git diff --quiet HEAD -- src models bench/peers || commit="$commit (with uncommitted changes)"
{
  echo "machine = AMD EPYC, 2 vCPU under KVM, shared (/work/.library/env/machines/cpp.md)"
  echo "cpu = $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//')"
  echo "compiler = $(g++ --version | head -1), CMake release preset (-O3)"
  echo "commit = $commit"
  echo "mujoco = $(version libmujoco-dev)"
  echo "simbody = $(version libsimbody-dev)"
  echo "kdl = $(version liborocos-kdl-dev)"
  echo "dart = $(version libdart-dev)"
  echo "valgrind = $(valgrind --version 2>/dev/null || echo none)"
  echo "rounds = $rounds"
  echo "duration = $(( $(date +%s) - start )) s for the whole of bench/peers/run.sh, of which $(( built - start )) s configuring and building"
} >"$work/meta.txt"
# What was measured stays in the build tree: report.py can rewrite the results from it.
mkdir -p build/release/bench/peers/last_run && cp "$work"/*.tsv "$work/meta.txt" build/release/bench/peers/last_run/
python3 bench/peers/report.py "$work" "$results"
echo "wrote $results in $(( $(date +%s) - start )) s"
