"""SciPy's 1-D cubic splines (`scipy.interpolate`'s names and signatures for the cubic case),
fitted in float64 on the host and evaluated through a `Context`: `import
splinegpu.interpolate as si` runs SciPy code unchanged where it is covered (python/README.md
has the table of what is and how it differs).

    >>> import numpy as np, splinegpu.interpolate as si
    >>> x = np.linspace(0, 10, 11)
    >>> s = si.PchipInterpolator(x, np.sqrt(x))
    >>> float(s(2.5))  # doctest: +ELLIPSIS
    1.57...
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from . import _bspline, _native
from ._arrays import _aligned, _axis, _flat, _float64, _natural, _order, _stacked
from ._context import Context, _default_context, _shared_context
from ._ppoly import PPoly, _extrapolate, _integrals, _solved

__all__ = ["Akima1DInterpolator", "Akima1DInterpolators", "BSpline", "BSplines",
           "CubicHermiteSpline", "CubicHermiteSplines", "CubicSpline", "CubicSplines", "PPoly",
           "PPolys", "PchipInterpolator", "PchipInterpolators", "make_interp_spline",
           "make_interp_splines", "pchip_interpolate"]

# The most coordinates a curve's point has (the crate's MAX_DIM): the columns fitted together.
_MAX_COLUMNS = 64
_F64 = np.dtype(np.float64)


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


def _restore(cls, attributes: dict, state):
    """A spline `__reduce__` saved: its attributes, and its tables restored bit for bit."""
    spline = cls.__new__(cls)
    spline.__dict__.update(attributes)
    spline._native = _native.Splines.from_state(state)
    return spline


def _tables(pieces: list, extents: Sequence[float], name: str) -> Any:
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


class _Piecewise:
    """What every spline of this module shares: knots `x` (a read-only copy), the fitted
    tables, SciPy's `extrapolate`, `axis` and `c`, calls with nu = 0 to 3, derivatives,
    pickling. Its subclasses are the constructors."""

    x: np.ndarray
    axis: int
    extrapolate: bool | str
    context: Context | None
    # The fitted tables (the extension's Splines), the coefficients and `c`, made once.
    _native: Any
    _pieces: np.ndarray | None
    _c: np.ndarray | None
    _complex: bool
    _trailing: tuple

    def _columns(self, x, y, axis, extrapolate, context, complex_ok: str | None = None):
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
    def _of_pieces(cls, x: np.ndarray, c: np.ndarray, extent: float, extrapolate, axis: int,
                   context: Context | None) -> _Piecewise:
        """The piecewise polynomial of degree <= 3 with breakpoints x and coefficients c
        (k + 1, P, ...) in SciPy's power form (real or complex), its tables made from them
        (no fit); `extent` is the spread of the points it was made from, which scales the
        GPU's accuracy promise."""
        spline = cls.__new__(cls)
        spline._complex = np.iscomplexobj(c)
        spline._trailing = c.shape[2:]
        spline.x = np.array(x, dtype=np.float64)
        spline.x.flags.writeable = False
        spline.axis, spline.extrapolate, spline.context = axis, extrapolate, context
        spline._pieces = spline._c = None
        columns = c.reshape(c.shape[0], c.shape[1], -1)
        if spline._complex:
            columns = np.concatenate([columns.real, columns.imag], axis=2)
        spline._native = _tables([(spline.x, columns)], [extent], "c")
        return spline

    def _as_columns(self, y, axis: int, name: str) -> np.ndarray:
        """An array of y's shape (`name`: y, or dydx) as the fitted columns."""
        y = np.moveaxis(np.asarray(y), axis, 0)
        y2 = y.reshape(y.shape[0], -1)
        if self._complex:
            y2 = np.concatenate([y2.real, y2.imag], axis=1)
        y2 = np.ascontiguousarray(_float64(y2, name))
        if y2.shape[1] > _MAX_COLUMNS:
            raise ValueError(f"{name}: at most {_MAX_COLUMNS} values per x are fitted together "
                             f"(y's axes but `axis`, a complex y counting twice), got "
                             f"{y2.shape[1]}")
        return y2

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

    def ppoly(self) -> PPoly:
        """The spline as a `PPoly` (its `c`, `x`, `extrapolate` and `axis`; SciPy's classes
        are PPoly subclasses, these convert)."""
        return PPoly._made(self.c.copy(), self.x, self.extrapolate, self.axis)

    def antiderivative(self, nu: int = 1) -> PPoly:
        """The nu-th antiderivative as a `PPoly` of degree 3 + nu, as SciPy's."""
        return self.ppoly().antiderivative(nu)

    def solve(self, y=0.0, discontinuity: bool = True, extrapolate=None):
        """The x where the spline equals y, as SciPy's (see `PPoly.solve`)."""
        return self.ppoly().solve(y, discontinuity, extrapolate)

    def roots(self, discontinuity: bool = True, extrapolate=None):
        """The spline's zeros, as SciPy's (see `PPoly.solve`)."""
        return self.ppoly().roots(discontinuity, extrapolate)

    def integrate(self, a, b, extrapolate=None) -> np.ndarray:
        """The integral from a to b (b < a: its negative), shape y's other axes, in float64
        from `c`, as SciPy's (see `PPoly.integrate`): `extrapolate` None (the spline's), True
        (the end pieces past the knots), False (NaN when a or b lies outside them) or
        "periodic" (whole periods and the rest, wrapped)."""
        return self.ppoly().integrate(a, b, extrapolate)


