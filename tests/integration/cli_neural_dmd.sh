# romkit neural-dmd (issue 20; koopman-dmd-log-linear paper, Sec. 5): a family of three cantilever
# beams whose thickness is the shape code gamma (0.14, 0.20, 0.26 m), each run at full order by
# romkit fom --snapshots, the neural DMD trained on them and baked at an unseen thickness
# (0.17 m) on that thickness's own mesh, stepped by romkit run against its own full-order run.
# Beside it: the same model baked at the nearest member's code (0.14) on the same mesh, which
# shows that the code is what carries the shape, and a classical DMD (romkit dmd) fitted on the
# unseen beam's own run, the best a DMD of that rank can do with the answer in hand. Then: the
# same seed gives the same asset, the report's keys, the shape optimisation (Sec. 7.4) checked
# against a full-order run at the thickness it finds, and bad input refused with nothing written.
. tests/lib.sh
g3() { if [ -n "$1" ]; then printf '%.3g' "$1"; else printf '?'; fi; }

# beam NAME THICKNESS: a 1 m cantilever, 6 x 2 x 1 cells, sagging under gravity for 1 s.
beam() {
    cat >"$TMP/$1.json" <<EOF
{"objects": [{"mesh": {"box": {"size": [1, $2, 0.2], "cells": [6, 2, 1]}},
  "material": {"model": "neohookean", "young": 5e6, "poisson": 0.35, "density": 1000},
  "fixed": [{"box": [[-1, -1, -1], [0.001, 1, 1]]}]}],
 "gravity": [0, -9.81, 0], "damping": {"mass": 0.5, "stiffness": 0.002},
 "time": {"step": 0.01, "duration": 1.0}}
EOF
    "$ROMKIT" fom "$TMP/$1.json" --snapshots "$TMP/$1.npy" --quiet >/dev/null 2>"$TMP/err" || fail "fom_$1" "$(cat "$TMP/err")"
}
beam b14 0.14; beam b20 0.20; beam b26 0.26; beam b17 0.17

# family MEMBER2_SNAPSHOTS MEMBER2_GAMMA [MORE_KEYS]: the family file (relative paths: next to it).
family() {
    cat <<EOF
{"members": [{"scene": "b14.json", "snapshots": "b14.npy", "gamma": [0.14]},
             {"scene": "b20.json", "snapshots": "$1", "gamma": $2},
             {"scene": "b26.json", "snapshots": "b26.npy", "gamma": [0.26]}],
 "rank": 8, "training": {"epochs": 600, "window": 10}, "seed": 1$3}
EOF
}
family b20.npy '[0.20]' >"$TMP/family.json"

# Trained, baked at 0.17, stepped against the 0.17 beam's own full-order run. Measured (seeds 1 to
# 5): relative error 0.080 to 0.131 (seed 1: 0.080); the bound 0.2 leaves half the worst again.
if "$ROMKIT" neural-dmd "$TMP/family.json" --scene "$TMP/b17.json" --gamma 0.17 -o "$TMP/n17.rombin" \
        --report "$TMP/n17.json" --save-model "$TMP/model.ndmd" >"$TMP/out" 2>"$TMP/err"; then
    sed 's/^/# /' "$TMP/out"
    json_checks neural_dmd_report_keys "$TMP/n17.json" koopman.rank=8 koopman.max_abs_eigenvalue neural.members=3 \
        'neural.gamma[0]' neural.final_loss neural.pretrained_loss 'neural.member_errors[2].mse_percent' asset.bytes
    top=$(json_num "$TMP/n17.json" koopman.max_abs_eigenvalue)
    below "$top" 1 && ok neural_dmd_inside_unit_circle || fail neural_dmd_inside_unit_circle "max |lambda| '$top'"
    "$ROMKIT" run "$TMP/n17.rombin" --steps 100 --reference "$TMP/b17.npy" --report "$TMP/r17.json" --quiet >/dev/null 2>"$TMP/err"
    e17=$(json_num "$TMP/r17.json" reference.relative_error)
    below "$e17" 0.2 && ok neural_dmd_unseen_thickness || fail neural_dmd_unseen_thickness "relative error '$e17' (limit 0.2)"
else
    fail neural_dmd_report_keys "$(cat "$TMP/err")"
fi

# The saved model bakes the same asset, byte for byte, without training again.
"$ROMKIT" neural-dmd "$TMP/family.json" --model "$TMP/model.ndmd" --scene "$TMP/b17.json" --gamma 0.17 \
    -o "$TMP/m17.rombin" --quiet >/dev/null 2>"$TMP/err" && cmp -s "$TMP/n17.rombin" "$TMP/m17.rombin" \
    && ok neural_dmd_saved_model_bakes_the_same_asset \
    || fail neural_dmd_saved_model_bakes_the_same_asset "$(head -c 300 "$TMP/err")"

