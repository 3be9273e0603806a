#!/usr/bin/env python3
"""Writes issue 30's pour scene: N soft objects dropped in a loose stack into an open mesh box.

Usage: python3 bench/pour_scene.py DIR N [DURATION]
Writes DIR/container.obj (an open box, 0.4 x 0.3 x 0.4 m, 10 triangles: a triangle-mesh obstacle)
and DIR/pour.json. The objects sit in layers of 4 on a 2 x 2 grid, 15 cm apart in height and shifted
1 cm per layer so no two faces start aligned: boxes of different sizes and stiffness (2 x 2 x 2
cells each) and, from N = 8 on, tests/data/meshes/octopus-low.mesh scaled to 12 cm in the top
layer. Every object gets its own skinning basis (rkpm_skinning, size 1: 24 columns each, r = 24 N;
an RKPM basis with several objects is each object's own, docs/scene.md). No cubature: 2 x 2 x 2
boxes have 48 tets each, all integrated exactly (the octopus's 1140 tets too). dt = 1/60 s.
Point clouds: splat clouds will share scenes with meshes (branch cloud-mesh); a cloud is one more
entry of OBJECTS below, {"mesh": {"points": PLY}, ...}, with "mesh_free" as docs/scene.md says.
"""
import json
import os
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
W, HEIGHT = 0.2, 0.3  # the container's half width and wall height (m)
SIZES = [(0.1, 0.06, 0.1), (0.08, 0.08, 0.08), (0.12, 0.05, 0.08), (0.07, 0.1, 0.07),
         (0.09, 0.07, 0.11), (0.1, 0.1, 0.06), (0.06, 0.06, 0.12), (0.11, 0.08, 0.09)]
OCTOPUS = os.path.join(HERE, "..", "tests", "data", "meshes", "octopus-low.mesh")


def container(path):
    v = [(-W, 0, -W), (W, 0, -W), (W, 0, W), (-W, 0, W), (-W, HEIGHT, -W), (W, HEIGHT, -W), (W, HEIGHT, W),
         (-W, HEIGHT, W)]
    f = [(1, 3, 2), (1, 4, 3), (1, 2, 6), (1, 6, 5), (2, 3, 7), (2, 7, 6), (3, 4, 8), (3, 8, 7), (4, 1, 5), (4, 5, 8)]
    with open(path, "w") as out:
        out.write("".join("v %g %g %g\n" % p for p in v) + "".join("f %d %d %d\n" % t for t in f))


def objects(n):
    out = []
    for k in range(n):
        layer, slot = divmod(k, 4)
        cx, cz = (-0.09 if slot % 2 == 0 else 0.09), (-0.09 if slot < 2 else 0.09)
        y = 0.01 + 0.15 * layer
        material = {"model": "neohookean", "young": 1e5 * (1 + 0.5 * (k % 3)), "poisson": 0.4, "density": 1000}
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
    if len(sys.argv) not in (3, 4):
        sys.exit("usage: pour_scene.py DIR N [DURATION]")
    d, n = sys.argv[1], int(sys.argv[2])
    duration = float(sys.argv[3]) if len(sys.argv) == 4 else 2.5
    if not 1 <= n <= 10:
        sys.exit("pour_scene.py: N must be 1 to 10 (r = 24 N within the runtime's 256)")
    container(os.path.join(d, "container.obj"))
    scene = {"objects": objects(n), "gravity": [0, -9.81, 0], "damping": {"mass": 2},
             "obstacles": [{"mesh": {"file": os.path.abspath(os.path.join(d, "container.obj"))}}],
             "contact": {"dhat": 0.002, "friction": 0.3}, "time": {"step": 1 / 60, "duration": duration},
             "rom": {"basis": "rkpm_skinning", "size": 1}}
    with open(os.path.join(d, "pour.json"), "w") as out:
        json.dump(scene, out, indent=1)


main()
