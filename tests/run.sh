#!/bin/sh
# Runs every unit test executable and integration script, counts "ok"/"FAIL" lines and
# prints the closing line "N passed, N failed". An executable that crashes or exits non-zero
# without saying FAIL counts as one failure of its own.
# Usage: BUILD=build [SUITES="unit integration"] sh tests/run.sh [filter]
# SUITES: unit (the executables $BUILD/tests/test_*) and folders of tests/ whose *.sh run
# (make test: unit integration; make test-web: web).
BUILD=${BUILD:-build}
FILTER=${1:-}
SUITES=${SUITES:-unit integration}
export ROMKIT=${ROMKIT:-$PWD/$BUILD/romkit}
export ROMKIT_BUILD=$BUILD
passed=0
failed=0
log=$(mktemp)
run_one() {
    name=$1; shift
    start=$(date +%s)
    "$@" >"$log" 2>&1
    rc=$?
    cat "$log"
    p=$(grep -c '^ok ' "$log")
    f=$(grep -c '^FAIL ' "$log")
    if [ "$rc" -ne 0 ] && [ "$f" -eq 0 ]; then
        echo "FAIL $name: exited with status $rc"
        f=1
    fi
    if [ "$p" -eq 0 ] && [ "$f" -eq 0 ]; then
        echo "FAIL $name: ran no test"
        f=1
    fi
    passed=$((passed + p))
    failed=$((failed + f))
    echo "# $name: $p passed, $f failed, $(( $(date +%s) - start )) s"
}
for suite in $SUITES; do
    if [ "$suite" = unit ]; then
        for t in "$BUILD"/tests/test_*; do
            case "$t" in *.d) continue ;; esac
            [ -x "$t" ] || continue
            case "$t" in *"$FILTER"*) ;; *) continue ;; esac
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
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]
