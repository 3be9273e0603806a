#!/bin/sh
# The adaptive subspace's enrichment made visible (issue 34): the octopus (1,140 tets, E 2e5)
# dropped at 1 m/s onto a sphere over a plane, the adaptive entry at its defaults (skinning 16):
# examples/scenes/adaptive_octopus_drop.json, tests/integration/adaptive_defaults.sh's scene;
# `romkit adaptive --frames --snapshots --fields`, drawn by tools/plot/enrichment.gp: per frame the oracle's error G (log10, in its
# thresholds' units, 0 the threshold) and the vertices enriched when the step's solve ended.
# Frames 3 (falling), 4 (the landing), 6 and 9 (both ran the oracle; the steps between went to
# full order at once, their G NaN). Writes docs/adaptive_enrichment.png (gnuplot needed).
# Usage: [BUILD=build] sh bench/adaptive_picture.sh
set -eu
BUILD=${BUILD:-build}
command -v gnuplot >/dev/null 2>&1 || { echo "adaptive_picture.sh: gnuplot is not installed" >&2; exit 1; }
T=$(mktemp -d)
trap 'rm -rf "$T"' EXIT
ROMKIT_THREADS=1 "$BUILD/romkit" adaptive examples/scenes/adaptive_octopus_drop.json --frames "$T/frames" \
    --snapshots "$T/frames/S.npy" --fields "$T/frames/F.npy" --report "$T/report.json"
gnuplot -e "dir='$T/frames'; frames='3 4 6 9'; box='-0.5 0.55 -0.5 0.55 -0.2 0.4'; out='docs/adaptive_enrichment.png'" \
    tools/plot/enrichment.gp
echo "wrote docs/adaptive_enrichment.png"
