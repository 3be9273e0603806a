#!/usr/bin/env python3
"""The adaptive simulator's enrichment drawn (issue 34): one frame of `romkit adaptive`'s output,
its boundary surface (--frames DIR, an OBJ per frame, its vertices matched to the mesh's by
position in --snapshots) rasterised orthographically with flat shading, a triangle red where any
of its vertices is enriched in --fields (column 0), grey elsewhere. Standard library only (zlib
writes the PNG).

Usage: enrichment_png.py FIELDS.npy SNAPSHOTS.npy FRAMES_DIR OUT.png [frame (default: the most
       enriched)] [view axis x|y|z (default z)] [width (default 640)]"""
import ast, math, os, struct, sys, zlib


def read_npy(path):
    with open(path, "rb") as f:
        data = f.read()
    if data[:6] != b"\x93NUMPY":
        sys.exit(f"{path}: not a .npy file")
    major = data[6]
    hlen = struct.unpack("<H" if major == 1 else "<I", data[8:10] if major == 1 else data[8:12])[0]
    start = 10 if major == 1 else 12
    header = ast.literal_eval(data[start:start + hlen].decode("latin1"))
    if header["descr"] != "<f8" or header["fortran_order"]:
        sys.exit(f"{path}: expected C-ordered float64")
    shape = header["shape"]
    count = 1
    for s in shape:
        count *= s
    return shape, struct.unpack(f"<{count}d", data[start + hlen:start + hlen + 8 * count])


def read_obj(path):
    verts, tris = [], []
    for line in open(path):
        p = line.split()
        if not p:
            continue
        if p[0] == "v":
            verts.append(tuple(float(x) for x in p[1:4]))
        elif p[0] == "f":
            idx = [int(x.split("/")[0]) - 1 for x in p[1:]]
            for k in range(1, len(idx) - 1):
                tris.append((idx[0], idx[k], idx[k + 1]))
    return verts, tris


def write_png(path, w, h, rgb):
    raw = b"".join(b"\x00" + bytes(rgb[y * w * 3:(y + 1) * w * 3]) for y in range(h))
    def chunk(tag, body):
        return struct.pack(">I", len(body)) + tag + body + struct.pack(">I", zlib.crc32(tag + body) & 0xffffffff)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b""))


def main():
    if len(sys.argv) < 5:
        sys.exit(__doc__)
    fields_path, snap_path, frames_dir, out = sys.argv[1:5]
    args = sys.argv[5:]
    (frames, nv, _), fields = read_npy(fields_path)
    _, snaps = read_npy(snap_path)
    enriched = [[fields[(f * nv + v) * 3] > 0.5 for v in range(nv)] for f in range(frames)]
    frame = int(args[0]) if len(args) > 0 else max(range(frames), key=lambda f: sum(enriched[f]))
    axis = "xyz".index(args[1]) if len(args) > 1 else 2
    width = int(args[2]) if len(args) > 2 else 640
    verts, tris = read_obj(os.path.join(frames_dir, "frame_%05d.obj" % frame))
    # the OBJ holds the boundary vertices: each one's mesh vertex by its position at the frame
    at = {}
    for i in range(nv):
        at[tuple(round(snaps[(frame * nv + i) * 3 + k], 9) for k in range(3))] = i
    mesh_id = [at.get(tuple(round(c, 9) for c in p), -1) for p in verts]
    if min(mesh_id) < 0:
        sys.exit(f"frame {frame}: {mesh_id.count(-1)} OBJ vertices match no mesh vertex")
    flag = [enriched[frame][mesh_id[i]] for i in range(len(verts))]
    u, v = [a for a in range(3) if a != axis]
    used = sorted({i for t in tris for i in t})
    lo_u, hi_u = min(verts[i][u] for i in used), max(verts[i][u] for i in used)
    lo_v, hi_v = min(verts[i][v] for i in used), max(verts[i][v] for i in used)
    scale = (width - 20) / max(hi_u - lo_u, 1e-12)
    height = int((hi_v - lo_v) * scale) + 20
    rgb = bytearray([255] * (width * height * 3))
    depth = [-math.inf] * (width * height)
    light = (0.3, 0.5, 0.8)
    for t in tris:
        a, b, c = (verts[i] for i in t)
        e1 = [b[k] - a[k] for k in range(3)]
        e2 = [c[k] - a[k] for k in range(3)]
        n = [e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]]
        ln = math.sqrt(sum(x * x for x in n)) or 1
        shade = 0.35 + 0.65 * abs(sum(n[k] * light[k] for k in range(3))) / ln
        red = any(flag[i] for i in t)
        col = (int(230 * shade), int(60 * shade), int(50 * shade)) if red else (int(190 * shade),) * 3
        pts = [((p[u] - lo_u) * scale + 10, height - 10 - (p[v] - lo_v) * scale, p[axis]) for p in (a, b, c)]
        x0, x1 = max(0, int(min(p[0] for p in pts))), min(width - 1, int(max(p[0] for p in pts)) + 1)
        y0, y1 = max(0, int(min(p[1] for p in pts))), min(height - 1, int(max(p[1] for p in pts)) + 1)
        (ax, ay, az), (bx, by, bz), (cx, cy, cz) = pts
        area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)
        if abs(area) < 1e-12:
            continue
        for y in range(y0, y1 + 1):
            for x in range(x0, x1 + 1):
                w0 = ((bx - x) * (cy - y) - (by - y) * (cx - x)) / area
                w1 = ((cx - x) * (ay - y) - (cy - y) * (ax - x)) / area
                w2 = 1 - w0 - w1
                if w0 < 0 or w1 < 0 or w2 < 0:
                    continue
                z = w0 * az + w1 * bz + w2 * cz
                k = y * width + x
                if z > depth[k]:
                    depth[k] = z
                    rgb[3 * k:3 * k + 3] = bytes(col)
    write_png(out, width, height, rgb)
    print(f"{out}: frame {frame}, {sum(enriched[frame])} of {nv} vertices enriched")


main()
