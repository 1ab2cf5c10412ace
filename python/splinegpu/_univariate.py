"""SciPy's object-oriented FITPACK curves: `UnivariateSpline` (smoothing, FITPACK's knots as
`make_splrep` places them; `set_smoothing_factor` goes on with FITPACK's knot search from
where it stopped), `InterpolatedUnivariateSpline` (s = 0) and `LSQUnivariateSpline` (given
interior knots), with their methods, answered by this package's B-splines."""

from __future__ import annotations

import warnings

import numpy as np

from . import _fitpack, _native
from ._arrays import _aligned
from ._bsplines import BSpline
from ._context import Context
from ._legacy import splint, sproot
from ._lsq import make_lsq_spline

_EXT = {"extrapolate": 0, "zeros": 1, "raise": 2, "const": 3}


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
    # Where FITPACK's knot search stopped, (t, fpold, nplus), for set_smoothing_factor; None
    # where it has not searched (s = 0, given knots, a derived spline).
    _search: tuple | None = None

    def __init__(self, x, y, w=None, bbox=(None, None), k: int = 3, s=None, ext=0,
                 check_finite: bool = False, context: Context | None = None):
        x, y, w, bbox, self.ext = self.validate_input(x, y, w, bbox, k, s, ext, check_finite)
        if s is None:
            s = float(len(x)) if w is None else float(len(w))
        self._data = (x, y, w, bbox, k)
        self.context = context
        if s == 0:
            self._spline = _interpolating(x, y, w, bbox, k, context)
        else:
            self._smooth(s, None)

    def _smooth(self, s: float, search) -> None:
        """The smoothing spline for s, FITPACK's knot search from the polynomial (search None)
        or on from an earlier search's (t, fpold, nplus); FITPACK's stop short of fp = s
        warns as SciPy's class warns it (a UserWarning)."""
        assert self._data is not None
        x, y, w, bbox, k = self._data
        x, y, w, k, s, xb, xe = _fitpack._validated(x, y, w, k, s, bbox[0], bbox[1], False)
        if len(x) <= k:
            raise ValueError(f"x: m > k must hold, got m = {len(x)} points for k = {k}")
        t, c, ier, self._search = _native.fit_splrep_from(
            _aligned(x, "x"), _aligned(np.ascontiguousarray(y[:, 0]), "y"), _aligned(w, "w"),
            xb, xe, k, s, search)
        if ier:
            warnings.warn(_fitpack._STOPPED[ier], UserWarning, stacklevel=3)
        self._spline = BSpline.construct_fast(t, c, k, context=self.context)

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
        x, y, w, _, _ = self._data
        weights = np.ones_like(x) if w is None else w
        return float(np.sum((weights * (y - self._spline(x))) ** 2))

    def integral(self, a, b) -> float:
        """The integral from a to b (zero outside the base interval)."""
        return splint(a, b, self._spline.tck)

    def derivatives(self, x) -> np.ndarray:
        """All derivatives (0 to k) at the point x."""
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
        if self._search is None and isinstance(self, LSQUnivariateSpline):
            warnings.warn("smoothing factor unchanged forLSQ spline with fixed knots",
                          stacklevel=2)
            return
        if not s > 0:
            raise ValueError(f"s: set_smoothing_factor takes s > 0, got {s}")
        self._smooth(float(s), self._search)


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
