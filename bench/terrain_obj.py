"""The benches' spiky terrain: a 40 x 40 heightfield of 3200 triangles over 0.3 x 0.3 m, random
heights up to 3 cm (a fixed LCG) with 6 cm spikes every 4th vertex, as an OBJ.
Usage: python3 bench/terrain_obj.py OUT.obj"""
import sys
n, seed, out = 40, 12345, []
for j in range(n + 1):
    for i in range(n + 1):
        seed = (seed * 1103515245 + 12345) & 0xFFFFFFFF
        h = 0.06 if i % 4 == 2 and j % 4 == 2 else 0.03 * ((seed >> 8) & 0xFFFF) / 65536.0
        out.append("v %.6f %.6f %.6f" % (-0.15 + 0.3 * i / n, h, -0.15 + 0.3 * j / n))
for j in range(n):
    for i in range(n):
        a = 1 + j * (n + 1) + i
        out += ["f %d %d %d" % (a, a + n + 1, a + 1), "f %d %d %d" % (a + 1, a + n + 1, a + n + 2)]
open(sys.argv[1], "w").write("\n".join(out) + "\n")
