#!/usr/bin/env python3
"""glb_check.py FILE.glb START.npy FRAMES.npy H ULPS: reads a .glb written by `romkit export` with
nothing but the standard library (struct, json) and checks it against the runtime:

- the container: magic, version 2, the length, 4-byte aligned JSON and BIN chunks;
- one mesh, one primitive (indexed triangles or points), POSITION and one POSITION morph target
  per weight (float32 VEC3 whose min/max bound their data), one animation of node 0's weights:
  LINEAR, keyframe times k H (H and the product rounded to float32, as the asset stores its step),
  frames x targets weights;
- at every keyframe k, X + sum_j w_j(k) D_j (summed in double from the file's float32 values)
  against the runtime's positions: frame 0 from START.npy (n x 3, `romkit run --steps 0
  --positions`), frames 1.. from FRAMES.npy (N x n x 3, `romkit run --steps N --snapshots`).

The float32 runtime rounds each position it returns, so the two agree to within a few units of
float32 rounding at the positions' size, u P (u = 2^-24, P the largest |x| over every vertex and
frame), not better. Prints "frames F, max |error| E m = K u P, displacement scale S m, relative
E/S R" and exits 1 when K > ULPS (or with a message naming the first structural problem)."""
import json
import math
import struct
import sys


def fail(msg):
    print("glb_check: " + msg)
    sys.exit(1)


def f32(x):
    return struct.unpack("<f", struct.pack("<f", x))[0]


def read_npy(path):
    """A float64 little-endian C-order .npy (format 1.0): shape and flat values."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:6] != b"\x93NUMPY":
        fail(path + ": not a .npy file")
    hlen = struct.unpack_from("<H", data, 8)[0]
    header = data[10:10 + hlen].decode("latin1")
    if "'descr': '<f8'" not in header or "'fortran_order': False" not in header:
        fail(path + ": expected little-endian float64 in C order: " + header)
    shape = tuple(int(s) for s in header.split("'shape': (")[1].split(")")[0].split(",") if s.strip())
    count = 1
    for s in shape:
        count *= s
    return shape, struct.unpack_from("<%dd" % count, data, 10 + hlen)


def read_glb(path):
    with open(path, "rb") as f:
        data = f.read()
    magic, version, length = struct.unpack_from("<III", data, 0)
    if magic != 0x46546C67 or version != 2 or length != len(data):
        fail("header: magic %x, version %d, length %d of %d bytes" % (magic, version, length, len(data)))
    chunks, at = [], 12
    while at < len(data):
        clen, ctype = struct.unpack_from("<II", data, at)
        if clen % 4 or at % 4:
            fail("chunk %x at %d: length %d not 4-byte aligned" % (ctype, at, clen))
        chunks.append((ctype, data[at + 8:at + 8 + clen]))
        at += 8 + clen
    if at != len(data) or len(chunks) != 2 or chunks[0][0] != 0x4E4F534A or chunks[1][0] != 0x004E4942:
        fail("expected a JSON chunk then a BIN chunk, got %s" % [hex(c[0]) for c in chunks])
    return json.loads(chunks[0][1].decode("utf-8")), chunks[1][1]


def accessor(gltf, bin_, index, want_type, want_comps):
    """An accessor's values as tuples of want_comps float32 (or uint32) numbers."""
    a = gltf["accessors"][index]
    v = gltf["bufferViews"][a["bufferView"]]
    size = {5126: 4, 5125: 4}[a["componentType"]]
    if a["componentType"] != want_type or {"SCALAR": 1, "VEC3": 3}[a["type"]] != want_comps:
        fail("accessor %d: componentType %d type %s" % (index, a["componentType"], a["type"]))
    stride = v.get("byteStride", size * want_comps)
    start = v.get("byteOffset", 0) + a.get("byteOffset", 0)
    if start % size or stride % size:
        fail("accessor %d: misaligned (offset %d, stride %d)" % (index, start, stride))
    if start + stride * (a["count"] - 1) + size * want_comps > v.get("byteOffset", 0) + v["byteLength"]:
        fail("accessor %d runs past its buffer view" % index)
    fmt = "<%d%s" % (want_comps, "f" if want_type == 5126 else "I")
    out = [struct.unpack_from(fmt, bin_, start + stride * i) for i in range(a["count"])]
    if "min" in a:  # the validator checks these are exact; here: they bound the data
        for c in range(want_comps):
            if min(o[c] for o in out) < a["min"][c] or max(o[c] for o in out) > a["max"][c]:
                fail("accessor %d: data outside its min/max" % index)
    return out