class CubicSpline(_Piecewise):
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
        x, y2 = self._columns(x, y, axis, extrapolate, context)
        name, start, end = _bc(bc_type, self._trailing, self._complex)
        self._native = _native.fit([x], [y2], name, start, end)


class CubicHermiteSpline(_Piecewise):
    """`scipy.interpolate.CubicHermiteSpline(x, y, dydx, axis=0, extrapolate=None)`: the
    cubic through every point with the derivative `dydx` there (y's shape; complex with a
    complex y). As `CubicSpline` in everything else; `extrapolate` None means True."""

    def __init__(self, x, y, dydx, axis: int = 0, extrapolate=None,
                 context: Context | None = None):
        extrapolate = _extrapolate(extrapolate)
        x, y2 = self._columns(x, y, axis, True if extrapolate is None else extrapolate, context)
        dydx = np.asarray(dydx)
        if dydx.shape != np.shape(y):
            raise ValueError(f"dydx: must have y's shape {np.shape(y)}, got {dydx.shape}")
        if np.iscomplexobj(dydx) and not self._complex:
            raise ValueError("dydx: complex values with a real y (make y complex too)")
        slopes = self._as_columns(dydx, self.axis, "dydx")
        self._native = _native.fit_hermite([x], [y2], "given", [slopes])


class PchipInterpolator(_Piecewise):
    """`scipy.interpolate.PchipInterpolator(x, y, axis=0, extrapolate=None)`: monotone cubic
    interpolation (Fritsch-Carlson-Butland slopes, SciPy's ends), each of y's columns on its
    own; real y only, as SciPy's. As `CubicSpline` in everything else; `extrapolate` None
    means True."""

    def __init__(self, x, y, axis: int = 0, extrapolate=None, context: Context | None = None):
        extrapolate = _extrapolate(extrapolate)
        x, y2 = self._columns(x, y, axis, True if extrapolate is None else extrapolate, context,
                              complex_ok="PchipInterpolator")
        self._native = _native.fit_hermite([x], [y2], "pchip", None)


class Akima1DInterpolator(_Piecewise):
    """`scipy.interpolate.Akima1DInterpolator(x, y, axis=0, *, method="akima",
    extrapolate=None)`: Akima's slopes, or the modified ("makima") ones, each of y's columns
    on its own; real y only, as SciPy's. As `CubicSpline` in everything else; `extrapolate`
    None means False, as SciPy's."""

    def __init__(self, x, y, axis: int = 0, *, method: str = "akima", extrapolate=None,
                 context: Context | None = None):
        if method not in ("akima", "makima"):
            raise ValueError(f"method: must be \"akima\" or \"makima\", got {method!r}")
        extrapolate = _extrapolate(extrapolate)
        x, y2 = self._columns(x, y, axis, False if extrapolate is None else extrapolate,
                              context, complex_ok="Akima1DInterpolator")
        self._native = _native.fit_hermite([x], [y2], method, None)


