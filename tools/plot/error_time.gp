# Error against time per step (log-log), one point per method, the full-order step as a line.
# gnuplot -e "data='summary.dat'; fom=0.6; out='error_time.png'" tools/plot/error_time.gp
# data columns: name, seconds per step, relative error, normalized MSE
set terminal pngcairo size 760,480 font "sans,10"
set output out
set logscale xy
set format x "10^{%L}"
set format y "10^{%L}"
set xlabel "runtime seconds per step (float32, median)"
set ylabel "relative error against full order"
set grid
set key top right
set arrow from fom, graph 0 to fom, graph 1 nohead lc rgb "#aa3333" dt 2
set label "full order" at fom, graph 0.95 right offset -0.5, 0 tc rgb "#aa3333"
set offsets graph 0.1, graph 0.3, graph 0.2, graph 0.2
plot data using 2:3 with points pt 7 ps 1.6 lc rgb "#3366aa" notitle, \
     data using 2:3:1 with labels offset 0, 1.1 font "sans,9" noenhanced notitle
