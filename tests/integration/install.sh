# tests/run.sh: make-lock (this script runs make in the shared build folder)
# make install into a scratch DESTDIR with a PREFIX that does not exist: the layout, the shared
# library's soname and exports, examples/embed built against the installed copy with
# pkg-config (shared, static, double) stepping an asset exactly as the tree's build does, the
# installed romkit running, nothing written outside DESTDIR, and make uninstall.
. tests/lib.sh
B=${ROMKIT_BUILD:-build}
CC=${CC:-cc}
CXX=${CXX:-c++}
D=$TMP/dest
P=/nonexistent-romkit-prefix-$$
I=$D$P
# The installed .pc files name PREFIX; point pkg-config at the staged copy instead.
pc() { PKG_CONFIG_PATH=$I/lib/pkgconfig PKG_CONFIG_LIBDIR=$I/lib/pkgconfig pkg-config --define-variable=prefix="$I" "$@"; }
# Under make test-sanitize the installed runtime is instrumented: the apps link the sanitizer too.
SAN=${SANFLAGS:-}
# The version the header states (the Makefile reads it from there): the shared library's names.
part() { sed -n "s/^#define ROMRT_VERSION_$1 \([0-9][0-9]*\)\$/\1/p" runtime/romrt.h; }
MAJ=$(part MAJOR)
VER=$MAJ.$(part MINOR).$(part PATCH)

: >"$TMP/stamp"
if make -s install BUILD="$B" DESTDIR="$D" PREFIX="$P" >"$TMP/out" 2>&1; then
    ok install_runs
else
    fail install_runs "$(tail -c 600 "$TMP/out")"
    exit 0
fi

want="bin/romkit include/romrt.h lib/libromrt.a lib/libromrt.so lib/libromrt.so.$MAJ lib/libromrt.so.$VER lib/libromrt_double.a
lib/pkgconfig/romrt-double.pc lib/pkgconfig/romrt.pc"
got=$(cd "$I" 2>/dev/null && find . ! -type d | sed 's|^\./||' | sort | tr '\n' ' ')
[ "$got" = "$(echo $want | tr ' ' '\n' | sort | tr '\n' ' ')" ] && ok install_layout || fail install_layout "installed: $got"
outside=$(cd "$D" && find . ! -type d | grep -v "^\.$P/"; find "$TMP" -newer "$TMP/stamp" ! -type d ! -path "$D/*" ! -path "$TMP/out")
[ -z "$outside" ] && [ ! -e "$P" ] && ok install_stays_in_destdir_prefix || fail install_stays_in_destdir_prefix "outside DESTDIR$P: $outside"
[ "$(readlink "$I/lib/libromrt.so")" = libromrt.so.$MAJ ] && [ "$(readlink "$I/lib/libromrt.so.$MAJ")" = libromrt.so.$VER ] \
    && ls -l "$I/bin/romkit" | grep -q '^-rwxr-xr-x' && ls -l "$I/include/romrt.h" | grep -q '^-rw-r--r--' \
    && ok install_links_and_modes || fail install_links_and_modes "$(ls -l "$I/lib" "$I/bin" "$I/include")"

# The shared library: its soname, and only the functions romrt.h declares are exported, under their
# float link names (romrt_f32_*: the installed header read as an app's compiler reads it).
readelf -d "$I/lib/libromrt.so.$VER" | grep -q "SONAME.*\[libromrt\.so\.$MAJ\]" && ok shared_library_soname \
    || fail shared_library_soname "$(readelf -d "$I/lib/libromrt.so.$VER" | grep SONAME)"
exported=$(nm -D --defined-only "$I/lib/libromrt.so" | awk '$2 == "T" {sub(/@.*/, "", $3); print $3}' | sort -u)
declared=$(grep -o 'romrt_[a-z0-9_]*(' "$I/include/romrt.h" | tr -d '(' | sort -u | sed 's/^romrt_/romrt_f32_/')
[ -n "$exported" ] && [ "$exported" = "$declared" ] && ok shared_library_exports_only_romrt_h \
    || fail shared_library_exports_only_romrt_h "$(echo "$exported" | tr '\n' ' ')"

# pkg-config names the installed copy (no romrt headers from the tree: the include is "romrt.h").
case "$(pc --cflags --libs romrt)" in
    *"-I$I/include"*"-L$I/lib"*"-lromrt"*) ok pkg_config_romrt ;;
    *) fail pkg_config_romrt "$(pc --cflags --libs romrt 2>&1)" ;;
esac
pc --static --libs romrt | grep -q -- '-lm' && ok pkg_config_static_adds_libm || fail pkg_config_static_adds_libm "$(pc --static --libs romrt 2>&1)"

SCENE=examples/scenes/cantilever_small.json
"$ROMKIT" build "$SCENE" -o "$TMP/a.rombin" --quiet >"$TMP/out" 2>&1 || fail asset_builds "$(cat "$TMP/out")"
"$B/embed" "$TMP/a.rombin" 40 >"$TMP/tree.out" 2>&1
tree=$(grep "tip at" "$TMP/tree.out")

# Shared: cc embed.c $(pkg-config --cflags --libs romrt), run with LD_LIBRARY_PATH.
if $CC -std=c99 -pedantic -Wall -Wextra -Werror $SAN -o "$TMP/embed_shared" examples/embed/embed.c $(pc --cflags --libs romrt) 2>"$TMP/err"; then
    readelf -d "$TMP/embed_shared" | grep -q "NEEDED.*\[libromrt\.so\.$MAJ\]" && ok embed_links_the_shared_library \
        || fail embed_links_the_shared_library "$(readelf -d "$TMP/embed_shared" | grep NEEDED)"
    LD_LIBRARY_PATH=$I/lib ldd "$TMP/embed_shared" | grep -q "libromrt.so.$MAJ => $I/lib/libromrt.so.$MAJ" \
        && LD_LIBRARY_PATH=$I/lib "$TMP/embed_shared" "$TMP/a.rombin" 40 >"$TMP/out" 2>&1 \
        && [ -n "$tree" ] && [ "$(grep "tip at" "$TMP/out")" = "$tree" ] && ok embed_shared_runs_like_the_tree_build \
        || fail embed_shared_runs_like_the_tree_build "$(cat "$TMP/out") / tree: $tree"
