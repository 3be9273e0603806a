# romkit build / inspect / run and examples/embed: the report keys (DESIGN.md), determinism,
# compression, precision, and the errors a user meets (nothing written half-way).
. tests/lib.sh
B=${ROMKIT_BUILD:-build}
SCENE=examples/scenes/cantilever_small.json

if "$ROMKIT" build "$SCENE" -o "$TMP/a.rombin" --report "$TMP/build.json" --quiet >"$TMP/out" 2>"$TMP/err"; then
    json_checks build_report_keys "$TMP/build.json" vertices tets 'basis.type="modes"' basis.size=12 \
        'basis.eigenvalues[0]' cubature.elements cubature.relative_error asset.bytes 'asset.chunks[0]' seconds.total
    # Only what the scene needs: fewer rows than mesh vertices, the shown ones are the surface.
    stored=$(json_num "$TMP/build.json" asset.stored_vertices)
    verts=$(json_num "$TMP/build.json" vertices)
    [ -n "$stored" ] && [ -n "$verts" ] && [ "$stored" -lt "$verts" ] && ok build_stores_fewer_vertices_than_the_mesh \
        || fail build_stores_fewer_vertices_than_the_mesh "stored $stored of $verts"
else
    fail build_report_keys "$(cat "$TMP/err")"
fi

"$ROMKIT" build "$SCENE" -o "$TMP/b.rombin" --quiet >/dev/null 2>&1
cmp -s "$TMP/a.rombin" "$TMP/b.rombin" && ok build_is_deterministic || fail build_is_deterministic "two builds differ"

"$ROMKIT" inspect "$TMP/a.rombin" >"$TMP/out" 2>"$TMP/err" && grep -q "ROWS  critical" "$TMP/out" && grep -q "opens with the runtime" "$TMP/out" \
    && ok inspect_lists_and_verifies || fail inspect_lists_and_verifies "$(head -c 400 "$TMP/out" "$TMP/err")"

# A cubature that stops above its tolerance is said on the terminal, not only in the report.
python3 -c "
import json, sys
s = json.load(open(sys.argv[1])); s['rom']['cubature'] = {'tolerance': 1e-6, 'max_points': 2}
json.dump(s, open(sys.argv[2], 'w'))" "$SCENE" "$TMP/cub2.json"
"$ROMKIT" build "$TMP/cub2.json" -o "$TMP/cub2.rombin" --quiet >"$TMP/out" 2>&1 \
    && grep -q "warning: the cubature missed its tolerance (rom.cubature.max_points: stopped at 2 of" "$TMP/out" \
    && ok build_warns_of_a_cubature_above_tolerance || fail build_warns_of_a_cubature_above_tolerance "$(cat "$TMP/out")"
"$ROMKIT" build "$SCENE" -o "$TMP/cub.rombin" >"$TMP/out" 2>&1 && ! grep -q "warning" "$TMP/out" \
    && ok build_quiet_about_a_cubature_in_tolerance || fail build_quiet_about_a_cubature_in_tolerance "$(cat "$TMP/out")"
# An object thrown with an initial velocity (a scene nobody tuned: a bar thrown at 2 m/s onto a
# sphere and a plane): the asset holds its reduced velocity (VEL0), so the runtime's free run
# follows full order as compare's does. Before VEL0 the runtime started it at rest: normalized
# MSE 0.241 against full order where compare's reduced simulator gave 5.7e-4.
cat >"$TMP/thrown.json" <<'EOF'
{"objects": [{"mesh": {"box": {"size": [0.3, 0.1, 0.1], "cells": [9, 3, 3]}},
  "material": {"model": "neohookean", "young": 2e5, "poisson": 0.4, "density": 1000},
  "velocity": [0, -2, 0]}],
 "obstacles": [{"sphere": {"center": [0.05, -0.25, 0], "radius": 0.08}}, {"plane": {"point": [0, -0.35, 0], "normal": [0, 1, 0]}}],
 "contact": {"dhat": 0.002, "friction": 0.3},
 "gravity": [0, -9.81, 0], "time": {"step": 0.01, "duration": 0.4, "integrator": "backward_euler"},
 "rom": {"basis": "skinning", "size": 8, "cubature": {"tolerance": 0.02}}}
