# romkit compare and romkit run --reference compute their errors through one module (util/metrics):
# an asset that shows every vertex, stepped by the runtime against the full-order frames, reports
# the normalized MSE and relative error that romkit compare reports for the same method. The two
# runs differ only by the runtime's float arithmetic (a float64 asset, float32 math).
. tests/lib.sh
JSONQ=${JSONQ:-$ROMKIT_BUILD/jsonq}
S=tests/data/scenes/cantilever_show_all.json
if "$ROMKIT" compare "$S" --quiet --report "$TMP/c.json" >/dev/null 2>"$TMP/err" &&
   "$ROMKIT" build "$S" -o "$TMP/a.rombin" --quiet >/dev/null 2>>"$TMP/err" &&
   "$ROMKIT" fom "$S" --snapshots "$TMP/S.npy" --quiet >/dev/null 2>>"$TMP/err" &&
   "$ROMKIT" run "$TMP/a.rombin" --steps 30 --reference "$TMP/S.npy" --report "$TMP/r.json" --quiet >/dev/null 2>>"$TMP/err"; then
    for k in normalized_mse relative_error; do
        c=$("$JSONQ" get "$TMP/c.json" "methods[1].$k") r=$("$JSONQ" get "$TMP/r.json" "reference.$k")
        rel=$(awk -v a="$c" -v b="$r" 'BEGIN { d = a - b; if (d < 0) d = -d; print d / a }')
        echo "# $k: romkit compare $c, romkit run --reference $r (relative difference $rel)"
        awk -v x="$rel" 'BEGIN { exit !(x < 1e-4) }' && ok "run_and_compare_agree_on_$k" \
            || fail "run_and_compare_agree_on_$k" "compare $c, run $r"
    done
else
    fail run_and_compare_agree "$(head -c 300 "$TMP/err")"
fi
