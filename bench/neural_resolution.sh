#!/bin/sh
# Neural DMD at the paper's resolutions (koopman-dmd-log-linear, Fig. 3; issue 35): one cantilever
# (1 x 0.1 x 0.1 m, linear, E = 5e7, clamped at x = 0, sagging under gravity from rest, 20 steps of
# 0.02 s, about 1.4 periods of its first bending mode) on box meshes of 2,401, 10,285 and 106,329
# vertices. Each level: romkit fom --snapshots, then romkit neural-dmd on a one-member family of
# that run (rank 8, 600 Adam steps, window 10, g = 0) baked on the same mesh; the training sees at
# most training.vertices vertices (default 4096: a fixed random sample of the larger meshes), the
# rollout error is measured at every vertex against the full-order run (the report's
# member_errors: relative error and normalized MSE of the positions, util's metrics). At 10k the
# same training on all vertices ("vertices": 0) beside it: the cost the sample bounds.
# Times: CPU seconds (user + system) and wall seconds of each command with one thread
# (ROMKIT_THREADS=1, OPENBLAS_NUM_THREADS=1) and its peak resident memory, all by /usr/bin/time -v;
# the load average when each started (on this shared 2-core machine wall time above load 2 is not a
# valid timing; CPU time is the one to compare).
# The 106k level's full-order run takes about 8 minutes of CPU and 3.4 GB (one factorization of
# 320k unknowns a step; 33 minutes of wall time at load 6-12): it runs only with NEURAL_RES_100K=1,
# which make bench-reference sets; the script is not part of make bench (the 10k training on all
# vertices alone is about 3 minutes of CPU).
# RUNS=DIR keeps the levels' scenes, snapshots and full-order reports there and reuses a level's run
# when its scene there is the one this script writes (the full-order columns then come from that run).
# Writes bench/results/neural_resolution.md. Usage: [BUILD=build] [NEURAL_RES_100K=1] [RUNS=DIR] sh bench/neural_resolution.sh
set -e
BUILD=${BUILD:-build}
R=$PWD/$BUILD/romkit
OUT=$PWD/bench/results/neural_resolution.md
if [ -n "$RUNS" ]; then mkdir -p "$RUNS"; T=$(cd "$RUNS" && pwd); else T=$(mktemp -d); trap 'rm -rf "$T"' EXIT; fi
export ROMKIT_THREADS=1 OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
command -v /usr/bin/time >/dev/null || { echo "bench/neural_resolution.sh: needs /usr/bin/time (GNU time)" >&2; exit 1; }
load() { cut -d' ' -f1 /proc/loadavg; }
# level NAME CELLS: the scene, its full-order run (unless RUNS holds it), the training on a sample
# and (ALL=1) on every vertex.
level() {
    cat >"$T/scene.tmp" <<EOF
{"objects": [{"mesh": {"box": {"size": [1, 0.1, 0.1], "cells": [$2]}},
  "material": {"model": "linear", "young": 5e7, "poisson": 0.35, "density": 1000},
  "fixed": [{"box": [[-1, -1, -1], [0.001, 1, 1]]}]}],
 "gravity": [0, -9.81, 0], "damping": {"mass": 0.5, "stiffness": 0.002},
 "newton": {"max_iterations": 1},
 "time": {"step": 0.02, "duration": 0.4}}
EOF
    if cmp -s "$T/scene.tmp" "$T/beam$1.json" && [ -s "$T/beam$1.npy" ] && [ -s "$T/fom$1.json" ] && [ -s "$T/fom$1.log" ]; then
        rm "$T/scene.tmp"
    else
        mv "$T/scene.tmp" "$T/beam$1.json"
        echo "load $(load)" >"$T/fom$1.load"
        /usr/bin/time -v "$R" fom "$T/beam$1.json" --snapshots "$T/beam$1.npy" --report "$T/fom$1.json" --quiet \
            >"$T/fom$1.log" 2>&1
    fi
    for v in sample ${ALL:+all}; do
        verts=4096; [ "$v" = all ] && verts=0
        cat >"$T/fam$1_$v.json" <<EOF
{"members": [{"scene": "beam$1.json", "snapshots": "beam$1.npy"}],
 "rank": 8, "training": {"epochs": 600, "window": 10, "vertices": $verts}, "seed": 1}
EOF
        echo "load $(load)" >"$T/nd$1_$v.load"
        /usr/bin/time -v "$R" neural-dmd "$T/fam$1_$v.json" --scene "$T/beam$1.json" -o "$T/n$1_$v.rombin" \
            --report "$T/nd$1_$v.json" >"$T/nd$1_$v.log" 2>&1
        echo "$1 $v $verts" >>"$T/levels"
    done
}
rm -f "$T/levels"
level 2k "48, 6, 6"
ALL=1 level 10k "84, 10, 10"
[ "${NEURAL_RES_100K:-0}" = 1 ] && level 100k "200, 22, 22"
python3 - "$T" "$OUT" "${NEURAL_RES_100K:-0}" <<'PY'
import json, re, sys
T, out, big = sys.argv[1], sys.argv[2], sys.argv[3] == "1"
def timev(path):
    text = open(path).read()
    user = float(re.search(r"User time \(seconds\): ([0-9.]+)", text).group(1))
    sys_ = float(re.search(r"System time \(seconds\): ([0-9.]+)", text).group(1))
    wall = re.search(r"Elapsed \(wall clock\) time \(h:mm:ss or m:ss\): ([0-9:.]+)", text).group(1).split(":")
    secs = sum(float(x) * 60 ** i for i, x in enumerate(reversed(wall)))
    rss = int(re.search(r"Maximum resident set size \(kbytes\): ([0-9]+)", text).group(1)) / 1024
    return user + sys_, secs, rss
