# romkit mesh as a user drives it: tetrahedralize a surface, convert between tet formats,
# and fail clearly (naming the file) on bad input without leaving output behind.
. tests/lib.sh
D=tests/data/meshes
if [ -z "${ROMKIT_TETGEN:-}" ] && ! command -v tetgen >/dev/null 2>&1; then
    echo "skip cli_mesh: tetgen not on PATH, and romkit mesh tetrahedralizes with it (sh tools/install-deps.sh test)"
    exit 0
fi

if "$ROMKIT" mesh "$D/decimated-knight.off" -o "$TMP/knight.mesh" >"$TMP/out" 2>"$TMP/err"; then
    ok knight_tetrahedralizes
else
    fail knight_tetrahedralizes "$(cat "$TMP/err")"
fi
grep -q "components   1" "$TMP/out" && grep -q "tetrahedra" "$TMP/out" \
    && ok mesh_prints_counts_and_quality || fail mesh_prints_counts_and_quality "$(cat "$TMP/out")"

# Convert the TetGen armadillo to VTK and back through MEDIT: counts survive (1,180 / 3,717).
"$ROMKIT" mesh "$D/armadillo_4k.node" -o "$TMP/a.vtk" --quiet && "$ROMKIT" mesh "$TMP/a.vtk" -o "$TMP/a.mesh" >"$TMP/out" 2>&1
grep -q "vertices     1180" "$TMP/out" && grep -q "tetrahedra   3717" "$TMP/out" \
    && ok convert_keeps_counts || fail convert_keeps_counts "$(cat "$TMP/out")"

# A truncated Gmsh file names itself and a line; nothing is written.
head -c 20000 "$D/bunny_19k.msh" >"$TMP/cut.msh"
expect_fail truncated_mesh_is_named "cut.msh" "$ROMKIT" mesh "$TMP/cut.msh" -o "$TMP/cut.vtk"
[ ! -e "$TMP/cut.vtk" ] && ok failed_convert_writes_nothing || fail failed_convert_writes_nothing "output exists"

# An open surface is refused, naming an edge.
# (all 502 vertices, the last three of the 1,000 faces dropped)
head -n -3 "$D/decimated-knight.off" | sed '2s/.*/502 997 0/' >"$TMP/open.off"
expect_fail open_surface_is_refused "open.off.*edge" "$ROMKIT" mesh "$TMP/open.off" -o "$TMP/open.mesh"
"$ROMKIT" mesh >/dev/null 2>&1; [ $? -eq 2 ] && ok mesh_without_input_exits_2 || fail mesh_without_input_exits_2 "wrong status"

# --refine: the armadillo split 1:8 (3,717 -> 29,736 tets; 1,180 vertices + 5,947 edge midpoints),
# written and read back; a level count out of range is bad usage (status 2).
"$ROMKIT" mesh "$D/armadillo_4k.node" -o "$TMP/a8.mesh" --refine 1 >"$TMP/out" 2>&1 \
    && "$ROMKIT" mesh "$TMP/a8.mesh" -o "$TMP/a8.vtk" >"$TMP/out2" 2>&1
grep -q "refined 1 time: 3717 -> 29736 tets" "$TMP/out" && grep -q "tetrahedra   29736" "$TMP/out2" \
    && grep -q "vertices     7127" "$TMP/out2" && grep -q "components   1" "$TMP/out2" \
    && ok refine_splits_every_tet_in_8 || fail refine_splits_every_tet_in_8 "$(cat "$TMP/out" "$TMP/out2")"
"$ROMKIT" mesh "$D/armadillo_4k.node" -o "$TMP/a5.mesh" --refine 5 >/dev/null 2>"$TMP/err"; rc=$?
[ $rc -eq 2 ] && grep -q "from 0 to 4" "$TMP/err" && [ ! -e "$TMP/a5.mesh" ] && ok refine_5_is_bad_usage \
    || fail refine_5_is_bad_usage "status $rc: $(cat "$TMP/err")"
