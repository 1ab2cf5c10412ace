"""Cubic splines fitted in float64 and evaluated in bulk on the GPU or on every CPU thread.

    >>> import numpy as np, splinegpu
    >>> ctx = splinegpu.Context("cpu")
    >>> curves = np.random.default_rng(0).uniform(-1, 1, (100, 10, 3))
    >>> r = ctx.tessellate(curves, kind="catmull-rom", per_segment=16)
    >>> r.points.shape, r.curve_offsets[:3]
    ((11300, 3), array([  0, 113, 226]))

The curve kinds, their fields and the four samplings are those of the `splinegpu` command line
(docs/input-format.md in the repository); results hold the same numbers as its NPZ output: float32
from the GPU backend, float64 from the CPU backend, t always float64.

`CubicSpline` follows `scipy.interpolate.CubicSpline` for the cases it covers.
"""

from __future__ import annotations

import os
import threading
from collections.abc import Sequence
from typing import Any

# Mesa's device-select Vulkan layer prints XDG_RUNTIME_DIR warnings on headless machines unless
# this is set before the first Vulkan instance exists (as the command line does).
os.environ.setdefault("NODEVICE_SELECT", "1")

import numpy as np

from . import _native

__all__ = ["KIND_NAMES", "Context", "CubicSpline", "CubicSplines", "Tessellation"]

KIND_NAMES: tuple = tuple(_native.KIND_NAMES)

_SAMPLINGS = ("per_segment", "at", "arc_length", "tolerance")


class Tessellation:
    """The samples of a `Context.tessellate` call.

    Attributes: `t` (N,) float64; `points` (N, D); `d1`, `d2` (N, D) or None when not asked
    for; `curve_offsets` (C + 1,) int64: curve c owns rows curve_offsets[c]:curve_offsets[c+1].
    """

    __slots__ = ("curve_offsets", "d1", "d2", "points", "t")

    def __init__(self, t, points, d1, d2, curve_offsets):
        self.t = t
        self.points = points
        self.d1 = d1
        self.d2 = d2
        self.curve_offsets = curve_offsets

    def curve(self, c: int) -> Tessellation:
        """Curve c's rows (views, no copy)."""
        a, b = self.curve_offsets[c], self.curve_offsets[c + 1]
        pick = lambda x: None if x is None else x[a:b]  # noqa: E731
        return Tessellation(self.t[a:b], self.points[a:b], pick(self.d1), pick(self.d2),
                            np.array([0, b - a], dtype=np.int64))

    def __len__(self) -> int:
        return len(self.t)

    def __repr__(self) -> str:
        return (f"Tessellation({len(self.curve_offsets) - 1} curves, {len(self.t)} samples, "
                f"points {self.points.dtype} {self.points.shape})")


def _float64(a, name: str) -> np.ndarray:
    """`a` as a float64 array (itself where it already is one). Complex values are refused,
    naming `name`, rather than cut to their real part."""
    try:
        a = np.asarray(a)
    except ValueError as e:
        # A nested list whose rows differ in length.
        raise ValueError(f"{name}: {e}") from None
    if np.iscomplexobj(a):
        raise ValueError(f"{name}: complex values are not supported (got {a.dtype}); pass the "
                         f"real and imaginary parts as coordinates of their own")
    if a.dtype.kind not in "biuf":
        # Strings would be parsed as numbers by astype, objects are ragged nested lists.
        raise TypeError(f"{name}: must be numbers, got an array of {a.dtype}"
                        + (" (rows of different lengths?)" if a.dtype.kind == "O" else ""))
    return a.astype(np.float64, copy=False)


