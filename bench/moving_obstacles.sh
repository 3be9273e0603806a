#!/bin/sh
# Moving obstacles in the runtime (issue 30): a soft slab (8 x 2 x 8 cells, modes r = 12 with
# cubature) thrown down at 2 m/s onto the benches' 3200-triangle spiky terrain (bench/terrain_obj.py)
# baked rising at 1 m/s, 40 steps, float32 (romkit) and float64 (romkit-double), and the same terrain
# static as the control. Each run's median us/step, Newton iterations, the closest approach and the
# crossings of the exact test (--scene); three runs a case alternating with the older build OLD
# (its romkit and romkit-double, e.g. a build of c6c166a, which moved obstacles in CCD-safe moves)
# when given: the median and range of the three, and old / new. Writes
# bench/results/moving_obstacles.md. Usage: [BUILD=build] [OLD=dir] sh bench/moving_obstacles.sh
set -e
BUILD=${BUILD:-build}
OUT=bench/results/moving_obstacles.md
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
python3 bench/terrain_obj.py "$T/terrain.obj"
scene() { # name, terrain motion
    cat >"$T/$1.json" <<JSON
{"objects": [{"mesh": {"box": {"size": [0.2, 0.05, 0.2], "cells": [8, 2, 8]}, "translate": [-0.087, 0.085, -0.079]},
  "material": {"model": "neohookean", "young": 1e5, "poisson": 0.4, "density": 1000}, "velocity": [0, -2, 0]}],
 "gravity": [0, -9.81, 0], "obstacles": [{"mesh": {"file": "$T/terrain.obj"}$2}],
 "contact": {"dhat": 0.002, "friction": 0.3}, "time": {"step": 0.01, "duration": 0.4},
 "rom": {"basis": "modes", "size": 12, "cubature": {"tolerance": 0.02}}}
JSON
}
scene static ""
scene rising ', "translate": {"velocity": [0, 1, 0]}'
load() { cut -d' ' -f1 /proc/loadavg; }
# run BUILD_DIR NAME PRECISION -> "us newton closest crossings" or "failed: why"
run() {
    exe="$1/romkit"; [ "$3" = float64 ] && exe="$1/romkit-double"
    asset="$T/$2.rombin"; [ "$3" = float64 ] && asset="$T/${2}64.rombin"
    if "$exe" run "$asset" --steps 40 --scene "$T/$2.json" --report "$T/r.json" --quiet >"$T/out" 2>&1; then
        python3 -c "import json; r = json.load(open('$T/r.json')); c = r['contact']
print('%.1f %d %.3g %d' % (1e6 * r['seconds_per_step'], r['newton_iterations'], c['min_distance'], c['intersections']))"
    else
        echo "failed: $(tail -n 1 "$T/out" | sed 's/^romkit run: //' | cut -c1-160)"
    fi
}
for s in static rising; do
    "$BUILD/romkit" build "$T/$s.json" -o "$T/$s.rombin" --quiet >/dev/null
    "$BUILD/romkit" build "$T/$s.json" -o "$T/${s}64.rombin" --quiet --precision float64 >/dev/null
done
l0=$(load)
for rep in 1 2 3; do
    for s in static rising; do
        for p in float32 float64; do
            run "$BUILD" $s $p >"$T/new.$s.$p.$rep"
            [ -n "$OLD" ] && run "$OLD" $s $p >"$T/old.$s.$p.$rep"
        done
    done
done
python3 - "$T" "$OUT" "$l0" "${OLD:-}" <<'PY'
import statistics, sys
T, out, load, old = sys.argv[1], sys.argv[2], float(sys.argv[3]), sys.argv[4]
def runs(who, s, p):
    return [open("%s/%s.%s.%s.%d" % (T, who, s, p, k)).read().strip() for k in (1, 2, 3)]
def cell(rs):
    if any(r.startswith("failed") for r in rs):
        return next(r for r in rs if r.startswith("failed")), None
    v = [r.split() for r in rs]
    us = sorted(float(x[0]) for x in v)
    return ("%.0f us (%.0f-%.0f), %s Newton, closest %s m, %s crossings"
            % (statistics.median(us), us[0], us[-1], v[0][1], v[0][2], max(int(x[3]) for x in v)), statistics.median(us))
with open(out, "w") as f:
    f.write("# Moving obstacles in the runtime (issue 30)\n\n`sh bench/moving_obstacles.sh`%s: a slab thrown down at 2 m/s onto the "
            "3200-triangle spiky terrain, static or baked rising at 1 m/s, 40 steps of 0.01 s, modes r = 12 with cubature; "
            "each cell the median (range) of three runs' median us/step, the Newton iterations of the run, the closest "
            "approach and the crossings of the exact segment-triangle test (`romkit run --scene`).%s\n\n"
            % (" with OLD=" + old if old else "", " Load %.2f at the start%s." % (load, " (above 3: the times are not valid)" if load > 3 else "")))
    f.write("| terrain | precision | this build |%s\n|---|---|---|%s\n" % (" OLD | old / new |" if old else "", "---|---|" if old else ""))
    for s in ("static", "rising"):
        for p in ("float32", "float64"):
            new, nm = cell(runs("new", s, p))
            row = "| %s | %s | %s |" % (s, p, new)
            if old:
                o, om = cell(runs("old", s, p))
                row += " %s | %s |" % (o, "%.2f" % (om / nm) if om and nm else "-")
            f.write(row + "\n")
print(out)
PY
