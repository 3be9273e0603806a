#!/bin/sh
# The runtime's step with the projected volume against the pointwise one (issue 37: "the asset's
# runtime step stays within 1.3x of today's for the same m and cubature"). The FreeForm bend's
# mesh-free entries of examples/scenes/beam_bend_table.json, baked as float32 assets (romkit
# build --entry K): m = 16 pointwise (entry 2) and projected (12), m = 32 pointwise (3) and
# projected (13), each on the same 5,000 exact integration points; each stepped STEPS steps from
# rest by romkit run, REPS times in turn (the pairs interleaved, so a shared machine's load
# falls on both alike), one thread. Writes $OUT/volume_runtime.csv: one row per run (the
# report's median seconds per step, Newton iterations, factorizations), and the ratio of the
# medians over the repetitions per m.
# Environment: BUILD (build), STEPS (100), REPS (3), OUT (bench/results), WORK ($BUILD/volume_runtime).
set -eu
BUILD=${BUILD:-build}
STEPS=${STEPS:-100}
REPS=${REPS:-3}
OUT=${OUT:-bench/results}
WORK=${WORK:-$BUILD/volume_runtime}
export ROMKIT_THREADS=1 OMP_NUM_THREADS=1 OPENBLAS_NUM_THREADS=1
SCENE=examples/scenes/beam_bend_table.json
mkdir -p "$WORK" "$OUT"
for e in 2 12 3 13; do
    "$BUILD/romkit" build "$SCENE" --entry "$e" -o "$WORK/e$e.rombin" --quiet >/dev/null
done
csv=$WORK/volume_runtime.csv.tmp
echo "m,volume,entry,rep,steps,seconds_per_step,newton_iterations,factorizations" >"$csv"
rep=1
while [ "$rep" -le "$REPS" ]; do
    for e in 2 12 3 13; do
        "$BUILD/romkit" run "$WORK/e$e.rombin" --steps "$STEPS" --quiet --report "$WORK/e$e.json" >/dev/null
        case $e in 2) m=16 v=pointwise ;; 12) m=16 v=projected ;; 3) m=32 v=pointwise ;; *) m=32 v=projected ;; esac
        python3 -c 'import json, sys
r = json.load(open(sys.argv[1]))
print("%s,%s,%s,%s,%d,%.6g,%d,%d" % (sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5], r["steps"],
      r["seconds_per_step"], r["newton_iterations"], r["factorizations"]))' "$WORK/e$e.json" "$m" "$v" "$e" "$rep" >>"$csv"
    done
    rep=$((rep + 1))
done
mv "$csv" "$OUT/volume_runtime.csv"
# the projected step over the pointwise one, medians over the repetitions
python3 - "$OUT/volume_runtime.csv" <<'PY'
import csv, statistics, sys
rows = list(csv.DictReader(open(sys.argv[1])))
for m in ("16", "32"):
    med = {v: statistics.median(float(r["seconds_per_step"]) for r in rows if r["m"] == m and r["volume"] == v)
           for v in ("pointwise", "projected")}
    print("volume_runtime: m = %s: projected %.4g s/step, pointwise %.4g s/step: %.2fx" %
          (m, med["projected"], med["pointwise"], med["projected"] / med["pointwise"]))
PY
echo "# wrote $OUT/volume_runtime.csv"
