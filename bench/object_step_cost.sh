#!/bin/sh
# The runtime's step cost with several objects (issue 30 part 2), by romkit run's median us/step:
#   boxes   test_runtime_objects' block of 4 x 4 x 4 cells dropped onto a slab of 8 x 2 x 8 on a
#           plane (rkpm_skinning, 2 objects), 80 steps
#   clouds  its two point clouds (a 11 x 3 x 11 slab, a 5 x 5 x 5 block 4 cm apart; each colliding
#           through its contact surface, rk_points_proxy)
# Each build bakes its own asset (an older build writes 1.5's sphere proxies, CRAD, which a newer
# one refuses), float32 (romkit) and float64 (romkit-double). BUILD names the build (build by
# default): run it once with the old build's directory and once with this one's.
# Usage: BUILD=dir sh bench/object_step_cost.sh [STEPS]   (from the repository root)
set -e
BUILD=${BUILD:-build}
STEPS=${1:-80}
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
python3 - "$T" <<'PY'
import sys
def lattice(path, n, o):
    pts = ["%g %g %g" % (o[0] + 0.04 * i, o[1] + 0.04 * j, o[2] + 0.04 * k)
           for i in range(n[0]) for j in range(n[1]) for k in range(n[2])]
    open(path, "w").write("ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\n"
                          "property float z\nend_header\n" % len(pts) + "\n".join(pts) + "\n")
lattice(sys.argv[1] + "/slab.ply", (11, 3, 11), (0, 0, 0))
lattice(sys.argv[1] + "/block.ply", (5, 5, 5), (0.1, 0.35, 0.1))
PY
cat >"$T/boxes.json" <<JSON
{"objects": [
  {"mesh": {"box": {"size": [0.4, 0.1, 0.4], "cells": [8, 2, 8]}, "translate": [0, 0.002, 0]},
   "material": {"model": "neohookean", "young": 2e5, "poisson": 0.4, "density": 1000}},
  {"mesh": {"box": {"size": [0.2, 0.2, 0.2], "cells": [4, 4, 4]}, "translate": [0.1, 0.25, 0.1]},
   "material": {"model": "neohookean", "young": 1e5, "poisson": 0.4, "density": 1000}}],
 "gravity": [0, -9.81, 0], "damping": {"mass": 2},
 "obstacles": [{"plane": {"point": [0, 0, 0], "normal": [0, 1, 0]}}],
 "contact": {"dhat": 0.002}, "time": {"step": 0.01, "duration": 0.8},
 "rom": {"basis": "rkpm_skinning", "size": 2}}
JSON
cat >"$T/clouds.json" <<JSON
{"objects": [{"mesh": {"points": "$T/slab.ply"}, "material": {"model": "neohookean", "young": 1e5, "poisson": 0.4, "density": 1000}},
 {"mesh": {"points": "$T/block.ply"}, "material": {"model": "neohookean", "young": 5e4, "poisson": 0.4, "density": 1000}}],
 "gravity": [0, -9.81, 0], "damping": {"mass": 2},
 "obstacles": [{"plane": {"point": [0, -0.05, 0], "normal": [0, 1, 0]}}],
 "contact": {"dhat": 0.002}, "time": {"step": 0.01, "duration": 0.5},
 "rom": {"basis": "rkpm_skinning", "size": 2, "kernels": 40}}
JSON
for s in boxes clouds; do
    "$BUILD/romkit" build "$T/$s.json" -o "$T/$s.rombin" --quiet >/dev/null
    "$BUILD/romkit" build "$T/$s.json" -o "$T/${s}64.rombin" --quiet --precision float64 >/dev/null
    echo "$s float32: $("$BUILD/romkit" run "$T/$s.rombin" --steps "$STEPS" 2>&1 | tail -1 | sed 's/^[^:]*: //')"
    echo "$s float64: $("$BUILD/romkit-double" run "$T/${s}64.rombin" --steps "$STEPS" 2>&1 | tail -1 | sed 's/^[^:]*: //')"
done
