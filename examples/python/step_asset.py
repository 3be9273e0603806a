"""Steps a .rombin asset with the romkit runtime from Python and writes the shown surface of every
frame as OBJ files, the way a Blender or Houdini pipeline script would (the frames load as a mesh
sequence). Uses bindings/python/romrt.py (ctypes over build/lib/libromrt.so.*, and numpy).

    python3 examples/python/step_asset.py beam.rombin --steps 100 --out frames/ --push tip 0 0 5
    blender --background --python examples/python/step_asset.py -- beam.rombin --steps 100 --out frames/

Writes OUT/frame_00000.obj (the rest shape) to OUT/frame_NNNNN.obj, vertices with 9 significant
digits (float32 to the bit), faces from the asset's surface triangles. --push puts a force (N) on a
named group for the whole run; --koopman steps the asset's Koopman operator; --double the double
runtime.
"""
import argparse
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "bindings", "python"))
import romrt  # noqa: E402


def write_obj(path, xyz, tris):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.writelines("v %.9g %.9g %.9g\n" % (x, y, z) for x, y, z in xyz.tolist())
        f.writelines("f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in tris.tolist())
    os.replace(tmp, path)  # a reader never sees half a frame


def main(argv):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("asset")
    p.add_argument("--steps", type=int, default=100)
    p.add_argument("--out", required=True, help="folder for frame_NNNNN.obj")
    p.add_argument("--push", nargs=4, metavar=("GROUP", "FX", "FY", "FZ"), help="a force (N) on a named group")
    p.add_argument("--koopman", action="store_true", help="step the asset's Koopman operator")
    p.add_argument("--double", action="store_true", help="the double runtime (libromrt_double.so)")
    a = p.parse_args(argv)
    try:
        m = romrt.Model(a.asset, kind=romrt.KOOPMAN if a.koopman else None, double=a.double)
        if a.push:
            m.add_force(a.push[0], [float(v) for v in a.push[1:]])
        os.makedirs(a.out, exist_ok=True)
        tris = m.triangles()
        write_obj(os.path.join(a.out, "frame_00000.obj"), m.positions(), tris)
        for k in range(1, a.steps + 1):
            m.step()
            write_obj(os.path.join(a.out, "frame_%05d.obj" % k), m.positions(), tris)
    except (romrt.Error, KeyError, OSError) as e:
        print("step_asset: %s" % e, file=sys.stderr)
        return 1
    print("%s: %d frames of %d vertices, %d triangles, t = %.4g s, into %s"
          % (a.asset, a.steps + 1, m.shown_count, len(tris), m.time, a.out))
    return 0


if __name__ == "__main__":
    # Blender passes its own arguments first; the script's come after "--".
    sys.exit(main(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else sys.argv[1:]))
