#!/usr/bin/env bash
# The pictures of the README and the docs (docs/images/*.png), made from real runs
# of this build, so that they show what symdyn does now:
#   trike_plot.png    symdyn-sim's run of models/scenarios/trike.json, plotted by
#                     scripts/lib/trike_plot.gp (gnuplot);
#   trike_viewer.png  the same run in symdyn-sim's HTML viewer at t = 3 s, as
#                     headless Chromium shows it;
#   top_viewer.png    the tutorial's spinning top (examples/spinning_top/top.json,
#                     its module built by tests/docs) in the viewer at t = 1 s.
# Usage: scripts/update_pictures.sh [build dir, build/release] [out dir, docs/images]
# The test "docs: the pictures are the ones scripts/update_pictures.sh makes"
# (tests/docs/check_pictures.py) makes them again in a scratch folder and compares.
set -euo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-$repo/build/release}" && pwd)
out=${2:-$repo/docs/images}
sim=$build/apps/sim/symdyn-sim
browser=${SYMDYN_CHROMIUM:-chromium}
for program in "$sim" gnuplot "$browser"; do
  command -v "$program" >/dev/null || { echo "error: $program not found" >&2; exit 1; }
done
mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

run() {  # symdyn-sim's run of a scenario, its viewer in $work/<name>.html
  local name=$1
  shift
  "$sim" "$@" --out "$work/$name.csv" --html "$work/$name.html" >"$work/$name.txt" ||
    { cat "$work/$name.txt" >&2; exit 1; }
}
# The viewer as tests/viewer/check_viewer.py opens it: software WebGL, a fixed
# window, virtual time to load and draw.
screenshot() {  # screenshot <name> <time>: $out/<name>_viewer.png
  "$browser" --headless=new --no-sandbox --disable-gpu --use-angle=swiftshader \
    --enable-unsafe-swiftshader --hide-scrollbars --window-size=900,560 --virtual-time-budget=4000 \
    --screenshot="$out/$1_viewer.png" "file://$work/$1.html#t=$2" 2>"$work/chromium.txt" ||
    { cat "$work/chromium.txt" >&2; exit 1; }
}

run trike trike
gnuplot -e "csv='$work/trike.csv'; png='$out/trike_plot.png'; width=1100; height=800" \
  "$repo/scripts/lib/trike_plot.gp"
screenshot trike 3

# The tutorial's top beside its module, as the tutorial lays them out.
mkdir -p "$work/top/build"
cp "$repo/examples/spinning_top/top.json" "$work/top/"
cp "$build/tests/docs/docs_spinning_top_module.so" "$work/top/build/spinning_top_module.so"
run top "$work/top/top.json"
screenshot top 1
for png in trike_plot.png trike_viewer.png top_viewer.png; do
  echo "wrote $out/$png ($(wc -c <"$out/$png") bytes)"
done
