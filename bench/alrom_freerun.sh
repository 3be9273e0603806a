#!/bin/sh
# Why the adaptive linear ROM's free run loses to PCA on the armadillo's bend (issue 33,
# docs/methods.md's free-run section): bench_alrom_freerun (the precompute's double simulators, the
# adaptive entry of bench_alrom_runtime.sh beside PCA's fixed basis in the same simulator) on the
# scenes $SCENES (default compress bend) of the objects $OBJECTS (default armadillo) in
# examples/scenes/alrom/, trained on the object's six other motions (alrom_object.sh), in variants:
#   free       the free run as romkit compare runs it
#   exact      every element's forces (no cubature)
#   realigned  each step from full order's state (romkit compare's realigned run, for both)
#   start20    both on full order's run for 20 steps, then free
#   lambda1    the decoder's basis alone (no history)
#   oracle     the test run's own frames added to the training (what a decoder that covers the
#              motion would give)
# and romkit compare's own PCA entry (the fixed ROM: total form, the moving box held by its
# penalty) with and without its cubature; ONLY_FREE=1: the free and exact variants alone.
# Writes bench/results/alrom_freerun.csv (object, scenario,
# variant, adaptive, pca_same_simulator, floor_pca, floor_decoder, dropped_kinetic_J,
# pca_fixed_rom); each error relative over the run against full order (the realigned variant's:
# the relative online error), the floors full order's own states through PCA's projection and the
# decoder's manifold (M-norm, over the run).
# Usage: BUILD=build sh bench/alrom_freerun.sh [unused] [OUT]   (make build/bench_alrom_freerun first)
set -e
BUILD=${BUILD:-build}
OUT=${2:-bench/results}
ROMKIT=$BUILD/romkit
for tool in "$ROMKIT" "$BUILD/jsonq" "$BUILD/bench_alrom_freerun"; do
    [ -x "$tool" ] || { echo "alrom_freerun.sh: $tool is not built (make $tool)" >&2; exit 1; }
done
DIR=$(cd examples/scenes/alrom && pwd)
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
mkdir -p "$OUT"
. bench/alrom_object.sh
echo "object,scenario,variant,adaptive,pca_same_simulator,floor_pca,floor_decoder,dropped_kinetic_J,pca_fixed_rom" >"$OUT/alrom_freerun.csv"
# the summary line of one bench_alrom_freerun run: adaptive, pca, floors, dropped kinetic energy
summary() {
    OPENBLAS_NUM_THREADS=1 "$BUILD/bench_alrom_freerun" "$1" 1 >"$TMP/run.csv"
    line=$(grep '^# free-run' "$TMP/run.csv")
    if [ "${BENCH_REALIGN:-0}" = 1 ]; then line=$(grep '^# realigned' "$TMP/run.csv"); fi
    echo "$line" | sed 's/.*adaptive \([^,]*\), pca (same simulator) \([^;]*\).*/\1,\2/' | tr -d '\n'
    grep '^# free-run' "$TMP/run.csv" | sed 's/.*dropped \([^ ]*\) J.*pca \([^,]*\), decoder \(.*\)$/,\2,\3,\1/'
}
for OBJECT in ${OBJECTS:-armadillo}; do
    alrom_train "$OBJECT"
    entries="{\"basis\": \"pod\", \"size\": 16, \"name\": \"pca\", \"cubature\": {\"tolerance\": 0.01}, \"training\": [$train]},
     {\"method\": \"adaptive_linear\", \"decoder\": \"quadratic_pod\", \"size\": 16, \"history\": 20, \"lambda\": 0.2, \"name\": \"adaptive\",
      \"cubature\": {\"tolerance\": 0.01, \"max_points\": 210}, \"training\": [$train]},
     {\"basis\": \"pod\", \"size\": 16, \"name\": \"pca_exact\", \"training\": [$train]}"
    for sc in ${SCENES:-compress bend}; do
        alrom_scene "$OBJECT" "$sc" "$entries"
        J=$TMP/${OBJECT}_$sc
        OPENBLAS_NUM_THREADS=1 "$ROMKIT" compare "$J.json" --report "$J.compare.json" --quiet >/dev/null 2>&1
        pca=$(printf '%.5g' "$("$BUILD/jsonq" get "$J.compare.json" methods[1].relative_error)")
        pcax=$(printf '%.5g' "$("$BUILD/jsonq" get "$J.compare.json" methods[3].relative_error)")
        pcar=$(printf '%.5g' "$("$BUILD/jsonq" get "$J.compare.json" methods[1].relative_online_error)")
        row="$OBJECT,$sc"
        echo "$row,free,$(summary "$J.json"),$pca" >>"$OUT/alrom_freerun.csv"
        echo "$row,exact,$(BENCH_EXACT=1 summary "$J.json"),$pcax" >>"$OUT/alrom_freerun.csv"
        [ "${ONLY_FREE:-0}" = 1 ] && continue
        echo "$row,realigned,$(BENCH_REALIGN=1 summary "$J.json"),$pcar" >>"$OUT/alrom_freerun.csv"
        echo "$row,start20,$(BENCH_START=20 summary "$J.json")," >>"$OUT/alrom_freerun.csv"
        echo "$row,lambda1,$(BENCH_LAMBDA=1 summary "$J.json")," >>"$OUT/alrom_freerun.csv"
        python3 -c "
import json, sys
s = json.load(open(sys.argv[1]))
for e in s['rom']:
    e['training'] = e['training'] + [{'snapshots': sys.argv[2]}]
json.dump(s, open(sys.argv[3], 'w'))" "$J.json" "$J.ref.npy" "$J.oracle.json"
        echo "$row,oracle,$(summary "$J.oracle.json")," >>"$OUT/alrom_freerun.csv"
    done
done
echo "$OUT/alrom_freerun.csv"
cat "$OUT/alrom_freerun.csv"
