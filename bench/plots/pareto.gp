# Error against time per step (a Pareto chart), every method and size, log-log. Two panels:
#
# left   make bench (rom.csv): on each bench mesh, the reduced model integrating every element
#        (exact, open circles, dashed) and with cubature (filled, solid) at r = 8, 16, 32, 64
#        linear modes (the labels), against the full-order run: relative error of the positions
#        over the first error_frames steps from rest (bench_rom_error). x: median s/step, error
#        bars fastest..slowest step. The full-order model (error 0) sits on the bottom edge.
# right  make paper-table (paper_table_{bend,twist}.json, from romkit compare, if present): the
#        FreeForm beam tests, every method's normalized MSE against its s/step (one run, no
#        spread); dashed verticals: the full-order s/step of each test. Colour: the test; point type:
#        the method (the legend).
# Writes pareto.png beside the CSVs.
load "bench/plots/common.gp"

rom = dir."/rom.csv"
set output dir."/pareto.png"
set terminal pngcairo size 1800,850 enhanced font "DejaVu Sans,11" linewidth 1.2

cases = system("awk -F, 'NR==1{for(i=1;i<=NF;i++)c[$i]=i;next} !s[$1]++{print $c[\"tets\"]\" \"$1}' '" . rom . "' | sort -n | awk '{printf \"%s \", $2}'")
nc = words(cases)

# the smallest error drawn: the full-order points sit at a third of it
stats rom using "exact_error" nooutput
emin = STATS_min
stats rom using "cubature_error" nooutput
emin = (STATS_min < emin ? STATS_min : emin)
floor = emin / 3.0

set multiplot layout 1,2 title "Error against time per step (make bench, make paper-table)" font ",14"

# ---- left: bench meshes
set title "bench meshes (rom.csv): relative position error vs full order over the first steps\nlabels: r; open/dashed: exact, filled/solid: cubature; error bars: fastest..slowest step" noenhanced
set xlabel "seconds per step (median)"
set ylabel "relative error vs full order"
set logscale xy
set yrange [floor / 2:*]
set key outside bottom center horizontal maxcols 5 noenhanced font ",10"
set lmargin 10
set bmargin 10

plot for [i=1:nc] rows(rom, "case", word(cases, i)) \
        using "exact_s_per_step":"exact_error":"exact_s_per_step_min":"exact_s_per_step_max" with xerrorbars \
        pt 6 ps 1.2 lc rgb palette[(i - 1) % 8 + 1] notitle, \
     for [i=1:nc] rows(rom, "case", word(cases, i)) \
        using "exact_s_per_step":"exact_error" with lines dt 2 lc rgb palette[(i - 1) % 8 + 1] notitle, \
     for [i=1:nc] rows(rom, "case", word(cases, i)) \
        using "cubature_s_per_step":"cubature_error":"cubature_s_per_step_min":"cubature_s_per_step_max" \
        with xerrorbars pt 7 ps 1.2 lc rgb palette[(i - 1) % 8 + 1] notitle, \
     for [i=1:nc] rows(rom, "case", word(cases, i)) \
        using "cubature_s_per_step":"cubature_error" with lines dt 1 lw 1.5 lc rgb palette[(i - 1) % 8 + 1] \
        title word(cases, i), \
     rows(rom, "", "") using "cubature_s_per_step":"cubature_error":(sprintf("%d", column("r"))) with labels \
        offset char 0.9,0.5 font ",8" tc rgb "#444444" noenhanced notitle, \
     rows(rom, "", "") using "exact_s_per_step":"exact_error":(sprintf("%d", column("r"))) with labels \
        offset char 0.9,0.5 font ",8" tc rgb "#444444" noenhanced notitle, \
     for [i=1:nc] rows(rom, "case", word(cases, i)) \
        using "fom_s_per_step":(floor):"fom_s_per_step_min":"fom_s_per_step_max" every ::0::0 with xerrorbars \
        pt 3 ps 1.8 lw 1.5 lc rgb palette[(i - 1) % 8 + 1] notitle, \
     keyentry with points pt 6 lc rgb "black" title "exact", \
     keyentry with points pt 7 lc rgb "black" title "cubature", \
     keyentry with points pt 3 ps 1.8 lc rgb "black" title "full order (error 0, on the edge)"

