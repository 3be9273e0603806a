"""romrt: the romkit runtime (runtime/romrt.h) from Python, through ctypes and numpy.

Steps a .rombin asset baked by `romkit build` exactly as a C application does: the same shared
library (build/lib/libromrt.so.*, or an installed libromrt.so), so positions are the C runtime's
to the bit. No compiled extension, nothing from PyPI: the standard library's ctypes and numpy.

    import romrt
    m = romrt.Model("beam.rombin")          # or bytes; the asset is copied and kept alive
    m.add_force("tip", [0, 0, 5])           # newtons on a named group, until cleared
    for frame in range(100):
        m.step()
        x = m.positions()                   # (shown, 3) float32 (float64 with double=True)
    tris = m.triangles()                    # (triangles, 3) int32 indices into the shown vertices

Precision: the float library by default; Model(..., double=True) loads the double one
(libromrt_double.so.*, built beside it by `make all`). The library's functions carry the precision
in their names (romrt_f32_step, romrt_f64_step), and the binding calls the ones of the library it
loaded, so a float array can never be handed to a double runtime.

Where the library is found: the `library` argument, else $ROMRT_LIBRARY (float) or
$ROMRT_LIBRARY_DOUBLE (double), else build/lib/ of the source tree this file sits in, else the
system's (ctypes.util.find_library("romrt")).

Errors: a refused call raises romrt.Error, whose .status is the runtime's status name
("damaged asset", ...), .chunk the asset chunk involved, .message the runtime's message (what
failed and where). A model belongs to one thread at a time; models may share nothing but the
library.
"""
import ctypes
import ctypes.util
import glob
import os

import numpy as np

__all__ = ["Model", "Error", "load_library", "version", "REDUCED", "KOOPMAN"]

REDUCED, KOOPMAN = 0, 1
_MESSAGE_BYTES = 160  # ROMRT_MESSAGE_BYTES
_STATUS = ["ok", "bad argument", "damaged asset", "unsupported format version", "wrong platform",
           "unsupported asset feature", "inconsistent model", "above the runtime's limits",
           "arena too small or misaligned", "step diverged"]


class Error(Exception):
    """A status other than ROMRT_OK, with the runtime's message."""

    def __init__(self, status, message, chunk=""):
        self.code = int(status)
        self.status = _STATUS[self.code] if 0 <= self.code < len(_STATUS) else "status %d" % self.code
        self.chunk = chunk
        self.message = message
        where = " (chunk '%s')" % chunk if chunk else ""
        super().__init__("%s: %s%s" % (self.status, message, where))


class _Err(ctypes.Structure):  # romrt_error
    _fields_ = [("status", ctypes.c_int), ("chunk", ctypes.c_char * 5),
                ("message", ctypes.c_char * _MESSAGE_BYTES)]


class _StepInfo(ctypes.Structure):  # romrt_step_info: size (set to sizeof), then what the last step did
    _fields_ = [("size", ctypes.c_size_t), ("newton_iterations", ctypes.c_size_t),
                ("line_search_halvings", ctypes.c_size_t), ("factorizations", ctypes.c_size_t),
                ("projected_hessians", ctypes.c_size_t), ("hessian_reuse", ctypes.c_size_t),
                ("contact_pairs", ctypes.c_size_t), ("friction_pairs", ctypes.c_size_t),
                ("pair_capacity", ctypes.c_size_t), ("converged", ctypes.c_int), ("colliders_behind", ctypes.c_int)]


class _Limits(ctypes.Structure):  # romrt_limits
    _fields_ = [("size", ctypes.c_size_t), ("max_reduced_size", ctypes.c_size_t),
                ("collider_slots", ctypes.c_size_t), ("mesh_max_count", ctypes.c_size_t)]


def _tree_library(double):
    here = os.path.dirname(os.path.abspath(__file__))
    name = "libromrt_double.so.*" if double else "libromrt.so.*"
    found = sorted(glob.glob(os.path.join(here, "..", "..", os.environ.get("ROMKIT_BUILD", "build"), "lib", name)))
    return found[-1] if found else None


_libraries = {}


