#!/bin/sh
# make demo: the main job on the built-in scene (the freeform paper's beam "bend").
# Today romkit has its foundation: this runs the full-order ground truth and reports its speed.
# The reduced pipeline (bake an asset, step it with the runtime, error against time) joins as it lands.
set -e
BUILD=${1:-build}
OUT=${ROMKIT_DEMO_OUT:-$BUILD/demo}
mkdir -p "$OUT"
echo "== full-order simulation: examples/scenes/beam_bend.json =="
"$BUILD/romkit" fom examples/scenes/beam_bend.json --snapshots "$OUT/bend_fom.npy" \
    --frames "$OUT/frames" --report "$OUT/bend_fom.json"
echo "wrote $OUT/bend_fom.npy (all frames), $OUT/frames/ (surface per frame), $OUT/bend_fom.json (report)"
