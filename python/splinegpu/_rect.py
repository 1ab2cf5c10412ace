"""SciPy's `RectBivariateSpline` for s = 0: the interpolating tensor B-spline of degrees kx, ky
through z on the grid x, y, as FITPACK's `regrid` makes it.

With s = 0 FITPACK places the interior knots as SciPy's not-a-knot knots (the data for odd k,
the midpoints of the data for even k, without k // 2 + (k odd) of them at each end) and the end
knots at the bounding box (default: the data's ends), and the spline interpolates: the unique
tensor B-spline on those knots through z, fitted here by separable banded solves
(`_ndbspline.solve_grid`). FITPACK evaluates at a point clipped to the bounding box (no
extrapolation: past an end, the value at the end), and so does this class; a smoothing s > 0
is refused by name (the fitting issue brings it).
"""

from __future__ import annotations

import numpy as np

from . import _bspline, _interp
from ._ndbspline import NdBSpline, solve_grid


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

    def _spline(self) -> NdBSpline:
        spline = self.__dict__.get("_tensor")
        if spline is None:
            (tx, ty, c), (kx, ky) = self.tck, self.degrees
            shape = (len(tx) - kx - 1, len(ty) - ky - 1)
            spline = NdBSpline((tx, ty), np.asarray(c).reshape(shape), (kx, ky))
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


class BivariateSpline(_Bivariate):
    """The evaluations every fitted bivariate spline has: `ev` and `integral`."""

    fp: float

    def ev(self, xi, yi, dx=0, dy=0) -> np.ndarray:
        """At the pairs (xi, yi): `self(xi, yi, dx, dy, grid=False)`."""
        return self(xi, yi, dx=dx, dy=dy, grid=False)

    def integral(self, xa, xb, ya, yb) -> float:
        """The integral over [xa, xb] x [ya, yb], each clipped to the knots' span as FITPACK's
        `dblint`: the B-splines' integrals along each axis, contracted with c."""
        (tx, ty, c), (kx, ky) = self.tck, self.degrees
        ix = _basis_integrals(tx, kx, xa, xb)
        iy = _basis_integrals(ty, ky, ya, yb)
        return float(ix @ np.asarray(c).reshape(len(ix), len(iy)) @ iy)

    def get_residual(self) -> float:
        return self.fp


def _basis_integrals(t: np.ndarray, k: int, a: float, b: float) -> np.ndarray:
    """The integral of each B_{i,k} over [a, b] clipped to [t_0, t_last]: the antiderivative
    of each (degree k + 1, coefficients the partial sums of (t_{i+k+1} - t_i) / (k + 1))
    differenced at the ends."""
    a, b = (float(np.clip(v, t[0], t[-1])) for v in (a, b))
    n = len(t) - k - 1
    identity = np.eye(n)
    ta, ca, ka = _bspline.antiderivative(t, identity, k, 1)
    ends = np.array([a, b])
    span = _bspline.intervals(ta, ka, ends)
    weights = _bspline.basis(ta, ka, ends, span)
    value = np.zeros((2, ca.shape[1]))
    for r in range(ka + 1):
        value += weights[:, r:r + 1] * ca[span - ka + r]
    return value[1] - value[0]


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
    """SciPy's `RectBivariateSpline(x, y, z, bbox=[None] * 4, kx=3, ky=3, s=0, maxit=20)` for
    s = 0 (see the module's documentation); `fp` (the residual) is 0."""

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
        if s:
            raise ValueError(f"s: smoothing (s = {s} > 0) is not supported yet; s = 0 "
                             f"interpolates")
        for name, k, v in (("kx", kx, x), ("ky", ky, y)):
            if not 1 <= k <= 5:
                raise ValueError(f"{name}: the degree must be 1 to 5, got {k}")
            if v.size <= k:
                raise ValueError(f"{name}: {v.size} points, need at least {k + 1} for degree "
                                 f"{k}")
        if np.iscomplexobj(z) or not np.isfinite(np.asarray(z, dtype=np.float64)).all():
            raise ValueError("z: the values must be real and finite")
        z = np.asarray(z, dtype=np.float64)
        knots = []
        for v, k, (lo, hi) in ((x, kx, bbox[:2]), (y, ky, bbox[2:])):
            lo = v[0] if lo is None else float(lo)
            hi = v[-1] if hi is None else float(hi)
            if not (lo <= v[0] and v[-1] <= hi):
                raise ValueError(f"bbox: [{lo}, {hi}] must hold the data [{v[0]}, {v[-1]}]")
            t = _interp.not_a_knot(v, k)
            t[:k + 1], t[-k - 1:] = lo, hi
            knots.append(t)
        c = solve_grid((x, y), tuple(knots), (kx, ky), z)
        self.fp = 0.0
        self.tck = (knots[0], knots[1], c.ravel())
        self.degrees = (kx, ky)
