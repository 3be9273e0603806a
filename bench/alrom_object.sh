# Sourced by bench_alrom_runtime.sh and bench_alrom_cadence.sh: an object's training runs and test
# scenes of examples/scenes/alrom/ (<object>_train_*.json, <object>_<scene>.json), run at full
# order into $TMP (set by the caller, as are $ROMKIT and $DIR). One place, so the benches train
# their methods on the same frames. SNAPSHOTS=DIR (optional) keeps the full-order runs' snapshot
# files there and reuses those already there (the bunny's eight took 86 s here; for iterating on a
# bench, not for its recorded run).

fix() { sed "s|../../../tests|$PWD/tests|" "$1"; }

# fom SCENE.json OUT.npy NAME: the full-order run, or the copy kept as $SNAPSHOTS/NAME.npy.
fom() {
    if [ -n "$SNAPSHOTS" ] && [ -f "$SNAPSHOTS/$3.npy" ]; then cp "$SNAPSHOTS/$3.npy" "$2"; return; fi
    OPENBLAS_NUM_THREADS=1 "$ROMKIT" fom "$1" --snapshots "$2" --quiet
    if [ -n "$SNAPSHOTS" ]; then mkdir -p "$SNAPSHOTS" && cp "$2" "$SNAPSHOTS/$3.npy"; fi
}

# alrom_train OBJECT: its six training motions at full order; sets $train to the entries' training
# list.
alrom_train() {
    train=""
    for s in "$DIR/$1"_train_*.json; do
        name=$(basename "$s" .json)
        fix "$s" >"$TMP/$name.json"
        fom "$TMP/$name.json" "$TMP/$name.npy" "$name"
        train="${train:+$train, }{\"snapshots\": \"$TMP/$name.npy\"}"
    done
}

# alrom_json OBJECT SCENE ENTRIES: the scene (compress, bend) with rom entries ENTRIES (a JSON
# list's items) as $TMP/OBJECT_SCENE.json; sets $steps to its step count.
alrom_json() {
    fix "$DIR/$1_$2.json" | python3 -c "
import json, sys
s = json.load(sys.stdin)
s['rom'] = json.loads('[' + sys.argv[1] + ']')
json.dump(s, open(sys.argv[2], 'w'))" "$3" "$TMP/$1_$2.json"
    # shellcheck disable=SC2034 # (steps: the caller's)
    steps=$(python3 -c "import json; t = json.load(open('$TMP/$1_$2.json'))['time']; print(round(t['duration'] / t['step']))")
}

# alrom_scene OBJECT SCENE ENTRIES: alrom_json, and the scene's full-order run as
# $TMP/OBJECT_SCENE.ref.npy.
alrom_scene() {
    alrom_json "$@"
    fom "$TMP/$1_$2.json" "$TMP/$1_$2.ref.npy" "$1_$2"
}

# alrom_assets OBJECT SCENE NAMES: the rom entries of $TMP/OBJECT_SCENE.json, in the order NAMES
# names them, each baked into $TMP/OBJECT_SCENE.NAME.rombin (its build report .build.json beside
# it; an asset already there is kept) and free-run against the scene's full-order run (.run.json),
# then all stepped in one process by bench_assets ($steps steps, 7 interleaved rounds) into
# $TMP/OBJECT_SCENE.times; sets $base to $TMP/OBJECT_SCENE.
alrom_assets() {
    base=$TMP/$1_$2 assets="" k=0
    for name in $3; do
        [ -f "$base.$name.rombin" ] ||
            "$ROMKIT" build "$base.json" --entry $k -o "$base.$name.rombin" --report "$base.$name.build.json" --quiet >/dev/null
        "$ROMKIT" run "$base.$name.rombin" --steps "$steps" --reference "$base.ref.npy" \
            --report "$base.$name.run.json" --quiet >/dev/null
        assets="$assets $base.$name.rombin" k=$((k + 1))
    done
    # shellcheck disable=SC2086 # (the assets' paths: mktemp's, no spaces)
    OPENBLAS_NUM_THREADS=1 "$BUILD/bench_assets" "$steps" 7 $assets | tail -n +2 >"$base.times"
}
