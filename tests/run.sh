#!/bin/sh
# Runs every unit test executable and integration script, counts "ok"/"FAIL"/"skip" lines and
# prints the closing line "N passed, N failed, N skipped". An executable that crashes or exits
# non-zero without saying FAIL counts as one failure of its own. A test that cannot run here (a
# tool absent) prints "skip NAME: why"; with ROMKIT_NO_SKIP=1 (.ci/run) each skip is a FAIL, so
# CI never passes by skipping.
# Usage: BUILD=build [SUITES="unit integration"] [TIERS="unit validation"] sh tests/run.sh [filter]
# SUITES: unit (the executables $BUILD/tests/test_*) and folders of tests/ whose *.sh run
# (make test: unit integration; make test-web: web).
# TIERS: which tiers of the unit suite's executables run (make test: unit validation; make
# test-unit: unit); a test's tier is its line in tests/tiers, and a test not listed is a unit test.
BUILD=${BUILD:-build}
FILTER=${1:-}
SUITES=${SUITES:-unit integration}
TIERS=${TIERS:-unit validation}
# tier_of NAME: the tier tests/tiers gives NAME (test_x_double: test_x's), else unit.
tier_of() {
    tier=$(awk -v n="${1%_double}" '$1 !~ /^#/ && $2 == n {print $1; exit}' tests/tiers)
    echo "${tier:-unit}"
}
export ROMKIT=${ROMKIT:-$PWD/$BUILD/romkit}
export ROMKIT_BUILD=$BUILD
passed=0
failed=0
skipped=0
log=$(mktemp)
run_one() {
    name=$1; shift
    start=$(date +%s)
    "$@" >"$log" 2>&1
    rc=$?
    cat "$log"
    p=$(grep -c '^ok ' "$log")
    f=$(grep -c '^FAIL ' "$log")
    s=$(grep -c '^skip ' "$log")
    if [ "$s" -gt 0 ] && [ "${ROMKIT_NO_SKIP:-0}" = 1 ]; then
        grep '^skip ' "$log" | sed 's/^skip /FAIL (skipped, ROMKIT_NO_SKIP=1) /'
        f=$((f + s))
        s=0
    fi
    if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then
        echo "FAIL $name: exited with status $rc"
        f=1
    fi
    if [ "$p" -eq 0 ] && [ "$f" -eq 0 ] && [ "$s" -eq 0 ]; then
        echo "FAIL $name: ran no test"
        f=1
    fi
    passed=$((passed + p))
    failed=$((failed + f))
    skipped=$((skipped + s))
    echo "# $name: $p passed, $f failed, $s skipped, $(( $(date +%s) - start )) s"
}
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
            run_one "$(basename "$t")" "$t"
        done
        continue
    fi
    for t in tests/"$suite"/*.sh; do
        [ -f "$t" ] || continue
        case "$t" in *"$FILTER"*) ;; *) continue ;; esac
        run_one "$(basename "$t")" sh "$t"
    done
done
rm -f "$log"
echo "$passed passed, $failed failed, $skipped skipped"
[ "$failed" -eq 0 ]
