# romkit track and romkit dmd --tracks (koopman-dmd-log-linear paper, Sec. 7.5, learning from
# video): a cantilever released under gravity (romkit fom, 1 s) carries 14 dark dots painted at
# surface vertices of its front and top faces; tests/tools/render_dots films them from two
# calibrated views (320 x 240, textured and shaded, 101 frames each); romkit track finds and follows
# the dots; romkit dmd --tracks lifts them onto the rest surface, fits 12 linear modes per frame
# and DMD on the modal coordinates; the runtime steps the asset against the full-order run at
# every vertex, beside the same fit from the exact 3D tracks of the same vertices (--markers).
. tests/lib.sh
RENDER=${ROMKIT_BUILD:-build}/render_dots
[ -x "$RENDER" ] || { fail track_renderer "no $RENDER (make all builds it)"; exit 0; }
g3() { if [ -n "$1" ]; then printf '%.3g' "$1"; else printf '?'; fi; }

cat >"$TMP/beam.json" <<'JSON'
{
  "objects": [{
    "mesh": {"box": {"size": [1.0, 0.1, 0.1], "cells": [10, 2, 2]}},
    "material": {"model": "neohookean", "young": 1e7, "poisson": 0.3, "density": 1000},
    "fixed": [{"box": [[-0.01, -1, -1], [0.01, 1, 1]]}]
  }],
  "gravity": [0, -9.81, 0],
  "damping": {"mass": 0.2},
  "time": {"step": 0.01, "duration": 1.0}
}
JSON
# Two views from above and in front, 0.6 m apart (x_cam = R X + t, pixel = K x_cam / z), each
# with its frames.
cat >"$TMP/cams.json" <<JSON
{"views": [
 {"name": "left", "frames": "$TMP/video/cam0/%04d.png", "K": [[330, 0, 159.5], [0, 330, 119.5], [0, 0, 1]], "size": [320, 240],
  "R": [[0.964763821238, 0.0, 0.263117405792], [-0.154853561091, -0.8084724073, 0.567796390665],
        [0.212723162463, -0.588534082815, -0.779984929032]], "t": [-0.495537780908, -0.015640831572, 1.295838598005]},
 {"name": "right", "frames": "$TMP/video/cam1/%04d.png", "K": [[330, 0, 159.5], [0, 330, 119.5], [0, 0, 1]], "size": [320, 240],
  "R": [[0.964763821238, 0.0, -0.263117405792], [0.154853561091, -0.8084724073, 0.567796390665],
        [-0.212723162463, -0.588534082815, -0.779984929032]], "t": [-0.469226040329, -0.170494392662, 1.508561760468]}
]}
JSON
"$ROMKIT" fom "$TMP/beam.json" --snapshots "$TMP/S.npy" --quiet >/dev/null 2>&1 || fail track_fom_run "romkit fom failed"
# Vertices v = i + 11 (j + 3 k) of the 10 x 2 x 2 box: the front face (k = 2) at mid height
# (j = 1) at x = 0.1 ... 0.9; the top face (j = 2) along its middle (k = 1) at x = 0.1, 0.3, 0.5,
# 0.7, 0.9. Dots of radius 2 cm, away from the faces' edges. Measured (relative error against the
# full-order run): 14 dots 1.2%, their exact 3D tracks 0.82%; with 9 of them 1.6% against 0.81%
# (the tracks' 0.05 px of noise, amplified by the fit of 12 modes to few points; the projected
# truth as tracks gives the exact tracks' error to every digit: the lift adds nothing).
VERTS="78 79 80 81 82 83 84 85 86 56 58 60 62 64"
for v in $VERTS; do echo $v; done >"$TMP/V.txt"
BOX="--box 1,0.1,0.1 --cells 10,2,2 --cameras $TMP/cams.json --dots $TMP/V.txt --radius 0.02"
"$RENDER" --snapshots "$TMP/S.npy" $BOX --out "$TMP/video" >/dev/null 2>"$TMP/err" || fail track_render "$(cat "$TMP/err")"

T=101
if "$ROMKIT" track --cameras "$TMP/cams.json" --frames $T -o "$TMP/tracks.json" --quiet >"$TMP/out" 2>"$TMP/err"; then
    sed 's/^/# /' "$TMP/out"
    json_checks track_file_keys "$TMP/tracks.json" frames=$T views[1].size[0]=320 views[0].dots.found=14 \
        views[1].dots.found=14 views[0].lost=0 views[1].lost=0 "views[0].tracks[13].xy[$((2 * T - 1))]" \
        cameras.views[1].name='"right"' cameras.views[0].size[1]=240
else
    fail track_file_keys "$(cat "$TMP/err")"
fi
# every dot found in frame 0 within 0.5 px of its projected vertex, in both views
"$RENDER" --snapshots "$TMP/S.npy" $BOX --check "$TMP/tracks.json" >"$TMP/check" 2>&1 && ok track_dots_within_half_a_pixel \
    || fail track_dots_within_half_a_pixel "$(cat "$TMP/check")"
