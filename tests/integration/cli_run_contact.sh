# romkit run --scene: the runtime's frames measured for contact as romkit fom measures its own
# (contact.min_distance, contact.intersections by the exact segment-triangle test,
# intersecting_frames, frames), on a block dropped at 1 m/s onto a plane; the same keys in the fom
# report; the scenes run refuses to measure against, by name; a hidden surface and a point cloud's
# contact surface measured on the asset's collision vertices; a ninth moving obstacle refused at
# bake, by name.
. tests/lib.sh
cat >"$TMP/drop.json" <<'JSON'
{"objects": [{"mesh": {"box": {"size": [0.1, 0.05, 0.1], "cells": [2, 1, 2]}, "translate": [0, 0.02, 0]},
  "material": {"model": "neohookean", "young": 1e5, "poisson": 0.3, "density": 1000}, "velocity": [0, -1, 0]}],
 "gravity": [0, -9.81, 0], "obstacles": [{"plane": {"point": [0, 0, 0], "normal": [0, 1, 0]}}],
 "contact": {"dhat": 1e-3, "friction": 0.3}, "time": {"step": 0.01, "duration": 0.5},
 "rom": {"basis": "modes", "size": 12}}
JSON

if "$ROMKIT" build "$TMP/drop.json" -o "$TMP/drop.rombin" --quiet >/dev/null 2>"$TMP/err" &&
    "$ROMKIT" run "$TMP/drop.rombin" --steps 50 --scene "$TMP/drop.json" --report "$TMP/run.json" --quiet \
        >"$TMP/out" 2>>"$TMP/err"; then
    json_checks run_reports_contact_keys "$TMP/run.json" contact.min_distance 'contact.intersections=0' \
        'contact.intersecting_frames=0' 'contact.frames=51'
    # it landed (closer than dhat: the barrier holds it) and never touched
    d=$(json_num "$TMP/run.json" contact.min_distance)
    if below 0 "$d" && below "$d" 1e-3; then ok run_contact_distance_is_positive_and_landed
    else fail run_contact_distance_is_positive_and_landed "min_distance '$d'"; fi
    grep -q "0 crossings in 0 of 51 frames" "$TMP/out" && ok run_prints_contact || fail run_prints_contact "$(cat "$TMP/out")"
else
    fail run_reports_contact_keys "$(cat "$TMP/err")"
fi

# the full-order run's report has the same keys, from the same tally
if "$ROMKIT" fom "$TMP/drop.json" --report "$TMP/fom.json" --quiet >/dev/null 2>"$TMP/err"; then
    json_checks fom_reports_the_same_contact_keys "$TMP/fom.json" contact.min_distance 'contact.intersections=0' \
        'contact.intersecting_frames=0' 'contact.frames=51'
else
    fail fom_reports_the_same_contact_keys "$(cat "$TMP/err")"
fi

# refusals: another scene's asset, a scene with nothing to collide with
SCENE=examples/scenes/cantilever_small.json
"$ROMKIT" build "$SCENE" -o "$TMP/c.rombin" --quiet >/dev/null 2>&1
expect_fail run_scene_must_be_the_assets "is this the scene the asset was built from" \
    "$ROMKIT" run "$TMP/c.rombin" --steps 1 --scene "$TMP/drop.json"
expect_fail run_scene_needs_contact "no contact to measure" "$ROMKIT" run "$TMP/c.rombin" --steps 1 --scene "$SCENE"
expect_fail run_scene_missing_file "cannot open" "$ROMKIT" run "$TMP/drop.rombin" --steps 1 --scene "$TMP/none.json"

# a surface the asset does not show is measured on its collision vertices (CVTX,
# romrt_collision_positions), as a point cloud's contact surface is (its proxy's corners, stored
# but not shown): a hidden block, and a cloud (tests/fuzz's 9 x 3 x 3 lattice) dropped at 1 m/s
# onto a meshed slab on a plane (0.2 s CPU here)
sed 's/"size": 12}}/"size": 12, "asset": {"show": "none", "groups": [{"name": "all", "box": [[-1, -1, -1], [1, 1, 1]]}]}}}/' \
    "$TMP/drop.json" >"$TMP/hidden.json"
