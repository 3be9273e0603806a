# tests/run.sh: make-lock (this script runs make in the shared build folder)
# The Python binding (bindings/python/romrt.py, ctypes + numpy over build/lib/libromrt.so.*):
# its positions equal the C runtime's bit for bit on the same asset and steps (romkit run
# --snapshots; build/rt_push for pushes; a Koopman asset; the double runtime against romkit-double),
# state, clock and GPU accessors, errors raised with the runtime's message, and the example script
# examples/python/step_asset.py writing OBJ frames. The checks themselves are
# bindings/python/test_romrt.py; this script makes the C side's files.
. tests/lib.sh
B=${ROMKIT_BUILD:-build}
make -s "$B/rt_push" "$B/romkit-double" >/dev/null 2>&1
V=$(sed -n 's/^#define ROMRT_VERSION_\(MAJOR\|MINOR\|PATCH\) \([0-9][0-9]*\)$/\2/p' runtime/romrt.h | tr '\n' . | sed 's/\.$//')
make -s "$B/lib/libromrt.so.$V" "$B/lib/libromrt_double.so.$V" >/dev/null 2>&1
export ROMKIT_BUILD=$B
# A python3 with numpy: $PYTHON, else python3 on PATH, else Debian's (python3-numpy, install-deps.sh).
PY=
for p in ${PYTHON:-} python3 /usr/bin/python3; do
    if command -v "$p" >/dev/null 2>&1 && "$p" -c 'import numpy' >/dev/null 2>&1; then PY=$p; break; fi
done
if [ -z "$PY" ]; then
    echo "skip python_binding: no python3 with numpy (sh tools/install-deps.sh test installs python3-numpy)"
    exit 0
fi
# Sanitized builds: the library is instrumented, and python is not; load the runtime first.
if [ -n "${SANFLAGS:-}" ]; then
    asan=$(${CC:-cc} -print-file-name=libasan.so)
    export LD_PRELOAD="$asan" ASAN_OPTIONS=detect_leaks=0
fi

cat >"$TMP/koop.json" <<'JSON'
{
  "objects": [{
    "mesh": {"box": {"size": [1.0, 0.1, 0.1], "cells": [10, 2, 2]}},
    "material": {"model": "neohookean", "young": 1e6, "poisson": 0.3, "density": 1000},
    "fixed": [{"box": [[-0.01, -1, -1], [0.01, 1, 1]]}]
  }],
  "gravity": [0, -9.81, 0],
  "damping": {"mass": 0.2},
  "time": {"step": 0.01, "duration": 1.0},
  "rom": {"basis": "pod", "size": 12, "koopman": {"rank": 20, "clamp": true},
          "asset": {"groups": [{"name": "tip", "box": [[0.95, -1, -1], [1.1, 1, 1]]}]}}
}
JSON
if "$ROMKIT" build examples/scenes/cantilever_small.json -o "$TMP/beam.rombin" --quiet >"$TMP/out" 2>&1 &&
   "$ROMKIT" run "$TMP/beam.rombin" --steps 30 --snapshots "$TMP/run.npy" --quiet >>"$TMP/out" 2>&1 &&
   "$B/romkit-double" run "$TMP/beam.rombin" --steps 30 --snapshots "$TMP/run_double.npy" --quiet >>"$TMP/out" 2>&1 &&
   "$B/rt_push" "$TMP/beam.rombin" 30 "$TMP/push.raw" tip 0 0 0.05 7 0.1 0 0.02 15 >>"$TMP/out" 2>&1 &&
   "$ROMKIT" build "$TMP/koop.json" -o "$TMP/koop.rombin" --quiet >>"$TMP/out" 2>&1 &&
   "$ROMKIT" run "$TMP/koop.rombin" --steps 25 --snapshots "$TMP/koop.npy" --quiet >>"$TMP/out" 2>&1; then
    ok python_reference_files_made
else
    fail python_reference_files_made "$(tail -c 600 "$TMP/out")"
    exit 0
fi
if "$PY" examples/python/step_asset.py "$TMP/beam.rombin" --steps 12 --out "$TMP/frames" --push tip 0 0 0.05 >"$TMP/ex.out" 2>&1 &&
   grep -q "13 frames" "$TMP/ex.out"; then ok python_example_runs
else fail python_example_runs "$(tail -c 600 "$TMP/ex.out")"; fi
"$PY" bindings/python/test_romrt.py "$TMP" 2>&1