def _order(name: str, value, most: int) -> int:
    """An integer argument `name` in 0..=most (a derivative order), refused by name otherwise."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not (
            0 <= value <= most):
        raise ValueError(f"{name}: must be an integer from 0 to {most}, got {value!r}")
    return int(value)


def _count(name: str, value) -> int:
    """A sample count `name` (per_segment, arc_length): an integer (0 goes on to the crate,
    whose message names the curve)."""
    if isinstance(value, bool) or not isinstance(value, (int, np.integer, float, np.floating)) \
            or not np.isfinite(value) or int(value) != value:
        raise ValueError(f"{name}: must be an integer, got {value!r}")
    if value < 0:
        raise ValueError(f"{name}: must be >= 1, got {value}")
    return int(value)


def _aligned(a, name: str) -> np.ndarray:
    """`a` (argument `name`) as an aligned, C-contiguous float64 array (itself where it already
    is one): arrays unpickled from a network buffer (Dask) may be misaligned."""
    return np.require(_float64(a, name), requirements=["C", "A"])


def _curves(points):
    """A (C, n, D) array (passed whole) or a list of (n_i, D) arrays (each made C-contiguous)."""
    if isinstance(points, np.ndarray):
        if points.ndim != 3:
            raise ValueError(f"points: must be a (C, n, D) array or a list of (n_i, D) arrays, "
                             f"got an array of shape {points.shape}")
        return _aligned(points, "points")
    if isinstance(points, (list, tuple)) and points and isinstance(points[0], np.ndarray) \
            and points[0].ndim == 2:
        stacked = _stacked(points)
        if stacked is not None:
            return _aligned(stacked, "points")
    out = []
    for c, p in enumerate(points):
        a = _float64(p, f"curve {c}: \"points\"")
        if a.ndim == 1:
            a = a[:, None]
        if a.ndim != 2:
            raise ValueError(f"curve {c}: \"points\" must be an (n, D) array, got shape {a.shape}")
        out.append(_aligned(a, "points"))
    return out


def _stacked(items, otherwise=None):
    """A list of arrays of one shape and type as one array (a copy), or None. Handing the
    extension thousands of views of one array made each borrow check the others (`list(arr)`
    of 40,000 curves took 2.4 s where the array took 0.07); one copy costs less than that.
    Anything else is returned as `otherwise`."""
    if not isinstance(items, (list, tuple)) or len(items) < 2:
        return otherwise
    first = items[0]
    if not isinstance(first, np.ndarray) or first.dtype.kind not in "biuf":
        return otherwise
    if all(isinstance(a, np.ndarray) and a.shape == first.shape and a.dtype == first.dtype
           for a in items):
        return np.stack(items)
    return otherwise


def _matrix(matrix) -> list:
    """A basis matrix: 4 rows of 4 numbers."""
    m = _float64(matrix, "matrix")
    if m.shape != (4, 4):
        raise ValueError(f"matrix: must be 4 rows of 4 numbers, got shape {m.shape}")
    return m.tolist()


def _per_curve(name: str, value, curves: int, ndim: int):
    """A per-curve argument (t, at, derivatives, knots, ...) of `ndim` dimensions per curve: one
    array for all curves, an array of one more dimension (a row per curve) or a list of arrays
    (ragged). To the native side as one (C, k) array where every curve's has one shape (see
    `_stacked`), else as a list of flat arrays (or None)."""
    if value is None:
        return None
    if isinstance(value, np.ndarray) and value.ndim == ndim:
        value = [value] * curves
    else:
        stacked = value if isinstance(value, np.ndarray) else _stacked(value)
        if isinstance(stacked, np.ndarray) and stacked.ndim == ndim + 1:
            if len(stacked) != curves:
                raise ValueError(f"{name}: {len(stacked)} entries for {curves} curves")
            return _aligned(stacked.reshape(curves, stacked[0].size if curves else 0), name)
    value = list(value)
    if value and np.ndim(value[0]) == 0 and ndim == 1:
        value = [_float64(value, name)] * curves
    if len(value) != curves:
        raise ValueError(f"{name}: {len(value)} entries for {curves} curves")
    return [None if v is None else _flat(v, name) for v in value]


def _per_point(name: str, value, curves: int) -> dict:
    """A number for every curve (`name`), or per point (`name + "_each"`: an array per curve)."""
    if value is None:
        return {name: None, f"{name}_each": None}
    if isinstance(value, (bool, np.bool_, str)):
        raise TypeError(f"{name}: must be a number or one number per point, got {value!r}")
    if isinstance(value, (int, float, np.integer, np.floating)):
        return {name: float(value), f"{name}_each": None}
    return {name: None, f"{name}_each": _per_curve(name, value, curves, 1)}


def _flat(v, name: str) -> np.ndarray:
    """`v` (argument `name`) as an aligned, contiguous 1-D float64 array (a view where it
    already is one)."""
    return _aligned(_float64(v, name).ravel(), name)


def _rows(name: str, value, curves: int):
    """Per-curve 1-D arrays for the native side: a (C, k) array whole, else a list."""
    if isinstance(value, np.ndarray) and value.ndim == 2:
        if len(value) != curves:
            raise ValueError(f"{name}: {len(value)} rows for {curves} curves")
        return _aligned(value, name)
    if isinstance(value, np.ndarray) and value.ndim == 1:
        return _aligned(np.broadcast_to(value, (curves, len(value))), name)
    return _per_curve(name, value, curves, 1)


class Context:
    """Where splines are evaluated: made once and reused (threads may share it).

    `backend`: "auto" (a hardware GPU when there is one, else the CPU), "gpu" (any adapter,
    lavapipe included; RuntimeError without one) or "cpu" (float64 on every thread).
    """

    def __init__(self, backend: str = "auto"):
        self._native = _native.Context(backend)
        self._requested = backend

    def __reduce__(self):
        # A context pickles as the backend asked for, and opens it again where it is unpickled
        # (a Dask worker, a process pool): an adapter cannot travel.
        return (Context, (self._requested,))

    @property
    def info(self) -> str:
        """The adapter (or the CPU) this context evaluates on."""
        return self._native.info

    @property
    def backend(self) -> str:
        """"gpu" or "cpu"."""
        return self._native.backend

    def __repr__(self) -> str:
        return f"splinegpu.Context({self.info!r})"

    def tessellate(self, points, kind: str = "catmull-rom", *, ends: str | None = None,
                   tension=None, bias=None, continuity=None,
                   matrix=None, t=None, start_derivative=None, end_derivative=None,
                   tangents=None, method: str | None = None, knots=None, weights=None,
                   per_segment: int | None = None, at=None, arc_length: int | None = None,
                   tolerance: float | None = None, derivatives: int = 0,
                   out: Tessellation | None = None) -> Tessellation:
        """Fits and samples a batch of curves of one kind.

        `points`: a (C, n, D) array or a list of (n_i, D) arrays (ragged). `kind` and its fields
        are the command line's (KIND_NAMES); `t`, `at` and the clamped derivatives are one array
        for every curve, a 2-D array with a row per curve, or a list (ragged); hermite's
        `tangents` are an (n, D) array for every curve, a (C, n, D) array or a list of (n_i, D)
        arrays; akima's `method` is "akima" or "makima"; kochanek-bartels' `tension`,
        `continuity` and `bias` are numbers, or per point: an (n,) array for every curve, a
        (C, n) array or a list of arrays; nurbs' `knots` (n + 4 per curve) likewise. One sampling:
        `per_segment=k` (the default, 16), `at=t values`, `arc_length=m` or `tolerance=tol`
        (arc-length samples within 1e-10 of the length on the CPU; the GPU places them itself,
        within 1e-5, so their t differ between backends in the low bits; tolerance t are the
        same on both). `derivatives`: 0, 1 or 2 (d/dt). `out`: an earlier result of the same
        shape, whose arrays are filled again instead of new ones.

        Raises ValueError naming the curve, field and value for bad input.
        """
        curves = _curves(points)
        given = [(name, v) for name, v in
                 (("per_segment", per_segment), ("at", at), ("arc_length", arc_length),
                  ("tolerance", tolerance)) if v is not None]
        if len(given) > 1:
            raise ValueError(f"sampling: give one of {', '.join(_SAMPLINGS)}, got "
                             f"{', '.join(n for n, _ in given)}")
        name, value = given[0] if given else ("per_segment", 16)
        if name == "at":
            value = _rows("at", value, len(curves))
        elif name in ("per_segment", "arc_length"):
            value = _count(name, value)
        else:
            value = float(_float64(value, "tolerance"))
        fields = {
            "ends": ends,
            **_per_point("tension", tension, len(curves)),
            **_per_point("continuity", continuity, len(curves)),
            **_per_point("bias", bias, len(curves)),
            "matrix": None if matrix is None else _matrix(matrix),
            "t": _per_curve("t", t, len(curves), 1),
            "start_derivative": _per_curve("start_derivative", start_derivative, len(curves), 1),
            "end_derivative": _per_curve("end_derivative", end_derivative, len(curves), 1),
            "tangents": _per_curve("tangents", tangents, len(curves), 2),
            "method": None if method is None else str(method),
            "knots": _per_curve("knots", knots, len(curves), 1),
            "weights": _per_curve("weights", weights, len(curves), 1),
        }
        derivatives = _order("derivatives", derivatives, 2)
        reuse = None
        if out is not None:
            for array, what, dtype in ((out.t, "t", np.float64),
                                       (out.curve_offsets, "curve_offsets", np.int64)):
                if not isinstance(array, np.ndarray) or array.dtype != dtype or array.ndim != 1:
                    raise ValueError(f"out: {what} must be a 1-D {np.dtype(dtype)} array, got "
                                     f"{getattr(array, 'dtype', type(array).__name__)}")
            reuse = (out.t, out.points, out.d1, out.d2, out.curve_offsets)
        result = self._native.tessellate(curves, kind, fields, (name, value), derivatives, reuse)
        return Tessellation(*result)


# The most coordinates a curve's point has (the crate's MAX_DIM): the columns fitted together.
_MAX_COLUMNS = 64
_F64 = np.dtype(np.float64)

_shared_cpu: Context | None = None
_shared_lock = threading.Lock()


def _default_context() -> Context:
    global _shared_cpu
    with _shared_lock:
        if _shared_cpu is None:
            _shared_cpu = Context("cpu")
        return _shared_cpu


def _shared_context():
    """The native half of `self.context`'s default, made once (a call takes no lock after)."""
    return (_shared_cpu or _default_context())._native


