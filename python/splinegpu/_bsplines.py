"""SciPy's `BSpline` and `make_interp_spline` (any degree k): knots and coefficients kept
as SciPy lays them out, evaluated as polynomial pieces (degree <= 3 through a `Context`, above
in NumPy); the cubic interpolant with SciPy's usual ends fitted as `CubicSpline` (O(n) in the
crate), every other degree and end through the banded collocation system of `_collocation`.
"""

from __future__ import annotations

import operator
from typing import Any

import numpy as np

from . import _bspl, _collocation, _native
from ._context import Context
from ._cubic import CubicSpline, PiecewiseCubic
from ._helpers import _F64, _axis, _extrapolate, _f64, _float64, _natural
from ._ppoly import PPoly

_COMPLEX = np.dtype(np.complex128)


class BSpline:
    """`scipy.interpolate.BSpline(t, c, k, extrapolate=True, axis=0)`: sum_i c_i B_{i,k}(x)
    on knots t, any degree k >= 0; c real or complex, of shape (>= n, ...) along `axis`
    (n = len(t) - k - 1; rows past n are kept and ignored, as SciPy's). Calls (any nu, and
    `extrapolate` True, False or "periodic" over the base interval [t[k], t[n]]),
    `derivative`, `antiderivative` (their t, c, k laid out as SciPy's), `integrate` (False:
    zero outside the base interval), `tck`.

    Evaluated on the CPU as SciPy evaluates it, by de Boor's sums over each x's knot span (in
    the extension, on every thread for large calls); on a GPU context as its polynomial pieces
    (made once in float64, degree 3 and below, within `CubicSpline`'s promise), but where an
    end interval is empty or a coefficient is not finite. Integrals, roots and conversions use
    the pieces. Differences from SciPy: `t` and `c` are read-only copies; `integrate` with
    extrapolate False gives 0 past the base interval for an N-D c too (SciPy's N-D path gives
    NaN there, its 1-D path 0).
    """

    t: np.ndarray
    c: np.ndarray
    k: int
    axis: int
    extrapolate: bool | str
    context: Context | None
    # The lam a smoothing spline was fitted with (make_smoothing_spline's; other splines have
    # none): a number, or an array of y's trailing shape.
    lam: Any
    # The polynomial pieces, made at the first call (or handed over by make_interp_spline).
    _pp: Any

    def __init__(self, t, c, k: int = 3, extrapolate=True, axis: int = 0,
                 context: Context | None = None):
        k = _natural("k", operator.index(k))
        t = np.array(_float64(t, "t"), order="C")
        c = np.asarray(c)
        if c.dtype.kind not in "biufc":
            raise TypeError(f"c: must be numbers, got an array of {c.dtype}")
        if c.ndim == 0:
            raise ValueError("c: must be at least 1-D, got a 0-d array")
        axis = _axis(axis, c.ndim, "c")
        c = np.array(np.moveaxis(c, axis, 0),
                     dtype=np.complex128 if c.dtype.kind == "c" else np.float64, order="C")
        _bspl.check(t, c.shape[0], k)
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

    @property
    def _t(self) -> np.ndarray:
        """`t`, under the name SciPy's tests read."""
        return self.t

    @property
    def _c(self) -> np.ndarray:
        """`c`, under the name SciPy's tests read."""
        return self.c

    def __iter__(self):
        """(t, c, k) unpacked as the tck tuple SciPy's FITPACK functions (`splev`, `splder`,
        `insert`, ...) take in place of a BSpline: c padded with zeros to len(t), FITPACK's
        layout, and its interpolation axis last, as they take it."""
        c = _bspl.padded(self.t, self.c)
        return iter((self.t, np.moveaxis(c, 0, -1) if c.ndim > 1 else c, self.k))

    @classmethod
    def basis_element(cls, t, extrapolate=True) -> BSpline:
        """The B-spline of degree len(t) - 2 on the knots t (zero outside [t[0], t[-1]]), as
        SciPy's: t padded with k knots one unit past each end, one coefficient 1."""
        t = _float64(t, "t")
        k = len(t) - 2
        if t.ndim != 1 or k < 0:
            raise ValueError(f"t: a basis element needs at least 2 knots, got shape {t.shape}")
        t = np.concatenate([np.full(k, t[0] - 1), t, np.full(k, t[-1] + 1)])
        c = np.zeros_like(t)
        c[k] = 1.0
        return cls.construct_fast(t, c, k, _extrapolate(extrapolate))

    @classmethod
    def design_matrix(cls, x, t, k, extrapolate=False):
        """SciPy's design matrix: a `scipy.sparse.csr_array` (len(x), len(t) - k - 1) whose
        row j holds B_{l-k,k}(x_j) .. B_{l,k}(x_j) at columns l - k .. l (SciPy's sparse
        arrays are needed to hold it). x outside [t[k], t[n]] is refused unless
        `extrapolate` (True: the end intervals' polynomials; "periodic": x wrapped into it)."""
        from scipy.sparse import csr_array

        x = _float64(x, "x").ravel()
        t = _float64(t, "t")
        k = operator.index(k)
        if k < 0:
            raise ValueError("Spline order cannot be negative.")
        if t.ndim != 1 or np.any(t[1:] < t[:-1]):
            raise ValueError(f"Expect t to be a 1-D sorted array_like, but got t={t}.")
        if len(t) < 2 * k + 2:
            raise ValueError(f"Length t is not enough for k={k}.")
        n = len(t) - k - 1
        if extrapolate == "periodic":
            x = t[k] + (x - t[k]) % (t[n] - t[k])
        elif not extrapolate and x.size and (x.min() < t[k] or x.max() > t[n]):
            raise ValueError(f"Out of bounds w/ x = {x}.")
        span = _bspl.intervals(t, k, x)
        data = _bspl.basis(t, k, x, span).ravel()
        index = np.int32 if x.size * (k + 1) < np.iinfo(np.int32).max else np.int64
        indices = ((span - k)[:, None] + np.arange(k + 1)[None, :]).astype(index).ravel()
        indptr = np.arange(0, (len(x) + 1) * (k + 1), k + 1, dtype=index)
        return csr_array((data, indices, indptr), shape=(len(x), n))

    @classmethod
    def from_power_basis(cls, pp, bc_type="not-a-knot") -> BSpline:
        """The cubic spline `pp` (a `CubicSpline`) as a BSpline on the knots SciPy picks for
        `bc_type` ("not-a-knot", "natural", "clamped" or "periodic"): the coefficients read
        off its pieces by blossoming (exact where pp lies in that spline space, as a
        CubicSpline of the same bc_type does)."""
        if not isinstance(pp, CubicSpline):
            raise NotImplementedError(f"Only CubicSpline objects are accepted for now. Got "
                                      f"{type(pp)} instead.")
        x = pp.x
        if bc_type == "not-a-knot":
            t = _collocation.not_a_knot(x, 3)
        elif bc_type in ("natural", "clamped"):
            t = _collocation.with_ends(x, 3)
        elif bc_type == "periodic":
            t = _collocation.periodic(x, 3)
        else:
            raise TypeError(f"Unknown boundary condition: {bc_type}")
        pieces = pp.c.reshape(4, len(x) - 1, -1)
        period = x[-1] - x[0] if bc_type == "periodic" else None
        c = _bspl.cubic_coefficients(t, x, pieces, period)
        return cls.construct_fast(t, c.reshape((len(c), *pp.c.shape[2:])), 3, pp.extrapolate,
                                  pp.axis)

    def insert_knot(self, x, m: int = 1) -> BSpline:
        """The same spline with the knot x inserted m times (Boehm's rule; for a periodic
        spline FITPACK's, so that it equals `scipy.interpolate.insert(per=1)`)."""
        x = float(x)
        if x < self.t[self.k] or x > self.t[-self.k - 1]:
            raise ValueError(f"Cannot insert a knot at {x}.")
        if m <= 0:
            raise ValueError(f"`m` must be positive, got {m = }.")
        t, c = self.t, self.c
        for _ in range(m):
            t, c = _bspl.insert(t, c, self.k, x, self.extrapolate == "periodic")
        return self.construct_fast(t, c, self.k, self.extrapolate, self.axis, self.context)

    def _pieces(self):
        """The spline's polynomial pieces on its base interval, made once."""
        if self._pp is None:
            n = len(self.t) - self.k - 1
            c = self.c[:n].reshape(n, -1)
            breaks, coeff = _bspl.pieces(self.t, c, self.k)
            coeff = coeff.reshape(coeff.shape[:2] + self.c.shape[1:])
            if self.k <= 3 and np.all(np.isfinite(coeff)):
                columns = np.concatenate([c.real, c.imag], axis=1)
                extent = float(np.max(np.ptp(columns, axis=0))) if columns.size else 0.0
                self._pp = PiecewiseCubic._of_pieces(breaks, coeff, extent, self.extrapolate,
                                                 self.axis, self.context)
            else:
                self._pp = PPoly._made(coeff, breaks, self.extrapolate, self.axis)
        return self._pp

    def __call__(self, x, nu: int = 0, extrapolate=None) -> np.ndarray:
        """Derivative nu (>= 0) at x, shape x.shape + c.shape[1:] (x's axes at `axis`);
        `extrapolate` None (the spline's), True (the end pieces continue), False (NaN outside
        [t[k], t[n]]) or "periodic" (x wrapped into it)."""
        if nu.__class__ is not int or nu < 0:
            nu = _natural("nu", int(nu) if isinstance(nu, bool) else nu)
        mode = self.extrapolate if extrapolate is None else _extrapolate(extrapolate)
        on_gpu = self.context is not None and self.context.backend == "gpu"
        regular = self._regular()
        if not on_gpu or not regular:
            return self._de_boor(x, nu, mode, regular)
        pp = self._pieces()
        if isinstance(pp, PiecewiseCubic) and nu <= 3:
            return pp(x, nu, mode)
        if isinstance(pp, PiecewiseCubic):
            pp = pp.ppoly()
        return pp(x, nu, mode)

    def _regular(self) -> bool:
        """Whether the pieces give SciPy's values everywhere: no empty end interval (where
        SciPy evaluates past the ends otherwise than the last non-empty piece), every
        coefficient finite (NaN only where its B-spline reaches). Found once (t and c are
        read-only)."""
        regular = self.__dict__.get("_is_regular")
        if regular is None:
            t, k = self.t, self.k
            n = len(t) - k - 1
            regular = bool(t[k] < t[k + 1] and t[n - 1] < t[n] and np.all(np.isfinite(self.c[:n])))
            self._is_regular = regular
        return regular

    def _columns(self) -> tuple:
        """t and c as the extension takes them, with what a call reads of them: (t, (c as
        (rows, m),)) or, for a complex c, (t, (real parts, imaginary parts)), then the base
        interval [t[k], t[n]] as floats and c's trailing shape; made once (t and c are
        read-only)."""
        made = self.__dict__.get("_as_columns")
        if made is None:
            c = self.c.reshape(len(self.c), -1)
            parts = (c.real, c.imag) if c.dtype == _COMPLEX else (c,)
            t, k = self.t, self.k
            n = len(t) - k - 1
            made = (_f64(t), tuple(_f64(part) for part in parts), float(t[k]), float(t[n]),
                    self.c.shape[1:])
            self._as_columns = made
        return made

    def _de_boor(self, x, nu: int, mode, regular: bool) -> np.ndarray:
        """Derivative nu at x as SciPy computes it: sum_r B_{l-k+r,k}^(nu)(x) c_{l-k+r} over
        the knot span l of each x (the extension's `evaluate_bspline`), in float64 (a complex
        c as its two parts); NaN at NaN, and outside [t[k], t[n]] when `mode` is False. Past
        the base interval of a `regular` spline (its end intervals not empty, c finite), the
        end polynomials in powers of x - t[k] or x - t[n] instead: the same polynomials,
        without the cancellation de Boor's blending suffers far from the knots (SciPy's loses
        1e-8 of a degree-5 antiderivative 5 knot spans past the end)."""
        if x.__class__ is float:
            x = np.array(x)
        elif x.__class__ is not np.ndarray or x.dtype != _F64:
            x = _float64(x, "x")
        flat = _f64(x if x.ndim == 1 else x.reshape(-1))
        knots, columns, lo, hi, trailing = self._columns()
        k = self.k
        if mode == "periodic":
            flat = lo + np.mod(flat - lo, hi - lo)
        powers = mode is True and regular
        if len(columns) == 2:
            out = (_native.evaluate_bspline(knots, columns[0], k, flat, nu, powers)
                   + 1j * _native.evaluate_bspline(knots, columns[1], k, flat, nu, powers))
        else:
            out = _native.evaluate_bspline(knots, columns[0], k, flat, nu, powers)
        if mode is False:
            out[(flat < lo) | (flat > hi)] = np.nan
        if x.ndim != 1 or len(trailing) != 1:
            # The extension's (len(x), m) is the shape already where both are 1-D.
            out = out.reshape(x.shape + trailing)
        if self.axis != 0 and x.ndim > 0:
            out = np.moveaxis(out, list(range(x.ndim)),
                              list(range(self.axis, self.axis + x.ndim)))
        return out

    def derivative(self, nu: int = 1) -> BSpline:
        """The nu-th derivative as a BSpline of degree k - nu (SciPy's t and c)."""
        t, c, k = _bspl.derivative(self.t, self.c, self.k, _natural("nu", nu))
        return self.construct_fast(t, c, k, self.extrapolate, self.axis, self.context)

    def antiderivative(self, nu: int = 1) -> BSpline:
        """The nu-th antiderivative, zero at t[0], as a BSpline of degree k + nu (SciPy's t and
        c); a periodic extrapolation becomes False, as SciPy's."""
        t, c, k = _bspl.antiderivative(self.t, self.c, self.k, _natural("nu", nu))
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
        # Without the arrays made for the extension (made again, aligned, where unpickled).
        attributes = {k: v for k, v in self.__dict__.items() if k != "_as_columns"}
        return (_restore_bspline, (attributes,))