def pchip_interpolate(xi, yi, x, der=0, axis: int = 0):
    """`scipy.interpolate.pchip_interpolate(xi, yi, x, der=0, axis=0)`: the PCHIP through
    (xi, yi) at x, derivative `der` (an order, or a list of orders for a list of arrays)."""
    spline = PchipInterpolator(xi, yi, axis=axis)
    if isinstance(der, (list, tuple, np.ndarray)):
        return [spline(x, int(nu)) for nu in der]
    return spline(x, der)


class BSpline:
    """`scipy.interpolate.BSpline(t, c, k, extrapolate=True, axis=0)`: sum_i c_i B_{i,k}(x)
    on knots t, any degree k >= 0; c real or complex, of shape (>= n, ...) along `axis`
    (n = len(t) - k - 1; rows past n are kept and ignored, as SciPy's). Calls (any nu, and
    `extrapolate` True, False or "periodic" over the base interval [t[k], t[n]]),
    `derivative`, `antiderivative` (their t, c, k laid out as SciPy's), `integrate` (False:
    zero outside the base interval), `tck`.

    Evaluated as its polynomial pieces (made once, in float64): of degree 3 and below through
    `context` as `CubicSpline`'s (the same promise on the GPU), above it (an antiderivative of
    a cubic) in NumPy on the CPU. Differences from SciPy: `t` and `c` are read-only copies;
    non-finite coefficients are refused (SciPy's evaluate to NaN); `integrate` with
    extrapolate False gives 0 past the base interval for an N-D c too (SciPy's N-D path gives
    NaN there, its 1-D path 0); `basis_element`, `design_matrix`, `from_power_basis` and
    `insert_knot` are absent.
    """

    t: np.ndarray
    c: np.ndarray
    k: int
    axis: int
    extrapolate: bool | str
    context: Context | None
    # The polynomial pieces, made at the first call (or handed over by make_interp_spline).
    _pp: Any

    def __init__(self, t, c, k: int = 3, extrapolate=True, axis: int = 0,
                 context: Context | None = None):
        k = _natural("k", k)
        t = np.array(_float64(t, "t"), order="C")
        c = np.asarray(c)
        if c.dtype.kind not in "biufc":
            raise TypeError(f"c: must be numbers, got an array of {c.dtype}")
        if c.ndim == 0:
            raise ValueError("c: must be at least 1-D, got a 0-d array")
        axis = _axis(axis, c.ndim, "c")
        c = np.array(np.moveaxis(c, axis, 0),
                     dtype=np.complex128 if c.dtype.kind == "c" else np.float64, order="C")
        _bspline.check(t, c.shape[0], k)
        if not np.all(np.isfinite(c)):
            raise ValueError("c: the coefficients must be finite")
        extrapolate = _extrapolate(extrapolate)
        self._set(t, c, k, True if extrapolate is None else extrapolate, axis, context)

    def _set(self, t, c, k, extrapolate, axis, context) -> None:
        t.flags.writeable = False
        c.flags.writeable = False
        self.t, self.c, self.k = t, c, k
        self.extrapolate, self.axis, self.context = extrapolate, axis, context
        self._pp = None

    @classmethod
    def construct_fast(cls, t, c, k: int, extrapolate=True, axis: int = 0,
                       context: Context | None = None) -> BSpline:
        """A BSpline of float64 (or complex128) t and c (axis first) taken as they are, as
        SciPy's (no checks; the arrays are made read-only)."""
        spline = cls.__new__(cls)
        spline._set(t, c, k, extrapolate, axis, context)
        return spline

    @property
    def tck(self) -> tuple:
        """(t, c, k)."""
        return self.t, self.c, self.k

    def _pieces(self):
        """The spline's polynomial pieces on its base interval, made once."""
        if self._pp is None:
            n = len(self.t) - self.k - 1
            c = self.c[:n].reshape(n, -1)
            breaks, coeff = _bspline.pieces(self.t, c, self.k)
            coeff = coeff.reshape(coeff.shape[:2] + self.c.shape[1:])
            if self.k <= 3:
                extent = float(np.max(np.ptp(np.concatenate([c.real, c.imag], axis=1), axis=0)))
                self._pp = _Piecewise._of_pieces(breaks, coeff, extent, self.extrapolate,
                                                 self.axis, self.context)
            else:
                self._pp = PPoly._made(coeff, breaks, self.extrapolate, self.axis)
        return self._pp

    def __call__(self, x, nu: int = 0, extrapolate=None) -> np.ndarray:
        """Derivative nu (>= 0) at x, shape x.shape + c.shape[1:] (x's axes at `axis`);
        `extrapolate` None (the spline's), True (the end pieces continue), False (NaN outside
        [t[k], t[n]]) or "periodic" (x wrapped into it)."""
        nu = _natural("nu", nu)
        mode = self.extrapolate if extrapolate is None else _extrapolate(extrapolate)
        pp = self._pieces()
        if isinstance(pp, _Piecewise) and nu <= 3:
            return pp(x, nu, mode)
        if isinstance(pp, _Piecewise):
            pp = pp.ppoly()
        return pp(x, nu, mode)

    def derivative(self, nu: int = 1) -> BSpline:
        """The nu-th derivative as a BSpline of degree k - nu (SciPy's t and c)."""
        t, c, k = _bspline.derivative(self.t, self.c, self.k, _natural("nu", nu))
        return self.construct_fast(t, c, k, self.extrapolate, self.axis, self.context)

    def antiderivative(self, nu: int = 1) -> BSpline:
        """The nu-th antiderivative, zero at t[0], as a BSpline of degree k + nu (SciPy's t and
        c); a periodic extrapolation becomes False, as SciPy's."""
        t, c, k = _bspline.antiderivative(self.t, self.c, self.k, _natural("nu", nu))
        extrapolate = False if self.extrapolate == "periodic" else self.extrapolate
        return self.construct_fast(t, c, k, extrapolate, self.axis, self.context)

    def integrate(self, a, b, extrapolate=None) -> np.ndarray:
        """The integral from a to b (b < a: its negative), shape c.shape[1:], in float64 from
        the pieces: `extrapolate` None (the spline's), True (the end pieces past the base
        interval), False (the spline taken as zero outside [t[k], t[n]]) or "periodic"."""
        mode = self.extrapolate if extrapolate is None else _extrapolate(extrapolate)
        pp = self._pieces()
        if mode is False:
            lo, hi = pp.x[0], pp.x[-1]
            a, b = min(max(float(a), lo), hi), min(max(float(b), lo), hi)
            mode = True
        return pp.integrate(a, b, mode)

    def __reduce__(self):
        return (_restore_bspline, (self.__dict__,))


