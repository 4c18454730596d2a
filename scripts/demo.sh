#!/usr/bin/env bash
# symdyn at work on the double pendulum (docs/models.md 1), for real:
#   1. installs what is missing (Debian 12, as root), configures the release
#      preset and builds what the demo runs (quick when already built);
#   2. runs the model's generator with --stats (time, operation counts) and
#      shows a few lines of the emitted C++;
#   3. simulates 10 s with symdyn-sim on that code, CSV in out/double_pendulum.csv;
#   4. prints the summary and plots theta1 and theta2 in the terminal (gnuplot, dumb);
#   5. runs the trike's scenario and writes its animation (HTML viewer, glTF)
#      and a picture of what it does (PNG: its path seen from above, its height
#      and tyre loads, steering and roll, speed and yaw rate; scripts/lib/trike_plot.gp)
#      in out/, saying how to open each.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/lib/setup.sh
symdyn_require_packages "${symdyn_base_packages[@]}" gnuplot-nox
symdyn_require_command npm npm  # bundles the HTML viewer

build=build/release
generator=$build/models/symdyn_generator_double_pendulum
sim=$build/apps/sim/symdyn-sim

echo "== symdyn: configure and build (release preset: the generator and symdyn-sim)"
cmake --preset release >/dev/null
cmake --build --preset release -j "$(nproc)" --target symdyn_generator_double_pendulum symdyn-sim >/dev/null

echo
echo "== generate the double pendulum (absolute variant) from models/double_pendulum.cpp"
generated=$build/demo
"$generator" --variant absolute --out "$generated" --stats

echo
echo "== the emitted mass matrix ($generated/double_pendulum_absolute.cpp)"
sed -n '/::mass_matrix(/,/^}/p' "$generated/double_pendulum_absolute.cpp" | head -n 14

echo
echo "== simulate 10 s: $sim double_pendulum --out out/double_pendulum.csv"
"$sim" double_pendulum --out out/double_pendulum.csv

echo
echo "== theta1 and theta2 (rad) over time (s)"
gnuplot -e "set terminal dumb size 100,24; set datafile separator ','; set key below;
  set xlabel 't (s)'; set ylabel 'rad';
  plot 'out/double_pendulum.csv' using 1:2 with lines title 'theta1',
       '' using 1:3 with lines title 'theta2'"

echo
echo "== the trike settles on its tyres, then turns: animation and plot"
"$sim" trike --out out/trike.csv --html out/trike.html --glb out/trike.glb | tail -n 3
gnuplot -e "csv='out/trike.csv'; png='out/trike.png'" scripts/lib/trike_plot.gp
echo "  wrote out/trike.png"
echo
echo "Open out/trike.html in a browser (play, scrub, orbit with the mouse; no network needed),"
echo "out/trike.glb in Blender or any glTF viewer, out/trike.png in an image viewer."
