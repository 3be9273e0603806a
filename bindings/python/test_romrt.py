"""Tests of the romrt Python binding, run by tests/integration/python_binding.sh, which makes the
files named on the command line with the C side (romkit run --snapshots, build/rt_push). Prints
"ok NAME" or "FAIL NAME: why" per check.

usage: test_romrt.py DIR   (DIR holds beam.rombin, run.npy, run_double.npy, push.raw, koop.rombin,
                            koop.npy, frames/ from examples/python/step_asset.py)
"""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import romrt  # noqa: E402

D = sys.argv[1]
failures = 0


def check(name, cond, why=""):
    global failures
    print("ok %s" % name if cond else "FAIL %s: %s" % (name, why))
    failures += not cond


def attempt(name, fn):
    """Runs fn() -> (cond, why); an exception is a failure naming it."""
    try:
        cond, why = fn()
    except Exception as e:  # noqa: BLE001 (a test reports whatever went wrong)
        cond, why = False, "%s: %s" % (type(e).__name__, e)
    check(name, cond, why)


def frames(model, steps):
    out = np.empty((steps, model.shown_count, 3), dtype=model.dtype)
    for k in range(steps):
        model.step()
        model.positions(out=out[k])
    return out


def first_difference(a, b):
    if a.shape != b.shape:
        return "shapes %s and %s" % (a.shape, b.shape)
    bad = np.argwhere(a != b)
    if len(bad) == 0:
        return ""
    i = tuple(bad[0])
    return "%d values differ, first at %s: %r against %r" % (len(bad), i, a[i], b[i])


beam = os.path.join(D, "beam.rombin")


# 1. The same steps as `romkit run --snapshots` (the C runtime, float): bit for bit.
def same_as_romkit_run():
    ref = np.load(os.path.join(D, "run.npy"))  # float64 holding the runtime's float32 positions
    m = romrt.Model(beam)
    got = frames(m, ref.shape[0]).astype(np.float64)
    why = first_difference(got, ref)
    return not why and m.dtype == np.float32, why


attempt("positions_equal_romkit_run_bit_for_bit", same_as_romkit_run)


# 2. Pushes (a group force, a vertex force, cleared half-way) against the same calls from C.
def same_pushes_as_c():
    m = romrt.Model(beam)
    ref = np.fromfile(os.path.join(D, "push.raw"), dtype=np.float32)
    steps = 30
    ref = ref.reshape(steps, m.shown_count, 3)
    m.add_force("tip", [0, 0, 0.05])
    m.add_vertex_force(7, [0.1, 0, 0.02])
    got = np.empty_like(ref)
    for k in range(steps):
        if k == 15:
            m.clear_forces()
        m.step()
        m.positions(out=got[k])
    why = first_difference(got, ref)
    moved = float(np.abs(got[-1] - m.rest_positions()).max())
    return not why and moved > 1e-4, why or "nothing moved (%g)" % moved


attempt("pushed_positions_equal_the_c_runtime_bit_for_bit", same_pushes_as_c)


# 3. A Koopman asset: steps as romkit run does, and a jump lands where single steps do (to rounding).
def koopman_steps():
    ref = np.load(os.path.join(D, "koop.npy"))
    m = romrt.Model(os.path.join(D, "koop.rombin"))
    got = frames(m, ref.shape[0]).astype(np.float64)
    why = first_difference(got, ref)
    if why:
        return False, why
    state = m.get_state()
    m.step(100)
    a = m.positions().copy()
    m.set_state(state)
    m.jump(100)
    b = m.positions()
    scale = float(np.abs(a - m.rest_positions()).max())
    rel = float(np.abs(a - b).max()) / scale
    return m.kind == romrt.KOOPMAN and rel < 1e-3, "jump against steps %g, kind %d" % (rel, m.kind)


attempt("koopman_positions_equal_romkit_run_bit_for_bit", koopman_steps)


# 4. The double runtime when asked: float64 positions equal to romkit-double run's.
def double_runtime():
    ref = np.load(os.path.join(D, "run_double.npy"))
    m = romrt.Model(beam, double=True)
    got = frames(m, ref.shape[0])
    why = first_difference(got, ref)
    return not why and m.dtype == np.float64 and "double" in os.path.basename(m.library), why or m.library


attempt("double_runtime_equals_romkit_double_run_bit_for_bit", double_runtime)


# 5. State, clock, reduced coordinates and the GPU accessors.
def state_and_accessors():
    m = romrt.Model(beam)
    m.set_hessian_reuse(1)  # bit-for-bit replay needs a fresh Newton matrix (romrt.h, romrt_set_state)
    m.add_force("tip", [0, 0.02, 0.05])
    m.step(10)
    s = m.get_state()
    m.step(5)
    a = m.positions().copy()
    t = m.time
    m.set_state(s)
    m.step(5)
    if not np.array_equal(a, m.positions()) or m.time != t:
        return False, "a restored state did not replay the same"
    if abs(t - 15 * m.time_step) > 1e-9:
        return False, "clock %r after 15 steps of %r" % (t, m.time_step)
    X, U, q = m.rest_positions(), m.basis_rows(), m.reduced_coordinates()
    x = X.astype(np.float64) + np.einsum("nkj,j->nk", U.astype(np.float64), q.astype(np.float64))
    rel = float(np.abs(x - m.positions()).max() / np.abs(m.positions() - X).max())
    inter = np.zeros((m.shown_count, 8), dtype=np.float32)
    m.positions(out=inter)
    same = np.array_equal(inter[:, :3], m.positions()) and not inter[:, 3:].any()
    return rel < 1e-5 and same and U.shape == (m.shown_count, 3, m.r), "X + U q off by %g; interleaved %s" % (rel, same)