if "$ROMKIT" build "$TMP/hidden.json" -o "$TMP/hidden.rombin" --quiet >/dev/null 2>"$TMP/err" &&
    "$ROMKIT" run "$TMP/hidden.rombin" --steps 50 --scene "$TMP/hidden.json" --report "$TMP/hidden_run.json" --quiet \
        >/dev/null 2>>"$TMP/err"; then
    json_checks run_scene_measures_a_hidden_surface "$TMP/hidden_run.json" 'contact.intersections=0' 'contact.frames=51'
else
    fail run_scene_measures_a_hidden_surface "$(cat "$TMP/err")"
fi
cat >"$TMP/cloud.json" <<JSON
{"objects": [{"mesh": {"box": {"size": [0.5, 0.04, 0.2], "cells": [5, 1, 2]}, "translate": [0.2, -0.13, 0]},
   "material": {"model": "neohookean", "young": 1e5, "poisson": 0.4, "density": 1000}},
  {"mesh": {"points": "$PWD/tests/fuzz/seed_points.ply"},
   "material": {"model": "neohookean", "young": 1e5, "poisson": 0.4, "density": 1000}, "velocity": [0, -1, 0]}],
 "gravity": [0, -9.81, 0], "obstacles": [{"plane": {"point": [0, -0.151, 0], "normal": [0, 1, 0]}}],
 "contact": {"dhat": 1e-3}, "time": {"step": 0.01, "duration": 0.3},
 "rom": {"basis": "rkpm_skinning", "size": 2, "kernels": 20, "mesh_free": {"points": 200},
         "cubature": {"tolerance": 0.05}, "volume": "projected"}}
JSON
if "$ROMKIT" build "$TMP/cloud.json" -o "$TMP/cloud.rombin" --quiet >/dev/null 2>"$TMP/err" &&
    "$ROMKIT" run "$TMP/cloud.rombin" --steps 30 --scene "$TMP/cloud.json" --report "$TMP/cloud_run.json" --quiet \
        >/dev/null 2>>"$TMP/err"; then
    json_checks run_scene_measures_a_cloud "$TMP/cloud_run.json" 'contact.intersections=0' \
        'contact.intersecting_frames=0' 'contact.frames=31'
    # apart, and landed (closer than dhat)
    d=$(json_num "$TMP/cloud_run.json" contact.min_distance)
    if below 0 "$d" && below "$d" 1e-3; then ok run_scene_cloud_distance_is_positive_and_landed
    else fail run_scene_cloud_distance_is_positive_and_landed "min_distance '$d'"; fi
else
    fail run_scene_measures_a_cloud "$(cat "$TMP/err")"
fi

# each moving obstacle is its own progress unknown in the runtime's joint solve, which has room for
# RK_MAX_MOVING_OBSTACLES (8): a ninth is refused at bake, by name
nine=""
for i in 0 1 2 3 4 5 6 7 8; do
    nine="$nine${nine:+, }{\"sphere\": {\"center\": [0.$i, -0.2, 0.3], \"radius\": 0.02}, \"translate\": {\"velocity\": [0, 0, 0.1]}}"
done
cat >"$TMP/nine.json" <<JSON
{"objects": [{"mesh": {"box": {"size": [0.2, 0.05, 0.2], "cells": [2, 1, 2]}, "translate": [-0.1, 0, -0.1]},
  "material": {"model": "neohookean", "young": 1e5, "poisson": 0.4, "density": 1000}}],
 "gravity": [0, -9.81, 0], "obstacles": [$nine], "contact": {"dhat": 0.002},
 "time": {"step": 0.01, "duration": 0.03}, "rom": {"basis": "modes", "size": 6}}
JSON
expect_fail build_refuses_a_ninth_moving_obstacle "obstacle 8 moves: the runtime takes at most 8 moving obstacles" \
    "$ROMKIT" build "$TMP/nine.json" -o "$TMP/nine.rombin" --quiet
