# Two chambers in one finger (issue 35): a 8 x 2 x 3 cm neo-Hookean finger clamped at its base with
# two voids placed mirror-wise about its middle plane z = 1.5 cm, walls c_lo (z 0.5-1 cm) and c_hi
# (z 2-2.5 cm), 2e4 Pa, three steps. Each chamber alone bends the tip one way in z by about as much,
# both at once hold it nearly straight, and two chambers of one name are refused: the chambers'
# faces and pressures are kept apart. The box's tets are not mirror-symmetric, so the two bends
# differ by the discretization: 17% on 16 x 4 x 6 cells, 3.3% on these 32 x 8 x 12 (both at once:
# 19% and 3.2% of one alone); the bars are 10%. About 4 s.
. tests/lib.sh

finger() { # finger FILE P_LO P_HI
    cat >"$1" <<JSON
{
  "objects": [{
    "mesh": {"box": {"size": [0.08, 0.02, 0.03], "cells": [32, 8, 12]},
             "voids": [{"box": [[0.0101, 0.0051, 0.0051], [0.0699, 0.0149, 0.0099]]},
                       {"box": [[0.0101, 0.0051, 0.0201], [0.0699, 0.0149, 0.0249]]}]},
    "material": {"model": "neohookean", "young": 5e5, "poisson": 0.45, "density": 1000},
    "fixed": [{"box": [[-0.001, -1, -1], [0.001, 1, 1]]}],
    "chambers": [{"name": "c_lo", "box": [[0.0095, 0.0045, 0.0045], [0.0705, 0.0155, 0.0105]], "pressure": $2},
                 {"name": "c_hi", "box": [[0.0095, 0.0045, 0.0195], [0.0705, 0.0155, 0.0255]], "pressure": $3}]
  }],
  "damping": {"mass": 10},
  "time": {"step": 0.01, "duration": 0.03}
}
JSON
}
# tip_dz NPY: the tip's (x = 8 cm) mean z displacement in the last frame, metres
tip_dz() {
    npy_values "$1" | awk -v nv="$2" '{ i = NR - 1; f = int(i / (3 * nv)); v = int(i / 3) % nv; c = i % 3
        if (f == 0) { X[v, c] = $1; next }
        if (c == 2) last[v] = $1 } END { for (v = 0; v < nv; v++) if (X[v, 0] > 0.0799) { s += last[v] - X[v, 2]; n++ }
        printf "%.6g\n", s / n }'
}
for run in "lo 2e4 0" "hi 0 2e4" "both 2e4 2e4"; do
    set -- $run
    finger "$TMP/$1.json" "$2" "$3"
    "$ROMKIT" fom "$TMP/$1.json" --snapshots "$TMP/$1.npy" --quiet >/dev/null 2>"$TMP/$1.err" || fail "two_chambers_$1_runs" "$(cat "$TMP/$1.err")"
done
nv=$(npy_shape "$TMP/lo.npy" | cut -d, -f2 | tr -d ' ')
lo=$(tip_dz "$TMP/lo.npy" "$nv") hi=$(tip_dz "$TMP/hi.npy" "$nv") both=$(tip_dz "$TMP/both.npy" "$nv")
echo "# tip z displacement: c_lo alone $lo m, c_hi alone $hi m, both $both m"
awk -v a="$lo" -v b="$hi" 'BEGIN { exit !(a * b < 0 && (a > 0 ? a : -a) > 1e-4 && (a + b > 0 ? a + b : -a - b) < 0.1 * (a > 0 ? a : -a)) }' \
    && ok two_chambers_bend_the_finger_opposite_ways_alike || fail two_chambers_bend_the_finger_opposite_ways_alike "c_lo $lo, c_hi $hi m"
awk -v a="$lo" -v c="$both" 'BEGIN { exit !((c > 0 ? c : -c) < 0.1 * (a > 0 ? a : -a)) }' \
    && ok two_chambers_together_hold_the_tip_straight || fail two_chambers_together_hold_the_tip_straight "both $both m against $lo m"
sed 's/"name": "c_hi"/"name": "c_lo"/' "$TMP/lo.json" >"$TMP/dup.json"
expect_fail two_chambers_with_one_name_are_refused "c_lo" "$ROMKIT" fom "$TMP/dup.json" --snapshots "$TMP/dup.npy" --quiet
