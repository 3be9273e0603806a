#!/usr/bin/env python3
"""The pour's cloud at rest (tests/integration/runtime_pour.sh): from romkit run --frames, the
surface pieces that start in bench/pour_scene.py's slot SLOT (its 2 x 2 grid's quadrant, bottom
layer: the donut's splats there, whose shown surface is their contact surface) and their lowest y
in the last frame, the container's floor being y = 0.

Usage: pour_cloud_rest.py POUR.json SLOT FIRST.obj LAST.obj
Prints "LOWEST_Y TRIANGLES"; exits 1 naming what is wrong when the slot holds no cloud or no
surface starts there."""
import json
import sys


def read_obj(path):
    v, f = [], []
    with open(path) as src:
        for line in src:
            w = line.split()
            if w and w[0] == "v":
                v.append(tuple(float(x) for x in w[1:4]))
            elif w and w[0] == "f":
                f.append(tuple(int(x.split("/")[0]) - 1 for x in w[1:4]))
    return v, f


def components(nv, tris):
    parent = list(range(nv))

    def root(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for t in tris:
        for a in t[1:]:
            parent[root(a)] = root(t[0])
    out = {}
    for t in tris:
        out.setdefault(root(t[0]), set()).update(t)
    return list(out.values())


def main():
    scene, slot, first, last = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
    objects = json.load(open(scene))["objects"]
    if slot >= 4 or slot >= len(objects) or "points" not in objects[slot]["mesh"]:
        sys.exit("%s: objects[%d] is not a point cloud in the bottom layer" % (scene, slot))
    v0, tris = read_obj(first)
    v1, tris1 = read_obj(last)
    if len(v1) != len(v0) or tris1 != tris:
        sys.exit("%s and %s: not the same surface" % (first, last))
    # the quadrant of slot k (pour_scene.py: x < 0 for even slots, z > 0 from slot 2 on), bottom layer
    sx, sz = (-1 if slot % 2 == 0 else 1), (-1 if slot < 2 else 1)
    mine = set()
    for c in components(len(v0), tris):
        n = len(c)
        cx, cy, cz = (sum(v0[i][a] for i in c) / n for a in range(3))
        if cx * sx > 0 and cz * sz > 0 and cy < 0.15:
            mine |= c
    if not mine:
        sys.exit("%s: no surface starts in slot %d" % (first, slot))
    ntri = sum(1 for t in tris if t[0] in mine)
    print("%.9g %d" % (min(v1[i][1] for i in mine), ntri))


main()
