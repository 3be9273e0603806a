#!/usr/bin/env python3
"""Writes issue 30's pour scene: N soft objects dropped in a loose stack into an open mesh box.

Usage: python3 bench/pour_scene.py [--meshes] DIR N [DURATION]
(--meshes: boxes in the clouds' slots too, the mesh-only pour of before the clouds, exactly
integrated with default kernels: tests/integration/runtime_pour.sh's float floor check)
Writes DIR/container.obj (an open box, 0.4 x 0.3 x 0.4 m, 10 triangles: a triangle-mesh obstacle),
DIR/donut.ply (the splat capture tests/data/meshes/donut_3dgs.ply, every STRIDE-th splat, turned
so its axis is the scene's y) and DIR/pour.json. The objects sit in layers of 4 on a 2 x 2 grid,
15 cm apart in height and shifted 1 cm per layer so no two faces start aligned: boxes of different
sizes and stiffness (2 x 2 x 2 cells each), the donut's splats as a point cloud in slots 2 and 5
(two sizes: from N = 3 on, one lands on the container, from N = 6 on the other on a box) and, from
N = 8 on, tests/data/meshes/octopus-low.mesh scaled to 12 cm in the top layer: 8 objects are 5
boxes, 2 splat clouds and the octopus. Every object gets its own skinning basis (rkpm_skinning,
size 1: 24 columns each, r = 24 N; an RKPM basis with several objects is each object's own,
docs/scene.md). A scene with a cloud is mesh-free (docs/scene.md): every object's elastic energy
and mass are integrated at MESH_FREE_POINTS points of its own (a grid clipped to a mesh, a subset
of a cloud's points), exactly, no cubature. A cloud collides through its contact surface, the
voxels of PROXY_VOXEL that hold its points (5 mm from them). dt = 1/60 s.
"""
import json
import math
import os
import struct
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
W, HEIGHT = 0.2, 0.3  # the container's half width and wall height (m)
SIZES = [(0.1, 0.06, 0.1), (0.08, 0.08, 0.08), (0.12, 0.05, 0.08), (0.07, 0.1, 0.07),
         (0.09, 0.07, 0.11), (0.1, 0.1, 0.06), (0.06, 0.06, 0.12), (0.11, 0.08, 0.09)]
OCTOPUS = os.path.join(HERE, "..", "tests", "data", "meshes", "octopus-low.mesh")
DONUT = os.path.join(HERE, "..", "tests", "data", "meshes", "donut_3dgs.ply")
# The clouds: slot -> the donut's scale (its capture is 0.21 x 0.21 x 0.095 m: 9.5 and 8.4 cm across).
CLOUDS = {2: 0.45, 5: 0.4}
STRIDE = 16  # 45,624 splats -> 2,852: a capture's density is far past what its motion needs
PROXY_VOXEL = 0.01  # the clouds' contact-surface voxel (m), as test_runtime_cloud_mesh's donut
MESH_FREE_POINTS = 200  # integration points per object
KERNELS = 40  # RKPM kernels per object: (default 1000) on 2,852 splats their supports miss the surface 5 mm off


def container(path):
    v = [(-W, 0, -W), (W, 0, -W), (W, 0, W), (-W, 0, W), (-W, HEIGHT, -W), (W, HEIGHT, -W), (W, HEIGHT, W),
         (-W, HEIGHT, W)]
    f = [(1, 3, 2), (1, 4, 3), (1, 2, 6), (1, 6, 5), (2, 3, 7), (2, 7, 6), (3, 4, 8), (3, 8, 7), (4, 1, 5), (4, 5, 8)]
    with open(path, "w") as out:
        out.write("".join("v %g %g %g\n" % p for p in v) + "".join("f %d %d %d\n" % t for t in f))