def _restore_bspline(attributes: dict) -> BSpline:
    """A BSpline `__reduce__` saved, its pieces included (as `make_interp_spline` fitted them),
    its t and c read-only again."""
    spline = BSpline.__new__(BSpline)
    spline.__dict__.update(attributes)
    spline.t.flags.writeable = spline.c.flags.writeable = False
    return spline


def make_interp_spline(x, y, k: int = 3, t=None, bc_type=None, axis: int = 0,
                       check_finite: bool = True, context: Context | None = None) -> BSpline:
    """`scipy.interpolate.make_interp_spline(x, y, k=3, t=None, bc_type=None, axis=0)`, the
    cubic case: the interpolating cubic B-spline with SciPy's knots and coefficients. bc_type
    None or "not-a-knot" (x_1 and x_{n-2} are not knots; at least 4 points), "natural",
    "clamped", "periodic", or a pair (left, right), each "natural", "clamped" or a list of one
    (order, value) with order 1 or 2.

    Fitted as `CubicSpline` (O(n), float64), whose pieces the result evaluates; the B-spline
    coefficients are read off them by blossoming. Differences from SciPy: only k = 3 and knots
    of its choosing (`t` None); two conditions at one end and none at the other, or orders 0
    and 3, are refused; `check_finite` is always on (NaN and infinity are refused)."""
    if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or k != 3:
        raise ValueError(f"k: only the cubic case (k=3) is built, got {k!r}")
    if t is not None:
        raise ValueError("t: only the knots make_interp_spline chooses itself are built (pass "
                         "t=None)")
    bc = _interp_bc(bc_type)
    fitted = CubicSpline(x, y, axis=axis, bc_type=bc, context=context)
    if bc == "not-a-knot" and len(fitted.x) < 4:
        raise ValueError(f"x: not-a-knot needs at least 4 points for k=3, got {len(fitted.x)}")
    knots, c = _interp_coefficients(fitted.x, fitted.c.reshape(4, len(fitted.x) - 1, -1), bc)
    c = c.reshape((len(c), *fitted.c.shape[2:]))
    spline = BSpline.construct_fast(knots, c, 3, "periodic" if bc == "periodic" else True,
                                    fitted.axis, context)
    fitted.extrapolate = spline.extrapolate
    spline._pp = fitted
    return spline


