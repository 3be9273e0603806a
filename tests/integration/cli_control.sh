# romkit control (koopman-dmd-log-linear paper, Sec. 7.3, Figs. 14-15): forces on a named group
# solved so that a scene's Koopman model follows a target trajectory, then replayed at full order.
# The target is another full-order run of the same beam, pushed at the tip by a load the control
# is not told ((0, 6, 3) N, held); the inputs are the tip group's y and z forces. The paper's bars,
# per frame: under 2% for most frames, under 6% for all. Measured (ranks 20, 40, 60 of this
# beam): at most 0.09%, 0.03%, 0.02%; the same beam 10x softer (0.2 m tip deflection, geometric
# nonlinearity) stays under 6% but not under 2% for most frames (NOTES-kctl.md).
. tests/lib.sh

cat >"$TMP/beam.json" <<'JSON'
{
  "objects": [{
    "mesh": {"box": {"size": [1.0, 0.1, 0.1], "cells": [10, 2, 2]}},
    "material": {"model": "neohookean", "young": 1e7, "poisson": 0.3, "density": 1000},
    "fixed": [{"box": [[-0.01, -1, -1], [0.01, 1, 1]]}]
  }],
  "gravity": [0, -9.81, 0],
  "damping": {"mass": 0.5},
  "time": {"step": 0.01, "duration": 1.0},
  "rom": {"basis": "pod", "size": 12, "koopman": {"rank": 40, "clamp": true},
          "asset": {"groups": [{"name": "tip", "box": [[0.95, -1, -1], [1.1, 1, 1]]}]}}
}
JSON
sed 's/"fixed": \[/"loads": [{"box": [[0.95, -1, -1], [1.1, 1, 1]], "force": [0, 6, 3]}], "fixed": [/' \
    "$TMP/beam.json" >"$TMP/pushed.json"
"$ROMKIT" fom "$TMP/pushed.json" --snapshots "$TMP/target.npy" --quiet >/dev/null 2>"$TMP/err" \
    || fail control_target_run "$(cat "$TMP/err")"

