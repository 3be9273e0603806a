#!/bin/sh
# Adaptive subspaces at their defaults on scenes nobody tuned them for (issue 34). Three drops: the
# octopus (1,140 tets), the armadillo (3,717 tets, scaled 0.5) and the bunny (19,379 tets, scaled
# 0.5), each E 2e5, nu 0.4, thrown down at 1 m/s onto a sphere over a plane, dhat 1 mm, BDF2, 10
# steps of 0.01 s. The issue's two other unseen contact scenes: a stiff object on a soft one (the
# octopus scaled 0.3 at E 1e7 thrown at 1 m/s onto a 1 m x 0.1 m slab at E 5e4 that lies on a
# plane; two objects, 2,340 tets, 10 steps) and a twisted bar with self-contact (1 m x 4 cm x 4 cm,
# 1,200 tets, E 1e5, one end clamped, the other turned at 2880 deg/s and pushed back at 1.5 m/s
# under a 3 m/s^2 sideways pull, "contact": {"self": true}; it folds and touches itself before the
# end, up to 81 pairs at once; 60 steps of 0.01 s). The large drop: the bunny refined once (155,032 tets), as the
# bunny above. The adaptive entry is skinning candidates of size 16, every other option at its
# default (its own tolerance, the residual check, full_fraction 0.25). `romkit fom` and `romkit
# adaptive` run with ROMKIT_THREADS=1, alternated, REPEATS times each (the large drop LARGE_REPEATS
# times; LARGE=0 leaves it out); CPU s: the whole process's user + system seconds (set-up
# included), the median over the runs (the machine is shared: the load average is printed before
# and after; CPU time is what a run did, wall time what the load let it). The error against full
# order is `romkit compare`'s (one run: it is deterministic), with the report's steps by full order
# (steps_full), mean columns and mean enriched share; the time shares are the first adaptive run's report's. Writes
# bench/results/adaptive_defaults.md.
# Usage: [BUILD=build] [REPEATS=2] [LARGE=1] [LARGE_REPEATS=1] sh bench/adaptive_defaults.sh
set -eu
BUILD=${BUILD:-build}
REPEATS=${REPEATS:-2}
LARGE=${LARGE:-1}
LARGE_REPEATS=${LARGE_REPEATS:-1}
OUT=bench/results/adaptive_defaults.md
M=$(pwd)/tests/data/meshes
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
mkdir -p bench/results
scene() { # name, objects, obstacles, contact, steps, gravity
    cat >"$T/$1.json" <<JSON
{
  "objects": $2,
  "gravity": $6,
  "obstacles": $3,
  "contact": $4,
  "time": {"step": 0.01, "duration": $5, "integrator": "bdf2"},
  "rom": [{"method": "adaptive_subspace", "basis": "skinning", "size": 16}]
}
JSON
}
drop() { # name, mesh json, sphere center, sphere radius, plane height
    scene "$1" "[{\"mesh\": $2, \"velocity\": [0, -1, 0],
      \"material\": {\"model\": \"neohookean\", \"young\": 2e5, \"poisson\": 0.4, \"density\": 1000}}]" \
        "[{\"sphere\": {\"center\": $3, \"radius\": $4}}, {\"plane\": {\"point\": [0, $5, 0], \"normal\": [0, 1, 0]}}]" \
        '{"dhat": 1e-3}' 0.1 '[0, -9.81, 0]'
}
drop octopus "{\"file\": \"$M/octopus-low.mesh\", \"translate\": [0, 0.3202, 0]}" "[0.1, -0.1, 0.05]" 0.1 -0.2
drop armadillo "{\"file\": \"$M/armadillo_4k.node\", \"scale\": 0.5, \"translate\": [0, 0.692, 0]}" "[0.335, 0, 0.101]" 0.15 0
drop bunny "{\"file\": \"$M/bunny_19k.msh\", \"scale\": 0.5, \"translate\": [0, 0.23, 0]}" "[-0.1, -0.1, 0]" 0.15 0
drop bunny_refined "{\"file\": \"$M/bunny_19k.msh\", \"scale\": 0.5, \"translate\": [0, 0.23, 0], \"refine\": 1}" \
    "[-0.1, -0.1, 0]" 0.15 0
scene stiff_on_soft "[
    {\"mesh\": {\"box\": {\"size\": [1, 0.1, 1], \"cells\": [10, 2, 10]}, \"translate\": [-0.5, 0.002, -0.5]},
     \"material\": {\"model\": \"neohookean\", \"young\": 5e4, \"poisson\": 0.4, \"density\": 1000}},
    {\"mesh\": {\"file\": \"$M/octopus-low.mesh\", \"scale\": 0.3, \"translate\": [0, 0.2, 0]},
     \"material\": {\"model\": \"neohookean\", \"young\": 1e7, \"poisson\": 0.4, \"density\": 1000},
     \"velocity\": [0, -1, 0]}]" \
    '[{"plane": {"point": [0, 0, 0], "normal": [0, 1, 0]}}]' '{"dhat": 1e-3}' 0.1 '[0, -9.81, 0]'
scene twisted_bar '[{
    "mesh": {"box": {"size": [1, 0.04, 0.04], "cells": [50, 2, 2]}},
    "material": {"model": "neohookean", "young": 1e5, "poisson": 0.4, "density": 1000},
    "fixed": [{"box": [[-1, -1, -1], [0.001, 1, 1]]}],
    "moving": [{"box": [[0.999, -1, -1], [2, 1, 1]],
                "twist": {"axis": [1, 0, 0], "center": [1, 0.02, 0.02], "degrees_per_second": 2880},
                "translate": {"velocity": [-1.5, 0, 0]}}]}]' '[]' '{"dhat": 1e-3, "self": true}' 0.6 '[0, -3, 0]'
