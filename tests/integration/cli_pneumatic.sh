# Pneumatic chambers (koopman-dmd-log-linear paper, Sec. 7.3, Figs. 14-15): a soft finger
# (examples/scenes/finger_pneumatic.json, 8 x 2 x 2 cm, E 5e5 Pa, nu 0.45, clamped at its base)
# with a void along its upper side whose walls are chamber c0. The target is a full-order run under
# a pressure schedule the control is not told (examples/scenes/finger_pneumatic_target.json's,
# compressed to 0.6 s: up to 1e4 Pa, down to 4e3, up to 7e3, held); romkit control solves for c0's
# pressure frame by frame (input c0:p, the tip followed, A(X) updated from the predicted state,
# trained at 7e3 Pa) and full order is replayed under it with the pressure as a follower load. The
# paper's bars, per frame: under 2% for most frames (read as 90%), under 6% for all. Measured: at
# most 2.83%, 57 of 61 frames under 2%; the solved pressures within 2.8% of the schedule from the
# sixth frame on (6.2% at the first). The finger is not linear: trained at 5e4 for a hidden 6e4 Pa
# full order misses by 11% (docs/commands.md), so the schedule stays below 0.02 E.
. tests/lib.sh

SCENE=examples/scenes/finger_pneumatic.json
sed 's/"duration": 1.0/"duration": 0.6/' "$SCENE" >"$TMP/finger.json"
sed 's/"pressure": 0}/"pressure": [[0, 0], [0.15, 1e4], [0.35, 4e3], [0.5, 7e3]]}/' "$TMP/finger.json" >"$TMP/pressed.json"
"$ROMKIT" fom "$TMP/pressed.json" --snapshots "$TMP/target.npy" --quiet >/dev/null 2>"$TMP/err" \
    || fail pneumatic_target_run "$(cat "$TMP/err")"

if "$ROMKIT" control "$TMP/finger.json" --target "$TMP/target.npy" --inputs c0:p --follow tip --train-pressure 7e3 \
        --regularize 0 --report "$TMP/c.json" --forces "$TMP/C.npy" --quiet >"$TMP/out" 2>"$TMP/err"; then
    echo "# $(cat "$TMP/out")"
    json_checks pneumatic_report_keys "$TMP/c.json" frames=61 'inputs[0].chamber="c0"' error.fom_vs_target.max_percent
    for which in fom_vs_target model_vs_fom; do
        mx=$(json_num "$TMP/c.json" error.$which.max_percent)
        u2=$(json_num "$TMP/c.json" error.$which.frames_under_2_percent)
        below "$mx" 6 && [ "${u2:-0}" -ge 55 ] && ok "pneumatic_${which}_meets_the_papers_bars" \
            || fail "pneumatic_${which}_meets_the_papers_bars" "max $mx% (limit 6), $u2 of 61 frames under 2% (limit 55)"
    done
    # row t acts from frame t to t + 1: against the schedule at (t + 1) h, within 5% from frame 5 on
    bad=$(npy_values "$TMP/C.npy" | awk '{ t = NR * 0.01
              if (t <= 0.15) p = 1e4 * t / 0.15; else if (t <= 0.35) p = 1e4 - 6e3 * (t - 0.15) / 0.2
              else if (t <= 0.5) p = 4e3 + 3e3 * (t - 0.35) / 0.15; else p = 7e3
              d = $1 - p; if (d < 0) d = -d; if (NR > 5 && d > 0.05 * p) n++ } END { print n + 0 }')
    [ "$(npy_shape "$TMP/C.npy")" = "60, 1" ] && [ "$bad" -eq 0 ] && ok pneumatic_recovers_the_hidden_schedule \
        || fail pneumatic_recovers_the_hidden_schedule "shape '$(npy_shape "$TMP/C.npy")', $bad of 55 pressures off by more than 5%"
else
    fail pneumatic_control_follows_the_target "$(cat "$TMP/err")"
fi

expect_fail pneumatic_names_an_unknown_chamber 'no chamber "c9"' \
    "$ROMKIT" control "$TMP/finger.json" --target "$TMP/target.npy" --inputs c9:p --follow tip --train-pressure 1 --quiet
expect_fail pneumatic_needs_a_followed_group "no group to follow" \
    "$ROMKIT" control "$TMP/finger.json" --target "$TMP/target.npy" --inputs c0:p --train-pressure 1 --quiet
expect_fail pneumatic_needs_a_training_pressure "needs a training pressure" \
    "$ROMKIT" control "$TMP/finger.json" --target "$TMP/target.npy" --inputs c0:p --follow tip --quiet

# Chambers refused by name: a box on no boundary face, half a void's walls (not closed), a name
# given twice, voids in a point cloud.
sed 's/"box": \[\[0.0095, 0.0095, 0.0045\], \[0.0705, 0.0155, 0.0155\]\]/"box": [[0.03, 0.005, 0.005], [0.04, 0.006, 0.006]]/' \
    "$TMP/finger.json" >"$TMP/empty.json"
expect_fail pneumatic_refuses_an_empty_chamber '("c0"): its box holds no boundary face' \
    "$ROMKIT" fom "$TMP/empty.json" --quiet
sed 's/\[0.0705, 0.0155, 0.0155\]/[0.0705, 0.0155, 0.0101]/' "$TMP/finger.json" >"$TMP/open.json"
expect_fail pneumatic_refuses_an_open_chamber "the faces are not a closed surface" \
    "$ROMKIT" fom "$TMP/open.json" --quiet
sed 's/"pressure": 0}/"pressure": 0}, {"name": "c0", "box": [[0, 0, 0], [1, 1, 1]]}/' "$TMP/finger.json" >"$TMP/twice.json"
expect_fail pneumatic_refuses_a_name_twice "'c0' is already objects" \
    "$ROMKIT" fom "$TMP/twice.json" --quiet
sed 's/"pressure": 0}/"pressure": "high"}/' "$TMP/finger.json" >"$TMP/word.json"
expect_fail pneumatic_refuses_a_pressure_that_is_no_number "pressure" \
    "$ROMKIT" fom "$TMP/word.json" --quiet
sed 's/"pressure": 0}/"pressure": [[0, 0], [0.2, 1e4], [0.1, 2e4]]}/' "$TMP/finger.json" >"$TMP/keys.json"
expect_fail pneumatic_refuses_keys_out_of_order "entry 2's time 0.1 s does not come after 0.2 s" \
    "$ROMKIT" fom "$TMP/keys.json" --quiet
sed 's/"pressure": 0}/"pressure": [[0, 0], [0.2, 1e4]]}/' "$TMP/finger.json" >"$TMP/keyed.json"
expect_fail pneumatic_control_refuses_a_pressurised_scene 'chamber "c0" holds' \
    "$ROMKIT" control "$TMP/keyed.json" --target "$TMP/target.npy" --inputs c0:p --follow tip --train-pressure 1 --quiet
# a Koopman bake of a pressurised scene: the fit would take the follower pressure for no forcing
expect_fail pneumatic_koopman_bake_refuses_a_pressure "chamber 0 holds a pressure" \
    "$ROMKIT" build "$TMP/pressed.json" -o "$TMP/pressed.rombin" --quiet
