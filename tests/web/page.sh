#!/bin/sh
# make test-web: the page of make web ($ROMKIT_BUILD/web) in Debian's chromium (tests/web/page.mjs),
# then the same demo asset stepped natively by romkit run: the ms per step of both, side by side.
. tests/lib.sh
BUILD=${ROMKIT_BUILD:-build}
WEB=$BUILD/web
STEPS=100

if [ ! -x /usr/bin/chromium ] || ! command -v node >/dev/null 2>&1; then
    fail web_tools_installed "chromium and node are needed (tools/install-deps.sh installs them)"
    exit 1
fi
if [ ! -f "$WEB/romrt.wasm" ] || [ ! -f "$WEB/rkpm.rombin" ]; then
    fail web_built "no $WEB/romrt.wasm or $WEB/rkpm.rombin: make web builds them"
    exit 1
fi
# For the file picker: a point cloud (the demo has none; RKPM skinning on 81 points, a second to
# bake), and a copy with one byte flipped, which the page must refuse with the runtime's message.
mkdir -p "$TMP/pick"
if ! "$ROMKIT" build tests/fuzz/seed_points.json -o "$TMP/pick/points.rombin" --quiet >/dev/null 2>"$TMP/err"; then
    fail point_cloud_baked "$(head -c 600 "$TMP/err")"
    exit 1
fi
# The same lattice as binary 3DGS splats (tests/web/splats_ply.py), for the page's Gaussian splats.
python3 tests/web/splats_ply.py tests/fuzz/seed_points.ply "$TMP/pick/splats.ply" &&
    sed "s#\"seed_points.ply\"#\"$TMP/pick/splats.ply\"#" tests/fuzz/seed_points.json >"$TMP/pick/splats.json"
if ! "$ROMKIT" build "$TMP/pick/splats.json" -o "$TMP/pick/splats.rombin" --quiet >/dev/null 2>"$TMP/err"; then
    fail splat_cloud_baked "$(head -c 600 "$TMP/err")"
    exit 1
fi
cp "$TMP/pick/points.rombin" "$TMP/pick/damaged.rombin"
printf '\377' | dd of="$TMP/pick/damaged.rombin" bs=1 seek=2000 conv=notrunc 2>/dev/null

# The glTF make web exported (demo.glb: romkit export rkpm.rombin --steps GLTF_STEPS): its frames
# are checked in the page against the native runtime's run of those steps.
GLTF_STEPS=20
if [ ! -f "$WEB/demo.glb" ]; then
    fail web_gltf_built "no $WEB/demo.glb: make web exports it"
    exit 1
fi
if ! "$ROMKIT" run "$WEB/rkpm.rombin" --steps $GLTF_STEPS --snapshots "$TMP/pick/gltf_run.npy" --quiet >/dev/null 2>"$TMP/err"; then
    fail gltf_native_run "$(head -c 600 "$TMP/err")"
    exit 1
fi

WEB_GLTF_STEPS=$GLTF_STEPS WEB_TIMED_STEPS=$STEPS node tests/web/page.mjs "$WEB" "$TMP/pick" "$TMP/browser.json"
[ -f "$WEB/screenshot.png" ] && echo "screenshot: $WEB/screenshot.png"

# The same asset from rest in the native float runtime (the desktop library: -O3, AVX2 and FMA
# where the machine has them), the same number of steps.
if "$ROMKIT" run "$WEB/rkpm.rombin" --steps $STEPS --report "$TMP/native.json" --quiet >/dev/null 2>"$TMP/err" &&
    native=$(json_num "$TMP/native.json" seconds_per_step); then
    ok native_step_time_measured
else
    fail native_step_time_measured "$(head -c 600 "$TMP/err")"
    exit 1
fi
browser=$(json_num "$TMP/browser.json" browser_ms_per_step) || { fail browser_step_time_read "no browser_ms_per_step"; exit 1; }
lo=$(json_num "$TMP/browser.json" browser_ms_per_step_min)
hi=$(json_num "$TMP/browser.json" browser_ms_per_step_max)
shown=$(json_num "$TMP/browser.json" shown)
r=$(json_num "$TMP/browser.json" r)
echo "ms per step, rkpm.rombin (the demo's RKPM model: $shown shown vertices, r = $r), median of the first $STEPS steps from rest:"
awk -v b="$browser" -v lo="$lo" -v hi="$hi" -v n="$native" 'BEGIN {
    printf "  browser (chromium headless, WebAssembly SIMD128): %.1f ms (fastest %.1f, slowest %.1f; the timer ticks in 0.1 ms)\n", b, lo, hi
    printf "  native  (romkit run, the float32 runtime library): %.1f ms\n", n * 1000
    printf "  browser / native: %.1f\n", b / (n * 1000) }'
