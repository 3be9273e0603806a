# The adaptive linear ROM's ablations (bench_alrom.sh, issue 19): total relative online error with
# per-step realignment against r (adaptive and PCA, the paper's Fig. 6), the history window m
# (Table 1) and lambda (Table 2), for the armadillo's compression and bending. Writes alrom.png.
load "bench/plots/common.gp"

src = dir."/alrom.csv"
set output dir."/alrom.png"
set terminal pngcairo size 1600,520 enhanced font "DejaVu Sans,11" linewidth 1.2
set multiplot layout 1,3 title "Adaptive linear ROM against PCA: relative online error (make bench: bench\\_alrom.sh; b and c: CROM decoder)"
# rows of the CSV with scenario s, sweep w, method k, sorted by value
sel(s, w, k) = sprintf("< awk -F, 'NR==1{print;next} $1==\"%s\"&&$2==\"%s\"&&$4==\"%s\"' '%s' | sort -t, -k3,3g", s, w, k, src)

set logscale y
set format y "10^{%T}"
set key top right
set title "a. basis size r (Fig. 6)"
set xlabel "r"
set logscale x 2
set format x "%g"
set xrange [3:40]
plot sel("compress", "r", "adaptive") using "value":"online_error" with linespoints lw 2 pt 7 lc rgb palette[1] title "adaptive (CROM), compression", \
     sel("compress", "r", "pca") using "value":"online_error" with linespoints lw 2 dt 2 pt 6 lc rgb palette[1] title "PCA, compression", \
     sel("bend", "r", "adaptive") using "value":"online_error" with linespoints lw 2 pt 5 lc rgb palette[2] title "adaptive (CROM), bending", \
     sel("bend", "r", "pca") using "value":"online_error" with linespoints lw 2 dt 2 pt 4 lc rgb palette[2] title "PCA, bending", \
     sel("compress", "r", "adaptive_quadratic_pod") using "value":"online_error" with linespoints lw 2 dt 3 pt 9 lc rgb palette[1] title "adaptive (fitted quadratic), compression", \
     sel("bend", "r", "adaptive_quadratic_pod") using "value":"online_error" with linespoints lw 2 dt 3 pt 11 lc rgb palette[2] title "adaptive (fitted quadratic), bending"

set title "b. history window m (Table 1), r = 16"
set xlabel "m"
unset logscale x
set xrange [0:52]
plot sel("compress", "m", "adaptive") using "value":"online_error" with linespoints lw 2 pt 7 lc rgb palette[1] title "compression", \
     sel("bend", "m", "adaptive") using "value":"online_error" with linespoints lw 2 pt 5 lc rgb palette[2] title "bending"

set title "c. interpolation lambda (Table 2), r = 16"
set xlabel "lambda (1: the decoder's basis alone)"
set xrange [-0.03:0.53]
plot sel("compress", "lambda", "adaptive") using "value":"online_error" with linespoints lw 2 pt 7 lc rgb palette[1] title "compression", \
     sel("bend", "lambda", "adaptive") using "value":"online_error" with linespoints lw 2 pt 5 lc rgb palette[2] title "bending"
unset multiplot
