#!/bin/sh
# A fuzz campaign: every libFuzzer target (tests/fuzz/fuzz.mk) in turn for SECONDS each, one
# process at a time (one core), from its seeds and what earlier campaigns left in its corpus
# ($BUILD/fuzz/corpus-NAME). Appends one row per target to OUT (bench/results/fuzz.csv):
#   target, inputs (libFuzzer's executed units), seconds, inputs_per_s, findings (0 or 1: libFuzzer
#   stops at its first finding; the input is kept in $BUILD/fuzz/crashes/), corpus (its size after)
# make results-tables writes docs/results/fuzz.md from it.
#   BUILD=build sh bench/fuzz_campaign.sh SECONDS [OUT] [TARGET...]
set -u
BUILD=${BUILD:-build}
SECONDS_EACH=${1:?usage: fuzz_campaign.sh SECONDS [OUT] [TARGET...]}
OUT=${2:-bench/results/fuzz.csv}
[ $# -ge 2 ] && shift 2 || shift $#
TARGETS=${*:-open-step gmsh medit tetgen vtk obj off stl ply splats points scene}
F=$BUILD/fuzz
# a slow input is a finding past TIMEOUT seconds: more than make fuzz's 20, as a campaign shares
# the machine (an input that takes 1.5 s alone took 25 s at nice 19 beside two builds)
TIMEOUT=${FUZZ_TIMEOUT:-60}
make -s BUILD="$BUILD" fuzz-targets $F/damage "$BUILD/romkit" || exit 1
mkdir -p "$F/crashes" "$(dirname "$OUT")"
[ -f "$OUT" ] || echo "target,inputs,seconds,inputs_per_s,findings,corpus" >"$OUT"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
export FUZZ_TMPDIR=$tmp
for t in $TARGETS; do
    if [ "$t" = open-step ]; then
        # the runtime's seeds: assets of every kind, as make fuzz-run-open-step builds them, without
        # the two-object one (112 kB, 1.5 s an input under ASan: it would take most of the time)
        mkdir -p "$F/corpus-open-step" "$tmp/seeds"
        for k in scene koopman both skinning points adaptive crom; do
            "$BUILD/romkit" build tests/fuzz/seed_$k.json -o "$tmp/seeds/$k.rombin" --quiet >/dev/null || exit 1
        done
        bin=$F/fuzz-open-step; seeds=$tmp/seeds
        maxlen=$((2 * $(wc -c <"$tmp/seeds/points.rombin")))
    else
        bin=$F/fuzz-read-$t; seeds=tests/fuzz/seeds/$t; maxlen=65536
    fi
    mkdir -p "$F/corpus-$t"
    start=$(date +%s)
    "$bin" -max_total_time="$SECONDS_EACH" -rss_limit_mb=2048 -max_len=$maxlen -timeout=$TIMEOUT -print_final_stats=1 \
        -artifact_prefix="$F/crashes/$t-" "$F/corpus-$t" "$seeds" >"$tmp/log" 2>&1
    rc=$?
    secs=$(($(date +%s) - start))
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$tmp/log")
    runs=${runs:-0}
    findings=0
    [ "$rc" -ne 0 ] && findings=1 && cp "$tmp/log" "$F/crashes/$t.log"
    corpus=$(ls "$F/corpus-$t" | wc -l)
    rate=$(awk -v n="$runs" -v s="$secs" 'BEGIN { printf "%.0f", (s > 0 ? n / s : 0) }')
    echo "$t,$runs,$secs,$rate,$findings,$corpus" >>"$OUT"
    echo "fuzz_campaign: $t: $runs inputs in $secs s ($rate/s), findings $findings, corpus $corpus"
done
