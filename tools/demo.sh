#!/bin/sh
# make demo: the main job on the built-in scene, examples/scenes/beam_bend.json (the FreeForm
# paper's beam "bend": 5 x 1 x 1 m, neo-Hookean, 15,360 tets, sagging under gravity for 1 s).
#   1. the full-order run: ground truth, and the training data of everything below;
#   2. three assets baked from it: RKPM skinning eigenmodes (m = 16) with cubature, a Koopman
#      operator fitted on this run, and one fitted on a run at half the gravity (a prediction);
#   3. each stepped by the float32 runtime, as an app would, against the full-order frames;
#   4. a table of error against time per step, a chart of it and a strip of rendered frames.
# Everything goes to $ROMKIT_DEMO_OUT (default build/demo). ROMKIT_DEMO_SCENE and ROMKIT_DEMO_STEPS
# (the scene's step count) run it on another scene whose rom list has the same three entries
# (tests/integration/demo.sh does, on a small one).
set -e
BUILD=${1:-build}
OUT=${ROMKIT_DEMO_OUT:-$BUILD/demo}
SCENE=${ROMKIT_DEMO_SCENE:-examples/scenes/beam_bend.json}
R=$BUILD/romkit
STEPS=${ROMKIT_DEMO_STEPS:-100}
mkdir -p "$OUT"
num() { tr -d ' \n\t' <"$1" | grep -o "\"$2\":[-0-9.eE+]*" | head -1 | cut -d: -f2; }

echo "== 1. full-order run of $SCENE =="
"$R" fom "$SCENE" --snapshots "$OUT/fom.npy" --frames "$OUT/frames_fom" --report "$OUT/fom.json" --quiet

echo "== 2. bake: RKPM skinning eigenmodes + cubature, and two Koopman operators =="
"$R" build "$SCENE" --entry 0 --training "$OUT/fom.npy" -o "$OUT/rkpm.rombin" --report "$OUT/rkpm_build.json" --quiet
"$R" build "$SCENE" --entry 1 --training "$OUT/fom.npy" -o "$OUT/koopman.rombin" --report "$OUT/koopman_build.json" --quiet
"$R" build "$SCENE" --entry 2 --training "$OUT/fom.npy" -o "$OUT/koopman_half_g.rombin" \
    --report "$OUT/koopman_half_g_build.json" --quiet

echo "== 3. step each asset with the runtime, against the full-order frames =="
"$R" run "$OUT/rkpm.rombin" --steps $STEPS --reference "$OUT/fom.npy" --frames "$OUT/frames_rkpm" \
    --report "$OUT/rkpm_run.json" --quiet
"$R" run "$OUT/rkpm.rombin" --steps $STEPS --newton 1 --reference "$OUT/fom.npy" --report "$OUT/rkpm_fixed_run.json" --quiet
"$R" run "$OUT/rkpm.rombin" --steps $STEPS --newton 1 --hessian-reuse 10 --reference "$OUT/fom.npy" \
    --report "$OUT/rkpm_kept_run.json" --quiet
"$R" run "$OUT/koopman.rombin" --steps $STEPS --reference "$OUT/fom.npy" --frames "$OUT/frames_koopman" \
    --jump 1000000 --report "$OUT/koopman_run.json" --quiet
"$R" run "$OUT/koopman_half_g.rombin" --steps $STEPS --reference "$OUT/fom.npy" --frames "$OUT/frames_koopman_half_g" \
    --report "$OUT/koopman_half_g_run.json" --quiet

