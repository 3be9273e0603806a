# tests/run.sh: make-lock (this script runs make in the shared build folder)
# Damaged assets: tests/fuzz/damage writes hundreds of variants of a freshly built asset (in both
# precisions); under ASan/UBSan (replay-san) the runtime must refuse every bad one with a status
# and a message, and open and step the good ones and the asset itself.
. tests/lib.sh
B=${ROMKIT_BUILD:-build}
if make -s BUILD="$B" "$B/fuzz/replay-san" "$B/fuzz/damage" >"$TMP/make" 2>&1; then
    ok damaged_tools_build
else
    fail damaged_tools_build "$(tail -c 600 "$TMP/make")"
    exit 0
fi

# replay MODE PREFIX PATH...: passes replay-san's ok/FAIL lines through, names prefixed with
# PREFIX; a sanitizer abort (no FAIL line of its own) becomes one FAIL with the report's tail.
replay() {
    mode=$1; prefix=$2; shift 2
    "$B/fuzz/replay-san" "$mode" "$@" >"$TMP/replay" 2>&1
    rc=$?
    sed -n "s#^\(ok\|FAIL\) \(rejects\|opens\) #\1 \2 $prefix/#p" "$TMP/replay"
    if [ "$rc" -ne 0 ] && ! grep -q '^FAIL ' "$TMP/replay"; then
        fail "replay_${prefix}_$mode" "exit status $rc after $(grep -c '^ok ' "$TMP/replay") files: $(tail -c 1500 "$TMP/replay")"
    fi
}

# A reduced model (tests/fuzz/seed_scene.json), a Koopman operator (seed_koopman.json), both in
# one asset (seed_both.json), a skinning basis stored as its weights (seed_skinning.json: SKIN, WGHT),
# a point cloud on mesh-free integration points with a projected volume (seed_points.json: IPNT,
# IPMD, GRAD, SPLY, VPRS), and an
# adaptive linear ROM (seed_adaptive.json: ALRH, ALRP, QDRV, VMSS, VLOD, AMOV, AMOT), and one with a
# CROM decoder (seed_crom.json: CRMS, CRMX, CRMW), two objects that collide (seed_objects.json:
# COBJ, OBHD, CEDG, CTRI), and a sphere, capsule, box and moving mesh obstacle (seed_obstacles.json: OBHD, OBJS,
# OBMO, OBVX, OBED, OBTR, OBVN, OBVB, OBIT, CEDG, CTRI), and a lifted moving group (seed_lifted.json: LIFT).
for kind in scene koopman both skinning points adaptive crom objects obstacles lifted; do
for prec in float32 float64; do
    name=$kind-$prec
    seed=$TMP/seed-$name.rombin
    if ! "$ROMKIT" build tests/fuzz/seed_$kind.json -o "$seed" --quiet --precision $prec >"$TMP/out" 2>&1; then
        fail "damaged_seed_builds_$name" "$(tail -c 600 "$TMP/out")"
        continue
    fi
    ok "damaged_seed_builds_$name"
    if ! "$B/fuzz/damage" "$seed" "$TMP/$name" >"$TMP/out" 2>&1; then
        fail "damaged_variants_written_$name" "$(tail -c 600 "$TMP/out")"
        continue
    fi
    n=$(ls "$TMP/$name/bad" | wc -l)
    [ "$n" -ge 50 ] && ok "damaged_at_least_50_bad_variants_$name ($n)" \
        || fail "damaged_at_least_50_bad_variants_$name" "only $n"
    replay --expect-error "$name" "$TMP/$name/bad"
    replay --expect-ok "$name" "$TMP/$name/good" "$seed"
done
done

# Inputs the fuzzer once broke the runtime with (tests/fuzz/regressions/open-step): a damaged one
# must now be refused cleanly; one named opens-* is a valid asset whose calls once broke the runtime
# (fuzz_short.sh replays all of them through the fuzz target's calls), and must open and step.
reg=tests/fuzz/regressions/open-step
replay --expect-error regressions $(ls "$reg"/* | grep -v '/opens-')
replay --expect-ok regressions "$reg"/opens-*