sed 's/^/# /' "$TMP/check"

set -- --scene "$TMP/beam.json" --modes 12 --dt 0.01 --from-rest --gravity 0,-9.81,0 --quiet
# DESIGN.md's form: a cameras file without names or sizes, with "dt"; no --frames (the files there),
# no --modes (12) and no --dt (the cameras'): the same asset as the explicit commands make.
sed 's/"name": "[a-z]*", //; s/, "size": \[320, 240\],/,/; s/^]}$/], "dt": 0.01}/' "$TMP/cams.json" >"$TMP/design.json"
if "$ROMKIT" track --cameras "$TMP/design.json" -o "$TMP/tracks_d.json" --quiet >/dev/null 2>"$TMP/err" \
    && "$ROMKIT" dmd --tracks "$TMP/tracks_d.json" --scene "$TMP/beam.json" --from-rest --gravity 0,-9.81,0 --quiet \
        -o "$TMP/vd.rombin" >/dev/null 2>>"$TMP/err" \
    && "$ROMKIT" dmd --tracks "$TMP/tracks.json" "$@" -o "$TMP/ve.rombin" >/dev/null 2>>"$TMP/err" \
    && cmp -s "$TMP/vd.rombin" "$TMP/ve.rombin"; then ok track_design_form_gives_the_same_asset
else fail track_design_form_gives_the_same_asset "$(grep -c dt "$TMP/design.json") dt; $(tail -c 400 "$TMP/err")"; fi
# the tracks carry their cameras: no --cameras
if "$ROMKIT" dmd --tracks "$TMP/tracks.json" "$@" -o "$TMP/v.rombin" --report "$TMP/v.json" >"$TMP/out" 2>"$TMP/err"; then
    echo "# $(cat "$TMP/out")"
    json_checks track_lift_report "$TMP/v.json" markers.count=14 markers.video.triangulated=14 markers.video.matched=14 \
        markers.video.single_view=0 markers.video.lost=0 markers.video.dots[1]=14 markers.video.reprojection_rms_px
    r=$(json_num "$TMP/v.json" markers.video.reprojection_max_px)
    below "$r" 0.5 && ok track_reprojection_below_half_a_pixel || fail track_reprojection_below_half_a_pixel "max $r px"
    "$ROMKIT" run "$TMP/v.rombin" --steps $((T - 1)) --reference "$TMP/S.npy" --report "$TMP/rv.json" --quiet >/dev/null 2>&1
    e=$(json_num "$TMP/rv.json" reference.relative_error)
    below "$e" 0.05 && ok track_video_asset_follows_the_full_order_run \
        || fail track_video_asset_follows_the_full_order_run "relative error $e (limit 0.05)"
    # the same fit from the exact 3D tracks of the same vertices
    "$ROMKIT" dmd --markers "$TMP/S.npy" --marker-vertices "$TMP/V.txt" "$@" -o "$TMP/x.rombin" >/dev/null 2>&1
    "$ROMKIT" run "$TMP/x.rombin" --steps $((T - 1)) --reference "$TMP/S.npy" --report "$TMP/rx.json" --quiet >/dev/null 2>&1
    f=$(json_num "$TMP/rx.json" reference.relative_error)
    below "$e" "$(awk -v f="$f" 'BEGIN { print 2 * f }')" && ok track_video_within_twice_exact_tracks \
        || fail track_video_within_twice_exact_tracks "video $e, exact 3D tracks $f"
    # the projected truth as tracks (a perfect tracker): the lift then gives the exact tracks' fit
    "$RENDER" --snapshots "$TMP/S.npy" $BOX --truth "$TMP/truth.json" >/dev/null 2>&1
    "$ROMKIT" dmd --tracks "$TMP/truth.json" --cameras "$TMP/cams.json" "$@" -o "$TMP/p.rombin" >/dev/null 2>&1
    "$ROMKIT" run "$TMP/p.rombin" --steps $((T - 1)) --reference "$TMP/S.npy" --report "$TMP/rp.json" --quiet >/dev/null 2>&1
    p=$(json_num "$TMP/rp.json" reference.relative_error)
    awk -v p="$p" -v f="$f" 'BEGIN { exit !(p != "" && f != "" && (p - f) ^ 2 <= (1e-6 * f) ^ 2) }' \
        && ok track_lift_of_perfect_tracks_is_the_exact_fit || fail track_lift_of_perfect_tracks_is_the_exact_fit "$p against $f"
    echo "# romkit run against the full-order run, relative error: 14 filmed dots on 12 modes $(g3 "$e"), the exact 3D tracks of the same vertices $(g3 "$f")"
else
    fail track_lift_report "$(cat "$TMP/err")"