def donut(path):
    """Every STRIDE-th splat of the capture, turned -90 degrees about x (its z, the donut's axis,
    becomes y, the scene's up): positions and the splats' orientations (rot_0..3, w x y z) turned
    alike, the other properties kept. Returns the turned splats' bounding box (lo, hi)."""
    with open(DONUT, "rb") as f:
        header = b""
        while not header.endswith(b"end_header\n"):
            line = f.readline()
            if not line:
                sys.exit("pour_scene.py: %s: no end_header" % DONUT)
            header += line
        data = f.read()
    props = [l.split()[-1] for l in header.decode().splitlines() if l.startswith("property float")]
    if props[:3] != ["x", "y", "z"] or props[-4:] != ["rot_0", "rot_1", "rot_2", "rot_3"]:
        sys.exit("pour_scene.py: %s: expected float x y z ... rot_0..3 splats" % DONUT)
    width = 4 * len(props)
    c = math.sqrt(0.5)  # the turn's quaternion (cos -45, sin -45 about x)
    rows, lo, hi = [], [math.inf] * 3, [-math.inf] * 3
    for i in range(0, len(data) // width, STRIDE):
        v = list(struct.unpack_from("<%df" % len(props), data, width * i))
        x, y, z = v[:3]
        v[:3] = [x, z, -y]
        w, a, b, d = v[-4:]
        v[-4:] = [c * (w + a), c * (a - w), c * (b + d), c * (d - b)]  # (c, -c, 0, 0) * (w, a, b, d)
        for j in range(3):
            lo[j], hi[j] = min(lo[j], v[j]), max(hi[j], v[j])
        rows.append(struct.pack("<%df" % len(props), *v))
    with open(path, "wb") as out:
        out.write(b"ply\nformat binary_little_endian 1.0\ncomment every %d-th splat of donut_3dgs.ply, turned "
                  b"-90 degrees about x\nelement vertex %d\n" % (STRIDE, len(rows)))
        out.write(b"".join(b"property float %s\n" % p.encode() for p in props) + b"end_header\n")
        out.write(b"".join(rows))
    return lo, hi


def objects(n, cloud, box):
    out = []
    for k in range(n):
        layer, slot = divmod(k, 4)
        cx, cz = (-0.09 if slot % 2 == 0 else 0.09), (-0.09 if slot < 2 else 0.09)
        y = 0.01 + 0.15 * layer
        material = {"model": "neohookean", "young": 1e5 * (1 + 0.5 * (k % 3)), "poisson": 0.4, "density": 1000}
        if k in CLOUDS and cloud:  # the donut's splats, its lowest point at y, centred over the slot
            s, (lo, hi) = CLOUDS[k], box
            t = [cx + 0.01 * layer - s * (lo[0] + hi[0]) / 2, y - s * lo[1], cz - 0.01 * layer - s * (lo[2] + hi[2]) / 2]
            out.append({"mesh": {"points": cloud, "scale": s, "proxy_voxel": PROXY_VOXEL, "translate": t},
                        "material": material})
            continue
        if k == 7:  # the octopus (about 1 x 0.74 x 0.55 m, centred near 0): 12 cm across
            s = 0.12
            out.append({"mesh": {"file": os.path.abspath(OCTOPUS), "scale": s,
                                 "translate": [cx + 0.01 * layer, y + 0.32 * s, cz - 0.01 * layer]},
                        "material": material})
            continue
        sx, sy, sz = SIZES[k % len(SIZES)]
        out.append({"mesh": {"box": {"size": [sx, sy, sz], "cells": [2, 2, 2]},
                             "translate": [cx - sx / 2 + 0.01 * layer, y, cz - sz / 2 - 0.01 * layer]},
                    "material": material})
    return out


def main():
    args = sys.argv[1:]
    meshes = "--meshes" in args
    args = [a for a in args if a != "--meshes"]
    if len(args) not in (2, 3):
        sys.exit("usage: pour_scene.py [--meshes] DIR N [DURATION]")
    d, n = args[0], int(args[1])
    duration = float(args[2]) if len(args) == 3 else 2.5
    if not 1 <= n <= 10:
        sys.exit("pour_scene.py: N must be 1 to 10 (r = 24 N within the runtime's 256)")
    container(os.path.join(d, "container.obj"))
    cloud, box, rom = None, None, {"basis": "rkpm_skinning", "size": 1}
    if not meshes and any(k < n for k in CLOUDS):
        cloud = os.path.abspath(os.path.join(d, "donut.ply"))
        box = donut(cloud)
        rom.update({"kernels": KERNELS, "mesh_free": {"points": MESH_FREE_POINTS}})
    scene = {"objects": objects(n, cloud, box), "gravity": [0, -9.81, 0], "damping": {"mass": 2},
             "obstacles": [{"mesh": {"file": os.path.abspath(os.path.join(d, "container.obj"))}}],
             "contact": {"dhat": 0.002, "friction": 0.3}, "time": {"step": 1 / 60, "duration": duration},
             "rom": rom}
    with open(os.path.join(d, "pour.json"), "w") as out:
        json.dump(scene, out, indent=1)


if __name__ == "__main__":
    main()
