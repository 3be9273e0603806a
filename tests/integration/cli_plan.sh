# romkit plan: the bake as a job graph run by make -j2 gives romkit build's asset byte for byte
# (the scene's own run, a training list of two scenes, a Koopman entry's trajectories); a rerun after deleting one intermediate
# redoes that step and its dependents only; entries not split yet are one build step; bad input
# writes nothing.
. tests/lib.sh
export ROMKIT_THREADS=2
command -v make >/dev/null 2>&1 || { echo "skip cli_plan: make is not installed"; exit 0; }

# scene FILE GRAVITY_Y ROM_JSON: a small cantilever (108 vertices), 0.2 s
scene() { cantilever "$1" 8 "$2" "$3"; } # tests/lib.sh's cantilever, 108 vertices
scene "$TMP/a.json" -9.81 '{"basis": "modes", "size": 6}'
scene "$TMP/b.json" -30 '{"basis": "modes", "size": 6}'
scene "$TMP/pod.json" -15 '[{"basis": "pod", "size": 5, "cubature": {"tolerance": 0.05}, "training": ["a.json", "b.json"]},
      {"basis": "skinning", "size": 2, "cubature": {"tolerance": 0.05}},
      {"basis": "modes", "size": 6, "cubature": {"tolerance": 0.05}, "asset": {"precision": "float64"}}]'
CANT=$PWD/examples/scenes/cantilever_small.json

# same NAME SCENE ENTRY DIR: the plan's asset equals romkit build's, byte for byte
same() {
    "$ROMKIT" build "$2" --entry "$3" -o "$TMP/$1.ref.rombin" --quiet >/dev/null 2>"$TMP/err" || {
        fail "$1" "romkit build failed: $(head -c 300 "$TMP/err")"; return; }
    if cmp "$TMP/$1.ref.rombin" "$4/asset.rombin" >/dev/null 2>&1; then ok "$1"
    else fail "$1" "$4/asset.rombin differs from romkit build's ($(wc -c <"$4/asset.rombin" 2>/dev/null) vs $(wc -c <"$TMP/$1.ref.rombin") bytes)"; fi
}

# the scene's own run: train, basis, cubature, bake
"$ROMKIT" plan "$CANT" -o "$TMP/own" >"$TMP/out" 2>"$TMP/err" && make -C "$TMP/own" -j2 >"$TMP/own.log" 2>&1 \
    && same plan_own_run_identical "$CANT" 0 "$TMP/own" || fail plan_own_run_identical "$(cat "$TMP/err" "$TMP/own.log" | tail -5)"
json_checks plan_json_lists_steps "$TMP/own/plan.json" split=true 'steps[0].id="train-0"' 'steps[1].id="basis"' \
    'steps[2].id="cubature"' 'steps[2].after[0]="basis"' 'steps[2].after[1]="train-0"' 'steps[3].id="bake"' \
    'steps[3].outputs[0]="asset.rombin"' threads=2

# a training list of two scenes: two training runs, a pod basis and a cubature trained on both
if "$ROMKIT" plan "$TMP/pod.json" -o "$TMP/pod" >"$TMP/out" 2>"$TMP/err" && make -C "$TMP/pod" -j2 >"$TMP/pod.log" 2>&1; then
    same plan_training_list_identical "$TMP/pod.json" 0 "$TMP/pod"
    json_checks plan_two_training_runs "$TMP/pod/plan.json" 'steps[0].id="train-0"' 'steps[1].id="train-1"' \
        'steps[2].id="basis"' 'steps[2].after[1]="train-1"' 'steps[4].id="bake"'
else fail plan_training_list_identical "$(cat "$TMP/err" "$TMP/pod.log" | tail -5)"; fi

# resumption: the cubature deleted, make redoes it and the bake, nothing else
rm -f "$TMP/pod/cubature.json"
make -C "$TMP/pod" -j2 >"$TMP/resume.log" 2>&1
ran=$(grep -c '/romkit ' "$TMP/resume.log")
if grep -q 'romkit cubature ' "$TMP/resume.log" && grep -q 'romkit build ' "$TMP/resume.log" && [ "$ran" -eq 2 ]; then
    same plan_resume_redoes_only_dependents "$TMP/pod.json" 0 "$TMP/pod"
else fail plan_resume_redoes_only_dependents "$ran commands ran: $(grep '/romkit ' "$TMP/resume.log" | cut -c1-200)"; fi
make -C "$TMP/pod" -q && ok plan_complete_is_up_to_date || fail plan_complete_is_up_to_date "make -q says something is stale"

