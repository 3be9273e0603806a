# tests/run.sh: make-lock (this script runs make in the shared build folder)
# A short fuzz run of every libFuzzer target (tests/fuzz/fuzz.mk): each target first replays its
# regression inputs (tests/fuzz/regressions/<target>/: inputs that once crashed it), then fuzzes
# for FUZZ_SHORT_SECONDS (3) from its seeds, so CI catches a reader or runtime change that the
# fuzzer finds in seconds. One ok/FAIL line per target and step; make fuzz runs the long campaign.
# Skips, saying why, when clang's libFuzzer is absent (ROMKIT_NO_SKIP=1 turns that into a FAIL).
. tests/lib.sh
B=${ROMKIT_BUILD:-build}
S=${FUZZ_SHORT_SECONDS:-3}
FCC=${FUZZ_CC:-clang}
R=tests/fuzz/regressions

printf 'int LLVMFuzzerTestOneInput(const unsigned char *d, unsigned long n) { return d && n ? 0 : 0; }\n' >"$TMP/probe.c"
if ! "$FCC" -fsanitize=fuzzer "$TMP/probe.c" -o "$TMP/probe" >"$TMP/probe.err" 2>&1; then
    echo "skip fuzz_short: $FCC cannot link libFuzzer (Debian: clang libclang-rt-14-dev, sh tools/install-deps.sh test): $(head -c 200 "$TMP/probe.err")"
    exit 0
fi
# The fuzz build takes its own flags; the sanitizer build's SANFLAGS must not reach it.
if env -u SANFLAGS make -s -j2 BUILD="$B" fuzz-targets >"$TMP/make" 2>&1; then
    ok fuzz_targets_build
else
    fail fuzz_targets_build "$(tail -c 800 "$TMP/make")"
    exit 0
fi

# fuzz NAME BINARY MAXLEN SEEDS...: S seconds from the seeds; "ok fuzz_short_NAME (N inputs)".
fuzz() {
    name=$1; bin=$2; maxlen=$3; shift 3
    mkdir -p "$TMP/corpus-$name"
    "$bin" -max_total_time="$S" -rss_limit_mb=2048 -max_len="$maxlen" -timeout=20 -print_final_stats=1 \
        -artifact_prefix="$TMP/crash-$name-" "$TMP/corpus-$name" "$@" >"$TMP/log-$name" 2>&1
    rc=$?
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$TMP/log-$name")
    if [ "$rc" -eq 0 ] && [ -n "$runs" ] && [ "$runs" -gt 0 ]; then
        ok "fuzz_short_$name ($runs inputs in $S s)"
    else
        fail "fuzz_short_$name" "exit $rc after ${runs:-no} inputs; input kept as $(ls "$TMP"/crash-"$name"-* 2>/dev/null | head -n 1): $(grep -m3 'ERROR\|runtime error\|contract broken' "$TMP/log-$name") $(tail -c 600 "$TMP/log-$name")"
    fi
}
# regress NAME CMD...: each regression input of NAME (a file argument: libFuzzer runs it once)
# goes through CMD without a crash.
regress() {
    name=$1; shift
    [ -d "$R/$name" ] && [ -n "$(ls "$R/$name")" ] || return 0
    if "$@" "$R/$name"/* >"$TMP/reg-$name" 2>&1; then ok "fuzz_regressions_$name ($(ls "$R/$name" | wc -l) inputs)"
    else fail "fuzz_regressions_$name" "$(grep -m3 'ERROR\|runtime error\|contract broken' "$TMP/reg-$name") $(tail -c 600 "$TMP/reg-$name")"; fi
}

# The runtime: its seeds are assets built from the fuzz scenes (a reduced model, a Koopman operator,
# a skinning basis, a point cloud), as make fuzz builds them.
mkdir -p "$TMP/seeds-open-step"
for kind in scene koopman skinning points; do
    "$ROMKIT" build tests/fuzz/seed_$kind.json -o "$TMP/seeds-open-step/$kind.rombin" --quiet >"$TMP/out" 2>&1 \
        || fail "fuzz_seed_builds_$kind" "$(tail -c 400 "$TMP/out")"
done
regress open-step "$B/fuzz/replay-san"
max=$(wc -c "$TMP"/seeds-open-step/* | sort -n | tail -n 2 | head -n 1 | awk '{print $1}')
fuzz open-step "$B/fuzz/fuzz-open-step" $((2 * max)) "$TMP/seeds-open-step"

# The readers write each input to a file: in this test's own folder.
export FUZZ_TMPDIR="$TMP"
for t in gmsh medit tetgen vtk obj off stl ply gltf splats points scene; do
    regress "$t" "$B/fuzz/fuzz-read-$t"
    fuzz "$t" "$B/fuzz/fuzz-read-$t" 8192 tests/fuzz/seeds/$t
done