EOF
if "$ROMKIT" fom "$TMP/thrown.json" --snapshots "$TMP/thrown.npy" --quiet >/dev/null 2>"$TMP/err" &&
    "$ROMKIT" build "$TMP/thrown.json" -o "$TMP/thrown.rombin" --quiet >"$TMP/out" 2>&1 &&
    "$ROMKIT" run "$TMP/thrown.rombin" --steps 40 --reference "$TMP/thrown.npy" --scene "$TMP/thrown.json" >"$TMP/run" 2>&1; then
    grep -q "moving at t = 0: the initial velocities baked (VEL0" "$TMP/out" &&
        ! grep warning "$TMP/out" | grep -qv "pointwise volume" && # no warning but the volume's (nu 0.4)
        "$ROMKIT" inspect "$TMP/thrown.rombin" | grep -q "VEL0  critical" \
        && ok build_bakes_an_initial_velocity || fail build_bakes_an_initial_velocity "$(cat "$TMP/out")"
    nmse=$(sed -n 's/.*normalized MSE \([0-9.e+-]*\).*/\1/p' "$TMP/run")
    crossings=$(sed -n 's/.*, \([0-9]*\) crossings in.*/\1/p' "$TMP/run")
    awk -v e="$nmse" 'BEGIN { exit !(e != "" && e < 5e-3) }' && [ "$crossings" = 0 ] \
        && ok run_follows_a_thrown_object "normalized MSE $nmse" || fail run_follows_a_thrown_object "$(cat "$TMP/run")"
else
    fail build_bakes_an_initial_velocity "$(cat "$TMP/err" "$TMP/out" "$TMP/run" 2>/dev/null)"
fi

# A POD entry that lists its training runs trains on them, not on the scene's own run (which
# would fit the basis to the very motion it is then tested on).
python3 -c "
import json, sys
s = json.load(open(sys.argv[1])); s['time']['duration'] = 0.2
train = dict(s, gravity=[0, 0, -9.81]); json.dump(train, open(sys.argv[2] + '/train.json', 'w'))
s['rom'] = {'basis': 'pod', 'size': 4, 'training': ['train.json', 'train.json']}
json.dump(s, open(sys.argv[2] + '/podtrain.json', 'w'))
del s['rom']['training']; json.dump(s, open(sys.argv[2] + '/podown.json', 'w'))" "$SCENE" "$TMP"
if "$ROMKIT" build "$TMP/podtrain.json" -o "$TMP/pt.rombin" --report "$TMP/pt.json" --quiet >/dev/null 2>"$TMP/err" &&
    "$ROMKIT" build "$TMP/podown.json" -o "$TMP/po.rombin" --report "$TMP/po.json" --quiet >/dev/null 2>>"$TMP/err"; then
    # two runs of 20 steps listed, against the scene's own 20
    json_checks build_pod_trains_on_its_training_list "$TMP/pt.json" basis.training_frames=40
    json_checks build_pod_without_a_list_trains_on_the_scene "$TMP/po.json" basis.training_frames=20
    "$JSONQ" get "$TMP/pt.json" basis.trained_on | grep -q "training list" &&
        "$JSONQ" get "$TMP/po.json" basis.trained_on | grep -q "own full-order run" &&
        ok build_reports_what_it_trained_on || fail build_reports_what_it_trained_on "$("$JSONQ" get "$TMP/pt.json" basis)"
else
    fail build_pod_trains_on_its_training_list "$(cat "$TMP/err")"
fi