def loadof(path):
    try:
        return open(path).read().split()[1]
    except OSError:
        return "?"
rows = []
for line in open(T + "/levels"):
    name, v, verts = line.split()
    f = json.load(open("%s/fom%s.json" % (T, name)))
    fc, fw, fr = timev("%s/fom%s.log" % (T, name))
    nd = json.load(open("%s/nd%s_%s.json" % (T, name, v)))
    nc, nw, nr = timev("%s/nd%s_%s.log" % (T, name, v))
    m = nd["neural"]["member_errors"][0]
    nv = m["vertices"]
    trained = nv if int(verts) == 0 or nv <= int(verts) else int(verts)
    rows.append("| %s | %d | %d | %.3g | %.0f | %.0f | %s | %d | %.1f | %.0f | %.0f | %.0f | %s | %.3g | %.3g |" % (
        name, nv, f.get("tets", 0), f["seconds_per_step"], fc, fr, loadof("%s/fom%s.load" % (T, name)), trained,
        nd["neural"]["seconds_training"], nc, nw, nr, loadof("%s/nd%s_%s.load" % (T, name, v)),
        m["relative_error"], m["normalized_mse"]))
with open(out, "w") as o:
    o.write("# Neural DMD at resolution (issue 35)\n\n")
    o.write("`sh bench/neural_resolution.sh`%s: a 1 x 0.1 x 0.1 m linear cantilever sagging under gravity from rest, "
            "20 steps of 0.02 s, on three box meshes; `romkit fom --snapshots`, then `romkit neural-dmd` on a one-member "
            "family of that run (rank 8, 600 Adam steps, window 10) baked on the same mesh. `trained on`: the vertices "
            "the training saw (`training.vertices`, default 4096: a fixed random sample of a larger mesh). Errors: the "
            "rollout from rest against the full-order run at every vertex (relative error and normalized MSE of the "
            "positions). CPU s: user + system of the whole command, one thread; peak MiB: its maximum resident set "
            "(`/usr/bin/time -v`); load: the 1-minute load average when it started (2 cores, shared: compare CPU "
            "seconds, not wall).\n\n" % ("" if big else " (without NEURAL_RES_100K=1: no 106k row)"))
    o.write("| level | vertices | tets | fom s/step (wall) | fom CPU s | fom peak MiB | fom load | trained on | training s (wall) "
            "| neural-dmd CPU s | wall s | peak MiB | load | relative error | normalized MSE |\n")
    o.write("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n")
    o.write("\n".join(rows) + "\n")
    o.write("\nfom load `?`: a full-order run reused from RUNS, whose load was not recorded. Training s: the "
            "report's seconds_training (wall, the Adam steps and the start).\n")
print(open(out).read())
PY
