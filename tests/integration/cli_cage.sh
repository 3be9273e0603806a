# A detailed surface simulated on a coarse cage (issue 32): romkit mesh --cage-tets, then a scene's
# mesh.cage baked with skinning eigenmodes and cubature, whose asset shows spot.obj itself: romkit
# run --frames writes OBJ frames with spot's 11,533 vertices and 23,062 triangles.
. tests/lib.sh
D=tests/data/meshes
if [ -z "${ROMKIT_TETGEN:-}" ] && ! command -v tetgen >/dev/null 2>&1; then
    echo "skip cli_cage: tetgen not on PATH, and the cage is tetrahedralized with it (sh tools/install-deps.sh test)"
    exit 0
fi

# The cage keeps to its budget and says how many surface vertices it holds.
"$ROMKIT" mesh "$D/spot.obj" -o "$TMP/cage.msh" --cage-tets 20000 >"$TMP/out" 2>"$TMP/err"
tets=$(sed -n 's/.*cage of \([0-9]*\) tets (at most 20000).*/\1/p' "$TMP/out")
[ -n "$tets" ] && [ "$tets" -le 20000 ] && grep -q "of 11533 surface vertices inside" "$TMP/out" \
    && ok cage_within_budget || fail cage_within_budget "$(cat "$TMP/out" "$TMP/err")"
expect_fail cage_needs_a_surface "surface input only" "$ROMKIT" mesh "$D/bunny_19k.msh" -o "$TMP/b.msh" --cage-tets 500
expect_fail cage_budget_at_least_100 "cage-tets" "$ROMKIT" mesh "$D/spot.obj" -o "$TMP/b.msh" --cage-tets 99

# A 5,000-tet cage is too coarse for spot's legs: the vertices it leaves outside are reported (a
# warning naming the count, the report's cage.outside), and still shown.
"$ROMKIT" build tests/data/scenes/spot_cage.json -o "$TMP/spot.rombin" --report "$TMP/A.json" >"$TMP/out" 2>"$TMP/err" \
    && ok cage_scene_builds || fail cage_scene_builds "$(cat "$TMP/err")"
outside=$(json_num "$TMP/A.json" cage.outside)
grep -q "surface vertices are outside the cage" "$TMP/err" && [ -n "$outside" ] && [ "$outside" -gt 0 ] \
    && ok outside_vertices_reported || fail outside_vertices_reported "outside=$outside $(cat "$TMP/err")"
json_checks asset_shows_the_surface "$TMP/A.json" asset.shown_vertices=11533 asset.triangles=23062 \
    cage.surface_vertices=11533 cage.surface_triangles=23062

"$ROMKIT" run "$TMP/spot.rombin" --steps 3 --frames "$TMP/frames" >"$TMP/out" 2>"$TMP/err" || fail run_frames "$(cat "$TMP/err")"
f="$TMP/frames/frame_00003.obj"
[ -f "$f" ] && [ "$(grep -c '^v ' "$f")" -eq 11533 ] && [ "$(grep -c '^f ' "$f")" -eq 23062 ] \
    && ok frames_have_the_original_counts || fail frames_have_the_original_counts "$(ls "$TMP/frames" | head -3)"
