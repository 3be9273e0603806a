# tests/run.sh: make-lock (this script runs make in the shared build folder)
# The runtime's rules (DESIGN.md): strict C99 in every configuration, only <math.h> <string.h>
# <stdint.h> <stddef.h> <float.h>, no allocation, no stdio, no writable globals.
. tests/lib.sh
B=${ROMKIT_BUILD:-build}
src="runtime/*.c formats/rombin_read.c"
ROOT=$PWD
for cfg in "" "-DROMRT_DOUBLE" "-DROMRT_NO_STRINGS -DROMBIN_NO_MESSAGES" "-DROMRT_MAX_R=8"; do
    name=$(echo "runtime_builds_c99_pedantic$cfg" | tr -c 'A-Za-z0-9_\n' '_')
    rc=0
    for f in $src; do
        ${CC:-cc} -std=c99 -pedantic -Wall -Wextra -Werror -Wshadow $cfg -I"$ROOT" -c "$ROOT/$f" -o "$TMP/o.o" 2>>"$TMP/err.$$" || rc=1
    done
    [ $rc -eq 0 ] && ok "$name" || fail "$name" "$(head -c 600 "$TMP/err.$$")"
    rm -f "$TMP/err.$$"
done
bad=$(grep -h '#include <' runtime/*.c runtime/*.h formats/rombin_read.c formats/rombin_read.h formats/rombin.h physics/physics_impl.h physics/collider_impl.h physics/contact_impl.h physics/contact_ad_impl.h \
      | grep -v -e '<math.h>' -e '<string.h>' -e '<stdint.h>' -e '<stddef.h>' -e '<float.h>')
[ -z "$bad" ] && ok runtime_includes_only_the_allowed_headers || fail runtime_includes_only_the_allowed_headers "$bad"
make -s "$B/lib/libromrt.a" >/dev/null 2>&1
# libm calls allowed: nearbyint (koopman.c's angle reduction) is inlined with SSE4.1 (NATIVE=1) and
# called at the portable default's baseline x86-64.
undefined=$(nm -u "$B/lib/libromrt.a" 2>/dev/null | awk '{print $2}' | sort -u | grep -v -e '^romrt_' -e '^rombin_' -e '^rt_' \
            | grep -v -x -e memcpy -e memset -e memcmp -e memchr -e memmove -e sincosf -e sincos -e strncmp -e strlen -e sqrtf -e logf -e cosf -e sinf -e fabsf \
                         -e sqrt -e log -e cos -e sin -e fabs -e atan2 -e atan2f -e exp -e expm1 -e log1p -e fmod -e nextafter -e nextafterf -e nearbyint -e '__.*' -e _GLOBAL_OFFSET_TABLE_ )
[ -z "$undefined" ] && ok runtime_calls_no_allocator_or_stdio || fail runtime_calls_no_allocator_or_stdio "calls: $undefined"
# Mutable data only: .data and .bss (const pointer tables sit in .data.rel.ro on a PIE host, which
# is read-only after relocation; on the MCU they are in flash).
writable=$(objdump -t "$B/lib/libromrt.a" 2>/dev/null | awk '$4 == ".data" || $4 == ".bss" || $4 == "*COM*" {print $NF}' | grep -v -e '^\.data$' -e '^\.bss$')
[ -z "$writable" ] && ok runtime_has_no_writable_globals || fail runtime_has_no_writable_globals "$writable"