_END_NAMES = {"natural": "second", "clamped": "first", "not-a-knot": "not-a-knot"}


def _bc(bc_type, trailing: tuple, complex_y: bool = False):
    """SciPy's bc_type as (name, start, end) for the native fit: a name, "clamped" with first
    derivatives at both ends, or "each" with every end on its own: (order name, values) where
    order name is "first", "second" or "not-a-knot". Derivative values broadcast to y's
    trailing shape, flattened as y is (for a complex y, real parts then imaginary parts)."""
    if isinstance(bc_type, str):
        return bc_type, None, None
    wrong = ("bc_type: must be \"not-a-knot\", \"natural\", \"clamped\", \"periodic\", a "
             "pair of those but \"periodic\", or a pair of (order, value) with order 1 or 2, "
             f"got {bc_type!r}")
    try:
        first, last = bc_type
    except (TypeError, ValueError):
        raise ValueError(wrong) from None

    def flat(v):
        v = np.asarray(v) if complex_y else _float64(v, "bc_type")
        try:
            v = np.broadcast_to(v, trailing).ravel()
        except ValueError:
            raise ValueError(f"bc_type: an end's value of shape {v.shape} does not broadcast "
                             f"to y's other axes {trailing}") from None
        return np.concatenate([v.real, v.imag]).tolist() if complex_y else v.tolist()

    def end(spec):
        if isinstance(spec, str):
            if spec not in _END_NAMES:
                raise ValueError(wrong)
            return (_END_NAMES[spec], None)
        try:
            order, value = spec
        except (TypeError, ValueError):
            raise ValueError(wrong) from None
        if isinstance(order, bool) or order not in (1, 2):
            raise ValueError(f"bc_type: the derivative order at an end must be 1 or 2, got "
                             f"{order!r}")
        return ("first" if order == 1 else "second", flat(value))

    start, end_ = end(first), end(last)
    if start[0] == end_[0] == "first" and start[1] is not None and end_[1] is not None:
        return "clamped", start, end_
    return "each", start, end_


