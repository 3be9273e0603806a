# Adaptive subspaces at their defaults on issue 34's "twisted bar with self-contact", small: a bar
# 0.6 m x 3 cm x 3 cm (144 tets, E 1e5), one end clamped, the other turned at 2880 deg/s and pushed
# back at 1.2 m/s under a 3 m/s^2 sideways pull, "contact": {"self": true}, 33 steps of 0.01 s: it
# folds and touches itself over the last steps (up to 21 pairs). It must come within the issue's
# bounds of full order (relative error 5e-2, normalized MSE 1e-4; measured 8.4e-5 and 5.9e-10).
# Not asserted: no step over the tolerance. Full order itself stops short at 500 iterations on 2
# steps where the bar first touches itself (romkit fom's unconverged_steps 2), and the adaptive run,
# which hands those steps to full order's Newton, leaves the same 2 (its residual 1.8e-3 m/s at
# most, against its tolerance 1.1e-4). bench/adaptive_defaults.sh runs a finer bar (1,200 tets, 60
# steps). About 5 s of CPU.
. tests/lib.sh

cat >"$TMP/twist.json" <<JSON
{
  "objects": [{
    "mesh": {"box": {"size": [0.6, 0.03, 0.03], "cells": [24, 1, 1]}},
    "material": {"model": "neohookean", "young": 1e5, "poisson": 0.4, "density": 1000},
    "fixed": [{"box": [[-1, -1, -1], [0.001, 1, 1]]}],
    "moving": [{"box": [[0.599, -1, -1], [2, 1, 1]],
                "twist": {"axis": [1, 0, 0], "center": [0.6, 0.015, 0.015], "degrees_per_second": 2880},
                "translate": {"velocity": [-1.2, 0, 0]}}]
  }],
  "gravity": [0, -3, 0],
  "contact": {"dhat": 1e-3, "self": true},
  "time": {"step": 0.01, "duration": 0.33, "integrator": "bdf2"},
  "rom": [{"method": "adaptive_subspace", "basis": "skinning", "size": 16}]
}
JSON

if ROMKIT_THREADS=1 "$ROMKIT" compare "$TMP/twist.json" --report "$TMP/r.json" >"$TMP/out" 2>"$TMP/err"; then
    rel=$(json_num "$TMP/r.json" 'methods[1].relative_error')
    nmse=$(json_num "$TMP/r.json" 'methods[1].normalized_mse')
    closest=$(json_num "$TMP/r.json" 'methods[1].contact.min_distance')
    below "$closest" 1e-3 && ok adaptive_twist_touches_itself || fail adaptive_twist_touches_itself "closest $closest m"
    below "$rel" 5e-2 && below "$nmse" 1e-4 && ok adaptive_twist_matches_full_order \
        || fail adaptive_twist_matches_full_order "relative error $rel, normalized MSE $nmse"
else
    fail adaptive_twist_matches_full_order "$(head -c 400 "$TMP/err")"
fi