def _interp_coefficients(x: np.ndarray, pieces: np.ndarray, bc):
    """make_interp_spline's knots for x and bc (CubicSpline's form), and the coefficients
    (n, m) of the cubic (pieces (4, len(x) - 1, m) in SciPy's power form) on them."""
    period = None
    if bc == "periodic":
        knots, period = _bspline.periodic_knots(x), x[-1] - x[0]
    elif bc == "not-a-knot":
        knots = _bspline.not_a_knot_knots(x)
    else:
        knots = _bspline.end_knots(x)
    return knots, _bspline.cubic_coefficients(knots, x, pieces, period)


def _interp_bc(bc_type):
    """make_interp_spline's bc_type as CubicSpline's."""
    if bc_type is None:
        return "not-a-knot"
    if isinstance(bc_type, str):
        if bc_type not in ("not-a-knot", "natural", "clamped", "periodic"):
            raise ValueError(f"bc_type: unknown boundary condition {bc_type!r}")
        return bc_type
    try:
        left, right = bc_type
    except (TypeError, ValueError):
        raise ValueError(f"bc_type: must be None, a name, or a pair (left, right), got "
                         f"{bc_type!r}") from None
    if left is None and right is None:
        return "not-a-knot"

    def end(spec, where: str):
        if isinstance(spec, str):
            if spec not in ("natural", "clamped"):
                raise ValueError(f"bc_type: unknown boundary condition {spec!r} at the {where}")
            return spec
        try:
            (order, value), = spec
        except (TypeError, ValueError):
            raise ValueError(f"bc_type: the {where} end must be \"natural\", \"clamped\" or a "
                             f"list of one (order, value) for k=3, got {spec!r}") from None
        if isinstance(order, bool) or order not in (1, 2):
            raise ValueError(f"bc_type: the derivative order at the {where} end must be 1 or 2 "
                             f"here, got {order!r}")
        return (int(order), value)

    return (end(left, "left"), end(right, "right"))


class _Derivative:
    """A derivative of a spline of this module: evaluated through its spline."""

    def __init__(self, spline: _Piecewise, nu: int):
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