# a retry: a damaged training run makes the basis step fail (make fails, the basis not rewritten); with
# the damaged file removed, rerunning make redoes that run and everything after it
printf 'not an npy' >"$TMP/pod/train-1.npy"
if make -C "$TMP/pod" -j2 >"$TMP/fail.log" 2>&1; then fail plan_failed_step_fails_make "make succeeded on a damaged run"
elif grep -q "train-1.npy" "$TMP/fail.log" && [ "$TMP/pod/basis.npy" -ot "$TMP/pod/train-1.npy" ]; then ok plan_failed_step_fails_make
else fail plan_failed_step_fails_make "$(tail -3 "$TMP/fail.log")"; fi
rm -f "$TMP/pod/train-1.npy"
make -C "$TMP/pod" -j2 >"$TMP/retry.log" 2>&1
ran=$(grep -c '/romkit ' "$TMP/retry.log")
[ "$ran" -eq 4 ] && ! grep -q 'a.json --snapshots' "$TMP/retry.log" && same plan_retry_after_failure "$TMP/pod.json" 0 "$TMP/pod" \
    || fail plan_retry_after_failure "$ran commands: $(grep '/romkit ' "$TMP/retry.log" | cut -c1-120)"

# the same plan made again leaves everything up to date; another entry's plan in the same folder
# makes every step out of date (each reads plan.json), not the last plan's files look done
"$ROMKIT" plan "$TMP/pod.json" -o "$TMP/pod" >/dev/null 2>&1 && make -C "$TMP/pod" -q \
    && ok plan_again_unchanged_is_up_to_date || fail plan_again_unchanged_is_up_to_date "make -q says something is stale"
cp -r "$TMP/pod" "$TMP/pod2"
"$ROMKIT" plan "$TMP/pod.json" --entry 2 -o "$TMP/pod2" >/dev/null 2>&1 && make -C "$TMP/pod2" -j2 >"$TMP/pod2.log" 2>&1 \
    && same plan_another_entry_redoes_all "$TMP/pod.json" 2 "$TMP/pod2" \
    || fail plan_another_entry_redoes_all "$(tail -3 "$TMP/pod2.log")"

# an entry not split yet (skinning): its training run, then one romkit build step
if "$ROMKIT" plan "$TMP/pod.json" --entry 1 -o "$TMP/skin" >"$TMP/out" 2>"$TMP/err" && make -C "$TMP/skin" -j2 >"$TMP/skin.log" 2>&1; then
    same plan_whole_entry_identical "$TMP/pod.json" 1 "$TMP/skin"
    json_checks plan_whole_entry_one_step "$TMP/skin/plan.json" split=false one_step_because 'steps[1].id="bake"' \
        'steps[1].command[1]="build"' 'steps[1].command[5]="--training"' 'steps[1].after[0]="train-0"'
else fail plan_whole_entry_identical "$(cat "$TMP/err" "$TMP/skin.log" | tail -5)"; fi

# a Koopman entry: its trajectories (one as written, two varied) and the scene's own run (its pod
# basis trains on it) are steps; the fit and the bake one romkit build step
cat >"$TMP/k.json" <<'JSON'
{
  "objects": [{
    "mesh": {"box": {"size": [1, 0.2, 0.2], "cells": [8, 2, 2]}},
    "material": {"model": "neohookean", "young": 2e6, "poisson": 0.4, "density": 1000},
    "fixed": [{"box": [[-1, -1, -1], [0.01, 1, 1]]}]
  }],
  "gravity": [0, -9.81, 0],
  "time": {"step": 0.01, "duration": 0.2},
  "rom": {"basis": "pod", "size": 6, "koopman": {"rank": 8, "clamp": true, "project": true,
          "trajectories": [{}, {"gravity": [0, -20, 0], "velocity": [0, 0, 0.5]}, {"load_scale": 2}]}}
}
JSON
if "$ROMKIT" plan "$TMP/k.json" -o "$TMP/kp" >"$TMP/out" 2>"$TMP/err" && make -C "$TMP/kp" -j2 >"$TMP/kp.log" 2>&1; then
    same plan_koopman_identical "$TMP/k.json" 0 "$TMP/kp"
    json_checks plan_koopman_trajectories_are_steps "$TMP/kp/plan.json" split=false 'steps[0].id="train-0"' \
        'steps[2].id="trajectory-1"' 'steps[2].command[5]="--trajectory"' 'steps[4].id="bake"' 'steps[4].after[3]="trajectory-2"'
    # the bake reads the trajectory files: another run's frames in trajectory-1.npy change the asset
    cp "$TMP/kp/trajectory-2.npy" "$TMP/kp/trajectory-1.npy"
    make -C "$TMP/kp" >/dev/null 2>&1
    cmp -s "$TMP/plan_koopman_identical.ref.rombin" "$TMP/kp/asset.rombin" \
        && fail plan_koopman_reads_trajectory_files "the asset did not change" || ok plan_koopman_reads_trajectory_files
else fail plan_koopman_identical "$(cat "$TMP/err" "$TMP/kp.log" | tail -5)"; fi
expect_fail fom_trajectory_out_of_range "one of rom's 3 trajectories, 0..2, got '3'" \
    "$ROMKIT" fom "$TMP/k.json" --entry 0 --trajectory 3 --snapshots "$TMP/t.npy"
expect_fail fom_trajectory_needs_koopman "has no koopman section" "$ROMKIT" fom "$TMP/a.json" --trajectory 0

# an adaptive_linear entry: its training list's two runs are steps, the decoder and the bake one
scene "$TMP/al.json" -15 '{"method": "adaptive_linear", "size": 4, "decoder": "quadratic_pod",
      "cubature": {"tolerance": 0.05}, "training": ["a.json", "b.json"]}'
