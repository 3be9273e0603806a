#!/bin/sh
# Installs what romkit needs on Debian 12 (run as root). Does nothing when all is present.
set -eu
PKGS="build-essential pkg-config libsuitesparse-dev libarpack2-dev libopenblas-dev liblapacke-dev \
libmetis-dev zlib1g-dev libcjson-dev tetgen gnuplot-nox clang libclang-rt-14-dev \
gcc-arm-none-eabi libnewlib-arm-none-eabi qemu-system-arm xxd python3 python3-numpy"
# make web compiles the runtime with emscripten; make test-web drives Debian's chromium headless
# (web/, playwright-core from web/package-lock.json pointed at /usr/bin/chromium).
PKGS="$PKGS emscripten chromium"
# Node runs the Khronos glTF validator on what romkit export writes (tools/gltf, npm ci from its lockfile).
# A node that came another way (NodeSource's nodejs bundles npm and conflicts with Debian's npm) is kept.
command -v node >/dev/null 2>&1 && command -v npm >/dev/null 2>&1 || PKGS="$PKGS nodejs npm"
missing=""
for p in $PKGS; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
[ -z "$missing" ] && exit 0
if [ "$(id -u)" != 0 ]; then
  echo "install-deps: missing packages:$missing (run this script as root)" >&2
  exit 1
fi
echo "install-deps: installing$missing" >&2
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends $missing >/dev/null