def _restore_bspline(attributes: dict) -> BSpline:
    """A BSpline `__reduce__` saved, its pieces included (as `make_interp_spline` fitted them),
    its t and c read-only again."""
    spline = BSpline.__new__(BSpline)
    spline.__dict__.update(attributes)
    spline.t.flags.writeable = spline.c.flags.writeable = False
    return spline


def make_interp_spline(x, y, k: int = 3, t=None, bc_type=None, axis: int = 0,
                       check_finite: bool = True, context: Context | None = None) -> BSpline:
    """`scipy.interpolate.make_interp_spline(x, y, k=3, t=None, bc_type=None, axis=0)`: the
    B-spline of degree k through (x, y), on SciPy's knots (or the given t), with its ends:
    bc_type None or "not-a-knot", "natural", "clamped", "periodic", or a pair (left, right),
    each None, "natural", "clamped" or a list of (order, value). SciPy's checks and messages.

    The cubic with one condition at each end (SciPy's usual case) is fitted as `CubicSpline`
    (O(n) in the crate) and its coefficients read off its pieces by blossoming; every other
    degree, end or knot vector through the banded collocation system (`_collocation`). A complex y
    gives complex coefficients (its parts fitted as columns of their own); `check_finite` is
    always on (NaN and infinity are refused)."""
    periodic = isinstance(bc_type, str) and bc_type == "periodic"
    if bc_type is None or (isinstance(bc_type, str) and bc_type in ("not-a-knot", "periodic")):
        left = right = None
    elif isinstance(bc_type, str):
        left = right = bc_type
    else:
        try:
            left, right = bc_type
        except (TypeError, ValueError):
            raise ValueError(f"Unknown boundary condition: {bc_type}") from None
    x = np.array(_float64(x, "x"), order="C")
    y = np.asarray(y)
    if y.dtype.kind not in "biufc":
        raise TypeError(f"y: must be numbers, got an array of {y.dtype}")
    y = y.astype(np.complex128 if y.dtype.kind == "c" else np.float64)
    if not np.all(np.isfinite(y)):
        raise ValueError("array must not contain infs or NaNs")
    if y.ndim == 0:
        raise ValueError("y: must be at least 1-D, got a 0-d array")
    axis = _axis(axis, y.ndim, "y")
    y = np.moveaxis(y, axis, 0)
    if periodic and not np.allclose(y[0], y[-1], atol=1e-15):
        raise ValueError("First and last points does not match while periodic case expected")
    if x.size != y.shape[0]:
        raise ValueError(f"Shapes of x {x.shape} and y {y.shape} are incompatible")
    if np.any(x[1:] == x[:-1]):
        raise ValueError("Expect x to not have duplicates")
    if x.ndim != 1 or np.any(x[1:] < x[:-1]):
        raise ValueError("Expect x to be a 1D strictly increasing sequence.")
    trailing = y.shape[1:]
    if isinstance(k, (int, np.integer)) and not isinstance(k, bool) and k in (0, 1) and (
            k == 0 or t is None):
        if t is not None or left is not None or right is not None:
            raise ValueError(f"Too much info for k={k}: "
                             f"{'t and bc_type' if k == 0 else 'bc_type'} can only be None.")
        knots = np.concatenate([x, x[-1:]] if k == 0 else [x[:1], x, x[-1:]])
        return BSpline.construct_fast(knots, np.ascontiguousarray(y), int(k), axis=axis,
                                      context=context)
    k = operator.index(k)
    if periodic and t is not None:
        raise NotImplementedError("For periodic case t is constructed automatically and can "
                                  "not be passed manually")
    columns = y.reshape(len(x), -1)
    if k == 3 and t is None and 0 < columns.size and columns.shape[1] * (
            2 if np.iscomplexobj(y) else 1) <= 64:
        fast = _cubic_ends(bc_type, len(x))
        if fast is not None:
            return _cubic_fit(x, np.moveaxis(y, 0, axis), fast, axis, context)
    if t is None:
        if left is None and right is None:
            t = _collocation.periodic(x, k) if periodic else _collocation.not_a_knot(x, k)
        else:
            t = _collocation.with_ends(x, k)
    t = np.array(_float64(t, "t"), order="C")
    if k < 0:
        raise ValueError("Expect non-negative k.")
    if t.ndim != 1 or np.any(t[1:] < t[:-1]):
        raise ValueError("Expect t to be a 1-D sorted array_like.")
    if t.size < x.size + k + 1:
        raise ValueError(f"Got {t.size} knots, need at least {x.size + k + 1}.")
    if x[0] < t[k] or x[-1] > t[-k]:
        raise ValueError(f"Out of bounds w/ x = {x}.")
    nt = len(t) - k - 1
    if periodic:
        c = _solved_columns(lambda rhs: _collocation.periodic_coefficients(x, rhs, t, k), columns)
        return BSpline.construct_fast(t, c.reshape((len(c), *trailing)), k, "periodic", axis,
                                      context)
    ends = [_end_conditions(end, trailing) for end in (left, right)]
    for (orders, _), at in zip(ends, (x[0], x[-1])):
        if not all(0 <= o <= k for o in orders):
            raise ValueError(f"Bad boundary conditions at {at}.")
    if nt - len(x) != len(ends[0][0]) + len(ends[1][0]):
        raise ValueError(f"The number of derivatives at boundaries does not match: expected "
                         f"{nt - len(x)}, got {len(ends[0][0])}+{len(ends[1][0])}")
    if y.size == 0:
        return BSpline.construct_fast(t, np.zeros((nt, *trailing)), k, axis=axis,
                                      context=context)
    if any(np.iscomplexobj(v) for _, values in ends for v in values):
        # A complex end value makes the spline complex, as SciPy's.
        columns = columns.astype(np.complex128)
    m = columns.shape[1]

    def solve(rhs):
        split = rhs.shape[1] != m
        conditions = [[(o, np.concatenate([v.real, v.imag]) if split else np.real(v))
                       for o, v in zip(*end)] for end in ends]
        return _collocation.coefficients(x, rhs, t, k, *conditions)

    c = _solved_columns(solve, columns)
    return BSpline.construct_fast(t, c.reshape((nt, *trailing)), k, axis=axis,
                                  context=context)