def _extrapolate(value):
    """SciPy's `extrapolate`: True, False or "periodic" (None: the spline's own)."""
    if value is None or isinstance(value, bool):
        return value
    if isinstance(value, str):
        if value != "periodic":
            raise ValueError(f"extrapolate: must be True, False or 'periodic', got {value!r}")
        return value
    return bool(value)


def _restore(cls, attributes: dict, state):
    """A spline `__reduce__` saved: its attributes, and its tables restored bit for bit."""
    spline = cls.__new__(cls)
    spline.__dict__.update(attributes)
    spline._native = _native.Splines.from_state(state)
    return spline


class CubicSpline:
    """`scipy.interpolate.CubicSpline(x, y, axis=0, bc_type="not-a-knot", extrapolate=None)`:
    bc_type "not-a-knot", "natural", "clamped", "periodic" (on 2 points too), or a pair of
    ends, each "not-a-knot", "natural", "clamped" or (order, value) with order 1 or 2 (a
    first or second derivative, value broadcast to y's other axes).

    Fitted in float64 on the host (O(n)); evaluated through `context` (None: a shared CPU
    context, float64; a GPU context gives float32 values within the crate's promise).
    `extrapolate` is SciPy's: True (the end pieces continue past the knots), False (NaN outside
    [x[0], x[-1]]) or "periodic" (x wrapped into it); None means "periodic" for a periodic
    bc_type, else True; a call may override it. Derivatives nu = 0 to 3; the third, piecewise
    constant, is formed from `c` in float64 on either backend, and so are values outside the
    knots. Like SciPy's, "not-a-knot" on 2 or 3 points gives the line or the parabola through
    them, and a complex y gives a complex spline (its real and imaginary parts fitted apart,
    the fit being linear in y). Splines pickle and deep-copy (their fitted tables, bit for bit,
    and their context as its backend choice), so they travel to Dask workers and process pools.

    Differences from SciPy: `x` and `c` are read-only (the fit is not redone when they
    change, so writing raises instead of being ignored); nu > 3 is refused; the object is not
    a `PPoly`.
    """

    def __init__(self, x, y, axis: int = 0, bc_type="not-a-knot", extrapolate=None,
                 context: Context | None = None):
        extrapolate = _extrapolate(extrapolate)
        if extrapolate is None:
            extrapolate = "periodic" if isinstance(bc_type, str) and bc_type == "periodic" \
                else True
        # A copy of x: the caller's array may change after the fit, the spline's knots may not.
        x = np.array(_float64(x, "x"), order="C")
        y = np.asarray(y)
        self._complex = np.iscomplexobj(y)
        if x.ndim != 1:
            raise ValueError(f"x: must be 1-D, got shape {x.shape}")
        if x.shape[0] < 2:
            raise ValueError(f"x: must contain at least 2 elements, got {x.shape[0]}")
        if y.ndim == 0:
            raise ValueError("y: must be at least 1-D, got a 0-d array")
        if isinstance(axis, bool) or not isinstance(axis, (int, np.integer)) or not (
                -y.ndim <= axis < y.ndim):
            raise ValueError(f"axis: must be an integer from {-y.ndim} to {y.ndim - 1} for a "
                             f"{y.ndim}-D y, got {axis!r}")
        # As SciPy does: a negative axis counts from the end, and is kept normalised.
        axis = int(axis) % y.ndim
        y = np.moveaxis(y, axis, 0)
        if y.shape[0] != x.shape[0]:
            raise ValueError(f"y: {y.shape[0]} values along axis {axis} for {x.shape[0]} x")
        self._trailing = y.shape[1:]
        y2 = y.reshape(y.shape[0], -1)
        if self._complex:
            y2 = np.concatenate([y2.real, y2.imag], axis=1)
        y2 = np.ascontiguousarray(_float64(y2, "y"))
        if y2.shape[1] > _MAX_COLUMNS:
            raise ValueError(f"y: at most {_MAX_COLUMNS} values per x are fitted together "
                             f"(y's axes but `axis`, a complex y counting twice), got "
                             f"{y2.shape[1]}")
        name, start, end = _bc(bc_type, self._trailing, self._complex)
        self._native = _native.fit([x], [y2], name, start, end)
        x.flags.writeable = False
        self.x = x
        self.axis = axis
        self.extrapolate = extrapolate
        self.context = context
        self._pieces = None
        self._c = None

    def __reduce__(self):
        attributes = {k: v for k, v in self.__dict__.items() if k != "_native"}
        attributes["_pieces"] = attributes["_c"] = None
        return (_restore, (type(self), attributes, self._native.state()))

    @property
    def c(self) -> np.ndarray:
        """Coefficients as SciPy's PPoly holds them: shape (4, n - 1) + y's other axes
        (read-only: the spline does not follow changes to them)."""
        if self._c is None:
            c = self._joined(self._coefficients()).reshape((4, -1, *self._trailing))
            c.flags.writeable = False
            self._c = c
        return self._c

    def _coefficients(self) -> np.ndarray:
        """The fitted columns' coefficients, (4, n - 1, m), made once."""
        if self._pieces is None:
            self._pieces = self._native.coefficients(0)
        return self._pieces

    def _joined(self, values: np.ndarray) -> np.ndarray:
        """`values` (..., m) of the fitted columns as y's: for a complex y, the real parts'
        columns and the imaginary parts' joined into complex numbers."""
        if not self._complex:
            return values
        m = values.shape[-1] // 2
        return values[..., :m] + 1j * values[..., m:]

    def __call__(self, x, nu: int = 0, extrapolate=None) -> np.ndarray:
        """The nu-th derivative (0 to 3) at x; shape x.shape + y's other axes (moved to
        `axis` as SciPy does). `extrapolate`: None (the spline's), True, False or
        "periodic"."""
        if nu.__class__ is not int or not 0 <= nu <= 2:
            nu = _order("nu", nu, 3)
        mode = self.extrapolate if extrapolate is None else _extrapolate(extrapolate)
        # The common call, a float64 array or a Python float, skips the general conversion.
        if x.__class__ is np.ndarray and x.dtype == _F64 and x.flags.c_contiguous \
                and x.flags.aligned:
            flat = x.reshape(-1)
        elif x.__class__ is float:
            flat = np.array((x,))
            x = flat.reshape(())
        else:
            x = _float64(x, "x")
            flat = _flat(x, "x")
        ctx = self.context
        native = _shared_context() if ctx is None else ctx._native
        values = None
        if nu <= 2 and mode != "periodic":
            try:
                values = self._native.evaluate_one(native, flat, nu)
            except ValueError:
                # x outside the knots, or NaN: the general route below, which raises again
                # where the reason is another.
                pass
        if values is None:
            values = self._anywhere(native, flat, nu, mode)
        if self._complex:
            values = self._joined(values)
        out = values.reshape(x.shape + self._trailing)
        if self.axis != 0 and x.ndim > 0:
            out = np.moveaxis(out, list(range(x.ndim)), list(range(self.axis, self.axis + x.ndim)))
        return out

    def _anywhere(self, native, flat: np.ndarray, nu: int, mode) -> np.ndarray:
        """Derivative nu at any x, as (len(x), m) in the fitted columns: inside the knots
        through the context (nu <= 2), elsewhere by the pieces (see `_by_pieces`); NaN outside
        when `mode` is False, x wrapped into the knots when it is "periodic"."""
        lo, hi = self.x[0], self.x[-1]
        if mode == "periodic":
            flat = lo + np.mod(flat - lo, hi - lo)
        inside = (flat >= lo) & (flat <= hi)
        dtype = np.float32 if native.backend == "gpu" else np.float64
        out = np.empty((len(flat), self._coefficients().shape[2]), dtype=dtype)
        if nu == 3:
            out[...] = self._by_pieces(flat, 3)
        else:
            if inside.any():
                out[inside] = self._native.evaluate_one(
                    native, np.ascontiguousarray(flat[inside]), nu)
            outside = ~inside
            if outside.any():
                out[outside] = self._by_pieces(flat[outside], nu)
        if mode is False:
            out[~inside] = np.nan
        return out

    def _by_pieces(self, x: np.ndarray, nu: int) -> np.ndarray:
        """Derivative nu at x from `c` in float64, as SciPy's PPoly evaluates it: the piece
        of the last knot at or below x (the first piece below x[0], the last at and above
        x[-1]), in powers of x - x_i; NaN at NaN."""
        c = self._coefficients()
        i = np.clip(np.searchsorted(self.x, x, side="right") - 1, 0, c.shape[1] - 1)
        dx = (x - self.x[i])[:, None]
        a, b, cc, d = c[0, i], c[1, i], c[2, i], c[3, i]
        if nu == 0:
            return d + dx * (cc + dx * (b + dx * a))
        if nu == 1:
            return cc + dx * (2 * b + dx * 3 * a)
        if nu == 2:
            return 2 * b + dx * 6 * a
        return 6 * a + 0 * dx

    def derivative(self, nu: int = 1) -> _Derivative:
        """The nu-th derivative (1 to 3) as a callable with `.x` and `.c` (SciPy returns a
        PPoly)."""
        return _Derivative(self, nu)


