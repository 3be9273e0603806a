#!/bin/sh
# make bench, issue 37: what the projected volume (rom.volume "projected", the B-bar pressure
# projection) costs in the runtime's step against the pointwise volume, for the same m and the
# same integration. The FreeForm beam's bend (examples/scenes/beam_bend_table.json, nu = 0.45),
# mesh-free skinning eigenmodes at m = 16 and 32, each baked twice (pointwise, projected), once
# with exact integration over the 5,000 grid points and once with a trained cubature (tolerance
# 0.01, trained on the scene's own full-order run); each pair stepped by the float32 runtime in one
# process (bench_assets: interleaved rounds of 40 steps from rest, medians and spread), so the
# ratio projected / pointwise holds on a noisy machine.
# Writes bench/results/volume_step.csv (m, integration, volume, points, us_per_step, us_min, us_max,
# ratio_to_pointwise, newton_iterations, asset_bytes).
set -e
BUILD=${BUILD:-build}
OUT=${1:-bench/results}
ROMKIT=$BUILD/romkit
JSONQ=$BUILD/jsonq
for tool in "$ROMKIT" "$JSONQ" "$BUILD/bench_assets"; do
    [ -x "$tool" ] || { echo "volume_step.sh: $tool is not built (make $tool)" >&2; exit 1; }
done
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
mkdir -p "$OUT"
SCENE=examples/scenes/beam_bend_table.json
OPENBLAS_NUM_THREADS=1 "$ROMKIT" fom "$SCENE" --snapshots "$TMP/bend.npy" --quiet
# One scene per integration: the table's mesh-free entries at m = 16 and 32, pointwise and projected.
for integ in exact cubature; do
    python3 - "$SCENE" "$integ" "$TMP/$integ.json" <<'EOF'
import json, sys
s = json.load(open(sys.argv[1]))
rom = []
for k in (2, 12, 3, 13):  # the table's mesh-free entries: m = 16 pointwise, projected; m = 32 the same
    e = dict(s["rom"][k])
    e.pop("reference", None)
    e.setdefault("volume", "pointwise")  # the scene marks its pointwise rows; the default is projected
    e["name"] = "m%d-%s" % (e["size"], e["volume"])
    if sys.argv[2] == "cubature":
        e["cubature"] = {"tolerance": 0.01}
    rom.append(e)
s["rom"] = rom
json.dump(s, open(sys.argv[3], "w"), indent=1)
EOF
done
echo "m,integration,volume,points,us_per_step,us_min,us_max,ratio_to_pointwise,newton_iterations,asset_bytes" >"$OUT/volume_step.csv"
for integ in exact cubature; do
    for k in 0 1 2 3; do
        "$ROMKIT" build "$TMP/$integ.json" --entry $k --training "$TMP/bend.npy" -o "$TMP/$integ.$k.rombin" \
            --report "$TMP/$integ.$k.json" --quiet >/dev/null 2>&1
    done
    for pair in "0 1" "2 3"; do
        set -- $pair
        OPENBLAS_NUM_THREADS=1 "$BUILD/bench_assets" 40 7 "$TMP/$integ.$1.rombin" "$TMP/$integ.$2.rombin" >"$TMP/raw"
        tail -n +2 "$TMP/raw" >"$TMP/times" # (a pipe would hide bench_assets failing)
        k=$1
        while IFS=, read -r asset us lo hi ratio its; do
            m=$([ "$k" -lt 2 ] && echo 16 || echo 32)
            volume=$([ $((k % 2)) -eq 0 ] && echo pointwise || echo projected)
            points=$("$JSONQ" get "$TMP/$integ.$k.json" cubature.elements)
            bytes=$(wc -c <"$TMP/$integ.$k.rombin")
            echo "$m,$integ,$volume,$points,$us,$lo,$hi,$ratio,$its,$bytes" >>"$OUT/volume_step.csv"
            k=$((k + 1))
        done <"$TMP/times"
    done
done
echo "$OUT/volume_step.csv"
cat "$OUT/volume_step.csv"
