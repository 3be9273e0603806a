# Shape optimisation of a lift through the neural DMD's jump (issue 35; koopman-dmd-log-linear
# paper, Sec. 7.4, Fig. 16): a pneumatic finger family (examples/shape_family/member.sh) whose code
# is the chamber's length and its bottom wall's thickness, moved in the family's "shape" by keys of
# the scene (whole cells: "step"), each member a full-order run under 3e4 Pa held from t = 0. The
# model is trained on five members, two more held out (their largest lift error is the model's own); from a
# short chamber with a thick wall it finds the code that lifts the tip most after 20 steps. Full
# order at the optimum (the scene --scene-out writes) must confirm the rise over the start, by
# more than the model's own error, and match the model's prediction there within 1.5 times that
# error (measured 1.0 times). Bad "shape" keys are refused naming the key. About 9 s of CPU.
. tests/lib.sh
M=examples/shape_family/member.sh
export STEPS=20
# member NAME G0 G1: the scene at code (G0, G1) and its full-order run.
member() {
    sh "$M" "$2" "$3" >"$TMP/$1.json"
    "$ROMKIT" fom "$TMP/$1.json" --snapshots "$TMP/$1.npy" --quiet >/dev/null 2>"$TMP/err" || fail "fom_$1" "$(cat "$TMP/err")"
}
member m00 0 0; member m10 1 0; member m01 0 1; member m11 1 1; member m55 0.5 0.5; member h65 0.6 0.5; member h80 0.8 0; member start 0.2 1
sh "$M" 0 0 >"$TMP/finger.json"
# family [EXTRA]: the family file (EXTRA: more keys of "shape", for the bad-input checks).
family() {
    cat <<EOF2
{"members": [{"scene": "m00.json", "snapshots": "m00.npy", "gamma": [0, 0]},
             {"scene": "m10.json", "snapshots": "m10.npy", "gamma": [1, 0]},
             {"scene": "m01.json", "snapshots": "m01.npy", "gamma": [0, 1]},
             {"scene": "m11.json", "snapshots": "m11.npy", "gamma": [1, 1]},
             {"scene": "m55.json", "snapshots": "m55.npy", "gamma": [0.5, 0.5]},
             {"scene": "h65.json", "snapshots": "h65.npy", "gamma": [0.6, 0.5], "held_out": true},
             {"scene": "h80.json", "snapshots": "h80.npy", "gamma": [0.8, 0], "held_out": true}],
 "rank": 8, "training": {"epochs": 50, "window": 10}, "seed": 1,
 "shape": {"scene": "finger.json", "keys": [$1
   {"key": "objects[0].mesh.voids[0].box[1][0]", "per_gamma": [0.025, 0], "step": 0.005, "range": [0.02, 0.075]},
   {"key": "objects[0].chambers[0].box[1][0]", "per_gamma": [0.025, 0], "step": 0.005},
   {"key": "objects[0].mesh.voids[0].box[0][1]", "per_gamma": [0, 0.005], "step": 0.0025},
   {"key": "objects[0].chambers[0].box[0][1]", "per_gamma": [0, 0.005], "step": 0.0025}]}}
EOF2
}
family >"$TMP/family.json"
TIP=0.0795,-1,-1,0.081,1,1
# lift FILE.npy: the mean y displacement at step 20 of the vertices at rest x >= 0.0795 (the tip).
lift() {
    npy_values "$1" | awk '{ v[NR - 1] = $1 } END {
        n3 = 0; while ((n3 in v)) n3++; n3 = n3 / 21                   # 21 frames: rest, then 20 steps
        for (i = 0; i < n3; i += 3) if (v[i] >= 0.0795) { s += v[20 * n3 + i + 1] - v[i + 1]; k++ }
        if (k) printf "%.9g\n", s / k }'
}
if "$ROMKIT" neural-dmd "$TMP/family.json" --lift "$TIP" --steps 20 --gamma-start 0.2,1 -o "$TMP/opt.rombin" \
        --scene-out "$TMP/opt.json" --report "$TMP/opt_report.json" >"$TMP/out" 2>"$TMP/err"; then
    sed 's/^/# /' "$TMP/out"
    json_checks shape_lift_report "$TMP/opt_report.json" shape_optimization.objective='"lift"' \
        'shape_optimization.gamma[1]' 'shape_optimization.history[0]' shape_optimization.value_start \
        shape_optimization.held_out_lift_relative_error 'shape_optimization.members[5].lift_full_order' neural.held_out=2
    R=shape_optimization
    pstart=$(json_num "$TMP/opt_report.json" $R.value_start); popt=$(json_num "$TMP/opt_report.json" $R.value)
    own=$(json_num "$TMP/opt_report.json" $R.held_out_lift_relative_error)
    "$ROMKIT" fom "$TMP/opt.json" --snapshots "$TMP/opt.npy" --quiet >/dev/null 2>"$TMP/err" || fail shape_lift_fom "$(cat "$TMP/err")"
    fstart=$(lift "$TMP/start.npy"); fopt=$(lift "$TMP/opt.npy")
    echo "# lift after 20 steps: model $pstart m at the start (0.2, 1), $popt m at the optimum; full order $fstart m and $fopt m; the model's own error (held-out member) $own"
    # the model's optimum is above its start
    awk -v a="$popt" -v b="$pstart" 'BEGIN { exit !(a > b) }' && ok shape_lift_model_rises \
        || fail shape_lift_model_rises "the model's lift $pstart m at the start, $popt m at the optimum"
    # full order rises by more than the model's own error could explain: the start's full-order
    # lift grown by that error is still below the optimum's shrunk by it
    awk -v s="$fstart" -v o="$fopt" -v e="$own" 'BEGIN { exit !(s != "" && o != "" && e != "" && s * (1 + e) < o * (1 - e)) }' \
        && ok shape_lift_full_order_confirms_the_rise \
        || fail shape_lift_full_order_confirms_the_rise "full order $fstart m at the start, $fopt m at the optimum, own error $own"
    # and the model's lift at the optimum is the full-order one within about the model's own
    # error. Measured (seed 1): the optimum (0.794, 0) has held-out h80's mesh (the keys round to
    # whole cells), 5.2% off there against an own error of 5.2% (h80's, the larger of two): bound 1.5
    # times. An earlier family (m55 on a jagged part-cell void) put it 12.0% off against 11.5%
    awk -v p="$popt" -v o="$fopt" -v e="$own" 'BEGIN { d = (p - o) / o; if (d < 0) d = -d; exit !(o != "" && d <= 1.5 * e) }' \
        && ok shape_lift_prediction_within_own_error \
        || fail shape_lift_prediction_within_own_error "model $popt m, full order $fopt m, own error $own"
