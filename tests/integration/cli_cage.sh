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

# The runtime's free run measured against full order at the surface it shows: the full-order frames
# are the cage's, carried to the surface by --scene (each vertex's rest position plus its cage
# tet's displacement at its barycentric coordinates). Without --scene the run says what to give.
if "$ROMKIT" fom tests/data/scenes/spot_cage.json --snapshots "$TMP/ref.npy" --quiet >"$TMP/out" 2>"$TMP/err" &&
   "$ROMKIT" run "$TMP/spot.rombin" --steps 20 --reference "$TMP/ref.npy" --scene tests/data/scenes/spot_cage.json \
       --quiet >"$TMP/out" 2>"$TMP/err"; then
    rel=$(sed -n 's/.*over 20 frames: relative error \([0-9.e+-]*\),.*/\1/p' "$TMP/out")
    [ -n "$rel" ] && below "$rel" 0.1 && ok run_reference_through_the_cage \
        || fail run_reference_through_the_cage "relative error '$rel': $(cat "$TMP/out")"
else
    fail run_reference_through_the_cage "$(tail -c 600 "$TMP/err")"
fi
expect_fail run_reference_cage_needs_the_scene "give --scene" "$ROMKIT" run "$TMP/spot.rombin" --steps 2 \
    --reference "$TMP/ref.npy"
