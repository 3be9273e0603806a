"""Splits every triangle of a closed OBJ surface into four at its edges' midpoints (the shape is
unchanged, 4x the triangles, V + E vertices): spot.obj's 11,533 vertices become 46,126, the size of
issue 32's 43k-vertex scan. Usage: python3 bench/subdivide_obj.py IN.obj OUT.obj"""
import sys


def main(src, dst):
    X, F = [], []
    for line in open(src):
        p = line.split()
        if not p:
            continue
        if p[0] == "v":
            X.append(tuple(float(t) for t in p[1:4]))
        elif p[0] == "f":
            idx = [int(t.split("/")[0]) - 1 for t in p[1:]]
            for k in range(1, len(idx) - 1):  # fan-triangulate polygons
                F.append((idx[0], idx[k], idx[k + 1]))
    mid = {}

    def midpoint(a, b):
        key = (min(a, b), max(a, b))
        if key not in mid:
            mid[key] = len(X)
            X.append(tuple(0.5 * (X[a][i] + X[b][i]) for i in range(3)))
        return mid[key]

    out = []
    for a, b, c in F:
        ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
        out += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
    with open(dst, "w") as f:
        f.write("# %s split 1:4 at edge midpoints (bench/subdivide_obj.py)\n" % src.split("/")[-1])
        for x in X:
            f.write("v %.17g %.17g %.17g\n" % x)
        for t in out:
            f.write("f %d %d %d\n" % (t[0] + 1, t[1] + 1, t[2] + 1))
    print("%s: %d vertices, %d triangles" % (dst, len(X), len(out)))


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])