# The same model at the nearest member's code on the same mesh: off by the thickness it ignores
# (measured 0.31 to 0.36, seeds 1 to 5); the code must buy at least a factor 2.
"$ROMKIT" neural-dmd "$TMP/family.json" --model "$TMP/model.ndmd" --scene "$TMP/b17.json" --gamma 0.14 -o "$TMP/n14.rombin" --quiet \
    >/dev/null 2>"$TMP/err" && "$ROMKIT" run "$TMP/n14.rombin" --steps 100 --reference "$TMP/b17.npy" \
    --report "$TMP/r14.json" --quiet >/dev/null 2>>"$TMP/err"
e14=$(json_num "$TMP/r14.json" reference.relative_error)
awk -v a="$e17" -v b="$e14" 'BEGIN { exit !(a != "" && b != "" && 2 * a < b) }' && ok neural_dmd_code_matters \
    || fail neural_dmd_code_matters "at 0.17: '$e17', at 0.14: '$e14': $(head -c 300 "$TMP/err")"
# A classical DMD of the same rank fitted on the 0.17 beam's own run (the answer in hand).
"$ROMKIT" dmd --snapshots "$TMP/b17.npy" --dt 0.01 --rank 8 --from-rest --gravity 0,-9.81,0 -o "$TMP/c17.rombin" \
    >/dev/null 2>&1 && "$ROMKIT" run "$TMP/c17.rombin" --steps 100 --reference "$TMP/b17.npy" \
    --report "$TMP/c17.json" --quiet >/dev/null 2>&1
ec=$(json_num "$TMP/c17.json" reference.relative_error)
echo "# unseen thickness 0.17 m, 100 steps against its own full-order run, relative error: neural DMD at gamma 0.17 $(g3 "$e17") (limit 0.2), at the nearest member's gamma 0.14 $(g3 "$e14"), a classical rank-8 DMD fitted on that run itself $(g3 "$ec")"

# One seed, one asset, whatever the thread count.
ROMKIT_THREADS=1 "$ROMKIT" neural-dmd "$TMP/family.json" --scene "$TMP/b17.json" --gamma 0.17 -o "$TMP/again.rombin" \
    --quiet >/dev/null 2>"$TMP/err"
cmp -s "$TMP/n17.rombin" "$TMP/again.rombin" && ok neural_dmd_seed_is_deterministic \
    || fail neural_dmd_seed_is_deterministic "the same seed on 1 thread gave another asset: $(head -c 200 "$TMP/err")"

# Shape optimisation (Sec. 7.4): the thickness whose tip corner (1, 0, 0) is, 100 steps after the
# release, at the height the 0.17 m beam's full-order run puts it. The family's "shape" says how a
# code makes a mesh (the box's y size is gamma); Newton on gamma runs through the model's jump.
# Measured (seeds 1 to 5): gamma 0.175 to 0.181, the full-order tip there 2.4% to 4.7% off the
# target (seed 1: 2.4%); the bound 8% leaves the worst 1.7 times over.
family b20.npy '[0.20]' ', "shape": {"scene": "b20.json", "size": [1, 0, 0.2], "size_per_gamma": [[0, 1, 0]]}' \
    >"$TMP/shape.json"
npy_values "$TMP/b17.npy" >"$TMP/v17"
tip=$(awk 'NR <= 126 { c[(NR - 1) % 3] = $1; if ((NR - 1) % 3 == 2 && c[0] == 1 && c[1] == 0 && c[2] == 0) print int((NR - 1) / 3) }' "$TMP/v17")
y17=$(sed -n "$((100 * 126 + 3 * ${tip:-0} + 2))p" "$TMP/v17")
if "$ROMKIT" neural-dmd "$TMP/shape.json" --objective "$tip,y" --target "$y17" --steps 100 --gamma-start 0.24 \
        -o "$TMP/opt.rombin" --report "$TMP/opt.json" --quiet >"$TMP/out" 2>"$TMP/err"; then
    sed 's/^/# /' "$TMP/out"
    json_checks neural_dmd_shape_report "$TMP/opt.json" 'shape_optimization.gamma[0]' shape_optimization.value \
        shape_optimization.iterations "shape_optimization.vertex=$tip" shape_optimization.steps=100 koopman.rank=8
    gopt=$(json_num "$TMP/opt.json" 'shape_optimization.gamma[0]')
    # the full-order run at the thickness found, against the target
    beam bopt "${gopt:-0}"
    yopt=$(npy_values "$TMP/bopt.npy" | sed -n "$((100 * 126 + 3 * ${tip:-0} + 2))p")
    miss=$(awk -v a="$yopt" -v t="$y17" 'BEGIN { d = (a - t) / t; print (d < 0 ? -d : d) }')
    below "$miss" 0.08 && ok neural_dmd_shape_optimization \
        || fail neural_dmd_shape_optimization "gamma '$gopt': the full-order tip there $yopt m, target $y17 m (limit 0.08)"
    echo "# shape optimisation from gamma 0.24 to the 0.17 m beam's full-order tip height after 100 steps, $(g3 "$y17") m: gamma $(g3 "$gopt"); the full-order run there ends at $(g3 "$yopt") m, $(g3 "$miss") of the target off (limit 0.08)"
