#!/bin/sh
# The runtime's step cost with the scene's obstacles (issue 30), by romkit run's median us/step:
#   planes   a slab of 8 x 2 x 8 cells dropped onto a plane (friction 0.3): a planes-only asset
#            never enters the obstacle code, so this is the number to hold against an older build
#            (BUILD=that build's directory gives its romkit and romkit-double)
#   spikes   the same slab at 0.2 m dropped at 2 m/s onto tests/data/contact/spikes.obj
#   terrain  onto a 40 x 40 heightfield of 3200 triangles with 6 cm spikes (as test_runtime_obstacles)
# modes r = 12 with cubature, float32 (romkit) and float64 (romkit-double). Prints one line a run.
# Usage: sh bench/obstacle_step_cost.sh [STEPS]   (from the repository root; BUILD=build by default)
set -e
BUILD=${BUILD:-build}
STEPS=${1:-50}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
python3 bench/terrain_obj.py "$T/terrain.obj"
scene() { # name, size, translate, obstacles
    cat >"$T/$1.json" <<JSON
{"objects": [{"mesh": {"box": {"size": $2, "cells": [8, 2, 8]}, "translate": $3},
  "material": {"model": "neohookean", "young": 1e5, "poisson": 0.4, "density": 1000}, "velocity": [0, -2, 0]}],
 "gravity": [0, -9.81, 0], "obstacles": [$4],
 "contact": {"dhat": 0.002, "friction": 0.3}, "time": {"step": 0.01, "duration": 0.5},
 "rom": {"basis": "modes", "size": 12, "cubature": {"tolerance": 0.02}}}
JSON
}
scene planes "[0.4, 0.1, 0.4]" "[-0.2, 0.05, -0.2]" '{"plane": {"point": [0, 0, 0], "normal": [0, 1, 0]}}'
scene spikes "[0.2, 0.05, 0.2]" "[-0.087, 0.085, -0.079]" "{\"mesh\": {\"file\": \"$PWD/tests/data/contact/spikes.obj\"}}"
scene terrain "[0.2, 0.05, 0.2]" "[-0.087, 0.085, -0.079]" "{\"mesh\": {\"file\": \"$T/terrain.obj\"}}"
for s in planes spikes terrain; do
    build/romkit build "$T/$s.json" -o "$T/$s.rombin" --quiet >/dev/null
    build/romkit build "$T/$s.json" -o "$T/${s}64.rombin" --quiet --precision float64 >/dev/null
    # an older build refuses the obstacle chunks (unknown critical chunk): its line says so
    echo "$s float32: $("$BUILD/romkit" run "$T/$s.rombin" --steps "$STEPS" 2>&1 | tail -1 | sed 's/^[^:]*: //')"
    echo "$s float64: $("$BUILD/romkit-double" run "$T/${s}64.rombin" --steps "$STEPS" 2>&1 | tail -1 | sed 's/^[^:]*: //')"
done
