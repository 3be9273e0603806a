# tests/run.sh: make-lock (this script runs make in the shared build folder)
# romkit export: every kind of asset as glTF 2.0. Each exported file passes the Khronos glTF
# validator (tools/gltf, npm ci from its lockfile) with no error, and is read back by
# tests/tools/glb_check.py (the standard library only): at every keyframe, the rest positions plus
# the weighted morph targets are `romkit run`'s positions to within 4 units of float32 rounding at
# the positions' size (u P, u = 2^-24; measured: about 1). A damaged asset is refused by name and
# nothing is written.
. tests/lib.sh
B=${ROMKIT_BUILD:-build}
STEPS=20
ULPS=4

# The validator: installed from the lockfile when missing (node_modules is not committed).
if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
    echo "skip cli_export: node and npm are needed for the glTF validator (sh tools/install-deps.sh test, as root)"
    exit 0
fi
if [ ! -f tools/gltf/node_modules/gltf-validator/package.json ] &&
    ! npm ci --prefix tools/gltf --no-audit --no-fund >"$TMP/npm" 2>&1; then
    fail gltf_validator_installed "npm ci in tools/gltf failed: $(tail -c 600 "$TMP/npm")"
    exit 0
fi
ok gltf_validator_installed
: >"$TMP/issues"
# validate NAME FILE: 0 errors from the validator; its other issues are kept for the summary.
validate() {
    if node tools/gltf/validate.mjs "$2" >"$TMP/val" 2>&1; then ok "$1_passes_the_gltf_validator"
    else fail "$1_passes_the_gltf_validator" "$(head -c 1500 "$TMP/val")"; fi
    sed -n 's/^  \([a-z]*\) \([A-Z_]*\) .*/\1 \2/p' "$TMP/val" >>"$TMP/issues"
}

# check NAME ASSET [--koopman]: export STEPS frames, validate, and read back against romkit run.
check() {
    name=$1; asset=$2; shift 2
    if ! "$ROMKIT" export "$asset" "$@" --gltf "$TMP/$name.glb" --steps $STEPS --quiet >"$TMP/out" 2>"$TMP/err"; then
        fail "${name}_exports" "$(head -c 600 "$TMP/err")"
        return
    fi
    ok "${name}_exports"
    validate "$name" "$TMP/$name.glb"
    "$ROMKIT" run "$asset" "$@" --steps 0 --positions "$TMP/$name.p0.npy" --quiet >/dev/null 2>"$TMP/err" &&
        "$ROMKIT" run "$asset" "$@" --steps $STEPS --snapshots "$TMP/$name.s.npy" --quiet >/dev/null 2>>"$TMP/err" ||
        { fail "${name}_animation_is_the_runtime_run" "romkit run: $(head -c 600 "$TMP/err")"; return; }
    if python3 tests/tools/glb_check.py "$TMP/$name.glb" "$TMP/$name.p0.npy" "$TMP/$name.s.npy" "$H" $ULPS >"$TMP/chk" 2>&1
    then ok "${name}_animation_is_the_runtime_run"
    else fail "${name}_animation_is_the_runtime_run" "$(head -c 600 "$TMP/chk")"; fi
    echo "# $name: $(sed -n 1p "$TMP/out" | sed 's/^[^:]*: //'); read back: $(tail -n 1 "$TMP/chk")"
}

# A linear basis: 12 modes with cubature, BDF2, damping, a pushable group (float32, float64, and
# deflated: the same file must come out of that one, the mesh named after the asset's file name).
H=0.01
"$ROMKIT" build examples/scenes/cantilever_small.json -o "$TMP/modes.rombin" --quiet >/dev/null 2>&1 &&
    "$ROMKIT" build examples/scenes/cantilever_small.json -o "$TMP/modes64.rombin" --precision float64 --quiet >/dev/null 2>&1 &&
    mkdir -p "$TMP/z" && "$ROMKIT" build examples/scenes/cantilever_small.json -o "$TMP/z/modes.rombin" --compress --quiet >/dev/null 2>&1 ||
    fail linear_assets_build "romkit build failed"
check modes "$TMP/modes.rombin"
check modes64 "$TMP/modes64.rombin"
"$ROMKIT" export "$TMP/z/modes.rombin" --gltf "$TMP/z/modes.glb" --steps $STEPS --quiet >/dev/null 2>&1 &&
    cmp -s "$TMP/modes.glb" "$TMP/z/modes.glb" && ok deflated_asset_exports_the_same_file \
    || fail deflated_asset_exports_the_same_file "differs from the stored asset's export"

