# romkit compare and romkit build on two small scenes against what they gave before the solver
# and pipeline refactor (tests/data/golden/*.before.json, assets.md5; recorded with romkit at
# commit 28277de): every error, size and iteration count to 1e-12 relative in the double path, and
# bit-identical assets. A change that alters these numbers on purpose records them again, and says
# why in its commit. Recorded again: the assets for rombin 1.1 (CVTX); the reports for the
# analytic PSD projection of dP/dF, which moved them by at most 1.5e-12 relative.
. tests/lib.sh
JSONQ=${JSONQ:-$ROMKIT_BUILD/jsonq}
G=tests/data/golden

method_keys() { # method_keys I: the deterministic keys of method I
    for k in name kind basis.type basis.size basis.columns cubature.elements cubature.relative_error \
             normalized_mse normalized_max_error max_error relative_online_error newton_iterations \
             unconverged_steps; do
        printf 'methods[%d].%s ' "$1" "$k"
    done
}

for s in cantilever twist; do
    if "$ROMKIT" compare "$G/golden_$s.json" --quiet --report "$TMP/$s.json" >"$TMP/out" 2>"$TMP/err"; then
        n=$("$JSONQ" get "$G/$s.before.json" methods | grep -o '"name"' | wc -l)
        keys="vertices tets steps bbox_diagonal fom.newton_iterations"
        i=1 # methods[0] is fom itself
        while [ "$i" -lt "$n" ]; do keys="$keys $(method_keys "$i")"; i=$((i + 1)); done
        # shellcheck disable=SC2086
        if "$JSONQ" same "$G/$s.before.json" "$TMP/$s.json" 1e-12 $keys >"$TMP/diff"; then
            ok "golden_compare_$s ($((n - 1)) methods)"
        else
            fail "golden_compare_$s" "$(head -c 600 "$TMP/diff")"
        fi
    else
        fail "golden_compare_$s" "$(head -c 300 "$TMP/err")"
    fi
    "$ROMKIT" build "$G/golden_$s.json" -o "$TMP/$s.rombin" --quiet >/dev/null 2>"$TMP/err" \
        || fail "golden_asset_$s" "$(head -c 300 "$TMP/err")"
    want=$(grep " $s.rombin" "$G/assets.md5" | cut -d' ' -f1)
    got=$(md5sum <"$TMP/$s.rombin" | cut -d' ' -f1)
    [ "$want" = "$got" ] && ok "golden_asset_$s" || fail "golden_asset_$s" "md5 $got, recorded $want"
done
