#!/bin/sh
# A member of the pneumatic finger family (family.json's "shape" over finger.json): the scene at
# shape code (G0, G1, G2) on stdout, the numbers family.json's keys move computed the same way:
#   G0 chamber length  void x end   0.0349 + 0.025 G0   (chamber 25 to 50 mm long at G2 = 0)
#   G1 wall thickness  void y start 0.0026 + 0.005 G1   (the bottom wall 2.5 to 7.5 mm)
#   G2 offset          void x start and end + 0.01 G2   (the chamber moved 0 to 10 mm toward the tip)
# Offsets are rounded to whole cells. The chamber's box is the void's grown by 0.5 mm. CELLS (default "16, 8, 4") and STEPS (default
# 40) make coarser or shorter members (the test's). The pressure, 3e4 Pa from t = 0, is the load.
# Usage: sh member.sh G0 G1 G2 >scene.json
CELLS=${CELLS:-16, 8, 4}
DURATION=$(awk -v n="${STEPS:-40}" 'BEGIN { print n * 0.01 }')
awk -v g0="$1" -v g1="$2" -v g2="${3:-0}" -v cells="$CELLS" -v dur="$DURATION" 'BEGIN {
    # each offset in whole cells (5 mm in x, 2.5 mm in y), as the family file rounds it ("step")
    x0 = 0.0101 + r(0.01 * g2, 0.005); x1 = 0.0349 + r(0.025 * g0 + 0.01 * g2, 0.005); y0 = 0.0026 + r(0.005 * g1, 0.0025)
    printf "{\n  \"objects\": [{\n"
    printf "    \"mesh\": {\"box\": {\"size\": [0.08, 0.02, 0.02], \"cells\": [%s]},\n", cells
    printf "             \"voids\": [{\"box\": [[%.6g, %.6g, 0.0051], [%.6g, 0.0099, 0.0149]]}]},\n", x0, y0, x1
    printf "    \"material\": {\"model\": \"neohookean\", \"young\": 5e5, \"poisson\": 0.45, \"density\": 1000},\n"
    printf "    \"fixed\": [{\"box\": [[-0.001, -1, -1], [0.001, 1, 1]]}],\n"
    printf "    \"chambers\": [{\"name\": \"c0\", \"box\": [[%.6g, %.6g, 0.0046], [%.6g, 0.0104, 0.0154]], \"pressure\": 3e4}]\n", \
        x0 - 0.0005, y0 - 0.0005, x1 + 0.0005
    printf "  }],\n  \"damping\": {\"mass\": 10},\n  \"time\": {\"step\": 0.01, \"duration\": %s}\n}\n", dur
}
function r(d, step) { return step * int(d / step + 0.5 + 1e-9) }'
