"""SciPy's object-oriented FITPACK splines (its `_fitpack2`), answered by this package's
B-splines.

Curves: `UnivariateSpline` (smoothing by FITPACK's curfit itself, `bsplines::curfit`: its
knots, coefficients, fp and ier, its room for m // 2 knots first and then for all, its class
changes and warnings; `set_smoothing_factor` goes on with the knot search from where it
stopped, as curfit's iopt = 1),
`InterpolatedUnivariateSpline` (s = 0) and `LSQUnivariateSpline` (given interior knots), with
their methods.

Surfaces: `RectBivariateSpline` for s = 0, the interpolating tensor B-spline of degrees kx, ky
through z on the grid x, y, as FITPACK's `regrid` makes it. With s = 0 FITPACK places the
interior knots as SciPy's not-a-knot knots (the data for odd k, the midpoints of the data for
even k, without k // 2 + (k odd) of them at each end) and the end knots at the bounding box
(default: the data's ends), and the spline interpolates: the unique tensor B-spline on those
knots through z, fitted here by separable banded solves (`_ndbspline.solve_grid`). FITPACK
evaluates at a point clipped to the bounding box (no extrapolation: past an end, the value at
the end), and so does this class. A smoothing s > 0 is FITPACK's regrid itself
(`bsplines::regrid`), as SciPy's.
"""

from __future__ import annotations

import warnings

import numpy as np

from . import _collocation, _fitpack_repro, _native
from ._bsplines import BSpline
from ._context import Context
from ._fitpack_py import bspline_integrals, curfit, splint, sproot
from ._helpers import _aligned
from ._lsq import make_lsq_spline
from ._ndbspline import NdBSpline, solve_grid

_EXT = {"extrapolate": 0, "zeros": 1, "raise": 2, "const": 3}

# SciPy's RectBivariateSpline errors for regrid's ier (its `_surfit_messages`, word for
# word).
_SURFIT_MESSAGES = {
    1: """
The required storage space exceeds the available storage space: nxest
or nyest too small, or s too small.
The weighted least-squares spline corresponds to the current set of
knots.""",
    2: """
A theoretically impossible result was found during the iteration
process for finding a smoothing spline with fp = s: s too small or
badly chosen eps.
Weighted sum of squared residuals does not satisfy abs(fp-s)/s < tol.""",
    3: """
the maximal number of iterations maxit (set to 20 by the program)
allowed for finding a smoothing spline with fp=s has been reached:
s too small.
Weighted sum of squared residuals does not satisfy abs(fp-s)/s < tol.
Try increasing maxit by passing it as a keyword argument.""",
}

# SciPy's UnivariateSpline warnings for FITPACK's ier (its `_curfit_messages`, word for word:
# callers match them).
_CURFIT_MESSAGES = {
    1: """
The required storage space exceeds the available storage space, as
specified by the parameter nest: nest too small. If nest is already
large (say nest > m/2), it may also indicate that s is too small.
The approximation returned is the weighted least-squares spline
according to the knots t[0],t[1],...,t[n-1]. (n=nest) the parameter fp
gives the corresponding weighted sum of squared residuals (fp>s).
""",
    2: """
A theoretically impossible result was found during the iteration
process for finding a smoothing spline with fp = s: s too small.
There is an approximation returned but the corresponding weighted sum
of squared residuals does not satisfy the condition abs(fp-s)/s < tol.""",
    3: """
The maximal number of iterations maxit (set to 20 by the program)
allowed for finding a smoothing spline with fp=s has been reached: s
too small.
There is an approximation returned but the corresponding weighted sum
of squared residuals does not satisfy the condition abs(fp-s)/s < tol.""",
}


def _ext(ext) -> int:
    if isinstance(ext, str):
        if ext not in _EXT:
            raise ValueError(f"Unknown extrapolation mode {ext}.")
        return _EXT[ext]
    if ext not in (0, 1, 2, 3):
        raise ValueError(f"Unknown extrapolation mode {ext}.")
    return int(ext)


