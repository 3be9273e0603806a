# Koopman assets from the command line: romkit build with rom.koopman, romkit dmd on outside
# snapshots (romkit fom's), romkit run stepping, jumping, rescaling and checking against the
# full-order frames; the report keys of DESIGN.md; and the errors a user meets.
. tests/lib.sh
flat() { tr -d ' \n\t' <"$1"; }
num() { flat "$1" | grep -o "\"$2\":[-0-9.eE+]*" | head -1 | cut -d: -f2; }
below() { awk -v a="$1" -v b="$2" 'BEGIN { exit !(a != "" && a + 0 < b + 0) }'; }

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
    r=$(flat "$TMP/k.json")
    case $r in *'"koopman":{"rank":20,"max_abs_eigenvalue":'*'"eigenvalues":[['*) ok build_koopman_report_keys ;;
        *) fail build_koopman_report_keys "$(head -c 300 "$TMP/k.json")" ;; esac
    top=$(num "$TMP/k.json" max_abs_eigenvalue)
    awk -v t="$top" 'BEGIN { exit !(t <= 1) }' && ok build_koopman_clamped || fail build_koopman_clamped "max |lambda| $top"
else
    fail build_koopman_report_keys "$(cat "$TMP/err")"
fi
"$ROMKIT" inspect "$TMP/k.rombin" >"$TMP/out" 2>&1 && grep -q "KHED  critical" "$TMP/out" && grep -q "opens with the runtime" "$TMP/out" \
    && ok inspect_koopman_asset || fail inspect_koopman_asset "$(head -c 400 "$TMP/out")"

# The runtime reproduces the full-order run it learned from.
if "$ROMKIT" run "$TMP/k.rombin" --steps 150 --reference "$TMP/S.npy" --jump 1000000 --report "$TMP/r.json" --quiet >"$TMP/out" 2>"$TMP/err"; then
    e=$(num "$TMP/r.json" relative_error)
    below "$e" 0.02 && ok koopman_run_matches_the_full_order_run || fail koopman_run_matches_the_full_order_run "relative error $e"
    case $(flat "$TMP/r.json") in *'"seconds_jump":'*'"kind":"koopman"'*) ok run_reports_seconds_jump ;;
        *) fail run_reports_seconds_jump "$(head -c 300 "$TMP/r.json")" ;; esac
    echo "# romkit run on the build's asset: $(sed -n 2,3p "$TMP/out" | tr '\n' ' ')"
else
    fail koopman_run_matches_the_full_order_run "$(cat "$TMP/err")"
fi
# A ten times larger step (Eq. 21) still follows the full-order motion at the common times.
"$ROMKIT" run "$TMP/k.rombin" --steps 15 --dt 0.1 --snapshots "$TMP/big.npy" --quiet >/dev/null 2>"$TMP/err" \
    && ok run_rescales_the_time_step || fail run_rescales_the_time_step "$(cat "$TMP/err")"
"$ROMKIT" run "$TMP/k.rombin" --steps 10 --damping 0.02 --quiet >/dev/null 2>"$TMP/err" \
    && ok run_damping_edit || fail run_damping_edit "$(cat "$TMP/err")"
expect_fail run_rejects_bad_damping "mu must be in" "$ROMKIT" run "$TMP/k.rombin" --steps 1 --damping 1.5