else
    fail shape_lift_report "$(cat "$TMP/err")"
fi

# Bad keys: refused naming the key and what is wrong, before any training.
bad() { family "$1" >"$TMP/bad.json"; "$ROMKIT" neural-dmd "$TMP/bad.json" --lift "$TIP" --steps 20 -o "$TMP/bad.rombin" --quiet; }
expect_fail shape_key_unknown "shape.keys\[0\]: key 'objects\[0\].mesh.void\[0\].box\[1\]\[0\]' .*unknown key: no \"void\"" \
    bad '{"key": "objects[0].mesh.void[0].box[1][0]", "per_gamma": [0.01, 0]},'
expect_fail shape_key_not_a_number "key 'objects\[0\].material.model' .* is not a number" \
    bad '{"key": "objects[0].material.model", "per_gamma": [0.01, 0]},'
expect_fail shape_key_index_out_of_range "key 'objects\[0\].mesh.voids\[1\].box\[0\]\[0\]' .*index 1 is out of range" \
    bad '{"key": "objects[0].mesh.voids[1].box[0][0]", "per_gamma": [0.01, 0]},'
expect_fail shape_key_outside_its_range "key 'objects\[0\].mesh.box.size\[0\]' goes from 0.08 to 0.13 .*outside its range \[0.05, 0.1\]" \
    bad '{"key": "objects[0].mesh.box.size[0]", "per_gamma": [0.05, 0], "range": [0.05, 0.1]},'
expect_fail shape_key_per_gamma_length "shape.keys\[0\]" \
    bad '{"key": "objects[0].mesh.box.size[0]", "per_gamma": [0.05]},'
[ ! -e "$TMP/bad.rombin" ] && ok shape_key_nothing_written || fail shape_key_nothing_written "bad.rombin written"