echo "== 4. error against time per step =="
fom=$(num "$OUT/fom.json" seconds_per_step)
: >"$OUT/summary.dat"
printf '%-34s %11s %11s %9s %11s %11s %9s\n' method "s/step" "+ draw s" speed-up "rel. error" "norm. MSE" "asset KB"
printf '%-34s %11.4g %11s %9s %11s %11s %9s\n' "full order (CHOLMOD, double)" "$fom" - 1 0 0 -
# the rom entries' names, in order: the reduced model, the Koopman fitted on this run, the one fitted at g/2
names=$(grep -o '"name": *"[^"]*"' "$SCENE" | sed 's/.*: *"\(.*\)"/\1/')
i=0
for key in rkpm koopman koopman_half_g; do
    i=$((i + 1))
    label=$(echo "$names" | sed -n ${i}p)
    s=$(num "$OUT/${key}_run.json" seconds_per_step)
    d=$(num "$OUT/${key}_run.json" seconds_positions)
    e=$(num "$OUT/${key}_run.json" relative_error)
    m=$(num "$OUT/${key}_run.json" normalized_mse)
    b=$(num "$OUT/${key}_run.json" bytes)
    printf '%-34s %11.3g %11.3g %9.0f %11.3g %11.3g %9.0f\n' "$label" "$s" "$d" \
        "$(echo "$fom $s $d" | awk '{print $1 / ($2 + $3)}')" "$e" "$m" "$(echo "$b" | awk '{print $1 / 1024}')"
    printf '"%s" %s %s %s\n' "$label" "$s" "$e" "$m" >>"$OUT/summary.dat"
    # the same asset at a fixed cost: one Newton iteration per step, as Vega runs; then with Newton's
    # matrix kept for 10 steps (one modified Newton step a step)
    for run in fixed:"  the same, 1 Newton step per step" kept:"  the same, matrix kept 10 steps"; do
        [ $key = rkpm ] || break
        json="$OUT/rkpm_${run%%:*}_run.json"
        s=$(num "$json" seconds_per_step)
        d=$(num "$json" seconds_positions)
        e=$(num "$json" relative_error)
        m=$(num "$json" normalized_mse)
        printf '%-34s %11.3g %11.3g %9.0f %11.3g %11.3g %9s\n' "${run#*:}" "$s" "$d" \
            "$(echo "$fom $s $d" | awk '{print $1 / ($2 + $3)}')" "$e" "$m" "\""
    done
done
echo "(the last row's Koopman operator was fitted on a run at half the gravity: a prediction; the one above it"
echo " was fitted on this very run, so its error is reconstruction. The reduced rows: the float32 runtime."
echo " s/step: median of $STEPS steps; + draw: the positions of every shown vertex;"
echo " speed-up: full order over step + draw; relative error: sqrt(sum |x - x_fom|^2 / sum |x_fom - X|^2) over the"
echo " shown vertices and all frames; normalized MSE: mean |x - x_fom|^2 over the bounding-box diagonal squared)"
jump=$(num "$OUT/koopman_run.json" seconds_jump)
echo "Koopman: one jump of 10^6 steps in $(echo "$jump" | awk '{printf "%.3g", $1 * 1e6}') us"

echo "== 5. pictures =="
if command -v gnuplot >/dev/null 2>&1; then
    gnuplot -e "data='$OUT/summary.dat'; fom=$fom; out='$OUT/error_time.png'" tools/plot/error_time.gp
    # one box for every panel: the full-order run's extent over its first and last frames (x, z, y)
    box=$(cat "$OUT/frames_fom/frame_00000.obj" "$OUT/frames_fom/frame_$(printf %05d $STEPS).obj" | awk '
        $1 == "v" { for (i = 1; i <= 3; i++) { v = $(i + 1); if (!n || v < lo[i]) lo[i] = v; if (!n || v > hi[i]) hi[i] = v } n = 1 }
        END { printf "%g %g %g %g %g %g", lo[1] - 0.1, hi[1] + 0.1, lo[3] - 0.1, hi[3] + 0.1, lo[2] - 0.1, hi[2] + 0.1 }')
    gnuplot -e "rows='$OUT/frames_fom $OUT/frames_rkpm $OUT/frames_koopman_half_g'; titles='full-order $(echo "$names" | sed -n 1p) $(echo "$names" | sed -n 3p)'; frames='$((STEPS / 4)) $((STEPS / 2)) $((3 * STEPS / 4)) $STEPS'; box='$box'; out='$OUT/strip.png'" \
        tools/plot/strip.gp
    echo "wrote $OUT/error_time.png and $OUT/strip.png"
else
    echo "gnuplot is not installed (tools/install-deps.sh installs it): no pictures"
fi
echo "everything is in $OUT"
