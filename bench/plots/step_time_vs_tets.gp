# Seconds per step against tet count: full order (fom_scaling.csv), the reduced model integrating
# every element (exact) and the reduced model with cubature (rom.csv), at r = 8, 16, 32, 64 linear
# modes. Points: medians; error bars: the fastest and slowest step (X_min .. X_max).
# Writes step_time_vs_tets.png beside the CSVs.
load "bench/plots/common.gp"

fom = dir."/fom_scaling.csv"
rom = dir."/rom.csv"
set output dir."/step_time_vs_tets.png"

set title "Time per step against mesh size (make bench: bench_fom, bench_rom)\nmedian of single steps; error bars: fastest..slowest step" noenhanced
set xlabel "tets"
set ylabel "seconds per step"
set logscale xy
set format x "%.0s%c"
set key outside right top vertical title "r: reduced size (linear modes)" noenhanced
set xrange [700:600000]

array R[4] = [8, 16, 32, 64]
array rc[4] = ["#6baed6", "#3182bd", "#08519c", "#08306b"]
array cc[4] = ["#fc9272", "#ef3b2c", "#a50f15", "#67000d"]

plot rows(fom, "", "") using "tets":"s_per_step":"s_per_step_min":"s_per_step_max" with yerrorlines \
        lw 2.5 lc rgb "black" pt 5 ps 1.1 title "full order", \
     for [i=1:4] rows(rom, "r", sprintf("%d", R[i])) \
        using "tets":"exact_s_per_step":"exact_s_per_step_min":"exact_s_per_step_max" with yerrorlines \
        dt 2 lw 1.8 lc rgb rc[i] pt 6 ps 1.0 title sprintf("reduced exact, r = %d", R[i]), \
     for [i=1:4] rows(rom, "r", sprintf("%d", R[i])) \
        using "tets":"cubature_s_per_step":"cubature_s_per_step_min":"cubature_s_per_step_max" with yerrorlines \
        dt 1 lw 1.8 lc rgb cc[i] pt 7 ps 1.0 title sprintf("reduced with cubature, r = %d", R[i])
