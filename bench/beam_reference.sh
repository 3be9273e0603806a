#!/bin/sh
# make bench-reference: how fine the FreeForm beam's full-order reference must be (Table 1). The
# issue: "refine the beam until the reference itself changes by less than a tenth of the error you
# report, and state its size"; the smallest errors Table 1 asks us to report are 2.93e-6 (bend,
# m = 32) and 3.46e-6 (twist, m = 16), so a level is converged when it changes by less than
# THRESHOLD = 3e-7 (normalized MSE) to the next.
#
# Scenes: examples/scenes/beam_bend_table.json (gravity, 1 s) and beam_twist_table.json (720
# degrees in 2 s; since issue 37 with a sideways 1 m/s^2 that picks the buckling mode, which
# bench/results/beam_reference.* predate), as `make paper-table` runs them: h = 0.01 s, backward Euler, neo-Hookean
# E = 5e6, nu = 0.45, rho = 1000. Chains: the box mesh with CELLS cells, then 1:8 refinements of it
# (rk_mesh_refine: what the scene key "reference": {"refine": k} runs), up to the chain's finest
# level. Every level's full-order run is kept at the chain's level-0 vertices (the refined meshes
# number them first), and the normalized MSE between two levels is taken there, over every frame
# (util/util.h's metric, romkit compare's). Default chains (CELLS:FINEST):
#   10x2x2:3   240 -> 1,920 -> 15,360 -> 122,880 tets: three pairs, the rate of convergence
#   20x4x4:3   the table scenes' own mesh (1,920 tets) -> 15,360 -> 122,880 -> 983,040 tets
#   40x8x8:1   the demo's 15,360-tet beam -> 122,880 tets
# (a box's 1:8 refinement is not the box with twice the cells: the same vertices, another tet
# layout, so each chain's levels are meshes of their own).
# A level over PROBE_TETS tets is probed first (PROBE_STEPS steps): when the whole run would take
# longer than BUDGET_S seconds by that estimate (every step at the probe's seconds per Newton
# iteration, with as many iterations per step as the level before took), it is skipped and the
# estimate recorded.
#
# Writes $OUT/beam_reference.csv (one row per level) and $OUT/beam_reference.md. Each level's
# frames and row (and probe) stay in WORK (default $BUILD/beam_reference) and are not run again
# unless FORCE=1: a study cut short goes on where it stopped, and a larger BUDGET_S runs a level
# skipped before.
#
# The nMSE is also taken over the first FIRST_STEPS steps (100: the first second, 360 degrees of the
# twist, whose second half buckles).
#
# Environment: BUILD (build), ROMKIT_THREADS (2), SCENES ("bend twist"), CHAINS, BUDGET_S (3600),
# PROBE_TETS (500000), PROBE_STEPS (3), THRESHOLD (3e-7), FIRST_STEPS (100), WORK, OUT
# (bench/results), FORCE.
set -eu
BUILD=${BUILD:-build}
TOOL=$BUILD/bench_reference
export ROMKIT_THREADS="${ROMKIT_THREADS:-2}"
SCENES=${SCENES:-bend twist}
CHAINS=${CHAINS:-10x2x2:3 20x4x4:3 40x8x8:1}
BUDGET_S=${BUDGET_S:-3600}
PROBE_TETS=${PROBE_TETS:-500000}
PROBE_STEPS=${PROBE_STEPS:-3}
THRESHOLD=${THRESHOLD:-3e-7}
FIRST_STEPS=${FIRST_STEPS:-100}
WORK=${WORK:-$BUILD/beam_reference}
OUT=${OUT:-bench/results}
FORCE=${FORCE:-}
mkdir -p "$WORK" "$OUT"
[ -x "$TOOL" ] || { echo "beam_reference: $TOOL missing (make $TOOL)" >&2; exit 1; }

csv=$WORK/beam_reference.csv.tmp
echo "scene,cells,level,vertices,tets,steps,status,seconds_total,seconds_per_step,newton_per_step,unconverged_steps,peak_rss_mib,coarse_vertices,nmse_to_next,max_error_to_next,nmse_to_finest,max_error_to_finest,first_steps,nmse_to_next_first,max_error_to_next_first" >"$csv"

tets_of() { # tets_of CELLS LEVEL: 6 tets per cell, 8 children per level
    echo "$1" | awk -Fx -v l="$2" '{ t = 6 * $1 * $2 * $3; for (i = 0; i < l; i++) t *= 8; printf "%.0f\n", t }'
}

