# tests/run.sh: make-lock (this script runs make in the shared build folder)
# What an app links against (issue 21): an app compiled with ROMRT_DOUBLE and linked against the
# float runtime (or the other way round) fails to link, naming a romrt_f64_/romrt_f32_ function,
# where the right precision links and runs; the static and shared libraries export romrt.h's
# functions under their link names and nothing else (no rt_*, rombin_*, romrt_phys_*: an app's own
# rt_dot or rombin_open links beside them); the version the header states is the shared library's
# file name and what romrt_version() returns; and the buffer writers (romrt_positions ...) on
# exact-size heap buffers under AddressSanitizer, the runtime's sources built with it here.
. tests/lib.sh
B=${ROMKIT_BUILD:-build}
CC=${CC:-cc}
SAN=${SANFLAGS:-}
make -s "$B/lib/libromrt.a" "$B/lib/libromrt_double.a" >/dev/null 2>&1
V=$(sed -n 's/^#define ROMRT_VERSION_\(MAJOR\|MINOR\|PATCH\) \([0-9][0-9]*\)$/\2/p' runtime/romrt.h | tr '\n' . | sed 's/\.$//')
MAJ=${V%%.*}
make -s "$B/lib/libromrt.so.$V" "$B/lib/libromrt_double.so.$V" >/dev/null 2>&1

# A small app: the version, and a few calls whose arguments' size depends on the precision.
cat >"$TMP/app.c" <<'EOF'
#include <stdio.h>
#include "romrt.h"
int main(void)
{
    romrt_real q[1];
    printf("version %d real %d\n", romrt_version(), (int)sizeof(romrt_real));
    return romrt_reduced_coordinates(NULL, q, 1, NULL) == ROMRT_E_ARGUMENT && romrt_version() == ROMRT_VERSION_NUMBER ? 0 : 1;
}
EOF
# link NAME FLAGS LIB...: compiles and links the app; its output in $TMP/link.err
link() { l_out=$1; l_flags=$2; shift 2; $CC -std=c99 -pedantic -Wall -Wextra -Werror $SAN $l_flags -Iruntime -o "$TMP/$l_out" "$TMP/app.c" "$@" -lm >"$TMP/link.err" 2>&1; }
# The shared libraries under their sonames, as an installed copy has them.
mkdir -p "$TMP/lib"
ln -s "$PWD/$B/lib/libromrt.so.$V" "$TMP/lib/libromrt.so.$MAJ"
ln -s "$PWD/$B/lib/libromrt_double.so.$V" "$TMP/lib/libromrt_double.so.$MAJ"

if link app_double_on_float -DROMRT_DOUBLE "$B/lib/libromrt.a"; then
    fail wrong_precision_fails_to_link_static "an app built with ROMRT_DOUBLE linked against the float library"
elif grep -q "undefined reference to .romrt_f64_" "$TMP/link.err"; then ok wrong_precision_fails_to_link_static
else fail wrong_precision_fails_to_link_static "failed, but not on a romrt_f64_ name: $(head -c 300 "$TMP/link.err")"; fi
if link app_float_on_double "" "$B/lib/libromrt_double.a"; then
    fail float_app_on_double_library_fails_to_link "linked"
elif grep -q "undefined reference to .romrt_f32_" "$TMP/link.err"; then ok float_app_on_double_library_fails_to_link
else fail float_app_on_double_library_fails_to_link "$(head -c 300 "$TMP/link.err")"; fi
if link app_double_on_float_so -DROMRT_DOUBLE "$B/lib/libromrt.so.$V"; then
    fail wrong_precision_fails_to_link_shared "linked against the float shared library"
elif grep -q "undefined reference to .romrt_f64_" "$TMP/link.err"; then ok wrong_precision_fails_to_link_shared
else fail wrong_precision_fails_to_link_shared "$(head -c 300 "$TMP/link.err")"; fi

