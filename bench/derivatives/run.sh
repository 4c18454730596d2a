#!/usr/bin/env bash
# One command: builds symdyn_bench_derivatives (bench/peers: the peers' models,
# chain_32 and chain_64 with their derivatives, MuJoCo where installed) and
# symdyn_bench_implicit_jacobians, checks the derivatives' values, times every
# method, counts instructions under callgrind (with where symdyn's exact path
# spends them), runs the implicit integrators, and writes bench/results/derivatives.md.
#
#   bench/derivatives/run.sh [--rounds N] [--reps N] [--no-count] [--no-integrators]
#                            [--integrators-only] [--measure-build] [--results FILE] [MODEL...]
#
# --rounds: interleaved timing rounds (21); --reps: repetitions of each integrator
# run (5); --no-count: skip callgrind; --no-integrators: skip the implicit
# integrators; --integrators-only: build and run symdyn_bench_implicit_jacobians
# alone and replace its sections (time per Jacobian, implicit integrators) in the
# results file, which names the commit they were measured at; --measure-build: also generate and compile chain_64 once more
# under /usr/bin/time, ccache off (about 4 min of CPU, 2.5 GB), for the build
# figures (kept in build/release/bench/derivatives/ for later reports);
# MODEL...: only these (e.g. chain_8_absolute); a partial run should go to another --results file.
set -euo pipefail
cd "$(git -C "$(dirname "$0")" rev-parse --show-toplevel)"
rounds=21 reps=5 count=1 integrators=1 measure_build=0 results=bench/results/derivatives.md models=()
while [ $# -gt 0 ]; do
  case $1 in
    --rounds) rounds=$2; shift 2 ;;
    --reps) reps=$2; shift 2 ;;
    --no-count) count=0; shift ;;
    --no-integrators) integrators=0; shift ;;
    --integrators-only) integrators=only; shift ;;
    --measure-build) measure_build=1; shift ;;
    --results) results=$2; shift 2 ;;
    -h|--help) sed -n '2,19p' "$0"; exit 0 ;;
    *) models+=("$1"); shift ;;
  esac
done
start=$(date +%s) load_start=$(cut -d" " -f1-3 /proc/loadavg)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
build=build/release
kept=$build/bench/derivatives

version() { dpkg-query -W -f='${Package} ${Version}' "$1" 2>/dev/null || echo "$1: not installed"; }
commit=$(git rev-parse --short HEAD)
git diff --quiet HEAD -- src models bench || commit="$commit (with uncommitted changes)"
machine="AMD EPYC, 2 vCPU under KVM, shared with other work (/work/.library/env/machines/cpp.md)"

if [ "$integrators" = only ]; then
  cmake --build --preset release -j2 --target symdyn_bench_implicit_jacobians
  echo "implicit integrators and Jacobians, exact against differenced ($reps repetitions)..."
  "$build/bench/derivatives/symdyn_bench_implicit_jacobians" --reps "$reps" | tee "$work/integrators.tsv" | cut -c1-160
  printf 'machine = %s\ncompiler = %s, CMake release preset (-O3, no -march)\ncommit = %s\nreps = %s\n' \
    "$machine" "$(g++ --version | head -1)" "$commit" "$reps" >"$work/meta.txt"
  python3 bench/derivatives/report.py --integrators-only "$work" "$results"
  echo "rewrote the integrators' sections of $results in $(( $(date +%s) - start )) s"
  exit 0
fi

cmake --preset release -DSYMDYN_PEERS_BENCH=ON >"$work/configure.log" || { cat "$work/configure.log"; exit 1; }
grep 'peers bench' "$work/configure.log" || true
cmake --build --preset release -j2 --target symdyn_bench_derivatives symdyn_bench_implicit_jacobians
built=$(date +%s)
bench=$build/bench/peers/symdyn_bench_derivatives
implicit=$build/bench/derivatives/symdyn_bench_implicit_jacobians

echo "checking and timing the derivatives ($rounds rounds)..."
"$bench" time --rounds "$rounds" "${models[@]}" | tee "$work/time.tsv" | grep -E '^(time|skip)' || true
echo "timing the solves alone..."
"$bench" solves --rounds "$rounds" | tee "$work/solves.tsv"

