#!/bin/sh
# make bench, the adaptive linear ROM in the runtime (issue 19, 33): its per-step cost against
# PCA's, both baked assets stepped by the float32 runtime in one process (bench_assets: interleaved
# rounds of the scene's steps from rest, medians and spread), and each one's error against the
# full-order run (romkit run --reference: relative error of the shown vertices over the free run,
# no realignment). Two objects, so a step cost that grows with the mesh shows: the armadillo
# (armadillo_4k, 1,180 vertices) and the bunny (bunny_19k, 19,379 tets, 4,670 vertices), each
# one's compress and bend scenes of examples/scenes/alrom/, r = 16:
#   pca        POD of the object's six training runs, cubature trained on them (tolerance 0.01)
#   adaptive   the quadratic manifold fitted to the same training frames (decoder quadratic_pod:
#              their 16 POD modes and a least-squares quadratic term),
#              m = 20, lambda = 0.2, the cubature trained for the moving basis (the decoder's
#              basis at each training frame's code) capped at PCA's element count on the same
#              object and scene (max_points, read from PCA's build report: like for like; its
#              tolerance 0.01 alone picks more, 300 against 210 on the armadillo, issue 33);
#              stepped over the stored vertices only
#   crom       the same with the CROM decoder trained on those frames (every vertex stored; the
#              decoder network's Jacobian at each vertex each step). On every object unless
#              CROM_OBJECTS names fewer (those left out get empty rows, "-" in the table): its
#              training is the long part, 103-117 s a build on the armadillo and 252 s on the
#              bunny here at load 2-4 (alrom_table3.sh's crom_train_s read 554-558 s a bunny
#              motion under heavier load), and the bunny's CROM step is about 0.3 s.
# The training runs are romkit fom jobs whose snapshots every entry lists (the job-array form).
# Each step's split (bench_alrom_split, the runtime built with -DROMRT_PROFILE: CPU fractions over
# 3 runs of the scene's steps, times the interleaved median): encode_us the encoder, basis_us the
# history and Grassmann work, rows_us the step basis at the used vertices and the elements' G_e,
# terms_us the reference, M_r, f_r and the commit, newton_us the reduced solve (PCA's whole step).
# Usage: sh bench/bench_alrom_runtime.sh [unused] [OUT]  (OBJECTS="armadillo bunny" picks objects,
# CROM_OBJECTS those with a CROM row; SNAPSHOTS=DIR keeps the full-order runs there and reuses them,
# for iterating only).
# Writes OUT/alrom_runtime.csv (object, scenario, method, us_per_step, us_min, us_max,
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
OBJECTS=${OBJECTS:-armadillo bunny}
CROM_OBJECTS=${CROM_OBJECTS-$OBJECTS}
. bench/alrom_object.sh
csv=$OUT/alrom_runtime.csv
echo "object,scenario,method,us_per_step,us_min,us_max,ratio_to_pca,newton_iterations,relative_error,stored_vertices,cubature_elements,encode_us,basis_us,rows_us,terms_us,newton_us" >"$csv.tmp"
for obj in $OBJECTS; do
    alrom_train "$obj"
    crom=0
    case " $CROM_OBJECTS " in *" $obj "*) crom=1 ;; esac
    pca="{\"basis\": \"pod\", \"size\": 16, \"name\": \"pca\", \"cubature\": {\"tolerance\": 0.01}, \"training\": [$train]}"
    for sc in compress bend; do
        base=$TMP/${obj}_$sc
        # PCA first: its cubature's element count caps the adaptive ROM's
        alrom_scene "$obj" "$sc" "$pca"
        "$ROMKIT" build "$base.json" --entry 0 -o "$base.pca.rombin" --report "$base.pca.build.json" --quiet
        cap=$("$JSONQ" get "$base.pca.build.json" cubature.elements)
        entries="$pca,
 {\"method\": \"adaptive_linear\", \"decoder\": \"quadratic_pod\", \"size\": 16, \"history\": 20, \"lambda\": 0.2, \"name\": \"adaptive\",
  \"cubature\": {\"tolerance\": 0.01, \"max_points\": $cap}, \"training\": [$train]}"
        names="pca adaptive"
        if [ $crom = 1 ]; then
            entries="$entries,
 {\"method\": \"adaptive_linear\", \"decoder\": \"crom\", \"size\": 16, \"history\": 20, \"lambda\": 0.2, \"name\": \"crom\",
  \"cubature\": {\"tolerance\": 0.01}, \"training\": [$train]}"
            names="$names crom"
        fi
        alrom_json "$obj" "$sc" "$entries"
        alrom_assets "$obj" "$sc" "$names"
        while IFS=, read -r asset us lo hi ratio its; do
            name=$(echo "$asset" | sed 's/.*\.\([a-z]*\)\.rombin/\1/')
            err=$("$JSONQ" get "$base.$name.run.json" reference.relative_error)
            stored=$("$JSONQ" get "$base.$name.build.json" asset.stored_vertices)
            elements=$("$JSONQ" get "$base.$name.build.json" cubature.elements)
            split=$(OPENBLAS_NUM_THREADS=1 "$BUILD/bench_alrom_split" "$base.$name.rombin" "$steps" 3 |
                awk -v us="$us" '{printf "%.4g,%.4g,%.4g,%.4g,%.4g", $1 * us, $2 * us, $3 * us, $4 * us, $5 * us}')
            echo "$obj,$sc,$name,$us,$lo,$hi,$ratio,$its,$err,$stored,$elements,$split" >>"$csv.tmp"
        done <"$base.times"
        [ $crom = 1 ] || echo "$obj,$sc,crom,,,,,,,,,,,,," >>"$csv.tmp"
    done
done
mv "$csv.tmp" "$csv"
echo "$csv"
cat "$csv"