def _solved_columns(solve, columns: np.ndarray) -> np.ndarray:
    """solve(real columns) for y's columns: a complex y's real and imaginary parts side by
    side (the systems are real), joined again."""
    if not np.iscomplexobj(columns):
        return solve(columns)
    m = columns.shape[1]
    both = solve(np.concatenate([columns.real, columns.imag], axis=1))
    return both[:, :m] + 1j * both[:, m:]


def _end_conditions(end, trailing: tuple):
    """One end of bc_type as (orders, values (one per order, flattened to y's columns)):
    "clamped" and "natural" as a first or second derivative of zero."""
    if end is None:
        return [], []
    if isinstance(end, str):
        if end == "clamped":
            end = [(1, np.zeros(trailing))]
        elif end == "natural":
            end = [(2, np.zeros(trailing))]
        else:
            raise ValueError(f"Unknown boundary condition : {end}")
    try:
        orders, values = zip(*end)
    except TypeError:
        raise ValueError("Derivatives, `bc_type`, should be specified as a pair of iterables "
                         "of pairs of (order, value).") from None
    size = int(np.prod(trailing))
    flat = []
    for v in values:
        v = np.asarray(v)
        if v.size != size:
            raise ValueError(f"bc_type: an end's value of shape {v.shape} does not fit y's "
                             f"other axes {trailing}")
        flat.append(v.reshape(size).astype(np.complex128 if v.dtype.kind == "c" else
                                            np.float64))
    return [int(o) for o in orders], flat


