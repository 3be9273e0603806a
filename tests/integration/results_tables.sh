# bench/tables.py (make results-tables): docs/results/*.md are what it writes from the committed
# bench/results (so no table there is edited by hand), and on a small CSV it merges X, X_min and
# X_max, splits by a section column, drops empty columns and keeps 4 significant digits.
. tests/lib.sh

if python3 bench/tables.py bench/results "$TMP/docs" >"$TMP/out" 2>"$TMP/err"; then
    if diff -r "$TMP/docs" docs/results >"$TMP/diff"; then ok results_tables_are_regenerated
    else fail results_tables_are_regenerated "docs/results differs from make results-tables' output: $(head -c 400 "$TMP/diff")"; fi
else
    fail results_tables_are_regenerated "$(cat "$TMP/err")"
fi

mkdir -p "$TMP/in"
cat >"$TMP/in/toy.csv" <<'CSV'
section,case,tets,s_per_step,s_per_step_min,s_per_step_max,unused
a,box,12000,0.123456789,0.1,0.2,
b,ball,7,2.5e-07,2e-07,3e-07,
CSV
python3 bench/tables.py "$TMP/in" "$TMP/toy" >/dev/null 2>"$TMP/err"
page=$TMP/toy/toy.md
if [ -f "$page" ] && grep -q '^## section a$' "$page" && grep -q '^## section b$' "$page" \
    && grep -q '^| box | 12,000 | 0.1235 (0.1..0.2) |$' "$page" && grep -q '^| ball | 7 | 2.5e-07 (2e-07..3e-07) |$' "$page" \
    && ! grep -q unused "$page" && grep -q '(toy.md)' "$TMP/toy/README.md"; then ok results_tables_format
else fail results_tables_format "$(cat "$TMP/err" "$page" 2>/dev/null | head -c 600)"; fi

expect_fail results_tables_names_a_missing_folder "no such folder" python3 bench/tables.py "$TMP/nothing" "$TMP/x"
