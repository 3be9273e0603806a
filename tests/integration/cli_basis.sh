# romkit basis: every basis type from a scene's rom section, sizes and tolerances, point clouds,
# and the errors a user meets.
. tests/lib.sh

scene() { # scene FILE ROM_JSON [FIXED]: a small cantilever (or free object) with gravity
    fixed=${3-'"fixed": [{"box": [[-1, -1, -1], [0.01, 1, 1]]}],'}
    cat >"$1" <<JSON
{
  "objects": [{
    "mesh": {"box": {"size": [1, 0.2, 0.2], "cells": [10, 2, 2]}},
    "material": {"model": "neohookean", "young": 2e6, "poisson": 0.4, "density": 1000},
    $fixed
    "velocity": [0, 0, 0]
  }],
  "gravity": [0, -9.81, 0],
  "time": {"step": 0.01, "duration": 0.3},
  "rom": $2
}
JSON
}

"$ROMKIT" basis --help | grep -q example && ok basis_help_has_example || fail basis_help_has_example "no example"

for b in modes modal_derivatives skinning rkpm_skinning pod; do
    scene "$TMP/$b.json" "{\"basis\": \"$b\", \"size\": 6, \"kernels\": 60, \"integration_points\": 3000}"
    if "$ROMKIT" basis "$TMP/$b.json" --basis "$TMP/$b.npy" --report "$TMP/$b.r.json" >"$TMP/out" 2>"$TMP/err"; then
        case $b in skinning|rkpm_skinning) want=84 ;; *) want=6 ;; esac
        json_is "$TMP/$b.r.json" basis.type "\"$b\"" && json_is "$TMP/$b.r.json" basis.size "$want" \
            && grep -q "'shape': (99, 3, $want)" "$TMP/$b.npy" && ok "basis_${b}_builds" \
            || fail "basis_${b}_builds" "type $("$JSONQ" get "$TMP/$b.r.json" basis.type 2>&1) size $("$JSONQ" get "$TMP/$b.r.json" basis.size 2>&1) $(head -c 100 "$TMP/$b.npy")"
    else
        fail "basis_${b}_builds" "$(cat "$TMP/err")"
    fi
done

# Free object: exactly six zero eigenvalues reported.
scene "$TMP/free.json" '{"basis": "modes", "size": 10}' ''
"$ROMKIT" basis "$TMP/free.json" --report "$TMP/free.r.json" >/dev/null 2>"$TMP/err" \
    && json_is "$TMP/free.r.json" basis.zero_eigenvalues 6 && ok free_object_six_rigid_modes \
    || fail free_object_six_rigid_modes "$(cat "$TMP/err") $(head -c 300 "$TMP/free.r.json")"

# Tolerance: the smallest basis whose projection error of the scene's own frames meets it. The
# beam sags by several centimetres, so linear modes level off near 1% while modal derivatives,
# skinning and POD go lower.
for bt in modes:0.05 modal_derivatives:0.01 pod:0.01 skinning:0.01; do
    b=${bt%%:*}; t=${bt#*:}
    scene "$TMP/tol_$b.json" "{\"basis\": \"$b\", \"tolerance\": $t}"
    if "$ROMKIT" basis "$TMP/tol_$b.json" --report "$TMP/tol_$b.r.json" >"$TMP/out" 2>"$TMP/err"; then
        e=$(json_num "$TMP/tol_$b.r.json" basis.projection_error)
        awk -v e="$e" -v t="$t" 'BEGIN { exit !(e != "" && e <= t && e >= 0) }' && ok "tolerance_${b}_met" \
            || fail "tolerance_${b}_met" "projection error $e"
    else
        fail "tolerance_${b}_met" "$(cat "$TMP/err")"
    fi
done
s1=$(json_num "$TMP/tol_modal_derivatives.r.json" basis.size)
scene "$TMP/tol2.json" '{"basis": "modal_derivatives", "tolerance": 0.001}'
"$ROMKIT" basis "$TMP/tol2.json" --report "$TMP/tol2.r.json" >/dev/null 2>&1
s2=$(json_num "$TMP/tol2.r.json" basis.size)
[ -n "$s1" ] && [ -n "$s2" ] && [ "$s2" -gt "$s1" ] && ok tighter_tolerance_needs_a_bigger_basis \
    || fail tighter_tolerance_needs_a_bigger_basis "1e-2: $s1 columns, 1e-3: $s2 columns"
scene "$TMP/plateau.json" '{"basis": "modes", "tolerance": 0.001}'
expect_fail linear_modes_plateau_is_reported "misses the full-order frames by" "$ROMKIT" basis "$TMP/plateau.json"

# A Gaussian-splat point cloud: RKPM weights without a mesh.
cat >"$TMP/splats.json" <<JSON
{"objects": [{"mesh": {"points": "$(pwd)/tests/data/meshes/donut_3dgs.ply"},
              "material": {"model": "neohookean", "young": 1e5, "poisson": 0.4, "density": 1000}}],
 "time": {"step": 0.01, "duration": 0.1},
 "rom": {"basis": "rkpm_skinning", "size": 8, "kernels": 300, "integration_points": 10000}}
JSON
"$ROMKIT" basis "$TMP/splats.json" --weights "$TMP/w.npy" --report "$TMP/splats.r.json" >/dev/null 2>"$TMP/err" \
    && grep -q "'shape': (45624, 9)" "$TMP/w.npy" && ok splat_cloud_weights \
    || fail splat_cloud_weights "$(cat "$TMP/err") $(head -c 100 "$TMP/w.npy" 2>/dev/null)"
sed 's/"rkpm_skinning"/"modes"/' "$TMP/splats.json" >"$TMP/splats_modes.json"
expect_fail point_cloud_needs_rkpm "only basis rkpm_skinning" "$ROMKIT" basis "$TMP/splats_modes.json"

# Errors: named, and nothing written.
scene "$TMP/bad.json" '{"basis": "wavelets", "size": 4}'
expect_fail unknown_basis_named "rom: basis must be" "$ROMKIT" basis "$TMP/bad.json"
scene "$TMP/big.json" '{"basis": "modes", "size": 4000}'
expect_fail size_above_problem "free degrees of freedom" "$ROMKIT" basis "$TMP/big.json" --report "$TMP/big.r.json"
[ ! -e "$TMP/big.r.json" ] && ok failed_basis_writes_nothing || fail failed_basis_writes_nothing "report written"
scene "$TMP/none.json" '{"basis": "modes"}'
expect_fail size_or_tolerance_needed "needs size" "$ROMKIT" basis "$TMP/none.json"
scene "$TMP/pod_big.json" '{"basis": "pod", "size": 50}'
expect_fail pod_needs_frames "more than the 30 full-order frames" "$ROMKIT" basis "$TMP/pod_big.json"
scene "$TMP/tight.json" '{"basis": "skinning", "size": 2, "tolerance": 1e-9}'
expect_fail unreachable_tolerance_says_how_close "tolerance 1e-09 not met" "$ROMKIT" basis "$TMP/tight.json"