def _cubic_ends(bc_type, n: int):
    """bc_type as CubicSpline's where the cubic fast path takes it (`interp_bc`'s forms, and
    not-a-knot on 4 points or more), else None."""
    bc, _ = _cubic_bc(bc_type)
    return None if bc is None or (bc == "not-a-knot" and n < 4) else bc


def _cubic_fit(x, y, bc, axis: int, context) -> BSpline:
    """make_interp_spline's cubic through CubicSpline's fit (bc in CubicSpline's form)."""
    fitted = CubicSpline(x, y, axis=axis, bc_type=bc, context=context)
    knots, c = interp_coefficients(fitted.x, fitted.c.reshape(4, len(fitted.x) - 1, -1), bc)
    c = c.reshape((len(c), *fitted.c.shape[2:]))
    spline = BSpline.construct_fast(knots, c, 3, "periodic" if bc == "periodic" else True,
                                    fitted.axis, context)
    fitted.extrapolate = spline.extrapolate
    spline._pp = fitted
    return spline


def interp_coefficients(x: np.ndarray, pieces: np.ndarray, bc):
    """make_interp_spline's knots for x and bc (CubicSpline's form), and the coefficients
    (n, m) of the cubic (pieces (4, len(x) - 1, m) in SciPy's power form) on them."""
    period = None
    if bc == "periodic":
        knots, period = _collocation.periodic(x, 3), x[-1] - x[0]
    elif bc == "not-a-knot":
        knots = _collocation.not_a_knot(x, 3)
    else:
        knots = _collocation.with_ends(x, 3)
    return knots, _bspl.cubic_coefficients(knots, x, pieces, period)