: >"$work/counts.tsv"
if [ "$count" = 1 ]; then
  command -v valgrind >/dev/null || { echo "run.sh: valgrind is needed (apt-get install valgrind)" >&2; exit 1; }
  echo "counting instructions (callgrind)..."
  # Calls per count: about 5 ms of the method's measured time (at least 1, at most 64).
  awk -F'\t' '$1 == "time" { c = int(5e6 / $4); if (c < 1) c = 1; if (c > 64) c = 64; print $2 "\t" $3 "\t" c }' \
    "$work/time.tsv" >"$work/calls.tsv"
  while IFS=$'\t' read -r model method calls; do
    out="$work/cg.$model.$method"
    if valgrind --tool=callgrind --toggle-collect='*counted_workload*' --callgrind-out-file="$out" \
        "$bench" --count "$method" "$model" "$calls" >"$work/cg.log" 2>&1; then
      total=$(grep -o 'Collected : [0-9]*' "$work/cg.log" | grep -o '[0-9]*$')
      printf '%s\t%s\t%s\t%s\n' "$model" "$method" $((total / calls)) "$calls" | tee -a "$work/counts.tsv"
      if [ "$method" = symdyn_exact ]; then
        # Inclusive instructions of the parts of the exact path, per call.
        callgrind_annotate --inclusive=yes "$out" 2>/dev/null | awk -v m="$model" -v c="$calls" '
          /^ *[0-9,]+ \(/ {
            n = $1; gsub(",", "", n)
            part = ""
            if ($0 ~ /symdyn_generated::[a-z_0-9]+::inverse_dynamics_(derivatives|jacobians)\(/) part = "emitted_derivatives"
            else if ($0 ~ /symdyn_generated::[a-z_0-9]+::mass_matrix\(/) part = "emitted_mass_matrix"
            else if ($0 ~ /MultibodySystem::accelerations\(/) part = "accelerations"
            else if ($0 ~ /(SpdSolver|TreeSolver)::factor\(/) part = "factor"
            else if ($0 ~ /(SpdSolver|TreeSolver)::solve_negated_in_place\(/) part = "solves"
            else if ($0 ~ /InPlaceTranspose/) part = "transposes"
            else if ($0 ~ /MultibodySystem::dynamics_derivatives\(/) part = "total"
            # Each part once, the dense and the tree solver summed (either may run).
            key = part ($0 ~ /TreeSolver::/ ? " tree" : "")
            if (part != "" && !(key in seen)) { seen[key] = 1; sum[part] += n }
          }
          END { for (p in sum) printf "%s\t%s\t%d\n", m, p, sum[p] / c }' >>"$work/breakdown.tsv"
      fi
      rm -f "$out"
    else
      echo "run.sh: callgrind of $method on $model failed:" >&2
      tail -5 "$work/cg.log" >&2
    fi
  done <"$work/calls.tsv"
fi
touch "$work/breakdown.tsv"

: >"$work/integrators.tsv"
if [ "$integrators" = 1 ]; then
  echo "implicit integrators, exact against differenced Jacobians ($reps repetitions)..."
  "$implicit" --reps "$reps" | tee "$work/integrators.tsv" | cut -c1-160
fi

# chain_64's generation and compilation with its derivatives, measured apart
# (--measure-build) and kept for later reports.
mkdir -p "$kept"
if [ "$measure_build" = 1 ]; then
  echo "generating and compiling chain_64 with its derivatives under /usr/bin/time..."
  gen=$build/models/symdyn_generator_chain
  dir=$work/chain_64_build
  cmake --build --preset release --target symdyn_generator_chain >/dev/null
  /usr/bin/time -f '%U %S %e %M' -o "$work/gen.time" \
    "$gen" --out "$dir" --basename chain_64_absolute --model chain_64 --variant absolute --derivatives --stats \
    >"$work/gen.stats"
  /usr/bin/time -f '%U %S %e %M' -o "$work/cc.time" \
    g++ -std=c++20 -O3 -DNDEBUG -c "$dir/chain_64_absolute.cpp" -I"$dir" -o "$dir/chain_64_absolute.o"
  {
    read -r u s e m <"$work/gen.time"
    printf 'generation\t%s\t%s\t%s\t%s\t%s\n' "$u" "$s" "$e" "$m" "$(stat -c %s "$dir/chain_64_absolute.cpp")"
    read -r u s e m <"$work/cc.time"
    printf 'compilation\t%s\t%s\t%s\t%s\t%s\n' "$u" "$s" "$e" "$m" "$(stat -c %s "$dir/chain_64_absolute.o")"
    grep -E '^ *inverse_dynamics_derivatives|^ *inverse_dynamics |^ *forward_dynamics_pivots' "$work/gen.stats" |
      awk '{ printf "operations\t%s\t%s\n", $1, $2 }'
    printf 'commit\t%s\n' "$(git rev-parse --short HEAD)"
  } >"$kept/chain_64_build.tsv"
fi
[ -f "$kept/chain_64_build.tsv" ] && cp "$kept/chain_64_build.tsv" "$work/build.tsv" || : >"$work/build.tsv"

{
  echo "machine = $machine"
  echo "cpu = $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//')"
  echo "compiler = $(g++ --version | head -1), CMake release preset (-O3, no -march; SpdSolver's kernels also built for AVX2 with FMA, taken at run time where the processor has them)"
  echo "commit = $commit"
  echo "mujoco = $(version libmujoco-dev)"
  echo "valgrind = $(valgrind --version 2>/dev/null || echo none)"
  echo "rounds = $rounds"
  echo "reps = $reps"
  echo "duration = $(( $(date +%s) - start )) s for the whole of bench/derivatives/run.sh, of which $(( built - start )) s configuring and building"
  echo "load = $load_start at the start, $(cut -d" " -f1-3 /proc/loadavg) at the end (1, 5, 15 minute averages, 2 vCPUs)"
} >"$work/meta.txt"
mkdir -p "$kept/last_run" && cp "$work"/*.tsv "$work/meta.txt" "$kept/last_run/"
python3 bench/derivatives/report.py "$work" "$results"
echo "wrote $results in $(( $(date +%s) - start )) s"
