# make demo's script (tools/demo.sh) end to end on a small scene with the built-in scene's three
# rom entries: it must bake, run, print the table and draw both pictures.
. tests/lib.sh
B=${ROMKIT_BUILD:-build}
if ROMKIT_DEMO_SCENE=tests/data/demo_small.json ROMKIT_DEMO_STEPS=40 ROMKIT_DEMO_OUT="$TMP/demo" \
        sh tools/demo.sh "$B" >"$TMP/out" 2>&1; then
    ok demo_runs
else
    fail demo_runs "$(tail -c 800 "$TMP/out")"
fi
grep -q "^rkpm_skinning-4-meshfree-cubature" "$TMP/out" && grep -q "the same, 1 Newton step" "$TMP/out" && grep -q "the same, matrix kept 10 steps" "$TMP/out" && grep -q "^koopman-from-half-g" "$TMP/out" && grep -q "speed-up" "$TMP/out" \
    && ok demo_prints_the_table || fail demo_prints_the_table "$(tail -c 800 "$TMP/out")"
for png in error_time strip; do
    f=$TMP/demo/$png.png
    if [ -s "$f" ] && head -c 8 "$f" | od -An -c | grep -q "P   N   G"; then ok demo_draws_$png; else fail demo_draws_$png "no PNG at $f"; fi
done
# Every reduced row has a finite error and time (the runtime ran against the reference).
n=$(grep -c '"' "$TMP/demo/summary.dat" 2>/dev/null)
awk '{ if ($(NF-2) + 0 <= 0 || $(NF-1) == "nan") bad = 1 } END { exit bad }' "$TMP/demo/summary.dat" && [ "$n" = 3 ] \
    && ok demo_summary_has_three_methods || fail demo_summary_has_three_methods "$(cat "$TMP/demo/summary.dat")"