def interp_bc(bc_type):
    """make_interp_spline's bc_type as CubicSpline's, or a ValueError saying why it has none."""
    bc, why = _cubic_bc(bc_type)
    if why is not None:
        raise ValueError(why)
    return bc


def _cubic_bc(bc_type):
    """(make_interp_spline's bc_type as CubicSpline's, None), or (None, why it has none)."""
    if bc_type is None:
        return "not-a-knot", None
    if isinstance(bc_type, str):
        if bc_type not in ("not-a-knot", "natural", "clamped", "periodic"):
            return None, f"bc_type: unknown boundary condition {bc_type!r}"
        return bc_type, None
    pair = _unpacked(bc_type, 2)
    if pair is None:
        return None, f"bc_type: must be None, a name, or a pair (left, right), got {bc_type!r}"
    left, right = pair
    if left is None and right is None:
        return "not-a-knot", None

    def end(spec, where: str):
        if isinstance(spec, str):
            if spec not in ("natural", "clamped"):
                return None, f"bc_type: unknown boundary condition {spec!r} at the {where}"
            return spec, None
        one = _unpacked(spec, 1)
        derivative = None if one is None else _unpacked(one[0], 2)
        if derivative is None:
            return None, (f"bc_type: the {where} end must be \"natural\", \"clamped\" or a "
                          f"list of one (order, value) for k=3, got {spec!r}")
        order, value = derivative
        if isinstance(order, bool) or order not in (1, 2):
            return None, (f"bc_type: the derivative order at the {where} end must be 1 or 2 "
                          f"here, got {order!r}")
        return (int(order), value), None

    (lo, why_left), (hi, why_right) = end(left, "left"), end(right, "right")
    why = why_left or why_right
    return (None, why) if why else ((lo, hi), None)


def _unpacked(value, count: int):
    """`value`'s `count` items as a tuple where it is an iterable of exactly that many, else
    None (strings and mappings are not unpacked)."""
    if isinstance(value, (str, bytes, dict)) or not hasattr(value, "__iter__"):
        return None
    items = tuple(value)
    return items if len(items) == count else None


