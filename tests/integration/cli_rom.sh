# romkit rom: a scene of two point clouds (the donut's splats falling onto a block of points) in
# the reduced simulator, the splats written at every frame, and the errors a user meets.
. tests/lib.sh

SCENE=examples/scenes/donut_on_object.json
if "$ROMKIT" rom "$SCENE" --steps 2 --splats "$TMP/splats" --quiet >"$TMP/out" 2>"$TMP/err"; then
    ok rom_runs_two_objects
    [ -f "$TMP/splats/frame_00000.ply" ] && [ -f "$TMP/splats/frame_00002.ply" ] && [ ! -f "$TMP/splats/frame_00003.ply" ] \
        && head -c 300 "$TMP/splats/frame_00002.ply" | grep -q "element vertex 45624" && ok rom_writes_every_frame \
        || fail rom_writes_every_frame "$(ls "$TMP/splats" 2>&1 | head -5)"
    grep -q "2 objects, r = 168" "$TMP/out" && grep -q "contact: 0 exact crossings at most" "$TMP/out" \
        && ok rom_reports_the_contact || fail rom_reports_the_contact "$(cat "$TMP/out")"
else
    fail rom_runs_two_objects "status $?: $(head -c 300 "$TMP/err")"
fi

expect_fail rom_refuses_a_plain_cloud_as_splats "plain point cloud" "$ROMKIT" rom "$SCENE" --steps 0 --splats "$TMP/s1" --object 1 --quiet
expect_fail rom_object_needs_splats "give --splats" "$ROMKIT" rom "$SCENE" --object 0 --quiet
expect_fail rom_names_a_missing_scene "nothing.json" "$ROMKIT" rom "$TMP/nothing.json" --quiet
