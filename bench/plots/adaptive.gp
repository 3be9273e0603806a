# The adaptive subspace bench (bench_adaptive, issue 18), four panels:
#  a  thresholds (paper Fig. 12): the final state's distance from full order and the full-space
#     Newton step left at each answer, against eps_G (nodal and modal together, nodal alone)
#  b  thresholds: the share of the mesh enriched and the active columns against eps_G
#  c  stiffness (Fig. 14/16): enrichment against Young's modulus, and PCG iterations of our
#     Schur complement beside full-space block-Jacobi CG on the same iterate
#  d  speed (Table 1, 3): seconds per step of full order and adaptive against tets (points:
#     medians over the steps; error bars: fastest..slowest step), and the linear solve
# Writes adaptive.png beside the CSVs.
load "bench/plots/common.gp"

th = dir."/adaptive_thresholds.csv"
st = dir."/adaptive_stiffness.csv"
sp = dir."/adaptive_speed.csv"
set output dir."/adaptive.png"
set terminal pngcairo size 1600,1100 enhanced font "DejaVu Sans,11" linewidth 1.2
set multiplot layout 2,2 title "Adaptive subspaces with an oracle and nodal enrichment (make bench: bench_adaptive; one thread)" noenhanced

tol = system("awk -F, 'NR==2{for(i=1;i<=NF;i++);} NR==1{for(i=1;i<=NF;i++)c[$i]=i} NR==2{print $c[\"newton_tol\"]}' '".th."'") + 0

set title "a. accuracy against the error threshold (soft slab on a sphere, 10k tets)" noenhanced
set xlabel "eps_G"
set ylabel "difference / diagonal;  full-space residual |d|/h (m/s)"
set logscale xy
set xrange [5e-7:0.2]
set key bottom right
plot rows(th, "vary", "both") using "eps_g":"difference" with linespoints lw 2 pt 7 lc rgb palette[1] title "final-state difference, nodal and modal", \
     rows(th, "vary", "nodal") using "eps_g":"difference" with linespoints lw 1.5 dt 2 pt 6 lc rgb palette[1] title "final-state difference, nodal only", \
     rows(th, "vary", "both") using "eps_g":"residual_mean" with linespoints lw 2 pt 5 lc rgb palette[2] title "full-space residual, nodal and modal", \
     rows(th, "vary", "nodal") using "eps_g":"residual_mean" with linespoints lw 1.5 dt 2 pt 4 lc rgb palette[2] title "full-space residual, nodal only", \
     tol with lines dt 3 lc rgb "black" title "Newton tolerance"

set title "b. model size against the error threshold" noenhanced
set ylabel "enriched share of the vertices"
unset logscale y
set format y "%.1f"
set y2label "active columns"
set y2tics
set yrange [0:1.05]
set key top right
plot rows(th, "vary", "both") using "eps_g":"enriched_share" with linespoints lw 2 pt 7 lc rgb palette[3] title "enriched share (nodal and modal)", \
     rows(th, "vary", "nodal") using "eps_g":"enriched_share" with linespoints lw 1.5 dt 2 pt 6 lc rgb palette[3] title "enriched share (nodal only)", \
     rows(th, "vary", "both") using "eps_g":"modes" axes x1y2 with linespoints lw 2 pt 5 lc rgb palette[4] title "columns (nodal and modal)", \
     rows(th, "vary", "modal") using "eps_g":"modes" axes x1y2 with linespoints lw 1.5 dt 2 pt 4 lc rgb palette[4] title "columns (modal only)"
unset y2tics
unset y2label

set title "c. stiffness: enrichment and iterations (eps_G fixed)" noenhanced
set xlabel "Young's modulus (Pa)"
set ylabel "PCG iterations at the contact step's first iteration"
set logscale xy
set format y "10^{%T}"
set xrange [5e4:2e9]
set yrange [*:*]
set y2label "enriched share of the vertices"
set y2tics
set format y2 "%.2f"
set key top center
plot rows(st, "", "") using "young":"probe_bjcg_iterations" with linespoints lw 2 pt 7 lc rgb palette[2] title "full-space block-Jacobi CG", \
     rows(st, "", "") using "young":(column("probe_schur_iterations") > 0 ? column("probe_schur_iterations") : NaN) with linespoints lw 2 pt 5 lc rgb palette[1] title "ours: Schur complement PCG", \
     rows(st, "", "") using "young":"enriched_share" axes x1y2 with linespoints lw 1.5 dt 2 pt 6 lc rgb palette[3] title "enriched share (right)"
unset y2tics
unset y2label

set title "d. time per step and per linear solve against mesh size" noenhanced
set xlabel "tets"
set ylabel "seconds"
set logscale xy
set xrange [1.5e4:2.5e5]
set format x "%.0s%c"
set key top left
plot rows(sp, "", "") using "tets":"fom_s_per_step":"fom_s_per_step_min":"fom_s_per_step_max" with yerrorlines lw 2.5 pt 5 lc rgb "black" title "full order (CHOLMOD), s/step", \
     rows(sp, "", "") using "tets":"s_per_step":"s_per_step_min":"s_per_step_max" with yerrorlines lw 2 pt 7 lc rgb palette[1] title "adaptive, s/step", \
     rows(sp, "", "") using "tets":"no_downdate_s_per_step" with linespoints lw 1.5 dt 2 pt 6 lc rgb palette[1] title "adaptive without downdating, s/step", \
     rows(sp, "", "") using "tets":"probe_cholmod_s" with linespoints lw 1.5 pt 4 lc rgb "#555555" title "one solve: CHOLMOD", \
     rows(sp, "", "") using "tets":"probe_bjcg_s" with linespoints lw 1.5 pt 8 lc rgb palette[2] title "one solve: block-Jacobi CG", \
     rows(sp, "", "") using "tets":"probe_schur_s" with linespoints lw 1.5 pt 9 lc rgb palette[3] title "one solve: ours (Schur PCG)"
unset multiplot
