# The trike's run as the demo tells it (scripts/demo.sh): it settles on its
# tyres, then turns. Four panels, each quantity in its unit:
#   the path seen from above (m, equal scales, a dot each second),
#   the chassis height settling (m) and the tyres' normal forces (kN),
#   the steering and the roll (deg),
#   the forward speed (m/s) and the yaw rate (deg/s).
# Usage: gnuplot -e "csv='out/trike.csv'; png='out/trike.png'" scripts/lib/trike_plot.gp
# (and optionally width=..., height=... in pixels, 1400 x 1000 by default).
# The CSV is symdyn-sim's of models/scenarios/trike.json (its columns by name).

if (!exists("width")) width = 1400
if (!exists("height")) height = 1000
set terminal pngcairo size width,height font ",11" noenhanced
set output png
set datafile separator ','
set key top left box opaque samplen 2
set grid lc rgb '#dddddd'
set border lc rgb '#555555'
deg = 180 / pi
# Tableau's ten, told apart by most eyes.
blue = '#4e79a7'; orange = '#f28e2b'; green = '#59a14f'; red = '#e15759'; purple = '#b07aa1'
set style line 1 lc rgb blue lw 2
set style line 2 lc rgb orange lw 2
set style line 3 lc rgb green lw 2
set style line 4 lc rgb red lw 2
set style line 5 lc rgb purple lw 2
set style line 6 lc rgb orange lw 2 dt 2

set multiplot layout 2,2 title 'trike: settles on its tyres, then turns (steering from t = 1 s)' font ",14"

set title 'path of the chassis seen from above (a dot each second)'
set xlabel 'x (m)'
set ylabel 'y (m)'
set size ratio -1
plot csv using 'x':'y' with lines ls 1 title 'chassis centre', \
     '' every 100 using 'x':'y' with points ls 4 pt 7 ps 1.2 title 't = 0, 1, 2, ... s'
set size noratio

set title 'settling on the tyres'
set key bottom right
set xlabel 't (s)'
set ylabel 'chassis height (m)'
set y2label 'normal force (kN)'
set ytics nomirror
set y2tics
plot csv using 't':'z' with lines ls 1 title 'chassis height (m, left)', \
     '' using 't':(column('normal_force_front') / 1000) axes x1y2 with lines ls 2 title 'front tyre (kN, right)', \
     '' using 't':(column('normal_force_rear_left') / 1000) axes x1y2 with lines ls 3 title 'rear left tyre (kN, right)', \
     '' using 't':(column('normal_force_rear_right') / 1000) axes x1y2 with lines ls 5 title 'rear right tyre (kN, right)'
unset y2tics
unset y2label
set ytics mirror

set title 'steering and roll'
set key center right
set ylabel 'angle (deg)'
plot csv using 't':(column('steer') * deg) with lines ls 1 title 'steering angle', \
     '' using 't':(column('steering_reference') * deg) with lines ls 6 title 'steering reference', \
     '' using 't':(column('roll') * deg) with lines ls 4 title 'chassis roll'

set title 'speed and turning'
set key bottom right
set ylabel 'forward speed (m/s)'
set y2label 'yaw rate (deg/s)'
set ytics nomirror
set y2tics
plot csv using 't':'forward_speed' with lines ls 1 title 'forward speed (m/s, left)', \
     '' using 't':(column('yaw_dot') * deg) axes x1y2 with lines ls 4 title 'yaw rate (deg/s, right)'

unset multiplot