class _Derivative:
    """A derivative of a `CubicSpline`: evaluated through its spline."""

    def __init__(self, spline: CubicSpline, nu: int):
        nu = _order("nu", nu, 3)
        self._spline, self._nu = spline, nu
        self.x = spline.x

    @property
    def c(self) -> np.ndarray:
        c = self._spline.c
        for _ in range(self._nu):
            k = c.shape[0]
            powers = np.arange(k - 1, 0, -1).reshape((k - 1,) + (1,) * (c.ndim - 1))
            c = c[:-1] * powers
        return c

    def __call__(self, x, nu: int = 0, extrapolate=None) -> np.ndarray:
        return self._spline(x, self._nu + _order("nu", nu, 3 - self._nu), extrapolate)


class CubicSplines:
    """Many cubic splines with their own knots, fitted and evaluated in one batch.

    `xs`: a list of 1-D knot arrays (or a 2-D array, one row per spline); `ys`: matching
    (n_i, m) arrays. Calling with one array of x per spline returns (values (N, m),
    offsets (S + 1,)): spline i's values are rows offsets[i]:offsets[i+1].
    """

    def __init__(self, xs, ys, bc_type="not-a-knot", context: Context | None = None):
        xs, ys = _stacked(xs, xs), _stacked(ys, ys)
        if isinstance(xs, np.ndarray) and xs.ndim == 2:
            xs = _aligned(xs, "xs")
        else:
            xs = [_flat(x, "xs") for x in xs]
        if isinstance(ys, np.ndarray) and ys.ndim >= 2:
            trailing = ys.shape[2:]
            ys2 = _aligned(_float64(ys, "ys").reshape(ys.shape[0], ys.shape[1], -1), "ys")
        else:
            ys = [_float64(y, "ys") for y in ys]
            trailing = ys[0].shape[1:] if ys else ()
            for i, y in enumerate(ys):
                if y.ndim == 0 or y.shape[1:] != trailing:
                    raise ValueError(f"ys[{i}]: every spline's values must have the shape "
                                     f"(n_i,) + {trailing}, got {y.shape}")
            ys2 = [_aligned(y.reshape(len(y), -1), "ys") for y in ys]
        name, start, end = _bc(bc_type, trailing)
        self._native = _native.fit(xs, ys2, name, start, end)
        self.context = context

    def __reduce__(self):
        # As a CubicSpline's: the fitted tables bit for bit, the context as its backend.
        return (_restore, (type(self), {"context": self.context}, self._native.state()))

    def __len__(self) -> int:
        return len(self._native)

    def __call__(self, xs: Sequence[Any], nu: int = 0):
        """Spline i at xs[i] (a list of arrays, or a (S, k) array) -> (values, offsets)."""
        xs = _stacked(xs, xs)
        if isinstance(xs, np.ndarray) and xs.ndim == 2:
            flat = _aligned(xs, "xs")
        else:
            flat = [_flat(x, "xs") for x in xs]
        ctx = self.context or _default_context()
        return self._native.evaluate(ctx._native, flat, _order("nu", nu, 2))
