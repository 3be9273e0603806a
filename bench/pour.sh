#!/bin/sh
# Issue 30's pour in the runtime: N objects (8 by default: 5 boxes, 2 Gaussian-splat clouds and an
# octopus, each with its own skinning basis; bench/pour_scene.py) dropped in a loose stack into an
# open triangle-mesh box,
# dt = 1/60 s, 150 steps (2.5 s: they pile up). Baked with romkit build in float32 and float64;
#   contact   romkit run --scene --report every frame: contact.intersections (the exact
#             segment-triangle test; must be 0) and contact.min_distance (> 0), float and double
#   cost      bench_pour (the runtime built with -DROMRT_PROFILE): the median CPU us/step over
#             REPEATS runs of all the steps, its spread (smallest and largest run median), and
#             the split into broad phase, narrow phase and Newton (bench/bench_pour.c says what
#             each covers); Newton to the asset's tolerance, and 2 fixed Newton steps per step
#             (romrt_set_newton_iterations: what an engine's frame budget runs; every step is
#             still CCD-filtered)
#   old       OLD=dir: that build's romkit (main at c1a2867, built in another directory), which
#             cannot bake the pour: a planes-only asset (bench/obstacle_step_cost.sh's planes
#             scene) baked by each build and stepped by its own romkit run, CPU seconds per step
#             (the smallest of 5 runs each), old against new
# Writes bench/results/contact_pour.md (make results-tables puts it in docs/results).
# Usage: [BUILD=build] [OLD=dir [OLD_NAME=text]] [REPEATS=5] sh bench/pour.sh [N] [STEPS]
set -e
BUILD=${BUILD:-build}
REPEATS=${REPEATS:-5}
N=${1:-8}
STEPS=${2:-150}
OUT=bench/results/contact_pour.md
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
python3 bench/pour_scene.py "$T" "$N"
"$BUILD/romkit" build "$T/pour.json" -o "$T/f32.rombin" --quiet >/dev/null
"$BUILD/romkit" build "$T/pour.json" -o "$T/f64.rombin" --quiet --precision float64 >/dev/null

