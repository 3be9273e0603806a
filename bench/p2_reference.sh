#!/bin/sh
# make bench-reference: how converged the bend's quadratic-tet reference is (issue 37; Table 1's
# bend is measured against P2 on the table box refined once, "reference": {"order": 2, "refine": 1}).
# Full-order runs of examples/scenes/beam_bend_table.json on quadratic tets (bench_reference run
# ... --order 2) along two chains of 1:8 refinements, each level kept at its chain's level-0
# vertices, and the normalized MSE between consecutive levels there (romkit compare's metric):
#   20x4x4:1   the table box (1,920 tets) -> 15,360: how far the reference is from the level below
#   10x2x2:2   240 -> 1,920 -> 15,360: the rate at which the change falls, a level to the next
# The reference's own distance to the limit is then estimated as its change from the level below
# times 1 / (sqrt(rate) - 1)^2 (a geometric series of changes; the rate is the second chain's).
# Writes $OUT/p2_reference.csv. Levels' frames stay in WORK ($BUILD/p2_reference) and are not run
# again unless FORCE=1. About 40 minutes on 2 cores, most of it the two 15,360-tet levels.
# Environment: BUILD (build), ROMKIT_THREADS (2), WORK, OUT (bench/results), FORCE.
set -eu
BUILD=${BUILD:-build}
TOOL=$BUILD/bench_reference
export ROMKIT_THREADS="${ROMKIT_THREADS:-2}"
WORK=${WORK:-$BUILD/p2_reference}
OUT=${OUT:-bench/results}
SCENE=examples/scenes/beam_bend_table.json
mkdir -p "$WORK" "$OUT"
[ -x "$TOOL" ] || { echo "p2_reference: $TOOL missing (make $TOOL)" >&2; exit 1; }
csv=$WORK/p2_reference.csv.tmp
echo "chain,level,vertices,tets,steps,seconds_total,seconds_per_step,newton_per_step,unconverged_steps,peak_rss_mib,nmse_to_next,max_error_to_next,change_ratio,estimated_nmse_to_limit" >"$csv"
for chain in 20x4x4:1 10x2x2:2; do
    cells=${chain%%:*}; finest=${chain##*:}
    l=0
    while [ "$l" -le "$finest" ]; do
        f=$WORK/$cells.l$l.npy
        if [ -n "${FORCE:-}" ] || [ ! -s "$f" ] || [ ! -s "$f.row" ]; then
            echo "p2_reference: $cells level $l" >&2
            "$TOOL" run "$SCENE" "$l" "$f" --order 2 --cells "$(echo "$cells" | tr x ,)" >"$f.row.tmp"
            mv "$f.row.tmp" "$f.row"
        fi
        l=$((l + 1))
    done
    prev=
    l=0
    while [ "$l" -le "$finest" ]; do
        f=$WORK/$cells.l$l.npy
        next= ratio= est=
        if [ "$l" -lt "$finest" ]; then next=$("$TOOL" nmse "$f" "$WORK/$cells.l$((l + 1)).npy"); fi
        n=${next%%,*}
        if [ -n "$prev" ] && [ -n "$n" ]; then ratio=$(awk -v a="$prev" -v b="$n" 'BEGIN { printf "%.4g", a / b }'); fi
        echo "$cells,$l,$(cat "$f.row"),${next:-,},$ratio," >>"$csv"
        prev=$n
        l=$((l + 1))
    done
done
# the estimate for the table reference (20x4x4 level 1): its change from level 0 over (sqrt(rate) - 1)^2
rate=$(awk -F, '$1 == "10x2x2" && $13 != "" { r = $13 } END { print r }' "$csv")
change=$(awk -F, '$1 == "20x4x4" && $2 == 0 { print $11 }' "$csv")
est=$(awk -v c="$change" -v r="$rate" 'BEGIN { if (c != "" && r > 1) printf "%.3g", c / (sqrt(r) - 1) ^ 2 }')
awk -F, -v OFS=, -v e="$est" 'NR > 1 && $1 == "20x4x4" && $2 == 1 { $14 = e } { print }' "$csv" >"$OUT/p2_reference.csv"
rm -f "$csv"
echo "p2_reference: the table reference (20x4x4 level 1) is about $est from its limit (rate $rate a level)" >&2