if "$ROMKIT" plan "$TMP/al.json" -o "$TMP/al" >"$TMP/out" 2>"$TMP/err" && make -C "$TMP/al" -j2 >"$TMP/al.log" 2>&1; then
    same plan_alrom_identical "$TMP/al.json" 0 "$TMP/al"
    json_checks plan_alrom_training_runs_are_steps "$TMP/al/plan.json" split=false 'steps[1].id="train-1"' \
        'steps[2].id="bake"' 'steps[2].command[5]="--training-run"' 'steps[2].after[1]="train-1"'
else fail plan_alrom_identical "$(cat "$TMP/err" "$TMP/al.log" | tail -5)"; fi

# --run: the same steps in order, without make; a float64 asset (an ulp off in a cubature weight
# would show in its bytes)
"$ROMKIT" plan "$TMP/pod.json" --entry 2 -o "$TMP/run" --run >"$TMP/run.log" 2>&1 \
    && same plan_run_identical "$TMP/pod.json" 2 "$TMP/run" || fail plan_run_identical "$(tail -5 "$TMP/run.log")"

# --slurm: the scripts, the training runs as one array
"$ROMKIT" plan "$TMP/pod.json" -o "$TMP/sl" --slurm >/dev/null 2>"$TMP/err" \
    && grep -q '^#SBATCH --array=0-1$' "$TMP/sl/slurm/train.sbatch" \
    && grep -q 'dependency=afterok:$train:$basis slurm/cubature.sbatch' "$TMP/sl/submit.sh" \
    && grep -q 'dependency=afterok:$basis:$cubature slurm/bake.sbatch' "$TMP/sl/submit.sh" \
    && sh -n "$TMP/sl/submit.sh" && sh -n "$TMP/sl/slurm/train.sbatch" && ok plan_slurm_scripts \
    || fail plan_slurm_scripts "$(cat "$TMP/err"; ls "$TMP/sl" "$TMP/sl/slurm" 2>&1 | tr '\n' ' ')"

# a scene named by a relative path: every file the steps read is absolute (they run in DIR), its
# mesh file among the inputs, so make redoes the steps when the mesh changes
(cd examples && "$ROMKIT" plan scenes/knight_sag.json -o "$TMP/kn" >/dev/null 2>"$TMP/err")
mesh=$("$JSONQ" get "$TMP/kn/plan.json" 'steps[1].inputs[2]' 2>/dev/null)
case $mesh in /*decimated-knight.off) ok plan_mesh_file_is_an_absolute_input ;;
    *) fail plan_mesh_file_is_an_absolute_input "steps[1].inputs[2] is '$mesh' $(cat "$TMP/err")" ;; esac

# bad input: a clear error, nothing written
expect_fail plan_entry_out_of_range "entry must be a rom entry of .*0..2, got '3'" "$ROMKIT" plan "$TMP/pod.json" --entry 3 -o "$TMP/bad1"
[ ! -e "$TMP/bad1" ] && ok plan_entry_out_of_range_writes_nothing || fail plan_entry_out_of_range_writes_nothing "$TMP/bad1 made"
: >"$TMP/afile"
expect_fail plan_unwritable_dir "afile/sub: cannot create the plan's folder" "$ROMKIT" plan "$TMP/pod.json" -o "$TMP/afile/sub"
printf '{"objects": [' >"$TMP/broken.json"
expect_fail plan_scene_parse_error "broken.json:1:" "$ROMKIT" plan "$TMP/broken.json" -o "$TMP/bad2"
[ ! -e "$TMP/bad2" ] && ok plan_parse_error_writes_nothing || fail plan_parse_error_writes_nothing "$TMP/bad2 made"
mkdir "$TMP/ro" && chmod 0555 "$TMP/ro"
if [ "$(id -u)" != 0 ]; then
    expect_fail plan_readonly_dir "ro/plan.json" "$ROMKIT" plan "$TMP/pod.json" -o "$TMP/ro"
    [ -z "$(ls -A "$TMP/ro")" ] && ok plan_readonly_dir_writes_nothing || fail plan_readonly_dir_writes_nothing "$(ls "$TMP/ro")"
fi

# the split steps' own errors: a basis for another entry kind, a cubature without rom.cubature
expect_fail build_basis_refused_for_skinning "only modes, modal_derivatives and pod" \
    "$ROMKIT" build "$TMP/pod.json" --entry 1 --basis "$TMP/pod/basis.npy" -o "$TMP/x.rombin"
expect_fail build_training_run_count "given 1 times; rom\[0\] lists 2" \
    "$ROMKIT" build "$TMP/pod.json" --training-run "$TMP/pod/train-0.npy" -o "$TMP/x.rombin"
expect_fail cubature_needs_rom_cubature "has no rom.cubature" "$ROMKIT" cubature "$TMP/a.json" -o "$TMP/c.json"
[ ! -e "$TMP/x.rombin" ] && [ ! -e "$TMP/c.json" ] && ok plan_steps_errors_write_nothing || fail plan_steps_errors_write_nothing "an output was written"
