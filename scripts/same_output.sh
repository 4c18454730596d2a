#!/usr/bin/env bash
# Whether a change to the generator changes what it emits. Runs every
# generator of a build (each model it registers, each variant; symdyn-urdf on
# each robot of tests/urdf/robots) with each option set below, and keeps what
# it wrote, printed and returned: DIR/<model>/<variant>/<set>/ holds gen.hpp,
# gen.cpp (and gen.2.cpp ... with --sources), stdout, stderr and rc. Save before the
# change, check after it:
#
#   cmake --build --preset release --target $(scripts/same_output.sh targets)
#   scripts/same_output.sh save /tmp/before
#   # ... change the generator, build the same targets again ...
#   scripts/same_output.sh check /tmp/before   # names each file that differs; exit 1 if any
#
# GENERATORS=dir takes the generators from dir (default: build/release), e.g.
# copies of those built before the change. Each run takes about half a minute.
set -uo pipefail
cd "$(dirname "$0")/.." || exit 2
root=$PWD
generators=${GENERATORS:-build/release}

# name|options. Errors count too: an entry point not emitted with the other
# options is refused with a message that lists those that are.
option_sets=(
  "default|"
  "no_simplify|--no-simplify"
  "numeric_partials|--partials numeric"
  "no_eom|--no-eom"
  "recursive|--dynamics recursive"
  "mass_matrix|--dynamics mass-matrix"
  "case1|--no-simplify --partials numeric --no-eom"
  "parts16|--part-size 16 --split-above 0"
  "sources3|--part-size 16 --split-above 0 --sources 3 --source-bytes 1000"
  "only_positions|--only positions"
  "only_relative|--only relative_accelerations,dependent_parameters"
  "only_inertia|--only inertia"
  "only_forward_dynamics|--dynamics recursive --only forward_dynamics"
  "only_inverse_recursive|--dynamics recursive --only inverse_dynamics,forward_dynamics_pivots"
  "only_numeric_partials|--partials numeric --only partial_velocities,mass_matrix"
  "only_without_eom|--no-eom --only dynamics"
  "only_unknown|--only nope"
)

usage() {
  awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"
  exit 2
}

# The generators of the build, without those of the error tests.
generator_files() {
  find "$generators" -type f -executable \( -name 'symdyn_generator_*' -o -name symdyn-urdf \) \
    ! -name '*bad_models' ! -name '*error_models' | sort
}

# One generation: run_one DIR generator [arguments...] (the option set's come last).
run_one() {
  local dir=$1 options=$2
  shift 2
  mkdir -p "$dir"
  # shellcheck disable=SC2086  # the options split into words
  "$@" --basename gen --out "$dir" $options >"$dir/stdout" 2>"$dir/stderr"
  echo $? >"$dir/rc"
}

generate_all() {
  local out=$1 generator line model variants variant set
  [[ -n $(generator_files) ]] || { echo "same_output.sh: no generator in $generators: build them first" >&2; exit 2; }
  while read -r generator; do
    if [[ $(basename "$generator") == symdyn-urdf ]]; then
      for urdf in "$root"/tests/urdf/robots/*.urdf; do
        for set in "${option_sets[@]}"; do
          run_one "$out/urdf_$(basename "$urdf" .urdf)/default/${set%%|*}" "${set#*|}" "$generator" --urdf "$urdf"
        done
      done
      continue
    fi
    while IFS= read -r line; do
      model=${line%%:*}
      variants=${line#*: variants }
      for variant in ${variants//,/ }; do
        for set in "${option_sets[@]}"; do
          run_one "$out/$model/$variant/${set%%|*}" "${set#*|}" "$generator" --model "$model" --variant "$variant"
        done
      done
    done < <("$generator" --list)
  done < <(generator_files)
}

# Compares every file of the reference with its namesake; returns 1 if any differs or is missing.
compare() {
  local reference=$1 out=$2 files=0 differ=0 file rel
  while IFS= read -r file; do
    rel=${file#"$reference"/}
    files=$((files + 1))
    if ! cmp -s "$file" "$out/$rel"; then
      echo "differs: $rel"
      differ=$((differ + 1))
    fi
  done < <(find "$reference" -type f | sort)
  while IFS= read -r file; do
    rel=${file#"$out"/}
    [[ -e $reference/$rel ]] || { echo "new: $rel"; differ=$((differ + 1)); }
  done < <(find "$out" -type f | sort)
  echo "same_output.sh: $files files of $(find "$reference" -name rc | wc -l) generations compared, $differ differ"
  ((differ == 0))
}

case ${1:-} in
  targets)
    ninja -C build/release -t targets all | grep -o '^symdyn_generator_[a-z0-9_]*\|^symdyn-urdf' |
      grep -v 'bad_models\|error_models\|^symdyn_generator_main$' | sort -u | tr '\n' ' '
    echo
    ;;
  save)
    [[ $# -eq 2 ]] || usage
    [[ ! -e $2 ]] || { echo "same_output.sh: $2 exists: choose a new directory" >&2; exit 2; }
    generate_all "$2"
    echo "same_output.sh: $(find "$2" -name rc | wc -l) generations saved in $2"
    ;;
  check)
    [[ $# -eq 2 ]] || usage
    out=$(mktemp -d)
    generate_all "$out"
    compare "$2" "$out"
    status=$?
    rm -rf "$out"
    exit $status
    ;;
  *) usage ;;
esac