# Damage: a truncated copy and one flipped payload byte are refused by inspect and run, by name.
size=$(wc -c <"$TMP/a.rombin")
head -c $((size - 100)) "$TMP/a.rombin" >"$TMP/cut.rombin"
expect_fail inspect_refuses_truncation "truncated" "$ROMKIT" inspect "$TMP/cut.rombin"
cp "$TMP/a.rombin" "$TMP/flip.rombin"
printf '\377' | dd of="$TMP/flip.rombin" bs=1 seek=2000 conv=notrunc 2>/dev/null
expect_fail run_refuses_a_flipped_byte "CRC mismatch" "$ROMKIT" run "$TMP/flip.rombin" --steps 1

if "$ROMKIT" run "$TMP/a.rombin" --steps 20 --positions "$TMP/p.npy" --snapshots "$TMP/s.npy" --report "$TMP/run.json" \
        --quiet >"$TMP/out" 2>"$TMP/err"; then
    # hessian_reuse: the mode in force, the asset's default (a matrix kept up to 10 steps) when
    # --hessian-reuse is not given (romrt_step_info), not 0
    json_checks run_report_keys "$TMP/run.json" vertices seconds_per_step newton_iterations arena_bytes asset.bytes \
        seconds.total hessian_reuse=10 factorizations contact_pairs_max=0
    head -c 80 "$TMP/s.npy" | grep -q "'shape': (20, [0-9]*, 3)" && ok run_writes_snapshots || fail run_writes_snapshots "$(head -c 80 "$TMP/s.npy")"
else
    fail run_report_keys "$(cat "$TMP/err")"
fi

# Compressed and float64 assets: smaller / larger, and the same motion.
"$ROMKIT" build "$SCENE" -o "$TMP/z.rombin" --compress --quiet >/dev/null 2>&1
[ "$(wc -c <"$TMP/z.rombin")" -lt "$size" ] && ok compress_makes_it_smaller || fail compress_makes_it_smaller "$(wc -c <"$TMP/z.rombin") vs $size"
"$ROMKIT" run "$TMP/z.rombin" --steps 20 --positions "$TMP/pz.npy" --quiet >/dev/null 2>"$TMP/err" && cmp -s "$TMP/p.npy" "$TMP/pz.npy" \
    && ok compressed_asset_runs_identically || fail compressed_asset_runs_identically "$(cat "$TMP/err")"
"$ROMKIT" inspect "$TMP/z.rombin" | grep -q deflate && ok inspect_shows_deflate || fail inspect_shows_deflate "no deflate chunk listed"
"$ROMKIT" build "$SCENE" -o "$TMP/d.rombin" --precision float64 --quiet >/dev/null 2>&1 && "$ROMKIT" inspect "$TMP/d.rombin" | grep -q "float64 reals" \
    && "$ROMKIT" run "$TMP/d.rombin" --steps 5 --quiet >/dev/null && ok float64_asset_opens_in_the_float_runtime \
    || fail float64_asset_opens_in_the_float_runtime "build, inspect or run failed"

# The embedding examples (C and C++) open, push and step it.
"$B/embed" "$TMP/a.rombin" 40 >"$TMP/out" 2>&1 && grep -q "tip at" "$TMP/out" && ok embed_c_example || fail embed_c_example "$(cat "$TMP/out")"
"$B/embed_cpp" "$TMP/a.rombin" >"$TMP/out" 2>&1 && grep -q "one step" "$TMP/out" && ok embed_cpp_example || fail embed_cpp_example "$(cat "$TMP/out")"

# Errors a user meets; no output file is left behind.
expect_fail build_needs_an_output "-o OUT.rombin is required" "$ROMKIT" build "$SCENE"
expect_fail build_rejects_bad_precision "float32 or float64" "$ROMKIT" build "$SCENE" -o "$TMP/x.rombin" --precision half
cat >"$TMP/norom.json" <<'JSON'
{"objects": [{"mesh": {"box": {"size": [1, 0.1, 0.1], "cells": [4, 1, 1]}},
  "material": {"model": "linear", "young": 1e6, "poisson": 0.3, "density": 1000}}], "time": {"step": 0.01, "duration": 0.1}}