class _Batch:
    """Many splines with their own knots, fitted and evaluated in one batch: `xs` a list of
    1-D knot arrays (or a 2-D array, one row per spline), `ys` matching (n_i, m) arrays (or an
    (S, n, m) array). Calling with one array of x per spline returns (values (N, m),
    offsets (S + 1,)): spline i's values are rows offsets[i]:offsets[i+1], every spline in one
    call on the context. Its subclasses are the constructors."""

    context: Context | None
    _native: Any

    @staticmethod
    def _arrays(xs, ys, name: str = "ys", xname: str = "xs"):
        """xs and ys as the extension takes them, and ys' trailing shape (its values per x)."""
        xs, ys = _stacked(xs, xs), _stacked(ys, ys)
        if isinstance(xs, np.ndarray) and xs.ndim == 2:
            xs = _aligned(xs, xname)
        else:
            xs = [_flat(x, xname) for x in xs]
        # One (S, n, m) array, or a list of (n_i, m) arrays.
        ys2: Any
        if isinstance(ys, np.ndarray) and ys.ndim >= 2:
            trailing = ys.shape[2:]
            ys2 = _aligned(_float64(ys, name).reshape(ys.shape[0], ys.shape[1], -1), name)
        else:
            ys = [_float64(y, name) for y in ys]
            trailing = ys[0].shape[1:] if ys else ()
            for i, y in enumerate(ys):
                if y.ndim == 0 or y.shape[1:] != trailing:
                    raise ValueError(f"{name}[{i}]: every spline's values must have the shape "
                                     f"(n_i,) + {trailing}, got {y.shape}")
            ys2 = [_aligned(y.reshape(len(y), -1), name) for y in ys]
        return xs, ys2, trailing

    def __reduce__(self):
        # As a single spline's: the fitted tables bit for bit, the context as its backend.
        attributes = {k: v for k, v in self.__dict__.items() if k != "_native"}
        return (_restore, (type(self), attributes, self._native.state()))

    def __len__(self) -> int:
        return len(self._native)

    # The single class's `extrapolate` default, which `solve`, `roots` and `integrate` take.
    _extrapolates: bool | str = True
    # Whether `integrate` with extrapolate False takes the splines as zero outside their knots
    # (BSpline's rule) rather than giving NaN (PPoly's).
    _zero_outside = False

    def solve(self, y=0.0, discontinuity: bool = True, extrapolate=None):
        """Every spline's x where it equals y, as the single class's `solve` finds them, all
        splines' pieces at once: (roots (R,), offsets (S + 1,)), spline i's roots in
        roots[offsets[i]:offsets[i+1]] (NaN after the start of a piece equal to y
        everywhere). For splines of one value per x."""
        mode = bool(self._extrapolates if extrapolate is None else _extrapolate(extrapolate))
        y, discontinuity = float(y), bool(discontinuity)
        return _solved(self._native.solve(y, discontinuity, mode), y)

    def roots(self, discontinuity: bool = True, extrapolate=None):
        """`solve(0, ...)`."""
        return self.solve(0.0, discontinuity, extrapolate)

    def integrate(self, a, b, extrapolate=None) -> np.ndarray:
        """Every spline's integral from a to b (each a number for all splines, or one per
        spline), as the single class's `integrate` answers, all splines' pieces at once:
        shape (S, m). `extrapolate` None (the single class's default), True, False (NaN where
        a or b lies outside the spline's knots) or "periodic"."""
        c, start, end, offsets = self._native.pieces()
        splines = len(offsets) - 1
        limits = []
        for name, value in (("a", a), ("b", b)):
            value = _float64(value, name)
            if value.ndim > 1 or value.size not in (1, splines):
                raise ValueError(f"{name}: must be a number or one per spline ({splines}), got "
                                 f"shape {value.shape}")
            limits.append(np.broadcast_to(value.reshape(-1), (splines,)))
        mode = self._extrapolates if extrapolate is None else _extrapolate(extrapolate)
        if mode is False and self._zero_outside:
            lo, hi = start[offsets[:-1]], end[offsets[1:] - 1]
            limits = [np.clip(limit, lo, hi) for limit in limits]
            mode = True
        return _integrals(c, start, end, offsets, limits[0], limits[1], mode)

    def __call__(self, xs: Sequence[Any], nu: int = 0):
        """Spline i at xs[i] (a list of arrays, or a (S, k) array), derivative nu (0 to 2)
        -> (values, offsets). Every x must lie within its spline's knots."""
        xs = _stacked(xs, xs)
        if isinstance(xs, np.ndarray) and xs.ndim == 2:
            flat = _aligned(xs, "xs")
        else:
            flat = [_flat(x, "xs") for x in xs]
        ctx = self.context or _default_context()
        return self._native.evaluate(ctx._native, flat, _order("nu", nu, 2))


class CubicSplines(_Batch):
    """Many `CubicSpline`s (any `bc_type` form, the same for all) in one batch; see `_Batch`."""

    def __init__(self, xs, ys, bc_type="not-a-knot", context: Context | None = None):
        xs, ys2, trailing = self._arrays(xs, ys)
        name, start, end = _bc(bc_type, trailing)
        self._native = _native.fit(xs, ys2, name, start, end)
        self.context = context
        if name == "periodic":
            self._extrapolates = "periodic"


