#!/usr/bin/env bash
# The size and generation cost of the exact derivatives, every reference model:
# operations of inverse_dynamics, inverse_dynamics_derivatives (and which form
# of tau it differentiates, or the recursive derivatives; what forward mode
# and the recursive derivatives each weighed) and kinematics_derivatives, from the generator's
# --stats; generation time (median of 5 runs) and peak memory with and without
# --derivatives. Writes bench/results/derivative_sizes.md.
#
#   bench/derivatives/sizes.sh [--results FILE]
set -euo pipefail
cd "$(git -C "$(dirname "$0")" rev-parse --show-toplevel)"
results=bench/results/derivative_sizes.md
[ "${1:-}" = "--results" ] && results=$2
cmake --build --preset release -j2 --target symdyn_generator_double_pendulum symdyn_generator_robot3d \
  symdyn_generator_slider_crank symdyn_generator_trike symdyn_generator_amru5 symdyn_generator_hexapod_tree \
  symdyn_generator_chain >/dev/null
bin=build/release/models
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# seconds and KB of one generation: the median of 5 runs' wall time, the largest resident size
measure() {
  local times=() peak=0
  for _ in 1 2 3 4 5; do
    /usr/bin/time -f "%e %M" -o "$work/time" "$@" --out "$work" >/dev/null 2>&1
    read -r t m <"$work/time"
    times+=("$t")
    [ "$m" -gt "$peak" ] && peak=$m
  done
  printf '%s %s\n' "$(printf '%s\n' "${times[@]}" | sort -g | sed -n 3p)" "$peak"
}
{
  echo "# Exact derivatives: size and generation cost"
  echo
  echo "Measured by \`bench/derivatives/sizes.sh\` at commit $(git rev-parse --short HEAD) on $(uname -m),"
  echo "$(nproc) vCPU ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')), shared and noisy."
  echo "Operations are the emitted programs' (generator --stats); generation is the median wall time of 5"
  echo "runs of the generator, peak the largest resident memory."
  echo
  echo "Forward mode is the best of the two forms differentiated (what inverse_dynamics_derivatives was"
  echo "before the recursive derivatives); \"recursive\" the recursive derivative algorithm's count, or why it"
  echo "does not apply (model/dynamics_derivatives.hpp)."
  echo
  echo "| model | nq | inverse_dynamics | inverse_dynamics_derivatives | ratio | form | forward mode | recursive | kinematics_derivatives | generation | with --derivatives | peak MB |"
  echo "|---|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|"
  for spec in double_pendulum:absolute: double_pendulum:relative: robot3d:absolute: robot3d:relative: \
              slider_crank:inline: slider_crank:dependent: trike:default: hexapod_tree:default: \
              amru5:inline: amru5:dependent: chain:relative:chain_2 chain:relative:chain_8 \
              chain:relative:chain_16 chain:relative:chain_32 chain:relative:chain_64; do
    IFS=: read -r gen variant model <<<"$spec"
    args=(--variant "$variant")
    [ -n "$model" ] && args+=(--model "$model")
    name=${model:-$gen}
    stats=$("$bin/symdyn_generator_$gen" "${args[@]}" --derivatives --stats --out "$work")
    nq=$(grep -h "static constexpr int nq" "$work"/*.hpp | head -1 | sed 's/.*= \([0-9]*\);/\1/')
    ops() { echo "$stats" | awk -v e="$1" '$1 == e {print $2}'; }
    id=$(ops inverse_dynamics) did=$(ops inverse_dynamics_derivatives) kd=$(ops kinematics_derivatives)
    form=$(echo "$stats" | sed -n 's/.*derivatives: of the \(.*\) form.*/\1/p')
    recursive=$(echo "$stats" | sed -n 's/.*derivatives: .*recursive derivatives \([0-9][0-9]*\).*/\1/p')
    forward=$did
    if [ "$form" = "recursive derivatives" ]; then
      forward=$(echo "$stats" | sed -n 's/.*derivatives: .*recursive derivatives [0-9]*, .* \([0-9][0-9]*\)$/\1/p')
    fi
    [ -n "$recursive" ] || recursive="does not apply"
    read -r plain _ < <(measure "$bin/symdyn_generator_$gen" "${args[@]}")
    read -r with peak < <(measure "$bin/symdyn_generator_$gen" "${args[@]}" --derivatives)
    rm -f "$work"/*.hpp "$work"/*.cpp
    printf '| %s %s | %s | %s | %s | %.1f | %s | %s | %s | %s | %s s | %s s | %d |\n' "$name" "$variant" "$nq" "$id" \
      "$did" "$(echo "$did / $id" | bc -l)" "$form" "$forward" "$recursive" "$kd" "$plain" "$with" $((peak / 1024))
  done
} >"$results"
echo "wrote $results"
