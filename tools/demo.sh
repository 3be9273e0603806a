#!/bin/sh
# make demo: the main job on the built-in scene (the freeform paper's beam "bend").
# It runs the full-order ground truth, then bakes a small reduced asset and steps it with the
# runtime. Error against time on one table joins with the Koopman and demo issues.
set -e
BUILD=${1:-build}
OUT=${ROMKIT_DEMO_OUT:-$BUILD/demo}
mkdir -p "$OUT"
echo "== full-order simulation: examples/scenes/beam_bend.json =="
"$BUILD/romkit" fom examples/scenes/beam_bend.json --snapshots "$OUT/bend_fom.npy" \
    --frames "$OUT/frames" --report "$OUT/bend_fom.json"
echo "wrote $OUT/bend_fom.npy (all frames), $OUT/frames/ (surface per frame), $OUT/bend_fom.json (report)"
echo "== bake a reduced asset and step it with the runtime: examples/scenes/cantilever_small.json =="
"$BUILD/romkit" build examples/scenes/cantilever_small.json -o "$OUT/cantilever.rombin" --report "$OUT/cantilever_build.json" --quiet
"$BUILD/romkit" run "$OUT/cantilever.rombin" --steps 100 --report "$OUT/cantilever_run.json" --quiet