for scene in $SCENES; do
    file=examples/scenes/beam_${scene}_table.json
    for chain in $CHAINS; do
        cells=${chain%%:*}
        finest=${chain#*:}
        tag=${scene}_$cells
        ran=""  # the levels with frames, in order
        skipped=""  # the level not run: level,probe row,estimated seconds
        level=0
        while [ "$level" -le "$finest" ]; do
            base=$WORK/${tag}_L$level
            if [ -z "$FORCE" ] && [ -s "$base.row" ] && [ -s "$base.npy" ]; then
                echo "# $tag level $level: kept from an earlier run ($(cat "$base.row"))"
                ran="$ran $level"
                level=$((level + 1))
                continue
            fi
            rm -f "$base.row" "$base.npy"
            tets=$(tets_of "$cells" "$level")
            if [ "$level" -gt 0 ] && [ "$tets" -gt "$PROBE_TETS" ]; then
                if [ -z "$FORCE" ] && [ -s "$base.probe" ]; then
                    probe=$(cat "$base.probe")
                else
                    echo "# $tag level $level ($tets tets): probing $PROBE_STEPS steps"
                    "$TOOL" run "$file" "$level" "$base.probe.npy" --cells "$(echo "$cells" | tr x ,)" \
                        --steps "$PROBE_STEPS" >"$base.probe.tmp"
                    mv "$base.probe.tmp" "$base.probe"
                    rm -f "$base.probe.npy"
                    probe=$(cat "$base.probe")
                fi
                # every step at the probe's seconds per Newton iteration, as many iterations per step
                # as the level before took over its whole run (the first steps of the bend take fewer)
                steps=$(cut -d, -f3 "$WORK/${tag}_L0.row")
                newton=$(cut -d, -f6 "$WORK/${tag}_L$((level - 1)).row")
                est=$(echo "$probe" | awk -F, -v n="$steps" -v it="$newton" \
                    '{ printf "%.0f\n", ($4 - $3 * $5) + n * $5 / $6 * it }')
                echo "# $tag level $level: probe $probe; the whole run would take about $est s (budget $BUDGET_S s)"
                if [ "$est" -gt "$BUDGET_S" ]; then
                    skipped="$level,$probe,$est"
                    break
                fi
            fi
            echo "# $tag level $level ($tets tets): running"
            "$TOOL" run "$file" "$level" "$base.npy" --cells "$(echo "$cells" | tr x ,)" >"$base.row.tmp"
            mv "$base.row.tmp" "$base.row"
            echo "# $tag level $level: $(cat "$base.row")"
            ran="$ran $level"
            level=$((level + 1))
        done
        last=$(echo "$ran" | awk '{ print $NF }')
        n0=$(cut -d, -f1 "$WORK/${tag}_L0.row")
        for l in $ran; do
            base=$WORK/${tag}_L$l
            to_next=","
            to_finest=","
            first=","
            if [ "$l" != "$last" ]; then
                to_next=$("$TOOL" nmse "$base.npy" "$WORK/${tag}_L$((l + 1)).npy")
                to_finest=$("$TOOL" nmse "$base.npy" "$WORK/${tag}_L$last.npy")
                first=$("$TOOL" nmse "$base.npy" "$WORK/${tag}_L$((l + 1)).npy" --steps "$FIRST_STEPS")
            fi
            awk -F, -v pre="$scene,$cells,$l" -v post="$n0,$to_next,$to_finest,$FIRST_STEPS,$first" \
                '{ print pre "," $1 "," $2 "," $3 ",run," $4 "," $5 "," $6 "," $7 "," $8 "," post }' "$base.row" >>"$csv"
        done
        if [ -n "$skipped" ]; then
            steps=$(cut -d, -f3 "$WORK/${tag}_L0.row")
            echo "$skipped" | awk -F, -v pre="$scene,$cells" -v n="$steps" -v n0="$n0" -v f="$FIRST_STEPS" \
                '{ print pre "," $1 "," $2 "," $3 "," n ",skipped_estimate," $10 "," $6 "," $7 ",," $9 "," n0 ",,,,," f ",," }' >>"$csv"
        fi
    done
done
mv "$csv" "$OUT/beam_reference.csv"
echo "# wrote $OUT/beam_reference.csv"

# The summary: one table per scene and chain, and which level is converged, over the whole run and
# over its first FIRST_STEPS steps.
cpu=$(awk -F': ' '/model name/ { print $2; exit }' /proc/cpuinfo 2>/dev/null || echo unknown)
{
    echo "# A converged full-order reference for the FreeForm beam (Table 1)"
    echo
    echo "Written by \`bench/beam_reference.sh\` (\`make bench-reference\`) on $(date -u +%Y-%m-%d), $cpu,"
    echo "ROMKIT_THREADS=$ROMKIT_THREADS. The table scenes (\`examples/scenes/beam_{bend,twist}_table.json\`: 5 x 1 x 1 m,"
    echo "E = 5e6 Pa, nu = 0.45, rho = 1000, neo-Hookean, h = 0.01 s, backward Euler; bend: gravity for 1 s;"
    echo "twist: 720 degrees in 2 s) at full order on a box mesh and its 1:8 refinements. nMSE: util's normalized"
    echo "MSE between two levels at the coarsest level's vertices over every frame (mean |x - x'|^2 over the"
    echo "squared bounding-box diagonal, 27 m^2); \"first $FIRST_STEPS\": over the first $FIRST_STEPS steps only. A level"
    echo "is converged when its nMSE to the next is below $THRESHOLD, a tenth of the smallest error Table 1 asks"
    echo "for (2.93e-6, bend m = 32; 3.46e-6, twist m = 16). Seconds: wall time of each level's own run (kept"
    echo "levels keep theirs), load average $(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null) when this was written; on a"
    echo "shared machine they vary with its load. A skipped level's row holds its probe: the estimated seconds,"
    echo "the probe's s/step and Newton/step (its first $PROBE_STEPS steps), its peak memory."
    echo
    awk -F, -v thr="$THRESHOLD" '
        function verdict(k, what, c,    r, m, d, t, j) {
            if ((k, c) in conv) { printf "%s: converged to %s at %s.\n", what, thr, conv[k, c]; return }
            printf "%s: no level studied is converged to %s; the finest pair, %s", what, thr, lastpair[k, c]
            if ((k, c) in prev) {
                r = prev[k, c] / last[k, c]
                printf " (the change %s %.2fx from the pair before", (r > 1 ? "fell" : "grew"), (r > 1 ? r : 1 / r)
                if (r > 1) { # the first level whose change to the next would be below thr at that rate
                    m = 0; d = last[k, c]
                    while (d >= thr && m < 30) { d /= r; m++ }
                    t = lastt[k]; for (j = 0; j < m; j++) t *= 8
                    printf "; at that rate level %d, %.3g tets, would be the first converged", lastl[k] + m, t
                }
                printf ")"
            }
            printf ".\n"
        }
        NR == 1 { next }
        {
            key = $1 " " $2
            if (!(key in seen)) { seen[key] = 1; order[++n] = key }
            rows[key] = rows[key] sprintf("| %s | %s | %s | %s | %.3g | %s | %s | %s | %s | %s | %s |\n", $3, $4, $5,
                $7 == "run" ? sprintf("%.4g", $8) : sprintf("(about %.0f: skipped)", $8), $9, $10, $11,
                $12 == "" ? "" : sprintf("%.0f", $12), $14 == "" ? "-" : sprintf("%.3g", $14),
                $19 == "" ? "-" : sprintf("%.3g", $19), $16 == "" ? "-" : sprintf("%.3g", $16))
            coarse[key] = $13; first[key] = $18
            for (c = 14; c <= 19; c += 5) {
                if ($7 != "run" || $c == "") continue
                if (!((key, c) in conv) && $c + 0 < thr + 0)
                    conv[key, c] = sprintf("level %s (%s tets, %s vertices): nMSE %.3g to level %d", $3, $5, $4, $c, $3 + 1)
                lastpair[key, c] = sprintf("level %s to %d: nMSE %.3g", $3, $3 + 1, $c)
                if ((key, c) in last) prev[key, c] = last[key, c]
                last[key, c] = $c; lastl[key] = $3 + 0; lastt[key] = $5 + 0
            }
        }
        END {
            for (i = 1; i <= n; i++) {
                k = order[i]
                split(k, p, " ")
                printf "## %s, %s cells (errors at its %s vertices)\n\n", p[1], p[2], coarse[k]
                printf "| level | vertices | tets | run s | s/step | Newton/step | unconverged steps | peak MiB | nMSE to next | nMSE to next, first %s | nMSE to finest |\n", first[k]
                print "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
                printf "%s\n", rows[k]
                verdict(k, "Whole run", 14)
                verdict(k, "First " first[k] " steps", 19)
                printf "\n"
            }
        }' "$OUT/beam_reference.csv"
} >"$OUT/beam_reference.md"
echo "# wrote $OUT/beam_reference.md"