SCENES="octopus armadillo bunny stiff_on_soft twisted_bar"
[ "$LARGE" = 0 ] || SCENES="$SCENES bunny_refined"
. bench/cpu.sh
load0=$(cut -d' ' -f1-3 /proc/loadavg)
for s in $SCENES; do
    R=$REPEATS
    [ "$s" != bunny_refined ] || R=$LARGE_REPEATS
    echo "$R" >"$T/$s.repeats"
    ROMKIT_THREADS=1 "$BUILD/romkit" compare "$T/$s.json" --report "$T/$s-compare.json" --quiet >/dev/null 2>>"$T/err"
    for r in $(seq 1 "$R"); do
        cpu "$T/$s-fom-$r.cpu" env ROMKIT_THREADS=1 "$BUILD/romkit" fom "$T/$s.json" --quiet 2>>"$T/err"
        rep=""
        [ "$r" != 1 ] || rep="--report $T/$s-adaptive.json"
        # shellcheck disable=SC2086
        cpu "$T/$s-adaptive-$r.cpu" env ROMKIT_THREADS=1 "$BUILD/romkit" adaptive "$T/$s.json" --quiet $rep 2>>"$T/err"
    done
done
load1=$(cut -d' ' -f1-3 /proc/loadavg)
python3 - "$T" "$load0" "$load1" $SCENES >"$OUT" <<'PY'
import json, os, statistics, sys
d, load0, load1, scenes = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
names = {"stiff_on_soft": "octopus E 1e7 on a slab E 5e4 (2 objects)", "twisted_bar": "twisted bar, self-contact",
         "bunny_refined": "bunny refined 1:8"}
def cpu(s, what):
    R = int(open(os.path.join(d, s + ".repeats")).read())
    return statistics.median(float(open(os.path.join(d, "%s-%s-%d.cpu" % (s, what, r))).read()) for r in range(1, R + 1)), R
print("# Adaptive subspaces at their defaults on untuned scenes (issue 34)")
print()
large = "bunny_refined" in scenes
print("`sh bench/adaptive_defaults.sh` (make bench): %s objects thrown at 1 m/s onto a sphere over a plane%s, "
      "10 steps of 0.01 s; a stiff object on a soft one (10 steps); a twisted "
      "bar that folds onto itself (self-contact, 60 steps); BDF2; the adaptive entry at its defaults (skinning "
      "candidates of size 16, its own tolerance, the residual check, full_fraction 0.25). CPU seconds of the whole "
      "process (set-up included), medians of the alternated runs of `romkit fom` and `romkit adaptive` on one "
      "thread (runs: the count of each); the error and the model's sizes from one `romkit compare`. "
      "The issue's bounds: relative error at most 5e-2, normalized MSE at most 1e-4. "
      "Load average %s before, %s after." % ("four" if large else "three",
                                             " (the last the bunny refined once)" if large else " (LARGE=0: not the refined bunny)",
                                             load0, load1))
print()
print("| scene | tets | runs | full order CPU s | adaptive CPU s | adaptive / full order | relative error | normalized MSE | steps by full order | mean columns | mean enriched share |")
print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
for s in scenes:
    rep = json.load(open(os.path.join(d, s + "-compare.json")))
    m = [x for x in rep["methods"] if x.get("adaptive")][0]
    a = m["adaptive"]
    (f, R), (ad, _) = cpu(s, "fom"), cpu(s, "adaptive")
    print("| %s | %d | %d | %.3g | %.3g | %.2f | %.2g | %.2g | %d of %d | %.1f | %.2f |" % (
        names.get(s, s), rep["tets"], R, f, ad, ad / f, m["relative_error"], m["normalized_mse"], a["steps_full"],
        rep["steps"], a["mean_modes"], a["mean_enriched_vertices"] / rep["vertices"]))
print()
print("Time shares of the adaptive run (its report's seconds over seconds.simulate; the first run):")
print()
parts = ("potential", "oracle", "subspace_hessian", "enriched_rows", "pcg", "line_search", "residual_check")
print("| scene | simulate s | " + " | ".join(parts) + " | full order's Newton and the rest |")
print("|---|---:|" + "---:|" * len(parts) + "---:|")
for s in scenes:
    sec = json.load(open(os.path.join(d, s + "-adaptive.json")))["seconds"]
    tot = sec["simulate"]
    sh = [sec[p] / tot for p in parts]
    print("| %s | %.3g | " % (names.get(s, s), tot) + " | ".join("%.2f" % x for x in sh) + " | %.2f |" % (1 - sum(sh)))
PY
cat "$OUT"