class CubicHermiteSplines(_Batch):
    """Many `CubicHermiteSpline`s in one batch: `dydxs` shaped as `ys`; see `_Batch`."""

    def __init__(self, xs, ys, dydxs, context: Context | None = None):
        xs, ys2, _ = self._arrays(xs, ys)
        _, slopes, _ = self._arrays(xs, dydxs, "dydxs")
        self._native = _native.fit_hermite(xs, ys2, "given", slopes)
        self.context = context


class PchipInterpolators(_Batch):
    """Many `PchipInterpolator`s in one batch; see `_Batch`."""

    def __init__(self, xs, ys, context: Context | None = None):
        xs, ys2, _ = self._arrays(xs, ys)
        self._native = _native.fit_hermite(xs, ys2, "pchip", None)
        self.context = context


class Akima1DInterpolators(_Batch):
    """Many `Akima1DInterpolator`s (one `method` for all) in one batch; see `_Batch`."""

    _extrapolates = False

    def __init__(self, xs, ys, *, method: str = "akima", context: Context | None = None):
        if method not in ("akima", "makima"):
            raise ValueError(f"method: must be \"akima\" or \"makima\", got {method!r}")
        xs, ys2, _ = self._arrays(xs, ys)
        self._native = _native.fit_hermite(xs, ys2, method, None)
        self.context = context


class BSplines(_Batch):
    """Many `BSpline`s of one degree k <= 3 in one batch: `ts` a list of knot arrays (or a 2-D
    array, one row per spline), `cs` matching (n_i, m) arrays of real coefficients (or an
    (S, n, m) array; rows past n_i are ignored, as BSpline's); each spline's pieces are made
    once, all splines' together. `extrapolate` (True, False or "periodic") is the default of
    `integrate` (False: zero outside each base interval, as BSpline's), `roots` and `solve`;
    calls take x within each spline's base interval (see `_Batch`). `batch[i]` is spline i as
    a `BSpline`."""

    k: int
    # Where the splines' t and c come from: ("given", ts, cs, trailing shape), or ("fitted",
    # the knots, bc_type, trailing shape) for make_interp_splines.
    _source: tuple
    _zero_outside = True

    def __init__(self, ts, cs, k: int = 3, extrapolate=True, context: Context | None = None):
        k = _natural("k", k)
        if k > 3:
            raise ValueError(f"k: a batch evaluates degrees up to 3, got {k} (BSpline takes "
                             f"any)")
        # As the extension takes them (a 2-D ts or 3-D cs stays one array, borrowed once), and
        # as lists of the splines' arrays.
        ts_given, cs_given, trailing = self._arrays(ts, cs, "cs", "ts")
        ts, cs2 = list(ts_given), list(cs_given)
        if len(ts) != len(cs2):
            raise ValueError(f"cs: {len(cs2)} splines' coefficients for {len(ts)} knot arrays")

        def named(s, what):
            return f"{what}s[{s}]"

        _bspline.check_many(ts, [len(c) for c in cs2], k, named)
        for i, c in enumerate(cs2):
            if not np.all(np.isfinite(c)):
                raise ValueError(f"cs[{i}]: the coefficients must be finite")
        self._native = _tables([], [], "cs") if not ts else None
        if k == 3 and ts:
            try:
                # The crate's cubic B-splines (kind "nurbs"), made on every thread.
                self._native = _native.fit_bspline(ts_given, cs_given)
            except ValueError:
                # What the crate refuses but SciPy takes (a knot inside the base interval 4
                # times, where the spline breaks): the pieces from NumPy.
                pass
        if self._native is None:
            made = _bspline.many_pieces(ts, cs2, k)
            # Each spline's extent: the largest per-column spread of its coefficients.
            n = [len(t) - k - 1 for t in ts]
            used = np.concatenate([c[:count] for c, count in zip(cs2, n)])
            starts = np.concatenate([[0], np.cumsum(n)[:-1]])
            spread = np.maximum.reduceat(used, starts, axis=0) - np.minimum.reduceat(
                used, starts, axis=0)
            self._native = _tables(made, spread.max(axis=1), "cs")
        self.k, self.context = k, context
        extrapolate = _extrapolate(extrapolate)
        self._extrapolates = True if extrapolate is None else extrapolate
        self._source = ("given", ts, cs2, trailing)

    def __getitem__(self, i: int) -> BSpline:
        i = range(len(self))[i]
        how, first, second, trailing = self._source
        if how == "given":
            t, c = np.array(first[i]), second[i]
        else:
            t, c = _interp_coefficients(first[i], self._native.coefficients(i), second)
        c = c.reshape((len(c), *trailing))
        return BSpline.construct_fast(t, np.array(c), self.k, self._extrapolates, 0,
                                      self.context)


