#!/bin/sh
# Issue 35's shape optimisation of a lift (koopman-dmd-log-linear paper, Sec. 7.4, Fig. 16) on
# the shipped pneumatic finger family (examples/shape_family: the chamber's length, its bottom
# wall's thickness and its offset toward the tip as a 3-value code, 9 members trained on and 2
# held out, 40 steps under 3e4 Pa each, 757 vertices at the start code): every member run at full
# order, the neural DMD trained, the code that lifts the tip most found from (0.2, 1, 1) by
# romkit neural-dmd --lift, and full order run at the optimum. Writes the objective per
# iteration, the code, the model's and full order's lifts at the start and the optimum, the
# held-out members' errors and the wall seconds with the load before each (above load 3 on this
# 2-core machine a time is not valid: the table says so) to bench/results/shape_family.md.
# Usage: [BUILD=build] sh bench/shape_family.sh
set -e
BUILD=${BUILD:-build}
R=$PWD/$BUILD/romkit
OUT=bench/results/shape_family.md
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
cp examples/shape_family/*.json "$T/"
export ROMKIT_THREADS=${ROMKIT_THREADS:-1} OMP_NUM_THREADS=${OMP_NUM_THREADS:-1} OPENBLAS_NUM_THREADS=${OPENBLAS_NUM_THREADS:-1}
load() { cut -d' ' -f1 /proc/loadavg; }
now() { date +%s.%N; }
sh examples/shape_family/member.sh 0.2 1 1 >"$T/start.json"
l0=$(load); t0=$(now)
for s in "$T"/m*.json "$T/start.json"; do "$R" fom "$s" --snapshots "${s%.json}.npy" --quiet >/dev/null; done
l1=$(load); t1=$(now)
(cd "$T" && "$R" neural-dmd family.json --lift 0.0795,-1,-1,0.081,1,1 --steps 40 --gamma-start 0.2,1,1 \
    -o opt.rombin --scene-out opt.json --report report.json) >"$T/out"
l2=$(load); t2=$(now)
"$R" fom "$T/opt.json" --snapshots "$T/opt.npy" --quiet >/dev/null
# lift FILE.npy: the mean y displacement at step 40 of the vertices at rest x >= 0.0795
lift() {
    od -A n -v -t f8 -j "$(python3 -c "import sys; d=open(sys.argv[1],'rb').read(10); print(10 + d[8] + 256 * d[9])" "$1")" "$1" |
        tr -s ' ' '\n' | sed '/^$/d' | awk '{ v[NR - 1] = $1 } END {
        n3 = NR / 41; for (i = 0; i < n3; i += 3) if (v[i] >= 0.0795) { s += v[40 * n3 + i + 1] - v[i + 1]; k++ }
        printf "%.4g", s / k }'
}
q() { "$BUILD/jsonq" get "$T/report.json" "$1" | awk '{ if ($1 ~ /^-?[0-9.]+([eE][-+]?[0-9]+)?$/) printf "%.4g\n", $1; else print }'; }
fs=$(lift "$T/start.npy"); fo=$(lift "$T/opt.npy")
valid() { awk -v l="$1" 'BEGIN { print (l > 3 ? " (load above 3: not valid)" : "") }'; }
{
    echo "# Shape optimisation of a pneumatic finger's lift (issue 35)"
    echo
    echo "\`sh bench/shape_family.sh\` on examples/shape_family (one thread). The lift: the mean y displacement (m) of the"
    echo "tip's vertices (rest x >= 0.0795 m) 40 steps after 3e4 Pa is applied; the code (chamber length, wall thickness,"
    echo "offset) each in [0, 1]."
    echo
    echo "| iteration | model's lift (m) |"
    echo "|---|---|"
    n=$(q shape_optimization.iterations)
    i=0; while [ "$i" -le "$n" ]; do echo "| $i | $(q "shape_optimization.history[$i]") |"; i=$((i + 1)); done
    echo
    echo "| | code | model's lift (m) | full order's lift (m) |"
    echo "|---|---|---|---|"
    echo "| start | $(q 'shape_optimization.gamma_start[0]'), $(q 'shape_optimization.gamma_start[1]'), $(q 'shape_optimization.gamma_start[2]') | $(q shape_optimization.value_start) | $fs |"
    echo "| optimum | $(q 'shape_optimization.gamma[0]'), $(q 'shape_optimization.gamma[1]'), $(q 'shape_optimization.gamma[2]') | $(q shape_optimization.value) | $fo |"
    echo
    echo "The model's own error (held-out members' lift, largest): $(q shape_optimization.held_out_lift_error) m,"
    echo "$(q shape_optimization.held_out_lift_relative_error) relative."
    echo
    echo "Every member (the model's lift against its own full-order run; the last two held out):"
    echo
    echo "| member | code | model's lift (m) | full order's lift (m) |"
    echo "|---|---|---|---|"
    for k in 0 1 2 3 4 5 6 7 8 9 10; do
        echo "| $k$( [ "$(q "shape_optimization.members[$k].held_out")" = true ] && echo ' (held out)') | $(q "shape_optimization.members[$k].gamma[0]"), $(q "shape_optimization.members[$k].gamma[1]"), $(q "shape_optimization.members[$k].gamma[2]") | $(q "shape_optimization.members[$k].lift_model") | $(q "shape_optimization.members[$k].lift_full_order") |"
    done
    echo
    echo "| stage | wall s | load before |"
    echo "|---|---|---|"
    echo "| 12 full-order runs (11 members, the start) | $(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.1f", b - a }') | $l0$(valid "$l0") |"
    echo "| training ($(q neural.final_loss) final loss) and the optimisation ($(q shape_optimization.evaluations) evaluations) | $(awk -v a="$t1" -v b="$t2" 'BEGIN { printf "%.1f", b - a }') | $l1$(valid "$l1") |"
    echo "| of which the optimisation | $(q shape_optimization.seconds) | |"
} >"$OUT"
cat "$OUT"