# A skinning basis (SKIN, WGHT: the rows formed from the weights) and a point cloud, mesh-free, drawn
# as points (tests/fuzz/seed_points.json: RKPM skinning on 81 points).
cat >"$TMP/skin.json" <<'JSON'
{
  "objects": [{
    "mesh": {"box": {"size": [1, 0.2, 0.2], "cells": [8, 2, 2]}},
    "material": {"model": "stvk", "young": 1e5, "poisson": 0.4, "density": 1000},
    "fixed": [{"box": [[-1, -1, -1], [0.01, 1, 1]]}]
  }],
  "gravity": [0, -9.81, 0],
  "time": {"step": 0.01, "duration": 0.1},
  "rom": {"basis": "skinning", "size": 3, "cubature": {"tolerance": 0.05}}
}
JSON
if "$ROMKIT" build "$TMP/skin.json" -o "$TMP/skin.rombin" --quiet >/dev/null 2>"$TMP/err" &&
    "$ROMKIT" inspect "$TMP/skin.rombin" | grep -q "WGHT  critical"; then
    check skinning "$TMP/skin.rombin"
else fail skinning_asset_builds "$(head -c 600 "$TMP/err")"; fi
# A surface on a simulation cage (mesh.cage, issue 32): the glTF carries spot.obj's own 11,533
# vertices and 23,062 triangles, not the cage's, their rows formed from the cage's skinning weights.
if "$ROMKIT" build tests/data/scenes/spot_cage.json -o "$TMP/caged.rombin" --quiet >/dev/null 2>"$TMP/err"; then
    check caged "$TMP/caged.rombin"
    grep -q "11533 shown vertices, 23062 triangles" "$TMP/out" && ok caged_gltf_is_the_surface \
        || fail caged_gltf_is_the_surface "$(head -c 300 "$TMP/out")"
    # and romkit's own glTF reader (issue 32) takes it back in as that closed surface
    "$ROMKIT" mesh "$TMP/caged.glb" -o "$TMP/caged_back.mesh" >"$TMP/back" 2>&1 &&
        grep -q "surface with 11533 vertices, 23062 triangles" "$TMP/back" && ok exported_gltf_reads_back_as_the_surface \
        || fail exported_gltf_reads_back_as_the_surface "$(head -c 300 "$TMP/back")"
else fail caged_asset_builds "$(head -c 600 "$TMP/err")"; fi
if "$ROMKIT" build tests/fuzz/seed_points.json -o "$TMP/points.rombin" --quiet >/dev/null 2>"$TMP/err"; then
    check points "$TMP/points.rombin"
    python3 -c 'import json, struct, sys
d = open(sys.argv[1], "rb").read(); n = struct.unpack_from("<I", d, 12)[0]
p = json.loads(d[20:20 + n])["meshes"][0]["primitives"][0]
sys.exit(0 if p["mode"] == 0 and "indices" not in p else 1)' "$TMP/points.glb" &&
        ok point_cloud_is_a_points_primitive || fail point_cloud_is_a_points_primitive "not mode 0 without indices"
else fail point_cloud_asset_builds "$(head -c 600 "$TMP/err")"; fi

# A Koopman operator alone (weights: its eigen-coordinates y, from y0 at frame 0), and one beside a
# reduced model in the same asset (the reduced model by default, --koopman for the operator).
cat >"$TMP/koop.json" <<'JSON'
{
  "objects": [{
    "mesh": {"box": {"size": [1, 0.2, 0.2], "cells": [6, 2, 2]}},
    "material": {"model": "neohookean", "young": 1e5, "poisson": 0.4, "density": 1000},
    "fixed": [{"box": [[-1, -1, -1], [0.01, 1, 1]]}]
  }],
  "gravity": [0, -9.81, 0],
  "time": {"step": 0.01, "duration": 0.3},
  "rom": {"basis": "modes", "size": 6, "koopman": {"rank": 10, "clamp": true}}
}
JSON
sed 's/"size": 6, "koopman"/"size": 6, "cubature": {"tolerance": 0.05}, "koopman"/' "$TMP/koop.json" >"$TMP/both.json"
if "$ROMKIT" build "$TMP/koop.json" -o "$TMP/koop.rombin" --quiet >/dev/null 2>"$TMP/err" &&
    "$ROMKIT" build "$TMP/both.json" -o "$TMP/both.rombin" --quiet >/dev/null 2>>"$TMP/err"; then
    check koopman "$TMP/koop.rombin"
    check both_reduced "$TMP/both.rombin"
    check both_koopman "$TMP/both.rombin" --koopman
else fail koopman_assets_build "$(head -c 600 "$TMP/err")"; fi

# The read-back is a real check: the same file against the run shifted by one step fails.
if [ -f "$TMP/modes.glb" ] && "$ROMKIT" run "$TMP/modes.rombin" --steps 1 --positions "$TMP/p1.npy" --quiet >/dev/null 2>&1; then
    python3 tests/tools/glb_check.py "$TMP/modes.glb" "$TMP/p1.npy" "$TMP/modes.s.npy" $H $ULPS >"$TMP/chk" 2>&1 &&
        fail read_back_sees_a_frame_off "passed: $(cat "$TMP/chk")" || ok read_back_sees_a_frame_off
fi
# ... and so is the validator: the same file with its positions' max lowered is an error.
if [ -f "$TMP/modes.glb" ]; then
    python3 -c 'import json, struct, sys