attempt("state_clock_and_gpu_accessors", state_and_accessors)


# 6. Errors: the runtime's message in a Python exception; a short buffer refused, nothing written.
def errors():
    data = bytearray(open(beam, "rb").read())
    data[len(data) // 2] ^= 0xFF
    try:
        romrt.Model(bytes(data))
        return False, "a damaged asset opened"
    except romrt.Error as e:
        if e.status != "damaged asset" or "CRC" not in e.message or not e.chunk:
            return False, "damaged: %s / %r / %r" % (e.status, e.message, e.chunk)
    try:
        romrt.Model(b"not an asset at all, just bytes")
        return False, "text opened"
    except romrt.Error as e:
        if not e.message:
            return False, "no message"
    m = romrt.Model(beam)
    short = np.full((m.shown_count - 1, 3), 7.0, dtype=np.float32)
    try:
        m.positions(out=short)
        return False, "a buffer one vertex short was accepted"
    except romrt.Error as e:
        if e.status != "bad argument" or (short != 7).any():
            return False, "short buffer: %s, written: %s" % (e, (short != 7).any())
    for bad in (lambda: m.add_force("no such group", [0, 0, 1]), lambda: m.add_vertex_force(m.shown_count, [0, 0, 1]),
                lambda: m.add_force("tip", [np.nan, 0, 0])):
        try:
            bad()
            return False, "a bad push was accepted"
        except (romrt.Error, KeyError):
            pass
    try:
        romrt.Model(open(beam, "rb").read(), kind=romrt.KOOPMAN)
        return False, "a reduced-only asset opened as Koopman"
    except romrt.Error as e:
        if e.status != "unsupported asset feature":
            return False, str(e)
    try:
        m.jump(10)
        return False, "a reduced model jumped"
    except romrt.Error as e:
        if "Koopman" not in e.message:
            return False, "jump: %s" % e
    return True, ""


attempt("errors_raise_with_the_runtime_message", errors)


# The Newton modes through the binding: a matrix kept 10 steps stays near the fresh run; -1 is refused.
def newton_modes():
    fresh = frames(romrt.Model(beam), 20)
    m = romrt.Model(beam)
    m.set_newton_iterations(1)
    m.set_hessian_reuse(10)
    kept = frames(m, 20)
    m2 = romrt.Model(beam)  # romrt_step_info through its size field: the mode in force, and its work
    m2.set_newton_iterations(1)
    m2.set_hessian_reuse(10)
    work = []
    for _ in range(20):
        m2.step()
        work.append(m2.last_step())
    built = sum(w["factorizations"] for w in work)
    # built at step 1 and again 10 steps on (and at BDF2's second step, whose inertia weight changes)
    if work[-1]["hessian_reuse"] != 10 or not 2 <= built <= 3 or sum(w["newton_iterations"] for w in work) != 20:
        return False, "20 steps of one iteration, a matrix kept 10 steps: %d factorizations, %s" % (built, work[-1])
    scale = np.abs(fresh - fresh[0]).max() + 1e-30
    drift = np.abs(kept - fresh).max() / scale
    try:
        m.set_hessian_reuse(-1)
        return False, "-1 accepted"
    except romrt.Error as e:
        if "romrt_set_hessian_reuse" not in e.message:
            return False, str(e)
    return np.isfinite(kept).all() and drift < 0.05, "kept matrix drifts %.3g of the motion" % drift


attempt("newton_modes_through_the_binding", newton_modes)


# 7. The library checks: version, precision names.
def library():
    v = romrt.version()
    header = open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "runtime", "romrt.h")).read()
    want = [int(line.split()[2]) for line in header.splitlines()
            if line.startswith("#define ROMRT_VERSION_M") or line.startswith("#define ROMRT_VERSION_PATCH")]
    try:  # the double runtime's path given as the float one is refused, not misread
        romrt.load_library(False, romrt.load_library(True)[4])
        return False, "the double library loaded as float"
    except OSError:
        pass
    lim = romrt.limits()  # the library's, not a header macro
    if lim["max_reduced_size"] != 512 or lim["collider_slots"] != 8:
        return False, "limits %s" % lim
    return v == want[0] * 10000 + want[1] * 100 + want[2], "version %d, header %s" % (v, want)


attempt("version_and_precision_of_the_library", library)


# 8. The example script's OBJ frames: every frame written, the last one where the binding puts it.
def example_frames():
    folder = os.path.join(D, "frames")
    names = sorted(f for f in os.listdir(folder) if f.endswith(".obj"))
    m = romrt.Model(beam)
    m.add_force("tip", [0, 0, 0.05])
    m.step(12)
    last = np.array([[float(v) for v in line.split()[1:]] for line in open(os.path.join(folder, names[-1]))
                     if line.startswith("v ")])
    faces = sum(1 for line in open(os.path.join(folder, names[-1])) if line.startswith("f "))
    ok = len(names) == 13 and last.shape == (m.shown_count, 3) and faces == m.triangle_count \
        and np.array_equal(last.astype(np.float32), m.positions())
    return ok, "%d frames, last %s, %d faces" % (len(names), last.shape, faces)


attempt("example_writes_obj_frames", example_frames)

sys.exit(1 if failures else 0)