# romkit dmd on the same frames brought from outside.
if "$ROMKIT" dmd --snapshots "$TMP/S.npy" --dt 0.01 --gravity 0,-9.81,0 --rank 20 --clamp -o "$TMP/d.rombin" \
        --report "$TMP/d.json" --quiet >"$TMP/out" 2>"$TMP/err"; then
    case $(flat "$TMP/d.json") in *'"koopman":{"rank":20,"max_abs_eigenvalue":'*'"eigenvalues":[['*'"residuals":['*) ok dmd_report_keys ;;
        *) fail dmd_report_keys "$(head -c 300 "$TMP/d.json")" ;; esac
    "$ROMKIT" run "$TMP/d.rombin" --steps 150 --reference "$TMP/S.npy" --report "$TMP/dr.json" --quiet >/dev/null 2>&1
    e=$(num "$TMP/dr.json" relative_error)
    below "$e" 0.02 && ok dmd_asset_matches_the_recording || fail dmd_asset_matches_the_recording "relative error $e"
    "$ROMKIT" dmd --snapshots "$TMP/S.npy" --dt 0.01 --gravity 0,-9.81,0 --rank 20 --clamp -o "$TMP/d2.rombin" --quiet >/dev/null 2>&1
    cmp -s "$TMP/d.rombin" "$TMP/d2.rombin" && ok dmd_is_deterministic || fail dmd_is_deterministic "two fits differ"
    # A recording that starts at rest gives one more training pair: the step out of rest.
    "$ROMKIT" dmd --snapshots "$TMP/S.npy" --dt 0.01 --gravity 0,-9.81,0 --rank 20 --clamp --from-rest -o "$TMP/f.rombin" --quiet >/dev/null 2>&1
    "$ROMKIT" run "$TMP/f.rombin" --steps 150 --reference "$TMP/S.npy" --report "$TMP/fr.json" --quiet >/dev/null 2>&1
    f=$(num "$TMP/fr.json" relative_error)
    below "$f" "$e" && ok dmd_from_rest_fits_better || fail dmd_from_rest_fits_better "relative error $f, without $e"
    echo "# romkit dmd on romkit fom's frames, rank 20: relative error $e, with --from-rest $f"
else
    fail dmd_report_keys "$(cat "$TMP/err")"
fi
"$ROMKIT" dmd --snapshots "$TMP/S.npy" --dt 0.01 --gravity 0,-9.81,0 --pod 12 --energy 0.9999999 -o "$TMP/p.rombin" --quiet \
    >/dev/null 2>"$TMP/err" && "$ROMKIT" run "$TMP/p.rombin" --steps 20 --quiet >/dev/null 2>&1 \
    && ok dmd_with_pod_projection || fail dmd_with_pod_projection "$(cat "$TMP/err")"
# T x d observables (d = 1661, not a multiple of 3: padded to whole points): the same bytes re-labelled.
sed '1s/(151, 99, 3), }/(27, 1661), }  /' "$TMP/S.npy" >"$TMP/obs.npy"
"$ROMKIT" dmd --snapshots "$TMP/obs.npy" --dt 0.01 --rank 10 -o "$TMP/o.rombin" --quiet >/dev/null 2>"$TMP/err" \
    && "$ROMKIT" run "$TMP/o.rombin" --steps 5 --quiet >/dev/null 2>&1 && ok dmd_takes_t_by_d_observables \
    || fail dmd_takes_t_by_d_observables "$(cat "$TMP/err")"

# An entry with both cubature and koopman (DESIGN.md's scene): one asset holding both models.
sed 's/"koopman": {"rank": 20, "clamp": true},/"cubature": {"tolerance": 0.05}, "koopman": {"rank": 20, "clamp": true},/' \
    "$TMP/beam.json" >"$TMP/both.json"
if "$ROMKIT" build "$TMP/both.json" -o "$TMP/both.rombin" --training "$TMP/S.npy" --report "$TMP/both_r.json" --quiet \
        >"$TMP/out" 2>"$TMP/err"; then
    case $(flat "$TMP/both_r.json") in *'"cubature":{"elements":'*'"koopman":{"rank":20'*) ok build_both_report_keys ;;
        *) fail build_both_report_keys "$(head -c 300 "$TMP/both_r.json")" ;; esac
    "$ROMKIT" inspect "$TMP/both.rombin" >"$TMP/out" 2>&1 && grep -q "^reduced model: opens" "$TMP/out" && \
        grep -q "^Koopman operator: opens" "$TMP/out" && ok inspect_opens_both_models || fail inspect_opens_both_models "$(tail -3 "$TMP/out")"
    "$ROMKIT" run "$TMP/both.rombin" --steps 20 --report "$TMP/b1.json" --quiet >/dev/null 2>&1
    "$ROMKIT" run "$TMP/both.rombin" --steps 150 --koopman --reference "$TMP/S.npy" --report "$TMP/b2.json" --quiet >/dev/null 2>&1
    e=$(num "$TMP/b2.json" relative_error)
    case $(flat "$TMP/b1.json") in *'"kind":"reduced"'*) ok run_opens_the_reduced_model_by_default ;;
        *) fail run_opens_the_reduced_model_by_default "$(head -c 200 "$TMP/b1.json")" ;; esac
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
