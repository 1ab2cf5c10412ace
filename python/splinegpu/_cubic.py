"""The 1-D splines of `splinegpu.interpolate` that SciPy holds as piecewise cubics
(`CubicSpline`, `CubicHermiteSpline`, `PchipInterpolator`, `Akima1DInterpolator`): fitted in
float64 on the host, their pieces kept in the extension's tables (blocks of at most 64 columns,
the crate's widest point) and evaluated through a `Context`. Each is a `PPoly`, as SciPy's, so
what SciPy answers through PPoly (derivatives, antiderivatives, integrals, roots) it answers
too.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from . import _bspl, _collocation, _native
from ._context import Context, shared_context
from ._helpers import _F64, _axis, _extrapolate, _f64, _flat, _float64, _order
from ._ppoly import PPoly

# The most coordinates a curve's point has (the crate's MAX_DIM): the columns fitted together.
_MAX_COLUMNS = 64
# The largest call on a spline made from pieces (a derivative) that its pieces answer before
# its tables exist.
_UNTABULATED_CALL = 1 << 16


_END_NAMES = {"natural": "second", "clamped": "first", "not-a-knot": "not-a-knot"}


def bc_of(bc_type, trailing: tuple, complex_y: bool = False, broadcast: bool = False):
    """SciPy's bc_type as (name, start, end) for the native fit: a name, "clamped" with first
    derivatives at both ends, or "each" with every end on its own: (order name, values) where
    order name is "first", "second" or "not-a-knot". Derivative values have y's trailing
    shape (as SciPy requires; the batches, ours, also `broadcast` them to it), flattened as y
    is (for a complex y, real parts then imaginary parts)."""
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
        if broadcast and v.shape != trailing:
            try:
                v = np.broadcast_to(v, trailing)
            except ValueError:
                raise ValueError(f"bc_type: an end's value of shape {v.shape} does not "
                                 f"broadcast to the values' other axes {trailing}") from None
        if v.shape != trailing:
            raise ValueError(f"bc_type: an end's value must have y's other axes' shape "
                             f"{trailing}, got {v.shape}")
        v = v.ravel()
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
    if start[0] == end_[0] == "not-a-knot":
        return "not-a-knot", None, None
    if start[0] == end_[0] == "first" and start[1] is not None and end_[1] is not None:
        return "clamped", start, end_
    return "each", start, end_


def _cut_end(end, cut: slice):
    """An end condition of `bc_of` for the columns `cut` of y."""
    if end is None or end[1] is None:
        return end
    return (end[0], end[1][cut])


def restore(cls, attributes: dict, state):
    """A spline `__reduce__` saved: its attributes, and its tables restored bit for bit."""
    spline = cls.__new__(cls)
    spline.__dict__.update(attributes)
    spline._native = _restored_tables(state)
    return spline


class _Blocks:
    """The tables of a spline wider than the crate's widest point: its columns in blocks of
    at most 64, each its own tables, answering as one."""

    def __init__(self, parts: list):
        self.parts = parts

    def evaluate_one(self, context, x: np.ndarray, nu: int) -> np.ndarray | None:
        parts = [p.evaluate_one(context, x, nu) for p in self.parts]
        return None if any(p is None for p in parts) else np.concatenate(parts, axis=1)

    def coefficients(self, i: int) -> np.ndarray:
        return np.concatenate([p.coefficients(i) for p in self.parts], axis=2)

    def state(self):
        return ("blocks", [p.state() for p in self.parts])


class _Empty:
    """The tables of a spline of no columns (y of zero size, as SciPy takes it): its values
    are arrays with no values per x."""

    def __init__(self, pieces: int):
        self.pieces = pieces

    def evaluate_one(self, context, x: np.ndarray, nu: int) -> np.ndarray:
        return np.zeros((len(x), 0))

    def coefficients(self, i: int) -> np.ndarray:
        return np.zeros((4, self.pieces, 0))

    def state(self):
        return ("empty", self.pieces)


def _restored_tables(state) -> Any:
    """The tables a `state()` saved."""
    if isinstance(state, tuple) and state[0] == "blocks":
        return _Blocks([_restored_tables(part) for part in state[1]])
    if isinstance(state, tuple) and state[0] == "empty":
        return _Empty(state[1])
    return _native.Splines.from_state(state)


def _in_blocks(fit, m: int, pieces: int) -> Any:
    """One spline's tables over its m columns: `fit(columns)` (a slice of them) for all of
    them where m <= 64, in blocks of 64 above, none at all where m = 0."""
    if m == 0:
        return _Empty(pieces)
    if m <= _MAX_COLUMNS:
        return fit(slice(0, m))
    return _Blocks([fit(slice(i, min(i + _MAX_COLUMNS, m))) for i in range(0, m, _MAX_COLUMNS)])


def piece_tables(pieces: list, extents: Sequence[float], name: str) -> Any:
    """The extension's tables of piecewise polynomials of degree <= 3 given in SciPy's power
    form: per spline (breakpoints x, real coefficients (k + 1, P, m)), all made in one call;
    extents[s] is the spread of the points spline s was made from, which scales the GPU's
    accuracy promise. Each piece is held as A u^3 + B u^2 + C u + D with u = (x - x_j) / h."""
    m = pieces[0][1].shape[2] if pieces else 1
    if m > _MAX_COLUMNS:
        raise ValueError(f"{name}: at most {_MAX_COLUMNS} values per coefficient are evaluated "
                         f"together, got {m}")
    knots = np.concatenate([x for x, _ in pieces]) if pieces else np.zeros(0)
    offsets = np.concatenate([[0], np.cumsum([len(x) for x, _ in pieces])]).astype(np.int64)
    c = np.concatenate([cc for _, cc in pieces], axis=1) if pieces else np.zeros((4, 0, m))
    cubic = np.zeros((4, *c.shape[1:]))
    cubic[4 - c.shape[0]:] = c
    # Each piece's width: the knots' steps but those from one spline's last knot to the next's
    # first.
    h = np.delete(np.diff(knots), offsets[1:-1] - 1)[:, None] if pieces else np.zeros((0, 1))
    power = np.stack([cubic[0] * h**3, cubic[1] * h**2, cubic[2] * h, cubic[3]], axis=1)
    return _native.Splines.from_pieces(m, knots, offsets, power.ravel(),
                                       np.asarray(extents, dtype=np.float64))


class PiecewiseCubic(PPoly):
    """What every spline of this module shares: knots `x` (a read-only copy), the fitted
    tables, SciPy's `extrapolate`, `axis` and `c`, calls, pickling; the rest (derivatives,
    antiderivatives, integrals, roots) it answers as the `PPoly` it is. Its subclasses are the
    constructors."""

    x: np.ndarray
    axis: int
    extrapolate: bool | str
    context: Context | None
    _fitted = True
    # Tables made at the first call that needs them (`_of_pieces`), until then.
    _deferred: Any
    # The fitted tables (the extension's Splines), the coefficients and `c`, made once.
    _native: Any
    _pieces: np.ndarray | None
    _c: np.ndarray | None
    _complex: bool
    _trailing: tuple

    def _setup(self, x, y, axis, extrapolate, context, complex_ok: str | None = None):
        """x as a read-only float64 copy and y as (n, m) float64 columns (axis `axis` first,
        the other axes flattened; a complex y's real parts then its imaginary parts, refused
        where `complex_ok` names the class that cannot take it), the attributes set."""
        # A copy of x: the caller's array may change after the fit, the spline's knots may not.
        x = np.array(_float64(x, "x"), order="C")
        y = np.asarray(y)
        self._complex = np.iscomplexobj(y)
        if self._complex and complex_ok is not None:
            raise ValueError(f"y: {complex_ok} only works with real values (as SciPy's)")
        if x.ndim != 1:
            raise ValueError(f"x: must be 1-D, got shape {x.shape}")
        if x.shape[0] < 2:
            raise ValueError(f"x: must contain at least 2 elements, got {x.shape[0]}")
        if y.ndim == 0:
            raise ValueError("y: must be at least 1-D, got a 0-d array")
        axis = _axis(axis, y.ndim, "y")
        self._trailing = np.moveaxis(y, axis, 0).shape[1:]
        y2 = self._as_columns(y, axis, "y")
        if y2.shape[0] != x.shape[0]:
            raise ValueError(f"y: {y2.shape[0]} values along axis {axis} for {x.shape[0]} x")
        x.flags.writeable = False
        self.x = x
        self.axis = axis
        self.extrapolate = extrapolate
        self.context = context
        self._pieces = None
        self._c = None
        return x, y2

    @classmethod
    def _of_pieces(cls, x: np.ndarray, c: np.ndarray, extent: float | None, extrapolate,
                   axis: int, context: Context | None) -> PiecewiseCubic:
        """The piecewise polynomial of degree <= 3 with breakpoints x and coefficients c
        (k + 1, P, ...) in SciPy's power form (real or complex), its tables made from them
        when first needed (no fit); `extent` is the spread of the points it was made from,
        which scales the GPU's accuracy promise (None: the spread of its values at the
        breakpoints)."""
        spline = cls.__new__(cls)
        spline._complex = np.iscomplexobj(c)
        spline._trailing = c.shape[2:]
        if x.dtype != np.float64 or x.flags.writeable:
            x = np.array(x, dtype=np.float64)
            x.flags.writeable = False
        spline.x = x
        spline.axis, spline.extrapolate, spline.context = axis, extrapolate, context
        spline._c = None
        columns = c.reshape(c.shape[0], c.shape[1], math.prod(c.shape[2:]))
        if spline._complex:
            columns = np.concatenate([columns.real, columns.imag], axis=2)
        cubic = np.zeros((4, *columns.shape[1:]))
        cubic[4 - columns.shape[0]:] = columns
        spline._pieces = cubic

        def tables():
            # Made at the first call that needs them (a derivative taken only for its roots,
            # integrals or small calls never pays for them). Without an extent given, the
            # spread of the values at the pieces' starts.
            spread = extent
            if spread is None:
                spread = float(np.max(np.ptp(columns[-1], axis=0))) if columns.size else 0.0
            return _in_blocks(
                lambda cut: piece_tables([(x, np.ascontiguousarray(columns[:, :, cut]))], [spread],
                                    "c"),
                columns.shape[2], columns.shape[1])

        spline._deferred = tables
        return spline

    def __getattr__(self, name: str):
        # The deferred tables of `_of_pieces`, made once when first asked for.
        deferred = self.__dict__.get("_deferred")
        if name == "_native" and deferred is not None:
            del self.__dict__["_deferred"]
            self._native = deferred()
            return self._native
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    def _as_columns(self, y, axis: int, name: str) -> np.ndarray:
        """An array of y's shape (`name`: y, or dydx) as the fitted columns."""
        y = np.moveaxis(np.asarray(y), axis, 0)
        y2 = y.reshape(y.shape[0], -1)
        if self._complex:
            y2 = np.concatenate([y2.real, y2.imag], axis=1)
        return np.ascontiguousarray(_float64(y2, name))

    def __reduce__(self):
        attributes = {k: v for k, v in self.__dict__.items() if k not in ("_native",
                                                                          "_deferred")}
        attributes["_pieces"] = attributes["_c"] = None
        return (restore, (type(self), attributes, self._native.state()))

    @property
    def c(self) -> np.ndarray:
        """Coefficients as SciPy's PPoly holds them: shape (4, n - 1) + y's other axes
        (read-only: the spline does not follow changes to them)."""
        if self._c is None:
            c = self._joined(self._coefficients()).reshape(
                (4, len(self.x) - 1, *self._trailing))
            c.flags.writeable = False
            self._c = c
        return self._c

    @c.setter
    def c(self, value) -> None:
        raise AttributeError("c: the spline's coefficients are read-only (its fit does not "
                             "follow them); make a PPoly(c, x) instead")

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
            nu = _order("nu", int(nu) if isinstance(nu, bool) else nu, 1 << 30)
            if nu > 3:
                # Zero, of the shape and type SciPy gives.
                return PPoly.__call__(self, x, nu, extrapolate)
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
        native = shared_context() if ctx is None else ctx._native
        values = None
        if native.backend == "cpu" and "_deferred" in self.__dict__ and \
                len(flat) <= _UNTABULATED_CALL:
            # A derivative's first calls, small: its pieces in float64 without making the
            # tables first (a large call makes them, and evaluates on every thread).
            values = self._by_pieces(self._wrapped(flat, mode), nu)
            if mode is False:
                values[(flat < self.x[0]) | (flat > self.x[-1])] = np.nan
        elif mode is True and len(flat) == 1 and not self.x[0] <= flat[0] <= self.x[-1]:
            # One x past the knots (or NaN): its end piece in float64, without the native
            # call's refusal.
            values = self._by_pieces(flat, nu)
            if native.backend == "gpu":
                values = values.astype(np.float32)
        elif nu <= 2 and mode != "periodic":
            # None for an x outside the knots, or NaN: the general route below takes it.
            values = self._native.evaluate_one(native, flat, nu)
        if values is None:
            values = self._anywhere(native, flat, nu, mode)
        if self._complex:
            values = self._joined(values)
        out = values.reshape(x.shape + self._trailing)
        if self.axis != 0 and x.ndim > 0:
            out = np.moveaxis(out, list(range(x.ndim)), list(range(self.axis, self.axis + x.ndim)))
        return out

    def _wrapped(self, flat: np.ndarray, mode) -> np.ndarray:
        """x wrapped into the knots where `mode` is "periodic"."""
        if mode != "periodic":
            return flat
        lo, hi = self.x[0], self.x[-1]
        return lo + np.mod(flat - lo, hi - lo)

    def _anywhere(self, native, flat: np.ndarray, nu: int, mode) -> np.ndarray:
        """Derivative nu at any x, as (len(x), m) in the fitted columns: inside the knots
        through the context (nu <= 2), elsewhere by the pieces (see `_by_pieces`); NaN outside
        when `mode` is False, x wrapped into the knots when it is "periodic"."""
        lo, hi = self.x[0], self.x[-1]
        flat = self._wrapped(flat, mode)
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
        return _native.evaluate_pieces(_f64(self.x), _f64(self._coefficients()), _f64(x), nu)

    def _like(self, c: np.ndarray, x: np.ndarray, extrapolate) -> PPoly:
        """A piecewise polynomial made from this one (a derivative, an antiderivative): of
        degree <= 3 this class, evaluated through the same context (SciPy's derivative of a
        CubicSpline is a CubicSpline too); above, a `PPoly` in NumPy."""
        if c.shape[0] > 4:
            poly = PPoly._made(c, x, extrapolate, self.axis)
            poly._fitted = True
            return poly
        return type(self)._of_pieces(x, c, None, extrapolate, self.axis, self.context)

    def ppoly(self) -> PPoly:
        """The spline as a plain `PPoly` (its `c`, `x`, `extrapolate` and `axis`), evaluated
        in NumPy."""
        return PPoly._made(self.c.copy(), self.x, self.extrapolate, self.axis)

    def extend(self, c, x) -> None:
        """Pieces c (k', m', ...) with breakpoints x added on the right or the left, as
        `PPoly.extend`; the spline keeps its class while its degree stays <= 3."""
        merged = self.ppoly()
        merged.extend(c, x)
        if merged.c.shape[0] > 4:
            raise ValueError(f"c: pieces of degree {merged.c.shape[0] - 1} make this spline a "
                             f"PPoly of another degree; extend spline.ppoly() instead")
        self.__dict__.update(self._like(merged.c, merged.x, self.extrapolate).__dict__)