d = open(sys.argv[1], "rb").read(); n = struct.unpack_from("<I", d, 12)[0]
g = json.loads(d[20:20 + n]); g["accessors"][0]["max"][0] *= 0.5
j = json.dumps(g).encode(); j += b" " * (-len(j) % 4); rest = d[20 + n:]
open(sys.argv[2], "wb").write(struct.pack("<III", 0x46546C67, 2, 20 + len(j) + len(rest)) +
                              struct.pack("<II", len(j), 0x4E4F534A) + j + rest)' "$TMP/modes.glb" "$TMP/tampered.glb"
    node tools/gltf/validate.mjs "$TMP/tampered.glb" >"$TMP/val" 2>&1 && fail validator_sees_a_wrong_max "$(cat "$TMP/val")" \
        || { grep -q ACCESSOR_MAX_MISMATCH "$TMP/val" && ok validator_sees_a_wrong_max || fail validator_sees_a_wrong_max "$(cat "$TMP/val")"; }
fi

# No steps: the mesh at the start, no animation, still valid.
if "$ROMKIT" export "$TMP/modes.rombin" --gltf "$TMP/still.glb" --steps 0 --quiet >/dev/null 2>"$TMP/err"; then
    validate still "$TMP/still.glb"
    python3 -c 'import json, struct, sys
d = open(sys.argv[1], "rb").read(); n = struct.unpack_from("<I", d, 12)[0]
sys.exit("animations" in json.loads(d[20:20 + n]))' "$TMP/still.glb" && ok no_steps_no_animation \
        || fail no_steps_no_animation "an animation was written"
else fail no_steps_no_animation "$(cat "$TMP/err")"; fi

# Damaged input: refused with a message naming the damage; the target is never touched (a file
# already there stays as it was, no temporary file is left).
echo "previous contents" >"$TMP/keep.glb"
cp "$TMP/modes.rombin" "$TMP/flip.rombin"
printf '\377' | dd of="$TMP/flip.rombin" bs=1 seek=2000 conv=notrunc 2>/dev/null
expect_fail export_refuses_a_flipped_byte "CRC mismatch" "$ROMKIT" export "$TMP/flip.rombin" --gltf "$TMP/keep.glb"
head -c 3000 "$TMP/modes.rombin" >"$TMP/cut.rombin"
expect_fail export_refuses_a_truncated_asset "truncated" "$ROMKIT" export "$TMP/cut.rombin" --gltf "$TMP/keep.glb"
expect_fail export_refuses_a_non_asset "not a .rombin" "$ROMKIT" export "$TMP/skin.json" --gltf "$TMP/keep.glb"
expect_fail export_koopman_needs_an_operator "no Koopman operator" "$ROMKIT" export "$TMP/modes.rombin" --koopman --gltf "$TMP/keep.glb"
expect_fail export_needs_gltf "--gltf OUT.glb is required" "$ROMKIT" export "$TMP/modes.rombin"
expect_fail export_rejects_bad_steps "whole number" "$ROMKIT" export "$TMP/modes.rombin" --gltf "$TMP/keep.glb" --steps x
expect_fail export_names_an_unwritable_target "cannot write" "$ROMKIT" export "$TMP/modes.rombin" --gltf "$TMP/none/x.glb"
[ "$(cat "$TMP/keep.glb")" = "previous contents" ] && ! ls "$TMP" | grep -q 'keep.glb.tmp' && ok failed_export_leaves_the_target_alone \
    || fail failed_export_leaves_the_target_alone "keep.glb changed or a temporary file was left"
# Every damaged variant tests/fuzz/damage makes of the skinning asset (header, table, chunk bounds,
# CRCs, model chunks): refused, nothing written.
if make -s BUILD="$B" "$B/fuzz/damage" >"$TMP/make" 2>&1 && "$B/fuzz/damage" "$TMP/skin.rombin" "$TMP/dmg" >/dev/null 2>&1; then
    total=0; bad=""
    for f in "$TMP"/dmg/bad/*; do
        total=$((total + 1))
        "$ROMKIT" export "$f" --gltf "$TMP/dmg.glb" --steps 2 --quiet >/dev/null 2>"$TMP/err"; rc=$?
        { [ $rc -eq 1 ] && grep -q "^romkit export: " "$TMP/err" && [ ! -e "$TMP/dmg.glb" ]; } || bad="$bad $(basename "$f"):$rc"
    done
    [ "$total" -ge 50 ] && [ -z "$bad" ] && ok "export_refuses_every_damaged_variant ($total)" \
        || fail export_refuses_every_damaged_variant "$total variants; not refused cleanly:$bad"
else fail export_refuses_every_damaged_variant "tests/fuzz/damage: $(tail -c 600 "$TMP/make")"; fi

# What the validator said beyond errors, over every file (the README lists it).
issues=$(sort "$TMP/issues" | uniq -c | tr -s ' \n' ' ')
echo "# validator issues other than errors, over every file: ${issues:-none}"
