# A smaller pour (issue 30; bench/pour.sh runs 8 objects): 4 boxes, each its own skinning basis,
# dropped in a loose stack into an open triangle-mesh box and stepped 60 times (1 s at 1/60 s: the
# top pair lands on the bottom pair) by the float and the double runtime, Newton to the asset's
# tolerance and 2 fixed Newton steps per step. Every frame is checked by the exact
# segment-triangle test: no crossing, and the closest pair stays apart.
. tests/lib.sh
python3 bench/pour_scene.py "$TMP" 4 1.0
if "$ROMKIT" build "$TMP/pour.json" -o "$TMP/f32.rombin" --quiet >/dev/null 2>"$TMP/err" &&
    "$ROMKIT" build "$TMP/pour.json" -o "$TMP/f64.rombin" --quiet --precision float64 >/dev/null 2>>"$TMP/err"; then
    for p in f32 f64; do
        rk="$ROMKIT"
        [ $p = f64 ] && rk="$ROMKIT-double"
        for k in 0 2; do
            name=pour_${p}_newton_${k}_never_crosses
            if "$rk" run "$TMP/$p.rombin" --steps 60 --newton $k --scene "$TMP/pour.json" --report "$TMP/$p$k.json" \
                --quiet >/dev/null 2>"$TMP/err"; then
                json_checks "$name" "$TMP/$p$k.json" 'contact.intersections=0' 'contact.intersecting_frames=0' \
                    'contact.frames=61'
                d=$(json_num "$TMP/$p$k.json" contact.min_distance)
                # apart, and in contact (within dhat = 2 mm): the stack has landed
                if below 0 "$d" && below "$d" 0.002; then ok "${name}_and_lands"
                else fail "${name}_and_lands" "min_distance '$d'"; fi
            else
                fail "$name" "$(cat "$TMP/err")"
            fi
        done
    done
else
    fail pour_bakes "$(cat "$TMP/err")"
fi
