# Sourced by bench_alrom_runtime.sh, bench_alrom_cadence.sh and alrom_freerun.sh: the armadillo's
# training runs and test scenes of examples/scenes/alrom/, run at full order into $TMP (set by the
# caller, as are $ROMKIT and $DIR). One place, so the benches train their methods on the same
# frames. $OBJECT (default armadillo) takes another object's runs of that folder (bunny, octopus).

fix() { sed "s|../../../tests|$PWD/tests|" "$1"; }

# The six training motions at full order; sets $train to the entries' training list.
alrom_train() {
    train=""
    for s in "$DIR"/"${OBJECT:-armadillo}"_train_*.json; do
        name=$(basename "$s" .json)
        fix "$s" >"$TMP/$name.json"
        OPENBLAS_NUM_THREADS=1 "$ROMKIT" fom "$TMP/$name.json" --snapshots "$TMP/$name.npy" --quiet
        train="${train:+$train, }{\"snapshots\": \"$TMP/$name.npy\"}"
    done
}

# Scene $1 (compress, bend) with rom entries $2 (a JSON list's items) as $TMP/$1.json, its full-order
# run as $TMP/$1.ref.npy; sets $steps to its step count.
alrom_scene() {
    fix "$DIR/${OBJECT:-armadillo}_$1.json" | python3 -c "
import json, sys
s = json.load(sys.stdin)
s['rom'] = json.loads('[' + sys.argv[1] + ']')
json.dump(s, open(sys.argv[2], 'w'))" "$2" "$TMP/$1.json"
    OPENBLAS_NUM_THREADS=1 "$ROMKIT" fom "$TMP/$1.json" --snapshots "$TMP/$1.ref.npy" --quiet
    steps=$(python3 -c "import json; t = json.load(open('$TMP/$1.json'))['time']; print(round(t['duration'] / t['step']))")
}