JSON
expect_fail build_needs_a_rom_section "no rom section" "$ROMKIT" build "$TMP/norom.json" -o "$TMP/x.rombin"
sed 's/"asset": {"groups"/"asset": {"show": "sideways", "groups"/' "$SCENE" >"$TMP/bad.json"
expect_fail build_names_a_bad_key "show must be" "$ROMKIT" build "$TMP/bad.json" -o "$TMP/x.rombin"
if [ -e "$TMP/x.rombin" ] || ls "$TMP" | grep -q 'x.rombin.tmp'; then fail no_partial_asset "a failed build left a file"; else ok no_partial_asset; fi
expect_fail run_rejects_bad_steps "whole number" "$ROMKIT" run "$TMP/a.rombin" --steps -3
expect_fail run_jump_needs_koopman "no Koopman operator" "$ROMKIT" run "$TMP/a.rombin" --steps 1 --jump 10
expect_fail run_missing_file "cannot open" "$ROMKIT" run "$TMP/none.rombin" --steps 1

# A point cloud, mesh-free (the fuzz seed's lattice): built, stepped, its splats written per frame
# as PLY (frame 0 the start) with the cloud's points in file order; a mesh asset has none to write.
# At full order the cloud runs on its body, its snapshots at the scene's vertices (its 81 points,
# then its contact surface's 130 vertices, the march surface's).
if "$ROMKIT" build tests/fuzz/seed_points.json -o "$TMP/p.rombin" --quiet >/dev/null 2>"$TMP/err" \
    && "$ROMKIT" run "$TMP/p.rombin" --steps 5 --splats "$TMP/splats" --snapshots "$TMP/ps.npy" --quiet >/dev/null 2>>"$TMP/err" \
    && [ "$(ls "$TMP/splats" | wc -l)" = 6 ] && head -c 300 "$TMP/splats/frame_00005.ply" | grep -q "element vertex 81" \
    && grep -q "'shape': (5, 81, 3)" "$TMP/ps.npy"; then ok point_cloud_builds_runs_and_writes_splats
else fail point_cloud_builds_runs_and_writes_splats "$(tail -c 600 "$TMP/err")"; fi
expect_fail run_splats_needs_a_cloud "holds no Gaussian splats" "$ROMKIT" run "$TMP/a.rombin" --steps 1 --splats "$TMP/nosplats"
if "$ROMKIT" fom tests/fuzz/seed_points.json --snapshots "$TMP/fs.npy" --quiet >"$TMP/out" 2>"$TMP/err" \
    && grep -q "81 points embedded in their full-order bodies (0 outside" "$TMP/out" \
    && grep -q "'shape': (11, 187, 3)" "$TMP/fs.npy"; then ok point_cloud_runs_at_full_order
else fail point_cloud_runs_at_full_order "$(cat "$TMP/out") $(tail -c 600 "$TMP/err")"; fi

# A point cloud and a tet mesh in one scene (the fuzz seed's lattice resting over a meshed slab):
# built into an asset and stepped by the runtime, and by the reduced simulator; at full order (the
# cloud on its body) with no crossing, and romkit compare measures the reduced model against it.
cat >"$TMP/mixed.json" <<JSON
{"objects": [
  {"mesh": {"box": {"size": [0.5, 0.04, 0.2], "cells": [5, 1, 2]}, "translate": [-0.05, -0.15, -0.1]},
   "material": {"model": "neohookean", "young": 1e5, "poisson": 0.4, "density": 1000}},
  {"mesh": {"points": "$PWD/tests/fuzz/seed_points.ply"},
   "material": {"model": "neohookean", "young": 1e5, "poisson": 0.4, "density": 1000}}],
 "gravity": [0, -9.81, 0], "obstacles": [{"plane": {"point": [0, -0.2, 0], "normal": [0, 1, 0]}}],
 "contact": {"dhat": 0.002}, "time": {"step": 0.01, "duration": 0.05},
 "rom": {"basis": "rkpm_skinning", "size": 2, "kernels": 20, "mesh_free": {"points": 200}}}
