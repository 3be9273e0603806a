# A skinning model of a nearly incompressible material with the pointwise volume locks (issue 37:
# 7-55% short of the converged sag on the FreeForm beam); romkit build and romkit compare say so
# when it is asked for, and say nothing with the projected volume (the skinning bases' default), a
# modal basis or a compressible material. romkit compare against linear tets at nu >= 0.4 says the
# reference locks (stderr and reference.warning), and not with "reference": {"order": 2}.
. tests/lib.sh
cantilever "$TMP/s.json" 4 -9.81 '[{"basis": "skinning", "size": 2, "volume": "pointwise"}, {"basis": "skinning", "size": 2},
      {"basis": "modes", "size": 6}]'
sed 's/"poisson": 0.4/"poisson": 0.3/' "$TMP/s.json" >"$TMP/soft.json"

# warns NAME SCENE ENTRY yes|no: romkit build's summary has the warning (yes) or not (no)
warns() {
    "$ROMKIT" build "$2" --entry "$3" -o "$TMP/$1.rombin" >"$TMP/$1.out" 2>&1 || { fail "$1" "$(tail -3 "$TMP/$1.out")"; return; }
    if grep -q "warning: Poisson's ratio 0.4 with the pointwise volume" "$TMP/$1.out"; then got=yes; else got=no; fi
    [ "$got" = "$4" ] && ok "$1" || fail "$1" "warning $got, expected $4: $(cat "$TMP/$1.out")"
}
warns build_warns_pointwise_skinning_at_nu_0_4 "$TMP/s.json" 0 yes
warns build_quiet_with_the_projected_volume "$TMP/s.json" 1 no
warns build_quiet_for_modes "$TMP/s.json" 2 no
"$ROMKIT" build "$TMP/soft.json" --entry 0 -o "$TMP/soft.rombin" >"$TMP/soft.out" 2>&1 && ! grep -q warning "$TMP/soft.out" \
    && ok build_quiet_at_nu_0_3 || fail build_quiet_at_nu_0_3 "$(cat "$TMP/soft.out")"

"$ROMKIT" compare "$TMP/s.json" --report "$TMP/c.json" >"$TMP/c.out" 2>&1 || fail compare_runs "$(tail -3 "$TMP/c.out")"
grep -q "warning: skinning-2: Poisson's ratio 0.4" "$TMP/c.out" && ok compare_prints_the_warning \
    || fail compare_prints_the_warning "$(tail -6 "$TMP/c.out")"
n=$(grep -c '"volume_warning"' "$TMP/c.json")
[ "$n" = 1 ] && ok compare_report_has_one_volume_warning || fail compare_report_has_one_volume_warning "$n in $TMP/c.json"
grep -q "romkit compare: warning: Poisson's ratio 0.4: the reference runs on linear tets" "$TMP/c.out" \
    && grep -q '"reference": {"order": 2}' "$TMP/c.out" && ok compare_says_the_p1_reference_locks \
    || fail compare_says_the_p1_reference_locks "$(tail -3 "$TMP/c.out")"
grep -q '"warning":.*linear tets' "$TMP/c.json" && ok compare_report_has_the_reference_warning \
    || fail compare_report_has_the_reference_warning "no reference.warning in $TMP/c.json"
# the same scene against quadratic tets (96 of them: a second), one entry: no reference warning
cantilever "$TMP/p2.json" 4 -9.81 '[{"basis": "skinning", "size": 2}]'
sed -i 's/"rom": \[/"reference": {"order": 2}, "rom": [/' "$TMP/p2.json"
if "$ROMKIT" compare "$TMP/p2.json" --report "$TMP/p2c.json" >"$TMP/p2c.out" 2>&1; then
    ! grep -q "the reference runs on linear tets" "$TMP/p2c.out" && ! grep -q '"warning"' "$TMP/p2c.json" \
        && ok compare_quiet_against_quadratic_tets || fail compare_quiet_against_quadratic_tets "$(tail -3 "$TMP/p2c.out")"
else
    fail compare_quiet_against_quadratic_tets "$(tail -3 "$TMP/p2c.out")"
fi
# a clamped skinning basis chosen by tolerance keeps a prefix of its weights; the default's
# pressure space rebuilds them unclamped without the frames, and takes as many (pipeline/volume.c)
cantilever "$TMP/tol.json" 4 -9.81 '{"basis": "skinning", "tolerance": 0.05}'
if "$ROMKIT" build "$TMP/tol.json" -o "$TMP/tol.rombin" --quiet >"$TMP/tol.out" 2>&1 &&
    "$ROMKIT" inspect "$TMP/tol.rombin" | grep -q '^ *VPRS'; then ok build_projected_by_tolerance
else fail build_projected_by_tolerance "$(tail -3 "$TMP/tol.out")"; fi
