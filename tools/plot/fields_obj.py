#!/usr/bin/env python3
"""A frame's surface (romkit adaptive --frames) as gnuplot pm3d triangles coloured by a per-vertex field.

usage: fields_obj.py FRAME.obj SNAPSHOTS.npy FIELDS.npy FRAME COLUMN

The OBJ holds the boundary's vertices renumbered (precompute/mesh/write.c); each is matched to its
mesh vertex by its position in the snapshots' frame FRAME (written round-trip exact, so equality is
exact). Prints each triangle (a face fanned into triangles) as a pm3d patch of corners "x y z value"
(value: column 1, the enriched flag, as it is; column 2, the oracle's error G, or 3, its progress E,
as log10, -3 at the least, 0 the threshold; a step that ran no oracle has NaN there, printed as
"nan" and left undrawn): scans (a, b) and (c, c), each patch its own data set (two blank lines):
gnuplot's `with polygons` takes no colour per face, pm3d does (the corners' mean).
"""
import array
import ast
import math
import struct
import sys


def npy(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:6] != b"\x93NUMPY":
        sys.exit(f"{path}: not a .npy file")
    major = data[6]
    size_len = 2 if major == 1 else 4
    hlen = struct.unpack("<H" if major == 1 else "<I", data[8:8 + size_len])[0]
    start = 8 + size_len + hlen
    header = ast.literal_eval(data[8 + size_len:start].decode("latin1"))
    if header["descr"] != "<f8" or header["fortran_order"] or len(header["shape"]) != 3:
        sys.exit(f"{path}: expected a C-order float64 array of frames x vertices x 3, got {header}")
    values = array.array("d")
    values.frombytes(data[start:])
    return header["shape"], values


def shown(value, column):
    if math.isnan(value):
        return "nan"
    return f"{value:g}" if column == 1 else f"{math.log10(max(value, 1e-3)):.4g}"


def main():
    if len(sys.argv) != 6:
        sys.exit(__doc__.strip().split("\n")[2])
    obj, snapshots, fields, frame, column = sys.argv[1:4] + [int(sys.argv[4]), int(sys.argv[5])]
    (nf, nv, _), x = npy(snapshots)
    (nf2, nv2, _), fld = npy(fields)
    if (nf, nv) != (nf2, nv2) or not 0 <= frame < nf or column not in (1, 2, 3):
        sys.exit(f"snapshots {nf} x {nv}, fields {nf2} x {nv2}, frame {frame}, column {column}: do not fit")
    where = {}
    for v in range(nv):
        o = 3 * (frame * nv + v)
        where.setdefault((x[o], x[o + 1], x[o + 2]), v)
    verts, out = [], []
    with open(obj) as f:
        for line in f:
            p = line.split()
            if p and p[0] == "v":
                key = tuple(float(c) for c in p[1:4])
                if key not in where:
                    sys.exit(f"{obj}: vertex {len(verts) + 1} at {key} is not at any mesh vertex of frame {frame}")
                verts.append((key, fld[3 * (frame * nv + where[key]) + column - 1]))
            elif p and p[0] == "f":
                corners = [verts[int(c.split("/")[0]) - 1] for c in p[1:]]
                for k in range(1, len(corners) - 1):
                    a, b, c = corners[0], corners[k], corners[k + 1]
                    for corner in (a, b, None, c, c, None, None):
                        if corner is None:
                            out.append("")
                        else:
                            (px, py, pz), value = corner
                            out.append(f"{px:.6g} {py:.6g} {pz:.6g} {shown(value, column)}")
    sys.stdout.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
