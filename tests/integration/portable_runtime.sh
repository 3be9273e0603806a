# tests/run.sh: make-lock (this script runs make in the shared build folder)
# The shipped runtime runs on any x86-64: a default build (no NATIVE=1) of libromrt.so and of the
# static libromrt.a has no AVX or FMA instruction (no ymm/zmm register, no vfmadd, no VEX-encoded
# v-prefixed arithmetic), so an installed library cannot die with an illegal instruction on an
# older CPU. On another architecture there is nothing to check: skip.
. tests/lib.sh
B=${ROMKIT_BUILD:-build}
case $(uname -m) in
    x86_64|amd64) ;;
    *) echo "skip portable_runtime: $(uname -m) is not x86-64"; exit 0 ;;
esac
if ! command -v objdump >/dev/null 2>&1; then
    echo "skip portable_runtime: objdump not found (binutils)"
    exit 0
fi
if [ -n "${RT_ARCH:-}${NATIVE:-}" ]; then
    echo "skip portable_runtime: RT_ARCH/NATIVE set in the environment ('${RT_ARCH:-}${NATIVE:-}'): not the default build"
    exit 0
fi
V=$(sed -n 's/^#define ROMRT_VERSION_\(MAJOR\|MINOR\|PATCH\) \([0-9][0-9]*\)$/\2/p' runtime/romrt.h | tr '\n' . | sed 's/\.$//')
# Built with the default flags, as make install ships them (a no-op when up to date).
make -s BUILD="$B" "$B/lib/libromrt.so.$V" "$B/lib/libromrt.a" >"$TMP/make" 2>&1 \
    || { fail portable_runtime_builds "$(tail -c 600 "$TMP/make")"; exit 0; }
# avx: any ymm/zmm operand, FMA, or an AVX-only VEX form of an SSE op (vaddps, vmulss, ...).
avx='%[yz]mm[0-9]|[[:space:]]vfn?m(add|sub)|[[:space:]]v(add|sub|mul|div|sqrt|max|min|and|or|xor|broadcast|perm|insert|extract|cvt|mov|unpck|shuf|blend|pxor|padd|pmul)[a-z0-9]*[[:space:]]'
for lib in "$B/lib/libromrt.so.$V" "$B/lib/libromrt.a"; do
    name=$(basename "$lib")
    objdump -d --no-show-raw-insn "$lib" >"$TMP/dis" 2>"$TMP/err" || { fail "portable_${name}_disassembles" "$(cat "$TMP/err")"; continue; }
    n=$(grep -cE '^ +[0-9a-f]+:' "$TMP/dis")
    if [ "$n" -lt 1000 ]; then fail "portable_${name}_disassembles" "only $n instructions"; continue; fi
    bad=$(grep -E "$avx" "$TMP/dis" | head -n 3)
    if [ -z "$bad" ]; then ok "portable_${name}_has_no_avx_or_fma ($n instructions)"
    else fail "portable_${name}_has_no_avx_or_fma" "$(grep -cE "$avx" "$TMP/dis") AVX/FMA instructions, first: $bad"; fi
done
# The check can fail: the same scan finds AVX in a translation unit built with -mavx2 -mfma.
if printf 'float f(const float *a, const float *b, int n) { float s = 0; for (int i = 0; i < n; i++) s += a[i] * b[i]; return s; }\n' >"$TMP/k.c" &&
    ${CC:-cc} -std=c99 -O3 -mavx2 -mfma -ffast-math -c "$TMP/k.c" -o "$TMP/k.o" 2>"$TMP/err"; then
    objdump -d "$TMP/k.o" | grep -qE "$avx" && ok portable_scan_finds_avx_in_an_avx_object \
        || fail portable_scan_finds_avx_in_an_avx_object "no AVX found in an -mavx2 -mfma object"
else
    fail portable_scan_finds_avx_in_an_avx_object "$(cat "$TMP/err")"
fi
