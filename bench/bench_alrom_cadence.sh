#!/bin/sh
# make bench, the adaptive linear ROM's formulation knobs in the runtime (issue 33): the basis
# cadence K (the encoder, history entry, Grassmann point, used rows and G_e formed every K steps
# and held between: a linear ROM's step there), the history m and the encoder's Gauss-Newton cap,
# each setting's runtime step cost against PCA's (bench_assets: all assets in one process,
# interleaved rounds of the scene's steps from rest, medians and the fastest and slowest round) and
# its free-run error against full order (romkit run --reference, no realignment). The armadillo's
# compress and bend scenes of examples/scenes/alrom/, r = 16, float32, lambda 0.2, the fitted
# quadratic decoder with the cubature trained for the moving basis to PCA's 210 elements, both
# trained on the six training runs (as bench_alrom_runtime.sh's pca and adaptive).
# Writes bench/results/alrom_cadence.csv (scenario, method, cadence, history, encoder_iterations,
# us_per_step, us_min, us_max, ratio_to_pca, newton_iterations, relative_error).
set -e
BUILD=${BUILD:-build}
OUT=${2:-bench/results}
ROMKIT=$BUILD/romkit
JSONQ=$BUILD/jsonq
for tool in "$ROMKIT" "$JSONQ" "$BUILD/bench_assets"; do
    [ -x "$tool" ] || { echo "bench_alrom_cadence.sh: $tool is not built (make $tool)" >&2; exit 1; }
done
# K:m:encoder iterations; the first is the default (every step, 20 entries, 20 iterations)
VARIANTS=${VARIANTS:-"1:20:20 2:20:20 4:20:20 8:20:20 1:10:20 1:5:20 1:20:2 1:20:1 2:20:2 4:20:2 8:10:2"}
DIR=$(cd examples/scenes/alrom && pwd)
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
mkdir -p "$OUT"
. bench/alrom_object.sh
alrom_train armadillo
entries="{\"basis\": \"pod\", \"size\": 16, \"name\": \"pca\", \"cubature\": {\"tolerance\": 0.01}, \"training\": [$train]}"
names=pca
for v in $VARIANTS; do
    K=${v%%:*} rest=${v#*:}
    M=${rest%%:*} E=${rest#*:}
    entries="$entries, {\"method\": \"adaptive_linear\", \"decoder\": \"quadratic_pod\", \"size\": 16, \"history\": $M,
  \"lambda\": 0.2, \"cadence\": $K, \"encoder_iterations\": $E, \"name\": \"k${K}m${M}e${E}\",
  \"cubature\": {\"tolerance\": 0.01, \"max_points\": 210}, \"training\": [$train]}"
    names="$names k${K}m${M}e${E}"
done
echo "scenario,method,cadence,history,encoder_iterations,us_per_step,us_min,us_max,ratio_to_pca,newton_iterations,relative_error" >"$OUT/alrom_cadence.csv"
for sc in compress bend; do
    alrom_scene armadillo "$sc" "$entries"
    alrom_assets armadillo "$sc" "$names"
    while IFS=, read -r asset us lo hi ratio its; do
        name=$(echo "$asset" | sed 's/.*\.\([a-z0-9]*\)\.rombin/\1/')
        err=$("$JSONQ" get "$base.$name.run.json" reference.relative_error)
        if [ "$name" = pca ]; then knobs="pca,,,"
        else knobs=$(echo "$name" | sed 's/k\([0-9]*\)m\([0-9]*\)e\([0-9]*\)/adaptive,\1,\2,\3/')
        fi
        echo "$sc,$knobs,$us,$lo,$hi,$ratio,$its,$err" >>"$OUT/alrom_cadence.csv"
    done <"$base.times"
done
echo "$OUT/alrom_cadence.csv"
cat "$OUT/alrom_cadence.csv"
