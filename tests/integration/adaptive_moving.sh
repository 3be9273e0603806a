# Adaptive subspaces through a moving obstacle (issue 34; refused before): a small bar (36 tets)
# falls onto a platform (a box obstacle) that starts 2 mm below it and rises at 0.5 m/s, so the
# platform meets the bar in the first step and lifts it for the other four. The obstacles'
# progress along their way is an unknown of the adaptive solve (precompute/adaptive/obstacles.c),
# as in the reduced simulator; full order moves each obstacle vertex as an unknown instead. Against
# full order (measured: relative error 5.6e-3, normalized MSE 7.5e-8, every step's full-space
# residual under the Newton tolerance), no crossing by the exact test. About 2 s.
. tests/lib.sh

cat >"$TMP/lift.json" <<JSON
{
  "objects": [{
    "mesh": {"box": {"size": [0.3, 0.05, 0.05], "cells": [6, 1, 1]}, "translate": [-0.15, -0.025, -0.025]},
    "material": {"model": "neohookean", "young": 1e5, "poisson": 0.4, "density": 1000}
  }],
  "gravity": [0, -9.81, 0],
  "obstacles": [{"box": {"min": [-0.1, -0.2, -0.1], "max": [0.1, -0.027, 0.1]}, "translate": {"velocity": [0, 0.5, 0]}}],
  "contact": {"dhat": 1e-3},
  "time": {"step": 0.01, "duration": 0.05, "integrator": "bdf2"},
  "rom": [{"method": "adaptive_subspace", "basis": "modes", "size": 12}]
}
JSON

if ROMKIT_THREADS=1 "$ROMKIT" compare "$TMP/lift.json" --report "$TMP/r.json" >"$TMP/out" 2>"$TMP/err"; then
    rel=$(json_num "$TMP/r.json" 'methods[1].relative_error')
    nmse=$(json_num "$TMP/r.json" 'methods[1].normalized_mse')
    below "$rel" 2e-2 && below "$nmse" 1e-6 && ok adaptive_moving_obstacle_matches_full_order \
        || fail adaptive_moving_obstacle_matches_full_order "relative error $rel, normalized MSE $nmse"
    json_checks adaptive_moving_obstacle_no_crossing "$TMP/r.json" 'methods[1].contact.intersections=0' \
        'methods[1].adaptive.residual.steps_over_tolerance=0' 'methods[1].unconverged_steps=0'
else
    fail adaptive_moving_obstacle_matches_full_order "$(head -c 400 "$TMP/err")"
fi