else
    fail neural_dmd_shape_optimization "$(cat "$TMP/err")"
fi

# Bad input: a message naming the file and the JSON path, nothing written.
nd() { "$ROMKIT" neural-dmd "$TMP/bad.json" --scene "$TMP/b17.json" --gamma "${G:-0.17}" -o "$TMP/bad.rombin" --quiet; }
family b17_4.npy '[0.20]' >"$TMP/bad.json"
sed 's/"cells": \[6, 2, 1\]/"cells": [4, 1, 1]/' "$TMP/b20.json" >"$TMP/b4.json" # a coarser mesh's run
"$ROMKIT" fom "$TMP/b4.json" --snapshots "$TMP/b17_4.npy" --quiet >/dev/null 2>&1
expect_fail neural_dmd_vertex_count_mismatch "bad.json: members\[1\].snapshots: .*b17_4.npy must be T x 42 x 3" nd
family missing.npy '[0.20]' >"$TMP/bad.json"
expect_fail neural_dmd_missing_snapshots "bad.json: members\[1\].snapshots: .*missing.npy" nd
family b20.npy '[0.20, 1]' >"$TMP/bad.json"
expect_fail neural_dmd_gamma_length "bad.json: members\[1\].gamma: 2 values, the first member's gamma has 1" nd
# a NaN in the snapshots (frame 5's first value: the bits of a quiet NaN)
cp "$TMP/b20.npy" "$TMP/nan.npy"; family nan.npy '[0.20]' >"$TMP/bad.json"
printf '\000\000\000\000\000\000\370\177' | dd of="$TMP/nan.npy" bs=1 seek=$(( $(npy_header_bytes "$TMP/nan.npy") + 5 * 42 * 24 )) \
    conv=notrunc 2>/dev/null
expect_fail neural_dmd_nan_snapshots "bad.json: members\[1\].snapshots: .*nan.npy: value 630 (frame 5) is not finite" nd
family b20.npy '[0.20]' | sed 's/"window": 10}/"window": 10, "polish": -1}/' >"$TMP/bad.json"
expect_fail neural_dmd_bad_polish "training: polish must be a whole number from 0 to 1e+07, got -1" nd
# a saved model that is damaged, or that this family could not have trained, or saved again
cp "$TMP/model.ndmd" "$TMP/bad.ndmd"
printf 'Z' | dd of="$TMP/bad.ndmd" bs=1 seek=200 conv=notrunc 2>/dev/null
expect_fail neural_dmd_damaged_model "bad.ndmd: checksum mismatch" \
    "$ROMKIT" neural-dmd "$TMP/family.json" --model "$TMP/bad.ndmd" --scene "$TMP/b17.json" --gamma 0.17 -o "$TMP/bad.rombin"
family b20.npy '[0.20]' | sed 's/"rank": 8/"rank": 6/' >"$TMP/bad.json"
expect_fail neural_dmd_model_of_another_rank "model.ndmd: rank 8, .* the family has rank 6" \
    "$ROMKIT" neural-dmd "$TMP/bad.json" --model "$TMP/model.ndmd" --scene "$TMP/b17.json" --gamma 0.17 -o "$TMP/bad.rombin"
expect_fail neural_dmd_model_saved_again "does not go with --model" \
    "$ROMKIT" neural-dmd "$TMP/family.json" --model "$TMP/model.ndmd" --save-model "$TMP/again.ndmd" \
    --scene "$TMP/b17.json" --gamma 0.17 -o "$TMP/bad.rombin"
family b20.npy '[0.20]' >"$TMP/bad.json"
G=0.3; expect_fail neural_dmd_gamma_out_of_range "value 0 (0.3) is outside the members' range \[0.14, 0.26\]" nd
G=0.17,0.2; expect_fail neural_dmd_gamma_wrong_length "need 1 comma-separated finite numbers" nd
unset G
expect_fail neural_dmd_objective_needs_a_shape 'the family file has no "shape"' \
    "$ROMKIT" neural-dmd "$TMP/family.json" --objective 6,y --target -0.03 --steps 100 -o "$TMP/bad.rombin"
[ ! -e "$TMP/bad.rombin" ] && ok neural_dmd_nothing_written_on_error || fail neural_dmd_nothing_written_on_error "bad.rombin exists"
