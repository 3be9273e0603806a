# romkit run --scene: the runtime's frames measured for contact as romkit fom measures its own
# (contact.min_distance, contact.intersections by the exact segment-triangle test,
# intersecting_frames, frames), on a block dropped at 1 m/s onto a plane; the same keys in the fom
# report; and the scenes run refuses to measure against, by name.
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

# refusals: another scene's asset, a scene with nothing to collide with, an asset that does not
# show its collision surface
SCENE=examples/scenes/cantilever_small.json
"$ROMKIT" build "$SCENE" -o "$TMP/c.rombin" --quiet >/dev/null 2>&1
expect_fail run_scene_must_be_the_assets "is this the scene the asset was built from" \
    "$ROMKIT" run "$TMP/c.rombin" --steps 1 --scene "$TMP/drop.json"
expect_fail run_scene_needs_contact "no contact to measure" "$ROMKIT" run "$TMP/c.rombin" --steps 1 --scene "$SCENE"
sed 's/"size": 12}}/"size": 12, "asset": {"show": "none", "groups": [{"name": "all", "box": [[-1, -1, -1], [1, 1, 1]]}]}}}/' \
    "$TMP/drop.json" >"$TMP/hidden.json"
"$ROMKIT" build "$TMP/hidden.json" -o "$TMP/hidden.rombin" --quiet >/dev/null 2>&1
expect_fail run_scene_needs_the_surface_shown "the asset does not show it" \
    "$ROMKIT" run "$TMP/hidden.rombin" --steps 1 --scene "$TMP/hidden.json"
expect_fail run_scene_missing_file "cannot open" "$ROMKIT" run "$TMP/drop.rombin" --steps 1 --scene "$TMP/none.json"
# a point cloud collides through its contact proxy, which its asset stores but does not show
"$ROMKIT" build tests/fuzz/seed_points.json -o "$TMP/points.rombin" --quiet >/dev/null 2>&1
expect_fail run_scene_says_a_cloud_is_not_measured "is a point cloud" \
    "$ROMKIT" run "$TMP/points.rombin" --steps 1 --scene tests/fuzz/seed_points.json