else
    fail embed_links_the_shared_library "$(head -c 600 "$TMP/err")"
fi

# Static: the same flags with --static, and the archive named instead of -lromrt (ld prefers .so).
libs=$(pc --static --libs romrt | sed 's/-lromrt\b/-l:libromrt.a/')
if $CC -std=c99 -pedantic -Wall -Wextra -Werror $SAN -o "$TMP/embed_static" examples/embed/embed.c $(pc --cflags romrt) $libs 2>"$TMP/err"; then
    ! readelf -d "$TMP/embed_static" | grep -q 'NEEDED.*libromrt' && "$TMP/embed_static" "$TMP/a.rombin" 40 >"$TMP/out" 2>&1 \
        && [ "$(grep "tip at" "$TMP/out")" = "$tree" ] && ok embed_static_runs_like_the_tree_build \
        || fail embed_static_runs_like_the_tree_build "$(cat "$TMP/out") / tree: $tree"
else
    fail embed_static_runs_like_the_tree_build "$(head -c 600 "$TMP/err")"
fi

# Double: romrt-double (static only, so plain --libs links the archive) and C++ against romrt.
if $CC -std=c99 -pedantic -Wall -Wextra -Werror $SAN -o "$TMP/embed_double" examples/embed/embed.c $(pc --cflags --libs --static romrt-double) 2>"$TMP/err" \
    && "$TMP/embed_double" "$TMP/a.rombin" 40 >"$TMP/out" 2>&1 && grep -q "tip at" "$TMP/out"; then
    ok embed_double_from_romrt_double
else
    fail embed_double_from_romrt_double "$(head -c 600 "$TMP/err") $(cat "$TMP/out")"
fi
# romrt.h's conventions on an app built against the installed header and library (the
# signatures, one error channel, out-structs with their size, limits from the library and no
# macro for them; tests/tools/api_contract.c says each).
if $CC -std=c99 -pedantic -Wall -Wextra -Werror $SAN -o "$TMP/api_contract" tests/tools/api_contract.c $(pc --cflags --libs romrt) 2>"$TMP/err" \
    && LD_LIBRARY_PATH=$I/lib "$TMP/api_contract" "$TMP/a.rombin" >"$TMP/out" 2>&1; then
    ok installed_header_keeps_the_api_contract
else
    fail installed_header_keeps_the_api_contract "$(head -c 600 "$TMP/err") $(grep -v '^ok' "$TMP/out" | head -c 600)"
fi
if $CXX -std=c++11 -pedantic -Wall -Wextra -Werror $SAN -o "$TMP/embed_cpp" examples/embed/embed_cpp.cpp $(pc --cflags --libs romrt) 2>"$TMP/err" \
    && LD_LIBRARY_PATH=$I/lib "$TMP/embed_cpp" "$TMP/a.rombin" >"$TMP/out" 2>&1 && grep -q "one step" "$TMP/out"; then
    ok embed_cpp_against_the_installed_copy
else
    fail embed_cpp_against_the_installed_copy "$(head -c 600 "$TMP/err") $(cat "$TMP/out")"
fi

"$I/bin/romkit" --help >"$TMP/out" 2>&1 && grep -q "romkit build\|usage: romkit" "$TMP/out" && ok installed_romkit_runs \
    || fail installed_romkit_runs "$(head -c 300 "$TMP/out")"
"$I/bin/romkit" run "$TMP/a.rombin" --steps 5 --quiet >"$TMP/out" 2>&1 && ok installed_romkit_steps_an_asset \
    || fail installed_romkit_steps_an_asset "$(head -c 300 "$TMP/out")"

# Nothing outside DESTDIR: PREFIX itself was never created (checked above and below), and every
# command make install runs (dry run) writes into DESTDIR: install/ln/chmod's last argument,
# sed's redirection. (Builds it would run first write in the build folder; not checked here.)
D2=$TMP/dest2
make -n -s install BUILD="$B" DESTDIR="$D2" PREFIX="$P" 2>&1 >"$TMP/dry" | head -c 300 >"$TMP/err"
stray=$(while read -r cmd; do
    case $cmd in
        install\ *|ln\ *|chmod\ *) target=${cmd##* } ;;
        sed\ *) target=${cmd##*>} ;;
        *) continue ;;
    esac
    case $target in \"$D2/*|$D2/*) ;; *) echo "$cmd" ;; esac
done <"$TMP/dry")
n=$(grep -c -e '^install ' -e '^ln ' -e '^chmod ' -e '^sed ' "$TMP/dry")
[ -z "$stray" ] && [ "$n" -ge 9 ] && [ ! -s "$TMP/err" ] && [ ! -e "$P" ] && ok install_writes_only_into_destdir \
    || fail install_writes_only_into_destdir "$n commands; outside DESTDIR: $stray $(cat "$TMP/err")"

make -s uninstall DESTDIR="$D" PREFIX="$P" >"$TMP/out" 2>&1
left=$(find "$D" ! -type d)
[ -z "$left" ] && ok uninstall_removes_what_install_put || fail uninstall_removes_what_install_put "left: $left"