want="version $(sed -n 's/^#define ROMRT_VERSION_MAJOR //p' runtime/romrt.h)"
for c in "float static:: $B/lib/libromrt.a:4" "double static:-DROMRT_DOUBLE: $B/lib/libromrt_double.a:8" \
         "float shared:: $B/lib/libromrt.so.$V:4" "double shared:-DROMRT_DOUBLE: $B/lib/libromrt_double.so.$V:8"; do
    name=$(echo "${c%%:*}" | tr ' ' _); rest=${c#*:}; flags=${rest%%:*}; rest=${rest#*:}; lib=${rest%:*}; size=${rest##*:}
    if link "app_$name" "$flags" $lib && LD_LIBRARY_PATH=$TMP/lib "$TMP/app_$name" >"$TMP/run.out" 2>&1 \
        && grep -q "real $size\$" "$TMP/run.out"; then ok "right_precision_links_and_runs_$name"
    else fail "right_precision_links_and_runs_$name" "$(head -c 300 "$TMP/link.err") $(cat "$TMP/run.out" 2>/dev/null)"; fi
done

# The version: the header's three numbers are the shared library's file name and soname, and the
# number the library returns (checked by the app above against ROMRT_VERSION_NUMBER).
[ -f "$B/lib/libromrt.so.$V" ] && readelf -d "$B/lib/libromrt.so.$V" | grep -q "SONAME.*\[libromrt\.so\.$MAJ\]" \
    && LD_LIBRARY_PATH=$TMP/lib "$TMP/app_float_shared" | grep -q "^version $(echo "$V" | awk -F. '{print $1 * 10000 + $2 * 100 + $3}') " \
    && ok version_is_the_headers || fail version_is_the_headers "header $V: $(ls "$B/lib" | grep so)"

# Exports: every defined global is a romrt.h function under its link name, and each one is there.
for c in "libromrt.a:f32:" "libromrt_double.a:f64:-DROMRT_DOUBLE" "libromrt.so.$V:f32:" "libromrt_double.so.$V:f64:-DROMRT_DOUBLE"; do
    lib=${c%%:*}; rest=${c#*:}; p=${rest%%:*}; flags=${rest#*:}
    case $lib in *.so.*) nmflags="-D --defined-only" ;; *) nmflags="-g --defined-only" ;; esac
    exported=$(nm $nmflags "$B/lib/$lib" | awk 'NF == 3 && $2 ~ /^[TDBRVW]$/ {sub(/@.*/, "", $3); print $3}' | sort -u)
    declared=$($CC -E -P -x c $flags runtime/romrt.h | grep -o "romrt_${p}_[a-z0-9_]*" | sort -u)
    stray=$(echo "$exported" | grep -v "^romrt_${p}_")
    [ -n "$declared" ] && [ "$exported" = "$declared" ] && ok "exports_only_romrt_h_$(echo "$lib" | tr . _)" \
        || fail "exports_only_romrt_h_$(echo "$lib" | tr . _)" "not declared: $(echo $stray) / declared $(echo "$declared" | wc -l), exported $(echo "$exported" | wc -l)"
done
# Every function romrt.h declares has its precision mapping (a new one without would export a bare name).
bare=$($CC -E -P -x c runtime/romrt.h | grep -o '\bromrt_[a-z0-9_]*[ ]*(' | grep -v '^romrt_f32_' | head -5)
[ -z "$bare" ] && ok every_function_has_a_link_name || fail every_function_has_a_link_name "$bare"
# An app with its own rt_dot and rombin_open links beside the static runtime.
cat >"$TMP/clash.c" <<'EOF'
#include "romrt.h"
int rt_dot(void) { return 1; }
int rombin_open(void) { return 2; }
int romrt_phys_barrier(void) { return 3; }
int main(void) { return rt_dot() + rombin_open() + romrt_phys_barrier() == 6 && romrt_version() > 0 ? 0 : 1; }
EOF
$CC -std=c99 $SAN -Iruntime -o "$TMP/clash" "$TMP/clash.c" "$B/lib/libromrt.a" -lm >"$TMP/link.err" 2>&1 && "$TMP/clash" \
    && ok app_symbols_do_not_clash_with_internals || fail app_symbols_do_not_clash_with_internals "$(head -c 400 "$TMP/link.err")"

# AddressSanitizer: the runtime's sources and tests/tools/rt_capacity.c (exact-size heap buffers).
if "$ROMKIT" build examples/scenes/cantilever_small.json -o "$TMP/a.rombin" --quiet >"$TMP/out" 2>&1; then
    if $CC -std=c99 -O1 -g -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer -I. -Iruntime \
        -o "$TMP/rt_capacity" tests/tools/rt_capacity.c runtime/*.c formats/rombin_read.c -lm >"$TMP/cc.err" 2>&1; then
        ASAN_OPTIONS=detect_leaks=0 "$TMP/rt_capacity" "$TMP/a.rombin" >"$TMP/asan.out" 2>&1
        rc=$?
        grep -E '^(ok|FAIL) ' "$TMP/asan.out"
        [ $rc -eq 0 ] && ! grep -q "ERROR: AddressSanitizer\|runtime error" "$TMP/asan.out" && ok asan_run_clean \
            || fail asan_run_clean "exit $rc: $(grep -A3 'ERROR\|runtime error' "$TMP/asan.out" | head -c 600)"
    else
        fail asan_build "$(head -c 400 "$TMP/cc.err")"
    fi
    # The embed examples' GPU path (X and U once, q per frame) lands where romrt_positions does.
    make -s "$B/embed" "$B/embed_cpp" >/dev/null 2>&1
    for e in embed embed_cpp; do
        "$B/$e" "$TMP/a.rombin" 20 >"$TMP/$e.out" 2>&1
        off=$(sed -n 's/.*\(against romrt_positions:\|shader sum off by\) \([0-9.e+-]*\) m.*/\2/p' "$TMP/$e.out")
        [ -n "$off" ] && awk -v d="$off" 'BEGIN { exit !(d < 1e-6) }' && ok "${e}_gpu_deformation_matches" \
            || fail "${e}_gpu_deformation_matches" "$(cat "$TMP/$e.out")"
    done
else
    fail asan_asset_builds "$(head -c 300 "$TMP/out")"
fi
