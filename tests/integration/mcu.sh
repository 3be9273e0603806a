# tests/run.sh: make-lock (this script runs make in the shared build folder)
# The runtime on a Cortex-M4F: `make mcu` cross-compiles it with the asset of
# tests/mcu/scene.json in flash, runs it under qemu (MPS2-AN386, -icount) and on the host, and
# compares the two (tests/mcu/compare.sh writes $BUILD/mcu/mcu.json).
. tests/lib.sh
BUILD=${ROMKIT_BUILD:-build}
missing=""
for t in arm-none-eabi-gcc qemu-system-arm xxd; do
    command -v $t >/dev/null 2>&1 || missing="$missing $t"
done
if [ -n "$missing" ]; then
    echo "skip mcu: missing$missing (sh tools/install-deps.sh test, as root)"
    exit 0
fi

# mcu_run NAME SCENE DIR: one scene on the MCU and the host, its three checks.
mcu_run() {
    name=$1; scene=$2; dir=$3
    rm -f "$dir/mcu.json" "$dir/qemu.rc"
    make -s mcu BUILD="$BUILD" MCU_SCENE="$scene" MCU_DIR="$dir" >"$TMP/out" 2>&1
    rc=$?
    if [ "$(cat "$dir/qemu.rc" 2>/dev/null)" = 0 ] && grep -q '^x ' "$dir/qemu.txt"; then
        ok ${name}_qemu_run_completes
    else
        fail ${name}_qemu_run_completes "$(grep -m1 '^error' "$dir/qemu.txt" 2>/dev/null || tail -n 5 "$TMP/out")"
    fi
    relative=$(json_num "$dir/mcu.json" max_relative_difference 2>/dev/null)
    if [ $rc -eq 0 ] && [ -n "$relative" ] && awk -v e="$relative" 'BEGIN { exit !(e <= 1e-4) }'; then
        ok "${name}_agrees_with_host ($(printf '%.3g' "$relative") of the largest displacement)"
    else
        fail ${name}_agrees_with_host "make mcu exited with $rc, relative difference '$relative': $(grep FAIL "$TMP/out" | head -n 3)"
    fi
    median=$(json_num "$dir/mcu.json" instructions_per_step_median 2>/dev/null)
    if [ -n "$median" ] && [ "$median" -gt 0 ] 2>/dev/null; then
        ok "${name}_instructions_per_step_measured ($median per step, median)"
    else
        fail ${name}_instructions_per_step_measured "median '$median'"
    fi
}

mcu_run mcu tests/mcu/scene.json "$BUILD/mcu"
mcu_run mcu_koopman tests/mcu/koopman.json "$BUILD/mcu-koopman"
