#!/bin/sh
# Installs what romkit needs on Debian 12, by group; does nothing when the group is present.
#   sh tools/install-deps.sh [GROUP...]     GROUP: build test web bench all (default: all)
#     build  the compiler and the libraries romkit links: what a plain `make` needs
#     test   build, and what `make test`'s tests use: tetgen (romkit mesh), clang with libFuzzer
#            (fuzz_short, damaged_assets), the Cortex-M cross compiler and qemu (mcu), python3
#            with numpy (the Python binding), node and npm (the glTF validator)
#     web    emscripten (make web) and Debian's chromium (make test-web drives it headless)
#     bench  gnuplot (make bench's charts) and python3 (its tables)
# As root, what is missing is installed with apt-get. As another user, a missing build package is
# an error (nothing builds without it); a missing package of another group is only reported: the
# tests that need it print "skip NAME: why" (tests/run.sh counts them; CI turns a skip into a FAIL).
set -eu
BUILD_PKGS="build-essential pkg-config libsuitesparse-dev libarpack2-dev libopenblas-dev liblapacke-dev \
libmetis-dev zlib1g-dev libcjson-dev libmeshoptimizer-dev libpng-dev"
TEST_PKGS="tetgen clang libclang-rt-14-dev gcc-arm-none-eabi libnewlib-arm-none-eabi qemu-system-arm xxd \
python3 python3-numpy binutils slurmctld slurmd munge"
# slurmctld, slurmd, munge (Slurm 22.05): tests/integration/slurm_bake.sh starts a one-node cluster.
# A node that came another way (NodeSource's nodejs bundles npm and conflicts with Debian's npm) is kept.
command -v node >/dev/null 2>&1 && command -v npm >/dev/null 2>&1 || TEST_PKGS="$TEST_PKGS nodejs npm"
WEB_PKGS="emscripten chromium"
BENCH_PKGS="gnuplot-nox python3"

[ $# -eq 0 ] && set -- all
status=0
for group in "$@"; do
    case $group in
        build) pkgs=$BUILD_PKGS ;;
        test) pkgs="$BUILD_PKGS $TEST_PKGS" ;;
        web) pkgs="$BUILD_PKGS $WEB_PKGS" ;;
        bench) pkgs="$BUILD_PKGS $BENCH_PKGS" ;;
        all) pkgs="$BUILD_PKGS $TEST_PKGS $WEB_PKGS $BENCH_PKGS" ;;
        *) echo "install-deps: unknown group '$group' (build, test, web, bench, all)" >&2; exit 2 ;;
    esac
    missing=""
    for p in $pkgs; do
        case " $missing " in *" $p "*) continue ;; esac
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
    done
    [ -z "$missing" ] && continue
    if [ "$(id -u)" = 0 ]; then
        echo "install-deps ($group): installing$missing" >&2
        export DEBIAN_FRONTEND=noninteractive
        apt-get update -qq
        # shellcheck disable=SC2086
        apt-get install -y -qq --no-install-recommends $missing >/dev/null
        continue
    fi
    build_missing=""
    for p in $missing; do
        case " $BUILD_PKGS " in *" $p "*) build_missing="$build_missing $p" ;; esac
    done
    if [ -n "$build_missing" ]; then
        echo "install-deps ($group): missing$build_missing, which the build needs: run 'sh tools/install-deps.sh build' as root" >&2
        status=1
    else
        echo "install-deps ($group): not installed:$missing (run 'sh tools/install-deps.sh $group' as root); the tests that need them skip" >&2
    fi
done
exit $status
