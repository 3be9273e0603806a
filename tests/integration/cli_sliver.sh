# Meshes as they come (issue 15): a sliver and a flat tet through romkit mesh (converted intact,
# reported) and romkit fom (the sliver simulated, the flat tet dropped with a warning naming it).
# The fixture is tests/data/meshes/beam_sliver.mesh: slivers tets 13 and 16, flat tet 120
# (tests/unit/test_pipeline_sliver.c says how it was made).
. tests/lib.sh
D=tests/data/meshes

# Converted, not refused: every tet written as it was, so .mesh -> .mesh gives the same file
# (rk_mesh_write wrote the fixture), and the summary names the slivers.
if "$ROMKIT" mesh "$D/beam_sliver.mesh" -o "$TMP/copy.mesh" >"$TMP/out" 2>"$TMP/err"; then
    ok sliver_mesh_converts
else
    fail sliver_mesh_converts "$(cat "$TMP/err")"
fi
cmp -s "$D/beam_sliver.mesh" "$TMP/copy.mesh" && ok sliver_mesh_converts_intact ||
    fail sliver_mesh_converts_intact "output differs"
grep -q "tetrahedra   121" "$TMP/out" && grep -q "slivers      3 " "$TMP/out" &&
    grep -q "flat         1 " "$TMP/out" && grep -q "tet 13 (vertices" "$TMP/out" &&
    grep -q "tet 120 (vertices 16 35 17 54) volume 0 flat" "$TMP/out" &&
    ok sliver_summary_names_them || fail sliver_summary_names_them "$(cat "$TMP/out")"
[ ! -s "$TMP/err" ] && ok conversion_warns_nothing || fail conversion_warns_nothing "$(cat "$TMP/err")"
# Through VTK and back: still 121 tets.
"$ROMKIT" mesh "$D/beam_sliver.mesh" -o "$TMP/b.vtk" --quiet &&
    "$ROMKIT" mesh "$TMP/b.vtk" -o "$TMP/b.msh" >"$TMP/out" 2>&1
grep -q "tetrahedra   121" "$TMP/out" && ok sliver_mesh_survives_vtk || fail sliver_mesh_survives_vtk "$(cat "$TMP/out")"

# A tet that uses a vertex twice is still refused (1-based in the file: tet 121 is 17 36 18 55).
sed 's/^17 36 18 55 0$/17 36 17 55 0/' "$D/beam_sliver.mesh" >"$TMP/twice.mesh"
expect_fail repeated_vertex_is_refused "twice.mesh: tet 120 .*uses vertex 16 twice" \
    "$ROMKIT" mesh "$TMP/twice.mesh" -o "$TMP/twice.vtk"
[ ! -e "$TMP/twice.vtk" ] && ok refused_mesh_writes_nothing || fail refused_mesh_writes_nothing "output exists"

# Simulated: the flat tet and its own vertex dropped, each named on stderr; the slivers kept and
# the run sound (the same 60 Newton iterations as the plain box beam, measured).
if "$ROMKIT" fom tests/data/scenes/beam_sliver.json --report "$TMP/r.json" --quiet >"$TMP/out" 2>"$TMP/err"; then
    ok sliver_scene_runs
else
    fail sliver_scene_runs "$(cat "$TMP/err")"
fi
grep -q "warning: .*beam_sliver.mesh: tet 120 (vertices 16 35 17 54) is flat.*dropped" "$TMP/err" &&
    grep -q "warning: .*vertex 54 used only by dropped flat tets" "$TMP/err" &&
    ok flat_tet_dropped_with_warning || fail flat_tet_dropped_with_warning "$(cat "$TMP/err")"
json_checks sliver_scene_report "$TMP/r.json" vertices=54 tets=120 mesh.flat_dropped=1 mesh.flat_inside=0 \
    mesh.orphans_removed=1 mesh.slivers=2 unconverged_steps=0 final.inverted_elements=0
it=$(json_num "$TMP/r.json" newton_iterations)
awk -v n="$it" 'BEGIN { exit !(n != "" && n <= 66) }' && ok sliver_scene_newton_iterations ||
    fail sliver_scene_newton_iterations "$it Newton iterations (60 without the slivers)"