def load_library(double=False, library=None):
    """The runtime's shared library, its functions typed (cached per path and precision)."""
    path = library or os.environ.get("ROMRT_LIBRARY_DOUBLE" if double else "ROMRT_LIBRARY") or _tree_library(double) \
        or ctypes.util.find_library("romrt_double" if double else "romrt")
    if not path:
        raise OSError("romrt: no %s runtime library found (run make all, or set %s)"
                      % ("double" if double else "float", "ROMRT_LIBRARY_DOUBLE" if double else "ROMRT_LIBRARY"))
    if (path, double) in _libraries:
        return _libraries[path, double]
    lib = ctypes.CDLL(path)
    prefix = "romrt_f64_" if double else "romrt_f32_"
    if not hasattr(lib, prefix + "version"):
        other = "float" if double else "double"
        raise OSError("romrt: %s is not the %s runtime (no %sversion: the %s one?)"
                      % (path, "double" if double else "float", prefix, other))
    real = ctypes.c_double if double else ctypes.c_float
    P, E, I, Z, R = ctypes.c_void_p, ctypes.POINTER(_Err), ctypes.c_int, ctypes.c_size_t, ctypes.POINTER(real)
    S = ctypes.c_int  # romrt_status
    signatures = {
        "version": (I, []), "status_string": (ctypes.c_char_p, [S]),
        "get_limits": (S, [ctypes.POINTER(_Limits), E]),
        "arena_size": (S, [P, Z, ctypes.POINTER(Z), E]),
        "arena_size_kind": (S, [P, Z, I, ctypes.POINTER(Z), E]),
        "open": (S, [P, Z, P, Z, ctypes.POINTER(P), E]),
        "open_kind": (S, [P, Z, I, P, Z, ctypes.POINTER(P), E]),
        "step": (S, [P, E]), "jump": (S, [P, ctypes.c_ulong, E]),
        "set_time_step": (S, [P, real, E]), "set_damping": (S, [P, real, E]),
        "set_newton_iterations": (S, [P, Z, E]), "set_hessian_reuse": (S, [P, Z, E]), "reset": (S, [P, E]),
        "model_kind": (I, [P]), "reduced_size": (Z, [P]), "shown_count": (Z, [P]),
        "triangle_count": (Z, [P]), "group_count": (Z, [P]),
        "time": (ctypes.c_double, [P]), "time_step": (real, [P]),
        "positions": (S, [P, R, Z, Z, E]), "rest_positions": (S, [P, R, Z, Z, E]),
        "basis_rows": (S, [P, R, Z, E]), "deformation_gradients": (S, [P, R, Z, E]),
        "triangles": (S, [P, ctypes.POINTER(ctypes.c_int32), Z, E]),
        "find_group": (S, [P, ctypes.c_char_p, ctypes.POINTER(Z), E]),
        "group_name": (S, [P, Z, ctypes.POINTER(ctypes.c_char_p), E]),
        "add_force": (S, [P, Z, R, E]), "add_vertex_force": (S, [P, Z, R, E]), "clear_forces": (S, [P, E]),
        "state_size": (Z, [P]), "get_state": (S, [P, R, Z, E]), "set_state": (S, [P, R, Z, E]),
        "reduced_coordinates": (S, [P, R, Z, E]), "last_step": (S, [P, ctypes.POINTER(_StepInfo), E]),
    }
    fns = {}
    for name, (restype, argtypes) in signatures.items():
        f = getattr(lib, prefix + name)
        f.restype, f.argtypes = restype, argtypes
        fns[name] = f
    entry = (lib, fns, np.float64 if double else np.float32, real, path)
    _libraries[path, double] = entry
    return entry


def version(double=False, library=None):
    """The library's ROMRT_VERSION_NUMBER (major * 10000 + minor * 100 + patch)."""
    return load_library(double, library)[1]["version"]()


def limits(double=False, library=None):
    """The library's limits: max_reduced_size, collider_slots, mesh_max_count."""
    lim, err = _Limits(), _Err()
    lim.size = ctypes.sizeof(_Limits)
    if load_library(double, library)[1]["get_limits"](ctypes.byref(lim), ctypes.byref(err)) != 0:
        raise Error(err.status, err.message.decode("utf-8", "replace"))
    return {name: getattr(lim, name) for name, _ in _Limits._fields_ if name != "size"}


