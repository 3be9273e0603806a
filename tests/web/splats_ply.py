"""splats_ply.py IN.ply OUT.ply: the fuzz seed's ASCII point lattice (x y z per line) as a binary
3DGS PLY (every point a Gaussian splat: colour, opacity, log-scales, a rotation), for make
test-web: a point-cloud asset whose SPLY chunk gaussian-splats-3d can read (it reads binary PLY
only). The splats are elongated along x and rotated a little, so F Sigma F^T is not a scaling."""
import math
import struct
import sys

src, dst = sys.argv[1], sys.argv[2]
with open(src) as f:
    lines = f.read().split('\n')
end = lines.index('end_header')
points = [tuple(map(float, l.split())) for l in lines[end + 1:] if l.strip()]
props = ['x', 'y', 'z', 'f_dc_0', 'f_dc_1', 'f_dc_2', 'opacity', 'scale_0', 'scale_1', 'scale_2',
         'rot_0', 'rot_1', 'rot_2', 'rot_3']
header = 'ply\nformat binary_little_endian 1.0\nelement vertex %d\n' % len(points)
header += ''.join('property float %s\n' % p for p in props) + 'end_header\n'
with open(dst, 'wb') as f:
    f.write(header.encode('ascii'))
    for i, (x, y, z) in enumerate(points):
        half = 0.2 * (i % 5) / 2  # a rotation about z of 0 to 0.8 rad
        f.write(struct.pack('<14f', x, y, z, 1.2 * x * 10 - 0.6, 0.2, 0.8 - 10 * x, 4.0,
                            math.log(0.015), math.log(0.006), math.log(0.006),
                            math.cos(half), 0.0, 0.0, math.sin(half)))