# ---- right: the paper's beam tests
unset yrange
set bmargin 10
set title "FreeForm beam tests (make paper-table: romkit compare, 1,920 tets)\nnormalized MSE over all frames against s/step (one run each); dashed: full order" noenhanced
set ylabel "normalized MSE"
set xlabel "seconds per step"
set key outside bottom center horizontal maxcols 3 noenhanced font ",10"
set offsets graph 0.1, graph 0.1, 0, 0

# "name,seconds_per_step,normalized_mse" per method (the method's own, not its paper reference),
# "fom" first, from a romkit compare report.
methods(f) = "< awk 'BEGIN{print \"name,s,nmse\"} /\"methods\"/{m=1} m&&/\"name\":/{gsub(/[\",\\t]/,\"\",$2); n=$2; s=\"\"; e=\"\"}" . \
             " m&&/\"seconds_per_step\":/&&s==\"\"{gsub(/[,\\t]/,\"\",$2); s=$2}" . \
             " m&&/\"normalized_mse\":/&&e==\"\"{gsub(/[,\\t]/,\"\",$2); e=$2}" . \
             " n!=\"\"&&s!=\"\"&&e!=\"\"{print n\",\"s\",\"e; n=\"\"}' '" . f . "'"
bend = dir."/paper_table_bend.json"
twist = dir."/paper_table_twist.json"
have(f) = system("test -s '" . f . "' && echo 1 || echo 0") + 0
fom_s(f) = system(substr(methods(f), 3, strlen(methods(f))) . " | awk -F, '$1==\"fom\"{print $2}'") + 0
# the reduced methods (every name but fom), in the report's order: one point type each
names(f) = system(substr(methods(f), 3, strlen(methods(f))) . " | awk -F, 'NR>1&&$1!=\"fom\"{printf \"%s \", $1}'")
array pts[12] = [7, 5, 9, 11, 13, 15, 1, 2, 3, 4, 6, 8]
ptype(name, list) = pts[(strstrt(" " . list, " " . name . " ") ? words(substr(" " . list, 1, strstrt(" " . list, " " . name . " "))) : 0) % 12 + 1]

if (have(bend) && have(twist)) {
    mn = names(bend)
    nm = words(mn)
    set arrow 1 from fom_s(bend), graph 0 to fom_s(bend), graph 1 nohead dt 2 lw 1.5 lc rgb "#1f77b4"
    set arrow 2 from fom_s(twist), graph 0 to fom_s(twist), graph 1 nohead dt 2 lw 1.5 lc rgb "#d62728"
    plot methods(bend) using (strcol("name") eq "fom" ? NaN : $2):3:(ptype(strcol("name"), mn)) \
            with points pt variable ps 1.6 lc rgb "#1f77b4" notitle, \
         methods(twist) using (strcol("name") eq "fom" ? NaN : $2):3:(ptype(strcol("name"), mn)) \
            with points pt variable ps 1.6 lc rgb "#d62728" notitle, \
         keyentry with points pt 7 ps 1.6 lc rgb "#1f77b4" title "bend (1 s)", \
         keyentry with points pt 7 ps 1.6 lc rgb "#d62728" title "twist (720°, 2 s)", \
         keyentry with lines dt 2 lw 1.5 lc rgb "black" title "full order (bend, twist)", \
         for [i=1:nm] keyentry with points pt ptype(word(mn, i), mn) ps 1.6 lc rgb "black" title word(mn, i)
} else {
    unset logscale
    unset format
    set label 1 "no paper\\_table\\_*.json here: run make paper-table" at graph 0.5, graph 0.5 center
    plot NaN notitle
}
unset multiplot
