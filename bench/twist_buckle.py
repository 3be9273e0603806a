"""When the 720-degree twist buckles, and where each reduced run's error comes from (issue 37).

    python3 bench/twist_buckle.py REFERENCE.npy RUN.npy [RUN.npy ...]

REFERENCE.npy: a full-order run, every frame from the start ((T + 1) x n x 3 float64: bench_reference
run, or romkit compare --reference-frames); RUN.npy: a runtime run's frames after each step (romkit
run --snapshots on an asset that shows every vertex: T x n x 3). Per 0.2 s window (20 steps of the
scene's 0.01 s): the centreline's largest sideways move (each cross-section's centroid, by the rest x
of its vertices, off its rest place in y and z, m), the reference's and each run's, and each run's
normalized MSE over the window (util.h's metric: mean squared vertex error over the squared rest
bounding-box diagonal). Python standard library only.
"""
import array, ast, sys
def load(p):
    f = open(p, 'rb'); f.read(6); maj = f.read(2)[0]
    hl = int.from_bytes(f.read(2 if maj == 1 else 4), 'little')
    h = ast.literal_eval(f.read(hl).decode()); a = array.array('d'); a.frombytes(f.read())
    return h['shape'], a
def frames(p):
    s, a = load(p); T, n = s[0], s[1]
    return [a[t*n*3:(t+1)*n*3] for t in range(T)], n
ref, n = frames(sys.argv[1])
X = ref[0]
lo = [min(X[i::3]) for i in range(3)]; hi = [max(X[i::3]) for i in range(3)]
D2 = sum((h - l) ** 2 for h, l in zip(hi, lo))
slices = {}
for i in range(n): slices.setdefault(round(X[3*i], 6), []).append(i)
def side(F):  # the centreline's largest sideways move (a section's centroid, y and z), m
    best = 0
    for ids in slices.values():
        dy = sum(F[3*i+1] - X[3*i+1] for i in ids) / len(ids); dz = sum(F[3*i+2] - X[3*i+2] for i in ids) / len(ids)
        best = max(best, (dy*dy + dz*dz) ** 0.5)
    return best
runs = [(p, [ref[0]] + frames(p)[0]) for p in sys.argv[2:]]  # the runtime's snapshots start after step 1
print('window_s  ref_side_m ' + ' '.join('%s_side %s_nmse' % (p.split('/')[-1], p.split('/')[-1]) for p, _ in runs))
for w0 in range(0, 200, 20):
    ts = range(w0 + 1, w0 + 21)
    row = ['%.1f-%.1f' % (w0 / 100, (w0 + 20) / 100), '%.3f' % max(side(ref[t]) for t in ts if t < len(ref))]
    for p, R in runs:
        e = 0
        for t in ts: e += sum((R[t][k] - ref[t][k]) ** 2 for k in range(3 * n)) / n
        row += ['%.3f' % max(side(R[t]) for t in ts), '%.2e' % (e / len(ts) / D2)]
    print('  '.join(row))