class CubicSpline(PiecewiseCubic):
    """`scipy.interpolate.CubicSpline(x, y, axis=0, bc_type="not-a-knot", extrapolate=None)`:
    bc_type "not-a-knot", "natural", "clamped", "periodic" (on 2 points too), or a pair of
    ends, each "not-a-knot", "natural", "clamped" or (order, value) with order 1 or 2 (a
    first or second derivative, value of the shape of y's other axes).

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
        if _complex_ends(bc_type) and not np.iscomplexobj(y):
            # A complex end value makes the spline complex, as SciPy's.
            y = np.asarray(y).astype(np.complex128)
        x, y2 = self._setup(x, y, axis, extrapolate, context)
        name, start, end = bc_of(bc_type, self._trailing, self._complex)
        if len(x) < 4 and name in ("natural", "clamped", "each"):
            # Fewer points than the crate's per-end fit takes: the same cubic through the
            # collocation system, as its pieces.
            self._native = _few_points(x, y2, name, start, end)
            return
        self._native = _in_blocks(
            lambda cut: _native.fit([x], [np.ascontiguousarray(y2[:, cut])], name,
                                    _cut_end(start, cut), _cut_end(end, cut)),
            y2.shape[1], len(x) - 1)


def _complex_ends(bc_type) -> bool:
    """Whether a bc_type of (order, value) ends gives a complex value."""
    if isinstance(bc_type, str):
        return False
    try:
        return any(not isinstance(end, str) and np.iscomplexobj(end[1]) for end in bc_type)
    except (TypeError, IndexError):
        return False


def _few_points(x: np.ndarray, y2: np.ndarray, name: str, start, end) -> Any:
    """The tables of the cubic spline through 2 or 3 points with its ends (`bc_of`'s form;
    "natural" and "clamped" as zero second or first derivatives), as SciPy fits it: on 2
    points a not-a-knot end is the line's slope; on 3, a not-a-knot end drops x_1 (or x_{n-2})
    from the knots, a derivative end adds a condition."""
    m = y2.shape[1]
    orders = {"first": 1, "second": 2}
    if start is None:
        start = end = ("second" if name == "natural" else "first", None)
    slope = (y2[-1] - y2[0]) / (x[-1] - x[0])
    ends: list = []
    inner = list(x[1:-1])
    for side, (order, values) in enumerate((start, end)):
        if order == "not-a-knot" and len(x) == 2:
            order, values = "first", slope
        if order == "not-a-knot":
            inner = inner[1:] if side == 0 else inner[:-1]
            ends.append([])
        else:
            ends.append([(orders[order], np.zeros(m) if values is None else
                          np.asarray(values, dtype=np.float64))])
    t = np.concatenate([np.repeat(x[:1], 4), inner, np.repeat(x[-1:], 4)])
    c = _collocation.coefficients(x, y2, t, 3, *ends)
    coeff = _bspl.taylor(t, c, 3, x[:-1])
    extent = float(np.max(np.ptp(y2, axis=0))) if y2.size else 0.0
    return _in_blocks(
        lambda cut: piece_tables([(x, np.ascontiguousarray(coeff[:, :, cut]))], [extent], "c"),
        m, len(x) - 1)


class CubicHermiteSpline(PiecewiseCubic):
    """`scipy.interpolate.CubicHermiteSpline(x, y, dydx, axis=0, extrapolate=None)`: the
    cubic through every point with the derivative `dydx` there (y's shape; complex with a
    complex y). As `CubicSpline` in everything else; `extrapolate` None means True."""

    def __init__(self, x, y, dydx, axis: int = 0, extrapolate=None,
                 context: Context | None = None):
        extrapolate = _extrapolate(extrapolate)
        x, y2 = self._setup(x, y, axis, True if extrapolate is None else extrapolate, context)
        dydx = np.asarray(dydx)
        if dydx.shape != np.shape(y):
            raise ValueError(f"dydx: must have y's shape {np.shape(y)}, got {dydx.shape}")
        if np.iscomplexobj(dydx) and not self._complex:
            raise ValueError("dydx: complex values with a real y (make y complex too)")
        slopes = self._as_columns(dydx, self.axis, "dydx")
        self._native = _in_blocks(
            lambda cut: _native.fit_hermite([x], [np.ascontiguousarray(y2[:, cut])], "given",
                                            [np.ascontiguousarray(slopes[:, cut])]),
            y2.shape[1], len(x) - 1)


class PchipInterpolator(PiecewiseCubic):
    """`scipy.interpolate.PchipInterpolator(x, y, axis=0, extrapolate=None)`: monotone cubic
    interpolation (Fritsch-Carlson-Butland slopes, SciPy's ends), each of y's columns on its
    own; real y only, as SciPy's. As `CubicSpline` in everything else; `extrapolate` None
    means True."""

    def __init__(self, x, y, axis: int = 0, extrapolate=None, context: Context | None = None):
        extrapolate = _extrapolate(extrapolate)
        x, y2 = self._setup(x, y, axis, True if extrapolate is None else extrapolate, context,
                              complex_ok="PchipInterpolator")
        self._native = _in_blocks(
            lambda cut: _native.fit_hermite([x], [np.ascontiguousarray(y2[:, cut])], "pchip",
                                            None),
            y2.shape[1], len(x) - 1)


class Akima1DInterpolator(PiecewiseCubic):
    """`scipy.interpolate.Akima1DInterpolator(x, y, axis=0, *, method="akima",
    extrapolate=None)`: Akima's slopes, or the modified ("makima") ones, each of y's columns
    on its own; real y only, as SciPy's. As `CubicSpline` in everything else; `extrapolate`
    None means False, as SciPy's."""

    def __init__(self, x, y, axis: int = 0, *, method: str = "akima", extrapolate=None,
                 context: Context | None = None):
        if method not in ("akima", "makima"):
            raise NotImplementedError(f"`method`={method} is unsupported.")
        extrapolate = _extrapolate(extrapolate)
        x, y2 = self._setup(x, y, axis, False if extrapolate is None else extrapolate,
                              context, complex_ok="Akima1DInterpolator")
        self._native = _in_blocks(
            lambda cut: _native.fit_hermite([x], [np.ascontiguousarray(y2[:, cut])], method,
                                            None),
            y2.shape[1], len(x) - 1)

    def extend(self, c, x) -> None:
        """Refused, as SciPy's."""
        raise NotImplementedError("Extending a 1-D Akima interpolator is not yet implemented")


def pchip_interpolate(xi, yi, x, der=0, axis: int = 0):
    """`scipy.interpolate.pchip_interpolate(xi, yi, x, der=0, axis=0)`: the PCHIP through
    (xi, yi) at x, derivative `der` (an order, or a list of orders for a list of arrays)."""
    spline = PchipInterpolator(xi, yi, axis=axis)
    if isinstance(der, (list, tuple, np.ndarray)):
        return [spline(x, int(nu)) for nu in der]
    return spline(x, der)


