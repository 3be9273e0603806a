# `make` as an unprivileged user, with the libraries present, builds: nothing in the build needs
# root (no install step, no write outside the tree). As root the script drops to nobody (setpriv);
# it skips, saying why, when no unprivileged user can be had. To stay within make test's time it
# builds in a copy of the tree holding a copy of this build's objects, the float runtime removed:
# that user compiles the float runtime (static and shared) and links romkit and the tests again. make deps-build must pass for that user (it only reports, never installs).
. tests/lib.sh
B=${ROMKIT_BUILD:-build}
case $B in /*) echo "skip nonroot_build: ROMKIT_BUILD is an absolute path ($B): the copy needs it relative"; exit 0 ;; esac
as=
if [ "$(id -u)" = 0 ]; then
    if ! command -v setpriv >/dev/null 2>&1; then
        echo "skip nonroot_build: running as root and setpriv (util-linux) is absent: no way to drop privileges"
        exit 0
    fi
    as="setpriv --reuid=65534 --regid=65534 --clear-groups"
    if ! $as true 2>"$TMP/err"; then
        echo "skip nonroot_build: cannot become nobody (uid 65534): $(head -c 200 "$TMP/err")"
        exit 0
    fi
fi
W=$TMP/tree
mkdir -p "$W/$B"
tar -c --exclude=./build --exclude="./$B" --exclude='./build-*' --exclude=./.git --exclude=node_modules . | tar -x -C "$W"
(cd "$B" && tar -c --exclude=./fuzz --exclude=./web --exclude=./mcu --exclude=./rt/float --exclude=./rt/pic \
    --exclude=./lib/libromrt.a --exclude='./lib/libromrt.so*' .) | tar -x -C "$W/$B"
if [ -n "$as" ]; then
    chmod 755 "$TMP"
    chown -R 65534:65534 "$W"
fi
if $as env HOME="$W" make -s -C "$W" deps-build >"$TMP/deps" 2>&1; then ok nonroot_deps_build_passes
else fail nonroot_deps_build_passes "$(tail -c 600 "$TMP/deps")"; fi
V=$(sed -n 's/^#define ROMRT_VERSION_\(MAJOR\|MINOR\|PATCH\) \([0-9][0-9]*\)$/\2/p' runtime/romrt.h | tr '\n' . | sed 's/\.$//')
if $as env HOME="$W" make -s -C "$W" -j2 BUILD="$B" all >"$TMP/make" 2>&1; then
    if [ -f "$W/$B/lib/libromrt.so.$V" ] && [ -x "$W/$B/romkit" ] && [ "$(stat -c %u "$W/$B/lib/libromrt.so.$V")" = "$(${as:+$as} id -u)" ]; then
        ok "nonroot_make_builds (as uid $(${as:+$as} id -u))"
    else
        fail nonroot_make_builds "make succeeded but libromrt.so.$V or romkit is missing or not the user's"
    fi
else
    fail nonroot_make_builds "$(tail -c 800 "$TMP/make")"
fi
