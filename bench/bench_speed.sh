#!/bin/sh
# make bench, the runtime's speed against error (issue 16). Two scenes, each timed against its own
# full-order run in the same script:
#
#  bunny   bunny_19k (4,670 vertices, 19,379 tets), stable Neo-Hookean E = 5 MPa, nu = 0.45,
#          1000 kg/m^3, the base (y < -0.03 m) fixed, gravity, backward Euler at h = 0.01 s;
#          r = 8, 16, 20, 32, 64 linear modes (the first r of one basis), cubature trained to 1%
#          force error on the full-order run's 100 frames; float32 assets and runtime.
#  beam    the demo's beam (examples/scenes/beam_bend.json, 15,360 tets): RKPM skinning m = 16
#          (r = 204) with cubature, as make demo bakes it: float64 through the double runtime
#          (romkit-double), and float32 through the float one, whose rounding moves this
#          ill-conditioned model's trajectory (the error column shows by how much).
#
# Per model and Newton mode (converged: to the asset's tolerance with a line search; fixed: one full
# Newton step per time step, romkit run --newton 1; both with a fresh Newton matrix every
# iteration, --hessian-reuse 1, the runtime's default being to keep it where that pays (issue 31,
# bench/newton_modes.sh); converged-kept and fixed-kept: the same with Newton's matrix kept for up
# to KEEP = 10 steps, romkit run --hessian-reuse, whose GFLOP/s is not given since the Hessians it
# builds are not counted):
#   us/step     the median, fastest and slowest of SAMPLES runs of STEPS steps from rest (each run's
#               own figure is the median of its steps' times, romkit run's seconds_per_step)
#   newton      Newton iterations per step
#   error       relative error and normalized MSE of the shown vertices over the first 100 steps
#               against the full-order frames (romkit run --reference, util/util.h's metrics)
#   GFLOP/s     the element kernels' useful flops per step over the step's time: per cubature
#               element and Newton iteration 9 r (r + 1) (the Hessian's upper triangle, rank 9),
#               162 r (w dP/dF G), 54 r (G), 18 r (the gradient), 24 r (F - I): a lower bound on the
#               rate of the whole step, which also runs the SVD, the line search and the solve
# against the core's peak: 32 float flops per cycle (two 8-lane FMAs) at the clock /proc/cpuinfo
# gives, for a runtime built with AVX2 and FMA (the Makefile's RT_ARCH), 8 (one 4-lane multiply and
# one add) for a portable SSE2 build.
#
# Vega FEM's reduced StVK on the same mesh, material, pins, gravity, h and an r = 20 linear-mode
# basis, one thread, measured on this kind of machine (issue 16): 10.6 us/step at one Newton
# iteration, 29.6 us converged. Output: bench/results/runtime_speed.{csv,json}.
set -eu
DATA=${1:-tests/data/meshes}
OUT=${2:-bench/results}
BUILD=${BUILD:-build}
R=$BUILD/romkit
J=$BUILD/jsonq
STEPS=${STEPS:-3000}
KEEP=${KEEP:-10} # the kept modes' romkit run --hessian-reuse
SAMPLES=${SAMPLES:-5}
[ -n "${ROMKIT_BENCH_QUICK:-}" ] && STEPS=300 && SAMPLES=3
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT
mkdir -p "$OUT"
DATA_ABS=$(cd "$DATA" && pwd)

cat >"$TMP/bunny.json" <<EOF
{
  "objects": [{
    "mesh": {"file": "$DATA_ABS/bunny_19k.msh"},
    "material": {"model": "neohookean", "young": 5e6, "poisson": 0.45, "density": 1000},
    "fixed": [{"box": [[-5, -1, -5], [5, -0.03, 5]]}]
  }],
  "gravity": [0, -9.81, 0],
  "time": {"step": 0.01, "duration": 1.0, "integrator": "backward_euler"},
  "rom": [
    {"name": "modes-8", "basis": "modes", "size": 8, "cubature": {"tolerance": 0.01}},
    {"name": "modes-16", "basis": "modes", "size": 16, "cubature": {"tolerance": 0.01}},
    {"name": "modes-20", "basis": "modes", "size": 20, "cubature": {"tolerance": 0.01}},
    {"name": "modes-32", "basis": "modes", "size": 32, "cubature": {"tolerance": 0.01}},
    {"name": "modes-64", "basis": "modes", "size": 64, "cubature": {"tolerance": 0.01}}
  ]
}
EOF

median3() { # median3 V...: "median min max" of the values
    printf '%s\n' "$@" | sort -g | awk '{v[NR] = $1} END {m = NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2; print m, v[1], v[NR]}'
}

mhz=$(awk -F: '/^cpu MHz/ {print $2; exit}' /proc/cpuinfo 2>/dev/null | tr -d ' ')
[ -n "$mhz" ] || mhz=0
if objdump -d "$BUILD/lib/libromrt.a" 2>/dev/null | grep -q vfmadd; then
    arch="AVX2+FMA"; per_cycle=32
else
    arch="SSE2"; per_cycle=8
fi
peak=$(awk -v m="$mhz" -v c="$per_cycle" 'BEGIN {printf "%.1f", m * c / 1000}')
echo "runtime built for $arch: peak $peak GFLOP/s per core ($per_cycle flops/cycle at $mhz MHz)"

printf 'scene,model,r,cubature_elements,mode,us_per_step,us_per_step_min,us_per_step_max,newton_per_step,relative_error,normalized_mse,gflops,peak_gflops,fom_s_per_step,fom_over_runtime\n' >"$OUT/runtime_speed.csv"

