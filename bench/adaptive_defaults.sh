#!/bin/sh
# Adaptive subspaces at their defaults on drops nobody tuned them for (issue 34): the octopus
# (1,140 tets), the armadillo (3,717 tets, scaled 0.5) and the bunny (19,379 tets, scaled 0.5), each
# E 2e5, nu 0.4, thrown down at 1 m/s onto a sphere over a plane, dhat 1 mm, BDF2, 10 steps of 0.01 s;
# the adaptive entry is skinning candidates of size 16, every other option at its default (its own
# tolerance, the residual check, full_fraction 0.25). `romkit fom` and `romkit adaptive` run with
# ROMKIT_THREADS=1, alternated, REPEATS times each; CPU s: the whole process's user + system seconds
# (set-up included), the median over the runs (the machine is shared: the load average is printed
# before and after; CPU time is what a run did, wall time what the load let it). The error against
# full order is `romkit compare`'s (one run: it is deterministic), with the report's steps_full, mean
# columns and mean enriched share. Writes bench/results/adaptive_defaults.md.
# Usage: [BUILD=build] [REPEATS=2] sh bench/adaptive_defaults.sh
set -eu
BUILD=${BUILD:-build}
REPEATS=${REPEATS:-2}
OUT=bench/results/adaptive_defaults.md
M=$(pwd)/tests/data/meshes
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
mkdir -p bench/results
scene() { # name, mesh json, sphere center, sphere radius, plane height
    cat >"$T/$1.json" <<JSON
{
  "objects": [{
    "mesh": $2,
    "material": {"model": "neohookean", "young": 2e5, "poisson": 0.4, "density": 1000},
    "velocity": [0, -1, 0]
  }],
  "gravity": [0, -9.81, 0],
  "obstacles": [{"sphere": {"center": $3, "radius": $4}},
                {"plane": {"point": [0, $5, 0], "normal": [0, 1, 0]}}],
  "contact": {"dhat": 1e-3},
  "time": {"step": 0.01, "duration": 0.1, "integrator": "bdf2"},
  "rom": [{"method": "adaptive_subspace", "basis": "skinning", "size": 16}]
}
JSON
}
scene octopus "{\"file\": \"$M/octopus-low.mesh\", \"translate\": [0, 0.3202, 0]}" "[0.1, -0.1, 0.05]" 0.1 -0.2
scene armadillo "{\"file\": \"$M/armadillo_4k.node\", \"scale\": 0.5, \"translate\": [0, 0.692, 0]}" "[0.335, 0, 0.101]" 0.15 0
scene bunny "{\"file\": \"$M/bunny_19k.msh\", \"scale\": 0.5, \"translate\": [0, 0.23, 0]}" "[-0.1, -0.1, 0]" 0.15 0
. bench/cpu.sh
load0=$(cut -d' ' -f1-3 /proc/loadavg)
for s in octopus armadillo bunny; do
    ROMKIT_THREADS=1 "$BUILD/romkit" compare "$T/$s.json" --report "$T/$s-compare.json" --quiet >/dev/null 2>>"$T/err"
    for r in $(seq 1 "$REPEATS"); do
        cpu "$T/$s-fom-$r.cpu" env ROMKIT_THREADS=1 "$BUILD/romkit" fom "$T/$s.json" --quiet 2>>"$T/err"
        cpu "$T/$s-adaptive-$r.cpu" env ROMKIT_THREADS=1 "$BUILD/romkit" adaptive "$T/$s.json" --quiet 2>>"$T/err"
    done
done
load1=$(cut -d' ' -f1-3 /proc/loadavg)
python3 - "$T" "$REPEATS" "$load0" "$load1" >"$OUT" <<'PY'
import json, os, statistics, sys
d, R, load0, load1 = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
def cpu(s, what):
    return statistics.median(float(open(os.path.join(d, "%s-%s-%d.cpu" % (s, what, r))).read()) for r in range(1, R + 1))
print("# Adaptive subspaces at their defaults on untuned drops (issue 34)")
print()
print("`sh bench/adaptive_defaults.sh` (make bench): three objects thrown at 1 m/s onto a sphere over a plane, "
      "10 steps of 0.01 s (BDF2), the adaptive entry at its defaults (skinning candidates of size 16, its own "
      "tolerance, the residual check, full_fraction 0.25). CPU seconds of the whole process (set-up included), "
      "medians of %d alternated runs of `romkit fom` and `romkit adaptive` on one thread; the error and the "
      "model's sizes from one `romkit compare`. Load average %s before, %s after." % (R, load0, load1))
print()
print("| object | tets | full order CPU s | adaptive CPU s | adaptive / full order | relative error | normalized MSE | steps by full order | mean columns | mean enriched share |")
print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
for s in ("octopus", "armadillo", "bunny"):
    rep = json.load(open(os.path.join(d, s + "-compare.json")))
    m = [x for x in rep["methods"] if x.get("adaptive")][0]
    a = m["adaptive"]
    f, ad = cpu(s, "fom"), cpu(s, "adaptive")
    print("| %s | %d | %.3g | %.3g | %.2f | %.2g | %.2g | %d of %d | %.1f | %.2f |" % (
        s, rep["tets"], f, ad, ad / f, m["relative_error"], m["normalized_mse"], a["steps_full"], rep["steps"],
        a["mean_modes"], a["mean_enriched_vertices"] / rep["vertices"]))
PY
cat "$OUT"
