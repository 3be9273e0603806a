#!/bin/sh
# make bench, the runtime's default Newton mode (issue 31): build/bench_newton_modes on the speed
# bench's models (bench_speed.sh: bunny_19k with r = 8, 20, 64 linear modes; the demo's RKPM beam,
# r = 204) and on the obstacle bench's slab dropped onto a plane and onto a spiked mesh
# (obstacle_step_cost.sh), each as a float32 asset stepped by the float runtime and a float64 one
# by the double runtime. Per asset: the converged mode with a fresh Newton matrix every iteration,
# with one kept for up to 2, 3, 5 and 10 steps, and the default romrt_open leaves; CPU us/step
# (median and range over ROUNDS interleaved rounds), Newton iterations per step, and each
# trajectory's distance from the fresh one (bench_newton_modes.c says how). The default is chosen
# from this table (runtime/step.c, reuse_steps). Output: bench/results/newton_modes.csv.
set -eu
DATA=${1:-tests/data/meshes}
OUT=${2:-bench/results}
BUILD=${BUILD:-build}
R=$BUILD/romkit
ROUNDS=${ROUNDS:-5}
[ -n "${ROMKIT_BENCH_QUICK:-}" ] && ROUNDS=3
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
mkdir -p "$OUT"
DATA_ABS=$(cd "$DATA" && pwd)

cat >"$T/bunny.json" <<JSON
{
  "objects": [{
    "mesh": {"file": "$DATA_ABS/bunny_19k.msh"},
    "material": {"model": "neohookean", "young": 5e6, "poisson": 0.45, "density": 1000},
    "fixed": [{"box": [[-5, -1, -5], [5, -0.03, 5]]}]
  }],
  "gravity": [0, -9.81, 0],
  "time": {"step": 0.01, "duration": 1.0, "integrator": "backward_euler"},
  "rom": [
    {"name": "modes-8", "basis": "modes", "size": 8, "cubature": {"tolerance": 0.01}},
    {"name": "modes-20", "basis": "modes", "size": 20, "cubature": {"tolerance": 0.01}},
    {"name": "modes-64", "basis": "modes", "size": 64, "cubature": {"tolerance": 0.01}}
  ]
}
JSON
slab() { # name, size, translate, obstacles: obstacle_step_cost.sh's slab
    cat >"$T/$1.json" <<JSON
{"objects": [{"mesh": {"box": {"size": $2, "cells": [8, 2, 8]}, "translate": $3},
  "material": {"model": "neohookean", "young": 1e5, "poisson": 0.4, "density": 1000}, "velocity": [0, -2, 0]}],
 "gravity": [0, -9.81, 0], "obstacles": [$4],
 "contact": {"dhat": 0.002, "friction": 0.3}, "time": {"step": 0.01, "duration": 0.5},
 "rom": {"basis": "modes", "size": 12, "cubature": {"tolerance": 0.02}}}
JSON
}
slab slab-plane "[0.4, 0.1, 0.4]" "[-0.2, 0.05, -0.2]" '{"plane": {"point": [0, 0, 0], "normal": [0, 1, 0]}}'
slab slab-spikes "[0.2, 0.05, 0.2]" "[-0.087, 0.085, -0.079]" "{\"mesh\": {\"file\": \"$PWD/tests/data/contact/spikes.obj\"}}"

# both NAME SCENE [BUILD ARGS]: NAME-float32.rombin and NAME-float64.rombin
both() {
    name=$1 scene=$2
    shift 2
    "$R" build "$scene" "$@" -o "$T/$name-float32.rombin" --quiet >/dev/null
    "$R" build "$scene" "$@" -o "$T/$name-float64.rombin" --precision float64 --quiet >/dev/null
}
"$R" fom "$T/bunny.json" --snapshots "$T/bunny.npy" --quiet >/dev/null
k=0
for name in modes-8 modes-20 modes-64; do
    both "bunny-$name" "$T/bunny.json" --entry "$k" --training "$T/bunny.npy"
    k=$((k + 1))
done
"$R" fom examples/scenes/beam_bend.json --snapshots "$T/beam.npy" --quiet >/dev/null
both beam-rkpm-16 examples/scenes/beam_bend.json --entry 0 --training "$T/beam.npy"
both slab-plane "$T/slab-plane.json"
both slab-spikes "$T/slab-spikes.json"

{
    "$BUILD/bench_newton_modes" 100 "$ROUNDS" "$T"/bunny-*-float32.rombin "$T/beam-rkpm-16-float32.rombin"
    "$BUILD/bench_newton_modes_double" 100 "$ROUNDS" "$T"/bunny-*-float64.rombin "$T/beam-rkpm-16-float64.rombin" | tail -n +2
    "$BUILD/bench_newton_modes" 50 "$ROUNDS" "$T"/slab-*-float32.rombin | tail -n +2
    "$BUILD/bench_newton_modes_double" 50 "$ROUNDS" "$T"/slab-*-float64.rombin | tail -n +2
} | sed 's/\.rombin,/,/' >"$T/newton_modes.csv"
mv "$T/newton_modes.csv" "$OUT/newton_modes.csv"
echo "bench/results: newton_modes.csv"
