# romkit compare: the report's keys (DESIGN.md), the table on stdout, and the errors a user meets.
. tests/lib.sh

scene() { cantilever "$1" 8 -9.81 "$2"; } # scene FILE ROM_JSON: tests/lib.sh's cantilever, 8 cells

"$ROMKIT" compare --help | grep -q "normalized MSE" && ok compare_help || fail compare_help "no description"

scene "$TMP/c.json" '[{"basis": "modes", "size": 6}, {"basis": "modes", "size": 6, "cubature": {"tolerance": 0.02}, "name": "modes-cub"}]'
if "$ROMKIT" compare "$TMP/c.json" --report "$TMP/r.json" >"$TMP/out" 2>"$TMP/err"; then
    # methods[0] is the full-order run, then the rom entries in order.
    set -- vertices tets seconds.total 'methods[0].name="fom"' 'methods[1].name="modes-6"' 'methods[2].name="modes-cub"'
    for i in 0 1 2; do
        set -- "$@" "methods[$i].seconds_per_step" "methods[$i].normalized_mse" "methods[$i].relative_online_error"
    done
    for i in 1 2; do
        set -- "$@" "methods[$i].cubature.elements" "methods[$i].cubature.relative_error" "methods[$i].cubature.bound_by"
    done
    json_checks compare_report_keys "$TMP/r.json" "$@"
    grep -q "modes-cub" "$TMP/out" && grep -q "speed-up" "$TMP/out" && ok compare_prints_table \
        || fail compare_prints_table "$(head -c 300 "$TMP/out")"
    # A cubature method has fewer elements than the mesh and a training error under its tolerance.
    n=$(json_num "$TMP/r.json" 'methods[2].cubature.elements')
    e=$(json_num "$TMP/r.json" 'methods[2].cubature.relative_error')
    tets=$(json_num "$TMP/r.json" tets)
    [ -n "$n" ] && [ -n "$e" ] && [ -n "$tets" ] && [ "$n" -ge 1 ] && [ "$n" -lt "$tets" ] \
        && awk -v e="$e" 'BEGIN { exit !(e >= 0 && e < 0.02) }' && ok compare_cubature_trained \
        || fail compare_cubature_trained "$n of $tets elements, training error $e (tolerance 0.02)"
else
    fail compare_report_keys "$(cat "$TMP/err")"
fi

# A refined reference: its size in the report and on stdout, the fom row its own error against it.
scene "$TMP/ref.json" '[{"basis": "modes", "size": 6}], "reference": {"refine": 1}'
if "$ROMKIT" compare "$TMP/ref.json" --quiet --report "$TMP/ref_r.json" >"$TMP/out" 2>"$TMP/err"; then
    json_checks compare_reference_keys "$TMP/ref_r.json" reference.refine=1 reference.vertices=425 \
        reference.tets=1536 reference.measured_vertices=81 reference.seconds_per_step vertices=81 tets=192 \
        'methods[0].name="fom"' 'methods[0].relative_online_error=null' 'methods[1].normalized_mse'
    e=$(json_num "$TMP/ref_r.json" 'methods[0].normalized_mse')
    [ -n "$e" ] && awk -v e="$e" 'BEGIN { exit !(e > 0) }' && ok compare_reference_fom_error \
        || fail compare_reference_fom_error "fom nMSE against the refined reference: '$e'"
    grep -q "reference: refine 1, 425 vertices, 1536 linear tets" "$TMP/out" && ok compare_reference_printed \
        || fail compare_reference_printed "$(head -c 400 "$TMP/out")"
else
    fail compare_reference_keys "$(cat "$TMP/err")"
fi
json_checks compare_reference_default "$TMP/r.json" reference.refine=0 'methods[0].normalized_mse=0'
# A quadratic-tet reference on the scene's own mesh (rk_p2_fom_run): P2 converges where P1 locks in
# bending (nu = 0.4), so the scene's P1 run is further from it than from P1 refined once.
scene "$TMP/p2.json" '[{"basis": "modes", "size": 6}], "reference": {"order": 2}'
if "$ROMKIT" compare "$TMP/p2.json" --quiet --report "$TMP/p2_r.json" >"$TMP/out" 2>"$TMP/err"; then
    json_checks compare_p2_reference_keys "$TMP/p2_r.json" reference.order=2 reference.refine=0 reference.tets=192
    e2=$(json_num "$TMP/p2_r.json" 'methods[0].normalized_mse'); e1=$(json_num "$TMP/ref_r.json" 'methods[0].normalized_mse')
    echo "# the scene's P1 run against P2 on its mesh: nMSE $e2; against P1 refined once: $e1"
    [ -n "$e2" ] && [ -n "$e1" ] && awk -v a="$e2" -v b="$e1" 'BEGIN { exit !(a > b && b > 0) }' \
        && ok compare_p2_reference_is_further_converged || fail compare_p2_reference_is_further_converged "P2 $e2, P1 refined $e1"
    grep -q "reference: refine 0, 81 vertices, 192 quadratic tets" "$TMP/out" && ok compare_p2_reference_printed \
        || fail compare_p2_reference_printed "$(head -c 400 "$TMP/out")"
else
    fail compare_p2_reference_keys "$(cat "$TMP/err")"
fi
scene "$TMP/badorder.json" '[{"basis": "modes", "size": 6}], "reference": {"order": 3}'
expect_fail compare_reference_bad_order "reference.order" "$ROMKIT" compare "$TMP/badorder.json"
scene "$TMP/badref.json" '[{"basis": "modes", "size": 6}], "reference": {"refine": 5}'
expect_fail compare_reference_too_fine "into 6291456 tets" "$ROMKIT" compare "$TMP/badref.json"

# A method that cannot be built is reported by name, the others still run, and the exit is 1.
scene "$TMP/bad.json" '[{"basis": "modes", "size": 4}, {"basis": "pod", "size": 500}]'
expect_fail compare_names_failed_method "pod-500 failed" "$ROMKIT" compare "$TMP/bad.json" --quiet
grep -q "modes-4" "$TMP/out" && ok compare_runs_the_rest || fail compare_runs_the_rest "$(head -c 300 "$TMP/out")"

scene "$TMP/norom.json" 'null'
sed -i '/"rom": null/d; s/"duration": 0.2},/"duration": 0.2}/' "$TMP/norom.json"
expect_fail compare_needs_rom "no \"rom\" section" "$ROMKIT" compare "$TMP/norom.json"
expect_fail compare_missing_scene "nope.json" "$ROMKIT" compare "$TMP/nope.json"
scene "$TMP/badcub.json" '{"basis": "modes", "size": 4, "cubature": {"tolerance": -1}}'
expect_fail compare_bad_cubature_tolerance "rom.cubature" "$ROMKIT" compare "$TMP/badcub.json"