def _aligned(nbytes, align=64):
    """A zeroed numpy byte buffer of nbytes whose start is `align`-aligned (a view into a larger one)."""
    raw = np.zeros(nbytes + align, dtype=np.uint8)
    off = (-raw.ctypes.data) % align
    return raw[off:off + nbytes]


class Model:
    """An asset opened in an arena this object owns; the asset's bytes are copied and kept alive.

    asset: a path, or bytes-like. kind: None (the asset's reduced model when it has one, else its
    Koopman operator), REDUCED or KOOPMAN. double: the double runtime."""

    def __init__(self, asset, kind=None, double=False, library=None):
        self._lib, self._f, self.dtype, self._real, self.library = load_library(double, library)
        if isinstance(asset, (str, os.PathLike)):
            with open(asset, "rb") as fh:
                asset = fh.read()
        data = np.frombuffer(asset, dtype=np.uint8)
        self._asset = _aligned(len(data))  # 8-byte alignment is what romrt_open needs; kept alive
        self._asset[:] = data
        err, need = _Err(), ctypes.c_size_t(0)
        a = self._asset.ctypes.data_as(ctypes.c_void_p)
        if kind is None:
            self._check(self._f["arena_size"](a, len(data), ctypes.byref(need), ctypes.byref(err)), err)
        else:
            self._check(self._f["arena_size_kind"](a, len(data), int(kind), ctypes.byref(need), ctypes.byref(err)), err)
        self._arena = _aligned(need.value)
        model = ctypes.c_void_p()
        arena = self._arena.ctypes.data_as(ctypes.c_void_p)
        if kind is None:
            st = self._f["open"](a, len(data), arena, need.value, ctypes.byref(model), ctypes.byref(err))
        else:
            st = self._f["open_kind"](a, len(data), int(kind), arena, need.value, ctypes.byref(model), ctypes.byref(err))
        self._check(st, err)
        self._m = model
        self.arena_bytes = need.value

    # -- errors --
    def _check(self, status, err):
        if status == 0:
            return
        if err.message:  # empty only in a build without message texts (ROMRT_NO_STRINGS)
            raise Error(status, err.message.decode("utf-8", "replace"), err.chunk.decode("ascii", "replace"))
        raise Error(status, self._f["status_string"](status).decode())

    def _call(self, name, *args):
        """A fallible call with the romrt_error last; raises Error with its message."""
        err = _Err()
        self._check(self._f[name](self._m, *args, ctypes.byref(err)), err)

    def _real_array(self, values, n, name):
        a = np.ascontiguousarray(values, dtype=self.dtype).reshape(-1)
        if a.size != n:
            raise ValueError("%s: %d values, expected %d" % (name, a.size, n))
        return a

    def _ptr(self, a):
        return a.ctypes.data_as(ctypes.POINTER(self._real))

    # -- sizes and clock --
    @property
    def kind(self):
        return self._f["model_kind"](self._m)

    @property
    def r(self):
        """The reduced size (a Koopman model: its rank)."""
        return self._f["reduced_size"](self._m)

    @property
    def shown_count(self):
        return self._f["shown_count"](self._m)

    @property
    def triangle_count(self):
        return self._f["triangle_count"](self._m)

    @property
    def time(self):
        """The clock (s), a double: steps x h, no drift."""
        return self._f["time"](self._m)

    @property
    def time_step(self):
        return float(self._f["time_step"](self._m))

    @property
    def groups(self):
        """The names of the groups an app may push, in index order."""
        names, name, err = [], ctypes.c_char_p(), _Err()
        for g in range(self._f["group_count"](self._m)):
            self._check(self._f["group_name"](self._m, g, ctypes.byref(name), ctypes.byref(err)), err)
            names.append(name.value.decode())
        return names

    # -- stepping --
    def step(self, steps=1):
        for _ in range(steps):
            self._call("step")

    def jump(self, steps):
        """A Koopman model: `steps` steps at once (O(log steps))."""
        self._call("jump", int(steps))

    def set_time_step(self, h):
        self._call("set_time_step", h)

    def set_damping(self, mu):
        self._call("set_damping", mu)

    def set_newton_iterations(self, k):
        self._call("set_newton_iterations", int(k))

    def set_hessian_reuse(self, k):
        self._call("set_hessian_reuse", int(k))

    def reset(self):
        self._call("reset")

    def last_step(self):
        info = _StepInfo()
        info.size = ctypes.sizeof(_StepInfo)
        self._call("last_step", ctypes.byref(info))
        return {name: getattr(info, name) for name, _ in _StepInfo._fields_ if name != "size"}

    # -- pushing --
    def group(self, name):
        """A group's index by name (KeyError if the asset has none of that name)."""
        g, err = ctypes.c_size_t(), _Err()
        if self._f["find_group"](self._m, name.encode(), ctypes.byref(g), ctypes.byref(err)) != 0:
            raise KeyError("romrt: the asset has no group %r (it has %s)" % (name, self.groups))
        return g.value

    def add_force(self, group, force):
        """The total force (N) spread over a group's vertices (a name or an index), held until cleared."""
        g = self.group(group) if isinstance(group, str) else int(group)
        f = self._real_array(force, 3, "force")
        if g < 0:
            raise Error(1, "romrt_add_force: group %d of %d" % (g, len(self.groups)))
        self._call("add_force", g, self._ptr(f))

    def add_vertex_force(self, vertex, force):
        """A force (N) on one shown vertex, held until cleared."""
        f = self._real_array(force, 3, "force")
        if int(vertex) < 0:
            raise Error(1, "romrt_add_vertex_force: vertex %d of %d shown" % (int(vertex), self.shown_count))
        self._call("add_vertex_force", int(vertex), self._ptr(f))

    def clear_forces(self):
        self._call("clear_forces")

    # -- reading --
    def _vertices(self, fn, out, what):
        n = self.shown_count
        if out is None:
            out = np.empty((n, 3), dtype=self.dtype)
        if out.dtype != self.dtype or out.ndim != 2 or not out.flags.c_contiguous or out.shape[1] < 3:
            raise ValueError("%s: out must be a C-contiguous (vertices, stride >= 3) %s array"
                             % (what, np.dtype(self.dtype).name))
        # capacity (reals) and stride as the runtime takes them: it refuses a buffer too small
        err = _Err()
        self._check(fn(self._m, self._ptr(out), out.size, out.shape[1], ctypes.byref(err)), err)
        return out

    def positions(self, out=None):
        """The shown vertices' positions, (shown, 3); `out` may be an interleaved (n, stride) buffer."""
        return self._vertices(self._f["positions"], out, "romrt_positions")

    def rest_positions(self, out=None):
        """The shown vertices' rest positions X, laid out as positions()."""
        return self._vertices(self._f["rest_positions"], out, "romrt_rest_positions")

    def basis_rows(self):
        """U of the shown vertices, (shown, 3, r): x = X + U q (a Koopman model: its output rows, q = y)."""
        n, r = self.shown_count, self.r
        out = np.empty((n, 3, r), dtype=self.dtype)
        self._call("basis_rows", self._ptr(out), out.size)
        return out

    def reduced_coordinates(self):
        """q (r reals; a Koopman model's eigen-coordinates y)."""
        out = np.empty(self.r, dtype=self.dtype)
        self._call("reduced_coordinates", self._ptr(out), out.size)
        return out

    def triangles(self):
        out = np.empty((self.triangle_count, 3), dtype=np.int32)
        self._call("triangles", out.ctypes.data_as(ctypes.POINTER(ctypes.c_int32)), out.size)
        return out

    def deformation_gradients(self):
        """F at each shown vertex, (shown, 3, 3), for assets with GRAD (point clouds, splats)."""
        out = np.empty((self.shown_count, 3, 3), dtype=self.dtype)
        self._call("deformation_gradients", self._ptr(out), out.size)
        return out

    def get_state(self):
        """The whole dynamic state (clock, q, velocities, history, forces) to save and restore."""
        out = np.empty(self._f["state_size"](self._m), dtype=self.dtype)
        self._call("get_state", self._ptr(out), out.size)
        return out

    def set_state(self, state):
        s = self._real_array(state, self._f["state_size"](self._m), "state")
        self._call("set_state", self._ptr(s), s.size)