# the CPU seconds per step of `romkit run` (children's user + system time, asset load included)
cpu_per_step() { # romkit asset [args]
    python3 - "$STEPS" "$@" <<'PY'
import resource, subprocess, sys
steps = int(sys.argv[1])
subprocess.run([sys.argv[2], "run", sys.argv[3], "--steps", str(steps), "--quiet"] + sys.argv[4:], check=True,
               stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
u = resource.getrusage(resource.RUSAGE_CHILDREN)
print("%.1f" % (1e6 * (u.ru_utime + u.ru_stime) / steps))
PY
}

contact() { # romkit asset tag [args]
    rk=$1 asset=$2 tag=$3
    shift 3
    "$rk" run "$asset" --steps "$STEPS" --scene "$T/pour.json" --report "$T/$tag.json" --quiet "$@" >/dev/null
    python3 - "$T/$tag.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
c = r["contact"]
print("%d %d %.3g %.1f %.2f" % (c["intersections"], c["frames"], c["min_distance"], 1e6 * r["seconds_per_step"],
                                r["newton_iterations"] / r["steps"]))
PY
}

LOAD0=$(cut -d' ' -f1 /proc/loadavg 2>/dev/null || echo ?)
{
    echo "# The pour in the runtime (issue 30)"
    echo
    echo "Written by \`sh bench/pour.sh\` ($(date -u +%Y-%m-%d), $(nproc) cores shared, $(uname -m), load average"
    echo "$LOAD0 at the start: CPU times run long while other jobs share the cores)."
    echo "$N objects (bench/pour_scene.py: boxes of 2 x 2 x 2 cells in several sizes and stiffnesses; from 3 on"
    echo "the donut splat capture (every 16th of its 45,624 splats) as a point cloud 9.5 cm across in slot 2"
    echo "and, from 6 on, 8.4 cm across in slot 5, each colliding through its marching-tets contact surface"
    echo "(proxy_voxel 1 cm: a 1.5 cm lattice, the second cloud retried on 1 cm, which left a splat past its"
    echo "spacing; slivers tidied: the 8-object asset 3,198 triangles against 2,590 on the voxel surfaces);"
    echo "from 8 on octopus-low scaled to 12 cm; each its own rkpm_skinning basis"
    echo "of size 1, r = $((24 * N)), mesh-free: 200 integration points an object, no cubature) dropped in two"
    echo "layers into an open box given as a 10-triangle OBJ obstacle; dhat 2 mm, friction 0.3,"
    echo "dt = 1/60 s, $STEPS steps. One core: the runtime is single-threaded."
    echo
    echo "## Contact (romkit run --scene, every frame, the exact segment-triangle test)"
    echo
    echo "| build | Newton | intersections | frames | min distance (m) | wall us/step (median) | Newton its/step |"
    echo "|---|---|---|---|---|---|---|"
    for p in f32 f64; do
        rk="$BUILD/romkit"
        [ $p = f64 ] && rk="$BUILD/romkit-double"
        set -- $(contact "$rk" "$T/$p.rombin" "$p-conv")
        echo "| $p | converged | $1 | $2 | $3 | $4 | $5 |"
        set -- $(contact "$rk" "$T/$p.rombin" "$p-fix2" --newton 2)
        echo "| $p | 2 fixed | $1 | $2 | $3 | $4 | $5 |"
    done
    echo
    echo "Wall times are the shared machine's (other jobs' time slices count); the table below is CPU time."
    echo
    echo "## Step cost and its split (bench_pour, $REPEATS runs of $STEPS steps, CPU time)"
    echo
    echo "| build | Newton | us/step (median) | spread (run medians) | steps/s | broad | narrow | Newton | Newton its/step | halvings/step |"
    echo "|---|---|---|---|---|---|---|---|---|---|"
    for p in f32 f64; do
        b="$BUILD/bench_pour"
        [ $p = f64 ] && b="$BUILD/bench_pour_double"
        for k in 0 2; do
            set -- $("$b" "$T/$p.rombin" "$STEPS" "$REPEATS" $k)
            name=converged
            [ $k = 2 ] && name="2 fixed"
            echo "| $p | $name | $1 | $2 - $3 | $(python3 -c "print('%.0f' % (1e6 / $1))") |" \
                "$(python3 -c "print('%.0f%%' % (100 * $5))") | $(python3 -c "print('%.0f%%' % (100 * $6))") |" \
                "$(python3 -c "print('%.0f%%' % (100 * $7))") | $8 | $9 |"
        done
    done
    echo
    echo "broad: BVH refit and traversal against the container, the objects' sort and sweep, the"
    echo "Verlet list's filter. narrow: per stencil distance, barrier, PSD projection, the pull into"
    echo "the r x r system, friction, CCD. Newton: the rest (elastic energy, inertia, the dense r x r"
    echo "Cholesky and solve, line search). The median step includes the first steps' free fall."
    echo
    echo "## Against the old code"
    echo
    echo "The old code (before issue 30) cannot bake the pour (its mesh container), so there is no old pour"
    echo "to time. What the issue asks of the old code's assets is that an asset with planes only costs what"
    echo "it costs today: the planes scene of bench/obstacle_step_cost.sh (a slab of 8 x 2 x 8 cells, r = 12"
    echo "with cubature, falling from rest onto a plane 5 cm below, friction 0.3, dt 0.01 s; from rest, since"
    echo "the old code bakes no initial velocity), baked by each build's"
    echo "romkit and stepped $STEPS times by its own \`romkit run\` (float32)."
    echo
    if [ -n "$OLD" ]; then
        cat >"$T/planes.json" <<JSON
{"objects": [{"mesh": {"box": {"size": [0.4, 0.1, 0.4], "cells": [8, 2, 8]}, "translate": [-0.2, 0.05, -0.2]},
  "material": {"model": "neohookean", "young": 1e5, "poisson": 0.4, "density": 1000}}],
 "gravity": [0, -9.81, 0], "obstacles": [{"plane": {"point": [0, 0, 0], "normal": [0, 1, 0]}}],
 "contact": {"dhat": 0.002, "friction": 0.3}, "time": {"step": 0.01, "duration": 0.5},
 "rom": {"basis": "modes", "size": 12, "cubature": {"tolerance": 0.02}}}
JSON
        "$OLD/romkit" build "$T/planes.json" -o "$T/old_planes.rombin" --quiet >/dev/null
        "$BUILD/romkit" build "$T/planes.json" -o "$T/new_planes.rombin" --quiet >/dev/null
        echo "CPU us per step of \`romkit run --steps $STEPS\` (asset load included; the smallest of 5 runs each,"
        echo "old and new interleaved), old build $OLD${OLD_NAME:+ ($OLD_NAME)} against this one."
        echo
        echo "| Newton | old | new | old / new |"
        echo "|---|---|---|---|"
        for k in 0 2; do
            a="" name=converged
            [ $k = 2 ] && a="--newton 2" name="2 fixed"
            o="" n=""
            for i in 1 2 3 4 5; do
                o="$o $(cpu_per_step "$OLD/romkit" "$T/old_planes.rombin" $a)"
                n="$n $(cpu_per_step "$BUILD/romkit" "$T/new_planes.rombin" $a)"
            done
            o=$(python3 -c "print(min(float(x) for x in '$o'.split()))")
            n=$(python3 -c "print(min(float(x) for x in '$n'.split()))")
            echo "| $name | $o | $n | $(python3 -c "print('%.2f' % ($o / $n))") |"
        done
    else
        echo "Not measured in this run (OLD=dir names a build of the old code, main at c1a2867)."
    fi
} >"$OUT.tmp"
mv "$OUT.tmp" "$OUT"
cat "$OUT"
