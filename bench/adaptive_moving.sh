#!/bin/sh
# Adaptive subspaces through a moving obstacle (issue 34): a bar dropped onto a platform (a box
# obstacle) 2 mm below it that rises at 0.5 m/s, so the platform meets the bar in the first step
# and lifts it; romkit compare on one thread, the adaptive method at its defaults against full
# order: relative error, normalized MSE, the speed ratio, the enriched share, Newton iterations,
# the full-space residual's steps over the tolerance and the crossings of the exact test. Two
# sizes: the test's (tests/integration/adaptive_moving.sh, 36 tets, modes r = 12), 384 and 3072
# tets (skinning, 16 handles), 6 steps each (a few minutes). Writes bench/results/adaptive_moving.md.
# Usage: [BUILD=build] sh bench/adaptive_moving.sh
set -e
BUILD=${BUILD:-build}
OUT=bench/results/adaptive_moving.md
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
mkdir -p bench/results
scene() { # file, cells, basis json
    cat >"$1" <<JSON
{
  "objects": [{
    "mesh": {"box": {"size": [0.3, 0.05, 0.05], "cells": $2}, "translate": [-0.15, -0.025, -0.025]},
    "material": {"model": "neohookean", "young": 1e5, "poisson": 0.4, "density": 1000}
  }],
  "gravity": [0, -9.81, 0],
  "obstacles": [{"box": {"min": [-0.1, -0.2, -0.1], "max": [0.1, -0.027, 0.1]}, "translate": {"velocity": [0, 0.5, 0]}}],
  "contact": {"dhat": 1e-3},
  "time": {"step": 0.01, "duration": 0.06, "integrator": "bdf2"},
  "rom": [{"method": "adaptive_subspace", $3}]
}
JSON
}
scene "$T/small.json" "[6, 1, 1]" '"basis": "modes", "size": 12'
scene "$T/bar.json" "[16, 2, 2]" '"basis": "skinning", "size": 16'
scene "$T/fine.json" "[32, 4, 4]" '"basis": "skinning", "size": 16'
{
    echo "# Adaptive subspaces through a moving obstacle (issue 34)"
    echo
    echo "\`sh bench/adaptive_moving.sh\`: a bar (0.3 x 0.05 x 0.05 m, E 1e5, free) dropped onto a box platform 2 mm"
    echo "below it that rises at 0.5 m/s; 6 steps of 0.01 s, BDF2, \`romkit compare\` with ROMKIT_THREADS=1, the"
    echo "adaptive method at its defaults against full order. The obstacles' progress along the step's way is"
    echo "an unknown of the adaptive solve (precompute/adaptive/obstacles.c, as in the reduced simulator);"
    echo "full order makes each obstacle vertex an unknown. Load $(cut -d' ' -f1 /proc/loadavg) at the start."
    echo
    echo "| tets | basis | relative error | nMSE | max error (m) | adaptive s/step | full order s/step | speed-up | enriched share | Newton its/step | steps over residual tol | residual max (m/s) | unconverged | crossings |"
    echo "|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
} >"$OUT"
for s in small bar fine; do
    if ROMKIT_THREADS=1 "$BUILD/romkit" compare "$T/$s.json" --report "$T/r.json" --quiet >"$T/out" 2>"$T/err"; then
        python3 - "$T/r.json" "$s" >>"$OUT" <<'PY'
import json, sys
r = json.load(open(sys.argv[1])); f, m = r["methods"][0], r["methods"][1]; a = m["adaptive"]; res = a["residual"]
tets = {"small": 36, "bar": 384, "fine": 3072}[sys.argv[2]]
basis = {"small": "modes 12", "bar": "skinning 16", "fine": "skinning 16"}[sys.argv[2]]
print("| %d | %s | %.3g | %.3g | %.3g | %.3g | %.3g | %.2f | %.3g | %.1f | %d of 6 | %.3g | %d | %d |" % (
    tets, basis, m["relative_error"], m["normalized_mse"], m["max_error"], m["seconds_per_step"],
    f["seconds_per_step"], m["speedup"], a["enriched_share"], a["newton_iterations_per_step"],
    res["steps_over_tolerance"], res["max"], m["unconverged_steps"], m["contact"]["intersections"]))
PY
    else
        echo "| $s | failed: $(tail -n 1 "$T/err" | cut -c1-160) |" >>"$OUT"
    fi
done
cat "$OUT"