fi

# Something passes in front of the right camera from frame 40 on (a flat patch over the image's
# right end, where the tip's dots are): the forward-backward check loses them in that view, and
# the lift drops those markers (one view left gives no depth) and fits the others.
mkdir -p "$TMP/occ" && cp "$TMP"/video/cam1/*.png "$TMP/occ/"
"$RENDER" --occlude "$TMP/occ/%04d.png" --rect 250,0,319,239 --from 40 --frames $T
if "$ROMKIT" track --view "$TMP/video/cam0/%04d.png" --view "$TMP/occ/%04d.png" --frames $T -o "$TMP/to.json" \
        --quiet >/dev/null 2>"$TMP/err" &&
    "$ROMKIT" dmd --tracks "$TMP/to.json" --cameras "$TMP/cams.json" "$@" -o "$TMP/o.rombin" --report "$TMP/o.json" \
        >/dev/null 2>>"$TMP/err"; then
    n=$(json_num "$TMP/to.json" views[1].lost); m=$(json_num "$TMP/o.json" markers.video.lost)
    k=$(json_num "$TMP/o.json" markers.count)
    [ -n "$n" ] && [ "$n" -ge 1 ] && [ "$(json_num "$TMP/to.json" views[0].lost)" = 0 ] && [ "$m" = "$n" ] &&
        [ "$k" = $((14 - n)) ] && ok track_occluded_dots_are_lost_and_dropped \
        || fail track_occluded_dots_are_lost_and_dropped "lost in view 1: $n, markers lost $m, kept $k"
    echo "# occluded from frame 40 in one view: $n dots lost there, $k markers kept"
else
    fail track_occluded_dots_are_lost_and_dropped "$(cat "$TMP/err")"
fi

# Bad input: named (view, frame, file, key), and nothing written.
V0="$TMP/video/cam0/%04d.png"
mkdir -p "$TMP/bad"
cp "$TMP"/video/cam1/*.png "$TMP/bad/"
mv "$TMP/bad/0037.png" "$TMP/bad/0037.moved"
expect_fail track_names_a_missing_frame "view 1, frame 37: $TMP/bad/0037.png: cannot open" "$ROMKIT" track --view "$V0" \
    --view "$TMP/bad/%04d.png" --frames $T -o "$TMP/no.json"
mv "$TMP/bad/0037.moved" "$TMP/bad/0037.png"
head -c 100 "$TMP/bad/0012.png" >"$TMP/bad/cut" && mv "$TMP/bad/cut" "$TMP/bad/0012.png"
expect_fail track_names_an_unreadable_png "view 1, frame 12: $TMP/bad/0012.png: PNG data unreadable" "$ROMKIT" track \
    --view "$V0" --view "$TMP/bad/%04d.png" --frames $T -o "$TMP/no.json"
expect_fail track_names_a_view_without_dots "view 0, frame 0 ($TMP/video/cam0/0000.png): no dots found" "$ROMKIT" track \
    --view "$V0" --frames 3 --threshold 0.02 -o "$TMP/no.json"
expect_fail track_refuses_a_pattern_without_a_number "expected one %d for the frame number" "$ROMKIT" track \
    --view "$TMP/video/cam0/0000.png" --frames 3 -o "$TMP/no.json"
sed 's/0.964763821238, 0.0, 0.263117405792/0.964763821238, 0.1, 0.263117405792/' "$TMP/cams.json" >"$TMP/skew.json"
expect_fail track_names_a_camera_that_is_not_a_rotation "skew.json: views\[0\].R is not a rotation" "$ROMKIT" dmd \
    --tracks "$TMP/tracks.json" --cameras "$TMP/skew.json" "$@" -o "$TMP/no.rombin"
"$ROMKIT" track --view "$V0" --frames 3 -o "$TMP/uncal.json" --quiet >/dev/null 2>&1
expect_fail track_needs_the_cameras "uncal.json carries no cameras (tracked with --view): give --cameras" "$ROMKIT" dmd \
    --tracks "$TMP/uncal.json" "$@" -o "$TMP/no.rombin"
sed 's|"frames": "[^"]*", ||' "$TMP/cams.json" >"$TMP/noframes.json"
expect_fail track_names_a_view_without_frames "noframes.json: views\[0\] has no \"frames\"" "$ROMKIT" track \
    --cameras "$TMP/noframes.json" --frames 3 -o "$TMP/no.json"
expect_fail track_refuses_cameras_that_are_not_rotations "skew.json: views\[0\].R is not a rotation" "$ROMKIT" track \
    --cameras "$TMP/skew.json" --frames 3 -o "$TMP/no.json"
if [ -e "$TMP/no.json" ] || [ -e "$TMP/no.rombin" ] || ls "$TMP" | grep -q '\.tmp\.'; then fail track_no_partial_output "a failure left a file"
else ok track_no_partial_output; fi
