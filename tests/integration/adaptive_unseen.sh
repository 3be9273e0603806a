# Adaptive subspaces at their defaults on issue 34's "stiff object on a soft one": the octopus
# scaled 0.3 at E 1e7 thrown at 1 m/s onto a soft slab (1 m x 0.1 m, E 5e4) lying on a plane, two
# objects, 2,340 tets, 10 steps (bench/adaptive_defaults.sh's stiff_on_soft). Two objects need each
# its own skinning weights (rk_basis_skinning_objects; one eigenproblem over both was refused, two
# zero eigenvalues) and each object's first weight among the initial blocks (24 columns; with the
# first object's alone the octopus had none). At the defaults it must come within the issue's
# bounds of full order (relative error 5e-2, normalized MSE 1e-4; measured 3.4e-3 and 8.1e-9) with
# no step above its tolerance. (RKPM skinning before these changes missed them, relative error
# 0.54, with every step full order's Newton: a fixed contact.kappa brought it to 9e-3-3e-2, so the
# adaptive run's barrier stiffness, adapted at its own iterates, is what differed; docs/methods.md.)
# The second entry checks that a step the adaptive method hands to full order's Newton starts from
# the step's own barrier stiffness, not the one the subspace's iterates set. IPC's adaptive kappa
# (precompute/contact/stiffness.c) is set at the first Hessian with a contact pair, from the
# gradient at that iterate, and doubled at later ones while the closest pair keeps closing, so a
# try in the subspace set it differently from full order's own run. With RKPM skinning candidates
# and only the slab's first weight active at the start (initial_size 12: the octopus enriched whole
# at its first contact, every step handed to full order) that ended at relative error 0.54 (nMSE
# 2.0e-4, 0.10 m off: the octopus bounced differently); a fixed contact.kappa (1e2, 1e4) brought it
# to 3.3e-2 and 9.3e-3, and restoring the step's kappa to 3.4e-3 (nMSE 8.1e-9). Both entries share
# the one full-order run. About 12 s of CPU.
. tests/lib.sh

cat >"$TMP/stiff.json" <<JSON
{
  "objects": [
    {"mesh": {"box": {"size": [1, 0.1, 1], "cells": [10, 2, 10]}, "translate": [-0.5, 0.002, -0.5]},
     "material": {"model": "neohookean", "young": 5e4, "poisson": 0.4, "density": 1000}},
    {"mesh": {"file": "$(pwd)/tests/data/meshes/octopus-low.mesh", "scale": 0.3, "translate": [0, 0.2, 0]},
     "material": {"model": "neohookean", "young": 1e7, "poisson": 0.4, "density": 1000},
     "velocity": [0, -1, 0]}
  ],
  "gravity": [0, -9.81, 0],
  "obstacles": [{"plane": {"point": [0, 0, 0], "normal": [0, 1, 0]}}],
  "contact": {"dhat": 1e-3},
  "time": {"step": 0.01, "duration": 0.1, "integrator": "bdf2"},
  "rom": [{"method": "adaptive_subspace", "basis": "skinning", "size": 16},
          {"method": "adaptive_subspace", "basis": "rkpm_skinning", "size": 16, "initial_size": 12, "name": "rkpm"}]
}
JSON

if ROMKIT_THREADS=1 "$ROMKIT" compare "$TMP/stiff.json" --report "$TMP/r.json" >"$TMP/out" 2>"$TMP/err"; then
    rel=$(json_num "$TMP/r.json" 'methods[1].relative_error')
    nmse=$(json_num "$TMP/r.json" 'methods[1].normalized_mse')
    below "$rel" 5e-2 && below "$nmse" 1e-4 && ok adaptive_stiff_on_soft_matches_full_order \
        || fail adaptive_stiff_on_soft_matches_full_order "relative error $rel, normalized MSE $nmse"
    json_checks adaptive_stiff_on_soft_each_object_moves "$TMP/r.json" 'methods[1].basis.columns=24' \
        'methods[1].adaptive.residual.steps_over_tolerance=0' 'methods[1].unconverged_steps=0'
    rel=$(json_num "$TMP/r.json" 'methods[2].relative_error')
    nmse=$(json_num "$TMP/r.json" 'methods[2].normalized_mse')
    full=$(json_num "$TMP/r.json" 'methods[2].adaptive.steps_full')
    below 9 "$full" && below "$rel" 5e-2 && below "$nmse" 1e-4 && ok adaptive_full_order_keeps_the_steps_kappa \
        || fail adaptive_full_order_keeps_the_steps_kappa "relative error $rel, normalized MSE $nmse, $full steps by full order"
else
    fail adaptive_stiff_on_soft_matches_full_order "$(head -c 400 "$TMP/err")"
fi
