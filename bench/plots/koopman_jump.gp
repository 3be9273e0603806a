# The runtime's Koopman jump: microseconds for one romrt_jump(N) against N = 1, 1e3, 1e6, per
# mesh and rank r (koopman.csv, section "runtime"), against N x the time of one romrt_step (dashed,
# the cost of stepping there). Points: medians of the samples; error bars: fastest..slowest sample.
# Colour: the rank r; point type: the mesh. Writes koopman_jump.png beside the CSVs.
load "bench/plots/common.gp"

src = dir."/koopman.csv"
set output dir."/koopman_jump.png"

# One block per runtime row, each opening with its header line (with columnheaders set, gnuplot
# reads the first line of every block as one): N, jump us, its min, its max, N x step us.
reshape = "awk -F, 'NR==1{for(i=1;i<=NF;i++)c[$i]=i;next}" . \
          " $c[\"section\"]==\"runtime\"{if(n++)print \"\\n\"; print \"N,jump_us,jump_us_min,jump_us_max,steps_us\"; s=$c[\"step_us\"];" . \
          " split(\"1 1e3 1e6\",J,\" \"); split(\"1 1000 1000000\",N,\" \");" . \
          " for(j=1;j<=3;j++){k=\"jump_\"J[j]\"_us\"; print N[j]\",\"$c[k]\",\"$c[k\"_min\"]\",\"$c[k\"_max\"]\",\"N[j]*s}}' '" . src . "'"
names = system("awk -F, 'NR==1{for(i=1;i<=NF;i++)c[$i]=i;next} $c[\"section\"]==\"runtime\"{printf \"%s:%s \", $c[\"case\"], $c[\"rank\"]}' '" . src . "'")
n = words(names)

set title "Koopman jump against N (make bench: bench_koopman, float32 runtime)\nmedian over repeated samples of 20 calls; error bars: fastest..slowest sample" noenhanced
set xlabel "N (steps advanced)"
set ylabel "microseconds per call"
set logscale xy
set xrange [0.5:2e6]
set format x "10^{%T}"
set key outside right top vertical noenhanced

# word i of names: "CASE:RANK"
name(i) = word(names, i)
case(i) = name(i)[1:strstrt(name(i), ":") - 1]
rank(i) = name(i)[strstrt(name(i), ":") + 1:]

# colour: r (first rank met blue, the next red, ...); point type: the mesh
ranks = system("awk -F, 'NR==1{for(i=1;i<=NF;i++)c[$i]=i;next} $c[\"section\"]==\"runtime\"&&!s[$c[\"rank\"]]++{printf \"%s \", $c[\"rank\"]}' '" . src . "'")
meshes = system("awk -F, 'NR==1{for(i=1;i<=NF;i++)c[$i]=i;next} $c[\"section\"]==\"runtime\"&&!s[$c[\"case\"]]++{printf \"%s \", $c[\"case\"]}' '" . src . "'")
# 1-based position of word w in list (1 when absent)
pos(w, list) = (strstrt(" " . list, " " . w . " ") ? words(substr(" " . list, 1, strstrt(" " . list, " " . w . " "))) + 1 : 1)
array mpt[6] = [7, 5, 9, 11, 13, 15]
colour(i) = palette[(pos(rank(i), ranks) - 1) % 8 + 1]
ptype(i) = mpt[(pos(case(i), meshes) - 1) % 6 + 1]

plot for [i=1:n] "< " . reshape using "N":"jump_us":"jump_us_min":"jump_us_max" index i-1 with yerrorlines \
        lw 1.8 pt ptype(i) ps 1.2 lc rgb colour(i) notitle, \
     for [i=1:n] "< " . reshape using "N":"steps_us" index i-1 with lines dt 2 lw 1 lc rgb colour(i) notitle, \
     for [j=1:words(ranks)] keyentry with lines lw 2 lc rgb palette[(j - 1) % 8 + 1] \
        title sprintf("jump(N), r = %s", word(ranks, j)), \
     for [j=1:words(meshes)] keyentry with points pt mpt[(j - 1) % 6 + 1] ps 1.2 lc rgb "black" title word(meshes, j), \
     keyentry with lines dt 2 lw 1 lc rgb "black" title "N x one step (per mesh and r)"
