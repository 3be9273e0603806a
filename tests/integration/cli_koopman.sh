# Koopman assets from the command line: romkit build with rom.koopman, romkit dmd on outside
# snapshots (romkit fom's), romkit run stepping, jumping, rescaling and checking against the
# full-order frames; the report keys of DESIGN.md; and the errors a user meets.
. tests/lib.sh
g3() { if [ -n "$1" ]; then printf '%.3g' "$1"; else printf '?'; fi; } # a number for a # line
# npy_frames FILE K OUT: frames 0, K, 2K, ... of a T x n x 3 file as a file of their own. The
# header's shape is rewritten in place (padded with spaces to the same length); fails unless the
# new header says the new shape and the file has exactly the bytes it promises.
npy_frames() {
    hb=$(npy_header_bytes "$1"); old=$(npy_shape "$1")
    case $old in *[0-9],\ *[0-9],\ 3) ;; *) return 1 ;; esac # T, n, 3 (else the arithmetic would end the script)
    T=${old%%,*}; rest=${old#*,}
    nf=$(( (T - 1) / $2 + 1 )); fb=$(( ${rest%%,*} * 24 ))
    from="($old), }"; to="($nf,$rest), }"
    while [ ${#to} -lt ${#from} ]; do to="$to "; done
    { head -c "$hb" "$1" | LC_ALL=C sed "1s/$from/$to/"; k=0
      while [ $k -lt "$nf" ]; do tail -c +$((hb + k * $2 * fb + 1)) "$1" | head -c "$fb"; k=$((k + 1)); done; } >"$3"
    [ "$(npy_shape "$3")" = "$nf,$rest" ] && [ "$(wc -c <"$3")" -eq $((hb + nf * fb)) ]
}

cat >"$TMP/beam.json" <<'JSON'
{
  "objects": [{
    "mesh": {"box": {"size": [1.0, 0.1, 0.1], "cells": [10, 2, 2]}},
    "material": {"model": "neohookean", "young": 1e7, "poisson": 0.3, "density": 1000},
    "fixed": [{"box": [[-0.01, -1, -1], [0.01, 1, 1]]}]
  }],
  "gravity": [0, -9.81, 0],
  "damping": {"mass": 0.2},
  "time": {"step": 0.01, "duration": 1.5},
  "rom": {"basis": "pod", "size": 12, "koopman": {"rank": 20, "clamp": true},
          "asset": {"groups": [{"name": "tip", "box": [[0.95, -1, -1], [1.1, 1, 1]]}]}}
}
JSON

"$ROMKIT" fom "$TMP/beam.json" --snapshots "$TMP/S.npy" >/dev/null 2>&1 || fail fom_snapshots "romkit fom failed"

# romkit build: the scene's own training run, baked as a Koopman asset.
if "$ROMKIT" build "$TMP/beam.json" -o "$TMP/k.rombin" --report "$TMP/k.json" --quiet >"$TMP/out" 2>"$TMP/err"; then
    json_checks build_koopman_report_keys "$TMP/k.json" koopman.rank=20 koopman.max_abs_eigenvalue 'koopman.eigenvalues[0][0]'
    top=$(json_num "$TMP/k.json" koopman.max_abs_eigenvalue)
    awk -v t="$top" 'BEGIN { exit !(t != "" && t <= 1) }' && ok build_koopman_clamped || fail build_koopman_clamped "max |lambda| '$top'"
else
    fail build_koopman_report_keys "$(cat "$TMP/err")"
fi
"$ROMKIT" inspect "$TMP/k.rombin" >"$TMP/out" 2>&1 && grep -q "KHED  critical" "$TMP/out" && grep -q "opens with the runtime" "$TMP/out" \
    && ok inspect_koopman_asset || fail inspect_koopman_asset "$(head -c 400 "$TMP/out")"

# The runtime reproduces the full-order run it learned from.
if "$ROMKIT" run "$TMP/k.rombin" --steps 150 --reference "$TMP/S.npy" --jump 1000000 --report "$TMP/r.json" --quiet >"$TMP/out" 2>"$TMP/err"; then
    e1=$(json_num "$TMP/r.json" reference.relative_error)
    below "$e1" 0.02 && ok koopman_run_matches_the_full_order_run || fail koopman_run_matches_the_full_order_run "relative error $e1"
    json_checks run_reports_seconds_jump "$TMP/r.json" seconds_jump 'kind="koopman"'
    echo "# romkit run on the build's asset: $(sed -n 2,3p "$TMP/out" | tr '\n' ' ')"
else
    fail koopman_run_matches_the_full_order_run "$(cat "$TMP/err")"
fi
# A ten times larger step (Eq. 21) still follows the full-order motion at the common times: 15
# steps of 0.1 s against romkit fom's frames 0, 10, ..., 150 (t = 0, 0.1, ..., 1.5 s), compared by
# --reference (step k against frame k). Measured: 6.3e-5, as close as the training step's own run
# above; a step 10% off (0.09 or 0.11 s) misses by 0.2, and no rescaling at all by 0.64.
if npy_frames "$TMP/S.npy" 10 "$TMP/S10.npy"; then
    if "$ROMKIT" run "$TMP/k.rombin" --steps 15 --dt 0.1 --snapshots "$TMP/big.npy" --reference "$TMP/S10.npy" \
            --report "$TMP/big.json" --quiet >/dev/null 2>"$TMP/err"; then
        e10=$(json_num "$TMP/big.json" reference.relative_error)
        json_is "$TMP/big.json" reference.frames 15 && below "$e10" 1e-3 && ok run_rescales_the_time_step \
            || fail run_rescales_the_time_step "relative error '$e10' over $("$JSONQ" get "$TMP/big.json" reference.frames) frames (limit 1e-3)"
        echo "# --dt 0.1 (10 training steps): relative error $(g3 "$e10") against the full-order frames at t = 0.1 .. 1.5 s (limit 1e-3; the training step's run: $(g3 "$e1"))"
    else
        fail run_rescales_the_time_step "$(cat "$TMP/err")"
    fi
else
    fail run_rescales_the_time_step "could not cut every 10th frame out of romkit fom's snapshots: $(npy_shape "$TMP/S10.npy")"
fi
# --damping MU multiplies every eigenvalue by (1 - MU) (Sec. 7.2). What that implies exactly, and
# is checked here: from the start at rest (state y_0 = 0) under the constant forcing c, the state
# after k steps is y_k = sum_{t=1..k} lambda^t c, so the k-th step moves it by lambda^k c, and
# with the edit by (1 - MU)^k lambda^k c. The shown positions are linear in y, so the damped run's
# k-th frame-to-frame displacement is (1 - MU)^k times the undamped run's, to float32 roundoff
# (measured: 7.8e-6 of the largest undamped displacement; against (1 - MU)^(k +- 1) instead 1.7e-2,
# and 0.32 if the edit did nothing). Its
# kinetic-energy proxy (sum of squared frame-to-frame displacements) over the last 50 steps falls
# to 0.009 of the undamped run's. Not compared with a full-order run with more Rayleigh damping:
# scaling the eigenvalues also moves the forced equilibrium (lambda c / (1 - lambda)), and mass
# damping adds the same decay rate to every mode only approximately, so no scene is its exact twin.
if "$ROMKIT" run "$TMP/k.rombin" --steps 150 --koopman --snapshots "$TMP/u.npy" --quiet >/dev/null 2>"$TMP/err" \
        && "$ROMKIT" run "$TMP/k.rombin" --steps 150 --damping 0.02 --snapshots "$TMP/dmp.npy" --quiet >/dev/null 2>>"$TMP/err"; then
    shape=$(npy_shape "$TMP/u.npy"); per=${shape#*, }; per=$(( ${per%%,*} * 3 ))
    npy_values "$TMP/u.npy" >"$TMP/u.txt"
    npy_values "$TMP/dmp.npy" >"$TMP/dmp.txt"
    # Row r (0-based) of --snapshots is the frame after step r + 1; r against r - 1 is step r + 1.
    set -- $(paste "$TMP/u.txt" "$TMP/dmp.txt" | awk -v per="$per" -v mu=0.02 -v rows=150 '
        NF != 2 { bad = 1 }
        { r = int((NR - 1) / per); j = (NR - 1) % per
          if (r > 0) {
              du = $1 - pu[j]; dd = $2 - pd[j]; e = dd - (1 - mu) ^ (r + 1) * du
              err[r] += e * e; und[r] += du * du
              if (r >= rows - 50) { ku += du * du; kd += dd * dd }
          }
          pu[j] = $1; pd[j] = $2 }
        END {
            if (bad || NR != rows * per || ku == 0) exit
            for (r = 1; r < rows; r++) { if (err[r] > worst) worst = err[r]; if (und[r] > big) big = und[r] }
            printf "%.3g %.3g\n", sqrt(worst / big), kd / ku
        }')
    rel=$1; ke=$2
    below "$rel" 1e-4 && below "$ke" 0.05 && ok run_damping_edit_scales_each_step_by_1_minus_mu \
        || fail run_damping_edit_scales_each_step_by_1_minus_mu "step k off (1 - mu)^k by '$rel' (limit 1e-4), kinetic ratio '$ke' (limit 0.05)"
    echo "# --damping 0.02: step k's displacement is (1 - mu)^k times the undamped run's within $rel of the largest (limit 1e-4); kinetic-energy proxy over the last 50 steps $ke of the undamped run's (limit 0.05)"
else
    fail run_damping_edit_scales_each_step_by_1_minus_mu "$(cat "$TMP/err")"
fi
expect_fail run_rejects_bad_damping "mu must be in" "$ROMKIT" run "$TMP/k.rombin" --steps 1 --damping 1.5

# romkit dmd on the same frames brought from outside.
if "$ROMKIT" dmd --snapshots "$TMP/S.npy" --dt 0.01 --gravity 0,-9.81,0 --rank 20 --clamp -o "$TMP/d.rombin" \
        --report "$TMP/d.json" --quiet >"$TMP/out" 2>"$TMP/err"; then
    json_checks dmd_report_keys "$TMP/d.json" koopman.rank=20 koopman.max_abs_eigenvalue 'koopman.eigenvalues[0][0]' \
        'koopman.residuals[0]'
    "$ROMKIT" run "$TMP/d.rombin" --steps 150 --reference "$TMP/S.npy" --report "$TMP/dr.json" --quiet >/dev/null 2>&1
    e=$(json_num "$TMP/dr.json" reference.relative_error)
    below "$e" 0.02 && ok dmd_asset_matches_the_recording || fail dmd_asset_matches_the_recording "relative error $e"
    "$ROMKIT" dmd --snapshots "$TMP/S.npy" --dt 0.01 --gravity 0,-9.81,0 --rank 20 --clamp -o "$TMP/d2.rombin" --quiet >/dev/null 2>&1
    cmp -s "$TMP/d.rombin" "$TMP/d2.rombin" && ok dmd_is_deterministic || fail dmd_is_deterministic "two fits differ"
    # A recording that starts at rest gives one more training pair: the step out of rest.
    "$ROMKIT" dmd --snapshots "$TMP/S.npy" --dt 0.01 --gravity 0,-9.81,0 --rank 20 --clamp --from-rest -o "$TMP/f.rombin" --quiet >/dev/null 2>&1
    "$ROMKIT" run "$TMP/f.rombin" --steps 150 --reference "$TMP/S.npy" --report "$TMP/fr.json" --quiet >/dev/null 2>&1
    f=$(json_num "$TMP/fr.json" reference.relative_error)
    below "$f" "$e" && ok dmd_from_rest_fits_better || fail dmd_from_rest_fits_better "relative error $f, without $e"
    echo "# romkit dmd on romkit fom's frames, rank 20: relative error $(g3 "$e"), with --from-rest $(g3 "$f")"
else
    fail dmd_report_keys "$(cat "$TMP/err")"
fi
"$ROMKIT" dmd --snapshots "$TMP/S.npy" --dt 0.01 --gravity 0,-9.81,0 --pod 12 --energy 0.9999999 -o "$TMP/p.rombin" --quiet \
    >/dev/null 2>"$TMP/err" && "$ROMKIT" run "$TMP/p.rombin" --steps 20 --quiet >/dev/null 2>&1 \
    && ok dmd_with_pod_projection || fail dmd_with_pod_projection "$(cat "$TMP/err")"
# T x d observables (d = 1661, not a multiple of 3: padded to whole points): the same bytes re-labelled.
# The relabelling must have happened (else this would fit the T x n x 3 file again): the new shape
# is in the header, and only the header's bytes changed.
LC_ALL=C sed '1s/(151, 99, 3), }/(27, 1661), }  /' "$TMP/S.npy" >"$TMP/obs.npy"
hb=$(npy_header_bytes "$TMP/S.npy")
if [ "$(npy_shape "$TMP/obs.npy")" != "27, 1661" ] || cmp -s "$TMP/S.npy" "$TMP/obs.npy" \
        || ! cmp -s -i "$hb" "$TMP/S.npy" "$TMP/obs.npy"; then
    fail dmd_takes_t_by_d_observables "the header rewrite did not take: shape '$(npy_shape "$TMP/obs.npy")'"
elif "$ROMKIT" dmd --snapshots "$TMP/obs.npy" --dt 0.01 --rank 10 -o "$TMP/o.rombin" --quiet >/dev/null 2>"$TMP/err" \
        && "$ROMKIT" run "$TMP/o.rombin" --steps 5 --quiet >/dev/null 2>&1; then
    ok dmd_takes_t_by_d_observables
else
    fail dmd_takes_t_by_d_observables "$(cat "$TMP/err")"
fi

# An entry with both cubature and koopman (DESIGN.md's scene): one asset holding both models.
sed 's/"koopman": {"rank": 20, "clamp": true},/"cubature": {"tolerance": 0.05}, "koopman": {"rank": 20, "clamp": true},/' \
    "$TMP/beam.json" >"$TMP/both.json"
if "$ROMKIT" build "$TMP/both.json" -o "$TMP/both.rombin" --training "$TMP/S.npy" --report "$TMP/both_r.json" --quiet \
        >"$TMP/out" 2>"$TMP/err"; then
    json_checks build_both_report_keys "$TMP/both_r.json" cubature.elements koopman.rank=20
    "$ROMKIT" inspect "$TMP/both.rombin" >"$TMP/out" 2>&1 && grep -q "^reduced model: opens" "$TMP/out" && \
        grep -q "^Koopman operator: opens" "$TMP/out" && ok inspect_opens_both_models || fail inspect_opens_both_models "$(tail -3 "$TMP/out")"
    "$ROMKIT" run "$TMP/both.rombin" --steps 20 --report "$TMP/b1.json" --quiet >/dev/null 2>&1
    "$ROMKIT" run "$TMP/both.rombin" --steps 150 --koopman --reference "$TMP/S.npy" --report "$TMP/b2.json" --quiet >/dev/null 2>&1
    e=$(json_num "$TMP/b2.json" reference.relative_error)
    json_checks run_opens_the_reduced_model_by_default "$TMP/b1.json" 'kind="reduced"'
    below "$e" 0.01 && ok run_koopman_opens_the_operator_beside_it || fail run_koopman_opens_the_operator_beside_it "error '$e'"
else
    fail build_both_report_keys "$(cat "$TMP/err")"
fi

# Errors: named, and nothing written.
expect_fail dmd_needs_dt "are required" "$ROMKIT" dmd --snapshots "$TMP/S.npy" -o "$TMP/x.rombin"
expect_fail dmd_rank_above_the_data "numerical rank" "$ROMKIT" dmd --snapshots "$TMP/S.npy" --dt 0.01 --rank 400 -o "$TMP/x.rombin"
expect_fail dmd_bad_dt "--dt must be a number" "$ROMKIT" dmd --snapshots "$TMP/S.npy" --dt -1 -o "$TMP/x.rombin"
expect_fail dmd_accel_count "one per --snapshots" "$ROMKIT" dmd --snapshots "$TMP/S.npy" --snapshots "$TMP/S.npy" \
    --snapshots "$TMP/S.npy" --accel 0,0,1 --accel 0,1,0 --dt 0.01 -o "$TMP/x.rombin"
expect_fail dmd_missing_file "cannot open" "$ROMKIT" dmd --snapshots "$TMP/none.npy" --dt 0.01 -o "$TMP/x.rombin"
head -c 2000 "$TMP/S.npy" >"$TMP/cut.npy"
expect_fail dmd_truncated_file "npy" "$ROMKIT" dmd --snapshots "$TMP/cut.npy" --dt 0.01 -o "$TMP/x.rombin"
if [ -e "$TMP/x.rombin" ] || ls "$TMP" | grep -q 'x.rombin.tmp'; then fail dmd_no_partial_asset "a failed fit left a file"; else ok dmd_no_partial_asset; fi