def main():
    if len(sys.argv) != 6:
        fail("usage: glb_check.py FILE.glb START.npy FRAMES.npy H ULPS")
    gltf, bin_ = read_glb(sys.argv[1])
    h, ulps = float(sys.argv[4]), float(sys.argv[5])
    if gltf["asset"]["version"] != "2.0" or len(gltf["meshes"]) != 1 or len(gltf["meshes"][0]["primitives"]) != 1:
        fail("expected glTF 2.0 with one mesh of one primitive")
    prim = gltf["meshes"][0]["primitives"][0]
    if "POSITION" not in prim["attributes"] or "accessors" not in gltf:
        fail("no POSITION")
    positions = [prim["attributes"]["POSITION"]] + [t["POSITION"] for t in prim["targets"]]
    if any("min" not in gltf["accessors"][p] or "max" not in gltf["accessors"][p] for p in positions):
        fail("a POSITION accessor without min/max")
    X = accessor(gltf, bin_, positions[0], 5126, 3)
    D = [accessor(gltf, bin_, p, 5126, 3) for p in positions[1:]]
    n, r = len(X), len(D)
    if prim.get("mode", 4) == 4:
        idx = accessor(gltf, bin_, prim["indices"], 5125, 1)
        if len(idx) % 3 or max(i[0] for i in idx) >= n:
            fail("indices: %d of them, largest %d for %d vertices" % (len(idx), max(i[0] for i in idx), n))
    elif prim.get("mode") != 0 or "indices" in prim:
        fail("a primitive that is neither indexed triangles nor points")

    start_shape, start = read_npy(sys.argv[2])
    frames_shape, frames = read_npy(sys.argv[3])
    if start_shape != (n, 3) or frames_shape[1:] != (n, 3):
        fail("the runtime's positions are %s and %s for %d shown vertices" % (start_shape, frames_shape, n))
    T = 1 + frames_shape[0]
    anims = gltf.get("animations", [])
    if len(anims) != 1 or len(anims[0]["channels"]) != 1:
        fail("expected one animation with one channel")
    ch = anims[0]["channels"][0]
    s = anims[0]["samplers"][ch["sampler"]]
    if ch["target"] != {"node": 0, "path": "weights"} or gltf["nodes"][0]["mesh"] != 0 or s["interpolation"] != "LINEAR":
        fail("the channel must animate node 0's weights with LINEAR interpolation: %s %s" % (ch, s))
    times = accessor(gltf, bin_, s["input"], 5126, 1)
    W = accessor(gltf, bin_, s["output"], 5126, 1)
    if len(times) != T or len(W) != T * r:
        fail("%d keyframes and %d weights for %d frames of %d targets" % (len(times), len(W), T, r))
    for k in range(T):
        if times[k][0] != f32(k * f32(h)):
            fail("keyframe %d at %r s, not %r" % (k, times[k][0], k * h))

    err = scale = size = 0.0
    for k in range(T):
        w = [W[k * r + j][0] for j in range(r)]
        ref = start if k == 0 else frames[(k - 1) * 3 * n:k * 3 * n]
        for i in range(n):
            for a in range(3):
                x = X[i][a] + math.fsum(w[j] * D[j][i][a] for j in range(r))
                err = max(err, abs(x - ref[3 * i + a]))
                scale = max(scale, abs(ref[3 * i + a] - X[i][a]))
                size = max(size, abs(ref[3 * i + a]))
    units = err / (2.0 ** -24 * size) if size > 0 else math.inf
    print("frames %d, max |error| %.3g m = %.2f u P, displacement scale %.3g m, relative %.3g"
          % (T, err, units, scale, err / scale if scale > 0 else math.inf))
    sys.exit(0 if units <= ulps else 1)

if __name__ == "__main__":
    main()