# one_model SCENE NAME ASSET REF FOM_S [RUNNER]: both modes of one asset, rows into the CSV
one_model() {
    scene=$1 name=$2 asset=$3 ref=$4 fom_s=$5 run=${6:-$R}
    build=${name%-float32}
    build=${build%-float64}
    r=$("$J" get "$TMP/$build.build.json" basis.columns)
    ne=$("$J" get "$TMP/$build.build.json" cubature.elements)
    for mode in converged fixed converged-kept fixed-kept; do
        case $mode in
        converged) flag="--hessian-reuse 1" ;;
        fixed) flag="--newton 1 --hessian-reuse 1" ;;
        converged-kept) flag="--hessian-reuse $KEEP" ;;
        fixed-kept) flag="--newton 1 --hessian-reuse $KEEP" ;;
        esac
        # shellcheck disable=SC2086
        "$run" run "$asset" --steps 100 $flag --reference "$ref" --report "$TMP/e.json" --quiet >/dev/null
        rel=$("$J" get "$TMP/e.json" reference.relative_error)
        nmse=$("$J" get "$TMP/e.json" reference.normalized_mse)
        times="" its=0
        sample=0
        while [ "$sample" -lt "$SAMPLES" ]; do
            # shellcheck disable=SC2086
            "$run" run "$asset" --steps "$STEPS" $flag --report "$TMP/t.json" --quiet >/dev/null
            times="$times $(awk -v s="$("$J" get "$TMP/t.json" seconds_per_step)" 'BEGIN {printf "%.4f", s * 1e6}')"
            its=$("$J" get "$TMP/t.json" newton_iterations)
            sample=$((sample + 1))
        done
        # shellcheck disable=SC2086
        set -- $(median3 $times)
        us=$1 lo=$2 hi=$3
        nps=$(awk -v i="$its" -v s="$STEPS" 'BEGIN {printf "%.3f", i / s}')
        gf=$(awk -v r="$r" -v e="$ne" -v n="$nps" -v us="$us" 'BEGIN {printf "%.2f", e * n * (9 * r * (r + 1) + 258 * r) / (us * 1e3)}')
        case $mode in *kept) gf=nan ;; esac # the Hessians built per step are not counted
        sp=$(awk -v f="$fom_s" -v us="$us" 'BEGIN {printf "%.0f", f * 1e6 / us}')
        printf '%-7s %-26s %4s %5s %-14s %9.1f %9.1f %9.1f %6.2f %10.3g %10.3g %7.2f %8.0f\n' "$scene" "$name" "$r" "$ne" \
            "$mode" "$us" "$lo" "$hi" "$nps" "$rel" "$nmse" "$gf" "$sp"
        printf '%s,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s,%s\n' "$scene" "$name" "$r" "$ne" "$mode" "$us" "$lo" "$hi" \
            "$nps" "$rel" "$nmse" "$gf" "$peak" "$fom_s" "$sp" >>"$OUT/runtime_speed.csv"
    done
}

printf '%-7s %-26s %4s %5s %-14s %9s %9s %9s %6s %10s %10s %7s %8s\n' scene model r elems mode "us/step" min max \
    newton "rel.error" "norm.MSE" GFLOP/s "fom/rt"

"$R" fom "$TMP/bunny.json" --snapshots "$TMP/bunny.npy" --report "$TMP/bunny.fom.json" --quiet >/dev/null
fom_s=$("$J" get "$TMP/bunny.fom.json" seconds_per_step)
echo "bunny full order: $fom_s s/step (mean of 100 steps)"
k=0
for name in modes-8 modes-16 modes-20 modes-32 modes-64; do
    "$R" build "$TMP/bunny.json" --entry "$k" --training "$TMP/bunny.npy" -o "$TMP/$name.rombin" \
        --report "$TMP/$name.build.json" --quiet >/dev/null
    one_model bunny "$name" "$TMP/$name.rombin" "$TMP/bunny.npy" "$fom_s"
    k=$((k + 1))
done

if [ -z "${ROMKIT_BENCH_QUICK:-}" ]; then
    "$R" fom examples/scenes/beam_bend.json --snapshots "$TMP/beam.npy" --report "$TMP/beam.fom.json" --quiet >/dev/null
    fom_s=$("$J" get "$TMP/beam.fom.json" seconds_per_step)
    echo "beam full order: $fom_s s/step (mean of 100 steps)"
    "$R" build examples/scenes/beam_bend.json --entry 0 --training "$TMP/beam.npy" -o "$TMP/rkpm-16.rombin" \
        --precision float64 --report "$TMP/rkpm-16.build.json" --quiet >/dev/null
    "$R" build examples/scenes/beam_bend.json --entry 0 --training "$TMP/beam.npy" -o "$TMP/rkpm-16-f32.rombin" \
        --quiet >/dev/null
    STEPS=100
    one_model beam rkpm-16-float64 "$TMP/rkpm-16.rombin" "$TMP/beam.npy" "$fom_s" "$BUILD/romkit-double"
    one_model beam rkpm-16-float32 "$TMP/rkpm-16-f32.rombin" "$TMP/beam.npy" "$fom_s"
fi

# the JSON beside the CSV
awk -F, 'NR == 1 {for (i = 1; i <= NF; i++) h[i] = $i; print "["; next}
         {sep = NR > 2 ? ",\n" : ""; printf "%s  {", sep
          for (i = 1; i <= NF; i++) {c = i > 1 ? ", " : ""; v = $i ~ /^[-0-9.e+]+$/ ? $i : "\"" $i "\""; printf "%s\"%s\": %s", c, h[i], v}
          printf "}"}
         END {print "\n]"}' "$OUT/runtime_speed.csv" >"$OUT/runtime_speed.json"
echo "bench/results: runtime_speed.csv, runtime_speed.json"
