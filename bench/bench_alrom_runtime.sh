#!/bin/sh
# make bench, the adaptive linear ROM in the runtime (issue 19): its per-step cost against PCA's,
# both baked assets stepped by the float32 runtime in one process (bench_assets: interleaved
# rounds of 40 steps from rest, medians and spread), and each one's error against the full-order
# run (romkit run --reference: relative error of the shown vertices over the free run, no
# realignment). The armadillo's compress and bend scenes of examples/scenes/alrom/, r = 16:
#   pca        POD of the six training runs, cubature trained on them (tolerance 0.01)
#   adaptive   the quadratic manifold fitted to the same training frames (decoder quadratic_pod:
#              their 16 POD modes and a least-squares quadratic term),
#              m = 20, lambda = 0.2, the cubature trained for the moving basis (the decoder's
#              basis at each training frame's code) to PCA's 210 elements (max_points; its
#              tolerance 0.01 alone picks 300, issue 33); stepped over the stored vertices only
#   crom       the same with the CROM decoder trained on those frames (every vertex stored; the
#              decoder network's Jacobian at each vertex each step)
# The training runs are romkit fom jobs whose snapshots both entries list (the job-array form).
# Each step's split (bench_alrom_split, the runtime built with -DROMRT_PROFILE: CPU fractions over
# 3 runs of the scene's steps, times the interleaved median): encode_us the encoder, basis_us the
# history and Grassmann work, rows_us the step basis at the used vertices and the elements' G_e,
# terms_us the reference, M_r, f_r and the commit, newton_us the reduced solve (PCA's whole step).
# Writes bench/results/alrom_runtime.csv (scenario, method, us_per_step, us_min, us_max,
# ratio_to_pca, newton_iterations, relative_error, stored_vertices, cubature_elements and the
# split).
set -e
BUILD=${BUILD:-build}
OUT=${2:-bench/results}
ROMKIT=$BUILD/romkit
JSONQ=$BUILD/jsonq
for tool in "$ROMKIT" "$JSONQ" "$BUILD/bench_assets" "$BUILD/bench_alrom_split"; do # (make bench builds them; a pipe would hide one missing)
    [ -x "$tool" ] || { echo "bench_alrom_runtime.sh: $tool is not built (make $tool)" >&2; exit 1; }
done
DIR=$(cd examples/scenes/alrom && pwd)
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
mkdir -p "$OUT"
. bench/alrom_armadillo.sh
alrom_train
entries="{\"basis\": \"pod\", \"size\": 16, \"name\": \"pca\", \"cubature\": {\"tolerance\": 0.01}, \"training\": [$train]},
 {\"method\": \"adaptive_linear\", \"decoder\": \"quadratic_pod\", \"size\": 16, \"history\": 20, \"lambda\": 0.2, \"name\": \"adaptive\",
  \"cubature\": {\"tolerance\": 0.01, \"max_points\": 210}, \"training\": [$train]},
 {\"method\": \"adaptive_linear\", \"decoder\": \"crom\", \"size\": 16, \"history\": 20, \"lambda\": 0.2, \"name\": \"crom\",
  \"cubature\": {\"tolerance\": 0.01}, \"training\": [$train]}"
echo "scenario,method,us_per_step,us_min,us_max,ratio_to_pca,newton_iterations,relative_error,stored_vertices,cubature_elements,encode_us,basis_us,rows_us,terms_us,newton_us" >"$OUT/alrom_runtime.csv"
for sc in compress bend; do
    alrom_scene "$sc" "$entries"
    for k in 0 1 2; do
        name=$(echo pca adaptive crom | cut -d' ' -f$((k + 1)))
        "$ROMKIT" build "$TMP/$sc.json" --entry $k -o "$TMP/$sc.$name.rombin" --report "$TMP/$sc.$name.build.json" --quiet
        "$ROMKIT" run "$TMP/$sc.$name.rombin" --steps "$steps" --reference "$TMP/$sc.ref.npy" \
            --report "$TMP/$sc.$name.run.json" --quiet >/dev/null
    done
    OPENBLAS_NUM_THREADS=1 "$BUILD/bench_assets" "$steps" 7 "$TMP/$sc.pca.rombin" "$TMP/$sc.adaptive.rombin" "$TMP/$sc.crom.rombin" | tail -n +2 >"$TMP/$sc.times"
    while IFS=, read -r asset us lo hi ratio its; do
        name=$(echo "$asset" | sed 's/.*\.\([a-z]*\)\.rombin/\1/')
        err=$("$JSONQ" get "$TMP/$sc.$name.run.json" reference.relative_error)
        stored=$("$JSONQ" get "$TMP/$sc.$name.build.json" asset.stored_vertices)
        elements=$("$JSONQ" get "$TMP/$sc.$name.build.json" cubature.elements)
        split=$(OPENBLAS_NUM_THREADS=1 "$BUILD/bench_alrom_split" "$TMP/$sc.$name.rombin" "$steps" 3 |
            awk -v us="$us" '{printf "%.4g,%.4g,%.4g,%.4g,%.4g", $1 * us, $2 * us, $3 * us, $4 * us, $5 * us}')
        echo "$sc,$name,$us,$lo,$hi,$ratio,$its,$err,$stored,$elements,$split" >>"$OUT/alrom_runtime.csv"
    done <"$TMP/$sc.times"
done
echo "$OUT/alrom_runtime.csv"
cat "$OUT/alrom_runtime.csv"
