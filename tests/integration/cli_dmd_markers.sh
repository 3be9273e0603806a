# romkit dmd --markers (koopman-dmd-log-linear paper, Sec. 7.5, learning from video): six tracked
# vertices of a cantilever released under gravity (romkit fom's run, 1.5 s), lifted to every vertex
# through the scene's first 12 linear modes, DMD on the modal coordinates, baked, and stepped by
# the runtime against the full-order run at every vertex. Measured: relative error 1.2% (6 markers,
# 12 modes); the same 12 modes fitted to every vertex give 0.74%, DMD on every vertex's
# snapshots 0.69%; 3 markers on 6 modes 42%. Four markers on 12 modes (12 equations for 12
# coordinates) fit the markers exactly and miss elsewhere, 9.8%; --marker-ridge 0.03 (Tikhonov on
# the modes' elastic energy) gives 1.2%.
. tests/lib.sh
g3() { if [ -n "$1" ]; then printf '%.3g' "$1"; else printf '?'; fi; }
# npy_vertices FILE "V..." OUT: the listed vertices' columns of a T x n x 3 file as a T x k x 3 file
# (a tracker's output); the header's shape rewritten in place, padded to the same length.
npy_vertices() {
    hb=$(npy_header_bytes "$1"); old=$(npy_shape "$1")
    case $old in *[0-9],\ *[0-9],\ 3) ;; *) return 1 ;; esac
    T=${old%%,*}; rest=${old#*, }; n=${rest%%,*}; k=$(echo $2 | wc -w)
    from="($old), }"; to="($T, $k, 3), }"
    while [ ${#to} -lt ${#from} ]; do to="$to "; done
    { head -c "$hb" "$1" | LC_ALL=C sed "1s/$from/$to/"; t=0
      while [ $t -lt "$T" ]; do
          for v in $2; do tail -c +$((hb + (t * n + v) * 24 + 1)) "$1" | head -c 24; done
          t=$((t + 1))
      done; } >"$3"
    [ "$(npy_shape "$3")" = "$T, $k, 3" ] && [ "$(wc -c <"$3")" -eq $((hb + T * k * 24)) ]
}

cat >"$TMP/beam.json" <<'JSON'
{
  "objects": [{
    "mesh": {"box": {"size": [1.0, 0.1, 0.1], "cells": [10, 2, 2]}},
    "material": {"model": "neohookean", "young": 1e7, "poisson": 0.3, "density": 1000},
    "fixed": [{"box": [[-0.01, -1, -1], [0.01, 1, 1]]}]
  }],
  "gravity": [0, -9.81, 0],
  "damping": {"mass": 0.2},
  "time": {"step": 0.01, "duration": 1.5}
}
JSON
"$ROMKIT" fom "$TMP/beam.json" --snapshots "$TMP/S.npy" --quiet >/dev/null 2>&1 || fail markers_fom_run "romkit fom failed"
# Vertices v = i + 11 (j + 3 k) of the 10 x 2 x 2 box: the top face (j = 2) at x = 0.3, 0.6, 1 on
# one side, x = 1 on the other, the bottom-side tip corner and the middle of the top far edge.
VERTS="25 28 32 98 65 93"
for v in $VERTS; do echo $v; done >"$TMP/V.txt"
npy_vertices "$TMP/S.npy" "$VERTS" "$TMP/M.npy" && ok markers_file_made || fail markers_file_made "shape '$(npy_shape "$TMP/M.npy")'"
set -- --scene "$TMP/beam.json" --dt 0.01 --from-rest --gravity 0,-9.81,0 --quiet
if "$ROMKIT" dmd --markers "$TMP/M.npy" --marker-vertices "$TMP/V.txt" --modes 12 "$@" -o "$TMP/m.rombin" \
        --report "$TMP/m.json" >"$TMP/out" 2>"$TMP/err"; then
    echo "# $(cat "$TMP/out")"
    json_checks markers_report_keys "$TMP/m.json" markers.count=6 markers.modes=12 markers.frames=151 markers.misfit \
        koopman.rank vertices=99
    # the same markers read out of the full recording (T x n x 3): the same asset, byte for byte
    "$ROMKIT" dmd --markers "$TMP/S.npy" --marker-vertices "$TMP/V.txt" --modes 12 "$@" -o "$TMP/m2.rombin" >/dev/null 2>&1
    cmp -s "$TMP/m.rombin" "$TMP/m2.rombin" && ok markers_from_a_full_recording_are_the_same \
        || fail markers_from_a_full_recording_are_the_same "the two assets differ"
    "$ROMKIT" run "$TMP/m.rombin" --steps 150 --reference "$TMP/S.npy" --report "$TMP/r.json" --quiet >/dev/null 2>&1
    e=$(json_num "$TMP/r.json" reference.relative_error)
    below "$e" 0.02 && ok markers_asset_follows_the_full_order_run || fail markers_asset_follows_the_full_order_run "relative error $e (limit 0.02)"
    # against the same 12 modes fitted to every vertex: six markers lose little
    seq 0 98 >"$TMP/all.txt"
    "$ROMKIT" dmd --markers "$TMP/S.npy" --marker-vertices "$TMP/all.txt" --modes 12 "$@" -o "$TMP/a.rombin" >/dev/null 2>&1
    "$ROMKIT" run "$TMP/a.rombin" --steps 150 --reference "$TMP/S.npy" --report "$TMP/ra.json" --quiet >/dev/null 2>&1
    f=$(json_num "$TMP/ra.json" reference.relative_error)
    below "$e" "$(awk -v f="$f" 'BEGIN { print 2 * f }')" && ok markers_within_twice_every_vertex \
        || fail markers_within_twice_every_vertex "6 markers $e, every vertex $f"
    echo "# romkit run against the full-order run, relative error: 6 markers on 12 modes $(g3 "$e"), every vertex on 12 modes $(g3 "$f")"
else
    fail markers_report_keys "$(cat "$TMP/err")"
fi

# Four markers on 12 modes: without the ridge, with it.
echo "25 32 98 93" | tr ' ' '\n' >"$TMP/V4.txt"
for ridge in 0 0.03; do
    "$ROMKIT" dmd --markers "$TMP/S.npy" --marker-vertices "$TMP/V4.txt" --modes 12 --marker-ridge $ridge "$@" \
        -o "$TMP/r$ridge.rombin" --report "$TMP/r$ridge.json" >/dev/null 2>"$TMP/err" || fail markers_ridge_$ridge "$(cat "$TMP/err")"
    "$ROMKIT" run "$TMP/r$ridge.rombin" --steps 150 --reference "$TMP/S.npy" --report "$TMP/rr$ridge.json" --quiet >/dev/null 2>&1
done
e0=$(json_num "$TMP/rr0.json" reference.relative_error); e3=$(json_num "$TMP/rr0.03.json" reference.relative_error)
echo "# 4 markers on 12 modes, relative error: no ridge $(g3 "$e0"), --marker-ridge 0.03 $(g3 "$e3")"
json_checks markers_report_the_ridge "$TMP/r0.03.json" markers.ridge=0.03 markers.count=4
below 0.05 "$e0" && ok markers_four_on_twelve_overfit_without_a_ridge || fail markers_four_on_twelve_overfit_without_a_ridge "relative error $e0"
below "$e3" 0.02 && ok markers_ridge_recovers_four_on_twelve || fail markers_ridge_recovers_four_on_twelve "relative error $e3 (limit 0.02)"

# Bad input: named (file, line, frame, marker), and nothing written.
printf '25\n28\nx9\n' >"$TMP/bad1.txt"
expect_fail markers_names_a_bad_line "bad1.txt line 3: 'x9' is not a vertex index" "$ROMKIT" dmd --markers "$TMP/M.npy" \
    --marker-vertices "$TMP/bad1.txt" --modes 6 "$@" -o "$TMP/x.rombin"
printf '25\n\n28\n99\n' >"$TMP/bad2.txt"
expect_fail markers_names_a_vertex_out_of_range "bad2.txt line 4: vertex 99 is outside 0..98" "$ROMKIT" dmd \
    --markers "$TMP/M.npy" --marker-vertices "$TMP/bad2.txt" --modes 6 "$@" -o "$TMP/x.rombin"
printf '25\n28\n25\n' >"$TMP/bad3.txt"
expect_fail markers_names_a_repeated_vertex "bad3.txt line 3: vertex 25 is listed twice (line 1)" "$ROMKIT" dmd \
    --markers "$TMP/M.npy" --marker-vertices "$TMP/bad3.txt" --modes 6 "$@" -o "$TMP/x.rombin"
head -n 4 "$TMP/V.txt" >"$TMP/four.txt"
expect_fail markers_names_a_shape_mismatch "shape 151 x 6 x 3 (3 dimensions); expected T x 4 x 3" "$ROMKIT" dmd \
    --markers "$TMP/M.npy" --marker-vertices "$TMP/four.txt" --modes 6 "$@" -o "$TMP/x.rombin"
head -n 2 "$TMP/V.txt" >"$TMP/two.txt"
expect_fail markers_too_few_for_the_modes "2 markers give 6 equations per frame for 12 basis coordinates" "$ROMKIT" dmd \
    --markers "$TMP/S.npy" --marker-vertices "$TMP/two.txt" --modes 12 "$@" -o "$TMP/x.rombin"
# a NaN (little-endian float64) at frame 2, marker 1 (vertex 28), y
cp "$TMP/M.npy" "$TMP/nan.npy"
printf '\000\000\000\000\000\000\370\177' | dd of="$TMP/nan.npy" bs=1 seek=$(($(npy_header_bytes "$TMP/M.npy") + 8 * 40)) \
    conv=notrunc 2>/dev/null
expect_fail markers_names_a_non_finite_value "frame 2, marker 1 (vertex 28) is not finite" "$ROMKIT" dmd \
    --markers "$TMP/nan.npy" --marker-vertices "$TMP/V.txt" --modes 6 "$@" -o "$TMP/x.rombin"
expect_fail markers_refuse_a_negative_ridge "--marker-ridge must be a number in" "$ROMKIT" dmd --markers "$TMP/M.npy" \
    --marker-vertices "$TMP/V.txt" --modes 6 --marker-ridge -1 "$@" -o "$TMP/x.rombin"
expect_fail markers_need_every_option "needs --markers, --marker-vertices, --scene, --modes" "$ROMKIT" dmd \
    --markers "$TMP/M.npy" --modes 6 --dt 0.01 -o "$TMP/x.rombin"
expect_fail markers_refuse_snapshots_too "--snapshots does not go with --markers" "$ROMKIT" dmd --snapshots "$TMP/S.npy" \
    --markers "$TMP/M.npy" --marker-vertices "$TMP/V.txt" --modes 6 "$@" -o "$TMP/x.rombin"
if [ -e "$TMP/x.rombin" ] || ls "$TMP" | grep -q 'x.rombin.tmp'; then fail markers_no_partial_asset "a failed fit left a file"
else ok markers_no_partial_asset; fi