def make_interp_splines(xs, ys, bc_type=None, context: Context | None = None) -> BSplines:
    """Many `make_interp_spline(x, y, k=3, bc_type=bc_type)`s in one batch: `xs` and `ys` as
    `CubicSplines` takes them, fitted together; evaluated as their fitted pieces, `batch[i]`
    is spline i with SciPy's knots and coefficients."""
    bc = _interp_bc(bc_type)
    batch = BSplines.__new__(BSplines)
    # A 2-D xs stays one array: the extension borrows it once (not once per row).
    xs, ys2, trailing = batch._arrays(xs, ys)
    if bc == "not-a-knot":
        for i, x in enumerate(xs):
            if len(x) < 4:
                raise ValueError(f"xs[{i}]: not-a-knot needs at least 4 points for k=3, got "
                                 f"{len(x)}")
    name, start, end = _bc(bc, trailing)
    batch._native = _native.fit(xs, ys2, name, start, end)
    batch.k, batch.context = 3, context
    batch._extrapolates = "periodic" if bc == "periodic" else True
    batch._source = ("fitted", [np.array(x) for x in xs], bc, trailing)
    return batch


class PPolys(_Batch):
    """Many `PPoly`s of degree <= 3 in one batch: `cs` a list of (k, P_i) or (k, P_i, m)
    coefficient arrays in SciPy's layout (k <= 4, one k and m for all), `xs` their P_i + 1
    increasing breakpoints each. `extrapolate` (True, False or "periodic") is the default of
    `integrate`, `roots` and `solve`; calls take x within each spline's breakpoints (see
    `_Batch`)."""

    def __init__(self, cs, xs, extrapolate=None, context: Context | None = None):
        cs = [np.asarray(_float64(c, f"cs[{i}]")) for i, c in enumerate(cs)]
        xs = [_flat(x, f"xs[{i}]") for i, x in enumerate(xs)]
        if len(cs) != len(xs):
            raise ValueError(f"cs: {len(cs)} coefficient arrays for {len(xs)} breakpoint arrays")
        shape = cs[0].shape[:1] + cs[0].shape[2:] if cs else (4,)
        pieces = []
        for i, (c, x) in enumerate(zip(cs, xs)):
            if c.ndim not in (2, 3) or c.shape[:1] + c.shape[2:] != shape or shape[0] > 4:
                raise ValueError(f"cs[{i}]: must have the shape (k, P, ...) of cs[0], {shape} "
                                 f"with k <= 4 (degree 3 at most), got {c.shape}")
            if len(x) != c.shape[1] + 1 or not np.all(np.diff(x) > 0):
                raise ValueError(f"xs[{i}]: must be {c.shape[1] + 1} increasing breakpoints "
                                 f"for {c.shape[1]} pieces, got {len(x)}")
            pieces.append((x, c.reshape(c.shape[0], c.shape[1], -1)))
        # Each spline's extent: the spread of its values at the pieces' starts.
        extents = [float(np.max(np.ptp(c[-1], axis=0))) for _, c in pieces]
        self._native = _tables(pieces, extents, "cs")
        self.context = context
        extrapolate = _extrapolate(extrapolate)
        self._extrapolates = True if extrapolate is None else extrapolate
