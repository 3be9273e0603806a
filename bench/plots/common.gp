# Shared settings of the make-bench charts (bench/plots/*.gp), loaded by each script.
# The scripts run from the repository root (make bench-plots) and read the CSVs of `make bench`
# from `dir` (default bench/results), writing their PNG beside them:
#   gnuplot -e "dir='/tmp/results'" bench/plots/pareto.gp
# Spread convention of every CSV: a timing column X is the median of its samples, X_min and X_max
# the fastest and slowest sample; error bars are drawn from X_min to X_max.

if (!exists("dir")) dir = "bench/results"

set datafile separator comma
set datafile columnheaders
set terminal pngcairo size 1200,800 enhanced font "DejaVu Sans,11" linewidth 1.2
set grid xtics ytics mxtics mytics lc rgb "#dddddd" lw 0.6
set border lw 1
set key box opaque samplen 2 spacing 1.1
set format x "10^{%T}"
set format y "10^{%T}"

# The rows of CSV `file` whose column named `col` equals `val` (as text; col "" keeps every row),
# sorted by the column "tets", header first: a stream gnuplot reads like the file itself.
rows(file, col, val) = sprintf("< awk -F, -v k='%s' -v v='%s' 'NR==1{for(i=1;i<=NF;i++)c[$i]=i;print \"-1,\"$0;next} k==\"\"||$c[k]==v{print $c[\"tets\"]\",\"$0}' '%s' | sort -t, -s -k1,1g | cut -d, -f2-", col, val, file)

# Colours for up to 8 series (cases, r values), dark enough to read on white.
array palette[8] = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#8c564b", "#e377c2"]
