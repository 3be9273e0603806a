#!/bin/sh
# compare.sh DIR: the report of `make mcu`. DIR holds romrt-m4.elf and its per-file objects
# (obj/), asset_data.c, and the two runs of tests/mcu/main.c with their exit statuses:
# qemu.txt/qemu.rc (Cortex-M4F) and host.txt/host.rc. Prints code size, arena and asset bytes,
# instructions per step and the largest qemu-host position difference relative to the largest
# displacement; writes DIR/mcu.json. Exits non-zero if a run failed or they disagree > 1e-4.
set -u
d=$1
tol=1e-4
status=0
die() { echo "mcu: FAIL $*"; status=1; }

for run in qemu host; do
    rc=$(cat "$d/$run.rc" 2>/dev/null || echo missing)
    if [ "$rc" != 0 ] || ! grep -q '^x ' "$d/$run.txt" 2>/dev/null; then
        die "$run run exited with status $rc: $(grep -m1 '^error' "$d/$run.txt" 2>/dev/null || tail -n 3 "$d/$run.txt" 2>/dev/null)"
    fi
done

# Code size: text (code + read-only data) of the runtime's own objects, as compiled for the MCU
# (before --gc-sections drops what this harness does not call).
code=$(arm-none-eabi-size "$d"/obj/runtime/*.o "$d/obj/formats/rombin_read.o" 2>/dev/null |
       awk 'NR > 1 { s += $1 } END { print s + 0 }')
# The M4F has a single-precision FPU only: double arithmetic or double libm calls in the runtime
# are emulated in software, many times slower. Not an error, but worth seeing.
soft=$(arm-none-eabi-nm -u "$d"/obj/runtime/*.o "$d/obj/formats/rombin_read.o" 2>/dev/null |
       awk '$2 ~ /^__aeabi_(d|[fil]2d|ui2d|l2d)/ || $2 ~ /^(sqrt|exp|log|pow|sin|cos|tan|atan2|floor|ceil|fabs|fmod)$/ { print $2 }' |
       sort -u | tr '\n' ' ')
asset=$(sed -n 's/.*romkit_asset_len = \([0-9]*\).*/\1/p' "$d/asset_data.c")
val() { sed -n "s/^$1 \([-0-9]*\).*/\1/p" "$d/$2.txt" 2>/dev/null | head -n 1; }
arena=$(val arena_bytes qemu); r=$(val r qemu); steps=$(val steps qemu)
median=$(val step_instructions_median qemu); max=$(val step_instructions_max qemu)
# arena_bytes may differ (pointer sizes of a 32- and a 64-bit machine); the model may not.
for k in r shown steps; do
    [ "$(val $k qemu)" = "$(val $k host)" ] || die "$k differs: qemu $(val $k qemu), host $(val $k host)"
done

# Largest |x_qemu - x_host| over the shown vertices, over the largest |x_host - rest| (host).
rel=$(awk '
    FNR == 1 { f++ }
    f == 1 && $1 == "rest" { rx[$2] = $3; ry[$2] = $4; rz[$2] = $5 }
    f == 1 && $1 == "x"    { hx[$2] = $3; hy[$2] = $4; hz[$2] = $5; nh++ }
    f == 2 && $1 == "x"    { qx[$2] = $3; qy[$2] = $4; qz[$2] = $5; nq++ }
    END {
        if (nh == 0 || nh != nq) { print "nan"; exit }
        for (i in hx) {
            if (!(i in qx)) { print "nan"; exit }
            dx = qx[i] - hx[i]; dy = qy[i] - hy[i]; dz = qz[i] - hz[i]
            e = sqrt(dx * dx + dy * dy + dz * dz); if (e > emax) emax = e
            dx = hx[i] - rx[i]; dy = hy[i] - ry[i]; dz = hz[i] - rz[i]
            u = sqrt(dx * dx + dy * dy + dz * dz); if (u > umax) umax = u
        }
        if (umax == 0) { print "nan"; exit }
        printf "%.3e\n", emax / umax
    }' "$d/host.txt" "$d/qemu.txt" 2>/dev/null)
rel=${rel:-nan}

printf 'mcu: runtime code        %s bytes (text + rodata, Cortex-M4F -Os)\n' "$code"
[ -n "$soft" ] && printf 'mcu: note: the runtime calls double-precision software float: %s\n' "$soft"
printf 'mcu: arena               %s bytes\n' "${arena:-?}"
printf 'mcu: asset               %s bytes (r = %s)\n' "${asset:-?}" "${r:-?}"
printf 'mcu: instructions/step   median %s, max %s (%s steps, qemu -icount)\n' "${median:-?}" "${max:-?}" "${steps:-?}"
printf 'mcu: qemu vs host        %s of the largest displacement (limit %s)\n' "$rel" "$tol"
if [ "$rel" = nan ] || ! awk -v e="$rel" -v t="$tol" 'BEGIN { exit !(e <= t) }'; then
    die "qemu and host positions differ by $rel of the largest displacement (or could not be compared)"
fi
[ -n "$median" ] && [ "$median" -gt 0 ] 2>/dev/null || die "no instruction count measured"

num() { [ -n "$1" ] && [ "$1" != nan ] && echo "$1" || echo null; }
cat >"$d/mcu.json" <<JSON
{
  "code_bytes": $(num "$code"),
  "arena_bytes": $(num "$arena"),
  "asset_bytes": $(num "$asset"),
  "instructions_per_step_median": $(num "$median"),
  "instructions_per_step_max": $(num "$max"),
  "max_relative_difference": $(num "$rel"),
  "steps": $(num "$steps"),
  "r": $(num "$r"),
  "ok": $([ $status = 0 ] && echo true || echo false)
}
JSON
exit $status
