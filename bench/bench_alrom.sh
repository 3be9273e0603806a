#!/bin/sh
# make bench, the adaptive linear ROM (issue 19): the Grassmann paper's Table 3 and its ablations
# (Fig. 6, Tables 1 and 2) on the armadillo (armadillo_4k, 3,717 tets, E 1e5 Pa, nu 0.45, base fixed,
# the top moved: compressed at 1.5 m/s, bent along x at 1.5 m/s; backward Euler, h = 0.01 s, 40
# steps), every data-driven method trained on the six other runs of examples/scenes/alrom/
# (compressions at 1 and 2 m/s, bends along x and z, a stretch, a twist; 240 frames). Each scenario
# is one romkit compare (the full-order test run once, the training set once, one CROM per r):
#   r       adaptive (CROM decoder, m 20, lambda 0.2) and PCA (pod) at r = 4, 8, 16, 32 (Fig. 6)
#   m       adaptive at r 16, m = 1, 5, 10, 20, 30, 50 (Table 1)
#   lambda  adaptive at r 16, lambda = 0, 0.1, 0.2, 0.3, 0.5 (Table 2)
#   qpod    adaptive with the quadratic decoder fitted to the same frames (the one the runtime
#           steps), r = 4, 8, 16, 32, m 20, lambda 0.2
# The error is the total relative online error with per-step realignment (util/util.h; the paper's
# Sec. 5.1); s/step the median step of the free run (precompute simulator: the exact reduced
# Hessian U^T H U over every element, so not the runtime's cost); train_s the decoder's training.
# Writes bench/results/alrom.csv (scenario, sweep, value, method, online_error, s_per_step, train_s,
# training_frames).
set -e
BUILD=${BUILD:-build}
OUT=${2:-bench/results}
ROMKIT=$BUILD/romkit
JSONQ=$BUILD/jsonq
DIR=$(cd examples/scenes/alrom && pwd)
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
mkdir -p "$OUT"
train=$(ls "$DIR"/armadillo_train_*.json | sed 's/.*/"&"/' | paste -sd, -)
crom() { # crom NAME R M LAMBDA
    printf '{"method": "adaptive_linear", "decoder": "crom", "size": %s, "history": %s, "lambda": %s, "name": "%s", "training": [%s]}' "$2" "$3" "$4" "$1" "$train"
}
entries=""
add() { entries="${entries:+$entries, }$1"; }
for r in 4 8 32; do add "$(crom "r_$r" $r 20 0.2)"; done
for m in 1 5 10 20 30 50; do add "$(crom "m_$m" 16 $m 0.2)"; done
for l in 0 0.1 0.2 0.3 0.5; do add "$(crom "lambda_$l" 16 20 $l)"; done
for r in 4 8 16 32; do add "{\"basis\": \"pod\", \"size\": $r, \"name\": \"pod_$r\", \"training\": [$train]}"; done
for r in 4 8 16 32; do
    add "{\"method\": \"adaptive_linear\", \"decoder\": \"quadratic_pod\", \"size\": $r, \"name\": \"qpod_$r\", \"training\": [$train]}"
done
echo "scenario,sweep,value,method,online_error,s_per_step,train_s,training_frames" >"$OUT/alrom.csv"
for sc in compress bend; do
    sed "s|../../../tests|$PWD/tests|" "$DIR/armadillo_$sc.json" | python3 -c "
import json, sys
s = json.load(sys.stdin)
s['rom'] = json.loads('[' + sys.argv[1] + ']')
json.dump(s, open(sys.argv[2], 'w'))" "$entries" "$TMP/$sc.json"
    "$ROMKIT" compare "$TMP/$sc.json" --quiet --report "$TMP/$sc.report.json" >"$TMP/$sc.txt"
    i=1
    while name=$("$JSONQ" get "$TMP/$sc.report.json" "methods[$i].name" 2>/dev/null) && [ -n "$name" ]; do
        set -- $("$JSONQ" get "$TMP/$sc.report.json" "methods[$i].relative_online_error" "methods[$i].seconds_per_step" \
            "methods[$i].seconds.basis" "methods[$i].training_frames")
        sweep=${name%%_*}; value=${name#*_}
        method=adaptive; [ "$sweep" = pod ] && { method=pca; sweep=r; }
        [ "$sweep" = qpod ] && { method=adaptive_quadratic_pod; sweep=r; }
        echo "$sc,$sweep,$value,$method,$1,$2,$3,$4" >>"$OUT/alrom.csv"
        [ "$name" = "m_20" ] && echo "$sc,r,16,adaptive,$1,$2,$3,$4" >>"$OUT/alrom.csv"
        i=$((i + 1))
    done
    cat "$TMP/$sc.txt"
done
echo "$OUT/alrom.csv"
cat "$OUT/alrom.csv"