if "$ROMKIT" control "$TMP/beam.json" --target "$TMP/target.npy" --inputs tip:yz --report "$TMP/c.json" \
        --forces "$TMP/C.npy" --snapshots "$TMP/S.npy" --quiet >"$TMP/out" 2>"$TMP/err"; then
    echo "# $(cat "$TMP/out")"
    json_checks control_report_keys "$TMP/c.json" frames=101 koopman.rank=40 'inputs[1].axis="z"' regularize=0.2 \
        error.fom_vs_target.per_frame_percent error.model_vs_fom.per_frame_percent seconds.solve_per_frame
    # Figs. 14-15's bars on the full-order run under the solved forces against the target, and on
    # the model against that full-order run (what Fig. 15 plots); "most" read as 90% of the frames.
    for which in fom_vs_target model_vs_fom; do
        mx=$(json_num "$TMP/c.json" error.$which.max_percent)
        u2=$(json_num "$TMP/c.json" error.$which.frames_under_2_percent)
        below "$mx" 6 && [ "${u2:-0}" -ge 91 ] && ok "control_${which}_meets_the_papers_bars" \
            || fail "control_${which}_meets_the_papers_bars" "max $mx% (limit 6), $u2 of 101 frames under 2% (limit 91)"
    done
    # The solved forces are the load that made the target: (6, 3) N, each frame within 5%, the
    # first frames included (from rest, where a one-step solve sees the least motion).
    if [ "$(npy_shape "$TMP/C.npy")" = "100, 2" ]; then
        bad=$(npy_values "$TMP/C.npy" | awk 'NR % 2 == 1 { t = 6 } NR % 2 == 0 { t = 3 }
              { d = $1 - t; if (d < 0) d = -d; if (d > 0.05 * t) n++ } END { print n + 0 }')
        [ "$bad" -eq 0 ] && ok control_recovers_the_hidden_load || fail control_recovers_the_hidden_load "$bad of 200 forces off by more than 5%"
    else
        fail control_recovers_the_hidden_load "forces shape '$(npy_shape "$TMP/C.npy")', expected 100, 2"
    fi
    [ "$(npy_shape "$TMP/S.npy")" = "101, 99, 3" ] && ok control_writes_the_full_order_run \
        || fail control_writes_the_full_order_run "shape '$(npy_shape "$TMP/S.npy")'"
else
    fail control_follows_the_target "$(cat "$TMP/err")"
fi

# The axial force too (tip:xyz) at rank 60: a pull along the stiff beam moves it little and the fit
# gets its column wrong. Unregularised the loop breaks the bars (asserted, so that this case keeps
# testing something); with the default regularisation it meets them, and the solved x force stays
# near the hidden load's 0 (under 5 N at every frame, where unregularised it reaches 405 N).
sed 's/"rank": 40/"rank": 60/' "$TMP/beam.json" >"$TMP/beam60.json"
for rho in 0 default; do
    if [ $rho = default ]; then set --; else set -- --regularize $rho; fi
    if "$ROMKIT" control "$TMP/beam60.json" --target "$TMP/target.npy" --inputs tip:xyz --report "$TMP/a.json" \
            --forces "$TMP/Ca.npy" --quiet "$@" >"$TMP/out" 2>"$TMP/err"; then
        mx=$(json_num "$TMP/a.json" error.fom_vs_target.max_percent)
        u2=$(json_num "$TMP/a.json" error.fom_vs_target.frames_under_2_percent)
        xmax=$(npy_values "$TMP/Ca.npy" | awk 'NR % 3 == 1 { x = $1 < 0 ? -$1 : $1; if (x > m) m = x } END { print m + 0 }')
        echo "# axial input, rank 60, regularize $rho: full order vs target max $(printf %.3g "$mx")%, $u2 of 101 frames under 2%, largest |x force| $xmax N"
        if [ $rho = 0 ]; then
            below 6 "$mx" && ok control_axial_unregularized_breaks_the_bars \
                || fail control_axial_unregularized_breaks_the_bars "max $mx%: the case no longer tests the regularisation"
        else
            below "$mx" 6 && [ "${u2:-0}" -ge 91 ] && below "$xmax" 5 && ok control_axial_regularized_meets_the_papers_bars \
                || fail control_axial_regularized_meets_the_papers_bars "max $mx% (limit 6), $u2 of 101 under 2% (limit 91), |x force| up to $xmax N (limit 5)"
        fi
    else
        fail control_axial_regularize_$rho "$(cat "$TMP/err")"
    fi
done
expect_fail control_refuses_a_negative_regularize "--regularize must be a number >= 0" \
    "$ROMKIT" control "$TMP/beam.json" --target "$TMP/target.npy" --inputs tip:yz --regularize -1 --quiet

# A target of another mesh (5 cells along: 54 vertices, not 99): refused, naming the shapes, and
# nothing written.
sed 's/\[10, 2, 2\]/[5, 2, 2]/' "$TMP/pushed.json" >"$TMP/coarse.json"
"$ROMKIT" fom "$TMP/coarse.json" --snapshots "$TMP/coarse.npy" --quiet >/dev/null 2>&1
rm -f "$TMP/bad.json" "$TMP/bad.npy" "$TMP/badS.npy"
expect_fail control_refuses_a_target_of_another_shape "shape 101 x 54 x 3; expected T x 99 x 3" \
    "$ROMKIT" control "$TMP/beam.json" --target "$TMP/coarse.npy" --inputs tip:yz --report "$TMP/bad.json" \
    --forces "$TMP/bad.npy" --snapshots "$TMP/badS.npy" --quiet
left=$(ls "$TMP" | grep -c '^bad')
[ "$left" -eq 0 ] && ok control_writes_nothing_on_bad_input || fail control_writes_nothing_on_bad_input "$(ls "$TMP" | grep '^bad')"
expect_fail control_names_an_unknown_group 'no group "tail"' \
    "$ROMKIT" control "$TMP/beam.json" --target "$TMP/target.npy" --inputs tail:y --quiet
expect_fail control_names_a_bad_axis "axis 'w'" \
    "$ROMKIT" control "$TMP/beam.json" --target "$TMP/target.npy" --inputs tip:w --quiet