class UnivariateSpline:
    """`scipy.interpolate.UnivariateSpline(x, y, w=None, bbox=[None, None], k=3, s=None,
    ext=0, check_finite=False)`: the smoothing spline with sum (w_i (y_i - f(x_i)))^2 <= s
    (s = len(w) by default), FITPACK's knots. `context` evaluates it on a GPU context."""

    # The data it was fitted to (x, y, w, bbox, k); None for a derived spline.
    _data: tuple | None
    # Where FITPACK's knot search stopped (`_native.fit_curfit`'s state, or None: start from
    # the polynomial) and the room for knots (nest) it had, for set_smoothing_factor; None
    # where it cannot go on (given knots, a derived spline).
    _search: tuple | None = None
    # FITPACK's fp of the fit (None: summed at the data when asked).
    _fp: float | None = None

    def __init__(self, x, y, w=None, bbox=(None, None), k: int = 3, s=None, ext=0,
                 check_finite: bool = False, context: Context | None = None):
        x, y, w, bbox, self.ext = self.validate_input(x, y, w, bbox, k, s, ext, check_finite)
        if s is None:
            s = float(len(x)) if w is None else float(len(w))
        self._data = (x, y, w, bbox, k)
        self.context = context
        if s == 0:
            self._spline = _interpolating(x, y, w, bbox, k, context)
            # FITPACK's room for the interpolating knots; a later s searches afresh.
            self._search = (None, len(x) + k + 1)
            self._reset_class(-1)
        else:
            # fpcurf0's room for knots when smoothing: m // 2 (at least 2k + 2).
            self._smooth(s, None, max(len(x) // 2, 2 * (k + 1)))

    def _smooth(self, s: float, state, nest: int) -> None:
        """The smoothing spline for s by FITPACK's curfit, from the polynomial (state None)
        or on from an earlier search (curfit's iopt = 1), with room for nest knots; where
        they are too few (ier 1), the search goes on with room for every knot, as SciPy's
        class does. The class and warnings then follow ier as SciPy's."""
        assert self._data is not None
        x, y, w, bbox, k = self._data
        x, y, w, k, s, xb, xe = _fitpack_repro._validated(x, y, w, k, s, bbox[0], bbox[1], False)
        if len(x) <= k:
            raise ValueError(f"x: m > k must hold, got m = {len(x)} points for k = {k}")
        t, c, fp, ier, state = curfit(x, y, w, xb, xe, k, s, nest, state=state)
        if ier == 1:
            nest = len(x) + k + 1
            t, c, fp, ier, state = curfit(x, y, w, xb, xe, k, s, nest, state=state)
        self._search, self._fp = (state, nest), fp
        self._spline = BSpline.construct_fast(t, c[:, 0], k, context=self.context)
        self._reset_class(ier)

    def _reset_class(self, ier: int) -> None:
        """SciPy's class after a fit with FITPACK's ier: InterpolatedUnivariateSpline for an
        interpolating spline (-1), LSQUnivariateSpline for the least-squares polynomial (-2)
        or too few knots (1); a warning for 1, 2 and 3. Subclasses keep their class."""
        made = {-1: InterpolatedUnivariateSpline, -2: LSQUnivariateSpline,
                1: LSQUnivariateSpline}.get(ier)
        if made is not None and type(self) in (UnivariateSpline, InterpolatedUnivariateSpline,
                                               LSQUnivariateSpline):
            self.__class__ = made
        if ier > 0:
            warnings.warn(_CURFIT_MESSAGES.get(ier, f"ier={ier}"), stacklevel=4)

    @staticmethod
    def validate_input(x, y, w, bbox, k, s, ext, check_finite):
        """SciPy's checks of the arguments, in its words: (x, y, w, bbox, ext)."""
        x, y = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
        bbox = np.asarray(bbox)
        if w is not None:
            w = np.asarray(w, dtype=np.float64)
        if check_finite:
            w_finite = np.isfinite(w).all() if w is not None else True
            if not np.isfinite(x).all() or not np.isfinite(y).all() or not w_finite:
                raise ValueError("x and y array must not contain NaNs or infs.")
        if s is None or s > 0:
            if not np.all(np.diff(x) >= 0.0):
                raise ValueError("x must be increasing if s > 0")
        else:
            if not np.all(np.diff(x) > 0.0):
                raise ValueError("x must be strictly increasing if s = 0")
        if x.size != y.size:
            raise ValueError("x and y should have a same length")
        if w is not None and not x.size == w.size:
            raise ValueError("x, y, and w should have a same length")
        if bbox.shape != (2,):
            raise ValueError("bbox shape should be (2,)")
        if not 1 <= k <= 5:
            raise ValueError("k should be 1 <= k <= 5")
        if s is not None and not s >= 0.0:
            raise ValueError("s should be s >= 0.0")
        bounds = (None if bbox[0] is None else float(bbox[0]),
                  None if bbox[1] is None else float(bbox[1]))
        return x, y, w, bounds, _ext(ext)

    @classmethod
    def _from_spline(cls, spline: BSpline, ext: int, context) -> UnivariateSpline:
        made = cls.__new__(cls)
        made._spline, made.ext, made.context, made._data = spline, ext, context, None
        return made

    def __call__(self, x, nu: int = 0, ext=None) -> np.ndarray:
        """The spline (or its nu-th derivative) at x; ext as the constructor's (None: its)."""
        ext = self.ext if ext is None else _ext(ext)
        x = np.asarray(x, dtype=np.float64)
        t, k = self._spline.t, self._spline.k
        if not 0 <= nu <= k:
            raise ValueError(f"0<=der={nu}<=k={k} must hold")
        lo, hi = t[k], t[len(t) - k - 1]
        outside = (x < lo) | (x > hi)
        if ext == 2 and np.any(outside):
            raise ValueError("Found x value not in the domain")
        at = np.clip(x, lo, hi) if ext == 3 else x
        values = np.asarray(self._spline(at.ravel(), nu=nu)).reshape(x.shape)
        return np.where(outside, 0.0, values) if ext == 1 else values

    def get_knots(self) -> np.ndarray:
        """The knots of the base interval: t[k:n+1], ends included."""
        t, k = self._spline.t, self._spline.k
        return t[k:len(t) - k]

    def get_coeffs(self) -> np.ndarray:
        """The B-spline coefficients."""
        return np.asarray(self._spline.c)

    def get_residual(self) -> float:
        """sum (w_i (y_i - f(x_i)))^2 over the data."""
        if self._data is None:
            raise ValueError("get_residual: a derived spline has no data")
        if self._fp is not None:
            return self._fp
        x, y, w, _, _ = self._data
        weights = np.ones_like(x) if w is None else w
        return float(np.sum((weights * (y - self._spline(x))) ** 2))

    def integral(self, a, b) -> float:
        """The integral from a to b (zero outside the base interval)."""
        return splint(a, b, self._spline.tck)

    def derivatives(self, x) -> np.ndarray:
        """All derivatives (0 to k) at the point x, which must lie within the knots (FITPACK's
        spalde refuses it otherwise, with SciPy's TypeError)."""
        t, k = self._spline.t, self._spline.k
        if not t[k] <= float(x) <= t[len(t) - k - 1]:
            raise TypeError("Invalid input data. t(k)<=x<=t(n-k+1) must hold.")
        return np.array([float(self._spline(np.array([float(x)]), nu=d)[0])
                         for d in range(self._spline.k + 1)])

    def roots(self) -> np.ndarray:
        """The zeros (cubic splines only, as FITPACK's sproot)."""
        if self._spline.k != 3:
            raise NotImplementedError("finding roots unsupported for non-cubic splines")
        return sproot(self._spline.tck)

    def derivative(self, n: int = 1) -> UnivariateSpline:
        """The n-th derivative as a spline of this class (zero outside where this one holds
        its end values, ext "const")."""
        return UnivariateSpline._from_spline(self._spline.derivative(n),
                                             1 if self.ext == 3 else self.ext, self.context)

    def antiderivative(self, n: int = 1) -> UnivariateSpline:
        """The n-th antiderivative as a spline of this class."""
        return UnivariateSpline._from_spline(self._spline.antiderivative(n), self.ext,
                                             self.context)

    def set_smoothing_factor(self, s) -> None:
        """The spline for a new s, in place, as FITPACK's curfit with iopt = 1: its knot
        search goes on from the knots it stopped at (knots are only added: a larger s keeps
        them and smooths on them), or starts again from the polynomial where that meets s."""
        if self._data is None:
            raise ValueError("set_smoothing_factor: a derived spline has no data to fit")
        if self._search is None:
            # Only LSQUnivariateSpline's own knots leave no search to go on from.
            warnings.warn("smoothing factor unchanged forLSQ spline with fixed knots",
                          stacklevel=2)
            return
        if not s > 0:
            raise ValueError(f"s: set_smoothing_factor takes s > 0, got {s}")
        state, nest = self._search
        self._smooth(float(s), state, nest)


def _interpolating(x, y, w, bbox, k, context) -> BSpline:
    """The interpolating spline on FITPACK's s = 0 knots (SciPy's not-a-knot knots, with the
    bounding box's ends)."""
    xb = x[0] if bbox[0] is None else bbox[0]
    xe = x[-1] if bbox[1] is None else bbox[1]
    if k % 2 == 1:
        inner = x[(k + 1) // 2:len(x) - (k + 1) // 2]
    else:
        inner = ((x[1:] + x[:-1]) / 2)[k // 2:len(x) - 1 - k // 2]
    t = np.concatenate([[xb] * (k + 1), inner, [xe] * (k + 1)])
    return make_lsq_spline(x, y, t, k, w=w, context=context)


class InterpolatedUnivariateSpline(UnivariateSpline):
    """`scipy.interpolate.InterpolatedUnivariateSpline(x, y, w=None, bbox=[None, None], k=3,
    ext=0, check_finite=False)`: the interpolating spline (s = 0)."""

    def __init__(self, x, y, w=None, bbox=(None, None), k: int = 3, ext=0,
                 check_finite: bool = False, context: Context | None = None):
        x, y, w, bbox, self.ext = self.validate_input(x, y, w, bbox, k, None, ext,
                                                      check_finite)
        if not np.all(np.diff(x) > 0.0):
            raise ValueError("x must be strictly increasing")
        self._data, self.context = (x, y, w, bbox, k), context
        self._spline = _interpolating(x, y, w, bbox, k, context)
        # FITPACK's room for the interpolating knots; a later s searches afresh.
        self._search = (None, len(x) + k + 1)


class LSQUnivariateSpline(UnivariateSpline):
    """`scipy.interpolate.LSQUnivariateSpline(x, y, t, w=None, bbox=[None, None], k=3, ext=0,
    check_finite=False)`: the least-squares spline on the interior knots t."""

    def __init__(self, x, y, t, w=None, bbox=(None, None), k: int = 3, ext=0,
                 check_finite: bool = False, context: Context | None = None):
        x, y, w, bbox, self.ext = self.validate_input(x, y, w, bbox, k, None, ext,
                                                      check_finite)
        if not np.all(np.diff(x) >= 0.0):
            raise ValueError("x must be increasing")
        xb = x[0] if bbox[0] is None else bbox[0]
        xe = x[-1] if bbox[1] is None else bbox[1]
        t = np.concatenate([[xb] * (k + 1), np.asarray(t, dtype=np.float64), [xe] * (k + 1)])
        if not np.all(t[1:] >= t[:-1]) or not xb < xe or not (t[k + 1] > xb or len(t) == 2 * (
                k + 1)):
            raise ValueError("Interior knots t must satisfy Schoenberg-Whitney conditions")
        self._data, self.context = (x, y, w, bbox, k), context
        try:
            self._spline = make_lsq_spline(x, y, t, k, w=w, context=context)
        except ValueError as e:
            if "Schoenberg-Whitney" in str(e):
                raise ValueError("Interior knots t must satisfy Schoenberg-Whitney "
                                 "conditions") from None
            raise


class _Bivariate:
    """What FITPACK's bivariate splines answer: `tck` (tx, ty, c flat, x outer), `degrees`."""

    tck: tuple
    degrees: tuple

    @classmethod
    def _from_tck(cls, tck):
        if len(tck) != 5:
            raise ValueError("tck should be a 5 element tuple of tx, ty, c, kx, ky")
        self = cls.__new__(cls)
        self.tck = tuple(tck[:3])
        self.degrees = tuple(tck[3:])
        return self

    def get_knots(self) -> tuple:
        return self.tck[:2]

    def get_coeffs(self) -> np.ndarray:
        return self.tck[2]

    def _spline(self):
        spline = self.__dict__.get("_tensor")
        if spline is None:
            (tx, ty, c), (kx, ky) = self.tck, self.degrees
            shape = (len(tx) - kx - 1, len(ty) - ky - 1)
            c = np.asarray(c).reshape(shape)
            if np.all(np.diff(tx) >= 0) and np.all(np.diff(ty) >= 0):
                spline = NdBSpline((tx, ty), c, (kx, ky))
            else:
                spline = _OutOfOrder((np.asarray(tx), np.asarray(ty)), c, (kx, ky))
            self.__dict__["_tensor"] = spline
        return spline

    def _at(self, x: np.ndarray, y: np.ndarray, dx: int, dy: int) -> np.ndarray:
        """Derivative (dx, dy) at the pairs (x, y) (1-D, equal length), each clipped to the
        knots' span as FITPACK clips it."""
        (tx, ty, _), (kx, ky) = self.tck, self.degrees
        for name, order, k in (("dx", dx, kx), ("dy", dy, ky)):
            if order != 0 and not 0 < order < k:
                raise ValueError(f"{name}: the order of derivative must be 0 <= {name} < "
                                 f"{k} (the degree), got {order}")
        points = np.stack([np.clip(x, tx[0], tx[-1]), np.clip(y, ty[0], ty[-1])], axis=-1)
        # A derivative is the derived spline's value, as FITPACK computes it (so that
        # partial_derivative(dx, dy)(x, y) equals self(x, y, dx, dy) bit for bit).
        derived = self.__dict__.setdefault("_derived", {})
        if (dx, dy) not in derived:
            derived[(dx, dy)] = self.partial_derivative(dx, dy)._spline()
        return derived[(dx, dy)](points)

    def __call__(self, x, y, dx=0, dy=0, grid=True) -> np.ndarray:
        """The spline (or its derivative (dx, dy)) on the grid x times y (grid: x and y sorted
        ascending; (len(x), len(y))) or at the pairs (x, y) broadcast together."""
        x, y = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
        if grid:
            if x.size == 0 or y.size == 0:
                return np.zeros((x.size, y.size), dtype=np.asarray(self.tck[2]).dtype)
            x, y = x.ravel(), y.ravel()
            for name, v in (("x", x), ("y", y)):
                if v.size >= 2 and not np.all(np.diff(v) >= 0.0):
                    raise ValueError(f"{name} must be strictly increasing when `grid` is True")
            xx, yy = np.meshgrid(x, y, indexing="ij")
            return self._at(xx.ravel(), yy.ravel(), dx, dy).reshape(x.size, y.size)
        x, y = np.broadcast_arrays(x, y)
        shape = x.shape
        if x.size == 0:
            return np.zeros(shape, dtype=np.asarray(self.tck[2]).dtype)
        return self._at(x.ravel(), y.ravel(), dx, dy).reshape(shape)

    def partial_derivative(self, dx, dy):
        """The derivative (dx, dy) as a spline of degrees (kx - dx, ky - dy) on the knots less
        dx (dy) at each end (FITPACK's `pardtc`)."""
        if dx == 0 and dy == 0:
            return self
        kx, ky = self.degrees
        if not (dx >= 0 and dy >= 0):
            raise ValueError("order of derivative must be positive or zero")
        if not (dx < kx and dy < ky):
            raise ValueError("order of derivative must be less than degree of spline")
        derived = self._spline().derivative((dx, dy))
        tx, ty = derived.t
        return _DerivedBivariateSpline._from_tck((tx, ty, derived.c.ravel(), kx - dx, ky - dy))


def _fitpack_basis(t: np.ndarray, k: int, x: np.ndarray) -> tuple:
    """FITPACK's B-splines at x as fpbisp finds them, knots in order or not (regrid can leave
    them out of order): each x's interval (0-based, from k: the first knot past it, or the
    last interval), and the k + 1 values of the Cox-de Boor recurrence there (a zero where two
    knots coincide). Returns (intervals, values (len(x), k + 1))."""
    nk1 = len(t) - k - 1
    beyond = t[k + 1:nk1][None, :] > x[:, None]
    span = np.where(beyond.any(axis=1), k + np.argmax(beyond, axis=1), nk1 - 1)
    h = np.zeros((len(x), k + 1))
    h[:, 0] = 1.0
    for j in range(1, k + 1):
        hh = h[:, :j].copy()
        h[:, 0] = 0.0
        for i in range(1, j + 1):
            right, left = t[span + i], t[span + i - j]
            width = right - left
            safe = np.where(width != 0.0, width, 1.0)
            f = np.where(width != 0.0, hh[:, i - 1] / safe, 0.0)
            h[:, i - 1] += f * (right - x)
            h[:, i] = f * (x - left)
    return span, h


class _OutOfOrder:
    """A tensor spline whose knots FITPACK's regrid left out of order, evaluated as FITPACK's
    bispev and derived as its parder (SciPy answers so on such fits): the calls and
    `derivative` that `_Bivariate` takes from an NdBSpline."""

    def __init__(self, t: tuple, c: np.ndarray, k: tuple):
        self.t, self.c, self.k = t, c, k

    def __call__(self, points: np.ndarray) -> np.ndarray:
        (tx, ty), (kx, ky) = self.t, self.k
        lx, hx = _fitpack_basis(tx, kx, points[:, 0])
        ly, hy = _fitpack_basis(ty, ky, points[:, 1])
        out = np.zeros(len(points))
        for i in range(kx + 1):
            rows = self.c[lx - kx + i]
            for j in range(ky + 1):
                out += hx[:, i] * hy[:, j] * rows[np.arange(len(points)), ly - ky + j]
        return out

    def derivative(self, nu: tuple) -> _OutOfOrder:
        """The derivative (nu_x, nu_y) as parder makes it: along each axis, nu times,
        c_i <- k (c_{i+1} - c_i) / (t_{i+k+1} - t_{i+1}) on the knots less one at each end."""
        t, c, k = list(self.t), self.c, list(self.k)
        for axis, order in enumerate(nu):
            for _ in range(order):
                tt, kk = t[axis], k[axis]
                span = (tt[kk + 1:len(tt) - 1] - tt[1:len(tt) - kk - 1])
                shape = [1, 1]
                shape[axis] = -1
                c = kk * np.diff(c, axis=axis) / span.reshape(shape)
                t[axis], k[axis] = tt[1:-1], kk - 1
        return _OutOfOrder(tuple(t), c, tuple(k))


class BivariateSpline(_Bivariate):
    """The evaluations every fitted bivariate spline has: `ev` and `integral`."""

    fp: float

    def ev(self, xi, yi, dx=0, dy=0) -> np.ndarray:
        """At the pairs (xi, yi): `self(xi, yi, dx, dy, grid=False)`."""
        return self(xi, yi, dx=dx, dy=dy, grid=False)

    def integral(self, xa, xb, ya, yb) -> float:
        """The integral over [xa, xb] x [ya, yb], each clipped to the knots' span as FITPACK's
        `dblint`: the B-splines' integrals along each axis (fpintb's), contracted with c."""
        (tx, ty, c), (kx, ky) = self.tck, self.degrees
        ix = bspline_integrals(np.asarray(tx, dtype=np.float64), kx, float(xa), float(xb))
        iy = bspline_integrals(np.asarray(ty, dtype=np.float64), ky, float(ya), float(yb))
        return float(ix @ np.asarray(c).reshape(len(ix), len(iy)) @ iy)

    def get_residual(self) -> float:
        return self.fp


class _DerivedBivariateSpline(BivariateSpline):
    """A derivative of a fitted spline (`partial_derivative`): no residual."""

    _why = ("is unavailable, because _DerivedBivariateSpline instance is not constructed "
            "from data that are to be interpolated or smoothed, but derived from the "
            "underlying knots and coefficients of another spline object")

    @property
    def fp(self):
        raise AttributeError(f'attribute "fp" {self._why}')

    def get_residual(self):
        raise AttributeError(f'method "get_residual" {self._why}')


class RectBivariateSpline(BivariateSpline):
    """SciPy's `RectBivariateSpline(x, y, z, bbox=[None] * 4, kx=3, ky=3, s=0, maxit=20)`:
    for s = 0 the interpolant (see the module's documentation; `fp` is 0), for s > 0
    FITPACK's regrid (`bsplines::regrid`: its knots, coefficients and fp; ier other than 0,
    -1 and -2 raises ValueError with SciPy's words)."""

    def __init__(self, x, y, z, bbox=(None,) * 4, kx=3, ky=3, s=0, maxit=20):
        x = np.ravel(np.asarray(x, dtype=np.float64))
        y = np.ravel(np.asarray(y, dtype=np.float64))
        bbox = np.ravel(np.asarray(bbox, dtype=object))
        z = np.asarray(z)
        if not np.all(np.diff(x) > 0.0):
            raise ValueError("x must be strictly increasing")
        if not np.all(np.diff(y) > 0.0):
            raise ValueError("y must be strictly increasing")
        if z.ndim != 2 or x.size != z.shape[0]:
            raise ValueError("x dimension of z must have same number of elements as x")
        if y.size != z.shape[1]:
            raise ValueError("y dimension of z must have same number of elements as y")
        if bbox.shape != (4,):
            raise ValueError("bbox shape should be (4,)")
        if s is not None and not s >= 0.0:
            raise ValueError("s should be s >= 0.0")
        for name, k, v in (("kx", kx, x), ("ky", ky, y)):
            if not 1 <= k <= 5:
                raise ValueError(f"{name}: the degree must be 1 to 5, got {k}")
            if v.size <= k:
                raise ValueError(f"{name}: {v.size} points, need at least {k + 1} for degree "
                                 f"{k}")
        if np.iscomplexobj(z) or not np.isfinite(np.asarray(z, dtype=np.float64)).all():
            raise ValueError("z: the values must be real and finite")
        z = np.ascontiguousarray(z, dtype=np.float64)
        knots, bounds = [], []
        for v, k, (lo, hi) in ((x, kx, bbox[:2]), (y, ky, bbox[2:])):
            lo = v[0] if lo is None else float(lo)
            hi = v[-1] if hi is None else float(hi)
            if not (lo <= v[0] and v[-1] <= hi):
                raise ValueError(f"bbox: [{lo}, {hi}] must hold the data [{v[0]}, {v[-1]}]")
            t = _collocation.not_a_knot(v, k)
            t[:k + 1], t[-k - 1:] = lo, hi
            knots.append(t)
            bounds.extend([lo, hi])
        self.degrees = (kx, ky)
        if s:
            # FITPACK's regrid: its knots, coefficients, fp and ier (SciPy raises for ier
            # other than 0, -1 and -2, with its words).
            if not isinstance(maxit, (int, np.integer)) or maxit < 1:
                raise ValueError(f"maxit: must be a positive integer, got {maxit!r}")
            tx, ty, c, fp, ier = _native.fit_regrid(_aligned(x, "x"), _aligned(y, "y"), z,
                                                     bounds, kx, ky, float(s), int(maxit))
            if ier not in (0, -1, -2):
                raise ValueError(_SURFIT_MESSAGES.get(ier, f"ier={ier}"))
            if not np.all(np.isfinite(c)):
                raise ValueError("z: the smoothing spline's coefficients are not finite (its "
                                 "knots coincide); try another s")
            self.fp, self.tck = fp, (tx, ty, c)
            return
        c = solve_grid((x, y), tuple(knots), (kx, ky), z)
        self.fp = 0.0
        self.tck = (knots[0], knots[1], c.ravel())
