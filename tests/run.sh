#!/bin/sh
# Runs every unit test executable and integration script, counts "ok"/"FAIL"/"skip" lines and
# prints the closing line "N passed, N failed, N skipped". An executable that crashes or exits
# non-zero without saying FAIL counts as one failure of its own. A test that cannot run here (a
# tool absent) prints "skip NAME: why"; with ROMKIT_NO_SKIP=1 (.ci/run) each skip is a FAIL, so
# CI never passes by skipping.
# Usage: BUILD=build [SUITES="unit integration"] [TIERS="unit validation"] [JOBS=N] sh tests/run.sh [filter]
# SUITES: unit (the executables $BUILD/tests/test_*) and folders of tests/ whose *.sh run
# (make test: unit integration; make test-web: web).
# TIERS: which tiers of the unit suite's executables run (make test: unit validation; make
# test-unit: unit); a test's tier is its line in tests/tiers, and a test not listed is a unit test.
# JOBS: how many tests run at once (default 1). The tests are single-threaded at heart, so on a
# 2-core machine two at a time take about half the time; each then gets ROMKIT_THREADS (and
# OpenMP/OpenBLAS) of nproc / JOBS, at least 1, unless the caller set them, so the machine is not
# oversubscribed. Each test's output is printed whole, in the usual order, as it completes in turn.
# A script holding the line "# tests/run.sh: make-lock" runs make in the shared build folder: such
# scripts run one at a time (flock on $BUILD/.make-lock), so two never build the same target.
BUILD=${BUILD:-build}
FILTER=${1:-}
SUITES=${SUITES:-unit integration}
TIERS=${TIERS:-unit validation}
JOBS=${JOBS:-1}
case $JOBS in '' | *[!0-9]* | 0) echo "tests/run.sh: JOBS=$JOBS: expected a whole number from 1" >&2; exit 2 ;; esac
# tier_of NAME: the tier tests/tiers gives NAME (test_x_double: test_x's), else unit.
tier_of() {
    tier=$(awk -v n="${1%_double}" '$1 !~ /^#/ && $2 == n {print $1; exit}' tests/tiers)
    echo "${tier:-unit}"
}
export ROMKIT=${ROMKIT:-$PWD/$BUILD/romkit}
export ROMKIT_BUILD=$BUILD
if [ "$JOBS" -gt 1 ]; then
    per=$(( $(nproc 2>/dev/null || echo 1) / JOBS ))
    [ "$per" -ge 1 ] || per=1
    export ROMKIT_THREADS=${ROMKIT_THREADS:-$per} OMP_NUM_THREADS=${OMP_NUM_THREADS:-$per} \
        OPENBLAS_NUM_THREADS=${OPENBLAS_NUM_THREADS:-$per}
fi
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# The job list: one line a test, "NAME KIND PATH" (KIND exe or sh), in the order they are reported.
: >"$work/jobs"
for suite in $SUITES; do
    if [ "$suite" = unit ]; then
        for t in "$BUILD"/tests/test_*; do
            case "$t" in *.d) continue ;; esac
            [ -x "$t" ] || continue
            case "$t" in *"$FILTER"*) ;; *) continue ;; esac
            case " $TIERS " in *" $(tier_of "$(basename "$t")") "*) ;; *) continue ;; esac
            # a build left from a test whose source is gone (moved to bench/, renamed) is not run
            name=$(basename "$t")
            [ -f "tests/unit/${name%_double}.c" ] || continue
            echo "$name exe $t" >>"$work/jobs"
        done
        continue
    fi
    for t in tests/"$suite"/*.sh; do
        [ -f "$t" ] || continue
        case "$t" in *"$FILTER"*) ;; *) continue ;; esac
        echo "$(basename "$t") sh $t" >>"$work/jobs"
    done
done

# run_one N NAME KIND PATH: runs one test; its output and its counts "P F S" go to $work/N.log and
# $work/N.count, and $work/N.done appears when both are written.
run_one() {
    n=$1; name=$2; kind=$3; path=$4
    log=$work/$n.log
    start=$(date +%s)
    if [ "$kind" = exe ]; then "$path" >"$log" 2>&1
    elif grep -q '^# tests/run.sh: make-lock' "$path"; then flock "$BUILD/.make-lock" sh "$path" >"$log" 2>&1
    else sh "$path" >"$log" 2>&1; fi
    rc=$?
    p=$(grep -c '^ok ' "$log")
    f=$(grep -c '^FAIL ' "$log")
    s=$(grep -c '^skip ' "$log")
    if [ "$s" -gt 0 ] && [ "${ROMKIT_NO_SKIP:-0}" = 1 ]; then
        grep '^skip ' "$log" | sed 's/^skip /FAIL (skipped, ROMKIT_NO_SKIP=1) /' >>"$log"
        f=$((f + s))
        s=0
    fi
    if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then
        echo "FAIL $name: exited with status $rc" >>"$log"
        f=1
    fi
    if [ "$p" -eq 0 ] && [ "$f" -eq 0 ] && [ "$s" -eq 0 ]; then
        echo "FAIL $name: ran no test" >>"$log"
        f=1
    fi
    echo "# $name: $p passed, $f failed, $s skipped, $(( $(date +%s) - start )) s" >>"$log"
    echo "$p $f $s" >"$work/$n.count"
    : >"$work/$n.done"
}

total=$(wc -l <"$work/jobs")
# JOBS workers share one counter (under flock): each takes the next test not yet taken, so a long
# test holds up one worker only.
echo 0 >"$work/next"
worker() {
    while :; do
        n=$(flock "$work/next" sh -c 'n=$(cat "$1"); echo $((n + 1)) >"$1"; echo "$n"' sh "$work/next")
        [ "$n" -lt "$total" ] || return 0
        set -- $(sed -n "$((n + 1))p" "$work/jobs")
        run_one "$n" "$1" "$2" "$3"
    done
}
if [ "$JOBS" -gt 1 ]; then
    w=0
    while [ "$w" -lt "$JOBS" ]; do worker & w=$((w + 1)); done
else
    worker &
fi
passed=0
failed=0
skipped=0
n=0
while [ "$n" -lt "$total" ]; do
    while [ ! -f "$work/$n.done" ]; do sleep 0.2; done
    cat "$work/$n.log"
    read -r p f s <"$work/$n.count"
    passed=$((passed + p))
    failed=$((failed + f))
    skipped=$((skipped + s))
    rm -f "$work/$n.log"
    n=$((n + 1))
done
wait
echo "$passed passed, $failed failed, $skipped skipped"
[ "$failed" -eq 0 ]