JSON
if "$ROMKIT" build "$TMP/mixed.json" -o "$TMP/mixed.rombin" --report "$TMP/mixed_build.json" --quiet >/dev/null 2>"$TMP/err" \
    && "$ROMKIT" run "$TMP/mixed.rombin" --steps 5 --quiet >/dev/null 2>>"$TMP/err" \
    && "$ROMKIT" rom "$TMP/mixed.json" --quiet >/dev/null 2>>"$TMP/err"; then ok cloud_and_mesh_build_run_and_rom
else fail cloud_and_mesh_build_run_and_rom "$(tail -c 600 "$TMP/err")"; fi
if "$ROMKIT" fom "$TMP/mixed.json" --report "$TMP/mixed_fom.json" --quiet >/dev/null 2>"$TMP/err" \
    && python3 -c "import json, sys; r = json.load(open(sys.argv[1])); sys.exit(not (r['contact']['intersections'] == 0 and r['cloud_body']['points'] == 81))" "$TMP/mixed_fom.json" \
    && "$ROMKIT" compare "$TMP/mixed.json" --report "$TMP/mixed_cmp.json" --quiet >/dev/null 2>>"$TMP/err" \
    && python3 -c "import json, math, sys; m = json.load(open(sys.argv[1]))['methods'][1]; sys.exit(not math.isfinite(m['normalized_mse']))" "$TMP/mixed_cmp.json"; then ok cloud_and_mesh_run_at_full_order_and_compare
else fail cloud_and_mesh_run_at_full_order_and_compare "$(tail -c 600 "$TMP/err")"; fi

# The freeform paper's largest model steps in the desktop runtime: m = 32 eigen-weights on the
# Table-1 beam is r = 396 (issue 37; the runtime refused it when ROMRT_MAX_R was 256).
python3 -c "
import json, sys
s = json.load(open(sys.argv[1])); s.pop('reference', None); s['time']['duration'] = 0.02
s['rom'] = [{'basis': 'rkpm_skinning', 'size': 32, 'mesh_free': {'points': 2000}}]
json.dump(s, open(sys.argv[2], 'w'))" examples/scenes/beam_bend_table.json "$TMP/m32.json"
if "$ROMKIT" build "$TMP/m32.json" -o "$TMP/m32.rombin" --quiet >"$TMP/out" 2>&1 \
    && "$ROMKIT" run "$TMP/m32.rombin" --steps 2 --report "$TMP/m32run.json" --quiet >>"$TMP/out" 2>&1; then
    json_checks run_steps_the_papers_largest_model "$TMP/m32run.json" r=396
else
    fail run_steps_the_papers_largest_model "$(tail -c 400 "$TMP/out")"
fi

# A basis whose columns are nearly dependent in float32 (a 1 x 0.1 x 0.1 bar of 20 layers, clamped,
# 7 skinning weights times affine handles): the double precompute bakes it, the float32 runtime
# cannot factor its reduced mass; romkit build says so and how to bake it instead.
cat >"$TMP/thinbar.json" <<'EOF2'
{"objects": [{"mesh": {"box": {"size": [1, 0.1, 0.1], "cells": [20, 2, 2]}},
  "material": {"model": "linear", "young": 1e5, "poisson": 0, "density": 1000},
  "fixed": [{"box": [[-1, -1, -1], [0.01, 1, 1]]}]}],
 "time": {"step": 0.01, "duration": 0.1}, "rom": {"basis": "skinning", "size": 6}}
EOF2
"$ROMKIT" build "$TMP/thinbar.json" -o "$TMP/thinbar.rombin" --quiet >"$TMP/out" 2>&1
grep -q "warning: .*thinbar.rombin does not open in this romkit's float32 runtime: .*'MASS'.*bake with --precision float64" "$TMP/out" \
    && ok build_warns_of_an_asset_its_runtime_refuses || fail build_warns_of_an_asset_its_runtime_refuses "$(cat "$TMP/out")"
